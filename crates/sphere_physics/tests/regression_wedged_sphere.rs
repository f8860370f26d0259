//! Regression: a sphere wedged between two fixed spheres it overlaps (a spawn inside a gap
//! too narrow for it) bounces between them at one instant without end. It used to spend the
//! whole world's collision budget on that every step, so every other collision in the world
//! was deferred: spheres elsewhere passed through each other. Found by review. Now one body
//! takes at most 256 times `max_collisions_per_body` collisions in a step (4096 at the default
//! of 16; 64 times until 2026-12-06; in a world with strings a quarter of the world's budget,
//! from 64 to 256 times). Since 2026-12-04 a body past that share is first solved at once
//! with every contact touching it (restitution 0, a few times at most: see
//! `regression_light_sphere_squeezed.rs`), and only then are its impacts deferred: the wedged
//! ball stops between the fixed spheres. In a world whose budget is below one body's share
//! the budget runs out first, and the fallback stops the ball.

use sphere_physics::{BodyId, Settings, SphereDesc, World, glam::DVec3};

/// Elsewhere in the world, `count` head-on pairs that meet within the first step.
fn add_head_on_pairs(world: &mut World, count: u32) -> Vec<(BodyId, BodyId)> {
    (0..count)
        .map(|k| {
            let centre = DVec3::new(10.0 + 3.0 * k as f64, 0.0, 0.0);
            let [a, b] = [-1.0, 1.0].map(|side| {
                let ball = SphereDesc::new(0.5)
                    .at(centre + DVec3::Y * (0.51 * side))
                    .moving(-DVec3::Y * side);
                world.add_sphere(ball).unwrap()
            });
            (a, b)
        })
        .collect()
}

/// Equal masses, elastic, head-on: every pair's velocities are exchanged.
fn assert_exchanged(world: &World, pairs: &[(BodyId, BodyId)]) {
    for &(a, b) in pairs {
        assert_eq!(world.body(a).unwrap().velocity(), -DVec3::Y);
        assert_eq!(world.body(b).unwrap().velocity(), DVec3::Y);
    }
}

/// Enough pairs that the world's budget (16 collisions a dynamic body: 6416) exceeds one
/// body's share (4096) and the other collisions of the step.
const PAIRS: u32 = 200;

/// A world with a ball of radius 0.5 wedged between fixed spheres at x = -1 and x = 1, moving.
fn wedged_world() -> (World, BodyId) {
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    // The wedge: fixed spheres at x = -1 and x = 1, a ball of radius 0.5 between them, moving.
    world
        .add_sphere(SphereDesc::new(1.0).at(DVec3::new(-1.0, 0.0, 0.0)).fixed())
        .unwrap();
    world
        .add_sphere(SphereDesc::new(1.0).at(DVec3::new(1.0, 0.0, 0.0)).fixed())
        .unwrap();
    let wedged = world
        .add_sphere(SphereDesc::new(0.5).moving(DVec3::X))
        .unwrap();
    (world, wedged)
}

#[test]
fn regression_a_wedged_sphere_does_not_stop_the_rest_of_the_world() {
    let (mut world, wedged) = wedged_world();
    let pairs = add_head_on_pairs(&mut world, PAIRS);
    let stats = *world.step(1.0 / 60.0).unwrap();
    assert_exchanged(&world, &pairs);
    // The wedged ball's bounces were cut off at its share, where it was squeezed to rest
    // between the two, and the step went on.
    let share = 256 * world.settings().max_collisions_per_body;
    assert!(stats.collisions >= share + PAIRS, "{stats:?}");
    assert!(!stats.fell_back, "{stats:?}");
    let velocity = world.body(wedged).unwrap().velocity();
    assert!(velocity.length() <= 1e-12, "{velocity}");
}

#[test]
fn regression_a_wedged_sphere_does_not_stop_the_rest_of_a_small_world() {
    let (mut world, wedged) = wedged_world();
    let pairs = add_head_on_pairs(&mut world, 40);
    let stats = *world.step(1.0 / 60.0).unwrap();
    assert_exchanged(&world, &pairs);
    // 81 dynamic bodies: the world's budget, 1296, ran out before the ball's share, and the
    // fallback stopped the ball.
    assert!(stats.fell_back, "{stats:?}");
    let velocity = world.body(wedged).unwrap().velocity();
    assert!(velocity.length() <= 1e-12, "{velocity}");
}

#[test]
fn regression_a_sphere_pressed_by_a_kinematic_one_does_not_stop_the_rest_of_the_world() {
    // A kinematic paddle closes on a ball resting against a fixed wall: the ball bounces
    // between them at ever closer times (not one instant), as often as the budget allows.
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    world
        .add_sphere(SphereDesc::new(1.0).at(DVec3::new(2.0, 0.0, 0.0)).fixed())
        .unwrap();
    world
        .add_sphere(SphereDesc::new(0.5).at(DVec3::new(0.5, 0.0, 0.0)))
        .unwrap();
    world
        .add_sphere(
            SphereDesc::new(1.0)
                .at(DVec3::new(-1.0, 0.0, 0.0))
                .fixed()
                .moving(DVec3::X),
        )
        .unwrap();
    let pairs = add_head_on_pairs(&mut world, PAIRS);
    let stats = *world.step(1.0 / 60.0).unwrap();
    assert_exchanged(&world, &pairs);
    assert!(stats.collisions_deferred > 0, "{stats:?}");
}
