//! A settled stack's contacts are solved together at the start of each step (the resting
//! solve), not found one at a time by the search for impacts: every contact of a step is a
//! resting one at the step's start, no pair goes to the time-of-impact method, and the stack
//! stays put. (A first pass that never found resting pairs left the stack standing too, but
//! chased its contacts through the step as slow impacts; no test noticed.)

use sphere_physics::{BodyId, Settings, SphereDesc, World, glam::DVec3};

const G: f64 = 9.81;
const DT: f64 = 1.0 / 60.0;

/// `stacks` columns of four balls of radius 0.1, touching, at rest, each on its own fixed
/// floor sphere (radius 0.4, its top at y = 0), a metre apart.
fn stacks(stacks: usize) -> (World, Vec<(usize, BodyId)>) {
    let mut world = World::new(Settings::with_gravity(DVec3::new(0.0, -G, 0.0)));
    let mut balls = Vec::new();
    for s in 0..stacks {
        let (x, z) = ((s % 4) as f64, (s / 4) as f64);
        world
            .add_sphere(SphereDesc::new(0.4).at(DVec3::new(x, -0.4, z)).fixed())
            .unwrap();
        for k in 0..4 {
            let ball = SphereDesc::new(0.1)
                .at(DVec3::new(x, 0.1 + 0.2 * k as f64, z))
                .with_restitution(0.5);
            balls.push((k, world.add_sphere(ball).unwrap()));
        }
    }
    (world, balls)
}

fn settles_at_the_start_of_each_step(count: usize) {
    let (mut world, balls) = stacks(count);
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
        assert!(
            stats.collisions as usize >= 4 * count,
            "{} contacts",
            stats.collisions
        );
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
    for &(k, id) in &balls {
        let body = world.body(id).unwrap();
        let height = 0.1 + 0.2 * k as f64;
        assert!(
            (body.position().y - height).abs() < 1e-4,
            "ball {k} of a stack at {}",
            body.position().y
        );
        assert!(body.velocity().length() < G * DT * 0.01, "ball {k} moves");
    }
}

/// One stack: a scene small enough that the broad phase tests all pairs.
#[test]
fn a_settled_stack_is_solved_at_the_start_of_each_step() {
    settles_at_the_start_of_each_step(1);
}

/// Sixteen stacks (80 bodies): the balls in the broad phase's grid, the floors in its
/// hierarchy.
#[test]
fn settled_stacks_in_the_grid_are_solved_at_the_start_of_each_step() {
    settles_at_the_start_of_each_step(16);
}
