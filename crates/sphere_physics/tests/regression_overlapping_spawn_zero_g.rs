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

mod common;

const DT: f64 = 1.0 / 60.0;

#[test]
fn regression_an_overlapping_crowd_with_no_gravity_gains_no_energy() {
    for restitution in [0.0, 0.5, 1.0] {
        let mut world = common::overlapping_crowd(5, 0.3, 0.01, restitution, 7);
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
