//! Invariants on random scenes: momentum conserved, no NaN, no overlap, energy never gained.
mod common;

use proptest::prelude::*;
use sphere_physics::{IntegratorKind, Settings, SphereDesc, World, glam::DVec3};

fn scene() -> impl Strategy<Value = Vec<(f64, f64, f64, f64, f64, f64, f64)>> {
    // Spheres on a grid of spacing 1, each moved by up to 0.1 along (1, 1, 1), so neighbours are
    // at least 1 - 0.2·√3 > 0.65 apart and radii up to 0.32 never overlap at start; random
    // velocity, density, restitution.
    prop::collection::vec(
        (
            -5.0..5.0f64,
            -5.0..5.0f64,
            -5.0..5.0f64,
            0.1..0.32f64,
            0.5..3.0f64,
            0.0..=1.0f64,
            -0.2..0.2f64,
        ),
        // Past 64 bodies the broad phase's grid takes over from all pairs: both are covered.
        2..160,
    )
}

proptest! {
    #![proptest_config(crate::common::proptest_config(64, crate::common::SEED))]
    #[test]
    fn invariants_hold(spheres in scene(), dt in 0.005..0.2f64) {
        let mut world = World::new(Settings::default());
        common::add_drops(&mut world, &spheres);
        let p0 = world.momentum();
        let mut energy = world.kinetic_energy();
        for _ in 0..60 {
            let stats = *world.step(dt).unwrap();
            prop_assert!(world.bodies().iter().all(|b| b.position().is_finite() && b.velocity().is_finite()));
            prop_assert!((stats.momentum - p0).length() <= 1e-9 * (1.0 + p0.length()));
            prop_assert!(stats.kinetic_energy <= energy * (1.0 + 1e-12) + 1e-12);
            prop_assert!(stats.max_overlap <= 1e-8, "overlap {}", stats.max_overlap);
            energy = stats.kinetic_energy;
        }
    }

    /// Elastic spheres with no gravity: every collision keeps the kinetic energy, so the
    /// scene keeps it step after step (to rounding), whatever the step.
    #[test]
    fn elastic_scenes_keep_their_energy(spheres in scene(), dt in 0.005..0.2f64) {
        let mut world = World::new(Settings::default());
        let elastic: Vec<common::Drop> = spheres.iter().map(|&(vx, vy, vz, r, rho, _, jitter)| (vx, vy, vz, r, rho, 1.0, jitter)).collect();
        common::add_drops(&mut world, &elastic);
        let energy = world.kinetic_energy();
        let mut collisions = 0;
        for step in 0..60 {
            let stats = *world.step(dt).unwrap();
            collisions += stats.collisions;
            prop_assert!(
                (stats.kinetic_energy - energy).abs() <= 1e-12 * energy * f64::from(collisions + 1),
                "step {}: {} after {} collisions, from {}", step, stats.kinetic_energy, collisions, energy
            );
        }
    }

    /// Many spheres raining onto a big fixed sphere under gravity: the grid keeps the big sphere
    /// on a level of its own; none may be missed, so overlap stays within the creep bound.
    #[test]
    fn rain_on_a_big_fixed_sphere(spheres in scene(), dt in 0.005..0.05f64) {
        let mut world = common::rain_on_a_dome(&spheres);
        let creep = common::creep(&world, dt);
        for _ in 0..60 {
            let stats = *world.step(dt).unwrap();
            prop_assert!(world.bodies().iter().all(|b| b.position().is_finite() && b.velocity().is_finite()));
            prop_assert!(stats.max_overlap <= creep, "overlap {} (creep allowance {})", stats.max_overlap, creep);
        }
    }

    /// Every contact the step counts has its record, and every record is well formed: ids in
    /// order, a time within the step (records in time order), a unit normal, an impulse >= 0.
    #[test]
    fn collision_records_match_the_stats(spheres in scene(), dt in 0.005..0.05f64) {
        let mut world = common::rain_on_a_dome(&spheres);
        for step in 0..60 {
            let start = world.time();
            let stats = *world.step(dt).unwrap();
            let records = world.collisions();
            prop_assert_eq!(stats.collisions as usize, records.len(), "step {}", step);
            prop_assert_eq!(
                stats.resting_contacts as usize,
                records.iter().filter(|c| c.resting).count(),
                "step {}", step
            );
            let slack = 1e-12 * (1.0 + stats.time.abs());
            let mut last = start - slack;
            for c in records {
                prop_assert!(c.a < c.b, "step {step}: {c:?}");
                prop_assert!(c.time >= last && c.time <= stats.time + slack, "step {step}: {c:?}");
                prop_assert!((c.normal.length() - 1.0).abs() < 1e-12, "step {step}: {c:?}");
                prop_assert!(c.impulse.is_finite() && c.impulse >= 0.0, "step {step}: {c:?}");
                last = c.time;
            }
        }
    }

    #[test]
    fn deterministic(spheres in scene()) {
        let run = || {
            let mut world = World::new(Settings::default());
            for (i, &(vx, vy, vz, r, rho, e, _)) in spheres.iter().enumerate() {
                let at = DVec3::new(i as f64, 0.0, 0.0);
                world.add_sphere(SphereDesc::new(r).at(at).moving(DVec3::new(vx, vy, vz))
                    .with_density(rho).with_restitution(e)).unwrap();
            }
            for _ in 0..30 { world.step(0.05).unwrap(); }
            world.bodies().iter().map(|b| (b.position().to_array(), b.velocity().to_array())).collect::<Vec<_>>()
        };
        let (a, b) = (run(), run());
        prop_assert!(a.iter().zip(&b).all(|(x, y)| x.0.map(f64::to_bits) == y.0.map(f64::to_bits) && x.1.map(f64::to_bits) == y.1.map(f64::to_bits)));
    }
}

proptest! {
    // More cases: the overlaps it checks come from spheres sliding together in piles, which
    // only some scenes make.
    #![proptest_config(crate::common::proptest_config(512, crate::common::SEED))]
    /// A step's reported largest overlap is the largest overlap of any pair at its end (the
    /// step finds it from the pairs it tested; the world's check looks at every pair).
    #[test]
    fn the_step_reports_the_largest_overlap(spheres in scene(), dt in 0.005..0.05f64) {
        let mut world = common::rain_on_a_dome(&spheres);
        for step in 0..40 {
            let reported = world.step(dt).unwrap().max_overlap;
            let actual = world.max_overlap();
            // The same arithmetic on the same positions: equal to the bit.
            prop_assert!(reported == actual, "step {step}: reported {reported}, actual {actual}");
        }
    }
}

/// The same check on a scene sure to overlap within the resting allowance (a column of five
/// balls resting on a fixed dome, as in `regression_stack_on_dome`), so that the comparison is
/// not of zeros only.
#[test]
fn the_step_reports_the_largest_overlap_of_a_resting_column() {
    let (mut world, _) = common::column_on_a_dome(5);
    let mut overlapping = 0;
    for step in 0..300 {
        let reported = world.step(0.0443324348313259).unwrap().max_overlap;
        let actual = world.max_overlap();
        assert!(
            reported == actual,
            "step {step}: reported {reported}, actual {actual}"
        );
        if actual > 0.0 {
            overlapping += 1;
        }
    }
    assert!(overlapping > 200, "{overlapping} of 300 steps overlapped");
}

/// Spheres at a few metres a second on a lattice of spacing 1 (four by four per layer), about
/// half of them hanging on strings from anchors straight above (0.5 to 3 m, up to 5 cm slack):
/// swinging, caught by their strings, striking the free ones and each other.
fn strung_scene() -> impl Strategy<Value = Vec<common::Strung>> {
    prop::collection::vec(
        (
            (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
            0.05..0.45f64,
            -1.0..3.0f64,
            0.0..=1.0f64,
            prop::option::of((0.5..3.0f64, 0.0..0.05f64)),
        ),
        2..48,
    )
}

proptest! {
    #![proptest_config(crate::common::proptest_config(128, crate::common::SEED))]
    /// Strings among free spheres, with or without gravity, either integrator: no step ends
    /// with two spheres more than 5% of the smaller one's radius into each other while no
    /// collision is deferred (a string's drift is a chord of its arc, so not 0: 3.3% at worst
    /// over the 626 scenes with strings of `sphere-fuzz --strings slow`), and no string ends
    /// longer than its length. Before a string that catches its sphere within a step held it
    /// from the catch on, 13 of those 626 scenes went past 5% within the collision budget.
    #[test]
    fn strings_among_free_spheres_leave_no_overlap(
        spheres in strung_scene(),
        gravity in prop::bool::ANY,
        leapfrog in prop::bool::ANY,
        steps_per_second in 30.0..240.0f64,
    ) {
        let settings = Settings {
            integrator: if leapfrog { IntegratorKind::Leapfrog } else { IntegratorKind::SemiImplicitEuler },
            ..Settings::with_gravity(DVec3::new(0.0, if gravity { -9.81 } else { 0.0 }, 0.0))
        };
        let mut world = common::strung_world(&spheres, settings);
        let dt = 1.0 / steps_per_second;
        let mut deferred_before = 0;
        let start = world.kinetic_energy();
        for step in 0..60 {
            let deferred_now = world.step(dt).unwrap().collisions_deferred;
            // A step is judged unless it or the one before put collisions off (found by
            // review: a sum over the case stopped judging every step after the first).
            let deferred = deferred_now + deferred_before;
            deferred_before = deferred_now;
            // With no gravity nothing does work: the strings pull across the motion and the
            // impacts take energy away. A string's drift is a chord, so not exactly: a step
            // might gain a little, though none did in these cases or three other seeds' (the
            // bound was 5% until a review asked for the measured gain).
            if !gravity {
                let energy = world.kinetic_energy();
                prop_assert!(
                    energy <= start * (1.0 + 1e-9) + 1e-12,
                    "step {}: kinetic energy {} from {}", step, energy, start
                );
            }
            let bodies = world.bodies();
            prop_assert!(bodies.iter().all(|b| b.position().is_finite() && b.velocity().is_finite()));
            // Once the step's collision budget has run out, the collisions it put off may
            // leave overlaps (as `Settings::max_collisions_per_body` says): a heavy sphere
            // pushing a light one along its string's arc, with no gravity, strikes it again
            // and again, its straight drift against the string's chord.
            for (i, a) in bodies.iter().enumerate().filter(|_| deferred == 0) {
                for b in &bodies[i + 1..] {
                    let overlap = a.radius() + b.radius() - (b.position() - a.position()).length();
                    let smaller = a.radius().min(b.radius());
                    prop_assert!(
                        overlap <= 0.05 * smaller,
                        "step {}: {:?} and {:?} overlap {} (radii {}, {})",
                        step, a.id(), b.id(), overlap, a.radius(), b.radius()
                    );
                }
            }
            for b in world.bodies() {
                if let Some(t) = b.tether() {
                    prop_assert!((b.position() - t.anchor).length() <= t.length * (1.0 + 1e-9));
                }
            }
        }
    }
}
