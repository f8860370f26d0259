//! Regression (found by `changes_between_steps.rs`): a step whose resting solve pushed a body
//! out of an overlap reported a kinetic energy and momentum that differed from the bodies' in
//! the last bits (here from the first step, a ball placed 0.3 m deep in the floor of a pit; up
//! to 1.6e-12 of the energy in the cases the property test found): the pushes were taken off
//! the sums as differences, exact only to the rounding of what the pushed body had before. The
//! step's sums now equal `World::kinetic_energy` and `World::momentum` to the bit.

mod common;

use sphere_physics::glam::DVec3;

#[test]
fn regression_step_sums_after_pushes_match_the_bodies() {
    let mut world = common::pit(5, 0, 0.0, 0.05, 1.0);
    let ball = world.bodies()[5].id();
    assert!(!world.body(ball).unwrap().is_fixed());
    // 0.3 m into the floor (a fixed sphere of radius 1e4 whose top is at y = 0).
    world
        .set_position(
            ball,
            DVec3::new(0.19672622307109147, -0.2992829634594084, 0.0),
        )
        .unwrap();
    for step in 0..60 {
        let stats = *world.step(1.0 / 60.0).unwrap();
        assert_eq!(stats.kinetic_energy, world.kinetic_energy(), "step {step}");
        assert_eq!(stats.momentum, world.momentum(), "step {step}");
    }
    // It is being moved out, by positions, and stays in the pit.
    let at = world.body(ball).unwrap().position();
    assert!(at.y > -0.3 && at.y < 0.0, "{at}");
}
