//! Pairs that start at (or within the tolerance of) contact: the exact method reports an impact
//! at 0 exactly when the tolerance calls them touching and they approach, whatever the radii and
//! the tolerance, right up to the edge of the tolerance band.

mod common;
use proptest::prelude::*;
use sphere_physics::{ExactToi, TimeOfImpact, Tolerance, glam::DVec3};

/// A distance `steps` ulps from the largest distance the tolerance still calls touching.
fn near_edge(contact: f64, eps: f64, steps: i64) -> f64 {
    let tol = Tolerance::new(eps).expect("valid");
    // Walk to the edge: the largest distance with `eq(distance, contact)`.
    let mut edge = (contact + eps) / (1.0 - eps);
    while !tol.eq(edge, contact) {
        edge = edge.next_down();
    }
    while tol.eq(edge.next_up(), contact) {
        edge = edge.next_up();
    }
    let mut d = edge;
    for _ in 0..steps.unsigned_abs() {
        d = if steps > 0 {
            d.next_up()
        } else {
            d.next_down()
        };
    }
    d
}

proptest! {
    #![proptest_config(crate::common::proptest_config(512, crate::common::SEED))]
    #[test]
    fn touching_at_start_follows_the_tolerance(
        contact in 1e-3..1e3f64,
        eps in prop::sample::select(vec![0.0, 1e-12, 1e-9, 1e-6, 1e-3]),
        steps in -3i64..=3,
        direction in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
        speed in 0.1..10.0f64,
    ) {
        let axis = DVec3::new(direction.0, direction.1, direction.2);
        prop_assume!(axis.length() > 0.1);
        let tol = Tolerance::new(eps).expect("valid");
        let distance = near_edge(contact, eps, steps);
        let d = axis.normalize() * distance;
        // Straight at each other: a long way from the tolerance on the speed.
        let w = -d.normalize() * speed;
        let outcome = ExactToi.time_of_impact(d, w, contact, 1.0, tol);
        let touching = d.length() <= contact || tol.eq(d.length(), contact);
        if touching {
            prop_assert_eq!(outcome.time, Some(0.0));
        } else {
            // Apart, but closing straight on: an impact later than 0 and no later than the gap
            // takes to close (give or take the rounding of the gap, a few units in the last
            // place of `contact`), or none if the gap takes longer than the interval.
            let gap = d.length() - contact;
            let slack = 4.0 * f64::EPSILON * contact / speed;
            let closes = gap / speed;
            if closes + slack < 1.0 {
                prop_assert!(
                    outcome.time.is_some_and(|t| t > 0.0 && t <= closes + slack),
                    "{:?}: gap {:e} closes at {:e}", outcome, gap, closes
                );
            } else if closes - slack > 1.0 {
                prop_assert_eq!(outcome.time, None, "gap {:e} closes at {:e}", gap, closes);
            }
        }
    }
}
