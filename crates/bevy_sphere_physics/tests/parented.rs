//! Spheres that are children of other entities (Bevy's `ChildOf`): each is simulated at its
//! place in the world, and drawn there, whatever its parent's translation, rotation and scale,
//! and however the game moves the parent. (Until the sixty-second session a child's
//! `Transform` was read and written as its place in the world, and such a sphere was drawn
//! somewhere else, with no warning.)

use std::time::Duration;

use bevy::ecs::schedule::{LogLevel, ScheduleBuildSettings};
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy::transform::TransformPlugin;
use bevy_sphere_physics::prelude::*;

/// 1/64 s: exact in nanoseconds and in binary, so fixed steps and frames line up exactly.
const STEP: Duration = Duration::from_nanos(15_625_000);

fn app(plugin: SpherePhysicsPlugin) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin, plugin))
        .insert_resource(Time::<Fixed>::from_duration(STEP))
        .insert_resource(TimeUpdateStrategy::ManualDuration(STEP));
    let strict = |s: &mut Schedule| {
        s.set_build_settings(ScheduleBuildSettings {
            ambiguity_detection: LogLevel::Error,
            ..default()
        });
    };
    app.edit_schedule(FixedUpdate, strict);
    app.edit_schedule(PostUpdate, strict);
    app
}

fn position(app: &App, entity: Entity) -> DVec3 {
    app.world().get::<SpherePosition>(entity).unwrap().0
}

/// Where Bevy draws the entity: its `GlobalTransform`, as propagated at the end of the frame.
fn drawn(app: &App, entity: Entity) -> Vec3 {
    app.world()
        .get::<GlobalTransform>(entity)
        .unwrap()
        .translation()
}

/// Asserts that the sphere is drawn where it is simulated (interpolation off), to `f32`
/// rounding of the places involved (a few metres: 1e-5 m).
fn assert_drawn_at_its_place(app: &App, sphere: Entity) {
    let at = position(app, sphere);
    let shown = drawn(app, sphere).as_dvec3();
    assert!(
        (shown - at).abs().max_element() < 1e-5,
        "drawn at {shown}, simulated at {at}"
    );
}

/// Spawns a sphere of `radius` at `at` in `parent`'s frame (its `Transform`'s translation).
fn child(app: &mut App, parent: Entity, radius: f64, at: Vec3) -> Entity {
    app.world_mut()
        .spawn((
            SphereBody::new(radius),
            Transform::from_translation(at),
            ChildOf(parent),
        ))
        .id()
}

/// An entity that spheres are put under, moved by a test's system.
#[derive(Component)]
struct Cart;

/// How many `SphereRejected` messages have been read.
#[derive(Resource, Default)]
struct Reports(u32);

fn count_reports(mut rejected: MessageReader<SphereRejected>, mut reports: ResMut<Reports>) {
    reports.0 += rejected.read().count() as u32;
}

/// A parent translated, rotated a quarter turn about z and scaled twice.
fn turned_parent() -> Transform {
    Transform::from_xyz(10.0, 0.0, 0.0)
        .with_rotation(Quat::from_rotation_z(std::f32::consts::FRAC_PI_2))
        .with_scale(Vec3::splat(2.0))
}

#[test]
fn a_sphere_under_a_moved_turned_and_scaled_parent_starts_and_falls_where_it_is_drawn() {
    let mut app = app(SpherePhysicsPlugin::default()
        .gravity(DVec3::NEG_Y * 9.81)
        .interpolate(false));
    let parent = app.world_mut().spawn(turned_parent()).id();
    // (0, 1, 0) in the parent's frame: scaled to (0, 2, 0), turned to (-2, 0, 0), moved to
    // (8, 0, 0).
    let sphere = child(&mut app, parent, 0.1, Vec3::new(0.0, 1.0, 0.0));
    app.update();
    app.update();
    let start = position(&app, sphere);
    assert!(
        (start.x - 8.0).abs() < 1e-6 && start.z.abs() < 1e-6,
        "joined at {start}, not (8, y, 0)"
    );
    for _ in 0..30 {
        app.update();
    }
    let at = position(&app, sphere);
    assert!((at.x - 8.0).abs() < 1e-6, "fell sideways to {at}");
    assert!(at.y < start.y - 0.5, "did not fall: {start} to {at}");
    assert_drawn_at_its_place(&app, sphere);
}

#[test]
fn a_parent_the_game_moves_does_not_carry_its_sphere_on_screen() {
    let mut app = app(SpherePhysicsPlugin::default().interpolate(false));
    // The cart moves in `Update`, after the spheres' `Transform`s are written for the frame.
    app.add_systems(Update, |mut carts: Query<&mut Transform, With<Cart>>| {
        for mut cart in &mut carts {
            cart.translation.x += 0.25;
            cart.rotate_y(0.1);
        }
    });
    let cart = app.world_mut().spawn((Cart, Transform::default())).id();
    let sphere = child(&mut app, cart, 0.1, Vec3::new(1.0, 2.0, 3.0));
    let mut joined_at = None;
    for _ in 0..20 {
        app.update();
        if let Some(&SpherePosition(at)) = app.world().get::<SpherePosition>(sphere) {
            // At rest, no gravity: it stays where it joined.
            assert_eq!(*joined_at.get_or_insert(at), at);
            assert_drawn_at_its_place(&app, sphere);
        }
    }
    assert!(joined_at.is_some(), "the sphere never joined");
    assert!(drawn(&app, cart).x > 4.0, "the cart did not move");
}

#[test]
fn a_sphere_parented_to_a_sphere_is_drawn_at_its_own_place() {
    let mut app = app(SpherePhysicsPlugin::default()
        .gravity(DVec3::NEG_Y * 9.81)
        .interpolate(false));
    let holder = app
        .world_mut()
        .spawn((
            SphereBody::new(0.5),
            Transform::from_xyz(0.0, 10.0, 0.0),
            SphereVelocity(DVec3::new(3.0, 0.0, 0.0)),
        ))
        .id();
    // Two deep, each a child of the one before, each 2 m beside its parent.
    let middle = child(&mut app, holder, 0.5, Vec3::new(0.0, 0.0, 2.0));
    let last = app
        .world_mut()
        .spawn((
            SphereBody::new(0.5),
            Transform::from_xyz(0.0, 0.0, 2.0),
            SphereVelocity(DVec3::new(-3.0, 0.0, 0.0)),
            ChildOf(middle),
        ))
        .id();
    app.update();
    app.update();
    assert_eq!(position(&app, middle).z, 2.0);
    assert_eq!(position(&app, last).z, 4.0);
    for _ in 0..20 {
        app.update();
    }
    // Each moves on its own: the holder to +x, the middle one nowhere sideways, the last to -x.
    assert!(position(&app, holder).x > 0.5);
    assert_eq!(position(&app, middle).x, 0.0);
    assert!(position(&app, last).x < -0.5);
    for sphere in [holder, middle, last] {
        assert_drawn_at_its_place(&app, sphere);
    }
}

#[test]
fn a_child_spawned_before_prepare_joins_at_its_place_in_the_world() {
    // Spawned in the fixed step itself, before `Prepare`: no `GlobalTransform` has been
    // propagated for it (nor for its parent) yet.
    #[derive(Resource, Default)]
    struct Spawned(Option<Entity>);
    let mut app = app(SpherePhysicsPlugin::default().interpolate(false));
    app.init_resource::<Spawned>().add_systems(
        FixedUpdate,
        (|mut commands: Commands, mut spawned: ResMut<Spawned>| {
            if spawned.0.is_none() {
                let parent = commands.spawn(turned_parent()).id();
                spawned.0 = Some(
                    commands
                        .spawn((
                            SphereBody::new(0.1),
                            Transform::from_xyz(0.0, 1.0, 0.0),
                            ChildOf(parent),
                        ))
                        .id(),
                );
            }
        })
        .before(SpherePhysicsSystems::Prepare),
    );
    for _ in 0..3 {
        app.update();
    }
    let sphere = app.world().resource::<Spawned>().0.unwrap();
    let at = position(&app, sphere);
    assert!(
        (at - DVec3::new(8.0, 0.0, 0.0)).length() < 1e-6,
        "joined at {at}"
    );
    assert_drawn_at_its_place(&app, sphere);
}

#[test]
fn a_position_given_to_a_child_moves_its_transform_through_the_parent() {
    let mut app = app(SpherePhysicsPlugin::default());
    let parent = app.world_mut().spawn(turned_parent()).id();
    let sphere = app
        .world_mut()
        .spawn((
            SphereBody::new(0.1),
            SpherePosition(DVec3::new(8.0, 0.0, 0.0)),
            ChildOf(parent),
        ))
        .id();
    // At once, before any update: (8, 0, 0) is (0, 1, 0) in the parent's frame.
    let local = app.world().get::<Transform>(sphere).unwrap().translation;
    assert!(
        (local - Vec3::Y).length() < 1e-6,
        "local translation {local}"
    );
}

#[test]
fn a_parent_scaled_to_zero_leaves_its_sphere_simulated_and_its_transform_finite() {
    let mut app = app(SpherePhysicsPlugin::default().gravity(DVec3::NEG_Y * 9.81));
    let parent = app
        .world_mut()
        .spawn(Transform::from_xyz(0.0, 5.0, 0.0).with_scale(Vec3::ZERO))
        .id();
    let sphere = child(&mut app, parent, 0.1, Vec3::new(3.0, 0.0, 0.0));
    for _ in 0..10 {
        app.update();
    }
    // Its place was the parent's (the scale takes its translation to nothing): it fell from
    // there. No `Transform` can draw it (the parent's frame has no inverse); the one it has
    // is left as it was, finite.
    let at = position(&app, sphere);
    assert!(at.x == 0.0 && at.y < 5.0, "at {at}");
    let transform = app.world().get::<Transform>(sphere).unwrap();
    assert!(transform.translation.is_finite());
}

#[test]
fn a_parent_turned_and_scaled_unevenly_draws_its_sphere_at_its_place() {
    // Turned about a slanted axis and scaled differently along each: the frame shears.
    let mut app = app(SpherePhysicsPlugin::default().interpolate(false));
    let parent = app
        .world_mut()
        .spawn(
            Transform::from_xyz(-3.0, 4.0, 1.0)
                .with_rotation(Quat::from_axis_angle(
                    Vec3::new(1.0, 2.0, 3.0).normalize(),
                    0.7,
                ))
                .with_scale(Vec3::new(0.5, 2.0, 3.0)),
        )
        .id();
    let sphere = child(&mut app, parent, 0.1, Vec3::new(1.0, -1.0, 0.5));
    app.update();
    app.update();
    // Where Bevy puts the sphere's own origin under that parent.
    let expected = (Transform::from_xyz(-3.0, 4.0, 1.0)
        .with_rotation(Quat::from_axis_angle(
            Vec3::new(1.0, 2.0, 3.0).normalize(),
            0.7,
        ))
        .with_scale(Vec3::new(0.5, 2.0, 3.0))
        .to_matrix()
        .transform_point3(Vec3::new(1.0, -1.0, 0.5)))
    .as_dvec3();
    let joined = position(&app, sphere);
    assert!(
        (joined - expected).length() < 1e-5,
        "{joined} against {expected}"
    );
    app.world_mut().get_mut::<SphereVelocity>(sphere).unwrap().0 = DVec3::new(1.0, 0.5, -2.0);
    for _ in 0..20 {
        app.update();
        assert_drawn_at_its_place(&app, sphere);
    }
}

#[test]
fn a_sphere_taken_off_its_parent_in_update_is_drawn_at_its_place_that_frame() {
    #[derive(Resource, Default)]
    struct TakeOff(Option<Entity>);
    let mut app = app(SpherePhysicsPlugin::default().interpolate(false));
    app.init_resource::<TakeOff>().add_systems(
        Update,
        |mut commands: Commands, mut take_off: ResMut<TakeOff>| {
            if let Some(sphere) = take_off.0.take() {
                commands.entity(sphere).remove::<ChildOf>();
            }
        },
    );
    let parent = app.world_mut().spawn(turned_parent()).id();
    let sphere = child(&mut app, parent, 0.1, Vec3::new(0.0, 1.0, 0.0));
    for _ in 0..3 {
        app.update();
    }
    assert_drawn_at_its_place(&app, sphere);
    app.world_mut().resource_mut::<TakeOff>().0 = Some(sphere);
    app.update();
    assert!(app.world().get::<ChildOf>(sphere).is_none());
    assert_drawn_at_its_place(&app, sphere);
}

#[test]
fn regression_a_rejected_child_of_a_moving_parent_is_reported_once() {
    // Rejected once for its radius; its parent, moved at every frame, changes where it would
    // join, which is not a change of the sphere's own (it was reported again at every step).
    let mut app = app(SpherePhysicsPlugin::default());
    app.init_resource::<Reports>().add_systems(
        Update,
        (
            |mut carts: Query<&mut Transform, With<Cart>>| {
                for mut cart in &mut carts {
                    cart.translation.x += 0.25;
                }
            },
            count_reports,
        ),
    );
    let cart = app.world_mut().spawn((Cart, Transform::default())).id();
    let sphere = child(&mut app, cart, -1.0, Vec3::new(0.0, 1.0, 0.0));
    for _ in 0..20 {
        app.update();
    }
    assert_eq!(app.world().resource::<Reports>().0, 1);
    assert!(app.world().get::<RejectedSphere>(sphere).is_some());
    // Mended, it joins where its parent has taken it.
    app.world_mut()
        .get_mut::<SphereBody>(sphere)
        .unwrap()
        .radius = 0.1;
    for _ in 0..3 {
        app.update();
    }
    assert!(app.world().get::<RejectedSphere>(sphere).is_none());
    assert!(position(&app, sphere).x > 4.0);
}

#[test]
fn a_sphere_under_a_disabled_parent_joins_through_that_parent() {
    // Bevy's `Disabled` hides the parent from queries, not from its children: the sphere, not
    // disabled, joins where the parent's `Transform` puts it (it joined at its translation
    // read as a place in the world, as if it had no parent).
    let mut app = app(SpherePhysicsPlugin::default());
    let parent = app
        .world_mut()
        .spawn((
            Transform::from_xyz(5.0, 0.0, 0.0),
            bevy::ecs::entity_disabling::Disabled,
        ))
        .id();
    let sphere = child(&mut app, parent, 0.1, Vec3::new(0.0, 1.0, 0.0));
    for _ in 0..3 {
        app.update();
    }
    assert_eq!(position(&app, sphere), DVec3::new(5.0, 1.0, 0.0));
}

#[test]
fn regression_a_child_refused_for_its_string_joins_when_its_parent_brings_it_in_reach() {
    // Refused because its parent put it beyond its string (a refusal of its place): tried
    // again as the parent moves, reported once, and taken once the parent brings it within
    // the string's length.
    let mut app = app(SpherePhysicsPlugin::default());
    app.init_resource::<Reports>().add_systems(
        Update,
        (
            |mut carts: Query<&mut Transform, With<Cart>>| {
                for mut cart in &mut carts {
                    cart.translation.x = (cart.translation.x + 0.25).min(3.0);
                }
            },
            count_reports,
        ),
    );
    let cart = app.world_mut().spawn((Cart, Transform::default())).id();
    let sphere = app
        .world_mut()
        .spawn((
            SphereBody::new(0.1),
            Transform::from_xyz(0.0, 1.0, 0.0),
            Tethered {
                anchor: DVec3::new(3.0, 1.5, 0.0),
                length: 0.6,
            },
            ChildOf(cart),
        ))
        .id();
    app.update();
    app.update();
    assert!(app.world().get::<RejectedSphere>(sphere).is_some());
    for _ in 0..20 {
        app.update();
    }
    assert_eq!(app.world().resource::<Reports>().0, 1);
    assert!(app.world().get::<RejectedSphere>(sphere).is_none());
    let at = position(&app, sphere);
    assert!(
        (at - DVec3::new(3.0, 1.5, 0.0)).length() <= 0.6,
        "joined at {at}"
    );
}
