//! Regression: with nothing accelerating, the separation that moves overlapping spheres apart
//! at a step's end moved a sphere out of a fixed one into a much smaller free one beside it,
//! and left the small one deep inside it.
//!
//! Found by `sphere-fuzz --strings fast` at seed 48 581 (a scene without strings): kinematic
//! spheres drive a free one of 128 kg, which ends each step in them; the separation moves it
//! out (a fixed or kinematic sphere gives no way), into a free sphere of 0.8 mg. That pair
//! was moved apart keeping its centre of mass, so the small sphere took nearly all of the
//! move, and its cap (a tenth of its radius, 1 mm a step) the large one none: 11.5 of the
//! small one's radii deep. Now a pair that only the separation's moves brought into overlap,
//! by a move that kept no centre of mass, is moved back to where the step left it, the small
//! sphere carried as far as the larger cap of the two; a crowd of free spheres still comes
//! apart about its centre of mass.
//!
//! The scene reduced to three spheres, no gravity: a fixed sphere (radius 0.5 m), a free one
//! (radius 0.9 m) placed 0.2 m into it, and a free one of radius 1 cm 1 mm beyond the large
//! one. Before, the first step's separation left the small sphere 8.8 of its radii into the
//! large one, 19.6 after three steps, and it took 200 steps to come out.

use sphere_physics::glam::DVec3;
use sphere_physics::{Body, BodyId, Settings, SphereDesc, World};

/// How deep `a` and `b` are into each other, in metres.
fn depth(world: &World, a: BodyId, b: BodyId) -> f64 {
    let (a, b): (&Body, &Body) = (world.body(a).unwrap(), world.body(b).unwrap());
    a.radius() + b.radius() - (b.position() - a.position()).length()
}

#[test]
fn regression_the_separation_carries_a_small_sphere_a_large_one_is_moved_into() {
    let mut world = World::new(Settings::with_gravity(DVec3::ZERO));
    let fixed = world.add_sphere(SphereDesc::new(0.5).fixed()).unwrap();
    let large = world
        .add_sphere(SphereDesc::new(0.9).at(DVec3::new(1.2, 0.0, 0.0)))
        .unwrap();
    let small = world
        .add_sphere(SphereDesc::new(0.01).at(DVec3::new(2.111, 0.0, 0.0)))
        .unwrap();
    assert!((depth(&world, fixed, large) - 0.2).abs() < 1e-12);

    for step in 0..5 {
        world.step(1.0 / 60.0).unwrap();
        let carried = depth(&world, large, small);
        assert!(
            carried <= 0.02 * 0.01,
            "step {step}: the small sphere {} of its radii deep",
            carried / 0.01
        );
        for body in world.bodies() {
            assert_eq!(body.velocity(), DVec3::ZERO, "positions only");
        }
    }
    // Out of the fixed sphere (to within its contact band, a micrometre) at a tenth of the
    // large one's radius a step, as it was before.
    assert!(depth(&world, fixed, large) <= 1e-5);
    assert!(world.body(small).unwrap().position().x > 2.3);
}
