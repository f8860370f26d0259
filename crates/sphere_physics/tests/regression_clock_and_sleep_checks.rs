//! Regressions found by review of the world's bookkeeping:
//! - A time step of `f64::MAX` is a normal number and was taken: two of them sent the world's
//!   clock (and every later collision's time) to infinity. A step that would take the clock
//!   past the largest finite time is now refused, and changes nothing.
//! - A step too small against the clock to advance it (1 s after a step of 1e300 s) was taken:
//!   the spheres moved while the clock stood still. It is refused now, and changes nothing.
//! - When groups are next checked for sleep was set from `Sleep::time` at the last check and
//!   kept when `Sleep::time` was then shortened: a group calm for the new time waited up to a
//!   quarter of the old one (25 s after 100 s) to fall asleep. It now falls asleep within a
//!   quarter of the time in force.

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, Sleep, SphereDesc, World, WorldError};

#[test]
fn regression_a_step_that_would_make_the_clock_infinite_is_refused() {
    let mut world = World::new(Settings {
        gravity: DVec3::ZERO,
        ..Settings::default()
    });
    world.add_sphere(SphereDesc::new(1.0)).unwrap();
    world.step(f64::MAX).unwrap();
    assert_eq!(world.time(), f64::MAX);
    let before = format!("{:?} {:?}", world.bodies(), world.stats());
    assert_eq!(
        world.step(f64::MAX).err(),
        Some(WorldError::InvalidTimeStep(f64::MAX))
    );
    assert_eq!(world.time(), f64::MAX);
    assert_eq!(world.steps(), 1);
    assert_eq!(format!("{:?} {:?}", world.bodies(), world.stats()), before);
}

#[test]
fn regression_a_step_that_would_not_advance_the_clock_is_refused() {
    let mut world = World::new(Settings {
        gravity: DVec3::ZERO,
        ..Settings::default()
    });
    world
        .add_sphere(SphereDesc::new(1.0).moving(DVec3::new(1e-300, 0.0, 0.0)))
        .unwrap();
    world.step(1e300).unwrap();
    assert_eq!(world.time(), 1e300);
    let before = format!("{:?} {:?}", world.bodies(), world.stats());
    assert_eq!(
        world.step(1.0).err(),
        Some(WorldError::InvalidTimeStep(1.0))
    );
    assert_eq!(world.time(), 1e300);
    assert_eq!(world.steps(), 1);
    assert_eq!(format!("{:?} {:?}", world.bodies(), world.stats()), before);
    // A step of the clock's last bit does advance it, and is taken.
    let last_bit = 1e300 - f64::from_bits(1e300f64.to_bits() - 1);
    world.step(last_bit).unwrap();
    assert!(world.time() > 1e300);
    assert_eq!(world.steps(), 2);
}

#[test]
fn regression_a_shorter_sleeping_time_takes_effect_at_once() {
    let mut world = World::new(Settings {
        sleep: Some(Sleep {
            speed: 0.2,
            time: 100.0,
        }),
        ..Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0))
    });
    // A floor whose top is at y = 0.
    world
        .add_sphere(SphereDesc::new(1e4).fixed().at(DVec3::new(0.0, -1e4, 0.0)))
        .unwrap();
    let first = world
        .add_sphere(SphereDesc::new(0.5).at(DVec3::new(0.0, 0.5, 0.0)))
        .unwrap();
    let dt = 1.0 / 60.0;
    // The first ball falls asleep after 100 s calm, and the groups are next checked 25 s on.
    let mut steps = 0;
    while !world.body(first).unwrap().is_asleep() {
        world.step(dt).unwrap();
        steps += 1;
        assert!(
            steps < 7000,
            "the first ball never fell asleep: {:?}",
            world.body(first)
        );
    }
    let second = world
        .add_sphere(SphereDesc::new(0.5).at(DVec3::new(5.0, 0.5, 0.0)))
        .unwrap();
    world.settings_mut().sleep = Some(Sleep {
        speed: 0.2,
        time: 1.0,
    });
    // Calm for 1 s, then checked within a quarter of it (a step or two of slack).
    for _ in 0..(1.25f64 / dt).ceil() as usize + 2 {
        world.step(dt).unwrap();
    }
    assert!(world.body(second).unwrap().is_asleep());
    assert!(world.body(first).unwrap().is_asleep());
}
