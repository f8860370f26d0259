//! Regression: a scene past the all-pairs size in which no sphere goes to the broad phase's
//! grid (every swept box too long for the grid's cells, or every sphere too far out for its
//! cell coordinates) made the grid's pair scan compute its row offsets for an empty, unpadded
//! block: an integer underflow, a panic in builds with overflow checks. Found by review.

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

/// Steps `world` once and checks that every pair of spheres heading for each other collided.
fn step_and_check(mut world: World, pairs: usize) {
    let stats = *world.step(1.0 / 60.0).unwrap();
    assert_eq!(stats.collisions as usize, pairs);
    assert!(stats.max_overlap <= 1e-9, "{}", stats.max_overlap);
}

#[test]
fn regression_no_sphere_in_the_grid_swept_boxes_along_three_axes() {
    // Twelve pairs along each axis, 600 m/s: each box is 11 m long on its own axis and 1 m on the
    // others, so the median side is 1 m on every axis and no box fits a cell.
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    for (a, axis) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
        for k in 0..12 {
            let centre = DVec3::new(40.0 * k as f64, 40.0 * a as f64, 0.0);
            world
                .add_sphere(
                    SphereDesc::new(0.5)
                        .at(centre - axis * 0.6)
                        .moving(axis * 600.0),
                )
                .unwrap();
            world
                .add_sphere(
                    SphereDesc::new(0.5)
                        .at(centre + axis * 0.6)
                        .moving(-axis * 600.0),
                )
                .unwrap();
        }
    }
    step_and_check(world, 36);
}

#[test]
fn regression_no_sphere_in_the_grid_far_from_the_origin() {
    // Cell coordinates saturate this far out, so no box lies within its cell.
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    for k in 0..35 {
        let centre = DVec3::new(1e10, 100.0 * k as f64, 0.0);
        world
            .add_sphere(
                SphereDesc::new(1.0)
                    .at(centre - DVec3::X * 1.5)
                    .moving(DVec3::X * 60.0),
            )
            .unwrap();
        world
            .add_sphere(
                SphereDesc::new(1.0)
                    .at(centre + DVec3::X * 1.5)
                    .moving(-DVec3::X * 60.0),
            )
            .unwrap();
    }
    step_and_check(world, 35);
}
