//! Regression (found by review): two spheres placed at the same centre with the same velocity
//! (a game spawning two balls at one spawn point in one frame) never came apart under
//! gravity: a pair at zero distance has no normal, so it was neither a resting contact nor an
//! impact, and the moves that part overlapping spheres run only where nothing accelerates.
//! Without gravity they part along x; under it they stayed one inside the other for ever.
//! Now the resting solve parts them along x too, by positions, giving them no speed.

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, SphereDesc, World};

fn spawned_together(count: usize, floor: bool) -> World {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    if floor {
        world
            .add_sphere(
                SphereDesc::new(10.0)
                    .fixed()
                    .at(DVec3::new(0.0, -10.0, 0.0)),
            )
            .unwrap();
    }
    for _ in 0..count {
        world
            .add_sphere(SphereDesc::new(0.5).at(DVec3::new(0.0, 0.5, 0.0)))
            .unwrap();
    }
    world
}

#[test]
fn regression_spheres_spawned_at_one_point_come_apart_under_gravity() {
    for count in [2, 3] {
        for floor in [false, true] {
            let mut world = spawned_together(count, floor);
            for _ in 0..120 {
                world.step(1.0 / 60.0).unwrap();
            }
            let balls = &world.bodies()[usize::from(floor)..];
            for (k, a) in balls.iter().enumerate() {
                for b in &balls[k + 1..] {
                    let apart = a.position().distance(b.position());
                    assert!(
                        apart >= 1.0 - 1e-3,
                        "{count} balls, floor {floor}: centres {apart} apart, overlap {}",
                        world.stats().max_overlap
                    );
                }
            }
            // Parted by positions: no speed is given, so the balls' momentum is gravity's.
            let momentum: DVec3 = balls.iter().map(|b| b.velocity() * b.mass()).sum();
            if !floor {
                let fall = DVec3::new(0.0, -9.81 * 2.0, 0.0) * balls[0].mass() * count as f64;
                assert!(
                    (momentum - fall).length() <= 1e-9 * fall.length(),
                    "{momentum}"
                );
            }
        }
    }
}
