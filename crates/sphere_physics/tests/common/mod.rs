//! The scene of `properties::rain_on_a_big_fixed_sphere`, shared with the tests that replay the
//! cases it found, the creep allowance, a sheet of spheres over fixed ones, head-on pairs
//! (alone or on a lattice) that must each collide within one step, a pit of spheres dropped into an open box,
//! spheres among others hanging on strings, a crowd placed overlapping with no gravity, a
//! crowd crushed together with a small collision budget, and
//! the deepest overlap (also beyond the contact band) and centre of mass of a world, a world
//! with sleeping on above a floor and the steps a ball takes to fall asleep there; directions
//! spread evenly over a sphere; a check that generated spheres do not overlap; and the
//! property tests' configuration from a fixed seed.
// Each test file uses part of this.
#![allow(dead_code)]

use sphere_physics::{BodyId, SceneDesc, Settings, SphereDesc, StepStats, World, glam::DVec3};

/// The property tests' usual seed.
pub const SEED: u64 = 0x5EED_5EED;

/// `cases` cases from the fixed `seed`, so that a run (and CI) repeats bit for bit; set
/// `PROPTEST_RNG_SEED` to explore other cases, and `PROPTEST_CASES` to run that many instead.
pub fn proptest_config(cases: u32, seed: u64) -> proptest::prelude::ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(cases);
    let mut config = proptest::prelude::ProptestConfig::with_cases(cases);
    if std::env::var_os("PROPTEST_RNG_SEED").is_none() {
        config.rng_seed = proptest::test_runner::RngSeed::Fixed(seed);
    }
    config
}

/// One sphere as the property draws it: velocity (x, y, z), radius, density, restitution, and
/// a jitter along (1, 1, 1).
pub type Drop = (f64, f64, f64, f64, f64, f64, f64);

/// Spheres on a lattice of spacing 1 (five by five per layer), one per drop, above a fixed
/// sphere of radius 3 at (2, -3.6, 1), under gravity 9.81 m/s².
pub fn rain_on_a_dome(drops: &[Drop]) -> World {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    world
        .add_sphere(SphereDesc::new(3.0).at(DVec3::new(2.0, -3.6, 1.0)).fixed())
        .unwrap();
    add_drops(&mut world, drops);
    world
}

/// Adds one sphere per drop on a lattice of spacing 1 (five by five per layer).
pub fn add_drops(world: &mut World, drops: &[Drop]) {
    for (i, &(vx, vy, vz, r, rho, e, jitter)) in drops.iter().enumerate() {
        let lattice = DVec3::new((i % 5) as f64, ((i / 5) % 5) as f64, (i / 25) as f64);
        world
            .add_sphere(
                SphereDesc::new(r)
                    .at(lattice + DVec3::splat(jitter * 0.5))
                    .moving(DVec3::new(vx, vy, vz))
                    .with_density(rho)
                    .with_restitution(e),
            )
            .unwrap();
    }
}

/// A fixed dome of radius 3 with its top at y = -0.6, and `n` balls of radius 0.1 (density
/// 0.5, restitution 0) stacked above its top, 1 apart, at rest, under gravity 9.81 m/s².
pub fn column_on_a_dome(n: usize) -> (World, Vec<BodyId>) {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    world
        .add_sphere(SphereDesc::new(3.0).at(DVec3::new(2.0, -3.6, 1.0)).fixed())
        .unwrap();
    let balls = (0..n)
        .map(|k| {
            world
                .add_sphere(
                    SphereDesc::new(0.1)
                        .at(DVec3::new(2.0, k as f64, 1.0))
                        .with_density(0.5)
                        .with_restitution(0.0),
                )
                .unwrap()
        })
        .collect();
    (world, balls)
}

/// How far a resting pair may sink into each other in one step of `dt` under that gravity
/// (the creep allowance), which the property holds every step to.
pub fn creep(world: &World, dt: f64) -> f64 {
    let settings = world.settings();
    settings.creep_fraction * settings.resting_factor * 9.81 * dt * dt
}

/// An `n` × `n` sheet of spheres of radius 0.5, 1.5 m apart, each `lift` above its own fixed
/// sphere of radius 0.5 (centre to centre) and moving at `velocity`, in a world with
/// `gravity`. Returns the world and the sheet's ids.
pub fn sheet_over_floors(
    n: usize,
    gravity: DVec3,
    lift: f64,
    velocity: DVec3,
) -> (World, Vec<BodyId>) {
    let mut world = World::new(Settings::with_gravity(gravity));
    let mut balls = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let floor = DVec3::new(i as f64 * 1.5, 0.0, j as f64 * 1.5);
            world
                .add_sphere(SphereDesc::new(0.5).at(floor).fixed())
                .unwrap();
            let ball = SphereDesc::new(0.5)
                .at(floor + DVec3::Y * lift)
                .moving(velocity);
            balls.push(world.add_sphere(ball).unwrap());
        }
    }
    (world, balls)
}

/// Two spheres of `radius` around `centre`, `gap` apart along `axis`, closing head-on at
/// `speed` each.
pub fn head_on_pair(
    centre: DVec3,
    axis: DVec3,
    radius: f64,
    gap: f64,
    speed: f64,
) -> [SphereDesc; 2] {
    let half = radius + gap / 2.0;
    [
        SphereDesc::new(radius)
            .at(centre - axis * half)
            .moving(axis * speed),
        SphereDesc::new(radius)
            .at(centre + axis * half)
            .moving(-axis * speed),
    ]
}

/// Head-on pairs of spheres of `radius` (see [`head_on_pair`]) on a lattice of `side` by
/// `side` by `side` sites `spacing` apart from `origin`, along x, y and z in turn.
pub fn head_on_lattice(
    origin: DVec3,
    side: u32,
    spacing: f64,
    radius: f64,
    gap: f64,
    speed: f64,
) -> Vec<[SphereDesc; 2]> {
    let axes = [DVec3::X, DVec3::Y, DVec3::Z];
    let mut pairs = Vec::new();
    for i in 0..side {
        for j in 0..side {
            for k in 0..side {
                let at = DVec3::new(f64::from(i), f64::from(j), f64::from(k)) * spacing;
                let axis = axes[(i + j + k) as usize % 3];
                pairs.push(head_on_pair(origin + at, axis, radius, gap, speed));
            }
        }
    }
    pairs
}

/// Steps `pairs` (equal masses, elastic, head-on, no gravity) once by `dt` and checks that
/// every pair collided: one collision each, the velocities exchanged. `label` names the case
/// in a failure.
pub fn step_head_on_pairs(pairs: &[[SphereDesc; 2]], dt: f64, label: &str) -> StepStats {
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    let ids: Vec<_> = pairs
        .iter()
        .map(|[a, b]| {
            (
                world.add_sphere(a.clone()).unwrap(),
                world.add_sphere(b.clone()).unwrap(),
            )
        })
        .collect();
    let stats = *world.step(dt).unwrap();
    assert_eq!(stats.collisions as usize, pairs.len(), "{label}");
    for ((a, b), [da, db]) in ids.iter().zip(pairs) {
        let (va, vb) = (
            world.body(*a).unwrap().velocity(),
            world.body(*b).unwrap().velocity(),
        );
        assert!(
            (va - db.velocity).length() <= 1e-12,
            "{label}: {va} at {}",
            da.position
        );
        assert!(
            (vb - da.velocity).length() <= 1e-12,
            "{label}: {vb} at {}",
            db.position
        );
    }
    stats
}

/// `count` spheres of radius `radius` and restitution `restitution` dropped from a lattice 16
/// cells (`2.2 radius`) high, one cell in two filled (from `seed`), into an open box with
/// `spare` columns of cells to spare across: a floor and four walls, fixed spheres of radius
/// 1e4 (`sphere_bench`'s `pile` scene has `spare` 0).
pub fn pit(count: u32, seed: u64, restitution: f64, radius: f64, spare: f64) -> World {
    let cells = (2.0 * f64::from(count) / 16.0).sqrt().ceil() + spare;
    let wall = 1.0e4;
    let cell = 2.0 * radius * 1.1;
    let (half, height) = (0.5 * cell * cells, 16.0 * cell);
    SceneDesc::from_ron(&format!(
        "(name: \"pit\", gravity: (0.0, -9.81, 0.0), restitution: {restitution:?},
          spheres: [
            (name: \"floor\", position: (0.0, {f:?}, 0.0), radius: {wall:?}, fixed: true),
            (name: \"wall x-\", position: ({n:?}, 0.0, 0.0), radius: {wall:?}, fixed: true),
            (name: \"wall x+\", position: ({p:?}, 0.0, 0.0), radius: {wall:?}, fixed: true),
            (name: \"wall z-\", position: (0.0, 0.0, {n:?}), radius: {wall:?}, fixed: true),
            (name: \"wall z+\", position: (0.0, 0.0, {p:?}), radius: {wall:?}, fixed: true)],
          generate: [Shower(count: {count}, seed: {seed}, min: ({lo:?}, 0.0, {lo:?}),
                            max: ({half:?}, {height:?}, {half:?}), radius: {radius:?})])",
        f = -wall,
        n = -half - wall,
        p = half + wall,
        lo = -half,
    ))
    .unwrap()
    .build()
    .unwrap()
}

/// A sphere among strung ones: velocity, radius, log10 of the density, restitution, and maybe a
/// string (its length above the sphere, and its slack at the start).
pub type Strung = ((f64, f64, f64), f64, f64, f64, Option<(f64, f64)>);

/// A world with `settings` and one sphere per entry of `spheres`, on a lattice of spacing 1
/// (four by four per layer), those with a string hanging from an anchor straight above.
pub fn strung_world(spheres: &[Strung], settings: Settings) -> World {
    let mut world = World::new(settings);
    for (i, &((vx, vy, vz), r, density, e, string)) in spheres.iter().enumerate() {
        let at = DVec3::new((i % 4) as f64, ((i / 4) % 4) as f64, (i / 16) as f64);
        let mut sphere = SphereDesc::new(r)
            .at(at)
            .moving(DVec3::new(vx, vy, vz))
            .with_density(10f64.powf(density))
            .with_restitution(e);
        if let Some((length, slack)) = string {
            sphere = sphere.tethered(at + DVec3::new(0.0, length, 0.0), length + slack);
        }
        world.add_sphere(sphere).unwrap();
    }
    world
}

/// A cube of `side`³ spheres of radius 0.5 whose centres are `spacing` apart (under a
/// diameter: each overlaps its neighbours), each velocity component up to `speed` either way
/// (a fixed sequence from `seed`), with `restitution`, and no gravity.
pub fn overlapping_crowd(
    side: usize,
    spacing: f64,
    speed: f64,
    restitution: f64,
    seed: u64,
) -> World {
    let mut world = World::new(Settings::default());
    let mut state = seed;
    let mut unit = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for i in 0..side {
        for j in 0..side {
            for k in 0..side {
                let at = DVec3::new(i as f64, j as f64, k as f64) * spacing;
                let velocity = DVec3::new(unit(), unit(), unit()) * speed;
                world
                    .add_sphere(
                        SphereDesc::new(0.5)
                            .at(at)
                            .moving(velocity)
                            .with_restitution(restitution),
                    )
                    .unwrap();
            }
        }
    }
    world
}

/// A ball of 343 spheres of radius 0.05 in zero gravity, 7 by 7 by 7 on a lattice of spacing
/// 0.105, each moving towards the centre at up to 3 m/s (with a little sideways, for irregular
/// meetings), with a collision budget of `budget` per sphere.
pub fn crushed_crowd(budget: u32) -> World {
    let mut world = World::new(Settings {
        max_collisions_per_body: budget,
        ..Settings::default()
    });
    for i in 0..7 {
        for j in 0..7 {
            for k in 0..7 {
                let at = DVec3::new(f64::from(i), f64::from(j), f64::from(k)) * 0.105
                    - DVec3::splat(0.315);
                let velocity = -at * 10.0 + DVec3::new(0.1 * f64::from((i * j) % 3), 0.0, 0.0);
                world
                    .add_sphere(SphereDesc::new(0.05).at(at).moving(velocity))
                    .unwrap();
            }
        }
    }
    world
}

/// The deepest overlap between any two spheres, by brute force (0 if none overlap).
pub fn deepest_overlap(world: &World) -> f64 {
    let bodies = world.bodies();
    let mut deepest = 0.0f64;
    for (i, a) in bodies.iter().enumerate() {
        for b in &bodies[i + 1..] {
            let overlap = a.radius() + b.radius() - (b.position() - a.position()).length();
            deepest = deepest.max(overlap);
        }
    }
    deepest
}

/// The mass-weighted mean position of the dynamic spheres.
/// A world with no gravity of spheres at rest, each `(x, y, z, radius, density)`, placed
/// with no regard for each other.
pub fn crowd_at_rest(spheres: &[(f64, f64, f64, f64, f64)]) -> World {
    let mut world = World::new(Settings::default());
    for &(x, y, z, radius, density) in spheres {
        world
            .add_sphere(
                SphereDesc::new(radius)
                    .at(DVec3::new(x, y, z))
                    .with_density(density),
            )
            .unwrap();
    }
    world
}

/// The deepest overlap of any pair beyond its contact band (a millionth of the smaller
/// diameter, plus the tolerance: within it the pair touches), 0 if none.
pub fn deepest_beyond_band(world: &World) -> f64 {
    let bodies = world.bodies();
    let mut worst = 0.0f64;
    for (i, a) in bodies.iter().enumerate() {
        for b in &bodies[i + 1..] {
            let reach = a.radius() + b.radius();
            let band = 2e-6 * a.radius().min(b.radius()) + 1e-9 * (1.0 + reach);
            worst = worst.max(reach - (b.position() - a.position()).length() - band);
        }
    }
    worst
}

pub fn centre_of_mass(world: &World) -> DVec3 {
    let (mut sum, mut mass) = (DVec3::ZERO, 0.0);
    for body in world.bodies().iter().filter(|b| !b.is_fixed()) {
        sum += body.mass() * body.position();
        mass += body.mass();
    }
    sum / mass
}

/// The radius of the spheres of [`heavy_ball_into_a_line`].
pub const HEAVY_LINE_RADIUS: f64 = 0.5;

/// A heavy sphere (radius 0.5, density 1e6) at 800 m/s, 11 cm from the first of a line of 200
/// light ones at rest (radius 0.5, 11 cm apart: farther than the fallback's first round
/// reaches, so each later link is brought in by the round before), and a sphere between two
/// fixed ones, half a micrometre from each, that spends a collision budget of one a body in
/// the step's first instants; with no gravity.
pub fn heavy_ball_into_a_line() -> World {
    let mut world = World::new(Settings {
        max_collisions_per_body: 1,
        ..Settings::default()
    });
    // The budget's spender: a sphere between two fixed ones, half a micrometre from each,
    // bouncing between them a hundred thousand times a second.
    for x in [0.0, 4.0 * HEAVY_LINE_RADIUS + 1e-6] {
        world
            .add_sphere(
                SphereDesc::new(HEAVY_LINE_RADIUS)
                    .at(DVec3::new(x, 10.0, 0.0))
                    .fixed(),
            )
            .unwrap();
    }
    world
        .add_sphere(
            SphereDesc::new(HEAVY_LINE_RADIUS)
                .at(DVec3::new(2.0 * HEAVY_LINE_RADIUS + 5e-7, 10.0, 0.0))
                .moving(DVec3::X * 10.0),
        )
        .unwrap();
    // The heavy sphere and the line, 11 cm apart (farther than the fallback's first round
    // reaches: each later link is brought in by the round before).
    let gap = 0.11;
    world
        .add_sphere(
            SphereDesc::new(HEAVY_LINE_RADIUS)
                .at(DVec3::new(-(2.0 * HEAVY_LINE_RADIUS + gap), 0.0, 0.0))
                .moving(DVec3::X * 800.0)
                .with_density(1e6),
        )
        .unwrap();
    for i in 0..200 {
        world
            .add_sphere(SphereDesc::new(HEAVY_LINE_RADIUS).at(DVec3::new(
                f64::from(i) * (2.0 * HEAVY_LINE_RADIUS + gap),
                0.0,
                0.0,
            )))
            .unwrap();
    }
    world
}

/// A world under Earth gravity with sleeping on (`Sleep::default()`) and a fixed floor of
/// radius `floor` whose top is at y = 0; returns the floor's id too.
pub fn sleeping_on_a_floor(floor: f64) -> (World, BodyId) {
    let mut world = World::new(Settings {
        sleep: Some(sphere_physics::Sleep::default()),
        ..Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0))
    });
    let id = world
        .add_sphere(SphereDesc::new(floor).at(DVec3::NEG_Y * floor).fixed())
        .unwrap();
    (world, id)
}

/// Steps `world` by `dt` until `ball` falls asleep (at most 600 steps); the steps taken.
pub fn steps_to_sleep(world: &mut World, ball: BodyId, dt: f64) -> u32 {
    for n in 1..=600 {
        world.step(dt).unwrap();
        if world.body(ball).unwrap().is_asleep() {
            return n;
        }
    }
    panic!("the ball never fell asleep: {:?}", world.body(ball))
}

/// `n` unit directions spread evenly over the sphere (a Fibonacci lattice).
pub fn sphere_directions(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - y * y).sqrt();
            let phi = golden * i as f64;
            DVec3::new(r * phi.cos(), y, r * phi.sin())
        })
        .collect()
}

/// Panics if any two of `spheres` overlap.
pub fn no_overlap(spheres: &[sphere_physics::SphereSpec]) {
    for (i, a) in spheres.iter().enumerate() {
        for b in &spheres[i + 1..] {
            let d: f64 = (0..3)
                .map(|k| (a.position[k] - b.position[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(d >= a.radius + b.radius, "{a:?} overlaps {b:?}");
        }
    }
}
