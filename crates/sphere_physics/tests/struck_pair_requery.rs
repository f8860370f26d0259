//! After an impact both spheres look for their neighbours again, in one scan of the grid for
//! the two: each must still find its own. Here only the struck sphere's new path reaches a
//! third sphere, within the same step: once with the striker first in the grid's order, once
//! with the struck sphere first.

use sphere_physics::glam::DVec3;
use sphere_physics::{BodyId, Settings, SphereDesc, World};

const R: f64 = 0.05;

/// `a` (at `origin`, moving along `direction` at 6 m/s) strikes `b` after 1/600 s; `b` then
/// reaches `c` 1/200 s later. After the first impact `a` rests far from `c`: only `b`'s new
/// box meets `c`'s.
fn trio(world: &mut World, origin: DVec3, direction: DVec3) -> [BodyId; 3] {
    let mut add = |at: f64, v: f64| {
        world
            .add_sphere(
                SphereDesc::new(R)
                    .at(origin + direction * at)
                    .moving(direction * v),
            )
            .unwrap()
    };
    [add(0.0, 6.0), add(0.11, 0.0), add(0.24, 0.0)]
}

#[test]
fn the_struck_sphere_finds_the_next_one_in_the_same_step() {
    let mut world = World::new(Settings::default());
    // Enough spheres at rest close by (in a layer 0.5 m away) that the broad phase puts all
    // of them in its grid, rather than testing all pairs.
    for i in 0..72 {
        let (x, y) = (f64::from(i % 9), f64::from(i / 9));
        world
            .add_sphere(SphereDesc::new(R).at(DVec3::new(0.15 * x, 0.15 * y, 0.5)))
            .unwrap();
    }
    let trios = [
        trio(&mut world, DVec3::ZERO, DVec3::X),
        trio(&mut world, DVec3::new(0.5, 0.3, 0.0), DVec3::NEG_X),
    ];
    let stats = *world.step(1.0 / 60.0).unwrap();
    let v = |id| world.body(id).unwrap().velocity();
    assert_eq!(stats.collisions, 4, "{:?}", world.collisions());
    for ([a, b, c], direction) in trios.into_iter().zip([DVec3::X, DVec3::NEG_X]) {
        assert!(v(a).length() < 1e-12, "a {}", v(a));
        assert!(v(b).length() < 1e-12, "b {}", v(b));
        assert!((v(c) - direction * 6.0).length() < 1e-12, "c {}", v(c));
    }
    assert!(stats.max_overlap <= 1e-12, "overlap {}", stats.max_overlap);
}
