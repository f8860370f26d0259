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

#[test]
fn regression_a_ball_whose_supporting_ball_goes_does_not_sleep_in_the_air() {
    let (mut world, _, upper) = stacked();
    let asleep_at = common::steps_to_sleep(&mut world, upper, DT);
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
        common::steps_to_sleep(&mut world, upper, DT);
        let y = world.body(upper).unwrap().position().y;
        assert!((y - 0.5).abs() < 1e-2, "{change}: asleep at y = {y}");
    }
}

#[test]
fn regression_a_ball_whose_support_goes_while_sleeping_is_off_does_not_sleep_in_the_air() {
    // Found by review of the mend: the places were kept only with sleeping on, so a ball
    // removed while sleeping was off (and on again before the next step) left the ball on it
    // its calm.
    let (mut world, _, upper) = stacked();
    let asleep_at = common::steps_to_sleep(&mut world, upper, DT);
    let (mut world, lower, upper) = stacked();
    for _ in 1..asleep_at {
        world.step(DT).unwrap();
    }
    let sleep = world.settings().sleep;
    world.settings_mut().sleep = None;
    world.remove_body(lower).unwrap();
    world.settings_mut().sleep = sleep;
    for _ in 0..10 {
        world.step(DT).unwrap();
    }
    let body = world.body(upper).unwrap();
    assert!(!body.is_asleep(), "asleep at {}", body.position());
    assert!(body.position().y < 1.42, "{}", body.position());
}

#[test]
fn regression_many_changes_between_steps_disturb_only_what_they_touch() {
    // Found by review of the mend: past one place per body (a ball moved and given a velocity
    // leaves three: where it was, where it is, and again for the velocity), every awake
    // body's calm started again at every step, so that steering a few hundred balls kept
    // every other from ever falling asleep. And with many places, the ball on a support
    // taken away is still found among them.
    let (mut world, lower, upper) = stacked();
    let asleep_at = {
        let (mut twin, _, upper) = stacked();
        common::steps_to_sleep(&mut twin, upper, DT)
    };
    // Forty balls resting apart on the floor, and 300 steered in a row far from them.
    let resting: Vec<BodyId> = (0..40)
        .map(|i| {
            let (x, z) = (-5.0 - f64::from(i % 8), f64::from(i / 8));
            // On the floor's curved top.
            let y = ((FLOOR + 0.1).powi(2) - x * x - z * z).sqrt() - FLOOR;
            let ball = SphereDesc::new(0.1)
                .at(DVec3::new(x, y, z))
                .with_restitution(0.5);
            world.add_sphere(ball).unwrap()
        })
        .collect();
    let steered: Vec<BodyId> = (0..300)
        .map(|i| {
            let at = DVec3::new(20.0 + 0.3 * f64::from(i), 0.1, 0.0);
            world.add_sphere(SphereDesc::new(0.1).at(at)).unwrap()
        })
        .collect();
    let steer = |world: &mut World| {
        for &id in &steered {
            let body = world.body(id).unwrap();
            let (at, v) = (body.position(), body.velocity());
            world.set_position(id, at).unwrap();
            world.set_velocity(id, v).unwrap();
        }
    };
    for step in 1..asleep_at {
        steer(&mut world);
        world.step(DT).unwrap();
        assert!(!world.body(upper).unwrap().is_asleep(), "step {step}");
    }
    // Taken away among the steering: the ball on it does not sleep in the air.
    steer(&mut world);
    world.remove_body(lower).unwrap();
    for _ in 0..10 {
        steer(&mut world);
        world.step(DT).unwrap();
    }
    let body = world.body(upper).unwrap();
    assert!(!body.is_asleep(), "asleep at {}", body.position());
    assert!(body.position().y < 1.42, "{}", body.position());
    // The resting balls, touching nothing steered, fall asleep as they would alone.
    for _ in 0..2 * asleep_at {
        steer(&mut world);
        world.step(DT).unwrap();
    }
    for &id in &resting {
        assert!(world.body(id).unwrap().is_asleep(), "{:?}", world.body(id));
    }
}

#[test]
fn regression_a_support_taken_away_while_sleeping_is_off_then_a_step_refused_leaves_no_calm() {
    // Found by review of the second mend: a step refused with sleeping off forgot the places
    // (and put the calms back), and a fixed support removed with sleeping off (nothing
    // asleep) reset no calm; sleeping on again, the ball on it fell asleep in the air.
    let (mut world, _, upper) = stacked();
    let asleep_at = common::steps_to_sleep(&mut world, upper, DT);
    for support in ["the floor", "the lower ball"] {
        let (mut world, lower, upper) = stacked();
        for _ in 1..asleep_at {
            world.step(DT).unwrap();
        }
        let sleep = world.settings().sleep;
        world.settings_mut().sleep = None;
        let taken = if support == "the floor" {
            let floor = world.bodies().iter().find(|b| b.radius() == FLOOR);
            floor.unwrap().id()
        } else {
            lower
        };
        world.remove_body(taken).unwrap();
        // A sphere far away at 1e308 m/s: a step of 2 s would take it past the finite range.
        let runaway = world
            .add_sphere(
                SphereDesc::new(0.1)
                    .at(DVec3::new(1.0e6, 0.0, 0.0))
                    .moving(DVec3::new(1.0e308, 0.0, 0.0)),
            )
            .unwrap();
        assert!(world.step(2.0).is_err(), "{support}: the step is refused");
        world.remove_body(runaway).unwrap();
        world.settings_mut().sleep = sleep;
        for _ in 0..10 {
            world.step(DT).unwrap();
        }
        let body = world.body(upper).unwrap();
        assert!(
            !body.is_asleep(),
            "{support}: asleep at {}",
            body.position()
        );
        assert!(body.position().y < 1.42, "{support}: {}", body.position());
    }
}
