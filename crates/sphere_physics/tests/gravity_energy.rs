//! Energy never gained under gravity: elastic spheres bouncing in a bowl of fixed spheres,
//! off its floor, its walls and one another. With `Leapfrog` the energy at each step's end
//! (kinetic plus potential) is exactly that of the start, to rounding: free flight keeps it
//! exactly, and every bounce answers the speed at its instant. With semi-implicit Euler, whose
//! velocity at a step's end is the middle of the step's, the energy read then wanders by
//! about `g·v·dt` but does not climb. Before bounces answered the speed at their instant
//! (2026-12-02), 20 balls in such a bowl gained up to 8% of their energy in 20 s with
//! semi-implicit Euler and 10% with `Leapfrog`.

use proptest::prelude::*;
use sphere_physics::glam::DVec3;
use sphere_physics::{IntegratorKind, Settings, SphereDesc, World};

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
        let half_kick = 9.81 * dt / 2.0;
        let (mut resting_before, mut resting_now) = (Vec::new(), Vec::new());
        let mut coming_to_rest = 0.0;
        for step in 0..(10 * hz) {
            let stats = *world.step(dt).unwrap();
            resting_now.clear();
            for c in world.collisions().iter().filter(|c| c.resting) {
                for id in [c.a, c.b] {
                    let body = world.body(id).unwrap();
                    if !body.is_fixed() && !resting_now.contains(&id) {
                        resting_now.push(id);
                        if !resting_before.contains(&id) {
                            coming_to_rest += 0.5 * body.mass() * half_kick * half_kick;
                        }
                    }
                }
            }
            std::mem::swap(&mut resting_before, &mut resting_now);
            let energy = stats.kinetic_energy + stats.potential_energy;
            prop_assert!(
                energy <= start + 1e-12 * start.abs() + coming_to_rest,
                "step {}: {} from {} ({:e} more; {:e} allowed for balls coming to rest)",
                step, energy, start, (energy - start) / start, coming_to_rest
            );
        }
    }

    /// Semi-implicit Euler: after 10 s the energy is within 2% of the start's (measured: 0.5%
    /// at worst over 20 bowls of 20 balls, 20 s; 8% before the fix).
    #[test]
    fn semi_implicit_euler_does_not_pump_a_bowl_of_elastic_balls(
        places in places(24),
        hz in 30u32..=240,
    ) {
        let mut world = bowl(IntegratorKind::SemiImplicitEuler, &places);
        let start = world.kinetic_energy() + world.potential_energy();
        for _ in 0..(10 * hz) {
            world.step(1.0 / f64::from(hz)).unwrap();
        }
        let end = world.kinetic_energy() + world.potential_energy();
        prop_assert!(end <= start * 1.02, "{} from {}", end, start);
    }
}
