//! Regression: a sphere on a string, pressed out against it by a heavier one on its anchor's
//! side, sank into it a little more at every step.
//!
//! At each step's start the pair met; solved on the string's tangent, the impact left them
//! parting (or gave no impulse, and the pair settled), but the strung sphere's drift, a chord
//! turning in towards the anchor, closed on the other for the rest of the step. The property
//! test of strings among free spheres (`properties.rs`, `PROPTEST_RNG_SEED=11`, 2000 cases)
//! drew this scene: a sphere of 0.14 kg on a string of 0.61 m under one of 3.1 kg, at
//! 106.5 steps a second; they ended each step about 0.7 mm deeper, 5.95% of the small one's
//! radius at the 60th.
//!
//! Now a pair settled on a string's tangent whose drifts still close has the string bend its
//! sphere's drift to reach the length (and be bent again, the pair looked at again) before
//! the drifts close by more than a hundredth of the smaller radius.

mod common;

use common::Strung;
use sphere_physics::Settings;
use sphere_physics::glam::DVec3;

#[test]
fn regression_a_strung_sphere_pressed_from_its_anchors_side_does_not_sink_in() {
    let still: Strung = ((0.0, 0.0, 0.0), 0.05, 0.0, 0.0, None);
    let mut spheres = vec![still; 43];
    spheres[20] = ((-1.7122447470433322, 0.0, 0.0), 0.05, 0.0, 0.0, None);
    spheres[21] = (
        (-2.510963788283943, 0.5219210908394848, 2.9947265388227304),
        0.07106729269153904,
        1.9845413829939402,
        0.05755179180403439,
        Some((0.5906955108506937, 0.019364081983432486)),
    );
    spheres[24] = (
        (0.7322002333770175, -2.817769689466589, 2.7887774233679634),
        0.4400817816428022,
        1.5332111407215965,
        0.8653206475588077,
        Some((0.5, 0.021281922394304185)),
    );
    spheres[25] = (
        (-2.760465060643313, 1.9144035024967698, 0.9820450781677335),
        0.39821193713985453,
        1.0694806652444855,
        0.4356524083929644,
        None,
    );
    spheres[26] = ((0.0, 0.0, -2.7436336081560153), 0.05, 0.0, 0.0, None);
    spheres[28] = (
        (1.932540667203915, -2.5431945002210314, 1.8214079522546618),
        0.05,
        -0.9827274713000878,
        0.0,
        None,
    );
    spheres[30] = ((2.079356152828949, 0.0, 0.0), 0.05, 0.0, 0.0, None);
    spheres[41] = ((0.0, 1.4921984253677152, 0.0), 0.05, 0.0, 0.0, None);
    spheres[42] = (
        (-0.415674794467661, 2.303914428331388, -1.9268220970275471),
        0.4371885135446685,
        1.4258347451699824,
        0.35253510528368753,
        None,
    );
    // As the property test draws it: on a lattice, under gravity, semi-implicit Euler.
    let gravity = Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0));
    let mut world = common::strung_world(&spheres, gravity);
    let dt = 1.0 / 106.52399544448814;
    let (mut deepest, mut met) = (0.0f64, 0);
    for step in 0..60 {
        let stats = world.step(dt).unwrap();
        assert_eq!(stats.collisions_deferred, 0, "step {step}");
        let bodies = world.bodies();
        let (strung, pressing) = (bodies[21].id(), bodies[25].id());
        met += world
            .collisions()
            .iter()
            .filter(|c| (c.a, c.b) == (strung, pressing))
            .count();
        for (i, a) in bodies.iter().enumerate() {
            for b in &bodies[i + 1..] {
                let overlap = a.radius() + b.radius() - (b.position() - a.position()).length();
                deepest = deepest.max(overlap / a.radius().min(b.radius()));
            }
        }
    }
    // The pair meets, again and again.
    assert!(met > 20, "{met} meetings");
    // No pair ends a step deeper than 2% of the smaller radius (5.95% before, 1.6% now).
    assert!(deepest < 0.02, "{}% of a radius deep", 100.0 * deepest);
}
