//! Regression (found by review in the fifty-seventh session): a finite force on a light
//! sphere (1e10 N on 1e-299 kg) gives an acceleration past an f64's range. It was accepted,
//! and every step from then on was refused, blaming the sphere's velocity. The force is now
//! refused where it is given, and the world steps on.

use sphere_physics::glam::DVec3;
use sphere_physics::{Field, Settings, SphereDesc, World, WorldError};

#[test]
fn regression_a_force_whose_acceleration_overflows_is_refused_where_it_is_given() {
    let light = SphereDesc::new(1.0).with_density(2.4e-300);
    let mut world = World::new(Settings::default());
    let error = world
        .add_sphere(light.clone().with_force(DVec3::X * 1e10))
        .unwrap_err();
    assert_eq!(error.field, Field::Force, "{error}");
    assert!(error.to_string().contains("acceleration"), "{error}");
    // The same sphere without it is taken; the force set on it later is refused, and it keeps
    // the one it had.
    let id = world.add_sphere(light.with_force(DVec3::X)).unwrap();
    match world.set_force(id, DVec3::X * 1e10) {
        Err(WorldError::Body(e)) => assert_eq!(e.field, Field::Force, "{e}"),
        other => panic!("{other:?}"),
    }
    assert_eq!(world.body(id).unwrap().force(), DVec3::X);
    world.step(1.0 / 60.0).unwrap();
    // A fixed sphere has no mass: any finite force is taken (and ignored).
    world
        .add_sphere(
            SphereDesc::new(1.0)
                .with_density(2.4e-300)
                .with_force(DVec3::X * 1e300)
                .fixed()
                .at(DVec3::X * 10.0),
        )
        .unwrap();
    world.step(1.0 / 60.0).unwrap();
}

/// The same with gravity: each within range, their sum past it (found by review of the mend
/// above: every step was still refused, blaming the velocity).
#[test]
fn regression_a_force_and_gravity_whose_sum_overflows_are_refused_where_given() {
    let gravity = DVec3::new(1e308, 0.0, 0.0);
    let mut world = World::new(Settings::with_gravity(gravity));
    // A light sphere (4.2e-10 kg) pushed at 1e308 m/s², with gravity's 1e308 beside it.
    let light = SphereDesc::new(1.0).with_density(1e-10);
    let force = DVec3::X * (1e308 * light.density * 4.0 / 3.0 * std::f64::consts::PI);
    let error = world
        .add_sphere(light.clone().with_force(force))
        .unwrap_err();
    assert_eq!(error.field, Field::Force, "{error}");
    assert!(error.to_string().contains("gravity"), "{error}");
    let id = world.add_sphere(light.clone()).unwrap();
    assert!(matches!(
        world.set_force(id, force),
        Err(WorldError::Body(e)) if e.field == Field::Force
    ));
    let again = light.with_force(force);
    assert!(world.set_desc(id, again).is_err());
    world.step(1e-200).unwrap();
}
