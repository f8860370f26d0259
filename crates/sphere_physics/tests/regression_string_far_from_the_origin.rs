//! Regression (found by review): a sphere on a short string far from the origin failed its own
//! validation. At each step's end a sphere at its string's length is put back on it, at
//! `anchor + normal · length`, rounded to the coordinates' precision there (a millionth of a
//! millimetre at a kilometre); a string of a centimetre a kilometre out was then longer than
//! the check's slack (a billionth of its length) allowed, and `set_velocity` with the body's
//! own velocity, or `set_desc` with its own description, was refused: "leaves the sphere
//! farther from its anchor than the string's length".

use sphere_physics::glam::DVec3;
use sphere_physics::{Settings, SphereDesc, World};

#[test]
fn regression_a_swinging_sphere_far_out_accepts_its_own_state() {
    for far in [1.0e3, 1.0e5, 1.0e7] {
        let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)));
        let anchor = DVec3::new(far, 0.3 * far, -0.7 * far);
        let length = 0.01;
        // Held out sideways at the string's length, at 37 degrees from the vertical.
        let (s, c) = 37f64.to_radians().sin_cos();
        let ball = world
            .add_sphere(
                SphereDesc::new(0.002)
                    .at(anchor + DVec3::new(s * length, -c * length, 0.0))
                    .tethered(anchor, length),
            )
            .unwrap();
        for step in 0..300 {
            world.step(1.0 / 240.0).unwrap();
            let body = world.body(ball).unwrap();
            let (velocity, desc) = (body.velocity(), body.desc().clone());
            let distance = (body.position() - anchor).length();
            // On its string (taut, swinging) to within rounding there.
            assert!(
                (distance - length).abs() <= length * 1e-6,
                "{far} m out, step {step}: {distance} m from the anchor"
            );
            world
                .set_velocity(ball, velocity)
                .unwrap_or_else(|e| panic!("{far} m out, step {step}: {e}"));
            world
                .set_desc(ball, desc)
                .unwrap_or_else(|e| panic!("{far} m out, step {step}: {e}"));
        }
    }
}
