//! Regression: a ball striking a row of touching spheres with restitution below 1 sets off an
//! inelastic collapse at the instant of the strike: each sphere behind catches up with the one
//! ahead again and again, each bounce smaller, without end in the exact model. The event loop
//! took every bounce until the step's collision budget ran out and the fallback solve ended
//! them: a row of 10 at restitution 0.5 took 186 impacts in one step (4 deferred), a row of 40
//! spent the budget in each of two steps (696 impacts each). Found in the fifty-eighth
//! session, mended in the fifty-ninth: an impact on a sphere that has bounced
//! `COLLAPSE_BOUNCES` times at its instant, approaching at under `COLLAPSE_SPEED` of the
//! instant's fastest bounce, is squeezed, solved at once with restitution 0 together with the
//! contacts along its line that are as slow, which is where the bounces lead. A sequence that
//! ends by itself (a row of 40 at restitution 0.9) keeps the energy its bounces leave, and an
//! elastic row is left to its bounces (one ball in, one ball out).

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, SphereDesc, World};

const RADIUS: f64 = 0.1;
const SPEED: f64 = 3.0;
const DT: f64 = 1.0 / 60.0;

/// A row of `n` touching spheres along x, no gravity, and a ball 5 cm short of its first,
/// moving into it at [`SPEED`], the world's last body; all of restitution `e`.
fn struck_row(n: usize, e: f64) -> World {
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    for i in 0..n {
        let at = DVec3::X * (2.0 * RADIUS * i as f64);
        world
            .add_sphere(SphereDesc::new(RADIUS).at(at).with_restitution(e))
            .unwrap();
    }
    let ball = SphereDesc::new(RADIUS)
        .at(DVec3::X * -(2.0 * RADIUS + 0.05))
        .moving(DVec3::X * SPEED)
        .with_restitution(e);
    world.add_sphere(ball).unwrap();
    world
}

/// Steps the struck row once, checks the laws, and returns the step's collisions and the
/// share of the energy kept.
fn strike(n: usize, e: f64) -> (u32, f64, World) {
    let mut world = struck_row(n, e);
    let (momentum, energy) = (world.momentum(), world.kinetic_energy());
    let stats = *world.step(DT).unwrap();
    let label = format!("a row of {n} at restitution {e}");
    assert!(!stats.fell_back, "{label}: the budget ran out: {stats:?}");
    assert_eq!(stats.collisions_deferred, 0, "{label}: {stats:?}");
    assert!(
        (world.momentum() - momentum).length() <= 1e-12 * momentum.length(),
        "{label}: momentum {} against {}",
        world.momentum(),
        momentum
    );
    assert!(world.kinetic_energy() <= energy, "{label}: energy gained");
    assert!(stats.max_overlap <= 1e-9, "{label}: {stats:?}");
    (stats.collisions, world.kinetic_energy() / energy, world)
}

/// Every sphere of `world` moves on with the row's centre of mass, as a collapse's bounces
/// would in the limit.
fn assert_together(world: &World, n: usize) {
    let together = SPEED / (n + 1) as f64;
    for body in world.bodies() {
        let v = body.velocity();
        assert!(
            (v - DVec3::X * together).length() <= 1e-3 * together,
            "a sphere at {v}, the row at {together}"
        );
    }
}

#[test]
fn regression_a_struck_row_of_ten_collapses_within_the_step() {
    let (collisions, _, world) = strike(10, 0.5);
    assert!(collisions <= 120, "{collisions} collisions (186 before)");
    assert_together(&world, 10);
}

#[test]
fn regression_a_struck_row_of_forty_collapses_within_its_budget() {
    // 41 bodies: a budget of 656 collisions, spent in each of two steps before.
    let (collisions, _, world) = strike(40, 0.5);
    assert!(collisions <= 250, "{collisions} collisions");
    assert_together(&world, 40);
}

/// At restitution 0.9 a struck row of 40 is no collapse: its bounces at the instant end by
/// themselves, after about 1100 (past the budget of 656, so the fallback ended them before),
/// with 3.55% of the energy left and the spheres at different speeds. Squeezed as a collapse
/// after 16 bounces a sphere (the first form of the mend), the row moved on as one, with
/// 2.44%. The squeeze takes only the slow end of such a sequence.
#[test]
fn a_struck_row_whose_bounces_end_keeps_their_energy() {
    let (collisions, kept, _) = strike(40, 0.9);
    assert!(collisions <= 656, "{collisions} collisions");
    assert!(
        (0.0345..0.0365).contains(&kept),
        "{:.2}% of the energy",
        100.0 * kept
    );
    // Shorter rows, whose bounces end well within the budget, as before: 55 impacts and 37.47%
    // for 10 (its 16th counted bounce is never reached), 14.93% for 20 (14.91% now: its slow
    // end squeezed; 4.8% were it squeezed whole, as the first form did).
    let (_, kept, _) = strike(10, 0.9);
    assert!(
        (0.374..0.375).contains(&kept),
        "{:.3}% of the energy",
        100.0 * kept
    );
    let (_, kept, _) = strike(20, 0.9);
    assert!(
        (0.1485..0.1500).contains(&kept),
        "{:.3}% of the energy",
        100.0 * kept
    );
}

/// A row struck in a lattice of 40 × 40 touching marbles, no gravity: the collapse runs along
/// the row, and its squeeze takes the row alone (contacts across the line of the impacts join
/// no collapse's squeeze). Before: 25 656 impacts, the budget spent and 4 deferred.
#[test]
fn regression_a_row_struck_in_a_lattice_collapses_within_the_budget() {
    let n = 40;
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    let mut row = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let at = DVec3::new(2.0 * RADIUS * i as f64, 0.0, 2.0 * RADIUS * j as f64);
            let id = world
                .add_sphere(SphereDesc::new(RADIUS).at(at).with_restitution(0.5))
                .unwrap();
            if j == n / 2 {
                row.push(id);
            }
        }
    }
    let ball = SphereDesc::new(RADIUS)
        .at(DVec3::new(
            -(2.0 * RADIUS + 0.05),
            0.0,
            2.0 * RADIUS * (n / 2) as f64,
        ))
        .moving(DVec3::X * SPEED)
        .with_restitution(0.5);
    row.push(world.add_sphere(ball).unwrap());
    let (momentum, energy) = (world.momentum(), world.kinetic_energy());
    let stats = *world.step(DT).unwrap();
    assert!(!stats.fell_back, "{stats:?}");
    assert!(world.kinetic_energy() <= energy, "energy gained");
    assert!(stats.max_overlap <= 1e-9, "{stats:?}");
    assert_eq!(stats.collisions_deferred, 0, "{stats:?}");
    assert!(stats.collisions <= 400, "{stats:?}");
    assert!((world.momentum() - momentum).length() <= 1e-12 * momentum.length());
    let together = SPEED / row.len() as f64;
    for body in world.bodies() {
        let v = body.velocity();
        if row.contains(&body.id()) {
            assert!((v - DVec3::X * together).length() <= 1e-3 * together, "{v}");
        } else {
            assert!(v.length() <= 1e-12, "a marble beside the row at {v}");
        }
    }
}

/// A guard for the cradle: an elastic struck row is no collapse. One ball in, one ball out,
/// one impact a ball, and nothing squeezed (a squeeze would take the row's energy). Each sphere
/// bounces once, far below the count, so this does not tell whether elastic bounces are
/// counted.
#[test]
fn an_elastic_struck_row_sends_one_ball_out() {
    let n = 40;
    let mut world = struck_row(n, 1.0);
    let stats = *world.step(DT).unwrap();
    assert_eq!(stats.collisions, n as u32, "{stats:?}");
    let bodies = world.bodies();
    let (last, ball) = (&bodies[n - 1], &bodies[n]);
    assert_eq!(ball.velocity(), DVec3::ZERO);
    assert_eq!(last.velocity(), DVec3::X * SPEED);
    for body in &bodies[..n - 1] {
        assert_eq!(body.velocity(), DVec3::ZERO);
    }
}
