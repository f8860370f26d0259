//! Regression: a step refused part-way (a sphere would leave the finite range) left traces
//! that later steps showed, though its bodies were put back as they were:
//! - With sleeping on and gravity changed since the last step, the step woke every sphere
//!   before it was refused: spheres asleep were awake after it, their calm started again.
//! - A step refused after its resting solve kept that solve's loads (the next step's warm
//!   start) and the bodies it found resting, so the steps after it differed in their last
//!   bits from those of a world that never took the refused call.
//!
//! Found by review. Each test plays the same calls on two worlds, one of them also making the
//! refused step, and then holds the two to the same bodies, bit for bit.

mod common;

use sphere_physics::glam::DVec3;
use sphere_physics::{BodyId, Sleep, SphereDesc, World, WorldError};

const DT: f64 = 1.0 / 60.0;

/// Every body's state (and whether it sleeps), the clock and the last step's statistics.
fn state(world: &World) -> String {
    let asleep: Vec<bool> = world.bodies().iter().map(|b| b.is_asleep()).collect();
    format!(
        "{:?} {:?} {} {:?}",
        world.bodies(),
        asleep,
        world.time(),
        world.stats()
    )
}

/// A pit of 30 spheres after two seconds, with sleeping on or off.
fn settled_pit(sleep: bool) -> World {
    let mut world = common::pit(30, 7, 0.3, 0.05, 1.0);
    world.settings_mut().sleep = sleep.then(Sleep::default);
    for _ in 0..120 {
        world.step(DT).unwrap();
    }
    world
}

/// A fixed sphere of the pit's size at `at`, moving along x at `speed`.
fn add_runaway(world: &mut World, at: DVec3, speed: f64) -> BodyId {
    world
        .add_sphere(
            SphereDesc::new(0.05)
                .fixed()
                .at(at)
                .moving(DVec3::new(speed, 0.0, 0.0)),
        )
        .unwrap()
}

#[test]
fn regression_a_refused_step_leaves_sleeping_spheres_asleep() {
    let (mut world, mut twin) = (settled_pit(true), settled_pit(true));
    for _ in 0..240 {
        world.step(DT).unwrap();
        twin.step(DT).unwrap();
    }
    let asleep = |w: &World| w.bodies().iter().filter(|b| b.is_asleep()).count();
    assert_eq!(asleep(&world), 30, "the pit must be asleep first");
    let gravity = world.settings().gravity;
    for w in [&mut world, &mut twin] {
        w.settings_mut().gravity = gravity * 1.5;
    }
    // Far from the pit, at 1e308 m/s: its drift over 2 s would be infinite.
    let far = DVec3::new(1.0e6, 0.0, 0.0);
    let runaway = add_runaway(&mut world, far, 1.0e308);
    assert!(matches!(world.step(2.0), Err(WorldError::Body(_))));
    assert_eq!(asleep(&world), 30, "a refused step woke the pit");
    add_runaway(&mut twin, far, 1.0e308);
    for w in [&mut world, &mut twin] {
        w.settings_mut().gravity = gravity;
        w.set_velocity(runaway, DVec3::ZERO).unwrap();
    }
    assert_eq!(state(&world), state(&twin));
    for _ in 0..30 {
        world.step(DT).unwrap();
        twin.step(DT).unwrap();
    }
    assert_eq!(asleep(&world), 30);
    assert_eq!(state(&world), state(&twin));
}

#[test]
fn regression_a_step_refused_after_its_resting_solve_changes_no_later_step() {
    let (mut world, mut twin) = (settled_pit(false), settled_pit(false));
    // Beside the pit's highest sphere, at the largest finite speed towards it: the sphere would
    // leave at an infinite speed, so the step is refused after its resting contacts were
    // solved.
    let top = world
        .bodies()
        .iter()
        .filter(|b| !b.is_fixed())
        .max_by(|a, b| a.position().y.total_cmp(&b.position().y))
        .unwrap()
        .position();
    let at = top - DVec3::new(0.1005, 0.0, 0.0);
    let runaway = add_runaway(&mut world, at, f64::MAX);
    assert!(matches!(world.step(DT), Err(WorldError::Body(_))));
    add_runaway(&mut twin, at, f64::MAX);
    for w in [&mut world, &mut twin] {
        w.set_velocity(runaway, DVec3::ZERO).unwrap();
    }
    assert_eq!(state(&world), state(&twin));
    for step in 0..60 {
        world.step(DT).unwrap();
        twin.step(DT).unwrap();
        assert_eq!(
            state(&world),
            state(&twin),
            "step {step} after the refused one"
        );
    }
}
