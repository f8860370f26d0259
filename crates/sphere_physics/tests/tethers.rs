//! Tethers: pendulums and the Newton's cradle that swings (issue 7's accuracy checks).

use sphere_physics::glam::DVec3;
use sphere_physics::{Field, IntegratorKind, SceneDesc, Settings, SphereDesc, World};

fn scene(name: &str) -> SceneDesc {
    let path = format!(
        "{}/../../assets/scenes/{name}.ron",
        env!("CARGO_MANIFEST_DIR")
    );
    SceneDesc::load(path).unwrap()
}

const DT: f64 = 1.0 / 60.0;

/// A pendulum released at 30°: the period matches the exact large-amplitude period, the string
/// is never longer than its length, and the energy stays within 0.1% without drifting.
#[test]
fn pendulum_period_and_energy() {
    let settings = Settings {
        integrator: IntegratorKind::Leapfrog,
        ..Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0))
    };
    let mut world = World::new(settings);
    let anchor = DVec3::new(0.0, 1.0, 0.0);
    let theta0 = 30f64.to_radians();
    let bob = world
        .add_sphere(
            SphereDesc::new(0.1)
                .at(anchor + DVec3::new(-theta0.sin(), -theta0.cos(), 0.0))
                .tethered(anchor, 1.0),
        )
        .unwrap();
    let energy = world.kinetic_energy() + world.potential_energy();
    // Period by the complete elliptic integral: T = 4 sqrt(L/g) K(sin(θ0/2)), K by the AGM.
    let k = (theta0 / 2.0).sin();
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..10 {
        (a, b) = ((a + b) / 2.0, (a * b).sqrt());
    }
    let period = 4.0 * (1.0 / 9.81f64).sqrt() * std::f64::consts::FRAC_PI_2 / a;
    // Time the upward crossings of x = 0 (moving right) by interpolation.
    let mut crossings = Vec::new();
    let mut previous = world.body(bob).unwrap().position().x;
    for step in 1..=3600 {
        world.step(DT).unwrap();
        let body = world.body(bob).unwrap();
        let x = body.position().x;
        if previous < 0.0 && x >= 0.0 {
            crossings.push((step as f64 - x / (x - previous)) * DT);
        }
        previous = x;
        assert!((body.position() - anchor).length() <= 1.0 + 1e-12);
        let e = world.kinetic_energy() + world.potential_energy();
        assert!(
            (e - energy).abs() <= 1e-3 * energy.abs(),
            "energy {e} vs {energy}"
        );
    }
    let measured = (crossings.last().unwrap() - crossings[0]) / (crossings.len() - 1) as f64;
    // Leapfrog's phase error over a swing, about (ωh)²/24 (1.1e-4 here; 1.5e-4 measured).
    assert!(
        (measured - period).abs() <= 3e-4 * period,
        "period {measured} vs {period}"
    );
}

/// One ball in, one ball out; the balls in the middle stay at rest; over 60 s every swing's
/// peak stays within 1% of the release height and the energy within 1%.
#[test]
fn cradle_one_in_one_out_for_a_minute() {
    let mut world = scene("newtons_cradle").build().unwrap();
    let ids: Vec<_> = world.bodies().iter().map(|b| b.id()).collect();
    let release = world.body(ids[0]).unwrap().position().y;
    let energy = world.kinetic_energy() + world.potential_energy();
    let mut peaks = Vec::new();
    let mut rising = [false; 5];
    let mut last_y = [0.0; 5];
    let mut worst_middle: f64 = 0.0;
    for _ in 0..3600 {
        world.step(DT).unwrap();
        let e = world.kinetic_energy() + world.potential_energy();
        assert!(
            (e - energy).abs() <= 0.01 * energy,
            "energy {e} vs {energy}"
        );
        let speeds: Vec<f64> = ids
            .iter()
            .map(|&id| world.body(id).unwrap().velocity().length())
            .collect();
        let striker = speeds.iter().copied().fold(0.0, f64::max);
        // Once a ball swings, the three middle balls stay at rest.
        if striker > 0.5 {
            worst_middle =
                worst_middle.max(speeds[1..4].iter().copied().fold(0.0, f64::max) / striker);
        }
        for k in [0, 4] {
            let y = world.body(ids[k]).unwrap().position().y;
            if rising[k] && y < last_y[k] && last_y[k] > 0.05 {
                peaks.push(last_y[k]);
            }
            rising[k] = y > last_y[k];
            last_y[k] = y;
        }
    }
    assert!(peaks.len() >= 55, "{} peaks in a minute", peaks.len());
    for (i, peak) in peaks.iter().enumerate() {
        assert!(
            (peak - release).abs() <= 0.01 * release,
            "peak {i}: {peak} vs {release}"
        );
    }
    assert!(
        worst_middle < 1e-6,
        "middle balls at {worst_middle} of the striker's speed"
    );
}

#[test]
fn cradle_two_in_two_out() {
    let mut world = scene("newtons_cradle_two").build().unwrap();
    let ids: Vec<_> = world.bodies().iter().map(|b| b.id()).collect();
    let g = world.settings().gravity.length();
    let y = |world: &World, k: usize| world.body(ids[k]).unwrap().position().y;
    // The raised pair's height above the hanging balls.
    let (release, bottom) = (y(&world, 0), y(&world, 4));
    assert!((y(&world, 1) - release).abs() < 1e-12);
    // The pair reaches the bottom in about a quarter period (0.5 s) and the far pair is out
    // soon after: look at t = 0.75 s.
    for _ in 0..45 {
        world.step(DT).unwrap();
    }
    let v: Vec<f64> = ids
        .iter()
        .map(|&id| world.body(id).unwrap().velocity().length())
        .collect();
    // Each ball out carries what one raised ball brought in: per kilogram, g times the
    // release height (to 1%, the tethered cradle's error at one step of 1/60 s).
    for k in [3, 4] {
        let energy = 0.5 * v[k] * v[k] + g * (y(&world, k) - bottom);
        let brought = g * (release - bottom);
        assert!(
            (energy - brought).abs() <= 0.01 * brought,
            "ball {k}: {energy} J/kg out against {brought} in: {v:?}"
        );
    }
    assert!((v[3] - v[4]).abs() < 1e-6 * v[4], "together: {v:?}");
    for (k, speed) in v.iter().enumerate().take(3) {
        assert!(*speed < 1e-6 * v[4], "ball {k} at {speed}");
    }
}

/// Restitution 0.9, a tethered ball striking one hanging ball: the first impact gives exactly
/// v(1 − e)/2 and v(1 + e)/2, and the energy then only ever falls; no sticking: the pair keeps
/// colliding with decaying swings.
#[test]
fn inelastic_pair_decays_as_physics_says() {
    let settings = Settings {
        integrator: IntegratorKind::Leapfrog,
        substeps: 2,
        ..Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0))
    };
    let mut world = World::new(settings);
    let (a0, a1) = (DVec3::new(-0.1, 1.0, 0.0), DVec3::new(0.1, 1.0, 0.0));
    let theta = 30f64.to_radians();
    let striker = world
        .add_sphere(
            SphereDesc::new(0.1)
                .at(a0 + DVec3::new(-theta.sin(), -theta.cos(), 0.0))
                .with_restitution(0.9)
                .tethered(a0, 1.0),
        )
        .unwrap();
    let target = world
        .add_sphere(
            SphereDesc::new(0.1)
                .at(a1 - DVec3::Y)
                .with_restitution(0.9)
                .tethered(a1, 1.0),
        )
        .unwrap();
    let v_bottom = (2.0 * 9.81 * (1.0 - theta.cos())).sqrt();
    let mut first = None;
    let mut energy = world.kinetic_energy() + world.potential_energy();
    let mut impacts = 0;
    for _ in 0..1200 {
        world.step(DT).unwrap();
        if world.stats().collisions > 0 {
            impacts += 1;
            if first.is_none() {
                first = Some((
                    world.collisions()[0],
                    world.body(striker).unwrap().velocity(),
                    world.body(target).unwrap().velocity(),
                ));
            }
        }
        let e = world.kinetic_energy() + world.potential_energy();
        assert!(
            e <= energy + 2e-3 * energy.abs(),
            "energy grew: {e} > {energy}"
        );
        energy = energy.min(e);
    }
    let (collision, vs, vt) = first.unwrap();
    assert!(!collision.resting);
    // The strings hang straight down at the bottom, square to the line of centres, so the
    // impact is a free one: impulse m(1 + e)v/2 along x (to the pendulum's error at the bottom).
    let mass = world.body(striker).unwrap().mass();
    let expected = mass * 1.9 / 2.0 * v_bottom;
    assert!(
        (collision.impulse - expected).abs() <= 1e-3 * expected,
        "impulse {} vs {expected}",
        collision.impulse
    );
    assert!(
        (collision.normal.x.abs() - 1.0).abs() <= 1e-6,
        "normal {}",
        collision.normal
    );
    // Right after the impact (within one step of swinging): v(1 ∓ e)/2 along x, to 1%.
    assert!(
        (vs.x - v_bottom * 0.05).abs() <= 0.01 * v_bottom,
        "striker {vs}"
    );
    assert!(
        (vt.x - v_bottom * 0.95).abs() <= 0.01 * v_bottom,
        "target {vt}"
    );
    assert!(
        impacts >= 10,
        "{impacts} impacts in 20 s: no early sticking"
    );
}

#[test]
fn a_string_too_short_is_a_typed_error() {
    let mut world = World::new(Settings::default());
    let err = world
        .add_sphere(
            SphereDesc::new(0.1)
                .at(DVec3::new(0.0, -2.0, 0.0))
                .tethered(DVec3::ZERO, 1.0),
        )
        .unwrap_err();
    assert_eq!(err.field, Field::Tether);
    let err = world
        .add_sphere(SphereDesc::new(0.1).tethered(DVec3::ZERO, -1.0))
        .unwrap_err();
    assert_eq!(err.field, Field::Tether);
    assert!(world.is_empty());
}

/// A slack string does nothing: a ball tossed up inside its reach flies a parabola.
#[test]
fn slack_string_leaves_a_parabola_alone() {
    let settings = Settings {
        integrator: IntegratorKind::Leapfrog,
        ..Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0))
    };
    let mut world = World::new(settings);
    let ball = world
        .add_sphere(
            SphereDesc::new(0.05)
                .at(DVec3::new(0.0, -1.0, 0.0))
                .moving(DVec3::new(0.5, 3.0, 0.0))
                .tethered(DVec3::ZERO, 5.0),
        )
        .unwrap();
    for _ in 0..30 {
        world.step(DT).unwrap();
    }
    let t = 0.5;
    let expected = DVec3::new(0.5 * t, -1.0 + 3.0 * t - 0.5 * 9.81 * t * t, 0.0);
    let p = world.body(ball).unwrap().position();
    assert!((p - expected).length() < 1e-12, "{p} vs {expected}");
}

/// Review finding: a sphere whose string will be taut by the end of the step, but is still slack
/// when it hits something, must collide as a free sphere (it used to be put on its string's
/// length first, into the sphere it hit, and lose its velocity).
#[test]
fn regression_slack_string_at_impact_is_free() {
    let mut world = World::new(Settings::default());
    let ball = world
        .add_sphere(
            SphereDesc::new(0.05)
                .at(DVec3::new(0.0, -0.92, 0.0))
                .moving(DVec3::new(0.0, -6.0, 0.0))
                .tethered(DVec3::ZERO, 1.0),
        )
        .unwrap();
    world
        .add_sphere(
            SphereDesc::new(0.05)
                .at(DVec3::new(0.0, -1.05, 0.0))
                .fixed(),
        )
        .unwrap();
    world.step(DT).unwrap();
    let body = world.body(ball).unwrap();
    assert!(
        (body.velocity() - DVec3::new(0.0, 6.0, 0.0)).length() < 1e-9,
        "bounced straight back: {}",
        body.velocity()
    );
    // The slack string bends nothing until it would catch the ball (at 0.08/6 s): the ball meets
    // the fixed sphere on its free path, at 0.03/6 s, and rises freely from there. Until the
    // forty-fifth session the whole step's drift was bent to end on the string (4.8 m/s
    // down), which met the fixed sphere at 0.03/4.8 s and ended the step 7.5 mm low.
    let free = -0.95 + 6.0 * (DT - 0.03 / 6.0);
    assert!(
        (body.position().y - free).abs() < 1e-12,
        "{}",
        body.position()
    );
    assert!(body.position().x == 0.0 && body.position().z == 0.0);
    assert_eq!(world.stats().max_overlap.max(0.0), 0.0);
}

/// Review finding: teleporting a tethered sphere beyond its string is refused.
#[test]
fn regression_set_position_beyond_the_string_is_an_error() {
    let mut world = World::new(Settings::default());
    let ball = world
        .add_sphere(
            SphereDesc::new(0.1)
                .at(DVec3::NEG_Y)
                .tethered(DVec3::ZERO, 1.0),
        )
        .unwrap();
    let err = world
        .set_position(ball, DVec3::new(0.0, -2.0, 0.0))
        .unwrap_err();
    assert!(err.to_string().contains("tether"), "{err}");
    assert_eq!(
        world.body(ball).unwrap().position(),
        DVec3::NEG_Y,
        "unchanged"
    );
}

/// A step's reported largest overlap is the overlap at the positions the step leaves its
/// bodies in, strings pulled taut included: equal to the bit to the world's own check of every
/// pair, step after step of swinging cradles whose balls overlap by a rounding error as they
/// pass the swing on (so the overlap is worked out for many steps: 220 and 34 of the 600
/// since a struck sphere is no longer put on its string's sphere deeper into the ball it
/// strikes, 482 and 479 before).
#[test]
fn the_reported_overlap_is_at_the_taut_positions() {
    for name in ["newtons_cradle", "newtons_cradle_two"] {
        let mut world = scene(name).build().unwrap();
        let mut overlapping = 0;
        for step in 0..600 {
            let reported = world.step(DT).unwrap().max_overlap;
            let actual = world.max_overlap();
            assert!(
                reported == actual,
                "{name}, step {step}: reported {reported}, actual {actual}"
            );
            overlapping += usize::from(actual > 0.0);
        }
        assert!(
            overlapping > 30,
            "{name}: {overlapping} steps with an overlap"
        );
    }
}
