//! Regression (found by review): a ball resting on another ball kept the calm it had gathered
//! there when the ball under it was removed, moved away or struck away a step before the two
//! would have fallen asleep together. It fell for that one step, slower than the sleeping
//! speed, and with a fixed peg 1 mm beside it seemed to rest on the peg: it fell asleep in the
//! air, for good. (The same for a fixed support was mended in the fifty-sixth session: see
//! `regression_support_moved_before_sleep.rs`.) Now the awake bodies touching a dynamic body
//! that is added, changed or removed are calm from then on only, as for a fixed one.

mod common;

use sphere_physics::glam::DVec3;
use sphere_physics::{BodyId, SphereDesc, World};

const DT: f64 = 1.0 / 64.0;
const FLOOR: f64 = 1.0e4;

/// Two balls of radius 0.5 (restitution 0.5) stacked on a floor whose top is at y = 0, a
/// fixed peg 1 mm beside the upper one, sleeping on: (world, lower, upper).
fn stacked() -> (World, BodyId, BodyId) {
    let (mut world, _) = common::sleeping_on_a_floor(FLOOR);
    world
        .add_sphere(SphereDesc::new(0.1).fixed().at(DVec3::new(0.601, 1.5, 0.0)))
        .unwrap();
    let ball = |y: f64| {
        SphereDesc::new(0.5)
            .at(DVec3::new(0.0, y, 0.0))
            .with_restitution(0.5)
    };
    let lower = world.add_sphere(ball(0.5)).unwrap();
    let upper = world.add_sphere(ball(1.5)).unwrap();
    (world, lower, upper)
}

/// Steps until the upper ball falls asleep (at most 600); the steps taken.
fn steps_to_sleep(world: &mut World, ball: BodyId) -> u32 {
    for n in 1..=600 {
        world.step(DT).unwrap();
        if world.body(ball).unwrap().is_asleep() {
            return n;
        }
    }
    panic!("the ball never fell asleep: {:?}", world.body(ball))
}

#[test]
fn regression_a_ball_whose_supporting_ball_goes_does_not_sleep_in_the_air() {
    let (mut world, _, upper) = stacked();
    let asleep_at = steps_to_sleep(&mut world, upper);
    for change in [
        "removed",
        "removed with others",
        "moved away",
        "struck away",
        "replaced",
    ] {
        let (mut world, lower, upper) = stacked();
        for _ in 1..asleep_at {
            world.step(DT).unwrap();
        }
        assert!(!world.body(upper).unwrap().is_asleep());
        let far = DVec3::new(5.0, 0.5, 0.0);
        match change {
            "removed" => {
                world.remove_body(lower).unwrap();
            }
            "removed with others" => {
                world.remove_bodies(&[lower]);
            }
            "moved away" => world.set_position(lower, far).unwrap(),
            "struck away" => world
                .set_velocity(lower, DVec3::new(3.0, 0.0, 0.0))
                .unwrap(),
            _ => world.set_desc(lower, SphereDesc::new(0.5).at(far)).unwrap(),
        }
        // Ten steps later it is falling, not asleep in the air.
        for _ in 0..10 {
            world.step(DT).unwrap();
        }
        let body = world.body(upper).unwrap();
        assert!(!body.is_asleep(), "{change}: asleep at {}", body.position());
        // Falling freely since the change (or, struck away, since the lower ball left it):
        // more than 8 cm in 10 steps.
        assert!(body.position().y < 1.42, "{change}: {}", body.position());
        // It lands on the floor, and sleeps there.
        steps_to_sleep(&mut world, upper);
        let y = world.body(upper).unwrap().position().y;
        assert!((y - 0.5).abs() < 1e-2, "{change}: asleep at y = {y}");
    }
}
