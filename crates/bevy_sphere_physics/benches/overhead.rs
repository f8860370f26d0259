//! The plugin's cost over the core alone: the same 10 000-sphere gas stepped by a bare
//! `sphere_physics::World` and through `SpherePhysicsPlugin` in a headless app (one fixed step
//! per update), in alternating rounds of 10 steps so both see the same machine, and with
//! `--features avian` the same scene in avian3d 0.7, in one run.
//!
//!     cargo bench -p bevy_sphere_physics [--features avian] [-- SPHERES STEPS]
#[cfg(feature = "avian")]
mod avian_peer;

use std::time::{Duration, Instant};

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_sphere_physics::prelude::*;
use bevy_sphere_physics::sphere_physics::{SceneDesc, SphereDesc, World};

const DT: Duration = Duration::from_nanos(15_625_000);

fn gas(n: u32) -> SceneDesc {
    let side = 0.11 * (4.0 * f64::from(n)).cbrt().ceil();
    let (lo, hi) = (-side / 2.0, side / 2.0);
    SceneDesc::from_ron(&format!(
        "(name: \"gas\", generate: [Gas(count: {n}, seed: 1, min: ({lo:?}, {lo:?}, {lo:?}),
          max: ({hi:?}, {hi:?}, {hi:?}), radius: 0.05, speed: 1.0)])"
    ))
    .expect("valid scene")
}

fn core_world(descs: &[SphereDesc]) -> World {
    let mut world = World::new(Default::default());
    for d in descs {
        world.add_sphere(d.clone()).expect("valid");
    }
    world
}

fn plugin_app(descs: &[SphereDesc]) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, SpherePhysicsPlugin::default()))
        .insert_resource(Time::<Fixed>::from_duration(DT))
        .insert_resource(TimeUpdateStrategy::ManualDuration(DT));
    for d in descs {
        let mut e = app.world_mut().spawn((
            SphereBody::new(d.radius),
            SpherePosition(d.position),
            SphereVelocity(d.velocity),
            Density(d.density),
            Restitution(d.restitution),
        ));
        if d.fixed {
            e.insert(FixedSphere);
        }
    }
    app
}

fn steps_taken(app: &App) -> u64 {
    app.world().resource::<SpherePhysicsDiagnostics>().steps
}

/// Steps the core and the plugin in alternating rounds of 10 steps (both simulate the same
/// scene, so they do the same physics), and returns their total times.
fn core_and_plugin(descs: &[SphereDesc], steps: u32) -> (f64, f64) {
    let (mut world, mut app) = (core_world(descs), plugin_app(descs));
    while steps_taken(&app) < 10 {
        app.update();
    }
    for _ in 0..10 {
        world.step(DT.as_secs_f64()).expect("valid dt");
    }
    let (mut core, mut plugin) = (0.0, 0.0);
    for _ in 0..steps.div_ceil(10) {
        let started = Instant::now();
        for _ in 0..10 {
            world.step(DT.as_secs_f64()).expect("valid dt");
        }
        core += started.elapsed().as_secs_f64();
        let target = steps_taken(&app) + 10;
        let started = Instant::now();
        while steps_taken(&app) < target {
            app.update();
        }
        plugin += started.elapsed().as_secs_f64();
    }
    (core, plugin)
}

fn main() {
    let args: Vec<u32> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let (n, steps) = (
        args.first().copied().unwrap_or(10_000),
        args.get(1).copied().unwrap_or(100),
    );
    let descs = gas(n).sphere_descs().expect("valid scene");
    let steps = steps.div_ceil(10) * 10;
    let per = |seconds: f64| seconds * 1e9 / (descs.len() as f64 * f64::from(steps));
    let (ours, through) = core_and_plugin(&descs, steps);
    println!(
        "{} spheres (gas), {steps} steps of 1/64 s, single-threaded physics:\n",
        descs.len()
    );
    println!("| engine | ns per sphere per step | vs core |");
    println!("|---|---|---|");
    println!("| sphere_physics core | {:.0} | 1.00 |", per(ours));
    println!(
        "| SpherePhysicsPlugin | {:.0} | {:.2} |",
        per(through),
        through / ours
    );
    #[cfg(feature = "avian")]
    {
        let spheres: Vec<avian_peer::Sphere> = descs
            .iter()
            .map(|d| avian_peer::Sphere {
                position: d.position.to_array(),
                velocity: d.velocity.to_array(),
                radius: d.radius,
                density: d.density,
                restitution: d.restitution,
                fixed: d.fixed,
            })
            .collect();
        let mut app = avian_peer::build_app(&spheres, [0.0; 3], DT, 6);
        for _ in 0..10 {
            app.update();
        }
        let before = avian_peer::kinetic_energy(&mut app);
        let started = Instant::now();
        for _ in 0..steps {
            app.update();
        }
        let avian = started.elapsed().as_secs_f64();
        let after = avian_peer::kinetic_energy(&mut app);
        println!(
            "| avian3d 0.7 (f64) | {:.0} | {:.2} |",
            per(avian),
            avian / ours
        );
        println!("\navian kinetic energy after/before: {:.4}", after / before);
    }
}
