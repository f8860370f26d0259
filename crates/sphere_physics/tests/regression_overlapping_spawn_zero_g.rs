//! Regression (found 2026-12-03 by `sphere-fuzz --overlapping`, 37 of 2000 random scenes with
//! no gravity): spheres placed overlapping with nothing outside acting gained energy, up to a
//! million times what they had. An overlapping crowd spends the step's collision budget at
//! once, and the fallback solve that takes over undoes each deep overlap by a push; between
//! two dynamic spheres that push stayed in their velocities, so every overlap became a speed
//! (125 spheres of radius 0.5, 0.3 m apart, at about 1 cm/s: from 3 mJ to 1.8 kJ in one step).
//! Now the fallback's deep pushes between dynamic spheres are solved as those against fixed
//! ones are: after the contacts, within each body's push budget, and taken off at the step's
//! end, so they move the spheres without leaving them a speed. The same search found a second
//! source, in impacts solved together: see `regression_mixed_restitution_group.rs`.

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, SphereDesc, World};

const DT: f64 = 1.0 / 60.0;

/// A cube of `side`³ spheres of radius 0.5 whose centres are `spacing` apart (under a
/// diameter: each overlaps its neighbours), moving at up to `speed` in random directions
/// (a fixed sequence), with `restitution`, and no gravity.
fn crowd(side: usize, spacing: f64, speed: f64, restitution: f64) -> World {
    let mut world = World::new(Settings::default());
    let mut state = 7u64;
    let mut unit = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for i in 0..side {
        for j in 0..side {
            for k in 0..side {
                let at = DVec3::new(i as f64, j as f64, k as f64) * spacing;
                let velocity = DVec3::new(unit(), unit(), unit()) * speed;
                world
                    .add_sphere(
                        SphereDesc::new(0.5)
                            .at(at)
                            .moving(velocity)
                            .with_restitution(restitution),
                    )
                    .unwrap();
            }
        }
    }
    world
}

#[test]
fn regression_an_overlapping_crowd_with_no_gravity_gains_no_energy() {
    for restitution in [0.0, 0.5, 1.0] {
        let mut world = crowd(5, 0.3, 0.01, restitution);
        let momentum = world.momentum();
        let mut energy = world.kinetic_energy();
        let mut fell_back = 0;
        for step in 0..120 {
            let stats = *world.step(DT).unwrap();
            fell_back += u32::from(stats.fell_back);
            let now = world.kinetic_energy();
            // Before: 3.1e-3 J to 1.8e3 J in the step that fell back (restitution 0.5).
            assert!(
                now <= energy * (1.0 + 1e-9) + 1e-15,
                "restitution {restitution}, step {step}: kinetic energy {energy} -> {now}"
            );
            assert!(
                (world.momentum() - momentum).length() <= 1e-12,
                "restitution {restitution}, step {step}: momentum moved"
            );
            assert!(
                world
                    .bodies()
                    .iter()
                    .all(|b| b.position().is_finite() && b.velocity().is_finite())
            );
            energy = now;
        }
        assert!(
            fell_back > 0,
            "restitution {restitution}: the budget ran out (the fallback was used)"
        );
    }
}
