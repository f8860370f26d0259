//! Regression (2026-12-03): with nothing accelerating (no gravity, no applied force) there is
//! no resting solve, and spheres placed overlapping stayed overlapping: a 4 x 4 x 4 crowd of
//! radius 0.5 placed 0.5 m apart at rest was still a radius deep after 10 s, and a moving
//! crowd that lost its speed in its first collisions kept its overlaps too (5 x 5 x 5, 0.6 m
//! apart, velocity components up to 1 m/s, restitution 0: 0.37 m deep after 2 s, 0.14 m
//! after 10 s). Now such overlaps are undone at
//! each step's end by moving the pair's spheres apart (each by its inverse mass's share, at
//! most a tenth of its radius a step), without touching a velocity: momentum and kinetic
//! energy are kept exactly, and so is the centre of mass.

mod common;

use common::{centre_of_mass, deepest_overlap as deepest, overlapping_crowd};
use sphere_physics::glam::DVec3;
use sphere_physics::{MIN_MASS, Settings, SphereDesc, World};

const DT: f64 = 1.0 / 60.0;

#[test]
fn regression_an_overlapping_crowd_at_rest_with_no_gravity_comes_apart() {
    let mut world = overlapping_crowd(4, 0.5, 0.0, 0.5, 11);
    let centre = centre_of_mass(&world);
    // Before: 0.5 m deep (a radius) at every step for 10 s.
    let (mut apart_at, mut peak) = (None, 0.0f64);
    for step in 0..120 {
        let stats = *world.step(DT).unwrap();
        assert!(
            world.bodies().iter().all(|b| b.velocity() == DVec3::ZERO),
            "step {step}: a sphere was given a speed"
        );
        assert!(
            (centre_of_mass(&world) - centre).length() <= 1e-12,
            "step {step}: the centre of mass moved by {}",
            (centre_of_mass(&world) - centre).length()
        );
        assert!(
            (stats.max_overlap - deepest(&world)).abs() <= 1e-12,
            "step {step}: reported {} against {}",
            stats.max_overlap,
            deepest(&world)
        );
        // Within the contact band (a millionth of the diameter): touching.
        peak = peak.max(deepest(&world));
        if apart_at.is_none() && deepest(&world) <= 1.01e-6 {
            apart_at = Some(step);
        }
    }
    // Measured: every pair apart or touching after 33 steps; on the way the deepest pair was
    // 0.63 m deep (the pairs moved first squeeze the spheres behind them for a few steps).
    let apart_at = apart_at.expect("the crowd comes apart within 2 s");
    assert!(apart_at <= 40, "apart only after {apart_at} steps");
    assert!(peak <= 0.65, "squeezed to {peak}");
    assert_eq!(world.stats().separated, 0, "nothing left to move");
}

#[test]
fn regression_a_crowd_stopped_by_its_collisions_with_no_gravity_comes_apart() {
    let mut world = overlapping_crowd(5, 0.6, 1.0, 0.0, 11);
    let momentum = world.momentum();
    let mut energy = world.kinetic_energy();
    for step in 0..120 {
        let stats = *world.step(DT).unwrap();
        // 125 spheres: the broad phase's grid finds the pairs the moves bring together.
        assert!(
            deepest(&world) <= stats.max_overlap + 1e-12,
            "step {step}: reported {} against {}",
            stats.max_overlap,
            deepest(&world)
        );
        let now = world.kinetic_energy();
        assert!(
            now <= energy * (1.0 + 1e-9),
            "step {step}: kinetic energy {energy} -> {now}"
        );
        assert!(
            (world.momentum() - momentum).length() <= 1e-9,
            "step {step}: momentum moved"
        );
        energy = now;
    }
    // Before: 0.37 m deep.
    assert!(
        deepest(&world) <= 1.01e-6,
        "still {} deep after 2 s",
        deepest(&world)
    );
}

/// Two spheres of radius 1 a radius into each other at rest, the second three times as heavy:
/// each step the light one moves a tenth of its radius (its cap) and the heavy one a third of
/// that (the centre of mass stays), until they touch.
#[test]
fn two_spheres_part_by_their_inverse_masses_a_tenth_of_a_radius_a_step() {
    let mut world = World::new(Settings::default());
    let light = world
        .add_sphere(SphereDesc::new(1.0).at(DVec3::ZERO).with_density(1.0))
        .unwrap();
    let heavy = world
        .add_sphere(SphereDesc::new(1.0).at(DVec3::X).with_density(3.0))
        .unwrap();
    let x = |world: &World, id| world.body(id).unwrap().position().x;
    for step in 1..=7 {
        let stats = *world.step(DT).unwrap();
        assert_eq!(stats.separated, 2, "step {step}");
        let k = f64::from(step);
        assert!((x(&world, light) + 0.1 * k).abs() < 1e-12, "step {step}");
        assert!((x(&world, heavy) - (1.0 + 0.1 * k / 3.0)).abs() < 1e-12);
    }
    // 1/15 m of overlap is left for the eighth step, shared 3 : 1.
    let stats = *world.step(DT).unwrap();
    assert_eq!(stats.separated, 2);
    assert!((x(&world, light) + 0.75).abs() < 1e-12);
    assert!((x(&world, heavy) - 1.25).abs() < 1e-12);
    assert!(stats.max_overlap.abs() < 1e-12);
    let stats = *world.step(DT).unwrap();
    assert_eq!(stats.separated, 0, "touching: nothing to move");
    for id in [light, heavy] {
        let body = world.body(id).unwrap();
        assert_eq!(body.velocity(), DVec3::ZERO);
        assert_eq!(body.position().y, 0.0);
        assert_eq!(body.position().z, 0.0);
    }
}

/// A small sphere placed deep inside a fixed one comes out along the line from its centre, a
/// tenth of its radius a step; the fixed one stays.
#[test]
fn a_sphere_inside_a_fixed_one_comes_out_along_its_normal() {
    let mut world = World::new(Settings::default());
    let fixed = world
        .add_sphere(SphereDesc::new(1.0).at(DVec3::ZERO).fixed())
        .unwrap();
    let direction = DVec3::new(1.0, 2.0, -2.0) / 3.0;
    let ball = world
        .add_sphere(SphereDesc::new(0.1).at(direction * 0.5))
        .unwrap();
    for step in 1..=60 {
        world.step(DT).unwrap();
        let at = world.body(ball).unwrap().position();
        let expected = (0.5 + 0.01 * f64::from(step)).min(1.1);
        assert!(
            (at - direction * expected).length() < 1e-12,
            "step {step}: {at} against {}",
            direction * expected
        );
    }
    assert_eq!(world.body(fixed).unwrap().position(), DVec3::ZERO);
    assert!(world.stats().max_overlap < 1e-12);
    assert_eq!(world.body(ball).unwrap().velocity(), DVec3::ZERO);
}

/// Under gravity the resting solve undoes overlaps (by pushes within the step), not the
/// separation, even for spheres that press on nothing (two falling side by side); with the
/// resting solve turned off (`resting_factor` 0) nothing moves them apart either.
#[test]
fn with_gravity_the_separation_is_not_used() {
    for resting_factor in [Settings::default().resting_factor, 0.0] {
        let mut settings = Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0));
        settings.resting_factor = resting_factor;
        let mut world = World::new(settings);
        world
            .add_sphere(SphereDesc::new(0.5).at(DVec3::new(0.0, 10.0, 0.0)))
            .unwrap();
        world
            .add_sphere(SphereDesc::new(0.5).at(DVec3::new(0.5, 10.0, 0.0)))
            .unwrap();
        for _ in 0..60 {
            assert_eq!(world.step(DT).unwrap().separated, 0);
        }
        if resting_factor > 0.0 {
            // Within the contact band (a millionth of the diameter): touching.
            assert!(deepest(&world) <= 1.01e-6, "{}", deepest(&world));
        } else {
            assert!((deepest(&world) - 0.5).abs() <= 1e-9, "{}", deepest(&world));
        }
    }
}

/// A sphere on a string is kept within its length. A free sphere overlapping it from between
/// it and its anchor moves the whole way, a tenth of its radius a step: the string stops the
/// hung one moving away.
#[test]
fn a_sphere_on_a_string_is_not_moved_past_its_length() {
    let mut world = World::new(Settings::default());
    let hung = world
        .add_sphere(SphereDesc::new(0.5).tethered(DVec3::new(0.0, 2.0, 0.0), 2.0))
        .unwrap();
    let free = world
        .add_sphere(SphereDesc::new(0.5).at(DVec3::new(0.0, 0.7, 0.0)))
        .unwrap();
    // 0.3 m of overlap: six steps of 5 cm. In the last, the move is no longer capped, and
    // the sweeps share it with the hung sphere, whose share the string takes: the free one
    // takes half of what is left each sweep, until the pair is within its contact band.
    for step in 1..=7 {
        let stats = *world.step(DT).unwrap();
        assert_eq!(stats.separated, u32::from(step <= 6), "step {step}");
        assert_eq!(world.body(hung).unwrap().position(), DVec3::ZERO);
        let y = world.body(free).unwrap().position().y;
        let expected = 0.7 + 0.05 * f64::from(step.min(6));
        assert!(
            y <= expected + 1e-12 && y >= expected - 1e-6,
            "step {step}: {y}"
        );
        if step < 6 {
            assert!((y - expected).abs() < 1e-12, "step {step}: {y}");
        }
    }
    assert_eq!(world.body(free).unwrap().velocity(), DVec3::ZERO);
}

/// A sphere on a taut string struck from the side moves along its swing, on its string's
/// sphere: it and the free sphere share the move (equal masses), and both stay at rest.
/// (Before, a sphere on a string was never moved, and two on strings pressed together by
/// their swings sank into each other: `regression_strung_spheres_pressed_zero_g`.)
#[test]
fn a_sphere_on_a_string_moves_along_its_swing() {
    let mut world = World::new(Settings::default());
    let anchor = DVec3::new(0.0, 2.0, 0.0);
    let hung = world
        .add_sphere(SphereDesc::new(0.5).tethered(anchor, 2.0))
        .unwrap();
    let free = world
        .add_sphere(SphereDesc::new(0.5).at(DVec3::new(0.7, 0.0, 0.0)))
        .unwrap();
    for step in 1..=4 {
        world.step(DT).unwrap();
        let (h, f) = (world.body(hung).unwrap(), world.body(free).unwrap());
        // On its string's sphere, in the plane of the pair's normal, swung away from the other.
        assert!(
            ((h.position() - anchor).length() - 2.0).abs() <= 1e-12,
            "step {step}"
        );
        assert!(h.position().x < 0.0 && h.position().z == 0.0, "step {step}");
        assert!(f.position().x > 0.7 && f.position().z == 0.0, "step {step}");
        assert_eq!(h.velocity(), DVec3::ZERO);
        assert_eq!(f.velocity(), DVec3::ZERO);
    }
    // 0.3 m of overlap, each moving at most 5 cm a step: apart after the third.
    assert!(deepest(&world) <= 1.01e-6, "{}", deepest(&world));
}

/// Found in review: a sphere of radius 1e-100 (inverse mass 2e299) deep in one of radius 1e10
/// overflowed the move's inverse-mass share to infinity, and wrote NaN into its position. Now
/// the share is taken first and the cap worked out in its own units: its move (its cap, a
/// tenth of its radius) is lost in rounding next to its position, the huge one's share
/// underflows, so neither moves nor is counted, and both stay finite.
#[test]
fn regression_a_tiny_sphere_deep_in_a_huge_one_stays_finite() {
    let mut world = World::new(Settings::default());
    let huge = world.add_sphere(SphereDesc::new(1e10)).unwrap();
    let tiny = world
        .add_sphere(SphereDesc::new(1e-100).at(DVec3::new(1.0, 0.0, 0.0)))
        .unwrap();
    for _ in 0..3 {
        let stats = *world.step(DT).unwrap();
        assert!(stats.max_overlap.is_finite());
        assert_eq!(stats.separated, 0);
        for id in [huge, tiny] {
            let body = world.body(id).unwrap();
            assert!(body.position().is_finite(), "{}", body.position());
            assert_eq!(body.velocity(), DVec3::ZERO);
        }
    }
    assert_eq!(world.body(tiny).unwrap().position().y, 0.0);
}

/// Found in review: two spheres so light that their inverse masses' sum overflows (radius 1,
/// density 2e-309: masses near 8e-309) got shares of 0 and were never moved apart. The
/// shares were then taken from the weights over the larger; since a later review (their
/// impulses overflowed the same way) such spheres are refused (`MIN_MASS`), and the lightest
/// allowed part as any: equal spheres share equally, a tenth of a radius a step each.
#[test]
fn regression_spheres_too_light_to_sum_their_inverse_masses_still_part() {
    let mut world = World::new(Settings::default());
    let radius = 1.0;
    let light = |x: f64, density: f64| {
        SphereDesc::new(radius)
            .at(DVec3::new(x, 0.0, 0.0))
            .with_density(density)
    };
    let error = world.add_sphere(light(0.0, 2e-309)).unwrap_err();
    assert_eq!(error.field, sphere_physics::Field::Density);
    let lightest = 1.000001 * MIN_MASS / (4.0 / 3.0 * std::f64::consts::PI);
    let a = world.add_sphere(light(0.0, lightest)).unwrap();
    let b = world.add_sphere(light(radius, lightest)).unwrap();
    assert!(world.body(a).unwrap().inverse_mass() > 0.99e300);
    // A radius of overlap: five steps of a tenth of a radius each.
    for step in 1..=6 {
        let stats = *world.step(DT).unwrap();
        assert_eq!(
            stats.separated,
            if step <= 5 { 2 } else { 0 },
            "step {step}"
        );
    }
    let gap = world.body(b).unwrap().position().x - world.body(a).unwrap().position().x;
    assert!((gap - 2.0 * radius).abs() <= 1e-12 * radius, "{gap:e}");
}
