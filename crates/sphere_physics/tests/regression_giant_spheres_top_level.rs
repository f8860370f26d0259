//! Regression (found by review): the broad phase's hierarchy has 41 levels, cells from the
//! typical box up to 2^40 times it; a sphere larger than that sits on the top level anyway, in
//! a cell smaller than itself. With more than 16 such spheres (fewer are tested directly),
//! pairs whose lower corners lay more than a cell apart were never tested: two of them could
//! pass through each other.

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

#[test]
fn regression_spheres_beyond_the_top_level_still_collide() {
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    // Small spheres set the typical box (0.1 m): the top level's cells are 0.1 · 2^40 m.
    for i in 0..200 {
        let at = DVec3::new(f64::from(i % 10), f64::from(i / 10), 0.0) * 0.5;
        world.add_sphere(SphereDesc::new(0.05).at(at)).unwrap();
    }
    // Twenty spheres of radius 1e11 m (boxes of 2e11 m, more than the top cell's 1.1e11 m)
    // in pairs along x, each pair 1 km apart and closing at 2e6 m/s: they meet 5e-4 s in.
    let radius = 1e11;
    let half = radius + 500.0;
    // The left sphere's box starts half a top cell in, so the right one's starts two top
    // cells further on: not neighbouring cells.
    let top_cell = 0.1 * 2f64.powi(40);
    let far = DVec3::new(0.5 * top_cell + radius + half, 0.0, 1e13);
    let mut pairs = Vec::new();
    for k in 0..10 {
        let centre = far + DVec3::new(0.0, f64::from(k) * 4.0 * radius, 0.0);
        let left = world
            .add_sphere(
                SphereDesc::new(radius)
                    .at(centre - DVec3::X * half)
                    .moving(DVec3::X * 1e6),
            )
            .unwrap();
        let right = world
            .add_sphere(
                SphereDesc::new(radius)
                    .at(centre + DVec3::X * half)
                    .moving(-DVec3::X * 1e6),
            )
            .unwrap();
        pairs.push((left, right));
    }
    let stats = *world.step(1.0 / 60.0).unwrap();
    assert_eq!(stats.collisions, 10, "one impact per pair");
    for (left, right) in pairs {
        // Equal masses, head-on, elastic: they swap velocities.
        let (vl, vr) = (
            world.body(left).unwrap().velocity(),
            world.body(right).unwrap().velocity(),
        );
        assert!((vl + DVec3::X * 1e6).length() <= 1e-6 * 1e6, "{vl}");
        assert!((vr - DVec3::X * 1e6).length() <= 1e-6 * 1e6, "{vr}");
    }
}
