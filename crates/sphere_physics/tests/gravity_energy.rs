//! Energy never gained under gravity: elastic spheres bouncing in a bowl of fixed spheres,
//! off its floor, its walls and one another. With `Leapfrog` the energy at each step's end
//! (kinetic plus potential) is exactly that of the start, to rounding: free flight keeps it
//! exactly, and every bounce answers the speed at its instant. With semi-implicit Euler, whose
//! drift takes the velocity at the step's end, the energy read then is off by `m·g·v_y·dt/2`
//! a ball; what it keeps to rounding is its shadow energy, the energy plus that. Before
//! bounces answered the speed at their instant (2026-12-02), 20 balls in such a bowl gained up
//! to 8% of their energy in 20 s with semi-implicit Euler and 10% with `Leapfrog`.

use proptest::prelude::*;
use sphere_physics::glam::DVec3;
use sphere_physics::{BodyId, IntegratorKind, Settings, SphereDesc, World};

/// A bowl: a floor (a fixed sphere of radius 50 whose top is at 0) and four walls (fixed
/// spheres 1.5 m from the centre), all elastic, with `balls` elastic spheres of radius 0.1
/// where `places` says (in the bowl, from 0.2 m to 2.2 m up), moving as `velocities` say.
fn bowl(integrator: IntegratorKind, places: &[(DVec3, DVec3)]) -> World {
    let mut settings = Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0));
    settings.integrator = integrator;
    let mut world = World::new(settings);
    let fixed = |at: DVec3| SphereDesc::new(50.0).at(at).with_restitution(1.0).fixed();
    world
        .add_sphere(fixed(DVec3::new(0.0, -50.0, 0.0)))
        .unwrap();
    for (x, z) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)] {
        world
            .add_sphere(fixed(DVec3::new(51.5 * x, 0.0, 51.5 * z)))
            .unwrap();
    }
    for &(at, velocity) in places {
        world
            .add_sphere(
                SphereDesc::new(0.1)
                    .at(at)
                    .moving(velocity)
                    .with_restitution(1.0),
            )
            .unwrap();
    }
    world
}

/// What semi-implicit Euler keeps exactly in free flight under gravity `g`: the energy plus
/// `dt/2 · Σ m g·v`. Its step kicks and then drifts at the kicked velocity, so over a step
/// `½v² - g·x` changes by `g·(v + v')·dt/2 - g·v'·dt = -(g·dt)²/2`, and `g·v·dt/2` by as much
/// the other way.
fn shadow_energy(world: &World, dt: f64) -> f64 {
    let g = DVec3::new(0.0, -9.81, 0.0);
    let tilt: f64 = world
        .bodies()
        .iter()
        .filter(|b| !b.is_fixed())
        .map(|b| b.mass() * g.dot(b.velocity()))
        .sum();
    world.kinetic_energy() + world.potential_energy() + 0.5 * dt * tilt
}

/// The energy balls coming to rest may add (see the tests): `m·(g·dt/2)²/2` for each ball
/// that takes a resting impact (a meeting slow enough for the resting rule, restitution 0) in
/// a step after one without, summed over the run.
#[derive(Default)]
struct ComingToRest {
    before: Vec<BodyId>,
    now: Vec<BodyId>,
    allowed: f64,
    /// Resting impacts so far.
    taken: usize,
}

impl ComingToRest {
    /// Counts the resting impacts of the step `world` just took (of `dt`), and returns what
    /// the run allows so far.
    fn allowance(&mut self, world: &World, dt: f64) -> f64 {
        let half_kick = 9.81 * dt / 2.0;
        self.now.clear();
        for c in world.collisions().iter().filter(|c| c.resting) {
            self.taken += 1;
            for id in [c.a, c.b] {
                let body = world.body(id).unwrap();
                if !body.is_fixed() && !self.now.contains(&id) {
                    self.now.push(id);
                    if !self.before.contains(&id) {
                        self.allowed += 0.5 * body.mass() * half_kick * half_kick;
                    }
                }
            }
        }
        std::mem::swap(&mut self.before, &mut self.now);
        self.allowed
    }
}

/// Up to `count` places 0.25 apart or more (a candidate too near one kept is dropped), in
/// the bowl, each with a velocity of up to 0.5 m/s per axis.
fn places(count: usize) -> impl Strategy<Value = Vec<(DVec3, DVec3)>> {
    let unit = || -1.0..1.0f64;
    prop::collection::vec(
        ((unit(), 0.0..1.0f64, unit()), (unit(), unit(), unit())),
        count,
    )
    .prop_map(|raw| {
        let mut kept: Vec<(DVec3, DVec3)> = Vec::new();
        for ((x, y, z), (u, v, w)) in raw {
            let at = DVec3::new(1.2 * x, 0.2 + 2.0 * y, 1.2 * z);
            if kept.iter().all(|(p, _)| (*p - at).length() > 0.25) {
                kept.push((at, 0.5 * DVec3::new(u, v, w)));
            }
        }
        kept
    })
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 24,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x0B0_3717),
        ..ProptestConfig::default()
    })]
    /// `Leapfrog`: over 10 s the energy at no step's end exceeds the start's by more than
    /// rounding (measured: 7.5e-15 of it at worst over 20 bowls of 20 and 40 balls, 20 s),
    /// but for what balls coming to rest may add: each time a ball takes a resting impact (a
    /// meeting slow enough for the resting rule, restitution 0) in a step after one without,
    /// up to `m·(g·dt/2)²/2`. A resting impact stops the pair's drift, which leapfrog takes at
    /// the step's middle speed, not the speed at its instant, so a ball at rest on the floor
    /// ends each step with the half kick after its drift, `g·dt/2` downward, in its velocity
    /// (the contact takes it back at the next step's start), and its energy reads that much
    /// more. (Found with `PROPTEST_RNG_SEED` 42 and 44 and 2 000 cases: a ball of 4.2 g coming
    /// to rest on the floor at 32 Hz read 1.3e-5 J more, 1.7e-5 of the bowl's energy, under
    /// the 4.9e-5 J this allows.)
    #[test]
    fn leapfrog_keeps_a_bowl_of_elastic_balls_energy_to_rounding(
        places in places(24),
        hz in 30u32..=240,
    ) {
        let mut world = bowl(IntegratorKind::Leapfrog, &places);
        let start = world.kinetic_energy() + world.potential_energy();
        let dt = 1.0 / f64::from(hz);
        let mut resting = ComingToRest::default();
        for step in 0..(10 * hz) {
            let stats = *world.step(dt).unwrap();
            let coming_to_rest = resting.allowance(&world, dt);
            let energy = stats.kinetic_energy + stats.potential_energy;
            prop_assert!(
                energy <= start + 1e-12 * start.abs() + coming_to_rest,
                "step {}: {} from {} ({:e} more; {:e} allowed for balls coming to rest)",
                step, energy, start, (energy - start) / start, coming_to_rest
            );
            // Nor less, until a ball takes a resting impact (restitution 0). (Only more was
            // checked until a review: an impulse 0.1% short of elastic passed.)
            if resting.taken == 0 {
                prop_assert!(
                    energy >= start - 1e-12 * start.abs(),
                    "step {}: {} from {} ({:e} less)",
                    step, energy, start, (start - energy) / start
                );
            }
        }
    }

    /// Semi-implicit Euler: over 10 s its shadow energy (see [`shadow_energy`]) at no step's
    /// end exceeds the start's by more than rounding (measured: 5.3e-15 of it at worst over
    /// 4 000 bowls, `PROPTEST_RNG_SEED` 60 and 61), but for what balls coming to rest may add,
    /// as with leapfrog (`PROPTEST_RNG_SEED=62`: a ball of 4.2 g struck onto the floor and
    /// brought to rest there by a resting impact at 37 Hz added 8.5e-6 J, under the 3.7e-5 J
    /// this allows). The energy read at a step's end is off the shadow energy by
    /// `m·g·v_y·dt/2` a ball: up to 3% of the bowl's at 33 Hz, where the 2% bound this test
    /// had on the energy read failed (`PROPTEST_RNG_SEED=60`, 2 000 cases: 2.02% more at the
    /// end, the shadow energy 0.07% less). Before bounces answered the speed at their
    /// instant, 8% was gained.
    #[test]
    fn semi_implicit_euler_does_not_pump_a_bowl_of_elastic_balls(
        places in places(24),
        hz in 30u32..=240,
    ) {
        let mut world = bowl(IntegratorKind::SemiImplicitEuler, &places);
        let dt = 1.0 / f64::from(hz);
        let start = shadow_energy(&world, dt);
        let mut resting = ComingToRest::default();
        for step in 0..(10 * hz) {
            world.step(dt).unwrap();
            let coming_to_rest = resting.allowance(&world, dt);
            let energy = shadow_energy(&world, dt);
            prop_assert!(
                energy <= start + 1e-12 * start.abs() + coming_to_rest,
                "step {}: {} from {} ({:e} more; {:e} allowed for balls coming to rest)",
                step, energy, start, (energy - start) / start, coming_to_rest
            );
            // Nor less, until a ball takes a resting impact (restitution 0). (Only more was
            // checked until a review: an impulse 0.1% short of elastic passed.)
            if resting.taken == 0 {
                prop_assert!(
                    energy >= start - 1e-12 * start.abs(),
                    "step {}: {} from {} ({:e} less)",
                    step, energy, start, (start - energy) / start
                );
            }
        }
    }
}
