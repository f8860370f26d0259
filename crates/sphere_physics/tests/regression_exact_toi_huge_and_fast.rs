//! Regression (found by review): the exact time of impact squared the relative speed times
//! the contact distance, which overflows an f64 past about 1e154 although every distance and
//! radius is far below the documented 1e150 m. A sphere meeting one of radius 1e100 m head-on
//! at 1e94 m/s was reported touching at the start of the step, still 1e92 m away (the root
//! `c / inf` is 0), and one meeting it obliquely was missed (`inf - inf` is NaN) and passed
//! into it. Such pairs now take the same root with the velocity scaled down.

use sphere_physics::glam::DVec3;
use sphere_physics::{ExactToi, Settings, SphereDesc, TimeOfImpact, Tolerance, World};

fn exact(d: DVec3, w: DVec3, contact: f64, t_max: f64) -> Option<f64> {
    ExactToi
        .time_of_impact(d, w, contact, t_max, Tolerance::default())
        .time
}

#[test]
fn regression_the_exact_time_of_impact_of_a_huge_fast_pair() {
    let contact = 1e100;
    let speed = 1e94;
    // Head-on from 2e100 m: the gap of 1e100 m closes in 1e6 s.
    let head_on = exact(
        DVec3::new(2e100, 0.0, 0.0),
        DVec3::new(-speed, 0.0, 0.0),
        contact,
        1e7,
    )
    .unwrap();
    assert!((head_on - 1e6).abs() <= 1e-12 * 1e6, "{head_on}");
    // Obliquely, half a contact distance off the line: it touches where x = √(3/4)·1e100.
    for speed in [speed, speed * 1e100] {
        let w = DVec3::new(-speed, 0.0, 0.0);
        let oblique = exact(DVec3::new(2e100, 0.5e100, 0.0), w, contact, 1e7).unwrap();
        let expected = (2e100 - 0.75f64.sqrt() * 1e100) / speed;
        assert!(
            (oblique - expected).abs() <= 1e-12 * expected,
            "{oblique} against {expected}"
        );
    }
    // Passing wide (1.5 contact distances off the line), or moving away: no impact.
    assert_eq!(
        exact(
            DVec3::new(2e100, 1.5e100, 0.0),
            DVec3::new(-speed, 0.0, 0.0),
            contact,
            1e7
        ),
        None
    );
    assert_eq!(
        exact(
            DVec3::new(2e100, 0.5e100, 0.0),
            DVec3::new(speed, 0.0, 0.0),
            contact,
            1e7
        ),
        None
    );
}

#[test]
fn regression_a_fast_sphere_meets_a_huge_one_when_it_reaches_it() {
    for offset in [0.0, 0.5e100] {
        let mut world = World::new(Settings::default());
        let huge = world.add_sphere(SphereDesc::new(1e100).fixed()).unwrap();
        // 1e92 m from the huge sphere's surface (along x), closing at 1e94 m/s: 0.01 s away.
        let x = (1e100f64 * 1e100 - offset * offset).sqrt() + 1e92;
        let ball = world
            .add_sphere(
                SphereDesc::new(1.0)
                    .at(DVec3::new(x, offset, 0.0))
                    .moving(DVec3::new(-1e94, 0.0, 0.0)),
            )
            .unwrap();
        world.step(1.0 / 60.0).unwrap();
        let hits = world.collisions();
        assert_eq!(hits.len(), 1, "offset {offset}: {hits:?}");
        assert_eq!((hits[0].a, hits[0].b), (huge, ball));
        assert!((hits[0].time - 0.01).abs() <= 1e-6, "{:?}", hits[0]);
    }
}
