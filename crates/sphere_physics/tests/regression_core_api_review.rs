//! Regressions found by a review of the core's public API: inputs that passed its checks and
//! then gave wrong physics (a sphere too big for an f64's squares let others through it), hung
//! a step (bisection asked for billions of iterations), or gained energy (a restitution or a
//! bias out of range given straight to the response functions).

use sphere_physics::generate::Generator;
use sphere_physics::glam::DVec3;
use sphere_physics::{
    Bisection, Field, GroupContact, MAX_BISECTION_ITERATIONS, MAX_MASS, MAX_RADIUS, SceneDesc,
    Settings, SphereDesc, TimeOfImpact, Tolerance, World, resolve, resolve_simultaneous,
};

#[test]
fn regression_a_radius_whose_square_overflows_is_refused() {
    let mut world = World::new(Settings::default());
    let error = world
        .add_sphere(
            SphereDesc::new(1e200)
                .at(DVec3::new(0.0, -1e200, 0.0))
                .fixed(),
        )
        .unwrap_err();
    assert_eq!(error.field, Field::Radius);
    assert!(error.to_string().contains("1e150"), "{error}");
    assert!(world.is_empty());
    world
        .add_sphere(SphereDesc::new(MAX_RADIUS).fixed())
        .unwrap();
}

#[test]
fn regression_bisection_iterations_are_capped() {
    // Two spheres closing from 3 apart at 4 (contact 1): they touch at 0.5 of the interval.
    let huge = Bisection {
        max_iterations: u32::MAX,
    };
    let outcome = huge.time_of_impact(
        DVec3::new(3.0, 0.0, 0.0),
        DVec3::new(-4.0, 0.0, 0.0),
        1.0,
        1.0,
        Tolerance::DEFAULT,
    );
    assert_eq!(outcome.iterations, MAX_BISECTION_ITERATIONS);
    // Touching within the tolerance (1e-9 of the contact distance) is touching.
    assert!((outcome.time.unwrap() - 0.5).abs() <= 1e-9, "{outcome:?}");
    // And in a world, as a custom method.
    let mut world = World::new(Settings::default());
    world.set_time_of_impact(Box::new(huge));
    world
        .add_sphere(SphereDesc::new(0.5).moving(DVec3::X))
        .unwrap();
    world
        .add_sphere(SphereDesc::new(0.5).at(DVec3::new(1.5, 0.0, 0.0)))
        .unwrap();
    world.step(1.0).unwrap();
    assert_eq!(world.stats().collisions, 1);
}

#[test]
fn regression_restitution_out_of_range_never_gains_energy() {
    // Equal masses, head on at 2: e = 1 swaps the velocities; above 1 is taken as 1, below 0
    // or NaN as 0 (they leave together at the mean).
    let run = |e: f64| resolve(1.0, 1.0, DVec3::X, -DVec3::X, DVec3::X, e);
    for e in [1.0, 3.0, f64::INFINITY] {
        let r = run(e);
        assert_eq!(
            (r.velocity_a, r.velocity_b, r.impulse),
            (-DVec3::X, DVec3::X, 2.0),
            "{e}"
        );
    }
    for e in [0.0, -3.0, f64::NAN] {
        let r = run(e);
        assert_eq!(
            (r.velocity_a, r.velocity_b, r.impulse),
            (DVec3::ZERO, DVec3::ZERO, 1.0),
            "{e}"
        );
    }
}

#[test]
fn regression_a_negative_or_nan_bias_counts_as_zero() {
    let plain = GroupContact::new(0, 1, DVec3::X, 0.0);
    for bias in [-1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut v = vec![DVec3::X, -DVec3::X];
        let mut impulses = Vec::new();
        resolve_simultaneous(&[1.0, 1.0], &mut v, &[plain.with_bias(bias)], &mut impulses);
        assert_eq!(v, vec![DVec3::ZERO, DVec3::ZERO], "bias {bias}");
        assert_eq!(impulses, vec![1.0], "bias {bias}");
    }
}

#[test]
fn regression_a_tolerance_the_settings_refuse_is_not_made() {
    assert!(Tolerance::new(0.7).is_none());
    assert!(Tolerance::new(0.5).is_none());
    assert!(Tolerance::new(-1e-9).is_none());
    assert!(Tolerance::new(f64::NAN).is_none());
    let tol = Tolerance::new(0.25).unwrap();
    let settings = Settings {
        tolerance: tol,
        ..Settings::default()
    };
    settings.validate().unwrap();
}

#[test]
fn regression_gas_walls_too_large_to_resolve_the_gas_are_refused() {
    let gas = |wall_radius: f64| Generator::Gas {
        count: 10,
        seed: 1,
        min: [-1.0; 3],
        max: [1.0; 3],
        radius: 0.1,
        speed: 1.0,
        density: 1.0,
        restitution: None,
        walls: true,
        wall_radius,
    };
    let error = gas(1e13).spheres().unwrap_err();
    assert!(error.to_string().contains("wall_radius"), "{error}");
    assert_eq!(gas(1e4).spheres().unwrap().len(), 16);
    // The same through a scene file, which names the generator.
    let scene = SceneDesc::from_ron(
        "(name: \"x\", generate: [Gas(count: 10, seed: 1, min: (-1.0, -1.0, -1.0), max: (1.0, 1.0, 1.0), radius: 0.1, speed: 1.0, wall_radius: 1e13)])",
    )
    .unwrap();
    let error = scene.build().unwrap_err().to_string();
    assert!(error.contains("wall_radius"), "{error}");
}

/// Regression (found by review of the solver): a step ended with a body's velocity infinite
/// and reported success: the check for the finite range looked at a struck body's velocity
/// before the integrator's kick after the drift (leapfrog's second half kick) was added.
#[test]
fn regression_the_kick_after_an_impulse_cannot_overflow_unnoticed() {
    let mut world = World::new(Settings {
        gravity: DVec3::X * 1.2e308,
        integrator: sphere_physics::IntegratorKind::Leapfrog,
        // An elastic impact, not a resting contact (under this gravity every contact rests).
        resting_factor: 0.0,
        ..Settings::default()
    });
    // A moving fixed (kinematic) striker at 0.9e308 m/s touching a ball that its first half
    // kick gives 0.6e308 m/s: the ball leaves at 2 · 0.9e308 - 0.6e308 = 1.2e308 m/s, and the
    // half kick after the drift would take it past the largest f64.
    world
        .add_sphere(SphereDesc::new(0.5).fixed().moving(DVec3::X * 0.9e308))
        .unwrap();
    let ball = world.add_sphere(SphereDesc::new(0.5).at(DVec3::X)).unwrap();
    let error = world.step(1.0).unwrap_err();
    assert!(error.to_string().contains("finite range"), "{error}");
    let body = world.body(ball).unwrap();
    assert_eq!((body.position(), body.velocity()), (DVec3::X, DVec3::ZERO));
    assert_eq!(world.steps(), 0);
}

/// Regression (found by review of the solver): spheres heavy enough that the impulse between
/// them (mass times speed) overflowed an f64 had every step refused from then on; a moving
/// sphere's mass is now held to `MAX_MASS` (1e200 kg), under which impulses stay finite.
#[test]
fn regression_a_mass_whose_impulses_overflow_is_refused() {
    let mut world = World::new(Settings::default());
    let error = world
        .add_sphere(SphereDesc::new(1e100).with_density(1e6))
        .unwrap_err();
    assert_eq!(error.field, Field::Radius);
    assert!(error.to_string().contains("1e200"), "{error}");
    let error = world
        .add_sphere(SphereDesc::new(1.0).with_density(1e201))
        .unwrap_err();
    assert_eq!(error.field, Field::Density);
    assert!(world.is_empty());
    // Two of the heaviest, touching head on at 30 m/s each: they swap velocities.
    let r = 2.8e66;
    let a = world
        .add_sphere(SphereDesc::new(r).at(DVec3::X * -r).moving(DVec3::X * 30.0))
        .unwrap();
    let b = world
        .add_sphere(SphereDesc::new(r).at(DVec3::X * r).moving(DVec3::X * -30.0))
        .unwrap();
    assert!(world.body(a).unwrap().mass() > 0.9e200 && world.body(a).unwrap().mass() <= MAX_MASS);
    world.step(1.0 / 60.0).unwrap();
    let (va, vb) = (
        world.body(a).unwrap().velocity(),
        world.body(b).unwrap().velocity(),
    );
    assert!(
        (va.x + 30.0).abs() < 1e-12 && (vb.x - 30.0).abs() < 1e-12,
        "{va} {vb}"
    );
    assert!(world.collisions()[0].impulse.is_finite());
}
