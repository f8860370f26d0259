//! The broad phase's grid covers the block of cells its spheres occupy: pairs in the block's
//! outermost cells (its faces, edges and corners) must be found like any other, in every
//! direction. Each pair here closes its gap within the first step, far too fast to be caught
//! by the next one: a pair the grid missed would pass through itself.

mod common;

use common::{head_on_pair, step_head_on_pairs};
use sphere_physics::{SphereDesc, glam::DVec3};

const RADIUS: f64 = 0.1;
const SPEED: f64 = 1.0;
const GAP: f64 = 0.004;
const DT: f64 = 1.0 / 60.0;

/// A head-on pair along `axis` around `centre`: `(left, right)` spheres' descriptions.
fn pair(centre: DVec3, axis: DVec3) -> [SphereDesc; 2] {
    head_on_pair(centre, axis, RADIUS, GAP, SPEED)
}

/// Every pair along every axis at every corner of a cube of side `side`, and at the middle
/// of every face, each axis's pair shifted off the others' lines (by half a metre: apart for
/// any side but 1, where two face pairs would meet at the centre).
fn scene(side: f64) -> Vec<[SphereDesc; 2]> {
    let h = side / 2.0;
    let mut centres = Vec::new();
    for x in [-h, h] {
        for y in [-h, h] {
            for z in [-h, h] {
                centres.push(DVec3::new(x, y, z));
            }
        }
    }
    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
        centres.push(axis * h);
        centres.push(-axis * h);
    }
    let mut pairs = Vec::new();
    for centre in centres {
        for (axis, shift) in [
            (DVec3::X, DVec3::new(0.0, 0.5, 0.0)),
            (DVec3::Y, DVec3::new(0.0, 0.0, 0.5)),
            (DVec3::Z, DVec3::new(0.5, 0.0, 0.0)),
        ] {
            pairs.push(pair(centre + shift, axis));
        }
    }
    pairs
}

#[test]
fn pairs_at_the_faces_edges_and_corners_of_the_grid_all_collide() {
    // 1.5: the block is every occupied cell; 3.0: over 64 cells per sphere, so the block is cut
    // down and the outermost pairs go to the hierarchy; 40: a sparse scene, mostly hierarchy.
    for side in [1.5, 3.0, 40.0] {
        let pairs = scene(side);
        // Past the 64 bodies up to which the broad phase tests all pairs directly.
        assert_eq!(2 * pairs.len(), 84);
        let stats = step_head_on_pairs(&pairs, DT, &format!("side {side}"));
        assert!(
            stats.max_overlap <= 1e-12,
            "side {side}: {}",
            stats.max_overlap
        );
    }
}
