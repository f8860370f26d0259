//! Scene generators: deterministic, inside their box, never overlapping, and checked.

mod common;

use common::no_overlap;
use sphere_physics::generate::Generator;
use sphere_physics::{SceneDesc, SceneError};

fn shower(count: u32, seed: u64) -> Generator {
    Generator::Shower {
        count,
        seed,
        min: [-1.0, 2.0, -1.0],
        max: [1.0, 4.0, 1.0],
        radius: 0.05,
        velocity: [0.0, -1.0, 0.0],
        density: 2.0,
        restitution: Some(0.5),
    }
}

fn gas(count: u32, walls: bool) -> Generator {
    Generator::Gas {
        count,
        seed: 3,
        min: [0.0, 0.0, 0.0],
        max: [4.0, 2.0, 2.0],
        radius: 0.1,
        speed: 1.5,
        density: 1.0,
        restitution: None,
        walls,
        wall_radius: 1.0e4,
    }
}

#[test]
fn same_seed_same_spheres_other_seed_other_spheres() {
    let a = shower(500, 1).spheres().unwrap();
    assert_eq!(a, shower(500, 1).spheres().unwrap());
    assert_ne!(a, shower(500, 2).spheres().unwrap());
}

#[test]
fn shower_spheres_fill_the_box_without_overlap() {
    // Dense (most cells used) and sparse (few cells used) placements.
    for count in [10, 600] {
        let spheres = shower(count, 9).spheres().unwrap();
        assert_eq!(spheres.len(), count as usize);
        no_overlap(&spheres);
        for s in &spheres {
            assert!((-1.0 + 0.05..=1.0 - 0.05).contains(&s.position[0]));
            assert!((2.0 + 0.05..=4.0 - 0.05).contains(&s.position[1]));
            assert_eq!(s.velocity, [0.0, -1.0, 0.0]);
            assert_eq!((s.density, s.restitution, s.fixed), (2.0, Some(0.5), false));
        }
    }
}

#[test]
fn gas_moves_at_its_speed_inside_six_walls() {
    let spheres = gas(300, true).spheres().unwrap();
    assert_eq!(spheres.len(), 306);
    let (molecules, walls) = spheres.split_at(300);
    assert_eq!(walls.len(), 6);
    no_overlap(molecules);
    // Walls overlap one another at the box's edges (fixed, so harmless), never a molecule.
    for wall in walls {
        let mut with_wall = molecules.to_vec();
        with_wall.push(wall.clone());
        no_overlap(&with_wall);
    }
    for m in molecules {
        let speed = m.velocity.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!((speed - 1.5).abs() < 1e-12, "speed {speed}");
    }
    // Each wall's surface passes through the middle of its face.
    let faces = [
        [0.0, 1.0, 1.0],
        [4.0, 1.0, 1.0],
        [2.0, 0.0, 1.0],
        [2.0, 2.0, 1.0],
        [2.0, 1.0, 0.0],
        [2.0, 1.0, 2.0],
    ];
    for (wall, face) in walls.iter().zip(faces) {
        assert!(wall.fixed);
        let d: f64 = (0..3)
            .map(|k| (wall.position[k] - face[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!((d - wall.radius).abs() < 1e-9, "{wall:?}");
    }
    assert_eq!(gas(300, false).spheres().unwrap().len(), 300);
}

#[test]
fn too_many_spheres_is_an_error_naming_the_generator() {
    let scene = SceneDesc::from_ron(
        r#"(name: "g", generate: [
            Shower(count: 5, seed: 1, min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0), radius: 0.1),
            Gas(count: 100000, seed: 1, min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0), radius: 0.1, speed: 1.0),
        ])"#,
    )
    .unwrap();
    match scene.build() {
        Err(SceneError::Generate(e)) => {
            assert_eq!((e.index, e.kind, e.field), (1, "Gas", "count"));
        }
        other => panic!("expected a generator error, got {other:?}"),
    }
}

#[test]
fn bad_generator_fields_are_errors() {
    let bad = [
        Generator::Shower {
            count: 1,
            seed: 0,
            min: [0.0; 3],
            max: [1.0, 1.0, f64::NAN],
            radius: 0.1,
            velocity: [0.0; 3],
            density: 1.0,
            restitution: None,
        },
        Generator::Shower {
            count: 1,
            seed: 0,
            min: [0.0; 3],
            max: [1.0; 3],
            radius: -0.1,
            velocity: [0.0; 3],
            density: 1.0,
            restitution: None,
        },
        Generator::Shower {
            count: 1,
            seed: 0,
            min: [0.0; 3],
            max: [1.0, -1.0, 1.0],
            radius: 0.1,
            velocity: [0.0; 3],
            density: 1.0,
            restitution: None,
        },
    ];
    let fields: Vec<_> = bad.iter().map(|g| g.spheres().unwrap_err().field).collect();
    assert_eq!(fields, ["max", "radius", "max"]);
}

#[test]
fn generated_scene_round_trips_through_ron() {
    let scene = SceneDesc::from_ron(
        r#"(name: "g", spheres: [(position: (0.0, 0.0, 0.0), radius: 3.0, fixed: true)], generate: [
            Shower(count: 50, seed: 1, min: (-1.0, 4.0, -1.0), max: (1.0, 5.0, 1.0), radius: 0.1),
        ])"#,
    )
    .unwrap();
    assert_eq!(SceneDesc::from_ron(&scene.to_ron()).unwrap(), scene);
    let world = scene.build().unwrap();
    assert_eq!(world.len(), 51);
}
