//! A step finds an impact exactly when its time-of-impact method does, right up to the end of
//! the step: the world may skip the method for a pair still closing at the end of the step and
//! farther apart than contact there, but only when neither built-in method would report an
//! impact. Pairs here meet at around the end of the step (from a tenth of a step before it to a
//! tenth after, and within a billionth of it), or early enough to pass each other by the end of
//! it, under every tolerance, with both methods.

mod common;

use proptest::prelude::*;
use sphere_physics::{
    Settings, SphereDesc, TimeOfImpact, ToiMethod, Tolerance, World, glam::DVec3,
};

const DT: f64 = 1.0 / 60.0;

proptest! {
    #![proptest_config(crate::common::proptest_config(1024, 0x00E1_0D57))]
    #[test]
    fn a_step_finds_an_impact_exactly_when_its_method_does(
        radii in (0.01..1.0f64, 0.01..1.0f64),
        speed in 0.1..100.0f64,
        // When they would meet head-on, in steps; a glancing offset makes some miss, and
        // some meet early, glance and are apart again by the end of the step.
        meet in prop_oneof![
            0.9..1.1f64,
            prop::sample::select(vec![1.0 - 1e-6, 1.0 - 1e-9, 1.0, 1.0 + 1e-9, 1.0 + 1e-6]),
            0.01..0.9f64,
        ],
        offset in 0.0..1.2f64,
        direction in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
        eps in prop::sample::select(vec![0.0, 1e-12, 1e-9, 1e-6, 1e-3]),
        bisection in any::<bool>(),
    ) {
        let axis = DVec3::new(direction.0, direction.1, direction.2);
        prop_assume!(axis.length() > 0.1);
        let axis = axis.normalize();
        let side = axis.any_orthonormal_vector();
        let reach = radii.0 + radii.1;
        // b starts `meet` steps of travel beyond contact along `axis`, shifted sideways by a
        // fraction of the reach, and comes straight back.
        let position = axis * (reach + speed * DT * meet) + side * (offset * reach);
        let velocity = -axis * speed;
        let method = if bisection {
            ToiMethod::Bisection { max_iterations: 8 }
        } else {
            ToiMethod::Exact
        };
        let tolerance = Tolerance::new(eps).expect("valid");
        let mut settings = Settings::with_gravity(DVec3::ZERO);
        settings.method = method;
        settings.tolerance = tolerance;
        let mut world = World::new(settings);
        world.add_sphere(SphereDesc::new(radii.0)).unwrap();
        world.add_sphere(SphereDesc::new(radii.1).at(position).moving(velocity)).unwrap();
        // Skip pairs the method calls touching already: those are a different story
        // (`toi_at_start.rs`).
        let distance = position.length();
        prop_assume!(!(distance <= reach || tolerance.eq(distance, reach)));
        let expected = method.time_of_impact(position, velocity, reach, DT, tolerance);
        let stats = *world.step(DT).unwrap();
        prop_assert_eq!(
            stats.collisions,
            u32::from(expected.time.is_some()),
            "method says {:?}", expected.time
        );
    }
}

#[test]
fn a_pair_that_cannot_meet_within_the_step_is_not_handed_to_the_method() {
    // Spheres of radius 0.5, one passing the other 0.9 off its line at 1 m/s, still closing at
    // the end of the step: their swept boxes overlap, so the pair is tested.
    let run = |end_distance: f64| {
        let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
        world.add_sphere(SphereDesc::new(0.5)).unwrap();
        let along = (end_distance * end_distance - 0.81).sqrt() + DT;
        world
            .add_sphere(
                SphereDesc::new(0.5)
                    .at(DVec3::new(along, 0.9, 0.0))
                    .moving(-DVec3::X),
            )
            .unwrap();
        let stats = *world.step(DT).unwrap();
        (stats.collisions, stats.toi_tests)
    };
    // 3 cm apart at the end of the step: no method would find an impact, none is asked.
    assert_eq!(run(1.03), (0, 0));
    // A tenth of a micrometre apart, within the margin of a millionth of the reach: the
    // method is asked (and finds none).
    assert_eq!(run(1.0 + 1e-7), (0, 1));
}
