//! The README's code snippets for a game, as written there (with the `use` lines it gives), so
//! that they keep compiling and running against the public API.

use bevy::prelude::*;
use bevy_sphere_physics::prelude::*;

#[test]
fn the_plugin_snippet_runs_and_the_ball_falls() {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        SpherePhysicsPlugin::default().gravity(DVec3::NEG_Y * 9.81),
    ))
    .add_systems(Startup, |mut commands: Commands| {
        commands.spawn((SphereBody::new(0.5), Transform::from_xyz(0.0, 2.0, 0.0)));
    });
    // Half a second in frames of 1/60 s (the test drives the clock).
    app.insert_resource(bevy::time::TimeUpdateStrategy::ManualDuration(
        std::time::Duration::from_secs_f64(1.0 / 60.0),
    ));
    for _ in 0..30 {
        app.update();
    }
    let y = app
        .world_mut()
        .query_filtered::<&Transform, With<SphereBody>>()
        .single(app.world())
        .expect("one ball")
        .translation
        .y;
    // Free fall for about half a second (the first frames run no fixed step): n steps of h
    // by semi-implicit Euler from rest take the ball down g·h²·n(n+1)/2, to rounding.
    let diagnostics = app.world().resource::<SpherePhysicsDiagnostics>();
    let (n, h) = (
        diagnostics.steps as f64,
        diagnostics.time / diagnostics.steps as f64,
    );
    assert!(n >= 20.0, "{n} steps in half a second");
    let fallen = |n: f64| 9.81 * h * h * n * (n + 1.0) / 2.0;
    let physics = app.world().resource::<SpherePhysicsWorld>();
    let exact = physics.world.bodies()[0].position().y;
    assert!(
        (exact - (2.0 - fallen(n))).abs() < 1e-9,
        "the ball at {exact} after {n} steps of {h} s, not {}",
        2.0 - fallen(n)
    );
    // What is drawn lies between the last two steps' positions (interpolated), in f32.
    let (low, high) = (2.0 - fallen(n), 2.0 - fallen(n - 1.0));
    assert!(
        (low - 1e-5..=high + 1e-5).contains(&f64::from(y)),
        "drawn at {y}, between {low} and {high}"
    );
}

#[cfg(feature = "render")]
#[test]
fn the_lab_scene_snippet_adds_a_scene_with_two_marbles() {
    use sphere_lab::*;
    let mut app = App::new();
    app.add_plugins(MinimalPlugins);
    // As the README has it (until the fifty-seventh session this test started the lab on the
    // marbles, without the scene files `LabPlugin::default()` lists beside them).
    app.add_plugins(LabPlugin::default()).add_lab_scene(
        LabScene::new("marbles", "Marbles", "Two marbles on a collision course."),
        |mut commands: Commands| {
            for (x, v) in [(-1.0, 1.0), (1.0, -1.0)] {
                commands.spawn((
                    SphereBody::new(0.1),
                    Transform::from_xyz(x, 0.0, 0.0),
                    SphereVelocity(DVec3::X * v),
                ));
            }
        },
    );
    app.update();
    let scenes = app.world().resource::<LabScenes>();
    assert!(scenes.get("newtons_cradle").is_some() && scenes.errors.is_empty());
    app.world_mut()
        .write_message(LabAction::Load("marbles".into()));
    for _ in 0..3 {
        app.update();
    }
    let marbles = app
        .world_mut()
        .query_filtered::<(), With<SphereBody>>()
        .iter(app.world())
        .count();
    assert_eq!(marbles, 2);
}

/// The tests above hold copies of the README's snippets: each of the copies' lines that carry
/// the API is still in the README (found by review: a snippet changed there would have left
/// its copy here passing).
#[test]
fn the_snippets_tested_are_the_readmes() {
    let readme = include_str!("../README.md");
    for line in [
        "SpherePhysicsPlugin::default().gravity(DVec3::NEG_Y * 9.81)",
        ".add_systems(Startup, |mut commands: Commands| {",
        "commands.spawn((SphereBody::new(0.5), Transform::from_xyz(0.0, 2.0, 0.0)));",
        "app.add_plugins(LabPlugin::default())",
        ".add_lab_scene(",
        "LabScene::new(\"marbles\", \"Marbles\", \"Two marbles on a collision course.\"),",
        "|mut commands: Commands| {",
        "for (x, v) in [(-1.0, 1.0), (1.0, -1.0)] {",
        "SphereBody::new(0.1),",
        "Transform::from_xyz(x, 0.0, 0.0),",
        "SphereVelocity(DVec3::X * v),",
        "use bevy::prelude::*; use bevy_sphere_physics::prelude::*;",
    ] {
        assert!(readme.contains(line), "the README no longer has `{line}`");
    }
}
