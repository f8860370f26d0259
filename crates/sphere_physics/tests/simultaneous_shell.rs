//! A shell of spheres landing at one instant on one central sphere: one simultaneous group of
//! 40 000 impacts, all sharing the central sphere. The physics at that size: every ball bounces
//! straight back off a fixed sphere, and off a heavy dynamic one momentum and energy are kept.
//! (Such a group used to be solved in time quadratic in its size: 0.41 s for this step on a
//! fixed sphere, 0.35 s on a heavy one; 0.08 s and 0.11 s since. Timing is the benchmarks'
//! job: `cargo bench -p sphere_bench -- simultaneous`. Found by review.)

mod common;

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

/// Balls in the shell: at impact they are 0.18 apart (centre to centre), radius 0.05.
const BALLS: usize = 40_000;

/// A world with `centre` at the origin (radius 10) and a shell of small balls around it, all
/// 0.03 from its surface and moving straight at it at 3 m/s: every one lands at t = 0.01 s.
fn shell(centre: SphereDesc) -> (World, Vec<DVec3>) {
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    world.add_sphere(centre).unwrap();
    let directions = common::sphere_directions(BALLS);
    for &d in &directions {
        let ball = SphereDesc::new(0.05).at(d * 10.08).moving(-d * 3.0);
        world.add_sphere(ball).unwrap();
    }
    (world, directions)
}

#[test]
fn a_shell_landing_at_one_instant_on_a_fixed_sphere_bounces_exactly() {
    let (mut world, directions) = shell(SphereDesc::new(10.0).fixed());
    let stats = *world.step(1.0 / 60.0).unwrap();
    assert_eq!(stats.collisions as usize, BALLS);
    assert_eq!(stats.collisions_deferred, 0);
    for (body, d) in world.bodies().iter().skip(1).zip(directions) {
        // Elastic, head-on, on an immovable sphere: straight back out at the same speed.
        assert!((body.velocity() - d * 3.0).length() < 1e-12);
    }
}

#[test]
fn a_shell_landing_at_one_instant_on_a_heavy_ball_keeps_momentum_and_energy() {
    let (mut world, _) = shell(SphereDesc::new(10.0).with_density(1e3));
    let (momentum, energy) = (world.momentum(), world.kinetic_energy());
    let stats = *world.step(1.0 / 60.0).unwrap();
    assert_eq!(stats.collisions as usize, BALLS);
    assert_eq!(stats.collisions_deferred, 0);
    assert!((world.momentum() - momentum).length() < 1e-12 * energy.sqrt());
    let after = world.kinetic_energy();
    assert!(
        (after - energy).abs() < 1e-9 * energy,
        "{after} vs {energy}"
    );
    // The ball's mass is 3e6 times each small ball's, and the shell is symmetric: it barely moves,
    // and each small ball comes back out at almost its speed.
    for body in world.bodies().iter().skip(1) {
        assert!((body.velocity().length() - 3.0).abs() < 1e-6);
    }
}
