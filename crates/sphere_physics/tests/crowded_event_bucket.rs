//! The step's event queue keeps one bucket of time per few expected events and sorts a bucket
//! when it reaches it. When a crowd of events falls within one bucket (here forty rows of balls
//! struck within four microseconds of each other, in a bucket four hundred microseconds wide)
//! and resolving them makes more in that bucket (each blow passed down a row a microsecond
//! later), the newcomers go to a heap beside the sorted bucket: the collisions must still be
//! resolved in time order, and every row must pass its blow on exactly (one ball in, one out).

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

const DT: f64 = 1.0 / 60.0;
const RADIUS: f64 = 0.1;
const ROWS: usize = 40;
/// Between the balls of a row: a microsecond at the speed of the blow.
const GAP: f64 = 1e-6;
/// Between the rows' first impacts.
const STAGGER: f64 = 1e-7;

#[test]
fn a_crowd_of_impacts_in_one_bucket_is_resolved_in_time_order() {
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    let mut rows = Vec::new();
    for k in 0..ROWS {
        let z = k as f64;
        // Struck at half the step, each row a little later than the one before.
        let first = 0.5 * DT + k as f64 * STAGGER;
        let striker = SphereDesc::new(RADIUS)
            .at(DVec3::new(-2.0 * RADIUS - first, 0.0, z))
            .moving(DVec3::X);
        let ids: Vec<_> = std::iter::once(striker)
            .chain((0..3).map(|b| {
                SphereDesc::new(RADIUS).at(DVec3::new(b as f64 * (2.0 * RADIUS + GAP), 0.0, z))
            }))
            .map(|desc| world.add_sphere(desc).unwrap())
            .collect();
        rows.push(ids);
    }
    let stats = *world.step(DT).unwrap();
    assert_eq!(stats.collisions as usize, 3 * ROWS);
    let times: Vec<f64> = world.collisions().iter().map(|c| c.time).collect();
    assert!(
        times.windows(2).all(|w| w[0] <= w[1]),
        "collisions out of time order: {times:?}"
    );
    for ids in &rows {
        let velocity = |i: usize| world.body(ids[i]).unwrap().velocity();
        for i in 0..3 {
            assert!(velocity(i).length() <= 1e-12, "{}", velocity(i));
        }
        assert!(
            (velocity(3) - DVec3::X).length() <= 1e-12,
            "{}",
            velocity(3)
        );
    }
}
