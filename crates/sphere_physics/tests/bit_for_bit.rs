//! The step's results, bit for bit: a landing ball pit, a shower onto a dome, an elastic gas
//! and spheres sliding on a floor, each stepped through the public API, digested (every step's collision counts and
//! largest overlap, and every sphere's final position and velocity, to the bit) and compared
//! with the digest recorded here. (Not the times of impact computed: a change for speed may
//! spare some.)
//!
//! Changes made for speed are meant to leave every result the same, bit for bit (the speed
//! history's "the same results bit for bit"); this test holds them to it in scenes that take
//! the step's many paths: a landing crowd's (impacts solved together and joined at one
//! instant, the resting solve, and the collision budget's fallback, which the pit is checked
//! to reach) as well as the shower's and the gas's. A change meant to alter the physics
//! changes these digests: record the new ones with the change, and say why in its message
//! (run `cargo test -p sphere_physics --test bit_for_bit -- --nocapture` to print them).
//! Every operation the step uses is IEEE 754's (`+ - * /`, square roots, comparisons; no fused
//! multiply-add, no library transcendentals), so the digests should be the same on every
//! platform; they are the same in the dev and release profiles, with and without the `portable`
//! feature (checked on x86-64). A change as small as the contact band's millionth of a diameter
//! becoming 1.5 millionths changes the pit's and the shower's.

mod common;

use sphere_physics::glam::DVec3;
use sphere_physics::{SceneDesc, World};

const DT: f64 = 1.0 / 60.0;

/// FNV-1a, 64 bits.
struct Digest(u64);

impl Digest {
    fn new() -> Self {
        Digest(0xcbf2_9ce4_8422_2325)
    }

    fn add(&mut self, value: u64) {
        for byte in value.to_le_bytes() {
            self.0 ^= u64::from(byte);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// Steps `world` `steps` times and digests each step's counts and the final state; and how
/// many steps spent the collision budget and fell back to solving the rest at once.
fn digest(mut world: World, steps: u32) -> (u64, u32) {
    let mut digest = Digest::new();
    let mut fell_back = 0;
    for _ in 0..steps {
        let stats = *world.step(DT).expect("the scene steps");
        digest.add(u64::from(stats.collisions));
        digest.add(u64::from(stats.resting_contacts));
        digest.add(u64::from(stats.collisions_deferred));
        digest.add(stats.max_overlap.to_bits());
        digest.add(u64::from(stats.fell_back));
        fell_back += u32::from(stats.fell_back);
    }

    for body in world.bodies() {
        for v in [body.position(), body.velocity()] {
            for x in v.to_array() {
                digest.add(x.to_bits());
            }
        }
    }
    (digest.0, fell_back)
}

fn check(name: &str, got: u64, recorded: u64) {
    println!("{name}: {got:#018x}");
    assert_eq!(
        got, recorded,
        "{name}: the results changed (digest {got:#018x}, recorded {recorded:#018x}); if the \
         physics was meant to change, record the new digest and say why"
    );
}

/// 300 spheres of radius 0.05 (restitution 0.5) dropped into an open box of fixed walls, over
/// their landing (1.5 s): groups, joins, the resting solve and the collision budget's fallback.
#[test]
fn a_landing_ball_pit_steps_the_same_bit_for_bit() {
    let world = common::pit(300, 1, 0.5, 0.05, 0.0);
    let (got, fell_back) = digest(world, 90);
    assert!(
        fell_back > 0,
        "the pit no longer spends its collision budget"
    );
    // (Recorded anew in the sixtieth session, from 0xfaab_8136_fb5c_efcd: the collision
    // counts, not the motion, changed, a squeeze's contacts that took no impulse no longer
    // reported.)
    check("pit", got, 0xd8e7_1b68_68e7_25f5);
}

/// 2000 spheres of radius 0.05 (restitution 0.5) raining onto a fixed dome (`sphere_bench`'s
/// shower at 2000): the grid's re-queries, the glances, resting contacts on the dome.
#[test]
fn a_shower_steps_the_same_bit_for_bit() {
    let side = 2.0 * 0.05 * 1.1 * (8.0f64 * 2000.0).cbrt().ceil();
    let (dome, half) = (0.75 * side, side / 2.0);
    let bottom = dome + 0.2;
    let world = SceneDesc::from_ron(&format!(
        "(name: \"shower\", gravity: (0.0, -9.81, 0.0), restitution: 0.5,
          spheres: [(name: \"dome\", position: (0.0, 0.0, 0.0), radius: {dome:?}, fixed: true)],
          generate: [Shower(count: 2000, seed: 1, min: ({lo:?}, {bottom:?}, {lo:?}),
                            max: ({half:?}, {top:?}, {half:?}), radius: 0.05)])",
        lo = -half,
        top = bottom + side,
    ))
    .unwrap()
    .build()
    .unwrap();
    check("shower", digest(world, 60).0, 0x818e_59c7_bc8a_6311);
}

/// 400 spheres of radius 0.05 (restitution 0.9) lying on a floor (a fixed sphere of radius
/// 1e4, each sphere touching its curved top), sliding at 1 m/s, walled (`sphere_bench`'s
/// table, smaller): every sphere on the floor at every step, its contact there a resting one,
/// and the resting solve changing them all (their pairs then tested again in one pass over the
/// broad phase).
#[test]
fn spheres_sliding_on_a_table_step_the_same_bit_for_bit() {
    let (count, wall, radius) = (400u32, 1.0e4, 0.05);
    let spacing = (std::f64::consts::PI * radius * radius / 0.25).sqrt();
    let across = f64::from(count).sqrt().ceil() as u32;
    let half = 0.5 * spacing * f64::from(across);
    let fixed = |[x, y, z]: [f64; 3]| {
        format!("(position: ({x:?}, {y:?}, {z:?}), radius: {wall:?}, fixed: true)")
    };
    let mut spheres = vec![
        fixed([0.0, -wall, 0.0]),
        fixed([-half - wall, 0.0, 0.0]),
        fixed([half + wall, 0.0, 0.0]),
        fixed([0.0, 0.0, -half - wall]),
        fixed([0.0, 0.0, half + wall]),
    ];
    // Each direction turned from the last by the angle whose cosine is 3/5 (no library
    // trigonometry, so the scene is the same on every platform).
    let (mut c, mut s) = (1.0f64, 0.0f64);
    for k in 0..count {
        let at = |cell: u32| -half + spacing * (f64::from(cell) + 0.5);
        let (x, z) = (at(k % across), at(k / across));
        let y = ((wall + radius) * (wall + radius) - x * x - z * z).sqrt() - wall;
        spheres.push(format!(
            "(position: ({x:?}, {y:?}, {z:?}), velocity: ({c:?}, 0.0, {s:?}), radius: {radius:?})"
        ));
        (c, s) = (0.6 * c - 0.8 * s, 0.8 * c + 0.6 * s);
    }
    let scene = SceneDesc::from_ron(&format!(
        "(name: \"table\", gravity: (0.0, -9.81, 0.0), restitution: 0.9, spheres: [{}])",
        spheres.join(", ")
    ))
    .unwrap();
    // Every sphere stays on the floor (within a tenth of a millimetre of touching its top),
    // and no pair ends a step a tenth of a millimetre deep.
    let mut world = scene.build().unwrap();
    for step in 0..60 {
        let stats = *world.step(DT).unwrap();
        assert!(
            stats.max_overlap < 1e-4,
            "step {step}: a pair {} m deep",
            stats.max_overlap
        );
        for body in world.bodies().iter().filter(|b| !b.is_fixed()) {
            let above = (body.position() - DVec3::new(0.0, -wall, 0.0)).length() - wall - radius;
            assert!(
                above.abs() < 1e-4,
                "step {step}: a sphere {above} m off the floor"
            );
        }
    }
    let (got, _) = digest(scene.build().unwrap(), 60);
    check("table", got, 0xd81c_562c_98f8_de84);
}

/// 1000 spheres at 1 m/s in a box of six fixed wall spheres, elastic, no gravity.
#[test]
fn a_gas_steps_the_same_bit_for_bit() {
    let world = SceneDesc::from_ron(
        "(name: \"gas\", gravity: (0.0, 0.0, 0.0), restitution: 1.0,
          generate: [Gas(count: 1000, seed: 1, min: (-1.1, -1.1, -1.1), max: (1.1, 1.1, 1.1),
                         radius: 0.05, speed: 1.0)])",
    )
    .unwrap()
    .build()
    .unwrap();
    check("gas", digest(world, 60).0, 0xe3a9_e2f1_a13e_a37d);
}
