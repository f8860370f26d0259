//! Regression: a ball striking a row of touching spheres with restitution below 1 sets off an
//! inelastic collapse at the instant of the strike: each sphere behind catches up with the one
//! ahead again and again, each bounce smaller, without end in the exact model. The event loop
//! took every bounce until the step's collision budget ran out and the fallback solve ended
//! them: a row of 10 at restitution 0.5 took 186 impacts in one step (4 deferred), a row of 40
//! spent the budget in three steps running (696 impacts each). Found in the fifty-eighth
//! session, mended in the fifty-ninth: a body's bounces at one instant past
//! `COLLAPSE_BOUNCES` are squeezed, solved at once with every contact touching them with
//! restitution 0, which is where the bounces lead (every sphere moving on together). Elastic
//! rows are left to their bounces (one ball in, one ball out).

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

/// Steps the struck row once, checks the laws and what the collapse leads to, and returns
/// the step's collisions.
fn strike(n: usize, e: f64) -> u32 {
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
    // Every sphere moves on with the row's centre of mass, as the bounces would in the limit.
    let together = SPEED / (n + 1) as f64;
    for body in world.bodies() {
        let v = body.velocity();
        assert!(
            (v - DVec3::X * together).length() <= 1e-3 * together,
            "{label}: a sphere at {v}, the row at {together}"
        );
    }
    assert!(stats.max_overlap <= 1e-9, "{label}: {stats:?}");
    stats.collisions
}

#[test]
fn regression_a_struck_row_of_ten_collapses_within_the_step() {
    let collisions = strike(10, 0.5);
    assert!(collisions <= 120, "{collisions} collisions (186 before)");
}

#[test]
fn regression_a_struck_row_of_forty_collapses_within_its_budget() {
    // 41 bodies: a budget of 656 collisions, all spent, step after step, before.
    for e in [0.5, 0.9] {
        let collisions = strike(40, e);
        assert!(
            collisions <= 250,
            "restitution {e}: {collisions} collisions"
        );
    }
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
    let momentum = world.momentum();
    let stats = *world.step(DT).unwrap();
    assert!(!stats.fell_back, "{stats:?}");
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

/// An elastic row is no collapse: one ball in, one ball out, one impact a ball, and nothing
/// squeezed (a squeeze would take the row's energy).
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
