//! Regression (found by review of the core's documentation): a step's
//! [`StepStats::potential_energy`](sphere_physics::StepStats::potential_energy), documented as
//! the dynamic bodies' potential energy at the end of the step (the same as
//! `World::potential_energy` to rounding), was summed as the bodies were written back, before
//! the separation that moves a pair with a sphere on a string back out of a deep overlap: after
//! such a move it told of where the bodies were before it.
//!
//! The scene of `regression_separation_pushes_a_bystander.rs`: a free sphere of 575 kg, a light
//! one on a string whose anchor lies inside it (the pair a radius of the small one deep), and a
//! third sphere above the large one, under gravity. The first step's separation moves the pair
//! apart.

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, SphereDesc, World};

#[test]
fn regression_potential_energy_is_summed_after_the_separation() {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    let (big, small, length) = (0.7, 0.05, 0.24);
    let hanging = DVec3::new(0.0, -big, 0.0);
    world
        .add_sphere(SphereDesc::new(big).with_density(400.0))
        .unwrap();
    world
        .add_sphere(
            SphereDesc::new(small)
                .at(hanging)
                .with_density(0.2)
                .tethered(hanging + DVec3::Y * length, length),
        )
        .unwrap();
    world
        .add_sphere(
            SphereDesc::new(0.047)
                .at(DVec3::new(0.0, big + 0.047 + 0.005, 0.0))
                .with_force(DVec3::new(0.5, 0.0, 0.0)),
        )
        .unwrap();
    let mut separated = 0;
    for step in 0..8 {
        let stats = *world.step(1.0 / 60.0).unwrap();
        separated += stats.separated;
        let now = world.potential_energy();
        assert!(
            (stats.potential_energy - now).abs() <= 1e-12 * now.abs().max(1.0),
            "step {step}: {} reported, {now} at the step's end ({} separated)",
            stats.potential_energy,
            stats.separated
        );
        assert_eq!(stats.kinetic_energy, world.kinetic_energy(), "step {step}");
    }
    assert!(separated > 0, "the scene no longer separates anything");
}
