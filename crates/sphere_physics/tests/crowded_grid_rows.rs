//! The broad phase's grid sizes its cells to the scene's typical box. When most spheres are
//! large, a cluster of tiny ones puts thousands of bodies into one row of cells: the grid's
//! first pass then meets rows too long for its fixed buffer of partners, hands over the
//! partners found so far and scans the rest one body at a time. Every pair must still be found.
//!
//! Each tiny pair closes its gap within the first step: a pair the grid missed would pass
//! through itself instead of exchanging velocities.

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

const TINY: f64 = 0.001;
const BIG: f64 = 0.1;
const SPEED: f64 = 0.06;
const GAP: f64 = 0.0005;
const DT: f64 = 1.0 / 60.0;

/// Head-on pairs of tiny spheres along x on a lattice (0.01 m between pairs along x, 0.004 m
/// across), straddling the planes y = 0.2 and z = 0.2 (cell boundaries of the grid sized to the
/// big spheres' boxes), and more big spheres at rest beyond them, so that the big spheres'
/// boxes are the typical ones. Returns the world and each pair's ids.
fn crowded() -> (World, Vec<[sphere_physics::BodyId; 2]>) {
    let mut world = World::new(Settings::default());
    let mut pairs = Vec::new();
    let half = TINY + GAP / 2.0;
    for i in 0..6 {
        for j in 0..16 {
            for k in 0..16 {
                let centre = DVec3::new(
                    0.01 * f64::from(i),
                    0.17 + 0.004 * f64::from(j),
                    0.17 + 0.004 * f64::from(k),
                );
                let left = SphereDesc::new(TINY)
                    .at(centre - DVec3::X * half)
                    .moving(DVec3::X * SPEED)
                    .with_restitution(1.0);
                let right = SphereDesc::new(TINY)
                    .at(centre + DVec3::X * half)
                    .moving(-DVec3::X * SPEED)
                    .with_restitution(1.0);
                pairs.push([
                    world.add_sphere(left).unwrap(),
                    world.add_sphere(right).unwrap(),
                ]);
            }
        }
    }
    let tiny = 2 * pairs.len();
    let mut big = 0;
    'lattice: for i in 0..20 {
        for j in 0..20 {
            for k in 0..20 {
                if big > tiny {
                    break 'lattice;
                }
                let at = DVec3::new(
                    1.0 + 0.3 * f64::from(i),
                    0.3 * f64::from(j),
                    0.3 * f64::from(k),
                );
                world
                    .add_sphere(SphereDesc::new(BIG).at(at).with_restitution(1.0))
                    .unwrap();
                big += 1;
            }
        }
    }
    (world, pairs)
}

#[test]
fn every_pair_in_crowded_rows_is_found() {
    let (mut world, pairs) = crowded();
    let stats = *world.step(DT).unwrap();
    // Each pair meets once, and nothing else meets.
    assert_eq!(stats.collisions as usize, pairs.len());
    for [left, right] in pairs {
        let (left, right) = (world.body(left).unwrap(), world.body(right).unwrap());
        // Equal masses, elastic, head on: the velocities are exchanged.
        assert!(
            (left.velocity() + DVec3::X * SPEED).length() <= 1e-12,
            "left {}",
            left.velocity()
        );
        assert!(
            (right.velocity() - DVec3::X * SPEED).length() <= 1e-12,
            "right {}",
            right.velocity()
        );
    }
}
