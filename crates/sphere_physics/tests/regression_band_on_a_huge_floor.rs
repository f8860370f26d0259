//! Regression: a small ball near a huge fixed sphere (a floor of radius 1e4, as the gas
//! generator's walls are) counted as touching it anywhere within a millionth of the sum of
//! their radii: a centimetre, a fifth of the ball's radius. A ball let go a few millimetres
//! above such a floor was stopped there by the resting solve, and hovered. Now the band is a
//! millionth of the smaller diameter, plus the contact tolerance (`ε · (1 + reach)`, 1e-5 m
//! for the floor of radius 1e4 at the default ε of 1e-9: within the creep distance).

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, SphereDesc, World};

const G: f64 = 9.81;
const DT: f64 = 1.0 / 60.0;
const RADIUS: f64 = 0.05;

/// A ball of radius 0.05 let go `gap` above the top of a fixed sphere of radius `floor`.
fn ball_above(floor: f64, gap: f64) -> (World, sphere_physics::BodyId) {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -G, 0.0)));
    world
        .add_sphere(
            SphereDesc::new(floor)
                .at(DVec3::new(0.0, -floor, 0.0))
                .fixed(),
        )
        .unwrap();
    let ball = world
        .add_sphere(
            SphereDesc::new(RADIUS)
                .at(DVec3::new(0.0, RADIUS + gap, 0.0))
                .with_restitution(0.5),
        )
        .unwrap();
    (world, ball)
}

#[test]
fn a_ball_let_go_just_above_a_huge_floor_lands_on_it() {
    let settings = Settings::default();
    let creep = settings.creep_fraction * settings.resting_factor * G * DT * DT;
    for floor in [1.0, 1.0e2, 1.0e4] {
        for gap in [1e-4, 1e-3, 3e-3, 8e-3] {
            let (mut world, ball) = ball_above(floor, gap);
            for _ in 0..120 {
                world.step(DT).unwrap();
            }
            let height = world.body(ball).unwrap().position().y - RADIUS;
            assert!(
                height.abs() <= creep,
                "floor of radius {floor:e}, let go {gap:e} above it: the ball rests {height:e} \
                 above its surface"
            );
        }
    }
}
