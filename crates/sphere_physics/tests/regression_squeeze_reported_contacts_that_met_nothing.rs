//! Regression: a squeeze (see `Solver::squeeze`: the end of an inelastic collapse at one
//! instant, or of a light sphere bouncing between heavier ones closing on it) solves the
//! touching contacts around its impacts together, restitution 0, and reported each of them as
//! a collision, those that took no impulse too: contacts parting, or closing too slowly to
//! need one, which met nothing. A rack of 55 balls struck at 8 m/s, restitution 0.9, reported
//! 307 collisions in the step of the strike, 68 of them with no impulse; a rack of 210, 966 of
//! 3442. Found and mended in the sixtieth session: a squeeze's contact that takes no impulse is
//! not reported (the motion is the same, bit for bit: only the reports and their counts
//! changed).

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, SphereDesc, World};

const RADIUS: f64 = 0.1;
const DT: f64 = 1.0 / 60.0;

/// A triangle of touching balls, `rows` rows deep, no gravity, restitution `e`, and a cue ball
/// 5 cm short of its apex moving into it at 8 m/s.
fn struck_rack(rows: usize, e: f64) -> World {
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    for k in 0..rows {
        for j in 0..=k {
            let at = DVec3::new(
                k as f64 * 3f64.sqrt() * RADIUS,
                0.0,
                (j as f64 - k as f64 / 2.0) * 2.0 * RADIUS,
            );
            world
                .add_sphere(SphereDesc::new(RADIUS).at(at).with_restitution(e))
                .unwrap();
        }
    }
    let cue = SphereDesc::new(RADIUS)
        .at(DVec3::X * -(2.0 * RADIUS + 0.05))
        .moving(DVec3::X * 8.0)
        .with_restitution(e);
    world.add_sphere(cue).unwrap();
    world
}

#[test]
fn regression_a_struck_racks_collisions_all_carry_an_impulse() {
    let mut world = struck_rack(10, 0.9);
    let (momentum, energy) = (world.momentum(), world.kinetic_energy());
    let stats = *world.step(DT).unwrap();
    let collisions = world.collisions();
    assert_eq!(stats.collisions as usize, collisions.len());
    // The collapse's squeezes ran (the rack takes 237 collisions, 307 reported before).
    assert!(stats.collisions > 200, "{stats:?}");
    // (A group of simultaneous impacts may still report one its others stopped, with no
    // impulse: this rack's have none.)
    let empty = collisions.iter().filter(|c| c.impulse <= 0.0).count();
    assert_eq!(
        empty,
        0,
        "{empty} of {} collisions took no impulse",
        collisions.len()
    );
    assert_eq!(stats.collisions_deferred, 0, "{stats:?}");
    assert!(stats.max_overlap <= 1e-9, "{stats:?}");
    assert!((world.momentum() - momentum).length() <= 1e-12 * momentum.length());
    // Where its bounces lead: 39.0% of the energy kept, as before the change.
    let kept = world.kinetic_energy() / energy;
    assert!((0.3900..0.3910).contains(&kept), "{kept}");
}
