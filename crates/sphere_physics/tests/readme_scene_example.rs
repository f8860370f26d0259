//! Regression: the README's example scene file started hundreds of its spheres inside others
//! (its gas's walls filled the space beyond the gas's box, where the shower and the floor
//! were). The example must parse, build, and start with no two spheres overlapping. Found by
//! review.

use sphere_physics::SceneDesc;

/// The indented RON block under the README's "Scene files (RON)" heading.
fn readme_example() -> String {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md"))
        .expect("the README is readable");
    let section = readme
        .split("## Scene files (RON)")
        .nth(1)
        .expect("the README has a scene files section");
    section
        .lines()
        .skip_while(|l| *l != "    (")
        .take_while(|l| l.starts_with("    ") || l.is_empty())
        .map(|l| format!("{}\n", l.trim_start()))
        .collect()
}

#[test]
fn the_readme_scene_example_builds_with_no_sphere_inside_another() {
    let text = readme_example();
    assert!(text.contains("generate"), "{text}");
    let scene = SceneDesc::from_ron(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let mut world = scene.build().unwrap();
    assert_eq!(world.len() as u64, scene.len());
    assert_eq!(world.max_overlap(), 0.0);
    // And it runs: the ball and the rain land.
    for _ in 0..120 {
        world.step(1.0 / 60.0).unwrap();
    }
    assert!(world.max_overlap() < 1e-3);
}
