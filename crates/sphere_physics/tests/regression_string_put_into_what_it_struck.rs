//! Regression: a sphere on a fast-turning string, put back on its string's sphere at an
//! impact, was put into the sphere it had just struck.
//!
//! Within a step a tethered sphere drifts along a chord of its swing, inside the string's
//! length by up to the chord's sagitta. At an impact it was put back on the string's sphere,
//! straight out from the anchor: into a sphere outside the swing that it strikes, by as much.
//! With restitution 0 the pair does not part, and the step ended with them overlapping. The
//! property test of strings among free spheres found it with 1 500 cases: a sphere on a
//! string of 0.56 m turning 0.9 rad a step ended one 1.5 cm (15% of its radius) into a light
//! sphere it struck 2.5 ms before the step's end.
//!
//! Now it is put back on its string only as far as that takes it no deeper into what it
//! strikes.

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, SphereDesc, World};

const DT: f64 = 1.0 / 40.0;
const LENGTH: f64 = 0.5;

/// A heavy sphere (radius 0.2) hanging from the origin on a string of 0.5 m, swinging at
/// at `speed` under gravity, and a light one (radius 0.1, restitution 0) outside its swing
/// about where its chord meets it `along` of the way through the first step.
fn swing_into_a_light_sphere(speed: f64, along: f64) -> World {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    world
        .add_sphere(
            SphereDesc::new(0.2)
                .at(DVec3::new(0.0, -LENGTH, 0.0))
                .moving(DVec3::new(speed, 0.0, 0.0))
                .with_density(25.0)
                .with_restitution(0.0)
                .tethered(DVec3::ZERO, LENGTH),
        )
        .unwrap();
    // The chord of the first step: from the bottom, a straight drift of speed·DT bent back
    // along the string to its length (the SHAKE correction).
    let reach = speed * DT;
    let start = DVec3::new(0.0, -LENGTH, 0.0);
    let end = DVec3::new(reach, -(LENGTH * LENGTH - reach * reach).sqrt(), 0.0);
    let point = start.lerp(end, along);
    // Touching there, straight out from the anchor (so the chord closes on it from before),
    // as high as it drifts down by then (semi-implicit Euler: kicked by a step's gravity, then
    // drifting).
    let fall = DVec3::new(0.0, 9.81 * DT * along * DT, 0.0);
    let light = point + point.normalize() * (0.3 + 1e-9) + fall;
    world
        .add_sphere(SphereDesc::new(0.1).at(light).with_restitution(0.0))
        .unwrap();
    world
}

fn overlap(world: &World) -> f64 {
    let [a, b] = world.bodies() else {
        unreachable!()
    };
    a.radius() + b.radius() - (b.position() - a.position()).length()
}

/// A string turning 0.9 rad a step strikes the light sphere near the step's end, about 2 cm
/// inside the string's length: the pair collides and ends the step apart (it ended 1.9 cm,
/// a fifth of the light sphere's radius, into it).
#[test]
fn a_struck_sphere_is_not_overlapped_by_the_string_put_back() {
    let mut world = swing_into_a_light_sphere(18.0, 0.9);
    let stats = *world.step(DT).unwrap();
    assert_eq!(stats.collisions, 1, "{stats:?}");
    assert_eq!(stats.collisions_deferred, 0);
    assert!(
        overlap(&world) <= 0.0,
        "the pair ends the step {} m into each other",
        overlap(&world)
    );
    // The string holds: the heavy sphere ends the step at its length, not past it.
    let heavy = &world.bodies()[0];
    assert!(heavy.position().length() <= LENGTH * (1.0 + 1e-9));
}

/// Over speeds (0.5 to 0.8 rad a step) and where in the step's second half the chord meets
/// it: a collision, and no overlap at the step's end (1.1 mm to 1.9 cm before).
#[test]
fn no_overlap_wherever_the_chord_strikes() {
    for speed in [12.0, 14.0, 16.0, 18.0] {
        for along in [0.6, 0.75, 0.9] {
            let mut world = swing_into_a_light_sphere(speed, along);
            let stats = *world.step(DT).unwrap();
            assert!(
                stats.collisions >= 1,
                "speed {speed}, along {along}: {stats:?}"
            );
            assert!(
                overlap(&world) <= 0.0,
                "speed {speed}, along {along}: {} m into each other",
                overlap(&world)
            );
        }
    }
}
