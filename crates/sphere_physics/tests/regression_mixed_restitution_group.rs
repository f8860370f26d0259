//! Regression (found 2026-12-03 by `sphere-fuzz --overlapping`, with no gravity): contacts
//! solved together gained energy when their restitutions differ. A group's compression
//! impulses `λ` just stop every contact approaching; each contact then gets `restitution · λ`
//! more. With one restitution for all that never gains energy, but with several it may: a
//! ball striking a line of two at one instant, restitution 1 where it strikes and 0 between
//! the two, left them with 0.611 J of the 0.5 J it brought. Now the restitution impulses are
//! scaled down together, where they would gain energy, to where the group has what it had.
//! The property test over random groups of mixed restitutions is in `simultaneous.rs`
//! (`groups_with_mixed_restitutions_never_gain_energy`; it fails before the fix too).

use sphere_physics::glam::DVec3;
use sphere_physics::{GroupContact, resolve_simultaneous};

fn energy(inverse_masses: &[f64], velocities: &[DVec3]) -> f64 {
    velocities
        .iter()
        .zip(inverse_masses)
        .filter(|(_, im)| **im > 0.0)
        .map(|(v, im)| 0.5 * v.length_squared() / im)
        .sum()
}

/// The strike below, solved: the scale `s` of the restitution impulse that keeps the energy,
/// and the three balls' speeds after it, in units of the striker's.
fn line_of_two_answer() -> (f64, [f64; 3]) {
    let s = 3f64.sqrt() / 2.0;
    (
        s,
        [
            1.0 / 3.0 - s * 2.0 / 3.0,
            1.0 / 3.0 + s * 2.0 / 3.0,
            1.0 / 3.0,
        ],
    )
}

#[test]
fn regression_a_strike_on_a_line_of_two_with_mixed_restitutions_gains_no_energy() {
    // Three equal balls on the x axis: the first at 1 m/s strikes the second, which touches
    // the third, at one instant. Compression leaves all three at 1/3 m/s, with impulses 2/3
    // and 1/3. The full restitution impulse (2/3, on the first contact only) would leave
    // -1/3, 1, 1/3 m/s: 11/18 J from 1/2. Its energy at a scale s of it is 1/6 + 4/9 s², so
    // s = √3/2 keeps the 1/2 J exactly.
    let inverse = [1.0, 1.0, 1.0];
    let before = [DVec3::X, DVec3::ZERO, DVec3::ZERO];
    let contacts = [
        GroupContact::new(0, 1, DVec3::X, 1.0),
        GroupContact::new(1, 2, DVec3::X, 0.0),
    ];
    let mut velocities = before;
    let mut impulses = Vec::new();
    resolve_simultaneous(&inverse, &mut velocities, &contacts, &mut impulses);
    let (s, expected) = line_of_two_answer();
    for (v, x) in velocities.iter().zip(expected) {
        assert!((*v - DVec3::X * x).length() <= 1e-12, "{velocities:?}");
    }
    assert!(
        (impulses[0] - (1.0 + s) * 2.0 / 3.0).abs() <= 1e-12,
        "{impulses:?}"
    );
    assert!((impulses[1] - 1.0 / 3.0).abs() <= 1e-12, "{impulses:?}");
    let momentum: DVec3 = velocities.iter().sum();
    assert!((momentum - DVec3::X).length() <= 1e-15);
    // Before: 11/18 J.
    assert!(energy(&inverse, &velocities) <= 0.5 * (1.0 + 1e-12));
}

#[test]
fn a_moving_fixed_body_is_judged_in_its_own_frame() {
    // A fixed paddle at 1 m/s strikes a ball (restitution 1) touching another (restitution 0
    // between the two), both at rest. In the paddle's frame both come at it at 1 m/s with
    // 1 J: compression stops both (impulses 2 and 1), and the paddle's whole restitution
    // impulse would send the first back at 2 m/s with 2 J. Scaled to keep the 1 J, by
    // s = 1/√2: the first leaves at √2 m/s in the paddle's frame, the second stays with the
    // paddle. (Judged in the world's frame, the paddle's bounce would be taken away whole:
    // the energy it gives is not the group's to refuse.)
    let inverse = [0.0, 1.0, 1.0];
    let contacts = [
        GroupContact::new(0, 1, DVec3::X, 1.0),
        GroupContact::new(1, 2, DVec3::X, 0.0),
    ];
    let mut velocities = [DVec3::X, DVec3::ZERO, DVec3::ZERO];
    let mut impulses = Vec::new();
    resolve_simultaneous(&inverse, &mut velocities, &contacts, &mut impulses);
    let expected = [1.0, 1.0 + 2f64.sqrt(), 1.0];
    for (v, x) in velocities.iter().zip(expected) {
        assert!((*v - DVec3::X * x).length() <= 1e-12, "{velocities:?}");
    }
    let relative: Vec<DVec3> = velocities.iter().map(|v| *v - DVec3::X).collect();
    assert!(energy(&inverse, &relative) <= 1.0 + 1e-12);
}

/// Regression (found by review in the fifty-seventh session): the same strike by spheres of
/// 1e200 kg at 1e60 m/s (within the documented limits: the impulses stay finite), whose
/// kinetic energy overflows an f64, skipped the check and kept 11/9 of its energy. The answer
/// is the one above, scaled.
#[test]
fn regression_the_strike_of_a_huge_energy_is_scaled_too() {
    let speed = 1e60;
    let inverse = [1e-200; 3];
    let contacts = [
        GroupContact::new(0, 1, DVec3::X, 1.0),
        GroupContact::new(1, 2, DVec3::X, 0.0),
    ];
    let mut velocities = [DVec3::X * speed, DVec3::ZERO, DVec3::ZERO];
    let mut impulses = Vec::new();
    resolve_simultaneous(&inverse, &mut velocities, &contacts, &mut impulses);
    let (_, expected) = line_of_two_answer();
    for (v, x) in velocities.iter().zip(expected) {
        assert!(
            (*v / speed - DVec3::X * x).length() <= 1e-12,
            "{velocities:?}"
        );
    }
    // Its energy, in units of the striker's: no more than it brought.
    let scaled: Vec<DVec3> = velocities.iter().map(|v| *v / speed).collect();
    assert!(energy(&[1.0; 3], &scaled) <= 0.5 * (1.0 + 1e-12));
}
