//! Adding sphere physics to a Bevy game: the plugin, spheres spawned in one line, a game system
//! ordered before the physics, collision messages, an observer on one sphere, and diagnostics.
//!
//! Headless (no window): it plays 3 simulated seconds and prints what happens. In a windowed
//! game, use `DefaultPlugins` instead of `MinimalPlugins` and give the spheres meshes.
//!
//!     cargo run --example add_to_your_game
use bevy::prelude::*;
use bevy_sphere_physics::prelude::*;

fn main() {
    App::new()
        .add_plugins((
            MinimalPlugins,
            SpherePhysicsPlugin::default().gravity(DVec3::NEG_Y * 9.81),
        ))
        .add_systems(Startup, spawn)
        // Game logic that feeds the physics runs before it, in the same fixed step.
        .add_systems(FixedUpdate, thrust.before(SpherePhysicsSystems::Prepare))
        .add_systems(FixedUpdate, report.after(SpherePhysicsSystems::Notify))
        .run();
}

#[derive(Component)]
struct Player;

fn spawn(mut commands: Commands) {
    // A fixed floor and a ball: one line each.
    commands.spawn((
        SphereBody::new(50.0),
        Transform::from_xyz(0.0, -50.0, 0.0),
        FixedSphere,
    ));
    commands
        .spawn((
            SphereBody::new(0.5),
            Transform::from_xyz(0.0, 3.0, 0.0),
            Restitution(0.6),
            Player,
        ))
        .observe(|hit: On<SphereHit>| {
            if !hit.resting {
                println!("the player hit {} at t = {:.3} s", hit.other, hit.time);
            }
        });
}

/// A rocket that fires for the first half second.
fn thrust(time: Res<Time>, mut player: Single<&mut AppliedForce, With<Player>>) {
    player.0 = if time.elapsed_secs() < 0.5 {
        DVec3::X * 2.0
    } else {
        DVec3::ZERO
    };
}

fn report(
    mut collisions: MessageReader<SphereCollision>,
    diagnostics: Res<SpherePhysicsDiagnostics>,
    player: Single<&SpherePosition, With<Player>>,
    mut exit: MessageWriter<AppExit>,
) {
    for c in collisions.read().filter(|c| !c.resting) {
        println!("collision: impulse {:.3} N·s", c.impulse);
    }
    if diagnostics.time >= 3.0 {
        println!(
            "after {} steps the player is at {:.3}",
            diagnostics.steps, player.0
        );
        exit.write(AppExit::Success);
    }
}
