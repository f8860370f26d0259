//! Balls resting on a floor that meet slowly, sideways, keep their restitution: the resting
//! solve stops a pair only where it presses the pair together itself (a bed's sideways load,
//! see `regression_ball_pit`), never a meeting of the balls' own. Elastic balls on a floor
//! struck at 0.1 m/s (below the resting speed of their weight, 0.25 m/s at 60 Hz) pass the
//! blow on exactly, whether they meet within a step, touch at its start, or stand in a
//! touching row (a Newton's cradle on a table: one ball in, one ball out).

use sphere_physics::glam::DVec3;
use sphere_physics::{BodyId, Settings, SphereDesc, World};

const DT: f64 = 1.0 / 60.0;
const R: f64 = 0.05;
const SPEED: f64 = 0.1;

/// Elastic balls on a fixed floor of radius 1e4, `gaps` apart along x (the row centred on the
/// floor's top), left on the floor for a step (their floor contacts loaded, the touching ones
/// still within the contact band); then the first is sent at the others at `SPEED`. The floor
/// is a sphere: a ball `x` from its top slides off at `g x / 1e4`, under 1e-5 m/s here.
fn row(gaps: &[f64]) -> (World, Vec<BodyId>) {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
    world
        .add_sphere(SphereDesc::new(1e4).at(DVec3::new(0.0, -1e4, 0.0)).fixed())
        .unwrap();
    let length: f64 = gaps.iter().map(|g| 2.0 * R + g).sum();
    let mut x = -0.5 * length;
    let mut balls = Vec::new();
    for k in 0..=gaps.len() {
        if k > 0 {
            x += 2.0 * R + gaps[k - 1];
        }
        let ball = SphereDesc::new(R)
            .at(DVec3::new(x, R, 0.0))
            .with_restitution(1.0);
        balls.push(world.add_sphere(ball).unwrap());
    }
    for _ in 0..1 {
        world.step(DT).unwrap();
    }
    world
        .set_velocity(balls[0], DVec3::new(SPEED, 0.0, 0.0))
        .unwrap();
    (world, balls)
}

/// The balls' speeds along x after `steps` steps.
fn speeds_after(world: &mut World, balls: &[BodyId], steps: u32) -> Vec<f64> {
    for _ in 0..steps {
        world.step(DT).unwrap();
    }
    balls
        .iter()
        .map(|&b| world.body(b).unwrap().velocity().x)
        .collect()
}

/// The last ball took the whole blow and the others none, within the floor's slide (a
/// thousandth of the blow; a resting stop would share it, half each for two balls).
fn assert_passed_on(speeds: &[f64]) {
    let (last, rest) = speeds.split_last().unwrap();
    assert!((last - SPEED).abs() < 1e-3 * SPEED, "{speeds:?}");
    for s in rest {
        assert!(s.abs() < 1e-3 * SPEED, "{speeds:?}");
    }
}

#[test]
fn balls_meeting_within_a_step_exchange_their_speeds() {
    let (mut world, balls) = row(&[1e-3]);
    assert_passed_on(&speeds_after(&mut world, &balls, 2));
}

#[test]
fn balls_touching_at_the_start_of_a_step_exchange_their_speeds() {
    let (mut world, balls) = row(&[0.0]);
    assert_passed_on(&speeds_after(&mut world, &balls, 1));
}

#[test]
fn a_touching_row_on_a_floor_passes_the_blow_to_its_last_ball() {
    let (mut world, balls) = row(&[0.0, 0.0, 0.0]);
    assert_passed_on(&speeds_after(&mut world, &balls, 1));
}
