//! The broad phase's grid compares boxes packed into 16-bit integers in a frame around its
//! block of cells (it once compared them in single precision, rounded outwards, whose step is
//! 0.008 at 1e5, a sixth of these spheres' radius). Far from the origin the frame's map from
//! space is a large offset minus a large product: a gas there must still find every
//! collision, keep its energy and leave no overlap.

use sphere_physics::SceneDesc;

fn gas_at(offset: [f64; 3]) -> SceneDesc {
    let [x, y, z] = offset;
    SceneDesc::from_ron(&format!(
        "(name: \"far gas\", generate: [
            Gas(count: 600, seed: 5, min: ({:?}, {:?}, {:?}), max: ({:?}, {:?}, {:?}),
                radius: 0.05, speed: 3.0),
        ])",
        x - 1.5,
        y - 1.5,
        z - 1.5,
        x + 1.5,
        y + 1.5,
        z + 1.5,
    ))
    .unwrap()
}

/// Steps the gas at `offset` for 2 s: no step ends with an overlap past `overlap` or a
/// collision put off, more than 500 collisions in all, the kinetic energy kept to `drift`
/// of itself, and every sphere inside its walls.
fn misses_no_collision(offset: [f64; 3], overlap: f64, drift: f64) {
    let mut world = gas_at(offset).build().unwrap();
    let energy = world.kinetic_energy();
    let mut collisions = 0;
    for _ in 0..120 {
        let stats = *world.step(1.0 / 60.0).unwrap();
        collisions += stats.collisions;
        assert!(
            stats.max_overlap <= overlap,
            "at {offset:?}: overlap {}",
            stats.max_overlap
        );
        assert_eq!(stats.collisions_deferred, 0);
    }
    assert!(collisions > 500, "at {offset:?}: {collisions} collisions");
    let kept = (world.kinetic_energy() - energy).abs() / energy;
    assert!(kept <= drift, "at {offset:?}: energy drift {kept}");
    // Inside its walls (1e4-radius spheres, flat to about 1.1e-4 over the box).
    for body in world.bodies().iter().filter(|b| !b.is_fixed()) {
        for (a, centre) in offset.iter().enumerate() {
            let reach = 1.5 - body.radius() + 2e-4;
            assert!(
                (body.position()[a] - centre).abs() <= reach,
                "at {offset:?}: {:?}",
                body.position()
            );
        }
    }
}

#[test]
fn a_gas_far_from_the_origin_misses_no_collision() {
    for offset in [[0.0; 3], [1.0e5, -2.0e5, 3.0e5], [-7.0e5, 4.0e5, 1.0e6]] {
        misses_no_collision(offset, 1e-9, 1e-10);
    }
}

/// Past the cells a grid counted from the origin can number (2e8 m out, in cells of about
/// 0.15 m: some 1.3e9 cells), the broad phase counts them from among the spheres instead (it
/// clamped them all to one and compared every two spheres: the same collisions, 28 times
/// slower for 2000). Checked here: the cells counted so still find every collision.
#[test]
fn a_gas_past_two_billion_cells_from_the_origin_misses_no_collision() {
    // Positions there are resolved to 3e-8 m.
    for offset in [[2.0e8, -2.0e8, 2.0e8], [-2.0e8, 1.0, 0.0]] {
        misses_no_collision(offset, 1e-6, 1e-9);
    }
}
