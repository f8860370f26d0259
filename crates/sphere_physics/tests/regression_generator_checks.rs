//! Regression: a generator's bad density or restitution was reported against a sphere's index
//! (`sphere #6: density ...`), naming neither the generator nor its field; and a generator's
//! box far from the origin put neighbouring spheres on the same rounded coordinates (at 1e16 m
//! the f64 spacing is 2 m), so spheres were made inside one another. Found by review.

use sphere_physics::generate::Generator;
use sphere_physics::{SceneDesc, SceneError};

fn generator_error(ron: &str) -> (usize, &'static str, &'static str) {
    match SceneDesc::from_ron(ron).unwrap().build() {
        Err(SceneError::Generate(e)) => (e.index, e.kind, e.field),
        other => panic!("expected a generator error, got {other:?}"),
    }
}

#[test]
fn regression_a_generators_bad_density_or_restitution_names_the_generator() {
    let floor =
        r#"spheres: [(name: "floor", position: (0.0, 0.0, 0.0), radius: 1.0, fixed: true)]"#;
    let first =
        "Shower(count: 5, seed: 1, min: (-1.0, 2.0, -1.0), max: (1.0, 3.0, 1.0), radius: 0.1)";
    for (second, expected) in [
        (
            "Shower(count: 5, seed: 1, min: (-1.0, 4.0, -1.0), max: (1.0, 5.0, 1.0), radius: 0.1, density: -1.0)",
            (1, "Shower", "density"),
        ),
        (
            "Gas(count: 5, seed: 1, min: (-1.0, 4.0, -1.0), max: (1.0, 5.0, 1.0), radius: 0.1, speed: 1.0, restitution: Some(2.0))",
            (1, "Gas", "restitution"),
        ),
        (
            // A mass that overflows.
            "Gas(count: 5, seed: 1, min: (-1.0, 4.0, -1.0), max: (1.0, 5.0, 1.0), radius: 0.1, speed: 1.0, density: 1e308)",
            (1, "Gas", "density"),
        ),
    ] {
        let ron = format!(r#"(name: "g", {floor}, generate: [{first}, {second}])"#);
        assert_eq!(generator_error(&ron), expected, "{second}");
    }
}

#[test]
fn regression_a_generator_box_too_far_from_the_origin_is_refused() {
    // Three spheres of radius 0.5 in a row along x, from `x` on.
    let row_at = |x: f64| Generator::Shower {
        count: 3,
        seed: 1,
        min: [x, 0.0, 0.0],
        max: [x + 4.0, 1.1, 1.1],
        radius: 0.5,
        velocity: [0.0; 3],
        density: 1.0,
        restitution: None,
    };
    let error = row_at(1e16).spheres().unwrap_err();
    assert_eq!((error.kind, error.field), ("Shower", "max"), "{error}");
    assert!(error.reason.contains("too far from the origin"), "{error}");
    // A box as far out as a millionth of the radius allows still generates, apart.
    let spheres = row_at(1e9).spheres().unwrap();
    for (i, a) in spheres.iter().enumerate() {
        for b in &spheres[i + 1..] {
            let d: f64 = (0..3)
                .map(|k| (a.position[k] - b.position[k]).powi(2))
                .sum();
            assert!(d.sqrt() >= 1.0 - 1e-6, "{a:?} {b:?}");
        }
    }
}

/// Regression: a generator's `count` was checked only against its box's capacity, so four
/// billion spheres in a box large enough were generated until the process ran out of memory
/// and aborted (a scene file could kill the lab at startup). Found by review.
#[test]
fn regression_a_huge_count_is_an_error_not_an_abort() {
    let over = sphere_physics::generate::MAX_GENERATED + 1;
    let huge = |count: u32, y: f64| {
        format!(
            "Shower(count: {count}, seed: 1, min: (-1000.0, {y:?}, -1000.0), \
             max: (1000.0, {:?}, 1000.0), radius: 0.1)",
            y + 2000.0
        )
    };
    let scene =
        |generators: &[String]| format!("(name: \"huge\", generate: [{}])", generators.join(", "));
    assert_eq!(
        generator_error(&scene(&[huge(4_000_000_000, 0.0)])),
        (0, "Shower", "count")
    );
    assert_eq!(
        generator_error(&scene(&[huge(over, 0.0)])),
        (0, "Shower", "count")
    );
    // Each within the limit, together over it: the second is named, before either is made.
    let half = sphere_physics::generate::MAX_GENERATED / 2 + 1;
    assert_eq!(
        generator_error(&scene(&[huge(half, 0.0), huge(half, 3000.0)])),
        (1, "Shower", "count")
    );
    // The generator alone says so too.
    let alone = SceneDesc::from_ron(&scene(&[huge(over, 0.0)])).unwrap();
    let error = alone.generate[0].spheres().unwrap_err();
    assert_eq!(error.field, "count", "{error}");
    // The scene still says how many spheres it asks for, without making them.
    assert_eq!(alone.len(), u64::from(over));
    assert_eq!(alone.to_string(), format!("huge ({over} spheres)"));
    // A gas's six walls count too: alone, one of the largest count asked for 10 000 006
    // spheres, and got them (found by review in the fifty-seventh session).
    let gas = SceneDesc::from_ron(&format!(
        "(name: \"gas\", generate: [Gas(count: {}, seed: 1, min: (-300.0, -300.0, -300.0),
                                          max: (300.0, 300.0, 300.0), radius: 0.1, speed: 1.0)])",
        sphere_physics::generate::MAX_GENERATED
    ))
    .unwrap();
    // (Not `unwrap_err()`, whose panic would print ten million spheres.)
    let Err(error) = gas.generate[0].spheres() else {
        panic!("ten million and six spheres made");
    };
    assert_eq!(error.field, "count", "{error}");
    assert!(error.to_string().contains("10000006"), "{error}");
}

/// Regression: a scene's `Display` counted only its listed spheres ("Gas in a box (0
/// spheres)" for 1000 generated ones and six walls). Found by review.
#[test]
fn regression_a_scene_counts_its_generated_spheres() {
    let scene = SceneDesc::from_ron(
        "(name: \"gas\", spheres: [(position: (9.0, 0.0, 0.0), radius: 1.0)],
          generate: [Gas(count: 20, seed: 1, min: (-1.0, -1.0, -1.0), max: (1.0, 1.0, 1.0),
                         radius: 0.1, speed: 1.0)])",
    )
    .unwrap();
    assert_eq!(scene.to_string(), "gas (27 spheres)");
    assert_eq!(scene.len(), 27);
    assert_eq!(scene.all_spheres().unwrap().len(), 27);
}

/// Regression: a gas's `wall_radius` past the largest radius a sphere may have (1e150 m)
/// passed the generator's checks, and the scene was then refused naming a sphere that is not
/// in the file (`sphere 'wall xmin' (#1): radius must be at most 1e150 ...`). Found by review
/// in the sixty-fourth session.
#[test]
fn regression_a_gas_wall_radius_past_the_largest_radius_names_the_generator() {
    let ron = "(name: \"huge walls\", generate: [
        Gas(count: 1, seed: 1, min: (-5e142, -5e142, -5e142), max: (5e142, 5e142, 5e142),
            radius: 1e142, speed: 0.0, density: 1e-250, wall_radius: 1e151)])";
    assert_eq!(generator_error(ron), (0, "Gas", "wall_radius"));
}
