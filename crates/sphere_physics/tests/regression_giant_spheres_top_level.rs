//! Regression (found by review): the broad phase's hierarchy has 41 levels, cells from the
//! typical box up to 2^40 times it; a sphere larger than that sits on the top level anyway, in
//! a cell smaller than itself. With more than 16 such spheres (fewer are tested directly),
//! pairs whose lower corners lay more than a cell apart were never tested: two of them could
//! pass through each other.

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

/// A world without gravity holding 200 small spheres at rest, which set the typical box
/// (0.1 m): the top level's cells are 0.1 · 2^40 m.
fn small_spheres() -> World {
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    for i in 0..200 {
        let at = DVec3::new(f64::from(i % 10), f64::from(i / 10), 0.0) * 0.5;
        world.add_sphere(SphereDesc::new(0.05).at(at)).unwrap();
    }
    world
}

#[test]
fn regression_spheres_beyond_the_top_level_still_collide() {
    let mut world = small_spheres();
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
        assert!((vl + DVec3::X * 1e6).length() <= 1e-9 * 1e6, "{vl}");
        assert!((vr - DVec3::X * 1e6).length() <= 1e-9 * 1e6, "{vr}");
    }
}

/// The same scale, with a third sphere that only a re-query finds: in each row of three, the
/// right one strikes the middle one, which then strikes the left one, all 1 km apart. The
/// left one lies two top cells below the middle one, beyond the reach a query had.
#[test]
fn regression_a_re_query_finds_spheres_beyond_the_top_level() {
    let mut world = small_spheres();
    let radius = 1e11;
    let spacing = 2.0 * radius + 1000.0;
    let top_cell = 0.1 * 2f64.powi(40);
    let mut rows = Vec::new();
    for k in 0..10 {
        // The left sphere's box starts half a top cell in.
        let left = DVec3::new(0.5 * top_cell + radius, f64::from(k) * 4.0 * radius, 1e13);
        let ids: Vec<_> = (0..3)
            .map(|n| {
                let desc = SphereDesc::new(radius).at(left + DVec3::X * (spacing * f64::from(n)));
                let desc = if n == 2 {
                    desc.moving(-DVec3::X * 1e6)
                } else {
                    desc
                };
                world.add_sphere(desc).unwrap()
            })
            .collect();
        rows.push(ids);
    }
    let stats = *world.step(1.0 / 60.0).unwrap();
    assert_eq!(stats.collisions, 20, "two impacts per row");
    for ids in rows {
        // Equal masses, head-on, elastic: the blow passes along, the left one leaves.
        let v: Vec<DVec3> = ids
            .iter()
            .map(|&id| world.body(id).unwrap().velocity())
            .collect();
        assert!((v[0] + DVec3::X * 1e6).length() <= 1e-9 * 1e6, "{}", v[0]);
        assert!(v[1].length() <= 1e-9 * 1e6, "{}", v[1]);
        assert!(v[2].length() <= 1e-9 * 1e6, "{}", v[2]);
    }
}
