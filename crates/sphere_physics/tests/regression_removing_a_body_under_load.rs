//! Removing a body between steps while bodies rest on others panicked at the next step (an
//! index out of bounds): the solver kept, by body index, which bodies had rested in the last
//! step, and a removal moves every later body down one index. The Bevy plugin removes a
//! sphere's body whenever its entity is despawned, so despawning a sphere in a pile crashed
//! the game.

use sphere_physics::{BodyId, Settings, SphereDesc, World, glam::DVec3};

const DT: f64 = 1.0 / 60.0;

fn world_with_floor() -> (World, BodyId) {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    let floor = world
        .add_sphere(
            SphereDesc::new(1.0e4)
                .at(DVec3::new(0.0, -1.0e4, 0.0))
                .fixed(),
        )
        .unwrap();
    (world, floor)
}

#[test]
fn regression_removing_the_floor_under_a_resting_ball() {
    let (mut world, floor) = world_with_floor();
    let ball = world
        .add_sphere(SphereDesc::new(0.5).at(DVec3::new(0.0, 0.5, 0.0)))
        .unwrap();
    for _ in 0..10 {
        world.step(DT).unwrap();
    }
    let before = world.body(ball).unwrap().clone();
    assert!(
        before.velocity().length() < 1e-9,
        "at rest: {}",
        before.velocity()
    );
    world.remove_body(floor).unwrap();
    world.step(DT).unwrap();
    // Free fall from rest, semi-implicit Euler's first step: down by g·dt².
    let fell = before.position().y - world.body(ball).unwrap().position().y;
    assert!((fell - 9.81 * DT * DT).abs() < 1e-9, "fell {fell}");
}

#[test]
fn regression_removing_one_of_a_row_resting_on_the_floor() {
    let (mut world, _) = world_with_floor();
    let balls: Vec<_> = (0..3)
        .map(|i| {
            let x = 1.5 * f64::from(i) - 1.5;
            let ball = SphereDesc::new(0.5)
                .at(DVec3::new(x, 0.5, 0.0))
                .with_restitution(0.5);
            world.add_sphere(ball).unwrap()
        })
        .collect();
    for _ in 0..30 {
        world.step(DT).unwrap();
    }
    world.remove_body(balls[0]).unwrap();
    for _ in 0..30 {
        world.step(DT).unwrap();
    }
    // The two left still rest on the floor where they were.
    for (&ball, x) in balls[1..].iter().zip([0.0, 1.5]) {
        let p = world.body(ball).unwrap().position();
        assert!((p - DVec3::new(x, 0.5, 0.0)).length() < 1e-3, "{p}");
    }
}
