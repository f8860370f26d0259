//! Headless Bevy apps with time advanced by hand: the plugin's order, its agreement with the
//! core, its messages and observers, interpolation, and what game systems may do.

use std::time::Duration;

use bevy::app::{RunFixedMainLoop, RunFixedMainLoopSystems};
use bevy::ecs::schedule::{LogLevel, ScheduleBuildSettings};
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_sphere_physics::prelude::*;
use bevy_sphere_physics::sphere_physics::{self, Field, SphereDesc};
use bevy_sphere_physics::{ResetSpherePhysics, SpherePhysicsWorld, SphereRejected};

/// 1/64 s: exact in nanoseconds and in binary, so fixed steps and frames line up exactly.
const STEP: Duration = Duration::from_nanos(15_625_000);

fn app(plugin: SpherePhysicsPlugin) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, plugin))
        .insert_resource(Time::<Fixed>::from_duration(STEP))
        .insert_resource(TimeUpdateStrategy::ManualDuration(STEP));
    let strict = |s: &mut Schedule| {
        s.set_build_settings(ScheduleBuildSettings {
            ambiguity_detection: LogLevel::Error,
            ..default()
        });
    };
    app.edit_schedule(FixedUpdate, strict);
    app.edit_schedule(RunFixedMainLoop, strict);
    app
}

/// Updates until the physics has taken `steps` more steps.
fn run_steps(app: &mut App, steps: u64) {
    let target = app.world().resource::<SpherePhysicsDiagnostics>().steps + steps;
    for _ in 0..10 * steps + 10 {
        if app.world().resource::<SpherePhysicsDiagnostics>().steps >= target {
            return;
        }
        app.update();
    }
    panic!("the physics did not step");
}

fn position(app: &App, entity: Entity) -> DVec3 {
    app.world().get::<SpherePosition>(entity).unwrap().0
}

fn velocity(app: &App, entity: Entity) -> DVec3 {
    app.world().get::<SphereVelocity>(entity).unwrap().0
}

#[derive(Resource, Default)]
struct Order(Vec<&'static str>);

#[test]
fn sets_run_in_the_documented_order_without_ambiguities() {
    let mut app = app(SpherePhysicsPlugin::default());
    app.init_resource::<Order>();
    for (name, set) in [
        ("prepare", SpherePhysicsSystems::Prepare),
        ("step", SpherePhysicsSystems::Step),
        ("writeback", SpherePhysicsSystems::Writeback),
        ("notify", SpherePhysicsSystems::Notify),
    ] {
        app.add_systems(
            FixedUpdate,
            (move |mut order: ResMut<Order>| order.0.push(name)).in_set(set),
        );
    }
    app.world_mut()
        .spawn((SphereBody::new(0.5), Transform::default()));
    run_steps(&mut app, 1);
    assert_eq!(
        app.world().resource::<Order>().0[..4],
        ["prepare", "step", "writeback", "notify"]
    );
}

/// A game system that writes `Transform`s after the fixed steps (a camera following a sphere)
/// can be ordered after the plugin's interpolation, with no ambiguity, and sees this frame's
/// interpolated `Transform`s.
#[test]
fn a_game_system_orders_itself_after_the_interpolation() {
    #[derive(Resource, Default)]
    struct Followed(Vec<Vec3>);
    let mut app = app(SpherePhysicsPlugin::default());
    app.init_resource::<Followed>().add_systems(
        RunFixedMainLoop,
        (|mut spheres: Query<&mut Transform, With<SphereBody>>, mut followed: ResMut<Followed>| {
            for transform in &mut spheres {
                followed.0.push(transform.translation);
            }
        })
        .in_set(RunFixedMainLoopSystems::AfterFixedMainLoop)
        .after(SphereInterpolation),
    );
    let ball = app
        .world_mut()
        .spawn((SphereBody::new(0.5), SphereVelocity(DVec3::X)))
        .id();
    run_steps(&mut app, 3);
    let shown = app.world().get::<Transform>(ball).unwrap().translation;
    assert_eq!(app.world().resource::<Followed>().0.last(), Some(&shown));
    assert!(shown.x > 0.0, "{shown}");
}

/// Regression (found by review): after a game removed `SphereBody` from an entity it kept, the
/// plugin went on writing its `Transform` until the next fixed step, contrary to the docs.
#[test]
fn regression_a_removed_sphere_body_gives_the_transform_back_at_once() {
    let mut app = app(SpherePhysicsPlugin::default());
    let ball = app
        .world_mut()
        .spawn((SphereBody::new(0.5), SphereVelocity(DVec3::X)))
        .id();
    run_steps(&mut app, 2);
    app.world_mut().entity_mut(ball).remove::<SphereBody>();
    let mine = Vec3::new(-7.0, 1.0, 2.0);
    app.world_mut()
        .get_mut::<Transform>(ball)
        .unwrap()
        .translation = mine;
    // A frame with no fixed step (the fixed clock barely moves), then one with.
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_micros(
        10,
    )));
    app.update();
    assert_eq!(
        app.world().get::<Transform>(ball).unwrap().translation,
        mine
    );
    app.insert_resource(TimeUpdateStrategy::ManualDuration(STEP));
    app.update();
    app.update();
    assert_eq!(
        app.world().get::<Transform>(ball).unwrap().translation,
        mine
    );
}

/// A touching 5-ball cradle spawned as entities gives the core's answer, bit for bit.
#[test]
fn cradle_from_entities_matches_the_core_alone() {
    let descs: Vec<SphereDesc> = (0..5)
        .map(|i| {
            let v = if i == 0 { DVec3::X * 2.0 } else { DVec3::ZERO };
            SphereDesc::new(0.5)
                .at(DVec3::new(i as f64 - 2.0, 0.0, 0.0))
                .moving(v)
        })
        .collect();
    let mut core = sphere_physics::World::new(sphere_physics::Settings::default());
    for d in &descs {
        core.add_sphere(d.clone()).unwrap();
    }
    let mut app = app(SpherePhysicsPlugin::default());
    let entities: Vec<Entity> = descs
        .iter()
        .map(|d| {
            app.world_mut()
                .spawn((
                    SphereBody::new(d.radius),
                    SpherePosition(d.position),
                    SphereVelocity(d.velocity),
                ))
                .id()
        })
        .collect();
    run_steps(&mut app, 40);
    let dt = STEP.as_secs_f64();
    for _ in 0..40 {
        core.step(dt).unwrap();
    }
    for (entity, body) in entities.iter().zip(core.bodies()) {
        assert_eq!(position(&app, *entity), body.position());
        assert_eq!(velocity(&app, *entity), body.velocity());
    }
    // One ball out at 2, the others at rest.
    assert_eq!(velocity(&app, entities[4]), DVec3::X * 2.0);
    for e in &entities[..4] {
        assert_eq!(velocity(&app, *e), DVec3::ZERO);
    }
}

#[derive(Resource, Default)]
struct Seen {
    messages: Vec<SphereCollision>,
    hits: Vec<(Entity, Entity)>,
    global: Vec<(Entity, Entity)>,
}

#[test]
fn collision_messages_and_observers_fire_once_per_collision() {
    let mut app = app(SpherePhysicsPlugin::default());
    app.init_resource::<Seen>().add_systems(
        FixedUpdate,
        (|mut reader: MessageReader<SphereCollision>, mut seen: ResMut<Seen>| {
            seen.messages.extend(reader.read().copied());
        })
        .after(SpherePhysicsSystems::Notify),
    );
    let observe = |hit: On<SphereHit>, mut seen: ResMut<Seen>| {
        seen.hits.push((hit.entity, hit.other));
    };
    // A global observer, on no entity, sees the collision once for each sphere.
    app.add_observer(|hit: On<SphereHit>, mut seen: ResMut<Seen>| {
        seen.global.push((hit.entity, hit.other));
    });
    let a = app
        .world_mut()
        .spawn((
            SphereBody::new(0.5),
            SpherePosition(DVec3::new(-1.0, 0.0, 0.0)),
            SphereVelocity(DVec3::X),
        ))
        .observe(observe)
        .id();
    let b = app
        .world_mut()
        .spawn((
            SphereBody::new(0.5),
            SpherePosition(DVec3::new(1.0, 0.0, 0.0)),
            SphereVelocity(-DVec3::X),
        ))
        .observe(observe)
        .id();
    run_steps(&mut app, 128); // 2 s: one head-on collision at t = 0.5 s.
    let seen = app.world().resource::<Seen>();
    assert_eq!(seen.messages.len(), 1, "{:?}", seen.messages);
    let m = seen.messages[0];
    assert!((m.a, m.b) == (a, b) || (m.a, m.b) == (b, a));
    // The normal points from `a` to `b`.
    assert_eq!(m.normal.x.signum(), if m.a == a { 1.0 } else { -1.0 });
    assert!((m.time - 0.5).abs() < 1e-12, "at {}", m.time);
    assert!(m.impulse > 0.0 && !m.resting);
    let mut hits = seen.hits.clone();
    hits.sort();
    let mut expected = vec![(a, b), (b, a)];
    expected.sort();
    assert_eq!(hits, expected, "each sphere's observer once");
    let mut global = seen.global.clone();
    global.sort();
    assert_eq!(global, expected, "the global observer once for each sphere");
}

#[test]
fn transforms_are_interpolated_between_fixed_steps() {
    let mut app = app(SpherePhysicsPlugin::default());
    let moving = app
        .world_mut()
        .spawn((SphereBody::new(0.1), SphereVelocity(DVec3::X)))
        .id();
    let jumping = app
        .world_mut()
        .spawn((
            SphereBody::new(0.1),
            SpherePosition(DVec3::new(0.0, 5.0, 0.0)),
            SphereVelocity(DVec3::X),
            NoInterpolation,
        ))
        .id();
    run_steps(&mut app, 4);
    shown_between_its_last_two_positions(&mut app, moving);
    let jumped = app.world().get::<Transform>(jumping).unwrap().translation.x;
    assert_eq!(f64::from(jumped), position(&app, jumping).x as f32 as f64);
}

/// Regression (found by review): a game system writing a sphere's `SpherePosition` back
/// unchanged after `Writeback` (a clamp to an arena that held) turned its interpolation off:
/// the change was judged by its tick alone, as a teleport, and the sphere shown at the end of
/// the last step, jumping on every frame.
#[test]
fn regression_a_position_written_back_unchanged_is_still_interpolated() {
    let mut app = app(SpherePhysicsPlugin::default());
    app.add_systems(
        FixedUpdate,
        (|mut spheres: Query<&mut SpherePosition>| {
            for mut position in &mut spheres {
                position.0.y = position.0.y.max(-10.0);
            }
        })
        .after(SpherePhysicsSystems::Writeback),
    );
    let moving = app
        .world_mut()
        .spawn((SphereBody::new(0.1), SphereVelocity(DVec3::X)))
        .id();
    run_steps(&mut app, 4);
    shown_between_its_last_two_positions(&mut app, moving);
}

/// Runs a frame of 1.5 fixed steps (the fixed clock half a step into the next one), and
/// checks `moving` (along x) is shown between its last two physics positions, by the fixed
/// clock's overstep, short of the last.
fn shown_between_its_last_two_positions(app: &mut App, moving: Entity) {
    app.insert_resource(TimeUpdateStrategy::ManualDuration(STEP * 3 / 2));
    app.update();
    let fraction = app
        .world()
        .resource::<Time<Fixed>>()
        .overstep_fraction_f64();
    assert!(fraction > 0.0 && fraction < 1.0, "overstep {fraction}");
    let current = position(app, moving).x;
    let previous = app.world().get::<PreviousSpherePosition>(moving).unwrap().x;
    let shown = app.world().get::<Transform>(moving).unwrap().translation.x;
    let expected = previous + (current - previous) * fraction;
    assert!(
        (f64::from(shown) - expected).abs() < 1e-6,
        "{shown} vs {expected} (the step's end {current})"
    );
    assert!(f64::from(shown) < current);
}

/// Regression (found by review): a sphere beyond `f32`'s range (3.4e38 m; the core takes
/// positions to 1e308) was given an infinite translation, at its spawn and at every frame,
/// which turns its `GlobalTransform` to NaN. It is shown at the range's edge.
#[test]
fn regression_a_sphere_beyond_f32_range_has_a_finite_translation() {
    let mut app = app(SpherePhysicsPlugin::default());
    let far = ball(&mut app, DVec3::new(1e39, -1e300, 0.0), DVec3::X);
    let shown = |app: &App| app.world().get::<Transform>(far).unwrap().translation;
    assert_eq!(shown(&app), Vec3::new(f32::MAX, -f32::MAX, 0.0));
    run_steps(&mut app, 2);
    assert_eq!(position(&app, far).x, 1e39);
    assert_eq!(shown(&app), Vec3::new(f32::MAX, -f32::MAX, 0.0));
    // Within the range, as ever.
    let near = ball(&mut app, DVec3::new(1e38, 0.0, 0.0), DVec3::ZERO);
    run_steps(&mut app, 1);
    let at = app.world().get::<Transform>(near).unwrap().translation;
    assert_eq!(at, Vec3::new(1e38, 0.0, 0.0));
}

/// Regression (found by review): a sphere whose `SphereBody` was removed and inserted again
/// between two `Prepare`s (a game swapping its size, say) lost its `SpherePosition` for a
/// step: the removal's clean-up was queued after `Prepare` had registered it again. Its
/// velocity was not written back in that step, and the stale one was put back at the next:
/// a step of gravity lost. It is now a new sphere from its components, which it keeps.
#[test]
fn regression_a_sphere_body_removed_and_inserted_again_keeps_its_components() {
    let g = 9.81;
    let mut app = app(SpherePhysicsPlugin::default().gravity(DVec3::NEG_Y * g));
    let falling = ball(&mut app, DVec3::new(0.0, 10.0, 0.0), DVec3::ZERO);
    run_steps(&mut app, 2);
    let mut entity = app.world_mut().entity_mut(falling);
    entity.remove::<SphereBody>();
    entity.insert(SphereBody::new(0.25));
    run_steps(&mut app, 1);
    assert!(app.world().get::<SpherePosition>(falling).is_some());
    assert!(app.world().get::<SphereHandle>(falling).is_some());
    run_steps(&mut app, 1);
    // Four steps of semi-implicit Euler from rest: four kicks of g·h.
    let h = STEP.as_secs_f64();
    let v = velocity(&app, falling).y;
    assert!(
        (v + 4.0 * g * h).abs() < 1e-12,
        "{v} against {}",
        -4.0 * g * h
    );
    let physics = app.world().resource::<SpherePhysicsWorld>();
    assert_eq!(physics.world.len(), 1);
    assert_eq!(physics.world.bodies()[0].radius(), 0.25);
}

/// A sphere of radius 0.5 spawned at `at`, moving at `velocity`.
fn ball(app: &mut App, at: DVec3, velocity: DVec3) -> Entity {
    app.world_mut()
        .spawn((
            SphereBody::new(0.5),
            SpherePosition(at),
            SphereVelocity(velocity),
        ))
        .id()
}

/// Sphere `a` at x = -2 moving at 1 m/s towards `b`, at rest at x = 2: they meet at t = 3 s.
fn head_on_pair(app: &mut App) -> (Entity, Entity) {
    (
        ball(app, DVec3::new(-2.0, 0.0, 0.0), DVec3::X),
        ball(app, DVec3::new(2.0, 0.0, 0.0), DVec3::ZERO),
    )
}

#[test]
fn despawning_a_sphere_mid_simulation_removes_it() {
    let mut app = app(SpherePhysicsPlugin::default());
    let (a, b) = head_on_pair(&mut app);
    run_steps(&mut app, 10);
    app.world_mut().despawn(b);
    run_steps(&mut app, 300); // Long past when they would have met.
    assert_eq!(app.world().resource::<SpherePhysicsWorld>().world.len(), 1);
    assert_eq!(velocity(&app, a), DVec3::X, "nothing left to hit");
    assert_eq!(
        app.world()
            .resource::<SpherePhysicsDiagnostics>()
            .collisions,
        0
    );
}

/// The core's step profiling, reached through the world resource as the README says: each
/// step's phases, the collision's included.
#[test]
fn a_game_reads_the_core_step_profile() {
    let mut app = app(SpherePhysicsPlugin::default());
    head_on_pair(&mut app);
    let profile = |app: &App| {
        app.world()
            .resource::<SpherePhysicsWorld>()
            .world
            .profile()
            .copied()
    };
    run_steps(&mut app, 1);
    assert_eq!(profile(&app), None, "off by default");
    app.world_mut()
        .resource_mut::<SpherePhysicsWorld>()
        .world
        .set_profiling(true);
    let mut events = Duration::ZERO;
    // They meet after 3 s (192 steps of 1/64 s).
    for _ in 0..200 {
        run_steps(&mut app, 1);
        let p = profile(&app).expect("profiling is on");
        assert!(p.integrate > Duration::ZERO && p.total() >= p.integrate);
        events += p.events;
    }
    assert_eq!(
        app.world()
            .resource::<SpherePhysicsDiagnostics>()
            .collisions,
        1
    );
    assert!(events > Duration::ZERO);
}

#[derive(Resource, Default)]
struct Rejections(Vec<SphereRejected>);

/// Gathers every `SphereRejected` message into [`Rejections`].
fn collect_rejections(app: &mut App) {
    app.init_resource::<Rejections>().add_systems(
        FixedUpdate,
        (|mut reader: MessageReader<SphereRejected>, mut seen: ResMut<Rejections>| {
            seen.0.extend(reader.read().cloned());
        })
        .after(SpherePhysicsSystems::Prepare),
    );
}

/// Regression (found by review): a sphere without `SphereVelocity` whose change was invalid
/// was reported twice (its stored rejection took the core's velocity, the retry the default).
#[test]
fn regression_a_sphere_without_velocity_is_rejected_once() {
    let mut app = app(SpherePhysicsPlugin::default());
    collect_rejections(&mut app);
    let ball = app
        .world_mut()
        .spawn((SphereBody::new(0.5), SphereVelocity(DVec3::X)))
        .id();
    run_steps(&mut app, 2);
    app.world_mut().entity_mut(ball).remove::<SphereVelocity>();
    app.world_mut().get_mut::<SphereBody>(ball).unwrap().radius = -1.0;
    run_steps(&mut app, 4);
    let seen = &app.world().resource::<Rejections>().0;
    assert_eq!(seen.len(), 1, "{seen:?}");
    assert_eq!(seen[0].error.field, Field::Radius);
    // Fixed: it joins again, once.
    app.world_mut().get_mut::<SphereBody>(ball).unwrap().radius = 0.5;
    run_steps(&mut app, 1);
    assert!(app.world().get::<RejectedSphere>(ball).is_none());
    assert_eq!(app.world().resource::<Rejections>().0.len(), 1);
}

/// A game steering a sphere every step (its velocity and force set before `Prepare`) gets
/// exactly what the core alone gives with the same calls; a bad value among them is rejected
/// once, naming its field, and the sphere joins again when it is fixed.
#[test]
fn steering_every_step_matches_the_core_and_bad_values_are_rejected() {
    let mut app = app(SpherePhysicsPlugin::default());
    collect_rejections(&mut app);
    let ball = app
        .world_mut()
        .spawn((SphereBody::new(0.5), SpherePosition(DVec3::ZERO)))
        .id();
    let mut core = sphere_physics::World::new(sphere_physics::Settings::default());
    let id = core.add_sphere(SphereDesc::new(0.5)).unwrap();
    run_steps(&mut app, 1);
    core.step(STEP.as_secs_f64()).unwrap();
    for k in 1..=20 {
        let (v, f) = (DVec3::new(f64::from(k), 0.5, 0.0), DVec3::Y * f64::from(k));
        app.world_mut().get_mut::<SphereVelocity>(ball).unwrap().0 = v;
        app.world_mut().get_mut::<AppliedForce>(ball).unwrap().0 = f;
        core.set_velocity(id, v).unwrap();
        core.set_force(id, f).unwrap();
        run_steps(&mut app, 1);
        core.step(STEP.as_secs_f64()).unwrap();
        let body = core.body(id).unwrap();
        assert_eq!(position(&app, ball), body.position(), "step {k}");
        assert_eq!(velocity(&app, ball), body.velocity(), "step {k}");
    }
    app.world_mut().get_mut::<AppliedForce>(ball).unwrap().0 = DVec3::X * f64::INFINITY;
    run_steps(&mut app, 3);
    let seen = &app.world().resource::<Rejections>().0;
    assert_eq!(seen.len(), 1, "{seen:?}");
    assert_eq!(seen[0].error.field, Field::Force);
    assert!(
        app.world()
            .resource::<SpherePhysicsWorld>()
            .body(ball)
            .is_none()
    );
    app.world_mut().get_mut::<AppliedForce>(ball).unwrap().0 = DVec3::ZERO;
    run_steps(&mut app, 1);
    assert!(
        app.world()
            .resource::<SpherePhysicsWorld>()
            .body(ball)
            .is_some()
    );
}

#[test]
fn invalid_components_are_reported_and_left_out_until_fixed() {
    let mut app = app(SpherePhysicsPlugin::default());
    collect_rejections(&mut app);
    let bad = app
        .world_mut()
        .spawn((SphereBody::new(-1.0), Name::new("flat")))
        .id();
    let nan = app
        .world_mut()
        .spawn((
            SphereBody::new(0.5),
            SphereVelocity(DVec3::new(f64::NAN, 0.0, 0.0)),
        ))
        .id();
    run_steps(&mut app, 5);
    let seen = &app.world().resource::<Rejections>().0;
    assert_eq!(seen.len(), 2, "reported once each: {seen:?}");
    let flat = seen.iter().find(|r| r.entity == bad).unwrap();
    assert_eq!(flat.error.field, Field::Radius);
    assert!(flat.error.to_string().contains("flat"), "{}", flat.error);
    assert_eq!(
        seen.iter().find(|r| r.entity == nan).unwrap().error.field,
        Field::Velocity
    );
    assert!(app.world().get::<RejectedSphere>(bad).is_some());
    assert_eq!(app.world().resource::<SpherePhysicsWorld>().world.len(), 0);
    // Fixed: it joins.
    app.world_mut().get_mut::<SphereBody>(bad).unwrap().radius = 0.5;
    run_steps(&mut app, 1);
    assert!(app.world().get::<RejectedSphere>(bad).is_none());
    assert_eq!(app.world().resource::<SpherePhysicsWorld>().world.len(), 1);
}

/// A rejected sphere is reported again when its components change to another bad value, and
/// not while they stay the same, NaN included (a NaN is the same value step after step), nor
/// when a component is written with the very same value.
#[test]
fn a_rejected_sphere_is_reported_again_only_when_it_changes() {
    let mut app = app(SpherePhysicsPlugin::default());
    collect_rejections(&mut app);
    let ball = app
        .world_mut()
        .spawn((
            SphereBody::new(0.5),
            SphereVelocity(DVec3::new(f64::NAN, 0.0, 0.0)),
        ))
        .id();
    run_steps(&mut app, 3);
    assert_eq!(app.world().resource::<Rejections>().0.len(), 1);
    // Written again, the same NaN (change detection fires; the description is the same).
    app.world_mut().get_mut::<SphereVelocity>(ball).unwrap().0 = DVec3::new(f64::NAN, 0.0, 0.0);
    run_steps(&mut app, 3);
    assert_eq!(app.world().resource::<Rejections>().0.len(), 1);
    // Another bad value: reported again, once.
    app.world_mut().get_mut::<SphereBody>(ball).unwrap().radius = -1.0;
    run_steps(&mut app, 3);
    let seen = &app.world().resource::<Rejections>().0;
    assert_eq!(seen.len(), 2, "{seen:?}");
    assert_eq!(seen[1].entity, ball);
    // -0.5 and then 0.5 in the velocity's y with the radius still bad: each a new sphere
    // description, each reported.
    app.world_mut().get_mut::<SphereVelocity>(ball).unwrap().0 = DVec3::new(f64::NAN, -0.5, 0.0);
    run_steps(&mut app, 2);
    app.world_mut().get_mut::<SphereVelocity>(ball).unwrap().0 = DVec3::new(f64::NAN, 0.5, 0.0);
    run_steps(&mut app, 2);
    assert_eq!(app.world().resource::<Rejections>().0.len(), 4);
}

#[test]
fn game_systems_change_velocity_radius_and_position() {
    let mut app = app(SpherePhysicsPlugin::default());
    let ball = app
        .world_mut()
        .spawn((SphereBody::new(0.5), Transform::from_xyz(1.0, 2.0, 3.0)))
        .id();
    run_steps(&mut app, 1);
    assert_eq!(
        position(&app, ball),
        DVec3::new(1.0, 2.0, 3.0),
        "starts at its Transform"
    );
    app.world_mut().get_mut::<SphereVelocity>(ball).unwrap().0 = DVec3::new(0.0, 0.0, 64.0);
    run_steps(&mut app, 1);
    assert_eq!(position(&app, ball), DVec3::new(1.0, 2.0, 4.0));
    app.world_mut().get_mut::<SpherePosition>(ball).unwrap().0 = DVec3::ZERO;
    app.world_mut().get_mut::<SphereBody>(ball).unwrap().radius = 2.0;
    run_steps(&mut app, 1);
    let physics = app.world().resource::<SpherePhysicsWorld>();
    let body = physics.world.body(physics.body(ball).unwrap()).unwrap();
    assert_eq!(body.radius(), 2.0);
    assert_eq!(body.position(), DVec3::new(0.0, 0.0, 1.0));
}

#[test]
fn pause_and_single_step() {
    let mut app = app(SpherePhysicsPlugin::default());
    let ball = app
        .world_mut()
        .spawn((SphereBody::new(0.5), SphereVelocity(DVec3::X)))
        .id();
    run_steps(&mut app, 2);
    app.world_mut().resource_mut::<SpherePhysicsClock>().paused = true;
    let (steps, at) = (
        app.world().resource::<SpherePhysicsDiagnostics>().steps,
        position(&app, ball),
    );
    for _ in 0..10 {
        app.update();
    }
    assert_eq!(
        app.world().resource::<SpherePhysicsDiagnostics>().steps,
        steps
    );
    assert_eq!(position(&app, ball), at);
    let shown = app.world().get::<Transform>(ball).unwrap().translation;
    assert_eq!(shown, at.as_vec3(), "no drift while paused");
    app.world_mut()
        .resource_mut::<SpherePhysicsClock>()
        .step_once();
    for _ in 0..5 {
        app.update();
    }
    assert_eq!(
        app.world().resource::<SpherePhysicsDiagnostics>().steps,
        steps + 1
    );
}

#[test]
fn the_same_app_twice_is_bit_identical() {
    let run = || {
        let mut app = app(SpherePhysicsPlugin::default()
            .gravity(DVec3::NEG_Y * 9.81)
            .restitution(0.8));
        app.world_mut().spawn((
            SphereBody::new(5.0),
            SpherePosition(DVec3::new(0.0, -5.0, 0.0)),
            FixedSphere,
        ));
        let balls: Vec<Entity> = (0..60)
            .map(|i| {
                let p = DVec3::new(
                    (i % 6) as f64 * 0.3,
                    1.0 + (i / 6) as f64 * 0.3,
                    (i % 5) as f64 * 0.1,
                );
                app.world_mut()
                    .spawn((
                        SphereBody::new(0.1),
                        SpherePosition(p),
                        Density(1.0 + (i % 3) as f64),
                    ))
                    .id()
            })
            .collect();
        run_steps(&mut app, 120);
        balls
            .iter()
            .map(|&e| {
                let bits = |v: DVec3| v.to_array().map(f64::to_bits);
                (bits(position(&app, e)), bits(velocity(&app, e)))
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(run(), run());
}

/// Review finding: a sphere despawned on a frame without a fixed step (a fast display with a
/// slower fixed clock) must still leave the simulation.
#[test]
fn regression_despawn_between_fixed_steps_is_not_missed() {
    let mut app = app(SpherePhysicsPlugin::default());
    let keep = app
        .world_mut()
        .spawn((
            SphereBody::new(0.5),
            SpherePosition(DVec3::new(-5.0, 0.0, 0.0)),
        ))
        .id();
    let gone = app
        .world_mut()
        .spawn((
            SphereBody::new(0.5),
            SpherePosition(DVec3::new(5.0, 0.0, 0.0)),
        ))
        .id();
    run_steps(&mut app, 2);
    // Frames of a quarter step: three frames in four run no fixed step.
    app.insert_resource(TimeUpdateStrategy::ManualDuration(STEP / 4));
    app.update();
    app.world_mut().despawn(gone);
    for _ in 0..12 {
        app.update();
    }
    let physics = app.world().resource::<SpherePhysicsWorld>();
    assert_eq!(physics.world.len(), 1);
    assert!(physics.body(gone).is_none());
    assert!(physics.body(keep).is_some());
}

/// Review finding: a game that removes a body from the core directly does not make the plugin
/// panic; the sphere is registered again.
#[test]
fn regression_body_removed_from_the_core_is_registered_again() {
    let mut app = app(SpherePhysicsPlugin::default());
    let ball = app
        .world_mut()
        .spawn((SphereBody::new(0.5), SphereVelocity(DVec3::X)))
        .id();
    run_steps(&mut app, 2);
    let mut physics = app.world_mut().resource_mut::<SpherePhysicsWorld>();
    let id = physics.body(ball).unwrap();
    physics.world.remove_body(id);
    run_steps(&mut app, 2);
    let physics = app.world().resource::<SpherePhysicsWorld>();
    assert_eq!(physics.world.len(), 1);
    assert_ne!(physics.body(ball), Some(id));
}

#[test]
fn reset_restarts_time_and_settings_and_keeps_live_spheres() {
    let mut app = app(SpherePhysicsPlugin::default().gravity(DVec3::NEG_Y * 9.81));
    let doomed = app
        .world_mut()
        .spawn((SphereBody::new(0.5), Transform::from_xyz(-5.0, 0.0, 0.0)))
        .id();
    let kept = app
        .world_mut()
        .spawn((SphereBody::new(0.5), Transform::from_xyz(5.0, 0.0, 0.0)))
        .id();
    run_steps(&mut app, 8);
    assert!(app.world().resource::<SpherePhysicsWorld>().world.time() > 0.1);
    // A despawn whose removal is still queued must not reach the new world.
    app.world_mut().despawn(doomed);
    app.world_mut().commands().queue(
        ResetSpherePhysics::new(sphere_physics::Settings::with_gravity(DVec3::ZERO))
            .restitution(0.5),
    );
    app.world_mut().flush();
    let physics = app.world().resource::<SpherePhysicsWorld>();
    assert_eq!(physics.world.time(), 0.0);
    assert!(physics.world.is_empty());
    assert_eq!(app.world().resource::<SpherePhysicsDiagnostics>().steps, 0);
    // The live sphere joins the new world at its current place and velocity, under no gravity.
    let falling = velocity(&app, kept);
    let at = position(&app, kept);
    run_steps(&mut app, 4);
    let physics = app.world().resource::<SpherePhysicsWorld>();
    assert_eq!(physics.world.len(), 1);
    let body = physics.world.body(physics.body(kept).unwrap()).unwrap();
    assert_eq!(body.velocity(), falling);
    assert_eq!(body.restitution(), 0.5);
    assert!((body.position() - (at + falling * 4.0 / 64.0)).length() < 1e-12);
    assert_eq!(physics.world.time(), 4.0 / 64.0);
}

/// Regression (found by review): a reset (every scene switch of the lab) turned profiling off,
/// so a game that had turned it on read no profiles after its first scene.
#[test]
fn regression_reset_keeps_profiling_on() {
    let mut app = app(SpherePhysicsPlugin::default());
    app.world_mut()
        .resource_mut::<SpherePhysicsWorld>()
        .world
        .set_profiling(true);
    app.world_mut()
        .spawn((SphereBody::new(0.5), SphereVelocity(DVec3::X)));
    app.world_mut()
        .commands()
        .queue(ResetSpherePhysics::new(sphere_physics::Settings::default()));
    app.world_mut().flush();
    run_steps(&mut app, 2);
    let physics = app.world().resource::<SpherePhysicsWorld>();
    assert_eq!(physics.world.len(), 1);
    assert!(
        physics.world.profile().is_some(),
        "profiling was turned off"
    );
    // And off stays off.
    app.world_mut()
        .resource_mut::<SpherePhysicsWorld>()
        .world
        .set_profiling(false);
    app.world_mut()
        .commands()
        .queue(ResetSpherePhysics::new(sphere_physics::Settings::default()));
    app.world_mut().flush();
    run_steps(&mut app, 1);
    let physics = app.world().resource::<SpherePhysicsWorld>();
    assert!(physics.world.profile().is_none());
}

/// Regression (found by review): a sphere the game moved by writing its `SpherePosition`
/// between fixed steps was drawn sliding from its old place (interpolated between its last
/// physics position and the new one); it is shown where it was put at once.
#[test]
fn regression_a_teleport_is_shown_at_once() {
    let mut app = app(SpherePhysicsPlugin::default());
    let ball = app
        .world_mut()
        .spawn((SphereBody::new(0.5), SphereVelocity(DVec3::X)))
        .id();
    run_steps(&mut app, 4);
    let target = DVec3::new(10.0, 5.0, -3.0);
    app.world_mut().get_mut::<SpherePosition>(ball).unwrap().0 = target;
    // A frame with no fixed step.
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_micros(
        10,
    )));
    let steps = app.world().resource::<SpherePhysicsDiagnostics>().steps;
    app.update();
    assert_eq!(
        app.world().resource::<SpherePhysicsDiagnostics>().steps,
        steps
    );
    let shown = |app: &App| app.world().get::<Transform>(ball).unwrap().translation;
    assert_eq!(shown(&app), target.as_vec3());
    // And it moves on from there.
    app.insert_resource(TimeUpdateStrategy::ManualDuration(STEP));
    run_steps(&mut app, 2);
    assert_eq!(position(&app, ball), target + DVec3::X * 2.0 / 64.0);
}

/// The sphere a game system despawns at its next run, if any.
#[derive(Resource, Default)]
struct Doomed(Option<Entity>);

/// Whether the [`Doomed`] sphere is disabled (Bevy's `Disabled`) rather than despawned.
#[derive(Resource, Default)]
struct DisableInstead(bool);

/// An app whose game system despawns (or disables, see [`DisableInstead`]) the [`Doomed`]
/// sphere between the sets `after` and `before`, and gathers the collision messages into
/// [`Seen`].
fn app_despawning_between(after: SpherePhysicsSystems, before: SpherePhysicsSystems) -> App {
    let mut app = app(SpherePhysicsPlugin::default());
    app.init_resource::<Seen>()
        .init_resource::<Doomed>()
        .init_resource::<DisableInstead>()
        .add_systems(
            FixedUpdate,
            (
                (|mut commands: Commands,
                  mut doomed: ResMut<Doomed>,
                  disable: Res<DisableInstead>| {
                    if let Some(e) = doomed.0.take() {
                        if disable.0 {
                            commands
                                .entity(e)
                                .insert(bevy::ecs::entity_disabling::Disabled);
                        } else {
                            commands.entity(e).despawn();
                        }
                    }
                })
                .after(after)
                .before(before),
                (|mut reader: MessageReader<SphereCollision>, mut seen: ResMut<Seen>| {
                    seen.messages.extend(reader.read().copied());
                })
                .after(SpherePhysicsSystems::Notify),
            ),
        );
    app
}

/// Regression (found by review): collision messages and hits named spheres a game had
/// despawned after `Writeback` (or an observer of an earlier hit had despawned), so the
/// game's handlers met dead entities.
#[test]
fn regression_no_hits_for_despawned_spheres() {
    let head_on = |app: &mut App| {
        let a = app
            .world_mut()
            .spawn((
                SphereBody::new(0.5),
                SpherePosition(DVec3::new(-0.6, 0.0, 0.0)),
                SphereVelocity(DVec3::X * 10.0),
            ))
            .id();
        let b = app
            .world_mut()
            .spawn((
                SphereBody::new(0.5),
                SpherePosition(DVec3::new(0.6, 0.0, 0.0)),
                SphereVelocity(-DVec3::X * 10.0),
            ))
            .id();
        (a, b)
    };
    // A game system after `Writeback` despawns one of the pair.
    let mut app = app_despawning_between(
        SpherePhysicsSystems::Writeback,
        SpherePhysicsSystems::Notify,
    );
    app.add_observer(|hit: On<SphereHit>, mut seen: ResMut<Seen>| {
        seen.hits.push((hit.entity, hit.other));
    });
    let (a, _) = head_on(&mut app);
    app.world_mut().resource_mut::<Doomed>().0 = Some(a);
    run_steps(&mut app, 1);
    let seen = app.world().resource::<Seen>();
    assert!(app.world().get_entity(a).is_err());
    assert!(
        seen.messages.is_empty() && seen.hits.is_empty(),
        "{:?}",
        seen.hits
    );

    // Regression (found by a later review): an observer of the first hit despawns its
    // sphere (a bullet), and the second hit, on the other sphere (its target), was dropped
    // because it named the despawned one: whether a target heard of its hit depended on the
    // order the two were spawned in. Each sphere alive when its hit comes is told, in either
    // order.
    for bullet_first in [true, false] {
        let mut app = self::app(SpherePhysicsPlugin::default());
        app.init_resource::<Seen>();
        let (a, b) = head_on(&mut app);
        let (bullet, target) = if bullet_first { (a, b) } else { (b, a) };
        app.world_mut()
            .entity_mut(bullet)
            .observe(|hit: On<SphereHit>, mut commands: Commands| {
                commands.entity(hit.entity).despawn();
            });
        app.world_mut()
            .entity_mut(target)
            .observe(|hit: On<SphereHit>, mut seen: ResMut<Seen>| {
                seen.hits.push((hit.entity, hit.other));
            });
        run_steps(&mut app, 1);
        assert!(app.world().get_entity(bullet).is_err());
        let seen = app.world().resource::<Seen>();
        assert_eq!(
            seen.hits,
            [(target, bullet)],
            "bullet first: {bullet_first}"
        );
    }
    // A sphere despawned by an observer before its own hit comes is not told of it.
    let mut app = self::app(SpherePhysicsPlugin::default());
    app.init_resource::<Seen>()
        .add_observer(|hit: On<SphereHit>, mut seen: ResMut<Seen>| {
            seen.hits.push((hit.entity, hit.other));
        })
        .add_observer(|hit: On<SphereHit>, mut commands: Commands| {
            commands.entity(hit.other).despawn();
        });
    let (a, b) = head_on(&mut app);
    run_steps(&mut app, 1);
    let seen = app.world().resource::<Seen>();
    assert_eq!(seen.hits.len(), 1, "{:?}", seen.hits);
    assert!([(a, b), (b, a)].contains(&seen.hits[0]));
}

/// Regression (found by review): a sphere despawned by a game system between `Prepare` and
/// `Step` (an unordered "bullet lifetime" system may run there) still collided in that step:
/// its body was removed only at the next `Prepare`. The other sphere bounced off nothing, and
/// the collision went unreported (its sphere was gone).
#[test]
fn regression_a_sphere_despawned_after_prepare_is_out_of_that_step() {
    let mut app = app_despawning_between(SpherePhysicsSystems::Prepare, SpherePhysicsSystems::Step);
    // 1 m apart, closing at 20 m/s: they would meet early in the fourth step of 1/64 s.
    let a = ball(&mut app, DVec3::new(-1.0, 0.0, 0.0), DVec3::X * 10.0);
    let b = ball(&mut app, DVec3::new(1.0, 0.0, 0.0), -DVec3::X * 10.0);
    run_steps(&mut app, 3);
    assert_eq!(velocity(&app, b), -DVec3::X * 10.0, "nothing met yet");
    app.insert_resource(Doomed(Some(a)));
    run_steps(&mut app, 1);
    assert!(app.world().get_entity(a).is_err());
    assert_eq!(velocity(&app, b), -DVec3::X * 10.0, "b struck nothing");
    assert!(app.world().resource::<Seen>().messages.is_empty());
    assert_eq!(app.world().resource::<SpherePhysicsWorld>().world.len(), 1);
}

/// Regression (found by review): a sphere disabled by a game system between `Prepare` and
/// `Step` (a pool of bullets disabled rather than despawned) still collided in that step: its
/// body was taken out only at the next `Prepare`. The other sphere bounced off it, and the
/// collision went unreported (a disabled sphere is hidden from the plugin's queries).
#[test]
fn regression_a_sphere_disabled_after_prepare_is_out_of_that_step() {
    let mut app = app_despawning_between(SpherePhysicsSystems::Prepare, SpherePhysicsSystems::Step);
    app.insert_resource(DisableInstead(true));
    // As above: they would meet early in the fourth step.
    let a = ball(&mut app, DVec3::new(-1.0, 0.0, 0.0), DVec3::X * 10.0);
    let b = ball(&mut app, DVec3::new(1.0, 0.0, 0.0), -DVec3::X * 10.0);
    run_steps(&mut app, 3);
    assert_eq!(velocity(&app, b), -DVec3::X * 10.0, "nothing met yet");
    app.insert_resource(Doomed(Some(a)));
    run_steps(&mut app, 1);
    assert!(
        app.world()
            .get::<bevy::ecs::entity_disabling::Disabled>(a)
            .is_some()
    );
    assert_eq!(velocity(&app, b), -DVec3::X * 10.0, "b struck nothing");
    assert!(app.world().resource::<Seen>().messages.is_empty());
    assert_eq!(app.world().resource::<SpherePhysicsWorld>().world.len(), 1);
    // Where it was disabled, three steps in, moving as it was.
    let dt = STEP.as_secs_f64();
    assert_eq!(position(&app, a), DVec3::new(-1.0 + 30.0 * dt, 0.0, 0.0));
    assert_eq!(velocity(&app, a), DVec3::X * 10.0);
}

/// Regression (found by review): a position a game set after `Prepare`, in the step in which
/// a sphere placed by its `Transform` joined, was overwritten with the step's result: the
/// `SpherePosition` that `Prepare` puts on such a sphere (by a command, applied after it ran)
/// made every change to it in that step look like `Prepare`'s own.
#[test]
fn regression_a_position_set_late_is_kept_when_a_sphere_joins_by_its_transform() {
    let mut app = app(SpherePhysicsPlugin::default());
    let ball = app
        .world_mut()
        .spawn((
            SphereBody::new(0.5),
            Transform::from_xyz(1.0, 2.0, 3.0),
            SphereVelocity(DVec3::X),
        ))
        .id();
    let target = DVec3::new(0.0, 5.0, 0.0);
    move_late(&mut app, ball, target);
    run_steps(&mut app, 1);
    assert!(app.world().get::<SphereHandle>(ball).is_some());
    assert_eq!(position(&app, ball), target);
    run_steps(&mut app, 1);
    assert_eq!(position(&app, ball), target + DVec3::X * STEP.as_secs_f64());
}

/// Regression (found by review): a sphere refused because of the world's gravity stayed out
/// after the game mended its gravity (it was tried again only once its components changed),
/// and under a gravity that is not finite every sphere was refused, its force of 0 blamed.
/// The latter is the settings' fault: the sphere is taken and the steps refused, counted,
/// until the gravity is mended. The former is tried again once the gravity changes, and
/// reported again only if refused for another reason.
#[test]
fn regression_a_sphere_refused_under_gravity_joins_once_gravity_is_mended() {
    let mend = |app: &mut App, gravity: DVec3| {
        let mut physics = app.world_mut().resource_mut::<SpherePhysicsWorld>();
        physics.world.settings_mut().gravity = gravity;
    };
    // Gravity not finite.
    let mut first = app(SpherePhysicsPlugin::default().gravity(DVec3::X * f64::NAN));
    collect_rejections(&mut first);
    let falling = ball(&mut first, DVec3::Y * 10.0, DVec3::ZERO);
    for _ in 0..5 {
        first.update();
    }
    assert!(first.world().get::<RejectedSphere>(falling).is_none());
    assert!(first.world().resource::<Rejections>().0.is_empty());
    assert!(first.world().get::<SphereHandle>(falling).is_some());
    let diagnostics = first.world().resource::<SpherePhysicsDiagnostics>();
    assert!(diagnostics.refused_steps > 0);
    assert_eq!(diagnostics.steps, 0);
    mend(&mut first, DVec3::NEG_Y * 8.0);
    run_steps(&mut first, 1);
    assert_eq!(
        velocity(&first, falling),
        DVec3::NEG_Y * 8.0 * STEP.as_secs_f64()
    );

    // Finite, but past the range with a light sphere's force.
    let mut app = app(SpherePhysicsPlugin::default().gravity(DVec3::X * 1e308));
    collect_rejections(&mut app);
    // Refused whatever the gravity: not tried again when it changes, nor reported again.
    let bad = app.world_mut().spawn(SphereBody::new(-1.0)).id();
    // A sphere of 4.2e-10 kg pushed at 1e308 m/s².
    let spawn_light = |app: &mut App| {
        let density = 1e-10;
        let mass = density * 4.0 / 3.0 * std::f64::consts::PI;
        app.world_mut()
            .spawn((
                SphereBody::new(1.0),
                Density(density),
                AppliedForce(DVec3::X * 1e308 * mass),
                SpherePosition(DVec3::ZERO),
            ))
            .id()
    };
    let light = spawn_light(&mut app);
    run_steps(&mut app, 2);
    let refused = app.world().get::<RejectedSphere>(light).unwrap();
    assert_eq!(refused.error.field, Field::Force);
    assert_eq!(
        app.world().get::<RejectedSphere>(bad).unwrap().error.field,
        Field::Radius
    );
    assert_eq!(app.world().resource::<Rejections>().0.len(), 2);
    // A sphere joins (the next would get another id), and gravity changes to one that refuses
    // the light sphere for the same reason: tried, not reported again.
    ball(&mut app, DVec3::Y * 10.0, DVec3::ZERO);
    for g in [1.5e308, 1.25e308] {
        mend(&mut app, DVec3::X * g);
        run_steps(&mut app, 2);
    }
    assert!(app.world().get::<RejectedSphere>(light).is_some());
    assert_eq!(app.world().resource::<Rejections>().0.len(), 2);
    // Mended: it joins.
    mend(&mut app, DVec3::ZERO);
    run_steps(&mut app, 2);
    assert!(app.world().get::<RejectedSphere>(light).is_none());
    assert!(app.world().get::<SphereHandle>(light).is_some());
    assert!(app.world().get::<RejectedSphere>(bad).is_some());
    assert_eq!(app.world().resource::<Rejections>().0.len(), 2);

    // In the simulation when the game sets a gravity its force's sum with overflows: the step
    // refuses it (a runaway), and it is tried again once the gravity is mended.
    let mut third = crate::app(SpherePhysicsPlugin::default());
    let light = spawn_light(&mut third);
    run_steps(&mut third, 1);
    assert!(third.world().get::<SphereHandle>(light).is_some());
    mend(&mut third, DVec3::X * 1e308);
    run_steps(&mut third, 2);
    assert!(third.world().get::<RejectedSphere>(light).is_some());
    mend(&mut third, DVec3::ZERO);
    run_steps(&mut third, 2);
    assert!(third.world().get::<RejectedSphere>(light).is_none());
    assert!(third.world().get::<SphereHandle>(light).is_some());
}

/// Regression (found by the random changes test, with changes made between `Prepare` and
/// `Step`): a sphere despawned or disabled there while the physics was paused stayed in the
/// core's world until the next fixed step's `Prepare` (`Step` returned before taking it out).
#[test]
fn regression_a_sphere_taken_out_after_prepare_while_paused_leaves_at_once() {
    for disable in [false, true] {
        let mut app =
            app_despawning_between(SpherePhysicsSystems::Prepare, SpherePhysicsSystems::Step);
        app.insert_resource(DisableInstead(disable));
        let a = ball(&mut app, DVec3::new(-1.0, 0.0, 0.0), DVec3::X);
        ball(&mut app, DVec3::new(1.0, 0.0, 0.0), -DVec3::X);
        run_steps(&mut app, 1);
        app.world_mut().resource_mut::<SpherePhysicsClock>().paused = true;
        app.insert_resource(Doomed(Some(a)));
        app.update();
        assert!(
            app.world().resource::<Doomed>().0.is_none(),
            "disable {disable}"
        );
        let physics = app.world().resource::<SpherePhysicsWorld>();
        assert_eq!(physics.world.len(), 1, "disable {disable}");
    }
}

/// Regression (found by review): a reset left a rejected sphere out of the new world for good
/// (its rejection stood, though the new settings would take it), and left the `Transform` of
/// an entity whose `SphereBody` had just been removed to the plugin.
#[test]
fn regression_a_reset_takes_rejected_spheres_again() {
    // Under gravity of 1e308 m/s² a sphere this far down would fall past the largest f64.
    let mut app = app(SpherePhysicsPlugin::default().gravity(DVec3::NEG_Y * 1e308));
    let low = app
        .world_mut()
        .spawn((
            SphereBody::new(0.5),
            SpherePosition(DVec3::new(0.0, -1.7976e308, 0.0)),
        ))
        .id();
    let kept = app
        .world_mut()
        .spawn((SphereBody::new(0.5), Transform::from_xyz(3.0, 0.0, 0.0)))
        .id();
    run_steps(&mut app, 1);
    assert!(app.world().get::<RejectedSphere>(low).is_some());
    // The game takes `kept` out of the physics and queues a reset in the same frame.
    app.world_mut().entity_mut(kept).remove::<SphereBody>();
    app.world_mut()
        .commands()
        .queue(ResetSpherePhysics::new(sphere_physics::Settings::default()));
    app.world_mut().flush();
    assert!(app.world().get::<SpherePosition>(kept).is_none());
    run_steps(&mut app, 2);
    assert!(app.world().get::<RejectedSphere>(low).is_none());
    let physics = app.world().resource::<SpherePhysicsWorld>();
    assert!(physics.body(low).is_some());
    assert_eq!(physics.world.len(), 1);
    assert_eq!(position(&app, low), DVec3::new(0.0, -1.7976e308, 0.0));
}

/// Regression (found by review): a sphere spawned with only a `SpherePosition` was drawn at
/// the origin (its required `Transform`'s default) until its first step, and for good if it
/// was rejected; its `Transform` shows its position from the moment it is spawned.
#[test]
fn regression_a_sphere_spawned_by_its_position_is_shown_there_at_once() {
    let mut app = app(SpherePhysicsPlugin::default());
    let at = DVec3::new(1.0, 2.0, 3.0);
    let ball = app
        .world_mut()
        .spawn((SphereBody::new(0.5), SpherePosition(at)))
        .id();
    let rejected = app
        .world_mut()
        .spawn((SphereBody::new(-1.0), SpherePosition(-at)))
        .id();
    let shown = |app: &App, entity| app.world().get::<Transform>(entity).unwrap().translation;
    assert_eq!(shown(&app, ball), at.as_vec3());
    assert_eq!(shown(&app, rejected), (-at).as_vec3());
    run_steps(&mut app, 2);
    assert!(app.world().get::<RejectedSphere>(rejected).is_some());
    assert_eq!(shown(&app, rejected), (-at).as_vec3());
    assert_eq!(shown(&app, ball), at.as_vec3());
}

#[test]
fn sphere_order_decides_body_ids_whatever_the_entities() {
    let mut app = app(SpherePhysicsPlugin::default());
    // Spawned in one order, asked to join in the reverse one.
    let entities: Vec<Entity> = (0..4)
        .map(|i| {
            app.world_mut()
                .spawn((
                    SphereBody::new(0.1),
                    Transform::from_xyz(i as f32, 0.0, 0.0),
                    SphereOrder(10 - i),
                ))
                .id()
        })
        .collect();
    // One without an order joins after them.
    let last = app
        .world_mut()
        .spawn((SphereBody::new(0.1), Transform::from_xyz(9.0, 0.0, 0.0)))
        .id();
    run_steps(&mut app, 1);
    let physics = app.world().resource::<SpherePhysicsWorld>();
    let ids: Vec<usize> = entities
        .iter()
        .chain([&last])
        .map(|e| physics.body(*e).unwrap().index())
        .collect();
    assert_eq!(ids, vec![3, 2, 1, 0, 4]);
}

/// Regression (found by review): a sphere that would leave the finite range made the core
/// refuse every step, silently: the whole simulation froze. Now that sphere is rejected (a
/// `SphereRejected` message and a `RejectedSphere` component) and the rest keep stepping.
#[test]
fn regression_a_runaway_sphere_is_rejected_and_the_rest_keep_stepping() {
    let mut app = app(SpherePhysicsPlugin::default());
    collect_rejections(&mut app);
    // At 1e308 m/s from x = 1.79e308, its first step would pass the largest finite f64.
    let runaway = app
        .world_mut()
        .spawn((
            SphereBody::new(0.5),
            SpherePosition(DVec3::new(1.79e308, 0.0, 0.0)),
            SphereVelocity(DVec3::new(1e308, 0.0, 0.0)),
        ))
        .id();
    let ball = app
        .world_mut()
        .spawn((SphereBody::new(0.5), SphereVelocity(DVec3::Y)))
        .id();
    run_steps(&mut app, 3);
    assert!(
        (position(&app, ball).y - 3.0 / 64.0).abs() < 1e-12,
        "{}",
        position(&app, ball)
    );
    let seen = &app.world().resource::<Rejections>().0;
    assert_eq!(seen.len(), 1, "{seen:?}");
    assert_eq!(
        (seen[0].entity, seen[0].error.field),
        (runaway, Field::Velocity)
    );
    assert!(app.world().get::<RejectedSphere>(runaway).is_some());
    assert_eq!(position(&app, runaway).x, 1.79e308, "left where it was");
    assert_eq!(app.world().resource::<SpherePhysicsWorld>().world.len(), 1);
}

/// Regression (found by review): a step the core refuses for a reason no sphere can be blamed
/// for (settings out of range) was dropped without a trace; now it is counted (and logged).
#[test]
fn regression_refused_steps_are_counted() {
    let mut app = app(SpherePhysicsPlugin::default().substeps(100_000));
    app.world_mut()
        .spawn((SphereBody::new(0.5), SphereVelocity(DVec3::X)));
    for _ in 0..10 {
        app.update();
    }
    let diagnostics = app.world().resource::<SpherePhysicsDiagnostics>();
    assert_eq!(diagnostics.steps, 0);
    assert!(diagnostics.refused_steps > 0);
}

/// Regression (found by review): removing one of the components a sphere is spawned with
/// (its force, density, velocity or Transform) took it out of the plugin's view while its body
/// kept the old values: a thrust "removed" kept pushing. A missing one now means its default.
#[test]
fn regression_removing_a_default_component_means_its_default() {
    let mut app = app(SpherePhysicsPlugin::default());
    let rocket = app
        .world_mut()
        .spawn((SphereBody::new(0.5), AppliedForce(DVec3::X)))
        .id();
    run_steps(&mut app, 2);
    app.world_mut().entity_mut(rocket).remove::<AppliedForce>();
    app.world_mut().get_mut::<SphereVelocity>(rocket).unwrap().0 = DVec3::ZERO;
    run_steps(&mut app, 2);
    let physics = app.world().resource::<SpherePhysicsWorld>();
    let body = physics.world.body(physics.body(rocket).unwrap()).unwrap();
    assert_eq!(body.force(), DVec3::ZERO);
    assert_eq!(velocity(&app, rocket), DVec3::ZERO);
}

/// Regression (found by review): a disabled sphere (Bevy's `Disabled`, as state-scoped
/// entities use) stayed in the simulation, invisible, and others bounced off it.
#[test]
fn regression_a_disabled_sphere_leaves_the_simulation_until_enabled() {
    let mut app = app(SpherePhysicsPlugin::default());
    let (a, b) = head_on_pair(&mut app);
    run_steps(&mut app, 10);
    app.world_mut()
        .entity_mut(b)
        .insert(bevy::ecs::entity_disabling::Disabled);
    run_steps(&mut app, 300); // Long past when they would have met.
    assert_eq!(velocity(&app, a), DVec3::X, "nothing left to hit");
    assert_eq!(app.world().resource::<SpherePhysicsWorld>().world.len(), 1);
    app.world_mut()
        .entity_mut(b)
        .remove::<bevy::ecs::entity_disabling::Disabled>();
    run_steps(&mut app, 1);
    assert_eq!(app.world().resource::<SpherePhysicsWorld>().world.len(), 2);
}

/// Regression (found by review): after its `SphereBody` was removed (the entity kept), the
/// plugin still wrote the entity's `Transform` every frame from its last physics positions.
#[test]
fn regression_removing_sphere_body_hands_the_transform_back() {
    let mut app = app(SpherePhysicsPlugin::default());
    let b = app
        .world_mut()
        .spawn((SphereBody::new(0.5), SphereVelocity(DVec3::X)))
        .id();
    run_steps(&mut app, 2);
    app.world_mut().entity_mut(b).remove::<SphereBody>();
    app.update();
    app.world_mut()
        .get_mut::<Transform>(b)
        .unwrap()
        .translation
        .x = 100.0;
    for _ in 0..3 {
        app.update();
    }
    assert_eq!(
        app.world().get::<Transform>(b).unwrap().translation.x,
        100.0
    );
    assert!(app.world().get::<SphereHandle>(b).is_none());
}

/// Regression (found by review): a pendulum spawned at its string's length by its `Transform`
/// (f32) was rejected: the rounded start lies a hair outside the string.
#[test]
fn regression_a_taut_pendulum_placed_by_its_transform_is_accepted() {
    let mut app = app(SpherePhysicsPlugin::default());
    let bob = app
        .world_mut()
        .spawn((
            SphereBody::new(0.1),
            Transform::from_xyz(0.0, 0.7, 0.0),
            Tethered {
                anchor: DVec3::new(0.0, 2.0, 0.0),
                length: 1.3,
            },
        ))
        .id();
    run_steps(&mut app, 1);
    assert!(app.world().get::<RejectedSphere>(bob).is_none());
    assert_eq!(app.world().resource::<SpherePhysicsWorld>().world.len(), 1);
    let from_anchor = position(&app, bob) - DVec3::new(0.0, 2.0, 0.0);
    assert!(from_anchor.length() <= 1.3 * (1.0 + 1e-9));
}

/// Regression (found by review): a sphere whose `SphereVelocity` was removed was set back to
/// rest at every step (a missing component was read as zero while the core's velocity was not
/// written back to it): its velocity is the core's, as its position is without
/// `SpherePosition`.
#[test]
fn regression_removing_sphere_velocity_keeps_the_motion() {
    let g = DVec3::new(0.0, -9.81, 0.0);
    let mut app = app(SpherePhysicsPlugin::default().gravity(g));
    let ball = app
        .world_mut()
        .spawn((SphereBody::new(0.5), Transform::from_xyz(0.0, 100.0, 0.0)))
        .id();
    run_steps(&mut app, 1);
    app.world_mut().entity_mut(ball).remove::<SphereVelocity>();
    run_steps(&mut app, 63);
    let physics = app.world().resource::<SpherePhysicsWorld>();
    let body = physics.world.body(physics.body(ball).unwrap()).unwrap();
    // One second of free fall: 9.81 m/s (semi-implicit Euler gets the speed exactly).
    assert!(
        (body.velocity().y + 9.81).abs() < 1e-9,
        "{}",
        body.velocity()
    );
    // Semi-implicit Euler from rest at y = 100 with h = 1/64: y_n = 100 - g h² n(n + 1)/2.
    let fallen = |n: f64| 100.0 - 9.81 * n * (n + 1.0) / 2.0 / 4096.0;
    let y = position(&app, ball).y;
    assert!((y - fallen(64.0)).abs() < 1e-9, "{y}");
    // Its position component removed: put back, and the fall goes on unchanged.
    app.world_mut().entity_mut(ball).remove::<SpherePosition>();
    run_steps(&mut app, 2);
    let y = position(&app, ball).y;
    assert!((y - fallen(66.0)).abs() < 1e-9, "{y}");
    run_steps(&mut app, 1);
    let y = position(&app, ball).y;
    assert!((y - fallen(67.0)).abs() < 1e-9, "{y}");
}

/// Regression (found by review): a runaway body the game had added to the core directly (no
/// entity) made every step be refused for good.
#[test]
fn regression_a_runaway_body_without_an_entity_is_removed_too() {
    let mut app = app(SpherePhysicsPlugin::default());
    let ball = app
        .world_mut()
        .spawn((SphereBody::new(0.5), SphereVelocity(DVec3::Y)))
        .id();
    run_steps(&mut app, 1);
    app.world_mut()
        .resource_mut::<SpherePhysicsWorld>()
        .world
        .add_sphere(
            SphereDesc::new(0.5)
                .at(DVec3::new(1.79e308, 0.0, 0.0))
                .moving(DVec3::new(1e308, 0.0, 0.0)),
        )
        .unwrap();
    run_steps(&mut app, 2);
    assert!((position(&app, ball).y - 3.0 / 64.0).abs() < 1e-12);
    assert_eq!(app.world().resource::<SpherePhysicsWorld>().world.len(), 1);
}

/// Spheres a game spawns overlapping, with no gravity, are moved apart by the core (a tenth
/// of a radius a step each, in equal shares for equal masses) and given no speed; their
/// components and transforms follow.
#[test]
fn spheres_spawned_overlapping_with_no_gravity_move_apart() {
    let mut app = app(SpherePhysicsPlugin::default().gravity(DVec3::ZERO));
    let a = ball(&mut app, DVec3::ZERO, DVec3::ZERO);
    let b = ball(&mut app, DVec3::new(0.7, 0.0, 0.0), DVec3::ZERO);
    run_steps(&mut app, 1);
    assert_eq!(
        app.world()
            .resource::<SpherePhysicsDiagnostics>()
            .last
            .separated,
        2
    );
    // 0.3 m of overlap, 5 cm a step each: apart after three steps.
    run_steps(&mut app, 9);
    assert!((position(&app, a).x + 0.15).abs() < 1e-12);
    assert!((position(&app, b).x - 0.85).abs() < 1e-12);
    assert_eq!(velocity(&app, a), DVec3::ZERO);
    assert_eq!(velocity(&app, b), DVec3::ZERO);
    let diagnostics = app.world().resource::<SpherePhysicsDiagnostics>();
    assert_eq!(diagnostics.last.separated, 0);
    assert_eq!(diagnostics.collisions, 0);
    app.update();
    let shown = app.world().get::<Transform>(b).unwrap().translation;
    assert!((shown.x - 0.85).abs() < 1e-6, "{shown}");
}

/// The plugin's docs said that spheres spawned overlapping at rest stay so ("spawn them
/// apart"); under gravity the core's resting solve moves them apart, without leaving them a
/// speed.
#[test]
fn spheres_spawned_overlapping_on_a_floor_move_apart_and_rest() {
    let mut app = app(SpherePhysicsPlugin::default().gravity(DVec3::NEG_Y * 9.81));
    let floor = 1.0e4;
    app.world_mut().spawn((
        SphereBody::new(floor),
        SpherePosition(DVec3::new(0.0, -floor, 0.0)),
        FixedSphere,
    ));
    // 0.3 m into each other, side by side on the floor: the pair parts by at most a tenth of
    // the smaller radius (5 cm) a step, so it is apart in six steps.
    let a = ball(&mut app, DVec3::new(-0.35, 0.5, 0.0), DVec3::ZERO);
    let b = ball(&mut app, DVec3::new(0.35, 0.5, 0.0), DVec3::ZERO);
    let depth = |app: &App| 1.0 - (position(app, b) - position(app, a)).length();
    run_steps(&mut app, 4);
    assert!(depth(&app) > 0.05, "apart too soon: {} m deep", depth(&app));
    run_steps(&mut app, 4);
    assert!(depth(&app) < 1e-6, "still {} m deep", depth(&app));
    // Then they rest: no speed but the slide off the huge floor's curve (g x / R over 1 s,
    // under 5e-4 m/s), still on it, still apart.
    run_steps(&mut app, 52);
    assert!(depth(&app) < 1e-6, "{} m deep again", depth(&app));
    for k in [a, b] {
        let v = velocity(&app, k);
        assert!(v.length() < 5e-4, "{k}: {v}");
        assert!(
            (position(&app, k).y - 0.5).abs() < 1e-4,
            "{k}: {}",
            position(&app, k)
        );
    }
}

/// A floor (a fixed sphere of radius 1e4 whose top is at y = 0) and a ball of radius 0.5
/// resting on it, under Earth gravity.
fn ball_on_a_floor(app: &mut App) -> (Entity, Entity) {
    let floor = app
        .world_mut()
        .spawn((
            SphereBody::new(1.0e4),
            SpherePosition(DVec3::new(0.0, -1.0e4, 0.0)),
            FixedSphere,
        ))
        .id();
    (floor, ball(app, DVec3::new(0.0, 0.5, 0.0), DVec3::ZERO))
}

/// Despawning a sphere that another rested on panicked at the next step (the core kept which
/// bodies rested by index; see the core's `regression_removing_a_body_under_load.rs`).
#[test]
fn regression_despawning_the_floor_under_a_resting_ball() {
    let mut app = app(SpherePhysicsPlugin::default().gravity(DVec3::NEG_Y * 9.81));
    let (floor, ball) = ball_on_a_floor(&mut app);
    run_steps(&mut app, 10);
    assert!(velocity(&app, ball).length() < 1e-9, "at rest on the floor");
    app.world_mut().despawn(floor);
    run_steps(&mut app, 5);
    // Falling freely from rest, semi-implicit Euler: after 5 steps at 9.81 · 5 · dt.
    let dt = STEP.as_secs_f64();
    let v = velocity(&app, ball);
    assert!((v.y + 9.81 * 5.0 * dt).abs() < 1e-9, "{v}");
}

/// How many spheres the last step left asleep.
fn asleep(app: &App) -> u32 {
    app.world()
        .resource::<SpherePhysicsDiagnostics>()
        .last
        .asleep
}

/// Earth gravity, restitution 0.5, and sleeping on (`Sleep::default()`).
fn sleeping_under_gravity() -> SpherePhysicsPlugin {
    SpherePhysicsPlugin::default()
        .gravity(DVec3::NEG_Y * 9.81)
        .restitution(0.5)
        .sleep(sphere_physics::Sleep::default())
}

#[test]
fn a_sphere_at_rest_falls_asleep_and_a_game_wakes_it() {
    let mut app = app(sleeping_under_gravity());
    let (_, ball) = ball_on_a_floor(&mut app);
    // Calm for a second (64 steps), checked four times a second.
    run_steps(&mut app, 90);
    assert_eq!(asleep(&app), 1);
    let at = position(&app, ball);
    run_steps(&mut app, 60);
    assert_eq!(position(&app, ball), at, "asleep, it does not move");
    // A game system pushes it along the floor: it wakes and slides at 1 m/s.
    app.world_mut().get_mut::<SphereVelocity>(ball).unwrap().0 = DVec3::X;
    run_steps(&mut app, 1);
    assert_eq!(asleep(&app), 0);
    let dt = STEP.as_secs_f64();
    let moved = position(&app, ball) - at;
    assert!((moved.x - dt).abs() < 1e-6, "{moved}");
}

/// `NeverSleeps` keeps a sphere at rest awake; taken off, the sphere falls asleep; put on a
/// sphere asleep, it wakes it.
#[test]
fn a_sphere_that_never_sleeps_stays_awake_until_the_game_lets_it() {
    let mut app = app(sleeping_under_gravity());
    let (_, ball) = ball_on_a_floor(&mut app);
    app.world_mut().entity_mut(ball).insert(NeverSleeps);
    run_steps(&mut app, 150);
    assert_eq!(asleep(&app), 0);
    app.world_mut().entity_mut(ball).remove::<NeverSleeps>();
    run_steps(&mut app, 90);
    assert_eq!(asleep(&app), 1);
    app.world_mut().entity_mut(ball).insert(NeverSleeps);
    run_steps(&mut app, 90);
    assert_eq!(asleep(&app), 0);
}

/// Spheres whose components changed since the last step (counted after `Writeback`).
#[derive(Resource, Default)]
struct ChangedPositions(usize);

/// While spheres sleep, `Prepare` looks only at those whose components changed and
/// `Writeback` leaves the asleep ones' components alone (a game asking for changed positions
/// sees none); every way a game changes a sphere still reaches the core: a component set, one
/// removed (its default), a sphere disabled and enabled, and a change made to the core's body
/// directly (undone, as the components are the truth).
#[test]
fn asleep_spheres_are_left_alone_and_every_change_still_reaches_them() {
    let mut app = app(sleeping_under_gravity());
    app.init_resource::<ChangedPositions>().add_systems(
        FixedUpdate,
        (|moved: Query<(), Changed<SpherePosition>>, mut count: ResMut<ChangedPositions>| {
            count.0 = moved.iter().count();
        })
        .after(SpherePhysicsSystems::Writeback),
    );
    let (_, a) = ball_on_a_floor(&mut app);
    let b = ball(&mut app, DVec3::new(3.0, 0.5, 0.0), DVec3::ZERO);
    app.world_mut().entity_mut(b).insert(Density(5.0));
    let body = |app: &App, e: Entity| {
        let physics = app.world().resource::<SpherePhysicsWorld>();
        physics.world.body(physics.body(e)?).cloned()
    };
    run_steps(&mut app, 90);
    assert_eq!(asleep(&app), 2);
    run_steps(&mut app, 2);
    assert_eq!(app.world().resource::<ChangedPositions>().0, 0);
    let at_a = position(&app, a);

    // A change made to the core's body directly is undone (and wakes it).
    let id = app.world().get::<SphereHandle>(a).unwrap().0;
    let mut physics = app.world_mut().resource_mut::<SpherePhysicsWorld>();
    physics.world.set_velocity(id, DVec3::X).unwrap();
    run_steps(&mut app, 1);
    assert!(body(&app, a).unwrap().velocity().x.abs() < 1e-12);
    assert!((position(&app, a).x - at_a.x).abs() < 1e-12);

    // A component removed means its default.
    assert_eq!(body(&app, b).unwrap().density(), 5.0);
    app.world_mut().entity_mut(b).remove::<Density>();
    run_steps(&mut app, 1);
    assert_eq!(body(&app, b).unwrap().density(), 1.0);

    // Disabled, it leaves; enabled again, it joins where it was.
    run_steps(&mut app, 90);
    assert_eq!(asleep(&app), 2);
    let disabled = bevy::ecs::entity_disabling::Disabled;
    app.world_mut().entity_mut(a).insert(disabled);
    run_steps(&mut app, 1);
    assert!(body(&app, a).is_none());
    run_steps(&mut app, 90);
    assert_eq!(asleep(&app), 1);
    app.world_mut()
        .entity_mut(a)
        .remove::<bevy::ecs::entity_disabling::Disabled>();
    run_steps(&mut app, 1);
    assert!((body(&app, a).unwrap().position() - at_a).length() < 1e-9);

    // A component set on an asleep sphere wakes it.
    run_steps(&mut app, 90);
    assert_eq!(asleep(&app), 2);
    let at_b = position(&app, b);
    app.world_mut().entity_mut(b).insert(AppliedForce(DVec3::X));
    run_steps(&mut app, 1);
    // It wakes, alone: the other ball is a group of its own.
    assert!(!body(&app, b).unwrap().is_asleep());
    assert_eq!(asleep(&app), 1);
    assert!(position(&app, b).x > at_b.x);
}

/// Regression (found by review): while any sphere slept, `Writeback` wrote a sphere's
/// `SpherePosition` without its `PreviousSpherePosition` when the two had been the same (a
/// sphere starting to move after standing still), and the interpolation took it for a
/// teleport: the sphere was drawn a whole step ahead, then stood there until the next step.
#[test]
fn regression_a_sphere_starting_to_move_beside_a_sleeper_is_interpolated() {
    let mut app = app(sleeping_under_gravity());
    let (_, a) = ball_on_a_floor(&mut app);
    let b = ball(&mut app, DVec3::new(3.0, 0.5, 0.0), DVec3::ZERO);
    run_steps(&mut app, 90);
    assert_eq!(asleep(&app), 2);
    let at = position(&app, b);
    // `b` is pushed along the floor; `a` sleeps on.
    app.world_mut().get_mut::<SphereVelocity>(b).unwrap().0 = DVec3::X;
    // A frame of 1.5 fixed steps: one step, and the fixed clock half a step into the next.
    app.insert_resource(TimeUpdateStrategy::ManualDuration(STEP * 3 / 2));
    let steps = app.world().resource::<SpherePhysicsDiagnostics>().steps;
    app.update();
    assert_eq!(
        app.world().resource::<SpherePhysicsDiagnostics>().steps,
        steps + 1
    );
    assert_eq!(asleep(&app), 1);
    assert!(!position(&app, a).is_nan());
    let fraction = app
        .world()
        .resource::<Time<Fixed>>()
        .overstep_fraction_f64();
    assert!((fraction - 0.5).abs() < 1e-9, "overstep {fraction}");
    let now = position(&app, b);
    assert!(now.x > at.x, "it moved: {at} to {now}");
    let shown = app.world().get::<Transform>(b).unwrap().translation;
    let expected = at.lerp(now, fraction).as_vec3();
    assert!(
        (shown - expected).length() < 1e-6,
        "shown at {shown}, half a step back from {now} is {expected}"
    );
}

/// Writes a game system made to `SphereVelocity` and `SpherePosition` once, after `Prepare`
/// and before `Writeback` (where a system in `FixedUpdate` with no order against the plugin's
/// sets may run).
#[derive(Resource)]
struct LateWrites {
    pushed: Entity,
    moved: Entity,
    target: DVec3,
    done: bool,
}

/// Regression (found by review): a game system that set a sphere's velocity or position
/// after `Prepare` had read it (one with no order against the plugin's sets may run there)
/// had it overwritten by `Writeback` with the step's result, and the change was lost. It is
/// now kept, and applied at the next step.
#[test]
fn regression_a_change_made_after_prepare_is_kept_for_the_next_step() {
    for sleeping in [false, true] {
        let plugin = if sleeping {
            sleeping_under_gravity()
        } else {
            SpherePhysicsPlugin::default().gravity(DVec3::NEG_Y * 9.81)
        };
        let mut app = app(plugin);
        let (_, pushed) = ball_on_a_floor(&mut app);
        let moved = ball(&mut app, DVec3::new(3.0, 0.5, 0.0), DVec3::ZERO);
        run_steps(&mut app, 90);
        assert_eq!(asleep(&app), if sleeping { 2 } else { 0 });
        // `moved` goes to the other side of the floor's top, where it rests as it did.
        let (at, was) = (position(&app, pushed), position(&app, moved));
        let target = DVec3::new(-was.x, was.y, was.z);
        app.insert_resource(LateWrites {
            pushed,
            moved,
            target,
            done: false,
        })
        .add_systems(
            FixedUpdate,
            (|mut late: ResMut<LateWrites>,
              mut velocities: Query<&mut SphereVelocity>,
              mut positions: Query<&mut SpherePosition>| {
                if !late.done {
                    late.done = true;
                    velocities.get_mut(late.pushed).unwrap().0 = DVec3::X;
                    positions.get_mut(late.moved).unwrap().0 = late.target;
                }
            })
            .after(SpherePhysicsSystems::Prepare)
            .before(SpherePhysicsSystems::Writeback),
        );
        run_steps(&mut app, 1);
        assert_eq!(velocity(&app, pushed), DVec3::X, "sleeping {sleeping}");
        assert_eq!(position(&app, moved), target, "sleeping {sleeping}");
        run_steps(&mut app, 2);
        // Applied at the next step's `Prepare`: it slides for two steps (a step would be
        // 0.0156 m), from where it was.
        let dt = STEP.as_secs_f64();
        let slid = position(&app, pushed) - at;
        assert!(
            (slid.x - 2.0 * dt).abs() < 1e-6,
            "sleeping {sleeping}: {slid}"
        );
        // It goes on from there (sliding off the floor's top at a few mm/s, as it was: a
        // teleport lost would leave it 6 m away).
        let moved_by = position(&app, moved) - target;
        assert!(moved_by.length() < 1e-3, "sleeping {sleeping}: {moved_by}");
    }
}

/// Moves a sphere to a place once, after `Prepare` and before `Writeback` (as a game system
/// with no order against the plugin's sets may).
#[derive(Resource)]
struct LateMove {
    moved: Entity,
    target: DVec3,
    done: bool,
}

fn move_late(app: &mut App, moved: Entity, target: DVec3) {
    app.insert_resource(LateMove {
        moved,
        target,
        done: false,
    })
    .add_systems(
        FixedUpdate,
        (|mut late: ResMut<LateMove>, mut positions: Query<&mut SpherePosition>| {
            if !late.done {
                late.done = true;
                positions.get_mut(late.moved).unwrap().0 = late.target;
            }
        })
        .after(SpherePhysicsSystems::Prepare)
        .before(SpherePhysicsSystems::Writeback),
    );
}

/// Regression (found by review): a position a game set after `Prepare` was overwritten with
/// the step's result, and lost, in the step in which `Prepare` gave the sphere its handle (it
/// joined, or had lost its handle): any change after the handle was put on was taken for
/// `Prepare`'s own. It is kept, and applied at the next step, as in any other step.
#[test]
fn regression_a_position_set_late_is_kept_in_the_step_a_sphere_gets_its_handle() {
    for joins in [true, false] {
        let mut app = app(SpherePhysicsPlugin::default());
        let ball = ball(&mut app, DVec3::ZERO, DVec3::X);
        if !joins {
            run_steps(&mut app, 3);
            app.world_mut().entity_mut(ball).remove::<SphereHandle>();
        }
        let target = DVec3::new(0.0, 5.0, 0.0);
        move_late(&mut app, ball, target);
        run_steps(&mut app, 1);
        assert!(app.world().get::<SphereHandle>(ball).is_some());
        assert_eq!(position(&app, ball), target, "joins {joins}");
        // Applied at the next step: it moves on from there.
        run_steps(&mut app, 1);
        let dt = STEP.as_secs_f64();
        assert_eq!(
            position(&app, ball),
            target + DVec3::X * dt,
            "joins {joins}"
        );
    }
}

/// Regression (found by review): an invalid change made together with a component's removal
/// was reported twice. With a sphere asleep (so that `Prepare` looks only at the spheres that
/// changed, and at those that lost a component), a sphere in both lists was rejected, then
/// taken for a new sphere and rejected again. And a sphere whose `SpherePosition` was removed
/// kept a rejection placed by its `Transform`, while the position put back said otherwise: it
/// was retried, and rejected again, at the next step.
#[test]
fn regression_an_invalid_change_with_a_removal_is_rejected_once() {
    for (sleeping, removes_position) in [(true, false), (false, true), (true, true)] {
        let label = format!("sleeping {sleeping}, removes its position {removes_position}");
        let mut app = app(if sleeping {
            sleeping_under_gravity()
        } else {
            SpherePhysicsPlugin::default()
        });
        collect_rejections(&mut app);
        ball_on_a_floor(&mut app);
        let thrown = ball(&mut app, DVec3::new(5.0, 50.0, 0.0), DVec3::X);
        run_steps(&mut app, 90);
        assert_eq!(asleep(&app), u32::from(sleeping), "{label}");
        let mut e = app.world_mut().entity_mut(thrown);
        if removes_position {
            e.remove::<SpherePosition>();
        } else {
            e.remove::<SphereVelocity>();
        }
        e.get_mut::<SphereBody>().unwrap().radius = -1.0;
        run_steps(&mut app, 4);
        let seen = &app.world().resource::<Rejections>().0;
        assert_eq!(seen.len(), 1, "{label}: {seen:?}");
        assert_eq!(seen[0].error.field, Field::Radius, "{label}");
        // Fixed: it joins again, once.
        app.world_mut()
            .get_mut::<SphereBody>(thrown)
            .unwrap()
            .radius = 0.5;
        run_steps(&mut app, 1);
        assert!(app.world().get::<SphereHandle>(thrown).is_some(), "{label}");
        assert_eq!(app.world().resource::<Rejections>().0.len(), 1, "{label}");
    }
}

/// Regression (found by review): a sphere whose `PreviousSpherePosition` a game removed (a
/// component it is spawned with) was no longer written back, nor shown, and at every step its
/// body was put back where its stale components said, so it stood still. The component is now
/// put back, as a removed `SpherePosition` is.
#[test]
fn regression_a_removed_previous_position_is_put_back() {
    for sleeping in [false, true] {
        let mut app = app(if sleeping {
            sleeping_under_gravity()
        } else {
            SpherePhysicsPlugin::default()
        });
        if sleeping {
            ball_on_a_floor(&mut app);
        }
        // Thrown along x, high above anything: x grows by a step's 1/64 m each step.
        let thrown = ball(&mut app, DVec3::new(5.0, 50.0, 0.0), DVec3::X);
        run_steps(&mut app, 90);
        assert_eq!(asleep(&app), u32::from(sleeping));
        let x = position(&app, thrown).x;
        app.world_mut()
            .entity_mut(thrown)
            .remove::<PreviousSpherePosition>();
        run_steps(&mut app, 4);
        let dt = STEP.as_secs_f64();
        assert_eq!(
            position(&app, thrown).x,
            x + 4.0 * dt,
            "sleeping {sleeping}"
        );
        assert!(app.world().get::<PreviousSpherePosition>(thrown).is_some());
        let shown = app.world().get::<Transform>(thrown).unwrap().translation;
        assert_eq!(shown.x, (x + 3.0 * dt) as f32, "sleeping {sleeping}");
    }
}

/// Regression (found by review): while any sphere slept, a sphere rejected when it joined
/// (placed by its `Transform` beyond its string) was not retried when a game moved its
/// `Transform` to a valid place: `Prepare` looked only at spheres whose physics components
/// changed.
#[test]
fn regression_a_rejected_sphere_moved_by_its_transform_joins_while_others_sleep() {
    let mut app = app(sleeping_under_gravity());
    ball_on_a_floor(&mut app);
    run_steps(&mut app, 90);
    assert_eq!(asleep(&app), 1);
    let anchor = DVec3::new(5.0, 3.0, 0.0);
    let hanging = app
        .world_mut()
        .spawn((
            SphereBody::new(0.1),
            Transform::from_xyz(5.0, 0.5, 0.0),
            Tethered {
                anchor,
                length: 1.0,
            },
        ))
        .id();
    run_steps(&mut app, 2);
    assert!(app.world().get::<RejectedSphere>(hanging).is_some());
    assert!(app.world().get::<SphereHandle>(hanging).is_none());
    app.world_mut()
        .get_mut::<Transform>(hanging)
        .unwrap()
        .translation = Vec3::new(5.0, 2.5, 0.0);
    run_steps(&mut app, 2);
    assert!(app.world().get::<SphereHandle>(hanging).is_some());
    assert!(app.world().get::<RejectedSphere>(hanging).is_none());
    assert_eq!(asleep(&app), 1);
}

/// Every sphere's position and velocity components are its body's, to the bit, its previous
/// position is `before` (its position when the update began), and its `Transform` shows the
/// previous position (each update takes one whole step: the interpolation's fraction is 0).
fn check_written(app: &mut App, before: &[(Entity, DVec3)], label: &str) {
    let physics = app.world().resource::<SpherePhysicsWorld>();
    for &(entity, was) in before {
        let id = physics.body(entity).expect("in the world");
        let body = physics.world.body(id).unwrap();
        let world = app.world();
        assert_eq!(position(app, entity), body.position(), "{label}: {entity}");
        assert_eq!(velocity(app, entity), body.velocity(), "{label}: {entity}");
        let previous = world.get::<PreviousSpherePosition>(entity).unwrap().0;
        assert_eq!(previous, was, "{label}: {entity}'s previous position");
        let shown = world.get::<Transform>(entity).unwrap().translation;
        assert_eq!(shown, previous.as_vec3(), "{label}: {entity} shown");
    }
}

/// Every dynamic sphere's position now.
fn positions(app: &mut App, spheres: &[Entity]) -> Vec<(Entity, DVec3)> {
    spheres.iter().map(|&e| (e, position(app, e))).collect()
}

/// A step that leaves out the spheres asleep beyond the reach of what moves (a bed of 80,
/// each asleep on the floor) lists the bodies it took (`World::last_step_bodies`), and
/// `Writeback` looks only at those and at the spheres it moved the update before: every
/// sphere's components must still be its body's, and every previous position the position
/// before the step, as a sphere starts to slide, slides, is stopped, and as a sphere asleep
/// is pushed by a game late in an update (kept for the next step) or moved by one.
#[test]
fn writeback_of_a_step_that_leaves_a_bed_out_keeps_every_sphere_right() {
    let mut app = app(sleeping_under_gravity());
    let (_, slider) = ball_on_a_floor(&mut app);
    let mut spheres = vec![slider];
    for i in 0..80 {
        let at = DVec3::new(10.0 + 1.2 * f64::from(i % 10), 0.5, 1.2 * f64::from(i / 10));
        spheres.push(ball(&mut app, at, DVec3::ZERO));
    }
    run_steps(&mut app, 120);
    assert_eq!(asleep(&app), 81);
    let step = |app: &mut App, label: &str| {
        let before = positions(app, &spheres);
        run_steps(app, 1);
        check_written(app, &before, label);
    };
    // The slider is pushed: it slides alone, the bed left out.
    app.world_mut().get_mut::<SphereVelocity>(slider).unwrap().0 = DVec3::X;
    for k in 0..20 {
        step(&mut app, &format!("sliding {k}"));
        let physics = app.world().resource::<SpherePhysicsWorld>();
        let listed = physics.world.last_step_bodies().expect("the bed left out");
        assert!(listed.len() <= 2, "sliding {k}: {listed:?}");
    }
    // Stopped by the game: it stands, its previous position catching up.
    app.world_mut().get_mut::<SphereVelocity>(slider).unwrap().0 = DVec3::ZERO;
    for k in 0..3 {
        step(&mut app, &format!("stopped {k}"));
    }
    // A sphere asleep pushed late in an update (after `Prepare`): kept, then applied.
    let pushed = spheres[40];
    app.insert_resource(LateWrites {
        pushed,
        moved: pushed,
        target: position(&app, pushed),
        done: false,
    })
    .add_systems(
        FixedUpdate,
        (|mut late: ResMut<LateWrites>, mut velocities: Query<&mut SphereVelocity>| {
            if !late.done {
                late.done = true;
                velocities.get_mut(late.pushed).unwrap().0 = DVec3::Z;
            }
        })
        .after(SpherePhysicsSystems::Prepare)
        .before(SpherePhysicsSystems::Writeback),
    );
    run_steps(&mut app, 1);
    assert_eq!(velocity(&app, pushed), DVec3::Z, "kept for the next step");
    let was = position(&app, pushed);
    for k in 0..5 {
        step(&mut app, &format!("pushed {k}"));
    }
    assert!(position(&app, pushed).z > was.z + 0.05, "it slid");
    // A sphere asleep moved by the game.
    let moved = spheres[70];
    let target = position(&app, moved) + DVec3::new(0.0, 0.0, -0.1);
    app.world_mut().get_mut::<SpherePosition>(moved).unwrap().0 = target;
    for k in 0..5 {
        step(&mut app, &format!("moved {k}"));
    }
    assert!((position(&app, moved) - target).length() < 1e-3);
}

/// An app with one sphere (radius 0.5) at the origin moving at 1 m/s along x, no gravity,
/// after its first step.
fn one_sphere_moving_along_x() -> (App, Entity) {
    let mut app = app(SpherePhysicsPlugin::default());
    let a = app
        .world_mut()
        .spawn((
            SphereBody::new(0.5),
            SpherePosition(DVec3::ZERO),
            SphereVelocity(DVec3::X),
        ))
        .id();
    run_steps(&mut app, 1);
    (app, a)
}

#[test]
fn a_sphere_cloned_with_its_handle_becomes_a_sphere_of_its_own() {
    // Cloning a sphere's entity copies its handle too: the copy is still a new sphere, with a
    // body of its own, and the original keeps its body.
    let (mut app, a) = one_sphere_moving_along_x();
    let handle_a = app.world().get::<SphereHandle>(a).unwrap().0;
    let b = app.world_mut().entity_mut(a).clone_and_spawn();
    assert_eq!(app.world().get::<SphereHandle>(b).unwrap().0, handle_a);
    // Far from the original, and moving the other way: the two never meet.
    app.world_mut().get_mut::<SpherePosition>(b).unwrap().0 = DVec3::new(0.0, 0.0, 10.0);
    app.world_mut().get_mut::<SphereVelocity>(b).unwrap().0 = DVec3::NEG_X;
    run_steps(&mut app, 2);
    let handle_b = app.world().get::<SphereHandle>(b).unwrap().0;
    assert_ne!(handle_b, handle_a);
    assert_eq!(app.world().get::<SphereHandle>(a).unwrap().0, handle_a);
    assert_eq!(app.world().resource::<SpherePhysicsWorld>().world.len(), 2);
    assert_eq!(velocity(&app, a).x, 1.0);
    assert_eq!(velocity(&app, b).x, -1.0);
    assert!(position(&app, b).z > 9.0 && position(&app, a).z.abs() < 1.0);
}

#[test]
fn a_sphere_given_back_an_old_handle_keeps_its_body() {
    // A game that saved a sphere's handle and puts it back after the sphere joined the world
    // again (here after being disabled) does not cost the sphere its body: the stale handle is
    // refused, its own put back, and no body is left behind without an entity.
    let (mut app, a) = one_sphere_moving_along_x();
    let old = *app.world().get::<SphereHandle>(a).unwrap();
    app.world_mut()
        .entity_mut(a)
        .insert(bevy::ecs::entity_disabling::Disabled);
    run_steps(&mut app, 1);
    app.world_mut()
        .entity_mut(a)
        .remove::<bevy::ecs::entity_disabling::Disabled>();
    run_steps(&mut app, 1);
    let current = app.world().get::<SphereHandle>(a).unwrap().0;
    assert_ne!(current, old.0);
    app.world_mut().entity_mut(a).insert(old);
    run_steps(&mut app, 3);
    let physics = app.world().resource::<SpherePhysicsWorld>();
    assert_eq!(physics.world.len(), 1, "one body, the sphere's");
    assert_eq!(physics.body(a), Some(current));
    assert_eq!(app.world().get::<SphereHandle>(a).unwrap().0, current);
    assert_eq!(velocity(&app, a).x, 1.0);
}

/// The plugin's components and resources are registered for reflection, as editors and
/// inspectors read them, and a reflected resource reads as the resource itself. (Until the
/// fifty-seventh session the diagnostics and the shown time were not reflected.)
#[test]
fn components_and_resources_are_registered_for_reflection() {
    use bevy::ecs::reflect::{ReflectComponent, ReflectResource};
    use bevy::reflect::ReflectRef;
    use std::any::TypeId;

    let mut app = app(SpherePhysicsPlugin::default());
    app.world_mut().spawn(SphereBody::new(0.5));
    run_steps(&mut app, 3);
    let world = app.world();
    let registry = world.resource::<AppTypeRegistry>().read();
    let components = [
        ("SphereBody", TypeId::of::<SphereBody>()),
        ("SpherePosition", TypeId::of::<SpherePosition>()),
        (
            "PreviousSpherePosition",
            TypeId::of::<PreviousSpherePosition>(),
        ),
        ("SphereVelocity", TypeId::of::<SphereVelocity>()),
        ("Density", TypeId::of::<Density>()),
        ("Restitution", TypeId::of::<Restitution>()),
        ("AppliedForce", TypeId::of::<AppliedForce>()),
        ("FixedSphere", TypeId::of::<FixedSphere>()),
        ("NeverSleeps", TypeId::of::<NeverSleeps>()),
        ("Tethered", TypeId::of::<Tethered>()),
        ("SphereOrder", TypeId::of::<SphereOrder>()),
        ("NoInterpolation", TypeId::of::<NoInterpolation>()),
    ];
    let resources = [
        ("SpherePhysicsClock", TypeId::of::<SpherePhysicsClock>()),
        (
            "SpherePhysicsDiagnostics",
            TypeId::of::<SpherePhysicsDiagnostics>(),
        ),
        ("SphereShownTime", TypeId::of::<SphereShownTime>()),
    ];
    let all = components.map(|(name, id)| (name, id, false));
    for (name, id, resource) in all.into_iter().chain(resources.map(|(n, i)| (n, i, true))) {
        let reflected = registry.get(id).is_some_and(|r| {
            if resource {
                r.data::<ReflectResource>().is_some()
            } else {
                r.data::<ReflectComponent>().is_some()
            }
        });
        assert!(reflected, "{name}");
    }
    // The diagnostics read through reflection as they are.
    let id = TypeId::of::<SpherePhysicsDiagnostics>();
    let component = world.components().get_valid_id(id).unwrap();
    let entity = world.resource_entities().get(component).unwrap();
    let reflected = world.get_reflect(entity, id).unwrap();
    let ReflectRef::Struct(fields) = reflected.reflect_ref() else {
        panic!("the diagnostics reflect as a struct");
    };
    let steps = fields.field("steps").unwrap().try_downcast_ref::<u64>();
    assert_eq!(steps, Some(&3));
    assert!(fields.field("last").is_none());
}
