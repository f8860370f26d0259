//! Overlaps with nothing accelerating, on random scenes: spheres placed overlapping with no
//! gravity are moved apart by their positions alone (see `World::step`), so velocities,
//! momentum, kinetic energy and the centre of mass are kept, and the scene comes apart.

mod common;

use common::{centre_of_mass, crowd_at_rest, deepest_beyond_band, deepest_overlap};
use proptest::prelude::*;
use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

const DT: f64 = 1.0 / 60.0;

/// Up to 40 spheres (position in a cube 2 m wide, radius 0.05 to 0.5 m, density 0.5 to 5)
/// placed with no regard for each other: most overlap, some deep inside bigger ones.
fn crowd() -> impl Strategy<Value = Vec<(f64, f64, f64, f64, f64)>> {
    prop::collection::vec(
        (
            -1.0..1.0f64,
            -1.0..1.0f64,
            -1.0..1.0f64,
            0.05..0.5f64,
            0.5..5.0f64,
        ),
        2..40,
    )
}

proptest! {
    #![proptest_config(crate::common::proptest_config(64, crate::common::SEED))]
    /// A crowd placed overlapping at rest: nothing gains a speed, the centre of mass stays,
    /// the step reports the deepest overlap, and within 2 s every pair is apart or touching
    /// (the slowest of these cases takes 52 steps; a sphere at the centre of one ten times its
    /// radius would take 110, at a tenth of its radius a step).
    #[test]
    fn a_crowd_at_rest_comes_apart_in_place(spheres in crowd()) {
        let mut world = crowd_at_rest(&spheres);
        let centre = centre_of_mass(&world);
        let mut apart = false;
        for step in 0..120 {
            let stats = *world.step(DT).unwrap();
            prop_assert!(world.bodies().iter().all(|b| b.velocity() == DVec3::ZERO), "step {}", step);
            prop_assert!((centre_of_mass(&world) - centre).length() <= 1e-12, "step {}", step);
            let deepest = deepest_overlap(&world);
            prop_assert!(deepest <= stats.max_overlap + 1e-12, "step {}: {} over {}", step, deepest, stats.max_overlap);
            if deepest_beyond_band(&world) <= 0.0 {
                apart = true;
                break;
            }
        }
        prop_assert!(apart, "still {} m deep beyond the band", deepest_beyond_band(&world));
    }

    /// Moving crowds placed overlapping, with restitutions from 0 to 1: momentum kept, kinetic
    /// energy never gained, and after 5 s every pair apart or touching.
    #[test]
    fn a_moving_crowd_comes_apart_and_keeps_its_momentum(
        spheres in crowd(),
        velocities in prop::collection::vec((-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, 0.0..=1.0f64), 40),
    ) {
        let mut world = World::new(Settings::default());
        for (&(x, y, z, radius, density), &(vx, vy, vz, restitution)) in spheres.iter().zip(&velocities) {
            world
                .add_sphere(
                    SphereDesc::new(radius)
                        .at(DVec3::new(x, y, z))
                        .moving(DVec3::new(vx, vy, vz))
                        .with_density(density)
                        .with_restitution(restitution),
                )
                .unwrap();
        }
        let momentum = world.momentum();
        let scale = world.bodies().iter().map(|b| b.mass() * b.velocity().length()).sum::<f64>();
        let mut energy = world.kinetic_energy();
        for step in 0..300 {
            world.step(DT).unwrap();
            prop_assert!((world.momentum() - momentum).length() <= 1e-9 * scale, "step {}", step);
            let now = world.kinetic_energy();
            prop_assert!(now <= energy * (1.0 + 1e-9) + 1e-12, "step {}: {} -> {}", step, energy, now);
            energy = now;
        }
        // Measured: every case ends with no pair overlapping (0 here in every case).
        prop_assert!(deepest_beyond_band(&world) <= 0.0, "still {} m deep beyond the band", deepest_beyond_band(&world));
    }
}
