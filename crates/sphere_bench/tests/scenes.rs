//! The benchmark scenes are what their docs say: the counts, the walls, the spheres inside
//! them, and the pile as deep at every size (so that its cost per sphere compares across sizes);
//! and a measured run's steps, one by one, add up to its totals, its mean kinetic energy over
//! them.

use sphere_bench::scenes::{self, RADIUS};

#[test]
fn every_scene_has_its_spheres_and_fixed_bodies() {
    for n in [1000, 10_000] {
        let shower = scenes::shower(n, 1).build().unwrap();
        let gas = scenes::gas(n, 1).build().unwrap();
        let pile = scenes::pile(n, 1).build().unwrap();
        // The dome; six walls; a floor and four walls.
        for (world, fixed) in [(&shower, 1), (&gas, 6), (&pile, 5)] {
            assert_eq!(world.len(), n as usize + fixed);
            assert_eq!(
                world.bodies().iter().filter(|b| b.is_fixed()).count(),
                fixed
            );
        }
    }
}

#[test]
fn the_pile_starts_inside_its_open_box_and_is_as_deep_at_every_size() {
    let mut depths = Vec::new();
    for n in [1000, 10_000, 100_000] {
        let world = scenes::pile(n, 1).build().unwrap();
        let walls: Vec<_> = world.bodies().iter().filter(|b| b.is_fixed()).collect();
        let spheres: Vec<_> = world.bodies().iter().filter(|b| !b.is_fixed()).collect();
        // Inside every wall and above the floor (each a sphere of radius 1e4), at rest.
        for s in &spheres {
            assert_eq!(s.radius(), RADIUS);
            assert_eq!(s.velocity(), sphere_physics::glam::DVec3::ZERO);
            for w in &walls {
                let gap = (s.position() - w.position()).length() - s.radius() - w.radius();
                assert!(
                    gap >= 0.0,
                    "sphere {} overlaps {:?} by {}",
                    s.id(),
                    w.name(),
                    -gap
                );
            }
        }
        // The floor's width from the walls along x: the bed's depth if the spheres packed at
        // 0.6 over it.
        let x_walls: Vec<f64> = walls
            .iter()
            .filter(|w| w.name().is_some_and(|name| name.starts_with("wall x")))
            .map(|w| w.position().x.abs() - w.radius())
            .collect();
        assert_eq!(x_walls.len(), 2);
        let width = 2.0 * x_walls[0];
        let volume = n as f64 * 4.0 / 3.0 * std::f64::consts::PI * RADIUS.powi(3);
        depths.push(volume / 0.6 / (width * width));
    }
    // About six sphere diameters deep at every size (the floor's side rounds up to a cell).
    for depth in &depths {
        assert!(
            (0.5..0.7).contains(depth),
            "the pile's beds would be {depths:?} m deep"
        );
    }
}

#[test]
fn the_showers_are_the_1k_shower_side_by_side_and_stay_apart() {
    // One tile is the 1k shower itself.
    let (one, tiles) = (scenes::shower(1000, 1), scenes::showers(1000, 1));
    let (one, tiles) = (one.build().unwrap(), tiles.build().unwrap());
    assert_eq!(one.len(), tiles.len());
    for (a, b) in one.bodies().iter().zip(tiles.bodies()) {
        assert_eq!(
            (a.position(), a.radius(), a.is_fixed()),
            (b.position(), b.radius(), b.is_fixed())
        );
    }
    // A dome a tile, the spheres shared out evenly.
    for (n, domes) in [(2500, 3), (10_000, 10)] {
        let world = scenes::showers(n, 1).build().unwrap();
        assert_eq!(world.len(), n as usize + domes);
        assert_eq!(
            world.bodies().iter().filter(|b| b.is_fixed()).count(),
            domes
        );
    }
    // Over a benchmark's 61 steps no sphere meets another tile's sphere or dome. The domes
    // come first (tile t's is body t), then each tile's rain in turn.
    let (n, per_tile) = (4000u32, 1000u64);
    let mut world = scenes::showers(n, 1).build().unwrap();
    let tile = |id: u64| if id < 4 { id } else { (id - 4) / per_tile };
    let mut collisions = 0;
    for _ in 0..61 {
        world.step(1.0 / 60.0).unwrap();
        for c in world.collisions() {
            let (a, b) = (tile(c.a.index() as u64), tile(c.b.index() as u64));
            assert_eq!(a, b, "a collision between tiles {a} and {b}");
            collisions += 1;
        }
    }
    assert!(
        collisions > 4 * 1000,
        "the rain landed: {collisions} collisions"
    );
}

#[test]
fn the_two_gases_apart_are_the_gas_split_in_two_a_kilometre_apart() {
    for n in [1000, 10_001] {
        let world = scenes::apart(n, 1).build().unwrap();
        assert_eq!(world.len(), n as usize);
        assert!(world.bodies().iter().all(|b| !b.is_fixed()));
        // Split in two at x = 500 m: as many on each side (the first has the odd one), each
        // group within the box of the gas of its count, at the gas's speed.
        let near: Vec<_> = world
            .bodies()
            .iter()
            .filter(|b| b.position().x < 500.0)
            .collect();
        let far: Vec<_> = world
            .bodies()
            .iter()
            .filter(|b| b.position().x >= 500.0)
            .collect();
        assert_eq!(
            (near.len(), far.len()),
            (n.div_ceil(2) as usize, n as usize / 2)
        );
        let gas = scenes::gas(n.div_ceil(2), 1).build().unwrap();
        let reach = gas
            .bodies()
            .iter()
            .filter(|b| !b.is_fixed())
            .map(|b| b.position().abs().max_element())
            .fold(0.0, f64::max);
        for (group, x) in [(&near, 0.0), (&far, scenes::APART)] {
            for b in group {
                let offset = b.position() - sphere_physics::glam::DVec3::X * x;
                assert!(offset.abs().max_element() <= reach + RADIUS, "{offset}");
                assert!((b.velocity().length() - 1.0).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn a_measured_run_lists_each_timed_step_and_they_add_up() {
    // A small shower: the first collisions come in the second tenth of a second.
    let m = sphere_bench::measure_ours(&scenes::shower(200, 1), 1, 20, 1.0 / 60.0, true);
    assert_eq!(m.per_step.len(), 20);
    let sum = |f: fn(&sphere_bench::StepRecord) -> u64| m.per_step.iter().map(f).sum::<u64>();
    assert_eq!(sum(|r| u64::from(r.collisions)), m.collisions);
    assert_eq!(sum(|r| r.toi_tests), m.toi_tests);
    assert!(m.collisions > 0, "the rain reached the dome");
    assert!(m.per_step.iter().all(|r| r.resting <= r.collisions));
    let seconds: f64 = m.per_step.iter().map(|r| r.seconds).sum();
    assert!((seconds - m.seconds).abs() <= 1e-9 * m.seconds.max(1.0));
    // The slowest step is the slowest of those listed.
    let slowest = m.per_step.iter().map(|r| r.seconds).fold(0.0, f64::max);
    assert_eq!(m.slowest, slowest);
    let events: f64 = m.per_step.iter().map(|r| r.events.unwrap()).sum();
    let phases = m.phases.unwrap().events.as_secs_f64();
    assert!((events - phases).abs() <= 1e-6, "{events} against {phases}");
    // Without profiling there is no event loop's time to give.
    let plain = sphere_bench::measure_ours(&scenes::gas(100, 1), 1, 3, 1.0 / 60.0, false);
    assert!(plain.per_step.iter().all(|r| r.events.is_none()));
}

#[test]
fn the_mean_kinetic_energy_is_over_the_timed_steps() {
    // A shower falling from rest: its energy grows every step, so a mean over the wrong steps
    // (the untimed ones too, or only the last) comes out different.
    let (scene, dt) = (scenes::shower(200, 1), 1.0 / 60.0);
    let m = sphere_bench::measure_ours(&scene, 3, 10, dt, false);
    let mut world = scene.build().unwrap();
    for _ in 0..3 {
        world.step(dt).unwrap();
    }
    let mut energies = Vec::new();
    for _ in 0..10 {
        world.step(dt).unwrap();
        energies.push(world.kinetic_energy());
    }
    let mean = energies.iter().sum::<f64>() / 10.0;
    assert_eq!(m.kinetic_mean, mean);
    assert_eq!(m.kinetic_after, energies[9]);
    assert!(energies[0] < mean && mean < energies[9]);
}

#[test]
fn the_sparse_gas_is_the_gas_scattered_evenly_and_far_apart() {
    let n = 1000;
    let sparse = scenes::sparse(n, 1).build().unwrap();
    let gas = scenes::gas(n, 1).build().unwrap();
    // The median distance from a sphere to its nearest neighbour.
    let nearest = |world: &sphere_physics::World| {
        let at: Vec<_> = world
            .bodies()
            .iter()
            .filter(|b| !b.is_fixed())
            .map(|b| b.position())
            .collect();
        let mut d: Vec<f64> = at
            .iter()
            .enumerate()
            .map(|(i, p)| {
                at.iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .map(|(_, q)| p.distance(*q))
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        d.sort_by(f64::total_cmp);
        (at, d[d.len() / 2])
    };
    let (at, far) = nearest(&sparse);
    let (_, near) = nearest(&gas);
    assert_eq!(at.len(), n as usize);
    assert_eq!(sparse.len(), n as usize + 6, "the gas's six walls");
    assert!(
        far > 0.5 && near < 0.2,
        "nearest neighbours {far} m apart against the gas's {near}"
    );
    // Evenly: every octant of the box holds about an eighth of the spheres.
    let mut octants = [0; 8];
    for p in &at {
        octants
            [usize::from(p.x > 0.0) + 2 * usize::from(p.y > 0.0) + 4 * usize::from(p.z > 0.0)] += 1;
    }
    assert!(
        octants.iter().all(|&k| (90..160).contains(&k)),
        "{octants:?}"
    );
    // All at the gas's speed.
    assert!(
        sparse
            .bodies()
            .iter()
            .filter(|b| !b.is_fixed())
            .all(|b| (b.velocity().length() - 1.0).abs() < 1e-12)
    );
}

#[test]
fn the_far_gas_is_a_gas_as_large_moved_out() {
    let (near, far) = (scenes::gas(1000, 1), scenes::far_gas(1000, 1));
    let (near, far) = (near.sphere_descs().unwrap(), far.sphere_descs().unwrap());
    assert_eq!(near.len(), far.len());
    // The same box around a centre 2e8 m out on each axis (its lattice sites, drawn at that
    // distance, are not the gas's to the bit).
    let reach = |descs: &[sphere_physics::SphereDesc], centre: f64| {
        descs
            .iter()
            .filter(|d| !d.fixed)
            .map(|d| {
                (d.position - sphere_physics::glam::DVec3::splat(centre))
                    .abs()
                    .max_element()
            })
            .fold(0.0, f64::max)
    };
    let (a, b) = (reach(&near, 0.0), reach(&far, scenes::FAR));
    assert!((a - b).abs() <= 0.2, "{a} against {b}");
    for d in far.iter().filter(|d| !d.fixed) {
        assert!((d.velocity.length() - 1.0).abs() < 1e-12);
    }
}
