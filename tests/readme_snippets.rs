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
    // Free fall for about half a second: some 1.2 m (the first frames run no fixed step).
    assert!((0.5..1.5).contains(&(2.0 - y)), "the ball fell: y = {y}");
}

#[cfg(feature = "render")]
#[test]
fn the_lab_scene_snippet_adds_a_scene_with_two_marbles() {
    use sphere_lab::*;
    let mut app = App::new();
    app.add_plugins(MinimalPlugins);
    app.add_plugins(LabPlugin {
        scene_folder: None,
        start: Some("marbles".into()),
        ..default()
    })
    .add_lab_scene(
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
