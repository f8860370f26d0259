//! The broad phase's grid packs each box into 16-bit integers in a frame around its block of
//! cells, each side rounded to an integer step: 256 steps per cell (0.85 mm here), but fewer
//! along a block too long for that (here 358 cells along x: 88 steps per cell, 2.5 mm). Pairs
//! whose swept boxes meet by 1 mm must still be found, those closing along the coarse axis (a
//! line of 150 pairs) as well as along the fine ones (a line of 300): each pair closes its gap
//! at 0.97 of the first step, far too fast to be caught by the next one, so a pair the grid
//! missed would end the step overlapping. (Rounding the boxes inwards instead misses many.)

mod common;

use common::{head_on_pair, step_head_on_pairs};
use sphere_physics::{SphereDesc, glam::DVec3};

const RADIUS: f64 = 0.1;
const SPEED: f64 = 1.0;
const DT: f64 = 1.0 / 60.0;
/// Closed at 0.97 of the step: the two swept boxes overlap by 3% of the distance the pair
/// closes in a step (1 mm).
const GAP: f64 = 2.0 * SPEED * 0.97 * DT;

/// A head-on pair along `axis` around `centre`.
fn pair(centre: DVec3, axis: DVec3) -> [SphereDesc; 2] {
    head_on_pair(centre, axis, RADIUS, GAP, SPEED)
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
    let stats = step_head_on_pairs(&scene(), DT, "long block");
    assert!(stats.max_overlap <= 1e-9, "{}", stats.max_overlap);
}
