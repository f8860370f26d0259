//! Groups of spheres far apart share the broad phase's grid with the empty space between them
//! squeezed out of its block, one axis at a time, in chunks of cells (two gases a kilometre
//! apart stepped 2.4x faster than with one group left to the general tier). A cell's
//! neighbours must stay its neighbours wherever the chunks' edges fall: here four groups a
//! kilometre or more apart along x and z, each a lattice of head-on pairs, every pair closing
//! its gap within the first step, far too fast to be caught by the next one. A pair the grid
//! missed would pass through itself. And on random scenes: a gas steps bit for bit the same
//! with another far away along any axis as alone, where its own block needs no squeeze.

mod common;

use common::{head_on_lattice, step_head_on_pairs};
use proptest::prelude::*;
use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

const RADIUS: f64 = 0.1;
const SPEED: f64 = 1.0;
const GAP: f64 = 0.004;
const DT: f64 = 1.0 / 60.0;

/// Head-on pairs around `origin` on a lattice 0.5 m apart filling a cube of side 3 m, 7 by 7
/// by 7, along x, y and z in turn (dense enough for the squeezed block to hold them all).
fn group(origin: DVec3) -> Vec<[SphereDesc; 2]> {
    head_on_lattice(origin, 7, 0.5, RADIUS, GAP, SPEED)
}

#[test]
fn pairs_in_groups_a_kilometre_apart_all_collide() {
    let mut pairs = Vec::new();
    for origin in [
        DVec3::ZERO,
        DVec3::new(1000.0, 0.0, 0.0),
        DVec3::new(2500.0, 0.0, 0.0),
        DVec3::new(1000.0, 0.0, 1000.0),
    ] {
        pairs.extend(group(origin));
    }
    // Past the 64 bodies up to which the broad phase tests all pairs directly.
    assert!(2 * pairs.len() > 64);
    let stats = step_head_on_pairs(&pairs, DT, "groups apart");
    assert!(stats.max_overlap <= 1e-12, "{}", stats.max_overlap);
}

/// One sphere of a gas as the property draws it: a jitter from its lattice site (x, y, z), a
/// velocity (x, y, z), a restitution and a density.
type Sphere = ([f64; 3], [f64; 3], f64, f64);

/// A gas of 70 to 160 spheres: jitters up to 1.5 cm, up to 2 m/s along each axis,
/// restitutions 0.5 to 1, densities 0.5 to 5.
fn gas() -> impl Strategy<Value = Vec<Sphere>> {
    let jitter = -0.015..0.015f64;
    let speed = -2.0..2.0f64;
    prop::collection::vec(
        (
            [jitter.clone(), jitter.clone(), jitter],
            [speed.clone(), speed.clone(), speed],
            0.5..1.0f64,
            0.5..5.0f64,
        ),
        70..160,
    )
}

/// Adds `spheres` to `world`, of radius 0.05, on a lattice 0.14 m apart from `origin`.
fn add_gas(world: &mut World, spheres: &[Sphere], origin: DVec3) {
    let side = (spheres.len() as f64).cbrt().ceil() as usize;
    for (i, &(jitter, velocity, restitution, density)) in spheres.iter().enumerate() {
        let site = DVec3::new(
            (i % side) as f64,
            (i / side % side) as f64,
            (i / (side * side)) as f64,
        );
        let desc = SphereDesc::new(0.05)
            .at(origin + site * 0.14 + DVec3::from_array(jitter))
            .moving(DVec3::from_array(velocity))
            .with_restitution(restitution)
            .with_density(density);
        world.add_sphere(desc).unwrap();
    }
}

proptest! {
    #![proptest_config(common::proptest_config(32, common::SEED))]
    /// A gas of 70 to 160 spheres, stepped alone and with another gas `distance` away along
    /// one axis (two blocks of cells too many apart to span, so squeezed): its spheres end
    /// every step of half a second at the same positions and velocities, bit for bit. A pair
    /// the squeezed block missed would have changed them.
    #[test]
    fn a_gas_steps_the_same_with_another_far_away(
        near in gas(),
        far in gas(),
        axis in 0usize..3,
        distance in 30.0..3000.0f64,
    ) {
        let settings = Settings::with_gravity(DVec3::ZERO);
        let mut alone = World::new(settings.clone());
        add_gas(&mut alone, &near, DVec3::ZERO);
        let mut both = World::new(settings);
        add_gas(&mut both, &near, DVec3::ZERO);
        let away = [DVec3::X, DVec3::Y, DVec3::Z][axis] * distance;
        add_gas(&mut both, &far, away);
        let mut collisions = 0;
        for step in 0..30 {
            collisions += alone.step(DT).unwrap().collisions;
            both.step(DT).unwrap();
            for (a, b) in alone.bodies().iter().zip(both.bodies()) {
                let bits = |v: DVec3| v.to_array().map(f64::to_bits);
                prop_assert_eq!(
                    (bits(a.position()), bits(a.velocity())),
                    (bits(b.position()), bits(b.velocity())),
                    "sphere {} at step {}", a.id(), step
                );
            }
        }
        prop_assert!(collisions > 0);
    }
}
