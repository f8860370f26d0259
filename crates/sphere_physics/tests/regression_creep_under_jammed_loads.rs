//! Regression (found 2026-12-04 by `landing_pits_stay_shallow` in
//! `regression_fallback_rounds.rs`, with `PROPTEST_RNG_SEED=60` and 2000 cases): in a pit at
//! rest, two spheres ended a step 6.4% of a radius into each other, with no
//! collision deferred and no fallback.
//!
//! A touching pair closing slower than its creep speed is left to the next step's resting
//! solve, and the creep speed grows with the contact's load (`Settings::creep_fraction`). The
//! bottom layer of a pit can jam between two walls (here a diagonal chain of three spheres
//! across a corner): its contacts' small overlaps cannot be undone, the solve's pushes against
//! them cancel, and the warm start carries them over, so the ring's loads grew step after step
//! (the largest 109 m/s² at 0.5 s, 6273 at 1.5 s). At that load the creep speed was 1.5 m/s,
//! and a pair closing at 0.25 m/s sank 6.4% of a radius in one step. Now a pair that would end
//! the step more than 1% of the smaller radius deep is met as an impact, however slowly it
//! closes (the jammed ring's loads still grow; they no longer let pairs sink).

mod common;

use sphere_physics::World;

const DT: f64 = 1.0 / 60.0;

/// Steps `world` for two seconds and returns the deepest overlap at a step's end, as a
/// fraction of `radius`.
fn deepest(world: &mut World, radius: f64) -> f64 {
    let mut overlap = 0.0f64;
    for _ in 0..120 {
        let stats = *world.step(DT).unwrap();
        overlap = overlap.max(stats.max_overlap);
        assert!(
            world
                .bodies()
                .iter()
                .all(|b| b.position().is_finite() && b.velocity().is_finite())
        );
    }
    overlap / radius
}

/// The pit that showed it: before, 6.4% of a radius deep at step 90; now 1.0%.
#[test]
fn regression_a_jammed_rings_load_does_not_let_a_pair_sink() {
    let radius = 0.055985876335067644;
    let mut world = common::pit(70, 335, 0.10424206768781548, radius, 1.0);
    let overlap = deepest(&mut world, radius);
    assert!(overlap <= 0.02, "overlap {overlap} of a radius");
}
