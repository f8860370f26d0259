//! Regression (found by review): a step reports the largest overlap from the pairs it tested
//! whose drifts end them overlapping; far from the origin, the two spheres' end positions
//! (each reckoned on its own) differ by more rounding than "a billionth of their reach"
//! allowed, so a pair separating by a hair could be dropped and still end overlapping by
//! 5e-15 m: the step reported 0.

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

#[test]
fn regression_a_pair_far_out_that_ends_overlapping_is_reported() {
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    let r = 1e-6;
    // One unit in the last place at 1000. The spheres start 10 units closer than their reach
    // (overlapping by about 1e-12 m), and the second moves away at a speed that carries it
    // about those 10 units in the step: the drifts say they end a hair apart, the positions
    // (each rounded on its own) that they end overlapping by about 5e-15 m.
    let ulp = 2f64.powi(-43);
    let d = (2.0 * r / ulp).floor() * ulp - 10.0 * ulp;
    world
        .add_sphere(SphereDesc::new(r).at(DVec3::new(1000.0, 0.0, 0.0)))
        .unwrap();
    world
        .add_sphere(
            SphereDesc::new(r)
                .at(DVec3::new(1000.0 + d, 0.0, 0.0))
                .moving(DVec3::new(1.1444178917098998e-10, 0.0, 0.0)),
        )
        .unwrap();
    let reported = world.step(0.01).unwrap().max_overlap;
    let actual = world.max_overlap();
    assert!(
        actual > 0.0,
        "the case needs a pair that ends overlapping: {actual}"
    );
    assert_eq!(reported, actual);
}
