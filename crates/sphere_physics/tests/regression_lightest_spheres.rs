//! Regression (found by review): spheres lighter than about 1.1e-308 kg were accepted, though
//! the sum of two of their inverse masses, which every impulse divides by, overflows to
//! infinity. Two such spheres met head-on with an impulse of 0 and kept their velocities
//! (where they should swap them); one resting on another carried no load. Moving spheres must
//! now weigh at least `MIN_MASS` (1e-300 kg), refused below it with the field to blame, and
//! the lightest allowed collide as any.

use sphere_physics::glam::DVec3;
use sphere_physics::{Field, MIN_MASS, Settings, SphereDesc, World};

/// The density that gives a sphere of `radius` the mass `mass`.
fn density_for(mass: f64, radius: f64) -> f64 {
    mass / (4.0 / 3.0 * std::f64::consts::PI * radius * radius * radius)
}

fn head_on(density: f64) -> Result<World, sphere_physics::BodyError> {
    let mut world = World::new(Settings::default());
    for (x, v) in [(-1.0, 1.0), (1.0, -1.0)] {
        world.add_sphere(
            SphereDesc::new(0.5)
                .at(DVec3::new(x, 0.0, 0.0))
                .moving(DVec3::new(v, 0.0, 0.0))
                .with_density(density),
        )?;
    }
    Ok(world)
}

#[test]
fn regression_spheres_too_light_to_collide_are_refused() {
    // The review's spheres: 1.05e-308 kg each, inverse masses 9.5e307.
    let error = head_on(2e-308).err().unwrap();
    assert_eq!(error.field, Field::Density);
    assert!(error.to_string().contains("1e-300 kg"), "{error}");
    // A volume too small for any density to matter: the radius is to blame.
    let mut world = World::new(Settings::default());
    let error = world.add_sphere(SphereDesc::new(1e-101)).unwrap_err();
    assert_eq!(error.field, Field::Radius, "{error}");
    // Just below the least mass, refused; just above it, taken. Fixed spheres have no mass.
    assert!(head_on(density_for(0.99999 * MIN_MASS, 0.5)).is_err());
    assert!(head_on(density_for(1.00001 * MIN_MASS, 0.5)).is_ok());
    world
        .add_sphere(SphereDesc::new(0.5).with_density(1e-320).fixed())
        .unwrap();
}

#[test]
fn regression_the_lightest_spheres_swap_velocities_head_on() {
    let mut world = head_on(density_for(1.00001 * MIN_MASS, 0.5)).unwrap();
    for _ in 0..60 {
        world.step(1.0 / 60.0).unwrap();
    }
    let v: Vec<f64> = world.bodies().iter().map(|b| b.velocity().x).collect();
    assert_eq!(v, [-1.0, 1.0]);
}
