//! Bad input never panics, hangs or poisons the state: settings are checked at every step
//! (their fields are public), a subnormal time step is refused, a density or radius whose mass
//! (or its inverse) overflows is refused when the sphere is added, and a generator's box far
//! larger than its spheres neither overflows nor panics; substeps that cut a step into
//! subnormal ones are refused, and so is a step in which an impulse would send a sphere beyond
//! the finite range. Found by reviews; each case used to return Ok and leave NaN or infinities
//! behind, hang, or panic on an overflow.

use sphere_physics::generate::Generator;
use sphere_physics::{Field, Settings, SphereDesc, ToiMethod, World, WorldError, glam::DVec3};

fn world_on_a_dome() -> World {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    world.add_sphere(SphereDesc::new(1.0).fixed()).unwrap();
    world
        .add_sphere(SphereDesc::new(0.5).at(DVec3::new(0.0, 1.5, 0.0)))
        .unwrap();
    world
}

fn refused(change: impl Fn(&mut Settings), field: &str) {
    let mut world = world_on_a_dome();
    let before: Vec<_> = world.bodies().to_vec();
    change(world.settings_mut());
    match world.step(1.0 / 60.0) {
        Err(WorldError::InvalidSetting { field: f, .. }) => assert_eq!(f, field),
        other => panic!("{field}: expected an invalid setting, got {other:?}"),
    }
    assert_eq!(world.bodies(), &before[..], "{field}: the state changed");
    assert_eq!(world.steps(), 0);
}

#[test]
fn regression_invalid_settings_are_typed_errors_and_change_nothing() {
    refused(|s| s.gravity = DVec3::new(0.0, f64::NAN, 0.0), "gravity");
    refused(
        |s| s.gravity = DVec3::new(f64::INFINITY, 0.0, 0.0),
        "gravity",
    );
    refused(|s| s.creep_fraction = f64::NEG_INFINITY, "creep_fraction");
    refused(|s| s.creep_fraction = 2.0, "creep_fraction");
    refused(|s| s.resting_factor = f64::NAN, "resting_factor");
    refused(|s| s.resting_factor = -1.0, "resting_factor");
    refused(|s| s.max_collisions_per_body = 0, "max_collisions_per_body");
    // These three used to run for hours (the first: a sphere wedged between two fixed ones
    // took some 4e9 collisions in a step, each recorded).
    refused(
        |s| s.max_collisions_per_body = u32::MAX,
        "max_collisions_per_body",
    );
    refused(|s| s.substeps = u32::MAX, "substeps");
    refused(
        |s| {
            s.method = ToiMethod::Bisection {
                max_iterations: u32::MAX,
            }
        },
        "method",
    );
    // And the defaults step, as do the largest values allowed.
    let mut world = world_on_a_dome();
    world.step(1.0 / 60.0).unwrap();
    world.settings_mut().max_collisions_per_body = sphere_physics::MAX_COLLISIONS_PER_BODY;
    world.step(1.0 / 60.0).unwrap();
}

#[test]
fn regression_a_subnormal_time_step_is_refused() {
    let mut world = world_on_a_dome();
    for dt in [1e-310, f64::MIN_POSITIVE / 2.0, 0.0, -0.0] {
        assert_eq!(world.step(dt).err(), Some(WorldError::InvalidTimeStep(dt)));
    }
    // The smallest normal step is taken, and leaves everything finite.
    world.step(f64::MIN_POSITIVE).unwrap();
    assert!(world.bodies().iter().all(|b| b.position().is_finite()));
}

#[test]
fn regression_a_mass_that_overflows_is_refused() {
    let mut world = World::new(Settings::default());
    // The field to blame: the density, or (found by review: a tiny sphere was said to have a
    // bad density of 1) the radius when its volume alone is out of range.
    for (desc, field) in [
        (SphereDesc::new(1.0).with_density(1e-309), Field::Density),
        (SphereDesc::new(1.0).with_density(1e308), Field::Density),
        (SphereDesc::new(1e-103), Field::Radius),
        (SphereDesc::new(1e103), Field::Radius),
    ] {
        let error = world.add_sphere(desc.clone()).unwrap_err();
        assert_eq!(error.field, field, "{desc:?}");
    }
    assert!(world.is_empty());
    // Fixed spheres have no mass to overflow.
    world
        .add_sphere(SphereDesc::new(1e103).with_density(1e308).fixed())
        .unwrap();
}

/// A mass in range from a density and a radius whose product in the usual order overflows or
/// underflows (found by review in the fifty-seventh session: a radius of 1e-100 at a density
/// of 5e307, 2.1e8 kg, was refused as a mass above 1e200 kg).
#[test]
fn regression_a_mass_in_range_from_extreme_factors_is_kept() {
    let mut world = World::new(Settings::default());
    for (radius, density) in [(1e-100, 5e307), (1e120, 1e-300)] {
        let id = world
            .add_sphere(SphereDesc::new(radius).with_density(density))
            .unwrap();
        let expected = 4.0 / 3.0 * std::f64::consts::PI * (density * radius * radius * radius);
        let mass = world.body(id).unwrap().mass();
        assert!(
            (mass - expected).abs() <= 1e-14 * expected,
            "radius {radius}, density {density}: {mass} kg, not {expected}"
        );
    }
}

#[test]
fn regression_a_huge_box_of_tiny_spheres_does_not_overflow() {
    let shower = |min: [f64; 3], max: [f64; 3], radius: f64| Generator::Shower {
        count: 10,
        seed: 1,
        min,
        max,
        radius,
        velocity: [0.0; 3],
        density: 1.0,
        restitution: None,
    };
    let (min, max, radius) = ([0.0; 3], [1000.0; 3], 1e-4);
    let spheres = shower(min, max, radius).spheres().unwrap();
    assert_eq!(spheres.len(), 10);
    for s in &spheres {
        for k in 0..3 {
            assert!(s.position[k] - radius >= min[k] && s.position[k] + radius <= max[k]);
        }
    }
    // So far out that positions round onto each other: refused, without overflowing (see
    // regression_generator_checks.rs).
    let error = shower([-1e308; 3], [1e308; 3], 1.0).spheres().unwrap_err();
    assert_eq!(error.field, "min");
}

#[test]
fn regression_a_step_that_would_overflow_is_refused() {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    world
        .add_sphere(SphereDesc::new(0.5).named("ball"))
        .unwrap();
    world
        .add_sphere(
            SphereDesc::new(0.5)
                .at(DVec3::new(5.0, 0.0, 0.0))
                .moving(DVec3::new(1e300, 0.0, 0.0)),
        )
        .unwrap();
    let before = world.bodies().to_vec();
    // Gravity alone takes the first ball to -inf over 1e300 s; the second is past f64 in 1e9 s.
    for (dt, culprit) in [(1e300, "'ball'"), (1e9, "#1")] {
        match world.step(dt) {
            Err(WorldError::Body(error)) => {
                assert_eq!(error.field, Field::Velocity);
                assert!(error.body.starts_with(culprit), "{error}");
            }
            other => panic!("dt {dt}: expected an error, got {other:?}"),
        }
        assert_eq!(world.bodies(), &before[..]);
    }
    world.step(1.0 / 60.0).unwrap();
    assert!(world.bodies().iter().all(|b| b.position().is_finite()));
}

#[test]
fn regression_substeps_that_make_a_subnormal_substep_are_refused() {
    // dt is normal, but two substeps of it are not: the correction speed of the ball's resting
    // contact (its overlap divided by the substep) threw it out at some 1e306 m/s, its kinetic
    // energy infinite. Found by a review.
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    world.add_sphere(SphereDesc::new(1.0).fixed()).unwrap();
    world
        .add_sphere(SphereDesc::new(0.5).at(DVec3::new(0.0, 1.49, 0.0)))
        .unwrap();
    let before = world.bodies().to_vec();
    world.settings_mut().substeps = 2;
    let dt: f64 = 3e-308; // normal; half of it is not
    assert!(dt.is_normal() && !(dt / 2.0).is_normal());
    match world.step(dt) {
        Err(WorldError::InvalidSetting { field, .. }) => assert_eq!(field, "substeps"),
        other => panic!("expected the substeps refused, got {other:?}"),
    }
    assert_eq!(world.bodies(), &before[..]);
    world.settings_mut().substeps = 1;
    world.step(dt).unwrap();
    // Not merely finite (1e306 m/s is): the resting solve's push against the overlap is taken
    // off at the step's end, so the ball is left with what gravity gives it in 3e-308 s, and
    // is moved out by no more than a push's cap, a tenth of its radius.
    let ball = &world.bodies()[1];
    assert!(ball.velocity().length() < 1e-300, "{}", ball.velocity());
    let risen = ball.position().y - 1.49;
    assert!((0.0..=0.05).contains(&risen), "risen {risen}");
    assert_eq!(ball.position().x, 0.0);
    assert_eq!(ball.position().z, 0.0);
}

#[test]
fn regression_an_impulse_beyond_the_finite_range_is_refused() {
    // A kinematic sphere near the largest finite speed strikes a ball at rest: the ball would
    // leave at twice that speed, which is infinite. Found by a review: the step returned Ok
    // and wrote the infinite velocity back.
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    let paddle = world
        .add_sphere(
            SphereDesc::new(1.0)
                .fixed()
                .moving(DVec3::new(1e308, 0.0, 0.0)),
        )
        .unwrap();
    world
        .add_sphere(
            SphereDesc::new(1.0)
                .at(DVec3::new(2.05, 0.0, 0.0))
                .named("ball"),
        )
        .unwrap();
    let before = world.bodies().to_vec();
    match world.step(1.0 / 60.0) {
        Err(WorldError::Body(error)) => {
            assert_eq!(error.field, Field::Velocity);
            assert!(error.body.starts_with("'ball'"), "{error}");
        }
        other => panic!("expected an error, got {other:?}"),
    }
    assert_eq!(world.bodies(), &before[..]);
    // Not poisoned: at a sane speed the same strike is exact.
    world
        .set_velocity(paddle, DVec3::new(10.0, 0.0, 0.0))
        .unwrap();
    world.step(1.0 / 60.0).unwrap();
    let ball = world
        .bodies()
        .iter()
        .find(|b| b.name() == Some("ball"))
        .unwrap();
    assert!(
        (ball.velocity() - DVec3::new(20.0, 0.0, 0.0)).length() <= 1e-9,
        "{}",
        ball.velocity()
    );
}

/// Regression: `Settings::validate` let `substeps: 0` through (the step took it as 1) while a
/// scene file with `substeps: 0` was refused. Found by review.
#[test]
fn regression_zero_substeps_are_refused_as_in_scene_files() {
    let mut world = World::new(Settings {
        substeps: 0,
        ..Settings::default()
    });
    world.add_sphere(SphereDesc::new(1.0)).unwrap();
    assert!(matches!(
        world.step(1.0 / 60.0),
        Err(WorldError::InvalidSetting {
            field: "substeps",
            ..
        })
    ));
    assert_eq!(world.steps(), 0);
}

/// Regression: a fixed sphere's tether, which `SphereDesc::tether` says is ignored, was still
/// checked, so a fixed sphere with a string too short for it was refused. Found by review.
#[test]
fn regression_a_fixed_spheres_tether_is_ignored() {
    let mut world = World::new(Settings::with_gravity(DVec3::NEG_Y * 9.81));
    let desc = SphereDesc::new(1.0)
        .fixed()
        .tethered(DVec3::ZERO, 1.0)
        .at(DVec3::X * 5.0);
    let id = world.add_sphere(desc).unwrap();
    world.set_position(id, DVec3::X * 7.0).unwrap();
    world.step(1.0 / 60.0).unwrap();
    let body = world.body(id).unwrap();
    assert_eq!((body.position(), body.tether()), (DVec3::X * 7.0, None));
    // A dynamic sphere's tether is still checked.
    let short = SphereDesc::new(1.0)
        .tethered(DVec3::ZERO, 1.0)
        .at(DVec3::X * 5.0);
    assert_eq!(world.add_sphere(short).unwrap_err().field, Field::Tether);
}

/// Regression (found by review of the Bevy plugin): under a gravity that is not finite, every
/// sphere added (or changed) was refused, its force blamed (a force of 0, "with gravity must give
/// a finite acceleration"), so a game that mended its gravity found its spheres gone. The fault
/// is the settings': the sphere is taken, and the step refused, naming gravity, until mended.
#[test]
fn regression_a_sphere_added_under_gravity_not_finite_is_not_blamed() {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, f64::NAN, 0.0)));
    let ball = world
        .add_sphere(SphereDesc::new(0.5).at(DVec3::Y * 10.0))
        .unwrap();
    world.set_force(ball, DVec3::X).unwrap();
    world.set_velocity(ball, DVec3::X).unwrap();
    match world.step(1.0 / 64.0) {
        Err(WorldError::InvalidSetting { field, .. }) => assert_eq!(field, "gravity"),
        other => panic!("expected gravity refused, got {other:?}"),
    }
    assert_eq!(world.steps(), 0);
    // Mended: the sphere falls from where it was put, pushed by its force.
    world.settings_mut().gravity = DVec3::NEG_Y * 8.0;
    world.step(1.0 / 64.0).unwrap();
    let body = world.body(ball).unwrap();
    let mass = body.mass();
    let expected = DVec3::new(1.0 + 1.0 / mass / 64.0, -8.0 / 64.0, 0.0);
    assert!(
        (body.velocity() - expected).length() < 1e-12,
        "{}",
        body.velocity()
    );
    // A finite gravity still blames a force whose sum with it overflows.
    world.settings_mut().gravity = DVec3::X * 1e308;
    let error = world.set_force(ball, DVec3::X * 1e308 * mass).unwrap_err();
    assert!(
        matches!(&error, WorldError::Body(e) if e.field == Field::Force),
        "{error}"
    );
}

/// Regression (found by review of the core's documentation): a step refused because a sphere
/// would leave the finite range gave the sphere's speed as the offending value, where
/// `BodyError::value` is one component of a vector; past about 1.3e154 m/s the speed itself
/// overflowed, and the error said "got inf" of a finite velocity. It gives the fastest
/// component.
#[test]
fn regression_a_refused_step_names_a_component_of_the_velocity() {
    for (velocity, fastest) in [
        (DVec3::new(3.0, -4.0, 0.0), -4.0),
        (DVec3::new(3e200, 4e200, 0.0), 4e200),
    ] {
        let mut world = World::new(Settings::default());
        world
            .add_sphere(
                SphereDesc::new(1.0)
                    .at(DVec3::new(1.7e308, -1.7e308, 0.0))
                    .moving(velocity),
            )
            .unwrap();
        match world.step(1e308) {
            Err(WorldError::Body(error)) => {
                assert_eq!(error.field, Field::Velocity);
                assert_eq!(error.value, fastest, "{error}");
            }
            other => panic!("{velocity}: expected an error, got {other:?}"),
        }
    }
}
