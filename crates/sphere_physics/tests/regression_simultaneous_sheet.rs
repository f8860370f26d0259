//! Regression: a flat sheet of spheres landing at one instant, each on its own fixed sphere,
//! makes one simultaneous group of as many impacts as spheres. Sorting such a group into its
//! independent parts took time quadratic in its size (2.2 s for a 200 × 200 sheet's step,
//! measured; 0.04 s now): found by review. Every impact is still resolved on its own, exactly.

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

#[test]
fn regression_a_sheet_landing_at_one_instant_bounces_exactly() {
    let n = 120;
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    let mut balls = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let floor = DVec3::new(i as f64 * 1.5, 0.0, j as f64 * 1.5);
            world
                .add_sphere(SphereDesc::new(0.5).at(floor).fixed())
                .unwrap();
            let ball = SphereDesc::new(0.5)
                .at(floor + DVec3::Y * 1.05)
                .moving(-DVec3::Y * 6.0);
            balls.push(world.add_sphere(ball).unwrap());
        }
    }
    let stats = *world.step(1.0 / 60.0).unwrap();
    assert_eq!(stats.collisions as usize, n * n);
    assert_eq!(stats.collisions_deferred, 0);
    // All at one instant: every impact at the same time.
    let time = world.collisions()[0].time;
    assert!(world.collisions().iter().all(|c| c.time == time));
    for ball in balls {
        // Elastic, on an immovable sphere, head-on: straight back up at the same speed.
        assert_eq!(world.body(ball).unwrap().velocity(), DVec3::Y * 6.0);
    }
}
