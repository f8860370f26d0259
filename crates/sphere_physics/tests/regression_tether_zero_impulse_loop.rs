//! A tethered sphere's drift is bent along its string (a chord); at an impact the sphere moves
//! with its free velocity (slack string) or along its swing (taut string). With a partner on the
//! anchor's side the bent drift approaches it while the real velocity does not: the impact gave
//! no impulse, the bent drift found the same pair approaching at the same instant again, and the
//! loop ran until the step's collision budget was spent, after which every other collision of
//! the step was dropped (two bystanders passed through each other).

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

fn scene(gravity: DVec3, bob: SphereDesc, obstacle: DVec3) -> World {
    let mut world = World::new(Settings::with_gravity(gravity));
    world.add_sphere(bob).unwrap();
    world
        .add_sphere(SphereDesc::new(0.1).at(obstacle).fixed())
        .unwrap();
    // Bystanders closing at 20 m/s with a 0.1 m gap: they meet at t = 0.005 s.
    world
        .add_sphere(
            SphereDesc::new(0.05)
                .at(DVec3::new(5.0, 0.0, 0.0))
                .moving(DVec3::new(10.0, 0.0, 0.0)),
        )
        .unwrap();
    world
        .add_sphere(
            SphereDesc::new(0.05)
                .at(DVec3::new(5.2, 0.0, 0.0))
                .moving(DVec3::new(-10.0, 0.0, 0.0)),
        )
        .unwrap();
    world
}

fn check(mut world: World, case: &str) {
    let stats = *world.step(1.0 / 60.0).unwrap();
    assert_eq!(stats.collisions_deferred, 0, "{case}: {stats:?}");
    assert!(
        stats.collisions <= 4,
        "{case}: {} collisions",
        stats.collisions
    );
    // The bystanders met and swapped velocities (equal masses, elastic).
    let (a, b) = (&world.bodies()[2], &world.bodies()[3]);
    assert!(
        (a.velocity().x + 10.0).abs() < 1e-9,
        "{case}: {:?}",
        a.velocity()
    );
    assert!(
        (b.velocity().x - 10.0).abs() < 1e-9,
        "{case}: {:?}",
        b.velocity()
    );
    assert!(
        a.position().x < b.position().x,
        "{case}: they passed through each other"
    );
}

#[test]
fn regression_slack_string_bent_towards_a_touching_obstacle() {
    for gravity in [DVec3::ZERO, DVec3::new(0.0, 0.0, -9.81)] {
        let bob = SphereDesc::new(0.1)
            .at(DVec3::new(0.0, 0.0, -0.99))
            .moving(DVec3::new(12.0, 0.0, 0.0))
            .tethered(DVec3::ZERO, 1.0);
        check(
            scene(gravity, bob, DVec3::new(0.0, 0.0, -0.79)),
            &format!("slack, gravity {gravity}"),
        );
    }
}

#[test]
fn regression_taut_string_bent_towards_a_touching_obstacle() {
    let bob = SphereDesc::new(0.1)
        .at(DVec3::new(0.0, 0.0, -1.0))
        .moving(DVec3::new(2.0, 0.0, 0.0))
        .tethered(DVec3::ZERO, 1.0);
    check(
        scene(DVec3::new(0.0, 0.0, -9.81), bob, DVec3::new(0.0, 0.0, -0.8)),
        "taut",
    );
}
