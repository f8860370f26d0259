//! Regression: a generator's box a whole number of cells wide held one cell fewer along each
//! axis whose width divided by the cell's side rounded to just under that number. The cells
//! are `2 · radius · 1.1` across: for spheres of radius 0.05 that is 0.11000000000000001, and
//! 0.88 / 0.11000000000000001 is 7.999999999999999. The lab's ball pit (a box of 8 by 16 by 8
//! cells) got 7 by 15 by 7, its crowd packed towards the box's lower corner, a strip two
//! radii wide left empty along two walls; a count that fills the box was refused; and boxes
//! placed away from the origin (the bench's tiles of showers) lost a cell or not as their
//! corners rounded. Found by review (sixty-fourth session).

mod common;

use sphere_physics::SphereSpec;
use sphere_physics::generate::Generator;

fn shower(count: u32, min: [f64; 3], max: [f64; 3], radius: f64) -> Generator {
    Generator::Shower {
        count,
        seed: 1,
        min,
        max,
        radius,
        velocity: [0.0; 3],
        density: 1.0,
        restitution: None,
    }
}

/// Every sphere inside `min..max`, to the rounding of the box's corners.
fn inside(spheres: &[SphereSpec], min: [f64; 3], max: [f64; 3]) {
    for s in spheres {
        for k in 0..3 {
            let rounding = 8.0 * f64::EPSILON * (min[k].abs() + max[k].abs());
            assert!(
                s.position[k] - s.radius >= min[k] - rounding
                    && s.position[k] + s.radius <= max[k] + rounding,
                "{s:?} leaves the box {min:?}..{max:?} along axis {k}"
            );
        }
    }
}

/// Every sphere inside `min..max`, and no two overlapping.
fn inside_and_apart(spheres: &[SphereSpec], min: [f64; 3], max: [f64; 3]) {
    inside(spheres, min, max);
    common::no_overlap(spheres);
}

#[test]
fn regression_a_box_of_eight_cells_a_side_holds_eight_cubed_spheres() {
    let (min, max) = ([0.0; 3], [0.88; 3]);
    // The box is exactly full: 512 spheres, one in each cell.
    let spheres = shower(512, min, max, 0.05).spheres().unwrap();
    assert_eq!(spheres.len(), 512);
    inside_and_apart(&spheres, min, max);
    // The eighth layer along each axis is used: a centre within its cell, [0.77, 0.88].
    for k in 0..3 {
        let far = spheres.iter().map(|s| s.position[k]).fold(0.0, f64::max);
        assert!(far > 0.77 + 0.05, "axis {k}: the farthest centre is {far}");
    }
}

#[test]
fn regression_a_box_one_cell_wide_holds_one_sphere() {
    let (min, max) = ([0.0; 3], [0.022; 3]);
    let spheres = shower(1, min, max, 0.01).spheres().unwrap();
    assert_eq!(spheres.len(), 1);
    inside_and_apart(&spheres, min, max);
}

#[test]
fn regression_the_lab_ball_pits_crowd_is_centred_in_its_box() {
    // The lab's ball pit: 400 spheres in 8 by 16 by 8 cells between walls at ±0.44.
    let (min, max) = ([-0.44, 0.0, -0.44], [0.44, 1.76, 0.44]);
    let spheres = shower(400, min, max, 0.05).spheres().unwrap();
    inside_and_apart(&spheres, min, max);
    for k in [0, 2] {
        let lowest = spheres.iter().map(|s| s.position[k]).fold(1.0, f64::min);
        let highest = spheres.iter().map(|s| s.position[k]).fold(-1.0, f64::max);
        // Centres reach into the outermost cells at both ends (within 0.11 of the walls):
        // before, nothing came within 0.22 of the wall on the positive side.
        assert!(lowest < -0.44 + 0.11, "axis {k}: lowest centre {lowest}");
        assert!(highest > 0.44 - 0.11, "axis {k}: highest centre {highest}");
    }
}

#[test]
fn regression_boxes_of_twenty_cells_hold_as_many_wherever_they_are() {
    // Boxes twenty cells wide centred away from the origin, as the bench's tiles of showers
    // are: each corner rounds on its own, and the width they span is twenty cells to within
    // that rounding (at 75.45, 100.6 and 104.6 their width divides to 19.999999999999893 of
    // the cells).
    let cell = 2.0 * 0.05 * 1.1;
    let side = cell * 20.0;
    for x in [0.0, 3.3, 52.3, 75.45, 100.6, 104.6] {
        let (min, max) = (
            [x - side / 2.0, 1.0, x - side / 2.0],
            [x + side / 2.0, 1.0 + side, x + side / 2.0],
        );
        let spheres = shower(8000, min, max, 0.05).spheres();
        let spheres = spheres.unwrap_or_else(|e| panic!("at x = {x}: {e}"));
        assert_eq!(spheres.len(), 8000);
        inside(&spheres, min, max);
    }
}
