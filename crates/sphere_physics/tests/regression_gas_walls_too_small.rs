//! Regression (found by review): a gas's walls could be so small that they did not close its
//! box (a 2 m box with walls of radius 0.01: six small spheres, and the gas flew off). Walls
//! too small to close the box's corners are refused, naming the field; walls just large
//! enough keep the gas in.

use sphere_physics::SceneDesc;
use sphere_physics::generate::Generator;

fn gas(wall_radius: f64) -> Generator {
    Generator::Gas {
        count: 60,
        seed: 4,
        min: [-0.5; 3],
        max: [0.5; 3],
        radius: 0.05,
        speed: 3.0,
        density: 1.0,
        restitution: None,
        walls: true,
        wall_radius,
    }
}

#[test]
fn regression_walls_that_leave_the_box_open_are_refused() {
    let error = gas(0.01).spheres().unwrap_err().to_string();
    assert!(
        error.contains("wall_radius") && error.contains("too small"),
        "{error}"
    );
    // Half a box's width out, the bound for this box is 1.95 m.
    assert!(gas(1.9).spheres().is_err());
    assert!(gas(2.0).spheres().is_ok());
    // Just large enough, and the gas stays in for 20 s: every centre within the walls' reach
    // (they curve away from the faces' middles, by an eighth of a metre at their corners).
    let mut world = SceneDesc::from_ron(
        "(name: \"gas\", generate: [Gas(count: 60, seed: 4, min: (-0.5, -0.5, -0.5),
          max: (0.5, 0.5, 0.5), radius: 0.05, speed: 3.0, wall_radius: 2.0)])",
    )
    .unwrap()
    .build()
    .unwrap();
    for _ in 0..1200 {
        world.step(1.0 / 60.0).unwrap();
    }
    for body in world.bodies().iter().filter(|b| !b.is_fixed()) {
        let p = body.position();
        assert!(
            p.abs().max_element() <= 0.65,
            "{} left the box: {p}",
            body.id()
        );
    }
}
