//! Regression (found 2026-12-02 by driving a fast sphere into long lines of spheres): a line of
//! inelastic spheres struck hard collides without end (each contact closes the next, and the
//! struck ones catch up again), so the step's collision budget runs out and the fallback solve
//! takes over. Its Gauss–Seidel sweeps pass an impulse along about one contact a sweep, and
//! after its rounds' sweeps a long line was left closing through itself: 100 spheres of radius
//! 0.5, 1 cm apart, restitution 0.5, struck at 1 km/s, ended a step 2.1 cm (4% of a radius)
//! into each other; 300 struck at 10 km/s, 84 cm. Now the fallback sweeps on while any pair
//! would end more than 1% of a radius deeper than it is allowed (at most 1024 more sweeps):
//! 4.4 mm and 9.6 cm (the latter still at that cap). A landing pit of 1000, whose fallback
//! steps rarely leave a pair that deep, keeps its speed.

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, SphereDesc, World};

const DT: f64 = 1.0 / 60.0;
const RADIUS: f64 = 0.5;

/// `count` spheres in a line along x, `gap` apart, the first moving at `speed` into the rest.
fn line(count: usize, gap: f64, speed: f64, restitution: f64) -> World {
    let mut world = World::new(Settings::default());
    for i in 0..count {
        let velocity = if i == 0 {
            DVec3::X * speed
        } else {
            DVec3::ZERO
        };
        world
            .add_sphere(
                SphereDesc::new(RADIUS)
                    .at(DVec3::new(i as f64 * (2.0 * RADIUS + gap), 0.0, 0.0))
                    .moving(velocity)
                    .with_restitution(restitution),
            )
            .unwrap();
    }
    world
}

#[test]
fn regression_a_long_line_struck_hard_does_not_close_through_itself() {
    let mut world = line(100, 0.01, 1000.0, 0.5);
    let (momentum, energy) = (world.momentum(), world.kinetic_energy());
    let (mut deepest, mut fell_back) = (0.0f64, 0);
    for _ in 0..60 {
        let stats = *world.step(DT).unwrap();
        deepest = deepest.max(stats.max_overlap);
        fell_back += u32::from(stats.fell_back);
        assert!((stats.momentum - momentum).length() <= 1e-12 * momentum.length());
        assert!(stats.kinetic_energy <= energy);
        assert!(world.bodies().iter().all(|b| b.position().is_finite()));
    }
    assert!(fell_back > 0, "the budget ran out: the fallback was used");
    // 1% of a radius (the finishing sweeps' reach), and a fifth more for the rounding of
    // where each sweep stops. Before: 2.1 cm.
    assert!(deepest <= 0.012 * RADIUS, "{deepest} m into each other");
}
