//! Regression: a flat sheet of spheres landing at one instant, each on its own fixed sphere,
//! makes one simultaneous group of as many impacts as spheres. Sorting such a group into its
//! independent parts took time quadratic in its size (2.2 s for a 200 × 200 sheet's step,
//! measured; 0.04 s now): found by review. Every impact is still resolved on its own, exactly.

mod common;

use sphere_physics::glam::DVec3;

#[test]
fn regression_a_sheet_landing_at_one_instant_bounces_exactly() {
    let n = 120;
    let (mut world, balls) = common::sheet_over_floors(n, DVec3::ZERO, 1.05, -DVec3::Y * 6.0);
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
