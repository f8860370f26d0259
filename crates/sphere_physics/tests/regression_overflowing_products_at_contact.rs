//! Regression (found by review in the fifty-seventh session): where a product of distance and
//! speed, or a distance itself, overflowed an f64, the tolerance took the infinity as within
//! it of a finite number (it scales with the larger). A touching pair closing at 1e209 m/s
//! had a normal speed of minus infinity, "equal" to 0 within the tolerance, so not approaching:
//! no impact, and the sphere passed through a fixed one. Two spheres 2e154 m apart had a
//! distance of infinity, "equal" to their contact distance: `classify` called them resting.

use sphere_physics::glam::DVec3;
use sphere_physics::{
    Bisection, ContactKind, ExactToi, Settings, SphereDesc, TimeOfImpact, Tolerance, World,
};

fn both(d: DVec3, w: DVec3, contact: f64) -> [Option<f64>; 2] {
    let tol = Tolerance::default();
    [
        ExactToi.time_of_impact(d, w, contact, 1.0, tol).time,
        Bisection::default()
            .time_of_impact(d, w, contact, 1.0, tol)
            .time,
    ]
}

#[test]
fn regression_a_touching_pair_closing_too_fast_for_a_product_collides_at_once() {
    // Touching (1e90 m into a contact of 1e100 m: within the band of 1e91), closing head-on.
    let d = DVec3::new(1e100 - 1e90, 0.0, 0.0);
    for speed in [1e208, 1e209, 1e300] {
        assert_eq!(
            both(d, DVec3::NEG_X * speed, 1e100),
            [Some(0.0); 2],
            "{speed}"
        );
        assert_eq!(both(d, DVec3::X * speed, 1e100), [None; 2], "{speed:e}");
    }
    // Products of both signs overflowing: `inf - inf` is NaN, though the pair closes.
    let d = DVec3::new(1e150, 1e150, 0.0);
    let w = DVec3::new(-4e159, 2e159, 0.0);
    assert_eq!(both(d, w, d.length()), [Some(0.0); 2]);
    assert_eq!(both(d, -w, d.length()), [None; 2]);
}

#[test]
fn regression_a_sphere_touching_a_huge_fixed_one_at_a_huge_speed_bounces() {
    let mut world = World::new(Settings::default());
    world.add_sphere(SphereDesc::new(1e100).fixed()).unwrap();
    let speed = 1e209;
    let ball = world
        .add_sphere(
            SphereDesc::new(1.0)
                .at(DVec3::new(1e100 + 1.0 - 1e90, 0.0, 0.0))
                .moving(DVec3::NEG_X * speed),
        )
        .unwrap();
    world.step(1.0 / 60.0).unwrap();
    assert_eq!(world.stats().collisions, 1);
    let body = world.body(ball).unwrap();
    assert_eq!(body.velocity(), DVec3::X * speed);
    assert!(body.position().x > 1e100, "{}", body.position());
}

#[test]
fn regression_spheres_too_far_apart_for_their_distance_are_apart() {
    let mut world = World::new(Settings::default());
    let a = world.add_sphere(SphereDesc::new(1.0)).unwrap();
    let b = world
        .add_sphere(SphereDesc::new(1.0).at(DVec3::X * 2e154))
        .unwrap();
    assert_eq!(world.classify(a, b).unwrap(), ContactKind::Apart);
    let tol = Tolerance::default();
    assert!(!tol.eq(f64::INFINITY, 2.0) && !tol.eq(f64::NEG_INFINITY, 0.0));
    assert!(tol.eq(f64::INFINITY, f64::INFINITY) && tol.eq(1e300, 1e300 * (1.0 + 1e-12)));
}
