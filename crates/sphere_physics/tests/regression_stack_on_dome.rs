//! Regression: a column of balls falling together onto the top of a fixed dome sank into it
//! for ever (found by `properties::rain_on_a_big_fixed_sphere`).
//!
//! At the start of a step every ball of the column had the same velocity, so only the bottom
//! contact was approaching and only it went to the resting solve; the others were chased one
//! contact at a time, and a leftover approach just under the creep speed was let through every
//! step. The column sank by about `creep · dt` a step, without bound (1.3 cm in 60 steps).
//! Now touching pairs separating no faster than the resting speed join the resting solve, and an
//! overlap deeper than half the creep distance is undone by a separating speed.

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

const G: f64 = 9.81;
const DT: f64 = 0.0443324348313259;

/// A fixed dome of radius 3 with its top at y = -0.6, and `n` balls of radius 0.1 stacked
/// above its top, 1 apart, at rest.
fn column(n: usize) -> (World, Vec<sphere_physics::BodyId>) {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -G, 0.0)));
    world
        .add_sphere(SphereDesc::new(3.0).at(DVec3::new(2.0, -3.6, 1.0)).fixed())
        .unwrap();
    let balls = (0..n)
        .map(|k| {
            world
                .add_sphere(
                    SphereDesc::new(0.1)
                        .at(DVec3::new(2.0, k as f64, 1.0))
                        .with_density(0.5)
                        .with_restitution(0.0),
                )
                .unwrap()
        })
        .collect();
    (world, balls)
}

#[test]
fn a_column_on_a_dome_stays_up() {
    let (mut world, balls) = column(5);
    let settings = world.settings().clone();
    let creep = settings.creep_fraction * settings.resting_factor * G * DT * DT;
    let mut worst: f64 = 0.0;
    for _ in 0..300 {
        let stats = *world.step(DT).unwrap();
        worst = worst.max(stats.max_overlap);
    }
    assert!(
        worst <= 2.0 * creep,
        "overlap {worst:e} > 2 · creep {creep:e}"
    );
    // Resting on the dome's top (y = -0.6): centres at -0.5, -0.3, ... within the allowance.
    for (k, &id) in balls.iter().enumerate() {
        let y = world.body(id).unwrap().position().y;
        let ideal = -0.5 + 0.2 * k as f64;
        assert!(
            (y - ideal).abs() <= 2.0 * creep * (k + 1) as f64,
            "ball {k} at y = {y}, resting height {ideal}"
        );
        assert!(world.body(id).unwrap().velocity().length() < G * DT * 0.02);
    }
}
