//! Regression (found by review, sixty-fourth session): the exact time of impact squared the
//! relative speed times the contact distance, which underflows an f64 below about 1e-162.
//! Spheres of radius 1e-80 m closing head-on at 1e-83 m/s from 3e-80 m apart meet at 1000 s,
//! but the discriminant's 4e-326 was 0 and the root came out at 1666.7 s: past a step of
//! 1500 s, so the pair was missed and ended the step a quarter of its contact distance deep.
//! Such pairs now take the same root in units of their size and speed.

use sphere_physics::glam::DVec3;
use sphere_physics::{ExactToi, TimeOfImpact, Tolerance};

fn exact(d: DVec3, w: DVec3, contact: f64, t_max: f64) -> Option<f64> {
    // With no tolerance, so that tiny spheres are not taken as touching already.
    let tolerance = Tolerance::new(0.0).unwrap();
    ExactToi
        .time_of_impact(d, w, contact, t_max, tolerance)
        .time
}

#[test]
fn regression_tiny_slow_spheres_meet_when_they_do() {
    let t = exact(
        DVec3::new(3e-80, 0.0, 0.0),
        DVec3::new(-1e-83, 0.0, 0.0),
        2e-80,
        1500.0,
    );
    let t = t.expect("the pair meets within the step");
    assert!((t - 1000.0).abs() <= 1e-12 * 1000.0, "{t}");
}

#[test]
fn regression_the_time_of_impact_does_not_depend_on_the_units() {
    // The same pairs in metres and seconds, and with lengths scaled by `length` and speeds by
    // `speed` (times scale by length / speed): head-on, oblique, grazing and missing.
    let pairs = [
        (DVec3::new(3.0, 0.0, 0.0), DVec3::new(-1.0, 0.0, 0.0)),
        (DVec3::new(3.0, 1.0, 0.0), DVec3::new(-1.0, 0.0, 0.0)),
        (DVec3::new(3.0, 1.9, 0.5), DVec3::new(-1.0, 0.1, -0.2)),
        (DVec3::new(3.0, 2.5, 0.0), DVec3::new(-1.0, 0.0, 0.0)),
        (DVec3::new(-4.0, 3.0, 1.0), DVec3::new(0.7, -0.5, -0.1)),
    ];
    for (length, speed) in [
        (1e-80, 1e-83),
        (1e-150, 1e-20),
        (1e-100, 1e-100),
        (1e-20, 1e-130),
    ] {
        for (d, w) in pairs {
            let unit = exact(d, w, 2.0, 10.0);
            let scaled = exact(d * length, w * speed, 2.0 * length, 10.0 * length / speed);
            match (unit, scaled) {
                (Some(a), Some(b)) => {
                    let b = b * speed / length;
                    assert!(
                        (a - b).abs() <= 1e-12 * a,
                        "{d} {w} at {length:e}, {speed:e}: {a} vs {b}"
                    );
                }
                (None, None) => {}
                other => panic!("{d} {w} at {length:e}, {speed:e}: {other:?}"),
            }
        }
    }
}
