//! A sphere much larger than the rest lives outside the broad phase's grid; when a collision
//! changes its path, it asks the grid again for everything its box meets: over a hundred rows
//! of cells, which the grid reads a batch at a time. A sphere in any of those rows must still
//! be found.
//!
//! A big sphere moving along +x strikes a small one dead ahead, then, a moment later, a second
//! one ahead of it and below (at low z, where the grid's rows are read first). Only the query
//! made after the first impact can find the second (the first pass found it with the old path).

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

const SMALL: f64 = 0.05;
const BIG: f64 = 0.5;
const SPEED: f64 = 3.0;
const DT: f64 = 1.0 / 60.0;

#[test]
fn a_large_sphere_finds_a_small_one_after_changing_course() {
    let mut world = World::new(Settings::default());
    let big = world
        .add_sphere(SphereDesc::new(BIG).moving(DVec3::X * SPEED))
        .unwrap();
    // Dead ahead, 0.01 m from the big sphere's surface: struck at 0.01 / 3 s.
    let first = world
        .add_sphere(SphereDesc::new(SMALL).at(DVec3::X * (BIG + SMALL + 0.01)))
        .unwrap();
    // Ahead and below, 0.01 m from its surface along the line of centres, which the big
    // sphere closes at about 3 cos 60° = 1.5 m/s: struck at about 0.0067 s, after the first.
    let below = DVec3::new(0.5, 0.0, -(3.0f64.sqrt()) / 2.0);
    let second = world
        .add_sphere(SphereDesc::new(SMALL).at(below * (BIG + SMALL + 0.01)))
        .unwrap();
    // Enough small spheres at rest beside them that the grid's cells are small-sphere sized
    // and the big sphere's query reads rows of cells rather than every grid body.
    for i in 0..13 {
        for j in 0..14 {
            for k in 0..14 {
                let at = DVec3::new(
                    2.0 + 0.15 * f64::from(i),
                    -1.0 + 0.15 * f64::from(j),
                    -1.0 + 0.15 * f64::from(k),
                );
                world.add_sphere(SphereDesc::new(SMALL).at(at)).unwrap();
            }
        }
    }
    let stats = *world.step(DT).unwrap();
    let collisions = world.collisions();
    assert_eq!(collisions.len(), 2, "{collisions:?}");
    assert_eq!((collisions[0].a, collisions[0].b), (big, first));
    let struck = collisions[1];
    assert_eq!((struck.a, struck.b), (big, second));
    assert!(struck.time > collisions[0].time);
    // Struck along the line of centres, which points ahead and below.
    assert!(struck.normal.dot(below) > 0.99, "{}", struck.normal);
    let body = world.body(second).unwrap();
    let expected = struck.normal * (struck.impulse / body.mass());
    assert!(
        (body.velocity() - expected).length() <= 1e-12,
        "{} {expected}",
        body.velocity()
    );
    assert!(stats.max_overlap <= 1e-12, "overlap {}", stats.max_overlap);
}
