//! Regression (found 2026-12-06, stepping the 100k shower benchmark through its climax): one
//! body may take only so many collisions in a step (its share, a multiple of
//! `max_collisions_per_body`), so that a sphere wedged between fixed ones cannot spend the
//! world's budget; past it the body is squeezed a few times, then its impacts are deferred to
//! the next step. The share was 1024 collisions. Spheres in a crowd that chatters take more
//! than that without anything being wrong: sliding down the 100k shower's dome in its film,
//! up to 2228 in a step, and dozens of them ran out of their shares in the same steps. Their
//! deferred impacts left pairs up to 6.4 mm deep (an eighth of a radius) at the step's end;
//! with a share of 4096 no pair ends any of those 150 steps 0.25 mm deep. The landing pit of
//! 10 000 showed the same in its first layer: spheres in a corner of the box took 1159 to 1410
//! collisions in its 16th step, and 21 impacts were deferred, though the world's budget had
//! not run out.
//!
//! In a world with strings a body's share stayed 1024 at first (there the fallback defers the
//! strung spheres' pairs, so a share must run out before a small world's budget does): with
//! one sphere on a string far above it, the same landing pit deferred 178 impacts in its
//! first second and ended a step with a pair 8.1 mm deep. There a share is now a quarter of
//! the world's budget, from 1024 to 4096.

mod common;

use sphere_physics::glam::DVec3;
use sphere_physics::{SphereDesc, World};

const DT: f64 = 1.0 / 60.0;

/// Steps `world` (the landing pit of 10 000) until its budget first runs out, asserting that
/// nothing is deferred before, and that it got past the 16th step, where the first layer's
/// corners chatter.
fn defers_nothing_before_its_budget_runs_out(mut world: World) {
    let mut steps = 0;
    for step in 1..=18 {
        let stats = *world.step(DT).expect("the pit steps");
        if stats.fell_back {
            break;
        }
        assert_eq!(stats.collisions_deferred, 0, "step {step}: {stats:?}");
        steps = step;
    }
    assert!(steps >= 16, "the budget ran out at step {}", steps + 1);
}

/// The bench's landing pit of 10 000 (`sphere_bench`'s `pile`, seed 1) until its first layer
/// lands in the box's corners: no impact is deferred before the world's budget first runs out.
#[test]
fn regression_a_landing_pit_defers_nothing_before_its_budget_runs_out() {
    defers_nothing_before_its_budget_runs_out(common::pit(10_000, 1, 0.5, 0.05, 0.0));
}

/// The same with a sphere hanging on a string far above the pit (the old core deferred 39
/// impacts at step 16).
#[test]
fn regression_a_landing_pit_in_a_world_with_a_string_defers_nothing_before_its_budget_runs_out() {
    let mut world = common::pit(10_000, 1, 0.5, 0.05, 0.0);
    world
        .add_sphere(
            SphereDesc::new(0.05)
                .at(DVec3::new(0.0, 1000.0, 0.0))
                .tethered(DVec3::new(0.0, 1001.0, 0.0), 1.0),
        )
        .unwrap();
    defers_nothing_before_its_budget_runs_out(world);
}
