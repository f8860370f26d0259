//! Timing a step's phases (`World::set_profiling`) reports them and changes nothing else.

use std::time::Duration;

use sphere_physics::{SceneDesc, World};

/// 2 000 spheres of a gas in a box of six fixed walls: collisions in every step.
fn gas() -> World {
    SceneDesc::from_ron(
        "(name: \"gas\", gravity: (0.0, -1.0, 0.0), restitution: 0.9,
          generate: [Gas(count: 2000, seed: 7, min: (-1.5, -1.5, -1.5), max: (1.5, 1.5, 1.5),
                         radius: 0.05, speed: 2.0)])",
    )
    .unwrap()
    .build()
    .unwrap()
}

#[test]
fn profiling_reports_every_step_and_changes_nothing() {
    let (mut plain, mut timed) = (gas(), gas());
    assert!(plain.profile().is_none(), "off by default");
    timed.set_profiling(true);
    let mut collisions = 0;
    for step in 0..30 {
        let a = *plain.step(1.0 / 60.0).unwrap();
        let b = *timed.step(1.0 / 60.0).unwrap();
        assert_eq!(a, b, "step {step}");
        assert_eq!(plain.collisions(), timed.collisions(), "step {step}");
        collisions += a.collisions;
        let profile = *timed.profile().expect("profiling is on");
        // Each step times its own phases: those that always run took some time.
        for (phase, time) in [
            ("integrate", profile.integrate),
            ("sort", profile.sort),
            ("first pass", profile.first_pass),
            ("write-back", profile.write_back),
        ] {
            assert!(time > Duration::ZERO, "step {step}: {phase} not timed");
        }
        if a.collisions > a.resting_contacts {
            assert!(
                profile.events > Duration::ZERO,
                "step {step}: events not timed"
            );
        }
        assert!(profile.total() >= profile.events + profile.first_pass);
    }
    assert!(collisions > 100, "the gas collides ({collisions})");
    let bits = |w: &World| {
        w.bodies()
            .iter()
            .flat_map(|b| [b.position().to_array(), b.velocity().to_array()])
            .flatten()
            .map(f64::to_bits)
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&plain), bits(&timed));
    timed.set_profiling(false);
    timed.step(1.0 / 60.0).unwrap();
    assert!(timed.profile().is_none());
}
