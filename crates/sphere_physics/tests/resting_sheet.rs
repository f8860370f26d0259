//! A sheet of spheres settling at one instant, each onto its own fixed sphere, slowly enough to
//! be resting contacts: each impact is its own part of one simultaneous group, and each part
//! asks whether the resting contacts already taken at that instant share a body with it. That
//! question once scanned them all, quadratic in the sheet (1.4 s for a 200 × 200 sheet's step;
//! a speed the bench `cargo bench -p sphere_bench -- simultaneous/resting_sheet` watches, not
//! this test). Here, the physics of that path: every sphere stops dead where it lands.

mod common;

use sphere_physics::glam::DVec3;

#[test]
fn a_sheet_settling_at_one_instant_stops_every_sphere_where_it_lands() {
    let n = 120;
    // At rest 1 mm above: gravity's kick brings it down at 0.16 m/s, under the resting speed
    // (1.5 · g · dt = 0.25 m/s).
    let (mut world, balls) =
        common::sheet_over_floors(n, DVec3::new(0.0, -9.81, 0.0), 1.001, DVec3::ZERO);
    let dt = 1.0 / 60.0;
    let stats = *world.step(dt).unwrap();
    assert_eq!(stats.collisions as usize, n * n);
    assert_eq!(stats.resting_contacts as usize, n * n);
    assert_eq!(stats.collisions_deferred, 0);
    let time = world.collisions()[0].time;
    assert!(world.collisions().iter().all(|c| c.time == time));
    for ball in balls {
        let body = world.body(ball).unwrap();
        // Stopped dead on its fixed sphere (restitution 0; semi-implicit Euler gives no kick
        // after the drift), sitting on top of it.
        assert!(body.velocity().length() <= 1e-12, "{}", body.velocity());
        assert!(
            (body.position() - DVec3::new(body.position().x, 1.0, body.position().z)).length()
                <= common::creep(&world, dt),
            "{}",
            body.position()
        );
    }
    assert!(
        stats.max_overlap <= common::creep(&world, dt),
        "{}",
        stats.max_overlap
    );
}
