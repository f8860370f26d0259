//! A settled stack's contacts are solved together at the start of each step (the resting
//! solve), not found one at a time by the search for impacts: every contact of a step is a
//! resting one at the step's start, no pair goes to the time-of-impact method, and the stack
//! stays put. (A first pass that never found resting pairs left the stack standing too, but
//! chased its contacts through the step as slow impacts; no test noticed.)

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

const G: f64 = 9.81;
const DT: f64 = 1.0 / 60.0;

#[test]
fn a_settled_stack_is_solved_at_the_start_of_each_step() {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -G, 0.0)));
    // A fixed floor (a large sphere whose top is at y = 0) and four balls stacked on it,
    // touching, at rest.
    world
        .add_sphere(SphereDesc::new(3.0).at(DVec3::new(0.0, -3.0, 0.0)).fixed())
        .unwrap();
    let balls: Vec<_> = (0..4)
        .map(|k| {
            world
                .add_sphere(
                    SphereDesc::new(0.1)
                        .at(DVec3::new(0.0, 0.1 + 0.2 * k as f64, 0.0))
                        .with_restitution(0.5),
                )
                .unwrap()
        })
        .collect();
    for _ in 0..30 {
        world.step(DT).unwrap();
    }
    for _ in 0..10 {
        let start = world.stats().time;
        let stats = *world.step(DT).unwrap();
        assert_eq!(
            stats.toi_tests, 0,
            "pairs sent to the time-of-impact method"
        );
        assert!(stats.collisions >= 4, "{} contacts", stats.collisions);
        assert_eq!(stats.resting_contacts, stats.collisions);
        for c in world.collisions() {
            assert!(c.resting, "{c:?}");
            assert_eq!(
                c.time, start,
                "a contact at {} in a step from {start}",
                c.time
            );
        }
    }
    for (k, &id) in balls.iter().enumerate() {
        let body = world.body(id).unwrap();
        let height = 0.1 + 0.2 * k as f64;
        assert!(
            (body.position().y - height).abs() < 1e-4,
            "ball {k} at {}",
            body.position().y
        );
        assert!(body.velocity().length() < G * DT * 0.01, "ball {k} moves");
    }
}
