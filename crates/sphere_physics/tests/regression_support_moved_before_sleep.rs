//! Regression (found by review): a ball resting on a fixed floor kept the calm it had gathered
//! there when the floor was moved away (or removed) a step before the ball would have fallen
//! asleep. It fell that one step, still slower than the sleeping speed and still near enough
//! to the floor's new place to seem to rest on it, and fell asleep in the air, for good. Now
//! the awake bodies touching a fixed sphere that is moved, changed or removed are calm from
//! then on only.

mod common;

use sphere_physics::glam::DVec3;
use sphere_physics::{BodyId, SphereDesc, World};

const DT: f64 = 1.0 / 64.0;
const FLOOR: f64 = 1.0e4;

/// A ball of radius 0.5 (restitution 0.5) resting on a floor whose top is at y = 0, a fixed
/// peg just beside it, sleeping on.
fn ball_on_floor() -> (World, BodyId, BodyId) {
    let (mut world, floor) = common::sleeping_on_a_floor(FLOOR);
    // A peg 1 mm from the ball's side.
    world
        .add_sphere(SphereDesc::new(0.1).fixed().at(DVec3::new(0.601, 0.5, 0.0)))
        .unwrap();
    let ball = world
        .add_sphere(
            SphereDesc::new(0.5)
                .at(DVec3::new(0.0, 0.5, 0.0))
                .with_restitution(0.5),
        )
        .unwrap();
    (world, floor, ball)
}

#[test]
fn regression_a_ball_whose_floor_moves_away_does_not_sleep_in_the_air() {
    let (mut world, _, ball) = ball_on_floor();
    let asleep_at = common::steps_to_sleep(&mut world, ball, DT);
    for change in ["moved down 1 cm", "removed"] {
        let (mut world, floor, ball) = ball_on_floor();
        for _ in 1..asleep_at {
            world.step(DT).unwrap();
        }
        assert!(!world.body(ball).unwrap().is_asleep());
        let place = world.body(floor).unwrap().position();
        if change == "removed" {
            world.remove_body(floor).unwrap();
        } else {
            world
                .set_position(floor, place - DVec3::new(0.0, 0.01, 0.0))
                .unwrap();
        }
        // Ten steps later it is falling, not asleep in the air.
        for _ in 0..10 {
            world.step(DT).unwrap();
        }
        let body = world.body(ball).unwrap();
        assert!(!body.is_asleep(), "{change}: asleep at {}", body.position());
        if change == "moved down 1 cm" {
            // It lands on the floor's new place, and sleeps there.
            common::steps_to_sleep(&mut world, ball, DT);
            let y = world.body(ball).unwrap().position().y;
            assert!((y - 0.49).abs() < 1e-3, "asleep at y = {y}");
        } else {
            // Falling freely: 12 cm in 10 steps (g t² / 2).
            assert!(body.position().y < 0.4, "{change}: {}", body.position());
        }
    }
}
