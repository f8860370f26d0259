//! The broad phase's grid packs each box into 16-bit integers in a frame around its block of
//! cells, each side rounded to an integer step: 256 steps per cell (0.85 mm here), but fewer
//! along a block too long for that (here 358 cells along x: 88 steps per cell, 2.5 mm). Pairs
//! whose swept boxes meet by 1 mm must still be found, those closing along the coarse axis (a
//! line of 150 pairs) as well as along the fine ones (a line of 300): each pair closes its gap
//! at 0.97 of the first step, far too fast to be caught by the next one, so a pair the grid
//! missed would end the step overlapping. (Rounding the boxes inwards instead misses many.)

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

const RADIUS: f64 = 0.1;
const SPEED: f64 = 1.0;
const DT: f64 = 1.0 / 60.0;
/// Closed at 0.97 of the step: the two swept boxes overlap by 3% of the distance the pair
/// closes in a step (1 mm).
const GAP: f64 = 2.0 * SPEED * 0.97 * DT;

/// A head-on pair along `axis` around `centre`.
fn pair(centre: DVec3, axis: DVec3) -> [SphereDesc; 2] {
    let half = RADIUS + GAP / 2.0;
    [
        SphereDesc::new(RADIUS)
            .at(centre - axis * half)
            .moving(axis * SPEED),
        SphereDesc::new(RADIUS)
            .at(centre + axis * half)
            .moving(-axis * SPEED),
    ]
}

/// Pairs closing across a line along x, a quarter of a metre apart, by turns along y and z;
/// beside it a line of pairs closing along x, half a metre apart; the whole far from the origin.
fn scene() -> Vec<[SphereDesc; 2]> {
    let start = DVec3::new(5_000.0, -300.0, 40.0);
    let mut pairs = Vec::new();
    for k in 0..300 {
        let axis = if k % 2 == 0 { DVec3::Y } else { DVec3::Z };
        pairs.push(pair(start + DVec3::X * (0.25 * f64::from(k)), axis));
    }
    for k in 0..150 {
        let centre = start + DVec3::new(0.5 * f64::from(k), 0.0, 1.0);
        pairs.push(pair(centre, DVec3::X));
    }
    pairs
}

#[test]
fn pairs_along_a_grid_block_hundreds_of_cells_long_all_collide() {
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    let pairs = scene();
    let ids: Vec<_> = pairs
        .iter()
        .map(|[a, b]| {
            (
                world.add_sphere(a.clone()).unwrap(),
                world.add_sphere(b.clone()).unwrap(),
            )
        })
        .collect();
    let stats = *world.step(DT).unwrap();
    assert_eq!(stats.collisions as usize, pairs.len());
    for ((a, b), [da, db]) in ids.iter().zip(&pairs) {
        // Equal masses, elastic, head-on: the velocities are exchanged.
        let (va, vb) = (
            world.body(*a).unwrap().velocity(),
            world.body(*b).unwrap().velocity(),
        );
        assert!(
            (va - db.velocity).length() <= 1e-12,
            "{va} at {}",
            da.position
        );
        assert!(
            (vb - da.velocity).length() <= 1e-12,
            "{vb} at {}",
            db.position
        );
    }
    assert!(stats.max_overlap <= 1e-9, "{}", stats.max_overlap);
}
