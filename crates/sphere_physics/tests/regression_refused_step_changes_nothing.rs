//! Regression: a step that is refused part-way (a sphere would leave the finite range) changes
//! nothing. With substeps, the substeps before the refused one had already written the bodies
//! back, so the bodies moved while the clock, the step count and the statistics did not; and
//! the collision list kept the records of the refused step (one with an infinite impulse that
//! was never applied). Found by review.

use sphere_physics::{Settings, SphereDesc, World, WorldError, glam::DVec3};

#[test]
fn regression_a_step_refused_in_a_later_substep_leaves_the_bodies_as_they_were() {
    let mut world = World::new(Settings {
        substeps: 2,
        ..Settings::default()
    });
    world
        .add_sphere(SphereDesc::new(0.5).moving(DVec3::new(1e308, 0.0, 0.0)))
        .unwrap();
    world
        .add_sphere(
            SphereDesc::new(0.5)
                .at(DVec3::new(0.0, 5.0, 0.0))
                .moving(DVec3::Y),
        )
        .unwrap();
    let before = world.bodies().to_vec();
    // The first substep (1 s) reaches x = 1e308; the second would reach 2e308.
    assert!(matches!(world.step(2.0), Err(WorldError::Body(_))));
    assert_eq!(world.bodies(), &before[..]);
    assert_eq!((world.time(), world.steps()), (0.0, 0));
    // Not poisoned: a sane step from the same state moves both.
    world.step(0.5).unwrap();
    assert!(world.bodies()[1].position().y > 5.0);
}

#[test]
fn regression_a_refused_step_leaves_no_collision_records() {
    let mut world = World::new(Settings::default());
    // A kinematic sphere near the largest finite speed strikes a ball: the ball would leave at
    // an infinite speed, so the step is refused after the impact was computed.
    world
        .add_sphere(
            SphereDesc::new(1.0)
                .fixed()
                .moving(DVec3::new(1e308, 0.0, 0.0)),
        )
        .unwrap();
    world
        .add_sphere(SphereDesc::new(1.0).at(DVec3::new(2.05, 0.0, 0.0)))
        .unwrap();
    assert!(world.step(1.0 / 60.0).is_err());
    assert!(world.collisions().is_empty(), "{:?}", world.collisions());
}

/// Regression: a refused step emptied `World::collisions` and reset `World::profile` while
/// `World::stats` still told of the step before, so `stats().collisions` counted records that
/// were gone. Now all three still tell of the last step taken. Found by review.
#[test]
fn regression_a_refused_step_keeps_the_last_steps_records_and_stats() {
    let mut world = World::new(Settings::default());
    world.set_profiling(true);
    let a = world
        .add_sphere(SphereDesc::new(0.5).moving(DVec3::X))
        .unwrap();
    world
        .add_sphere(SphereDesc::new(0.5).at(DVec3::new(1.01, 0.0, 0.0)))
        .unwrap();
    world.step(1.0 / 60.0).unwrap();
    let (stats, collisions, profile) = (
        *world.stats(),
        world.collisions().to_vec(),
        *world.profile().unwrap(),
    );
    assert_eq!(collisions.len(), 1);
    assert_eq!(stats.collisions, 1);
    // Now a force no long step can take: in 100 s the first sphere would reach an infinite
    // speed (its acceleration, 3.4e307 m/s², is finite: a force whose acceleration is not is
    // refused where it is given).
    world
        .set_force(a, DVec3::new(f64::MAX / 10.0, 0.0, 0.0))
        .unwrap();
    assert!(matches!(world.step(100.0), Err(WorldError::Body(_))));
    assert_eq!(*world.stats(), stats);
    assert_eq!(world.collisions(), &collisions[..]);
    assert_eq!(*world.profile().unwrap(), profile);
}
