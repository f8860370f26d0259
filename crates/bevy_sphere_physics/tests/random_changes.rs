//! What a game may do to its spheres, done at random between frames: spawn and despawn them,
//! change, add and remove their components (good values and bad), disable them, pause, single
//! step, reset the simulation with new settings (sleeping on or off); and the same, but for
//! teleports, by a game system that runs between `Prepare` and `Step` (one in `FixedUpdate`
//! with no order against the plugin's sets may run there). Spheres are also put under carts
//! (entities with a `Transform`, moved, turned, scaled and despawned at random, from a random
//! stream of their own) and taken off them. Nothing may panic; after every frame each body in
//! the core belongs to a live, enabled, unrejected sphere entity and each such entity has its
//! body, positions and transforms are finite, each is drawn (its `GlobalTransform`) between its
//! last two positions, the diagnostics count what the core holds, and the same frames give the
//! same spheres, bit for bit. (Despawning a floor under a resting ball once crashed the next
//! step.)

use std::time::Duration;

use bevy::ecs::entity_disabling::Disabled;
use bevy::ecs::query::Allow;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_sphere_physics::prelude::*;
use bevy_sphere_physics::sphere_physics::Settings;
use bevy_sphere_physics::{ResetSpherePhysics, SpherePhysicsWorld};

/// 1/64 s, as the plugin's tests use.
const STEP: Duration = Duration::from_nanos(15_625_000);

/// xorshift64*: a small generator, so a failing seed repeats.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in `[lo, hi)`.
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }

    fn chance(&mut self, p: f64) -> bool {
        self.range(0.0, 1.0) < p
    }

    /// Mostly in `[lo, hi)`, now and then NaN, infinite, negative or zero.
    fn value(&mut self, lo: f64, hi: f64) -> f64 {
        match self.below(64) {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => -1.0,
            3 => 0.0,
            _ => self.range(lo, hi),
        }
    }

    fn vector(&mut self, scale: f64) -> DVec3 {
        DVec3::new(
            self.range(-scale, scale),
            self.range(-scale, scale),
            self.range(-scale, scale),
        )
    }

    /// Now and then with a component that is not finite.
    fn maybe_bad_vector(&mut self, scale: f64) -> DVec3 {
        let v = self.vector(scale);
        match self.below(48) {
            0 => DVec3::new(f64::NAN, v.y, v.z),
            1 => DVec3::new(v.x, f64::INFINITY, v.z),
            _ => v,
        }
    }
}

fn app(sleep: bool) -> App {
    let mut plugin = SpherePhysicsPlugin::default().gravity(DVec3::NEG_Y * 9.81);
    if sleep {
        plugin = plugin.sleep(Sleep {
            speed: 0.2,
            time: 0.25,
        });
    }
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, bevy::transform::TransformPlugin, plugin))
        .insert_resource(Time::<Fixed>::from_duration(STEP))
        .insert_resource(TimeUpdateStrategy::ManualDuration(STEP));
    app
}

/// A pit 0.6 m across (a floor and four walls, fixed spheres of radius 1e4), and balls over
/// it.
fn spawn_scene(app: &mut App, rng: &mut Rng) {
    let (wall, half) = (1.0e4, 0.3);
    for at in [
        DVec3::new(0.0, -wall, 0.0),
        DVec3::new(-wall - half, 0.0, 0.0),
        DVec3::new(wall + half, 0.0, 0.0),
        DVec3::new(0.0, 0.0, -wall - half),
        DVec3::new(0.0, 0.0, wall + half),
    ] {
        app.world_mut()
            .spawn((SphereBody::new(wall), SpherePosition(at), FixedSphere));
    }
    for _ in 0..12 + rng.below(24) {
        let at = DVec3::new(
            rng.range(-0.2, 0.2),
            rng.range(0.05, 1.5),
            rng.range(-0.2, 0.2),
        );
        app.world_mut()
            .spawn((SphereBody::new(0.05), SpherePosition(at)));
    }
}

/// The sphere entities, in entity order.
fn spheres(world: &mut World) -> Vec<Entity> {
    let mut all: Vec<Entity> = world
        .query_filtered::<Entity, (With<SphereBody>, Allow<Disabled>)>()
        .iter(world)
        .collect();
    all.sort();
    all
}

/// A string from above `at` (now and then of a bad length, or too short to reach).
fn tether(rng: &mut Rng, at: DVec3) -> Tethered {
    let length = rng.value(0.3, 2.0);
    let reach = if length.is_finite() { length } else { 1.0 };
    Tethered {
        anchor: at + DVec3::Y * reach * rng.range(0.5, 1.02),
        length,
    }
}

/// Adds the marker `C` if the entity lacks it, removes it if not.
fn toggle<C: Component + Default>(entity: &mut EntityWorldMut) {
    if entity.contains::<C>() {
        entity.remove::<C>();
    } else {
        entity.insert(C::default());
    }
}

/// One random thing a game does between frames, or (`mid_step`) between `Prepare` and `Step`:
/// there, not a teleport (a position set after `Prepare` is kept for the next step, so the
/// sphere's component and its body differ until then, as `check` does not allow).
fn change(world: &mut World, rng: &mut Rng, mid_step: bool) {
    let all = spheres(world);
    let target = (!all.is_empty()).then(|| all[rng.below(all.len() as u64) as usize]);
    match (rng.below(20), target) {
        (0..=3, _) => {
            let at = DVec3::new(
                rng.range(-0.2, 0.2),
                rng.range(0.0, 1.5),
                rng.range(-0.2, 0.2),
            );
            let mut sphere = world.spawn((
                SphereBody::new(rng.value(0.03, 0.12)),
                SpherePosition(at),
                SphereVelocity(rng.maybe_bad_vector(2.0)),
            ));
            if rng.chance(0.3) {
                sphere.insert(Density(rng.value(0.5, 20.0)));
            }
            if rng.chance(0.3) {
                sphere.insert(Restitution(rng.value(0.0, 1.0)));
            }
            if rng.chance(0.1) {
                sphere.insert(FixedSphere);
            }
            if rng.chance(0.1) {
                sphere.insert(tether(rng, at));
            }
        }
        (4..=5, Some(e)) => {
            world.despawn(e);
        }
        (6, Some(e)) => {
            if let Some(mut v) = world.get_mut::<SphereVelocity>(e) {
                v.0 = rng.maybe_bad_vector(3.0);
            }
        }
        (7, Some(e)) if !mid_step => {
            let at = rng.maybe_bad_vector(0.2) + DVec3::Y * 0.5;
            world.entity_mut(e).insert(SpherePosition(at));
        }
        (8, Some(e)) => {
            if let Some(mut body) = world.get_mut::<SphereBody>(e) {
                body.radius = rng.value(0.03, 0.12);
            }
        }
        (9, Some(e)) => {
            world.entity_mut(e).insert(Density(rng.value(0.5, 20.0)));
        }
        (10, Some(e)) => {
            world.entity_mut(e).insert(Restitution(rng.value(0.0, 1.0)));
        }
        (11, Some(e)) => {
            world
                .entity_mut(e)
                .insert(AppliedForce(rng.maybe_bad_vector(5.0)));
        }
        (12, Some(e)) => {
            toggle::<FixedSphere>(&mut world.entity_mut(e));
        }
        (13, Some(e)) => {
            let mut entity = world.entity_mut(e);
            if entity.contains::<Tethered>() {
                entity.remove::<Tethered>();
            } else {
                let at = entity.get::<SpherePosition>().map_or(DVec3::ZERO, |p| p.0);
                entity.insert(tether(rng, at));
            }
        }
        (14, Some(e)) => {
            let mut entity = world.entity_mut(e);
            match rng.below(4) {
                0 => entity.remove::<SphereVelocity>(),
                1 => entity.remove::<Density>(),
                2 => entity.remove::<AppliedForce>(),
                _ => entity.remove::<Restitution>(),
            };
        }
        (15, Some(e)) => {
            toggle::<Disabled>(&mut world.entity_mut(e));
        }
        (16, _) if rng.chance(0.3) => {
            // Paused now and then, for a few frames: a step or two, then on again.
            let mut clock = world.resource_mut::<SpherePhysicsClock>();
            if !clock.paused || rng.chance(0.5) {
                clock.toggle();
            } else {
                clock.step_once();
            }
        }
        (17, _) if rng.chance(0.1) => {
            let mut settings = Settings::with_gravity(DVec3::NEG_Y * 9.81);
            if rng.chance(0.6) {
                settings.sleep = Some(Sleep::default());
            }
            if rng.chance(0.2) {
                settings.substeps = 1 + rng.below(3) as u32;
            }
            world.commands().queue(ResetSpherePhysics::new(settings));
            world.flush();
        }
        _ => {}
    }
}

/// An entity spheres are put under (`ChildOf`).
#[derive(Component)]
struct Cart;

/// The carts, in entity order.
fn carts(world: &mut World) -> Vec<Entity> {
    let mut all: Vec<Entity> = world
        .query_filtered::<Entity, With<Cart>>()
        .iter(world)
        .collect();
    all.sort();
    all
}

/// A cart's place: moved, turned and scaled (0.5 to 2 times).
fn cart_place(rng: &mut Rng) -> Transform {
    let turn = rng.vector(1.0).normalize_or(DVec3::Y).as_vec3();
    Transform::from_translation(rng.vector(0.3).as_vec3())
        .with_rotation(Quat::from_axis_angle(turn, rng.range(0.0, 6.3) as f32))
        .with_scale(Vec3::splat(rng.range(0.5, 2.0) as f32))
}

/// One random thing a game does with carts between frames: a sphere put under one (a new cart
/// now and then) or taken off its own, or a cart moved or (one time in ten) despawned, its
/// spheres with it (Bevy despawns an entity's children).
fn change_carts(world: &mut World, rng: &mut Rng) {
    let carts = carts(world);
    let all = spheres(world);
    if rng.chance(0.5) && !all.is_empty() {
        let e = all[rng.below(all.len() as u64) as usize];
        if world.get::<ChildOf>(e).is_some() {
            world.entity_mut(e).remove::<ChildOf>();
        } else {
            let cart = if carts.is_empty() || rng.chance(0.3) {
                world.spawn((Cart, cart_place(rng))).id()
            } else {
                carts[rng.below(carts.len() as u64) as usize]
            };
            world.entity_mut(e).insert(ChildOf(cart));
        }
    } else if !carts.is_empty() {
        let cart = carts[rng.below(carts.len() as u64) as usize];
        if rng.chance(0.1) {
            world.despawn(cart);
        } else {
            *world.get_mut::<Transform>(cart).unwrap() = cart_place(rng);
        }
    }
}

/// A sphere's state as a frame left it: its entity, position and velocity, to the bit (a
/// velocity set to NaN after `Prepare` stays on its sphere until the next step rejects it).
type State = (Entity, [u64; 3], [u64; 3]);

/// The state after a frame, checked.
fn check(app: &mut App) -> Vec<State> {
    let all = spheres(app.world_mut());
    let physics = app.world().resource::<SpherePhysicsWorld>();
    for body in physics.world.bodies() {
        let entity = physics
            .entity(body.id())
            .unwrap_or_else(|| panic!("body {:?} has no entity", body.id()));
        let e = app
            .world()
            .get_entity(entity)
            .unwrap_or_else(|_| panic!("body {:?}'s entity {entity} is gone", body.id()));
        assert!(e.contains::<SphereBody>(), "{entity}");
        assert!(!e.contains::<RejectedSphere>(), "{entity}");
        assert!(!e.contains::<Disabled>(), "{entity}");
        assert_eq!(physics.body(entity), Some(body.id()));
        assert!(body.position().is_finite() && body.velocity().is_finite());
        if body.is_asleep() {
            assert_eq!(body.velocity(), DVec3::ZERO);
        }
    }
    let mut state = Vec::new();
    for entity in all {
        let e = app.world().entity(entity);
        let Some(body) = physics.body(entity) else {
            continue;
        };
        assert!(!e.contains::<RejectedSphere>(), "{entity}");
        assert!(!e.contains::<Disabled>(), "{entity}");
        let in_core = physics.world.body(body).unwrap();
        let transform = e.get::<Transform>().unwrap();
        assert!(transform.translation.is_finite(), "{entity}: {transform:?}");
        let at = e.get::<SpherePosition>().unwrap().0;
        assert_eq!(at, in_core.position(), "{entity}");
        // Drawn between its last two positions (interpolated, or at the last one), to `f32`
        // rounding, under a cart or not.
        let drawn = e.get::<GlobalTransform>().unwrap().translation().as_dvec3();
        let previous = e.get::<PreviousSpherePosition>().unwrap().0;
        let (along, from) = (at - previous, drawn - previous);
        let t = (from.dot(along) / along.length_squared()).clamp(0.0, 1.0);
        let off = (previous + along * if t.is_finite() { t } else { 0.0 } - drawn).length();
        let rounding = 1e-6 * (1.0 + at.abs().max_element() + previous.abs().max_element());
        assert!(
            off <= rounding,
            "{entity} drawn at {drawn}, {off} m off its path from {previous} to {at}"
        );
        let v = e.get::<SphereVelocity>().map_or(DVec3::ZERO, |v| v.0);
        state.push((
            entity,
            at.to_array().map(f64::to_bits),
            v.to_array().map(f64::to_bits),
        ));
    }
    state
}

/// 70 balls resting 30 cm apart on a fixed sphere of radius 1 km whose top is 100 km above
/// the pit (beyond its walls): asleep soon, so that a step leaves them out (64 asleep or
/// more), and `Writeback` looks only at what the step took.
fn spawn_bed(app: &mut App) {
    let top = 1.0e5;
    app.world_mut().spawn((
        SphereBody::new(1.0e3),
        SpherePosition(DVec3::new(0.0, top - 1.0e3, 0.0)),
        FixedSphere,
    ));
    for i in 0..70 {
        let (x, z) = (
            f64::from(i % 10) * 0.3 - 1.35,
            f64::from(i / 10) * 0.3 - 0.9,
        );
        // On the sphere's surface, not into it.
        let y = top - 1.0e3 + ((1.0e3f64 + 0.05).powi(2) - (x * x + z * z)).sqrt();
        app.world_mut().spawn((
            SphereBody::new(0.05),
            SpherePosition(DVec3::new(x, y + 1e-9, z)),
        ));
    }
}

/// The random stream of the game system that changes spheres between `Prepare` and `Step`.
#[derive(Resource)]
struct MidStep(Rng);

/// Now and then (one fixed step in forty) a random change between `Prepare` and `Step`.
fn change_mid_step(world: &mut World) {
    let mut rng = std::mem::replace(&mut world.resource_mut::<MidStep>().0, Rng(1));
    if rng.chance(1.0 / 40.0) {
        change(world, &mut rng, true);
    }
    world.resource_mut::<MidStep>().0 = rng;
}

fn play(seed: u64, frames: u32) -> Vec<Vec<State>> {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let sleep = rng.chance(0.6);
    let mut app = app(sleep);
    // The carts' own stream: the other changes are drawn as they were before carts came in
    // (the sixty-second session), so that the seeds keep their scenes.
    let mut carts = Rng(seed.wrapping_mul(0xD1B5_4A32_D192_ED03) | 1);
    app.insert_resource(MidStep(Rng(rng.next() | 1)))
        .add_systems(
            FixedUpdate,
            change_mid_step
                .after(SpherePhysicsSystems::Prepare)
                .before(SpherePhysicsSystems::Step),
        );
    spawn_scene(&mut app, &mut rng);
    if sleep {
        spawn_bed(&mut app);
    }
    let mut states = Vec::new();
    for _ in 0..frames {
        // A change every third frame or so, to let the spheres settle (and fall asleep).
        if rng.chance(0.35) {
            change(app.world_mut(), &mut rng, false);
        }
        if carts.chance(0.2) {
            change_carts(app.world_mut(), &mut carts);
        }
        let mut clock = app.world_mut().resource_mut::<SpherePhysicsClock>();
        if clock.paused && rng.chance(0.2) {
            clock.toggle();
        }
        for _ in 0..1 + rng.below(6) {
            app.update();
        }
        states.push(check(&mut app));
    }
    states
}

/// Seeds 0 to 5; `RANDOM_CHANGES_FROM` and `RANDOM_CHANGES_SEEDS` run others.
#[test]
fn random_changes_between_frames_are_safe_and_repeat() {
    let env = |name: &str, default: u64| {
        std::env::var(name)
            .ok()
            .and_then(|n| n.parse().ok())
            .unwrap_or(default)
    };
    let from = env("RANDOM_CHANGES_FROM", 0);
    for seed in from..from + env("RANDOM_CHANGES_SEEDS", 6) {
        let first = play(seed, 600);
        let second = play(seed, 600);
        assert!(first == second, "seed {seed}: two runs differ");
    }
}
