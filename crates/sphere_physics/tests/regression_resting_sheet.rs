//! Regression (found by review): a sheet of spheres settling at one instant, each onto its own
//! fixed sphere, slowly enough to be resting contacts. Each impact is its own part of one
//! simultaneous group, and each part asked whether the resting contacts already taken at that
//! instant shared a body with it by scanning them all: quadratic in the sheet (measured on a
//! 200 × 200 sheet's step: see `cargo bench -p sphere_bench -- simultaneous/resting_sheet`).
//! Every sphere still settles on its own, exactly where it lands.

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

#[test]
fn regression_a_sheet_settling_at_one_instant_settles_every_sphere() {
    let n = 120;
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    let mut balls = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let floor = DVec3::new(i as f64 * 1.5, 0.0, j as f64 * 1.5);
            world
                .add_sphere(SphereDesc::new(0.5).at(floor).fixed())
                .unwrap();
            // At rest 1 mm above: gravity's kick brings it down at 0.16 m/s, under the resting
            // speed (1.5 · g · dt = 0.25 m/s).
            let ball = SphereDesc::new(0.5).at(floor + DVec3::Y * 1.001);
            balls.push(world.add_sphere(ball).unwrap());
        }
    }
    let dt = 1.0 / 60.0;
    let stats = *world.step(dt).unwrap();
    assert_eq!(stats.collisions as usize, n * n);
    assert_eq!(stats.resting_contacts as usize, n * n);
    assert_eq!(stats.collisions_deferred, 0);
    let time = world.collisions()[0].time;
    assert!(world.collisions().iter().all(|c| c.time == time));
    for ball in balls {
        let body = world.body(ball).unwrap();
        // Stopped dead on its fixed sphere (restitution 0), then given the step's last kick
        // at most; sitting on top, within the creep allowance.
        assert!(body.velocity().x == 0.0 && body.velocity().z == 0.0);
        assert!(body.velocity().y.abs() <= 9.81 * dt, "{}", body.velocity());
        assert!(
            (body.position().y - 1.0).abs() <= 1e-3 * 0.5,
            "{}",
            body.position()
        );
    }
    assert!(
        stats.max_overlap <= 0.01 * 1.5 * 9.81 * dt * dt,
        "{}",
        stats.max_overlap
    );
}
