//! Regression: a group of more than 64 contacts at one instant (solved by sweeps rather than
//! exactly) could gain or lose much of its energy, elastic or not. The sweeps' acceleration
//! could carry the impulses away from the answer, and the 256 sweeps ended wherever they
//! were: 80 balls striking a ball of their own mass at one instant from a ring around it
//! left with 8.6 times the energy they brought, 100 from a sphere around it with 2.2 times.
//! Found by review (sixty-fourth session).

mod common;

use common::sphere_directions;
use sphere_physics::{GroupContact, SphereDesc, World, glam::DVec3, resolve_simultaneous};

/// `n` unit directions evenly around a circle in the xy plane.
fn ring_directions(n: usize) -> Vec<DVec3> {
    (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            DVec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect()
}

/// Balls of inverse mass `ball` moving at 1 m/s straight at a centre of inverse mass 1 at
/// rest, one contact each, all of restitution `e`, everything moving at `frame` besides: the
/// velocities after the group's solve, and the contacts' impulses.
fn strike_in(
    directions: &[DVec3],
    ball: f64,
    e: f64,
    frame: DVec3,
) -> (Vec<DVec3>, Vec<f64>, Vec<f64>) {
    let mut inverse_masses = vec![1.0];
    let mut velocities = vec![frame];
    let mut contacts = Vec::new();
    for (i, &d) in directions.iter().enumerate() {
        inverse_masses.push(ball);
        velocities.push(frame - d);
        contacts.push(GroupContact::new(0, i + 1, d, e));
    }
    let mut impulses = Vec::new();
    resolve_simultaneous(&inverse_masses, &mut velocities, &contacts, &mut impulses);
    (velocities, inverse_masses, impulses)
}

fn strike(directions: &[DVec3], ball: f64, e: f64) -> (Vec<DVec3>, Vec<f64>, Vec<f64>) {
    strike_in(directions, ball, e, DVec3::ZERO)
}

fn kinetic_energy(velocities: &[DVec3], inverse_masses: &[f64]) -> f64 {
    velocities
        .iter()
        .zip(inverse_masses)
        .filter(|(_, w)| **w > 0.0)
        .map(|(v, &w)| 0.5 * v.length_squared() / w)
        .sum()
}

#[test]
fn regression_a_group_of_more_than_64_elastic_contacts_keeps_its_energy() {
    for (name, directions, ball) in [
        ("100 on a sphere", sphere_directions(100), 1.0),
        ("150 heavy on a sphere", sphere_directions(150), 0.1),
        ("80 in a ring", ring_directions(80), 1.0),
        ("65 in a ring", ring_directions(65), 1.0),
    ] {
        let n = directions.len();
        let before = 0.5 * n as f64 / ball;
        let (velocities, inverse_masses, _) = strike(&directions, ball, 1.0);
        let after = kinetic_energy(&velocities, &inverse_masses);
        assert!(
            (after - before).abs() <= 1e-9 * before,
            "{name}: kinetic energy {before} became {after}"
        );
        let momentum: DVec3 = velocities
            .iter()
            .zip(&inverse_masses)
            .map(|(v, &w)| *v / w)
            .sum();
        let brought: DVec3 = directions.iter().map(|&d| -d / ball).sum();
        assert!(
            (momentum - brought).length() <= 1e-9 * before.sqrt(),
            "{name}: momentum {brought} became {momentum}"
        );
        // Nothing is left closing.
        for (i, d) in directions.iter().enumerate() {
            let closing = (velocities[i + 1] - velocities[0]).dot(*d);
            assert!(
                closing >= -1e-9,
                "{name}: contact {i} still closes at {closing}"
            );
        }
    }
}

#[test]
fn regression_a_group_of_more_than_64_contacts_gains_no_energy_whatever_its_restitution() {
    for e in [0.0, 0.25, 0.5, 0.9] {
        for (name, directions) in [
            ("100 on a sphere", sphere_directions(100)),
            ("80 in a ring", ring_directions(80)),
        ] {
            let before = 0.5 * directions.len() as f64;
            let (velocities, inverse_masses, _) = strike(&directions, 1.0, e);
            let after = kinetic_energy(&velocities, &inverse_masses);
            assert!(
                after <= before * (1.0 + 1e-12),
                "{name}, restitution {e}: kinetic energy {before} became {after}"
            );
            for (i, d) in directions.iter().enumerate() {
                let closing = (velocities[i + 1] - velocities[0]).dot(*d);
                assert!(
                    closing >= -1e-9,
                    "{name}, e {e}: contact {i} closes at {closing}"
                );
            }
        }
    }
}

#[test]
fn regression_a_ring_of_80_balls_striking_a_ball_at_one_instant_bounces_back_elastically() {
    // A ball of radius 2.5 at rest, and 80 balls of radius 0.1 and the same mass around it
    // in a ring, 0.01 m from it, moving straight at it at 1 m/s: all 80 strike at one
    // instant. By symmetry the centre stays at rest and each ball bounces straight back at
    // 1 m/s.
    let mut world = World::new(Default::default());
    world.add_sphere(SphereDesc::new(2.5)).unwrap();
    let directions = ring_directions(80);
    for &d in &directions {
        let ball = SphereDesc::new(0.1)
            .with_density(15_625.0)
            .at(d * 2.61)
            .moving(-d);
        world.add_sphere(ball).unwrap();
    }
    let energy = world.kinetic_energy();
    world.step(1.0 / 60.0).unwrap();
    let after = world.kinetic_energy();
    assert!(
        (after - energy).abs() <= 1e-9 * energy,
        "kinetic energy {energy} became {after}"
    );
    assert!(world.momentum().length() <= 1e-9 * energy.sqrt());
    for (body, d) in world.bodies().iter().skip(1).zip(&directions) {
        assert!(
            (body.velocity() - *d).length() < 1e-6,
            "a ball left at {} instead of {d}",
            body.velocity()
        );
    }
    assert!(world.bodies()[0].velocity().length() < 1e-6);
}

/// A generator of numbers in [0, 1) for the clusters below (SplitMix64).
struct Numbers(u64);

impl Numbers {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn regression_large_clusters_of_mixed_masses_gain_no_energy_and_keep_momentum() {
    // Cubes of 4³ or 5³ bodies, each touching its lattice neighbours along the axes and the
    // faces' diagonals (252 to 540 contacts, less those between two fixed bodies), masses
    // spread over four decades, a few bodies fixed, random velocities: groups the sweeps may
    // leave short of the answer.
    let mut numbers = Numbers(7);
    for trial in 0..30 {
        let side = if numbers.next() < 0.5 { 4 } else { 5 };
        let index = |i: usize, j: usize, k: usize| (i * side + j) * side + k;
        let bodies = side * side * side;
        let mut inverse_masses: Vec<f64> = (0..bodies)
            .map(|_| {
                if numbers.next() < 0.5 {
                    10f64.powf(4.0 * numbers.next() - 2.0)
                } else {
                    1.0
                }
            })
            .collect();
        for _ in 0..(4.0 * numbers.next()) as usize {
            inverse_masses[(numbers.next() * bodies as f64) as usize] = 0.0;
        }
        let velocities: Vec<DVec3> = inverse_masses
            .iter()
            .map(|&w| {
                let v = DVec3::new(numbers.next(), numbers.next(), numbers.next());
                if w > 0.0 {
                    2.0 * v - DVec3::ONE
                } else {
                    DVec3::ZERO
                }
            })
            .collect();
        let e = if trial % 3 == 0 { 1.0 } else { numbers.next() };
        let mut contacts = Vec::new();
        for i in 0..side {
            for j in 0..side {
                for k in 0..side {
                    for d in [
                        [1, 0, 0],
                        [0, 1, 0],
                        [0, 0, 1],
                        [1, 1, 0],
                        [1, 0, 1],
                        [0, 1, 1],
                    ] {
                        let (x, y, z) = (i + d[0], j + d[1], k + d[2]);
                        let (a, b) = (index(i, j, k), index(x, y, z));
                        if x < side
                            && y < side
                            && z < side
                            && inverse_masses[a] + inverse_masses[b] > 0.0
                        {
                            let normal =
                                DVec3::new(d[0] as f64, d[1] as f64, d[2] as f64).normalize();
                            contacts.push(GroupContact::new(a, b, normal, e));
                        }
                    }
                }
            }
        }
        let momentum = |v: &[DVec3]| -> DVec3 {
            v.iter()
                .zip(&inverse_masses)
                .filter(|(_, w)| **w > 0.0)
                .map(|(v, &w)| *v / w)
                .sum()
        };
        let fixed_free = |v: &[DVec3]| -> DVec3 {
            // Momentum is kept only up to what the fixed bodies take: compared along no axis
            // when any is fixed.
            if inverse_masses.contains(&0.0) {
                DVec3::ZERO
            } else {
                momentum(v)
            }
        };
        let before = kinetic_energy(&velocities, &inverse_masses);
        let brought = fixed_free(&velocities);
        let mut after = velocities.clone();
        let mut impulses = Vec::new();
        resolve_simultaneous(&inverse_masses, &mut after, &contacts, &mut impulses);
        let energy = kinetic_energy(&after, &inverse_masses);
        assert!(
            energy <= before * (1.0 + 1e-12),
            "trial {trial} ({} contacts, restitution {e}): kinetic energy {before} became {energy}",
            contacts.len()
        );
        assert!(
            (fixed_free(&after) - brought).length() <= 1e-9 * (1.0 + brought.length()),
            "trial {trial}: momentum {brought} became {}",
            fixed_free(&after)
        );
        assert!(impulses.iter().all(|&l| l >= 0.0 && l.is_finite()));
    }
}

#[test]
fn regression_a_moving_group_of_more_than_64_elastic_contacts_keeps_its_energy() {
    // The same strikes, the whole group moving besides (a cluster that has fallen for a
    // second, say): rounding in speeds of 10 to 1000 m/s kept the solves from meeting a bound
    // set by the 1 m/s strike alone, and the 150 heavy balls lost 13% of their energy in the
    // group's frame (found by review of this fix).
    for (name, directions, ball) in [
        ("100 on a sphere", sphere_directions(100), 1.0),
        ("150 heavy on a sphere", sphere_directions(150), 0.1),
        ("80 in a ring", ring_directions(80), 1.0),
    ] {
        for frame in [
            DVec3::new(0.0, 0.0, 10.0),
            DVec3::new(30.0, 0.0, 0.0),
            DVec3::new(100.0, 0.0, 0.0),
            DVec3::new(1000.0, 300.0, 0.0),
        ] {
            let before = 0.5 * directions.len() as f64 / ball;
            let (velocities, inverse_masses, _) = strike_in(&directions, ball, 1.0, frame);
            let moved: Vec<DVec3> = velocities.iter().map(|v| *v - frame).collect();
            let after = kinetic_energy(&moved, &inverse_masses);
            assert!(
                (after - before).abs() <= 1e-9 * before,
                "{name} moving at {frame}: kinetic energy {before} became {after} in its frame"
            );
        }
    }
}
