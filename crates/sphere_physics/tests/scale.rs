//! Scenes big enough for the broad phase's grid (past 64 bodies), with huge fixed spheres on
//! levels of their own: nothing may be missed.

use sphere_physics::SceneDesc;

#[test]
fn gas_stays_in_its_box_with_energy_exact() {
    let scene = SceneDesc::from_ron(
        r#"(name: "gas", generate: [
            Gas(count: 600, seed: 3, min: (-1.5, -1.5, -1.5), max: (1.5, 1.5, 1.5), radius: 0.05, speed: 3.0),
        ])"#,
    )
    .unwrap();
    let mut world = scene.build().unwrap();
    let energy = world.kinetic_energy();
    let mut collisions = 0;
    for _ in 0..120 {
        let stats = *world.step(1.0 / 60.0).unwrap();
        collisions += stats.collisions;
        assert!(stats.max_overlap <= 1e-9, "overlap {}", stats.max_overlap);
        assert_eq!(stats.collisions_deferred, 0);
    }
    assert!(collisions > 500, "the gas collides: {collisions}");
    assert!((world.kinetic_energy() - energy).abs() <= 1e-10 * energy);
    // Walls are 1e4-radius spheres touching the box: flat to 3²/(8e4) ≈ 1.1e-4 at the edges.
    for body in world.bodies().iter().filter(|b| !b.is_fixed()) {
        let reach = 1.5 - body.radius() + 2e-4;
        assert!(
            body.position().abs().max_element() <= reach,
            "{:?}",
            body.position()
        );
    }
}

#[test]
fn shower_lands_on_the_dome_and_slides_off() {
    let scene = SceneDesc::from_ron(
        r#"(name: "shower", gravity: (0.0, -9.81, 0.0), restitution: 0.5,
            spheres: [(name: "dome", position: (0.0, 0.0, 0.0), radius: 1.0, fixed: true)],
            generate: [Shower(count: 400, seed: 2, min: (-0.8, 1.2, -0.8), max: (0.8, 2.5, 0.8), radius: 0.04)])"#,
    )
    .unwrap();
    let mut world = scene.build().unwrap();
    let settings = world.settings().clone();
    let dt = 1.0 / 60.0;
    let creep = settings.creep_fraction * settings.resting_factor * 9.81 * dt * dt;
    for _ in 0..90 {
        let stats = *world.step(dt).unwrap();
        assert!(stats.max_overlap <= creep, "overlap {}", stats.max_overlap);
    }
    let bodies = world.bodies();
    // Every sphere has met the dome or another sphere: none is still in plain free fall
    // straight down, and none is inside the dome.
    let moved_sideways = bodies
        .iter()
        .filter(|b| !b.is_fixed() && (b.velocity().x != 0.0 || b.velocity().z != 0.0))
        .count();
    assert!(moved_sideways > 300, "{moved_sideways} deflected");
    for b in bodies.iter().filter(|b| !b.is_fixed()) {
        assert!(b.position().length() >= 1.0 + b.radius() - creep);
    }
}
