//! A struck sphere whose box meets more than 64 others: a re-query glances at its candidates
//! 64 at a time (two at a time within each batch), and must still find the one it strikes
//! next, listed after all the others.
//!
//! A big ball at rest has a small one just ahead of it (+x) and more than a hundred small ones
//! in the corners of its box behind it (-x, low z: the grid lists them first), none of which it
//! can reach. A projectile strikes the big ball from behind; the big ball then strikes the small
//! one ahead within the same step. Only the big ball's re-query after the first impact can find
//! that second impact (at rest, the two never meet), and the small one ahead comes after every
//! corner sphere in its list of candidates.

use sphere_physics::{Settings, SphereDesc, World, glam::DVec3};

const BIG: f64 = 1.0;
const SMALL: f64 = 0.05;
const PROJECTILE: f64 = 0.5;
const SPEED: f64 = 30.0;
const GAP: f64 = 0.01;
const DT: f64 = 1.0 / 60.0;

#[test]
fn a_struck_sphere_with_many_candidates_finds_the_last_one() {
    let mut world = World::new(Settings::default());
    let big = world
        .add_sphere(SphereDesc::new(BIG).with_restitution(1.0))
        .unwrap();
    let ahead = world
        .add_sphere(
            SphereDesc::new(SMALL)
                .at(DVec3::X * (BIG + SMALL + GAP))
                .with_restitution(1.0),
        )
        .unwrap();
    // Corner spheres: inside the big ball's box, behind its centre and below it, well clear of
    // its surface (it only moves away from them).
    let mut corners = Vec::new();
    for i in 0..5 {
        for j in 0..17 {
            for k in 0..8 {
                let at = DVec3::new(
                    -0.95 + 0.12 * f64::from(i),
                    -0.95 + 0.12 * f64::from(j),
                    -0.95 + 0.12 * f64::from(k),
                );
                if at.length() > BIG + SMALL + 0.05 {
                    corners.push(world.add_sphere(SphereDesc::new(SMALL).at(at)).unwrap());
                }
            }
        }
    }
    assert!(corners.len() > 100, "{} corner spheres", corners.len());
    let projectile = world
        .add_sphere(
            SphereDesc::new(PROJECTILE)
                .at(-DVec3::X * (BIG + PROJECTILE + GAP))
                .moving(DVec3::X * SPEED)
                .with_restitution(1.0),
        )
        .unwrap();

    world.step(DT).unwrap();

    // Head-on and elastic: the big ball leaves at 2 m u / (m + M), masses as the cubes of the
    // radii (one density).
    let (m, big_mass) = (PROJECTILE.powi(3), BIG.powi(3));
    let struck_at = GAP / SPEED;
    let big_speed = 2.0 * m * SPEED / (m + big_mass);
    let reaches_at = struck_at + GAP / big_speed;
    assert!(reaches_at < DT);
    let collisions = world.collisions();
    let first = collisions
        .iter()
        .find(|c| [c.a, c.b] == [big, projectile] || [c.a, c.b] == [projectile, big])
        .expect("the projectile strikes the big ball");
    assert!((first.time - struck_at).abs() <= 1e-12, "{}", first.time);
    let second = collisions
        .iter()
        .find(|c| [c.a, c.b] == [big, ahead] || [c.a, c.b] == [ahead, big])
        .expect("the big ball strikes the small one ahead in the same step");
    assert!(
        (second.time - reaches_at).abs() <= 1e-9,
        "struck at {}, expected {reaches_at}",
        second.time
    );
    assert!(
        collisions
            .iter()
            .all(|c| !corners.contains(&c.a) && !corners.contains(&c.b)),
        "no corner sphere is touched"
    );
    // Head-on and elastic again: the small one leaves at 2 M v / (M + m).
    let ahead_velocity = world.body(ahead).unwrap().velocity();
    let small_mass = SMALL.powi(3);
    let ahead_speed = 2.0 * big_mass * big_speed / (big_mass + small_mass);
    assert!(
        (ahead_velocity - DVec3::X * ahead_speed).length() <= 1e-12 * ahead_speed,
        "{ahead_velocity}, expected {ahead_speed} along x"
    );
}
