//! Regression (found by review): `Collision::point` is documented on `a`'s surface (`a` the
//! body with the lower id), but it was worked out on the surface of the body the solver took
//! first, and the bodies then swapped to put the lower id first. In scenes of more than 64
//! bodies, where the solver takes them in spatial order, a pair overlapping when recorded (a
//! resting contact, a push against an overlap) had its point on the other body's surface,
//! as far off as the overlap.

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, SphereDesc, World};

const RADIUS: f64 = 0.1;
const FLOOR: f64 = 100.0;

/// 80 balls sunk `depth` into a fixed floor, added before it or after it.
fn sunk_row(floor_first: bool, depth: f64) -> World {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    let floor = SphereDesc::new(FLOOR)
        .fixed()
        .at(DVec3::new(0.0, -FLOOR, 0.0));
    if floor_first {
        world.add_sphere(floor.clone()).unwrap();
    }
    for k in 0..80 {
        let x = (f64::from(k) - 40.0) * 3.0 * RADIUS;
        // On the floor's surface, `depth` into it.
        let up = DVec3::new(x, FLOOR, 0.0).normalize();
        let centre = DVec3::new(0.0, -FLOOR, 0.0) + up * (FLOOR + RADIUS - depth);
        world
            .add_sphere(SphereDesc::new(RADIUS).at(centre))
            .unwrap();
    }
    if !floor_first {
        world.add_sphere(floor).unwrap();
    }
    world
}

#[test]
fn regression_a_collision_point_is_on_the_surface_of_the_body_with_the_lower_id() {
    let depth = 0.5 * RADIUS;
    for floor_first in [true, false] {
        let mut world = sunk_row(floor_first, depth);
        let start: Vec<DVec3> = world.bodies().iter().map(|b| b.position()).collect();
        world.step(1.0 / 60.0).unwrap();
        let hits = world.collisions();
        assert!(hits.len() >= 80, "{}", hits.len());
        for hit in hits {
            assert!(hit.a < hit.b);
            let a = world.body(hit.a).unwrap();
            let index = world.bodies().iter().position(|b| b.id() == hit.a).unwrap();
            // Within the step's motion (a few mm) of `a`'s surface; the other body's surface
            // is the overlap (5 cm) away.
            let off = (hit.point - (start[index] + hit.normal * a.radius())).length();
            assert!(
                off < 0.2 * depth,
                "floor first {floor_first}: {hit:?} {off}"
            );
        }
    }
}
