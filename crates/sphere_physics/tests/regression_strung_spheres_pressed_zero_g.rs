//! Two spheres on taut strings, no gravity, struck together and then swinging along together,
//! one pressing the other. Each step's impact stops their closing at its start, but their
//! drifts are chords of their swings, which curve into each other: each step closed them by
//! about 3 mm more. The separation that moves overlapping spheres apart when nothing
//! accelerates left spheres on strings where they were, so the overlap grew step after step,
//! to 2.1 cm (7% of the smaller radius). Found by `strings_among_free_spheres_leave_no_overlap`
//! (tests/properties.rs) with `PROPTEST_RNG_SEED=48` and 2 000 cases: this is its scene.
mod common;

use sphere_physics::{IntegratorKind, Settings, glam::DVec3};

#[test]
fn strung_spheres_pressed_together_without_gravity_do_not_sink_into_each_other() {
    let still = ((0.0, 0.0, 0.0), 0.05, 0.0, 0.0, None);
    let mut spheres: Vec<common::Strung> = vec![still; 30];
    spheres[4] = (
        (-2.201_961_976_217_547_5, 0.0, 2.350_961_972_961_509),
        0.292_698_039_897_540_5,
        0.0,
        0.951_592_608_193_593_3,
        Some((1.149_069_160_625_736, 0.0)),
    );
    spheres[8] = (
        (-2.337_604_615_789_617_3, 1.476_348_954_156_710_5, 0.0),
        0.398_325_683_077_329_24,
        -0.387_142_832_414_041_24,
        0.0,
        None,
    );
    spheres[21] = (
        (
            -1.119_547_971_458_465_3,
            0.265_817_868_994_085_6,
            -0.636_081_463_759_907_8,
        ),
        0.05,
        0.0,
        0.0,
        None,
    );
    spheres[24] = (
        (
            1.724_930_517_404_091_2,
            2.133_872_595_225_55,
            -2.633_348_473_780_247_7,
        ),
        0.396_800_888_439_694_13,
        -0.763_298_747_465_863_3,
        0.059_557_465_058_379_46,
        Some((0.957_687_011_474_043_4, 0.0)),
    );
    spheres[28] = ((0.0, 0.0, 2.119_256_232_075_301_2), 0.05, 0.0, 0.0, None);
    spheres[29] = (
        (
            -1.964_120_680_963_523_4,
            -2.897_396_997_059_743_3,
            -2.836_433_103_813_879_7,
        ),
        0.118_882_385_958_575_06,
        2.559_834_416_910_263,
        0.471_910_284_661_135_66,
        None,
    );
    let settings = Settings {
        integrator: IntegratorKind::SemiImplicitEuler,
        ..Settings::with_gravity(DVec3::ZERO)
    };
    let mut world = common::strung_world(&spheres, settings);
    let energy = world.kinetic_energy();
    let (mut deepest, mut touching) = (0.0f64, 0);
    for _ in 0..60 {
        let stats = *world.step(1.0 / 30.0).unwrap();
        assert_eq!(stats.collisions_deferred, 0);
        let b = world.bodies();
        let overlap =
            b[4].radius() + b[24].radius() - (b[24].position() - b[4].position()).length();
        deepest = deepest.max(stats.max_overlap);
        touching += u32::from(overlap > -1e-3);
        for b in [&b[4], &b[24]] {
            let t = b.tether().unwrap();
            assert!((b.position() - t.anchor).length() <= t.length * (1.0 + 1e-9));
        }
        // Moving spheres apart changes no velocity: no energy is gained.
        assert!(world.kinetic_energy() <= energy * (1.0 + 1e-12));
    }
    // The two are in touch for several steps (the scene tests what it says).
    assert!(touching >= 5, "in touch in {touching} steps");
    // Within the pairs' contact band (before: 2.1 cm).
    assert!(deepest <= 1e-6, "{deepest} deep");
}
