//! The step's results, bit for bit: a landing ball pit, a shower onto a dome and an elastic
//! gas, each stepped through the public API, digested (every step's collision counts and
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
    check("pit", got, 0xa799_547f_32ea_2e25);
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
