//! Regression: a sphere placed deep inside another was flung away.
//!
//! A resting contact that overlaps deeper than its allowance is pushed apart at the speed that
//! undoes the excess in one step: for a sphere placed 0.9 m into another (radius 0.5, at 60
//! steps a second), 54 m/s, and it flew 150 m up. A sphere placed overlapping two fixed ones on
//! opposite sides, which no velocity can free, took 60 m/s back and forth every step (with no
//! gravity; the collision budget's fallback solve, pushing against both). Found while looking
//! at spheres wedged between fixed ones. Now the push undoes at most a tenth of the smaller
//! radius a step: 3 m/s here, and the deep overlap is undone over a few steps.

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, SphereDesc, World};

const DT: f64 = 1.0 / 60.0;
const RADIUS: f64 = 0.5;
/// A tenth of the radius a step.
const MOST: f64 = 0.1 * RADIUS / DT;

#[test]
fn a_sphere_placed_inside_another_is_pushed_out_not_flung() {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    world
        .add_sphere(
            SphereDesc::new(100.0)
                .at(DVec3::new(0.0, -100.0, 0.0))
                .fixed(),
        )
        .unwrap();
    let [low, high] = [0.5, 0.6].map(|y| {
        world
            .add_sphere(
                SphereDesc::new(RADIUS)
                    .at(DVec3::new(0.0, y, 0.0))
                    .with_restitution(0.5),
            )
            .unwrap()
    });
    let mut fastest = 0.0f64;
    for _ in 0..180 {
        world.step(DT).unwrap();
        for id in [low, high] {
            fastest = fastest.max(world.body(id).unwrap().velocity().length());
        }
    }
    // The push, and a step of gravity on top. Before: 54 m/s.
    assert!(fastest <= MOST + 9.81 * DT, "{fastest} m/s");
    // Pushed out, and at rest on each other three seconds later.
    let (a, b) = (world.body(low).unwrap(), world.body(high).unwrap());
    let gap = (b.position() - a.position()).length() - 2.0 * RADIUS;
    assert!(gap > -1e-3, "still {:e} m inside", -gap);
    assert!(b.velocity().length() < 1e-3, "{:?}", b.velocity());
    // On the line they started on (every push and weight is along it), one on the other on
    // the dome's top: within a tenth of a millimetre of touching each (the creep allowance).
    for (body, y) in [(a, 0.5), (b, 1.5)] {
        let p = body.position();
        assert!(p.x.abs() < 1e-12 && p.z.abs() < 1e-12, "{p}");
        assert!((p.y - y).abs() < 1e-4, "{p}");
    }
}

#[test]
fn a_sphere_overlapping_fixed_ones_on_both_sides_is_not_flung() {
    let mut world = World::new(Settings::default());
    for x in [-1.0, 1.0] {
        world
            .add_sphere(SphereDesc::new(1.0).at(DVec3::new(x, 0.0, 0.0)).fixed())
            .unwrap();
    }
    let ball = world
        .add_sphere(SphereDesc::new(RADIUS).moving(DVec3::X))
        .unwrap();
    for step in 0..10 {
        world.step(DT).unwrap();
        let speed = world.body(ball).unwrap().velocity().length();
        // Before: 30 m/s after the first step, 60 after each of the others.
        assert!(speed <= MOST * (1.0 + 1e-12), "step {step}: {speed} m/s");
    }
}
