//! A fixed sphere with a velocity is kinematic: it moves through the step at that velocity and
//! pushes what it meets. The pair filter that skips bodies a fixed sphere's ball cannot reach
//! must use the ball swept over the step, not the ball where the step began: a paddle moving
//! at 10 m/s reaches a ball 0.05 m away within the step, though its starting ball misses it.

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

fn paddle_and_ball(extra: usize) -> World {
    let mut world = World::new(Settings::default());
    world
        .add_sphere(
            SphereDesc::new(1.0)
                .fixed()
                .moving(DVec3::new(10.0, 0.0, 0.0)),
        )
        .unwrap();
    world
        .add_sphere(SphereDesc::new(0.05).at(DVec3::new(1.1, 0.0, 0.0)))
        .unwrap();
    // Far-off bystanders, enough for the broad phase's grid to take over.
    for k in 0..extra {
        let p = DVec3::new(-50.0 - k as f64, 30.0, 0.0);
        world.add_sphere(SphereDesc::new(0.05).at(p)).unwrap();
    }
    world
}

#[test]
fn regression_a_moving_fixed_sphere_hits_what_its_start_misses() {
    for extra in [0, 80] {
        let mut world = paddle_and_ball(extra);
        let stats = *world.step(1.0 / 60.0).unwrap();
        assert_eq!(stats.collisions, 1, "with {extra} bystanders");
        let ball = &world.bodies()[1];
        // Elastic (restitution 1) off an infinite mass moving at 10: the ball leaves at 20.
        assert!(
            (ball.velocity().x - 20.0).abs() < 1e-9,
            "with {extra} bystanders: {:?}",
            ball.velocity()
        );
        assert!(stats.max_overlap <= 1e-9, "overlap {}", stats.max_overlap);
    }
}
