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
//! closes. And a contact's warm start carries at most 64 times the largest acceleration as
//! its load (the step's sweeps find any more it needs), so a jammed ring's loads stay bounded
//! (that pit's largest 800 m/s² instead of 5800).
//!
//! A column zig-zagging up a chimney is jammed the same way, between the chimney's walls: a
//! column of 100 spheres, from its tenth to its twentieth second, sank 2.6% of a radius into
//! itself and deferred 49 collisions with the loads carried whole; 1.0% and none with them
//! capped.

mod common;

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, SphereDesc, World};

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

/// `count` spheres of radius 0.05 (restitution 0.5) stacked in a chimney a tenth of a radius
/// wider than they are (a floor and four walls, fixed spheres of radius 1e4), each a hair above
/// the one below and off its axis, alternately to either side, so that they settle zig-zag.
fn column(count: usize) -> World {
    let (radius, wall) = (0.05, 1.0e4);
    let half = 1.1 * radius;
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    for at in [
        DVec3::new(0.0, -wall, 0.0),
        DVec3::new(-half - wall, 0.0, 0.0),
        DVec3::new(half + wall, 0.0, 0.0),
        DVec3::new(0.0, 0.0, -half - wall),
        DVec3::new(0.0, 0.0, half + wall),
    ] {
        world
            .add_sphere(SphereDesc::new(wall).at(at).fixed())
            .unwrap();
    }
    for k in 0..count {
        let side = if k % 2 == 0 { 0.04 } else { -0.04 };
        let at = DVec3::new(
            side * radius,
            radius + k as f64 * 2.02 * radius,
            0.01 * radius,
        );
        world
            .add_sphere(SphereDesc::new(radius).at(at).with_restitution(0.5))
            .unwrap();
    }
    world
}

/// The column of 100: from its tenth to its twentieth second no pair deeper than 1.5% of a
/// radius and no collision deferred (before the cap: 2.6% and 49).
#[test]
fn regression_a_column_jammed_in_a_chimney_does_not_sink_into_itself() {
    let radius = 0.05;
    let mut world = column(100);
    let (mut overlap, mut deferred) = (0.0f64, 0);
    for step in 0..1200 {
        let stats = *world.step(DT).unwrap();
        if step >= 600 {
            overlap = overlap.max(stats.max_overlap);
            deferred += stats.collisions_deferred;
        }
    }
    assert!(
        overlap <= 0.015 * radius,
        "overlap {} of a radius",
        overlap / radius
    );
    assert_eq!(deferred, 0);
}
