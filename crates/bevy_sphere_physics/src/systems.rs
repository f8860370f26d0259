//! The plugin's systems: copy components into the core, step it, copy results out, tell the
//! game what collided, and interpolate transforms between fixed steps.

use std::time::Instant;

use bevy::ecs::change_detection::Tick;
use bevy::ecs::entity_disabling::Disabled;
use bevy::ecs::query::Allow;
use bevy::ecs::system::SystemChangeTick;
use bevy::math::DVec3;
use bevy::prelude::*;
use sphere_physics::{Body, BodyId, Field, SphereDesc, Tether, WorldError};

use crate::components::*;
use crate::events::{SphereCollision, SphereHit, SphereRejected};
use crate::hierarchy::{MAX_DEPTH, Places, frame_of, local_translation};
use crate::resources::{
    SpherePhysicsClock, SpherePhysicsDiagnostics, SpherePhysicsWorld, SphereShownTime,
};

/// Plugin-wide options the systems read.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub(crate) struct PluginOptions {
    pub restitution: f64,
    pub interpolate: bool,
}

/// Spheres whose `SphereBody` was removed (or that were despawned) since the last `Prepare`,
/// recorded by an observer so none is missed on frames without a fixed step.
#[derive(Resource, Debug, Default)]
pub(crate) struct RemovedSpheres(pub Vec<Entity>);

/// Records a removed sphere for the next `Prepare`.
pub(crate) fn record_removal(removed: On<Remove, SphereBody>, mut queue: ResMut<RemovedSpheres>) {
    queue.0.push(removed.entity);
}

/// What the next `Prepare` must look at besides the spheres whose components changed:
/// every sphere (at the start), and the entities a component a sphere's description reads (or
/// `Disabled`) was removed from (a removed component means its default, and an enabled sphere
/// joins again). Recorded by an observer, as removals are, so none is missed on frames without
/// a fixed step; a despawned entity is recorded too, and passed over.
#[derive(Resource, Debug)]
pub(crate) struct RescanSpheres {
    /// Every sphere.
    pub all: bool,
    /// The entities a component was removed from.
    pub entities: Vec<Entity>,
}

impl Default for RescanSpheres {
    fn default() -> Self {
        Self {
            all: true,
            entities: Vec::new(),
        }
    }
}

/// Asks the next `Prepare` to look at the entity a component was removed from (see
/// [`RescanSpheres`]).
#[allow(clippy::type_complexity)]
pub(crate) fn record_part_removal(
    removed: On<
        Remove,
        (
            SpherePosition,
            PreviousSpherePosition,
            SphereVelocity,
            Density,
            Restitution,
            AppliedForce,
            FixedSphere,
            Tethered,
            NeverSleeps,
            Disabled,
        ),
    >,
    mut rescan: ResMut<RescanSpheres>,
) {
    rescan.entities.push(removed.entity);
}

/// The spheres `Prepare` must look at when nothing else has changed: those whose components
/// were added or changed since its last run (by the game, or by `Writeback` for the spheres
/// that moved), the `Transform` among them for a sphere it places (one without a
/// `SpherePosition`: not yet joined, or rejected when it joined). An asleep sphere, which
/// `Writeback` leaves alone, is not among them.
type ChangedSphere = (
    With<SphereBody>,
    Or<(
        (Changed<Transform>, Without<SpherePosition>),
        Changed<SpherePosition>,
        Changed<SphereVelocity>,
        Changed<SphereBody>,
        Changed<Density>,
        Changed<Restitution>,
        Changed<AppliedForce>,
        Changed<FixedSphere>,
        Changed<Tethered>,
        Changed<NeverSleeps>,
    )>,
);

/// Spheres the last `Step` left out (they would have left the finite range), reported by the
/// next `Prepare`: `SphereRejected` messages are all written there, so a game system that
/// reads them needs no order against `Step`.
#[derive(Resource, Debug, Default)]
pub(crate) struct RunawaySpheres(pub Vec<SphereRejected>);

/// The tick at which `Prepare` last ran: a sphere's velocity or position changed after it was
/// changed by a game system that `Prepare` did not see, and `Writeback` leaves it for the next
/// `Prepare` to apply.
#[derive(Resource, Clone, Copy, Debug, Default)]
pub(crate) struct PreparedAt(pub Tick);

/// Whether the last fixed step stepped the physics (false while paused).
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Stepped(pub bool);

/// The components of one sphere, as the core sees them. Those a sphere is spawned with by
/// default are optional here: a game that removes one (its force, say) means its default, and
/// the sphere must not drop out of view while its body keeps the old value.
type SphereQuery<'a> = (
    Entity,
    &'a SphereBody,
    Option<&'a Transform>,
    Option<&'a SpherePosition>,
    Option<&'a SphereVelocity>,
    Option<&'a Density>,
    Option<&'a Restitution>,
    Option<&'a AppliedForce>,
    Has<FixedSphere>,
    Option<&'a Tethered>,
    Option<&'a RejectedSphere>,
    Option<&'a Name>,
    Option<Ref<'a, SphereHandle>>,
    Has<PreviousSpherePosition>,
    Has<NeverSleeps>,
);

/// The description `item`'s components give. A body's state (its position and velocity) whose
/// component is missing keeps `current`'s value (none yet: the origin, at rest): that state is
/// the plugin's output, and a game that removes the component has not asked for it to change.
fn describe(
    item: &SphereQueryItem,
    options: &PluginOptions,
    current: Option<&Body>,
    places: &Places,
) -> SphereDesc {
    let (
        entity,
        body,
        transform,
        position,
        velocity,
        density,
        restitution,
        force,
        fixed,
        tether,
        _,
        name,
        _,
        _,
        never_sleeps,
    ) = item;
    let tether = tether.map(|t| Tether {
        anchor: t.anchor,
        length: t.length,
    });
    let position = match (position, current, transform) {
        (Some(p), _, _) => p.0,
        (None, Some(body), _) => body.position(),
        (None, None, Some(transform)) => on_string(places.place(*entity, transform), tether),
        (None, None, None) => DVec3::ZERO,
    };
    SphereDesc {
        name: Some(match name {
            Some(name) => format!("{name} ({entity})"),
            None => format!("entity {entity}"),
        }),
        position,
        velocity: velocity.map_or(current.map_or(DVec3::ZERO, Body::velocity), |v| v.0),
        radius: body.radius,
        density: density.copied().unwrap_or_default().0,
        restitution: restitution.map_or(options.restitution, |r| r.0),
        force: force.map_or(DVec3::ZERO, |f| f.0),
        fixed: *fixed,
        tether,
        never_sleeps: *never_sleeps,
    }
}

/// A start position read from a `Transform` (single precision): a sphere placed at its
/// string's length may have rounded to just outside it, which the core refuses; within that
/// rounding it is put back on the string.
fn on_string(position: DVec3, tether: Option<Tether>) -> DVec3 {
    let Some(tether) = tether else {
        return position;
    };
    let r = position - tether.anchor;
    let distance = r.length();
    let rounding = f64::from(f32::EPSILON) * position.abs().max_element().max(1.0);
    if distance > tether.length && distance - tether.length <= rounding {
        tether.anchor + r * (tether.length / distance)
    } else {
        position
    }
}

type SphereQueryItem<'a> = <SphereQuery<'a> as bevy::ecs::query::QueryData>::Item<'a, 'a>;

/// Whether the body still matches its components (exactly: the plugin writes the core's own
/// values back, so any difference is a change made by the game).
fn matches(body: &Body, item: &SphereQueryItem, options: &PluginOptions) -> bool {
    let (_, _, _, position, velocity, _, _, force, _, _, _, _, _, _, _) = item;
    position.is_none_or(|p| p.0 == body.position())
        && velocity.is_none_or(|v| v.0 == body.velocity())
        && force.map_or(DVec3::ZERO, |f| f.0) == body.force()
        && same_shape(body, item, options)
}

/// Whether the body's radius, density, restitution, fixedness, string and `never_sleeps` still
/// match its components: if so, only its position, velocity or force can have changed.
fn same_shape(body: &Body, item: &SphereQueryItem, options: &PluginOptions) -> bool {
    let (_, sphere, _, _, _, density, restitution, _, fixed, tether, _, _, _, _, never_sleeps) =
        item;
    sphere.radius == body.radius()
        && density.copied().unwrap_or_default().0 == body.density()
        && restitution.map_or(options.restitution, |r| r.0) == body.restitution()
        && *fixed == body.is_fixed()
        && *never_sleeps == body.desc().never_sleeps
        && tether.map(|t| (t.anchor, t.length)) == body.desc().tether.map(|t| (t.anchor, t.length))
}

/// A game steering a sphere (its velocity, force or position set every step): those set in
/// the core one by one, with no new description (and no name formatted for it). `false` if
/// one is refused: the caller then rebuilds the whole description, which reports it.
fn steer(world: &mut sphere_physics::World, id: BodyId, item: &SphereQueryItem) -> bool {
    let (_, _, _, position, velocity, _, _, force, _, _, _, _, _, _, _) = item;
    let Some(body) = world.body(id) else {
        return false;
    };
    let (p, v, f) = (body.position(), body.velocity(), body.force());
    let force = force.map_or(DVec3::ZERO, |f| f.0);
    position.is_none_or(|wanted| wanted.0 == p || world.set_position(id, wanted.0).is_ok())
        && velocity.is_none_or(|wanted| wanted.0 == v || world.set_velocity(id, wanted.0).is_ok())
        && (force == f || world.set_force(id, force).is_ok())
}

/// Whether `a` and `b` describe the same sphere, bit for bit, with NaN equal to NaN (a sphere
/// rejected for a NaN is still the same sphere). Checked for every rejected sphere at every
/// `Prepare`, so without allocating (comparing their `Debug` text took two strings each).
fn same_desc(a: &SphereDesc, b: &SphereDesc) -> bool {
    let same = |x: f64, y: f64| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan());
    let same3 = |x: DVec3, y: DVec3| same(x.x, y.x) && same(x.y, y.y) && same(x.z, y.z);
    // Every field named, so that a new one cannot be forgotten here.
    let SphereDesc {
        name,
        position,
        velocity,
        radius,
        density,
        restitution,
        force,
        fixed,
        tether,
        never_sleeps,
    } = a;
    *name == b.name
        && same3(*position, b.position)
        && same3(*velocity, b.velocity)
        && same(*radius, b.radius)
        && same(*density, b.density)
        && same(*restitution, b.restitution)
        && same3(*force, b.force)
        && *fixed == b.fixed
        && *never_sleeps == b.never_sleeps
        && match (tether, b.tether) {
            (None, None) => true,
            (Some(x), Some(y)) => same3(x.anchor, y.anchor) && same(x.length, y.length),
            _ => false,
        }
}

/// [`SpherePhysicsSystems::Prepare`](crate::SpherePhysicsSystems::Prepare): removes despawned
/// spheres, adds new ones, applies changes made by game systems, and rejects invalid ones.
#[allow(clippy::too_many_arguments)]
pub(crate) fn prepare(
    mut commands: Commands,
    mut physics: ResMut<SpherePhysicsWorld>,
    mut removed: ResMut<RemovedSpheres>,
    spheres: Query<SphereQuery>,
    changed: Query<SphereQuery, ChangedSphere>,
    mut rescan: ResMut<RescanSpheres>,
    options: Res<PluginOptions>,
    mut rejected: MessageWriter<SphereRejected>,
    orders: Query<&SphereOrder>,
    disabled: Query<Entity, (With<SphereBody>, With<Disabled>)>,
    mut runaways: ResMut<RunawaySpheres>,
    mut prepared: ResMut<PreparedAt>,
    places: Places,
    ticks: SystemChangeTick,
) {
    prepared.0 = ticks.this_run();
    // Every sphere is looked at while none is asleep (all that move are written back at
    // every step, and a plain scan is then the cheaper), when the core world was changed from
    // outside the plugin (a game's change to a body, undone here; a body removed, registered
    // again; a reset), or when the options changed; else only the spheres whose components
    // changed or lost one: the others still match their bodies (the plugin's own changes to
    // the world, here and in `Step`, do not count as changes to the resource).
    let every = std::mem::take(&mut rescan.all)
        | physics.is_changed()
        | options.is_changed()
        | (physics.world.stats().asleep == 0);
    let physics = physics.bypass_change_detection();
    // What a sphere is refused under (see `RejectedSphere::gravity`).
    let gravity = physics.world.settings().gravity;
    rejected.write_batch(runaways.0.drain(..));
    remove_bodies(physics, removed.0.iter().copied());
    for entity in removed.0.drain(..) {
        if spheres.contains(entity) {
            // Its `SphereBody` was inserted again since: a new sphere from its components,
            // which it keeps (registered below; until the fifty-sixth session they were
            // stripped after that, and its velocity lost a step).
            continue;
        }
        // The entity may live on without its `SphereBody`: its `Transform` is the game's
        // again (interpolation writes only spheres with a handle). A no-op if despawned.
        commands
            .entity(entity)
            .try_remove::<(SphereHandle, SpherePosition, PreviousSpherePosition)>();
    }
    // Disabled spheres (Bevy's `Disabled`: hidden from every other query) leave the
    // simulation, and join it again from where they were when enabled.
    remove_bodies(physics, disabled);
    let mut reject = |commands: &mut Commands,
                      entity: Entity,
                      desc: SphereDesc,
                      own: Option<SphereDesc>,
                      error| {
        warn!("sphere {entity} left out of the simulation: {error}");
        rejected.write(SphereRejected {
            entity,
            error: Clone::clone(&error),
        });
        let gravity = refused_for_gravity(&desc, gravity).then_some(gravity);
        commands.entity(entity).try_insert(RejectedSphere {
            error,
            desc,
            own,
            gravity,
        });
    };
    // New spheres by `SphereOrder`, then entity: ids never depend on query order.
    let mut new = Vec::new();
    // Spheres rejected by this run as they were changed: not looked at again in it (a sphere
    // both changed and listed for a removal would be taken as new the second time, its
    // handle's removal not yet applied, and reported twice).
    let mut rejected_now: Vec<Entity> = Vec::new();
    // What is done for each sphere looked at, in either scan (a macro: as a closure called
    // for each, or with the two scans chained into one loop, a scene of 3000 moving spheres
    // took 15% and 75% longer).
    macro_rules! look_at {
        ($item:expr) => {{
            let item = $item;
            let entity = item.0;
            if rejected_now.contains(&entity) {
                continue;
            }
            // A handle is trusted if it was put on this entity (one copied onto another, by
            // cloning the entity, is not) and, if it changed since the last `Prepare` (put on
            // then, or by the game, or left by a reset that ran before a handle put on for the
            // old world), if the map of entities agrees; an older one can outlive its body
            // (the entity removed and re-added), which `body` below finds gone. (The map
            // asked for every sphere at every step was a tenth of the plugin's time.)
            let handle = item.12.as_ref().map(|h| {
                let own = h.1 == entity
                    && (!h.is_changed() || physics.entities.get(&h.0) == Some(&entity));
                (h.0, own)
            });
            let trusted = handle.and_then(|(id, own)| own.then_some(id));
            match trusted.or_else(|| physics.bodies.get(&entity).copied()) {
                Some(id) => {
                    let Some(body) = physics.world.body(id) else {
                        // Removed from the core (by the game, or by the plugin while the
                        // entity was away): register it anew.
                        physics.bodies.remove(&entity);
                        physics.entities.remove(&id);
                        new.push(entity);
                        continue;
                    };
                    if handle != Some((id, true)) {
                        // A handle not its own, or none: its own put back.
                        commands.entity(entity).try_insert(SphereHandle(id, entity));
                    }
                    match item.3 {
                        // Its `SpherePosition` was removed: the plugin's output, put back (the
                        // body stays where the core has it).
                        None => {
                            commands.entity(entity).try_insert((
                                SpherePosition(body.position()),
                                PreviousSpherePosition(body.position()),
                            ));
                        }
                        // Its `PreviousSpherePosition` was removed: put back (at its position,
                        // so it is not shown sliding there).
                        Some(position) if !item.13 => {
                            commands
                                .entity(entity)
                                .try_insert(PreviousSpherePosition(position.0));
                        }
                        Some(_) => {}
                    }
                    if matches(body, &item, &options) {
                        continue;
                    }
                    if same_shape(body, &item, &options) && steer(&mut physics.world, id, &item) {
                        continue;
                    }
                    let Some(body) = physics.world.body(id) else {
                        continue;
                    };
                    // Where a removed `SpherePosition` is put back (above): what a retry reads.
                    let put_back = item.3.is_none().then(|| body.position());
                    let desc = describe(&item, &options, Some(body), &places);
                    if let Err(error) = physics.world.set_desc(id, desc.clone()) {
                        physics.world.remove_body(id);
                        physics.bodies.remove(&entity);
                        physics.entities.remove(&id);
                        commands.entity(entity).try_remove::<SphereHandle>();
                        if let sphere_physics::WorldError::Body(error) = error {
                            // Kept as the retry below describes it (with no body to take a
                            // missing state from, and the position put back), so that only a
                            // change of its components retries it.
                            let mut retried = describe(&item, &options, None, &places);
                            if let Some(position) = put_back {
                                retried.position = position;
                            }
                            reject(&mut commands, entity, retried, None, error);
                            rejected_now.push(entity);
                        }
                    }
                }
                None => new.push(entity),
            }
        }};
    }
    if every {
        rescan.entities.clear();
        for item in &spheres {
            look_at!(item);
        }
    } else {
        for item in &changed {
            look_at!(item);
        }
        // Those that lost a component (a sphere looked at twice matches its body the second
        // time, and a new one is listed once below); despawned ones are gone.
        for at in 0..rescan.entities.len() {
            let Ok(item) = spheres.get(rescan.entities[at]) else {
                continue;
            };
            look_at!(item);
        }
        rescan.entities.clear();
    }
    new.sort_unstable_by_key(|&e| (orders.get(e).map_or(u64::MAX, |o| o.0), e));
    new.dedup();
    for entity in new {
        let item = spheres.get(entity).expect("listed above");
        let desc = describe(&item, &options, None, &places);
        // A child placed by its `Transform`: its own description has its own translation,
        // where `desc` has the place its parent puts it at, which moves with the parent (such
        // a sphere, rejected, was reported again at every step its parent moved).
        let own = match (item.3, item.2) {
            (None, Some(transform)) if places.is_child(entity) => Some(SphereDesc {
                position: transform.translation.as_dvec3(),
                ..desc.clone()
            }),
            _ => None,
        };
        // Whether the sphere's own components are as they were when it was refused.
        let own_same = |r: &RejectedSphere| match (&r.own, &own) {
            (Some(then), Some(now)) => same_desc(then, now),
            (None, None) => same_desc(&r.desc, &desc),
            _ => false,
        };
        // Still the same invalid description: already reported (a child's refusal not of its
        // place, whatever its parent's place). Tried again if it was refused for its force's
        // sum with the world's gravity, and the gravity changed since (reported again only if
        // refused for another reason).
        let refused_as = item.10.filter(|r| {
            own_same(r)
                && (same_desc(&r.desc, &desc)
                    || (r.own.is_some()
                        && !matches!(r.error.field, Field::Position | Field::Tether)))
        });
        if refused_as.is_some_and(|r| r.gravity.is_none_or(|g| same_bits(g, gravity))) {
            continue;
        }
        match physics.world.add_sphere(desc.clone()) {
            Ok(id) => {
                physics.bodies.insert(entity, id);
                physics.entities.insert(id, entity);
                let mut e = commands.entity(entity);
                e.try_insert((
                    PreviousSpherePosition(desc.position),
                    SphereHandle(id, entity),
                ));
                if item.3.is_none() {
                    // Placed by its `Transform`. (One it has is left as it is: put on again
                    // here, it would overwrite a game's change made after `Prepare`.)
                    e.try_insert(SpherePosition(desc.position));
                }
                if item.10.is_some() {
                    e.try_remove::<RejectedSphere>();
                }
            }
            // Refused again for the same, its own components unchanged (gravity changed, or a
            // child's parent moved it): kept, not reported again.
            Err(error)
                if item.10.is_some_and(|r| {
                    own_same(r) && (r.error.field, r.error.reason) == (error.field, error.reason)
                }) =>
            {
                let gravity = match item.10.and_then(|r| r.gravity) {
                    Some(_) => Some(gravity),
                    None => refused_for_gravity(&desc, gravity).then_some(gravity),
                };
                commands.entity(entity).try_insert(RejectedSphere {
                    error,
                    desc,
                    own,
                    gravity,
                });
            }
            Err(error) => reject(&mut commands, entity, desc, own, error),
        }
    }
}

/// Spheres disabled since `Step` last ran (those disabled earlier are out already).
type JustDisabled = (With<SphereBody>, With<Disabled>, Added<Disabled>);

/// [`SpherePhysicsSystems::Step`](crate::SpherePhysicsSystems::Step): one core step of the fixed
/// timestep (integration, collision detection and response happen together inside it: the
/// core resolves collisions in time order between the integrator's kicks).
///
/// A step the core refuses because of one sphere (one that would leave the finite range) is
/// taken again without it: that sphere is rejected, as an invalid one is at `Prepare` (its
/// `SphereRejected` message is written by the next `Prepare`). A step
/// refused for any other reason (settings out of range, a zero time step) is skipped, counted
/// in [`SpherePhysicsDiagnostics::refused_steps`] and logged (once per distinct reason).
#[allow(clippy::too_many_arguments)]
pub(crate) fn step(
    mut commands: Commands,
    mut physics: ResMut<SpherePhysicsWorld>,
    mut clock: ResMut<SpherePhysicsClock>,
    mut stepped: ResMut<Stepped>,
    mut diagnostics: ResMut<SpherePhysicsDiagnostics>,
    mut runaways: ResMut<RunawaySpheres>,
    mut last_refusal: Local<Option<String>>,
    time: Res<Time<Fixed>>,
    removed: ResMut<RemovedSpheres>,
    disabled: Query<Entity, JustDisabled>,
) {
    // The plugin's own change: not one `Prepare` must look at every sphere for.
    let physics = physics.bypass_change_detection();
    // Spheres despawned (or no longer spheres) since `Prepare`, by a game system before this
    // one, are out of this step already (until the fifty-sixth session they still collided in
    // it, and the collision went unreported). `Prepare` does the rest for them, as for any
    // sphere removed. So are spheres disabled since (until the sixty-first session they
    // collided in it, unreported). Taken out while paused too, so that no body is left to an
    // entity gone or disabled.
    remove_bodies(physics, removed.0.iter().copied());
    remove_bodies(physics, disabled);
    stepped.0 = clock.take_step();
    if !stepped.0 {
        return;
    }
    let started = Instant::now();
    // Each retry leaves one sphere out, so this ends; the bound only caps one step's work.
    let mut result = physics.world.step(time.delta_secs_f64()).copied();
    for _ in 0..64 {
        let Err(WorldError::Body(error)) = &result else {
            break;
        };
        let Some(id) = error.id else {
            break;
        };
        let Some(body) = physics.world.remove_body(id) else {
            break;
        };
        let Some(entity) = physics.entities.remove(&id) else {
            // A body the game added to the core directly: out too, or every step would be
            // refused.
            warn!("body {id} (no entity) left out of the simulation: {error}");
            result = physics.world.step(time.delta_secs_f64()).copied();
            continue;
        };
        physics.bodies.remove(&entity);
        let gravity_now = physics.world.settings().gravity;
        warn!("sphere {entity} left out of the simulation: {error}");
        runaways.0.push(SphereRejected {
            entity,
            error: error.clone(),
        });
        commands
            .entity(entity)
            .try_remove::<SphereHandle>()
            .try_insert(RejectedSphere {
                error: error.clone(),
                desc: body.desc().clone(),
                own: None,
                // Tried again when gravity changes only if its force's sum with this gravity
                // is what ran away (a gravity the game set since it joined): else its motion
                // did, and its components must change.
                gravity: refused_for_gravity(body.desc(), gravity_now).then_some(gravity_now),
            });
        result = physics.world.step(time.delta_secs_f64()).copied();
    }
    let stats = match result {
        Ok(stats) => stats,
        Err(error) => {
            let reason = error.to_string();
            if last_refusal.as_ref() != Some(&reason) {
                error!("sphere physics: step refused: {reason}");
                *last_refusal = Some(reason);
            }
            diagnostics.refused_steps += 1;
            stepped.0 = false;
            return;
        }
    };
    *diagnostics = SpherePhysicsDiagnostics {
        last: stats,
        time: physics.world.time(),
        steps: physics.world.steps(),
        collisions: diagnostics.collisions + u64::from(stats.collisions),
        step_seconds: started.elapsed().as_secs_f64(),
        bodies: physics.world.len(),
        refused_steps: diagnostics.refused_steps,
    };
}

/// [`SpherePhysicsSystems::Writeback`](crate::SpherePhysicsSystems::Writeback): positions and
/// velocities back into the components (`f64`, exactly the core's values).
pub(crate) fn writeback(
    physics: Res<SpherePhysicsWorld>,
    stepped: Res<Stepped>,
    prepared: Res<PreparedAt>,
    ticks: SystemChangeTick,
    mut still: Local<bool>,
    mut written: Local<Written>,
    mut spheres: Query<(
        &SphereHandle,
        &mut SpherePosition,
        &mut PreviousSpherePosition,
        Option<&mut SphereVelocity>,
    )>,
) {
    // A step that moved nothing, after a `Writeback` that changed nothing (so every sphere's
    // last two positions are the same): every component already holds its body's values.
    // (A game's change before `Prepare` would have changed the world, and the step would not
    // be quiet; one after it is left as it is, as below.)
    let stats = physics.world.stats();
    if stepped.0 && stats.quiet && *still {
        return;
    }
    // With a sphere asleep, each component is written only if it changes (to the bit), so
    // that `Prepare` need not look at the spheres that did not move, nor a game system that
    // asks for changed positions; with none asleep, every one is written (comparing them
    // took a scene of 3000 moving spheres 40% longer here).
    let compare = stats.asleep > 0;
    // Changed after `Prepare` ran: by a game system that it did not see (one with no order
    // against the plugin's sets may run between them). Such a velocity or position is left as
    // the game set it, for the next `Prepare` to apply, not overwritten with the step's
    // result; a position `Prepare` itself put there is not the game's (a sphere that joined
    // by its `Transform`, or one whose position was removed, put back).
    let late = |tick: Tick| tick.is_newer_than(prepared.0, ticks.this_run());
    let mut wrote = !compare;
    // A step that left out the spheres asleep beyond the reach of what moves (see
    // `World::last_step_bodies`): only its own spheres are looked at, and those whose
    // position the last `Writeback` wrote (their previous position catches up), not every
    // sphere (a bed of 3000 asleep under a bouncing ball took 45 µs an update here).
    if stepped.0
        && compare
        && written.tracked
        && let Some(taken) = physics.world.last_step_bodies()
    {
        let mut last = std::mem::take(&mut written.entities);
        for &entity in &last {
            if let Ok((_, position, mut previous, _)) = spheres.get_mut(entity)
                && !same_bits(previous.0, position.0)
                && !moved_late(late, &position, previous.0)
            {
                previous.0 = position.0;
                wrote = true;
            }
        }
        last.clear();
        for id in taken {
            let Some(&entity) = physics.entities.get(id) else {
                continue;
            };
            let Some(body) = physics.world.body(*id) else {
                continue;
            };
            let Ok((_, position, previous, velocity)) = spheres.get_mut(entity) else {
                continue;
            };
            let (changed, moved) =
                write_sphere(body, (position, previous, velocity), true, true, late);
            wrote |= changed;
            if moved {
                last.push(entity);
            }
        }
        written.entities = last;
        *still = !wrote;
        return;
    }
    let tracked = compare && stepped.0;
    let mut moved_ones = std::mem::take(&mut written.entities);
    moved_ones.clear();
    for (handle, position, previous, velocity) in &mut spheres {
        let Some(body) = physics.world.body(handle.0) else {
            continue;
        };
        let id = handle.0;
        let (changed, moved) = write_sphere(
            body,
            (position, previous, velocity),
            compare,
            stepped.0,
            late,
        );
        wrote |= changed;
        if tracked
            && moved
            && let Some(&entity) = physics.entities.get(&id)
        {
            moved_ones.push(entity);
        }
    }
    *written = Written {
        entities: moved_ones,
        tracked,
    };
    *still = !wrote;
}

/// Whether a sphere is refused under `gravity` for its force's sum with it, and would be taken
/// without gravity (see [`RejectedSphere::gravity`]): a refusal a change of gravity may end.
/// (Asked of worlds of its own, with the core's own checks; only when a sphere is refused.)
fn refused_for_gravity(desc: &SphereDesc, gravity: DVec3) -> bool {
    let takes = |gravity| {
        sphere_physics::World::new(sphere_physics::Settings::with_gravity(gravity))
            .add_sphere(desc.clone())
            .is_ok()
    };
    !takes(gravity) && takes(DVec3::ZERO)
}

/// Takes the bodies of `entities` (spheres despawned, or that lost their `SphereBody`) out of
/// the world, if they are still in it, all at once (`World::remove_bodies`): removing a body
/// moves every body after it down one place, so thousands despawned together (a level left,
/// in the order they were spawned) moved the rest once each, in quadratic time (10 000: 314
/// ms); from the last body first, until the fifty-eighth session, 18 ms, but 0.2 to 0.3 s
/// for 40 000; at once, 1 to 6 ms. The world ends the same in any order.
fn remove_bodies(physics: &mut SpherePhysicsWorld, entities: impl IntoIterator<Item = Entity>) {
    // (No allocation unless a body is to go.)
    let ids: Vec<BodyId> = entities
        .into_iter()
        .filter_map(|entity| physics.bodies.remove(&entity))
        .collect();
    for id in &ids {
        physics.entities.remove(id);
    }
    physics.world.remove_bodies(&ids);
}

/// Whether a sphere's `position` was changed `late` by the game (see `writeback`): not when
/// `Prepare` put it there, as a sphere joined by its `Transform` or as the component came back,
/// with a `previous` position the same (added late, and still where it was put). (`Prepare`
/// changes a position it did not add only in its own run, not late. Until the fifty-fifth
/// session it put the position on again with a joining sphere's handle, and took any change
/// late in that step for its own, overwriting a game's; until the sixty-first it took a change
/// late in the step of such an addition for its own. The ticks cannot tell them apart: a game
/// system that runs just after `Prepare`'s commands are applied changes the position at the
/// tick they added it; so a position the game sets to exactly where the sphere joined is
/// taken for `Prepare`'s, and overwritten.)
#[inline(always)]
fn moved_late(
    late: impl Fn(Tick) -> bool,
    position: &Mut<SpherePosition>,
    previous: DVec3,
) -> bool {
    late(position.last_changed()) && (!late(position.added()) || !same_bits(position.0, previous))
}

/// What `writeback` keeps from one run to the next: the spheres whose position it wrote
/// (whose previous position must catch up at the next step), when it kept them.
#[derive(Default)]
pub(crate) struct Written {
    entities: Vec<Entity>,
    /// Whether `entities` holds every sphere whose position the last run wrote (it is not
    /// kept when every sphere is written).
    tracked: bool,
}

/// Writes one sphere's `body` into its components (see `writeback`): with `compare`, only
/// the values that change (to the bit); its position and velocity only if `stepped`, and
/// not one the game changed `late`. Returns whether it wrote anything (or left a late change
/// for the next step), and whether it wrote the position.
#[inline(always)]
fn write_sphere(
    body: &Body,
    (mut position, mut previous, velocity): (
        Mut<SpherePosition>,
        Mut<PreviousSpherePosition>,
        Option<Mut<SphereVelocity>>,
    ),
    compare: bool,
    stepped: bool,
    late: impl Fn(Tick) -> bool,
) -> (bool, bool) {
    let mut wrote = false;
    if let Some(mut velocity) = velocity
        && stepped
    {
        if late(velocity.last_changed()) {
            wrote = true;
        } else if !compare || !same_bits(velocity.0, body.velocity()) {
            velocity.0 = body.velocity();
            wrote = true;
        }
    }
    if moved_late(&late, &position, previous.0) {
        return (true, false);
    }
    if !compare {
        previous.0 = position.0;
        if stepped {
            position.0 = body.position();
        }
        return (true, stepped);
    }
    // A position is written with its previous one, even one the same as it (a sphere that
    // starts moving): the interpolation takes a position written after its previous one for
    // a game's teleport, shown where it was put.
    if stepped && !same_bits(position.0, body.position()) {
        previous.0 = position.0;
        position.0 = body.position();
        return (true, true);
    }
    if !same_bits(previous.0, position.0) {
        previous.0 = position.0;
        wrote = true;
    }
    (wrote, false)
}

/// Whether `a` and `b` are the same to the bit (a zero's sign included).
#[inline]
fn same_bits(a: DVec3, b: DVec3) -> bool {
    a.x.to_bits() == b.x.to_bits()
        && a.y.to_bits() == b.y.to_bits()
        && a.z.to_bits() == b.z.to_bits()
}

/// [`SpherePhysicsSystems::Notify`](crate::SpherePhysicsSystems::Notify): a [`SphereCollision`]
/// message per collision of the step, and a [`SphereHit`] on each of the two spheres.
pub(crate) fn notify(
    mut commands: Commands,
    physics: Res<SpherePhysicsWorld>,
    stepped: Res<Stepped>,
    mut collisions: MessageWriter<SphereCollision>,
    spheres: Query<(), With<SphereBody>>,
) {
    if !stepped.0 {
        return;
    }
    for c in physics.world.collisions() {
        let (Some(a), Some(b)) = (physics.entity(c.a), physics.entity(c.b)) else {
            continue;
        };
        // A sphere despawned (or no longer a sphere) since the step, by a game system after
        // `Writeback`: nothing is said about it.
        if !(spheres.contains(a) && spheres.contains(b)) {
            continue;
        }
        collisions.write(SphereCollision {
            a,
            b,
            time: c.time,
            normal: c.normal,
            point: c.point,
            impulse: c.impulse,
            resting: c.resting,
        });
        for (entity, other, normal) in [(a, b, c.normal), (b, a, -c.normal)] {
            let hit = SphereHit {
                entity,
                other,
                time: c.time,
                normal,
                impulse: c.impulse,
                resting: c.resting,
            };
            // Checked again when it is triggered: an observer of an earlier hit may have
            // despawned its sphere. Only the sphere it is for must still be one: a bullet that
            // despawns itself on a hit leaves its target's hit to be triggered (until the
            // fifty-sixth session the target was told only if it came first).
            commands.queue(move |world: &mut World| {
                if world.get::<SphereBody>(hit.entity).is_some() {
                    world.trigger(hit);
                }
            });
        }
    }
}

/// The spheres whose `Transform`s the plugin writes: in the simulation and still spheres (one
/// whose `SphereBody` was removed, its handle not yet, has its `Transform` back at once).
type Shown = (With<SphereHandle>, With<SphereBody>);

/// What `interpolate` reads and writes of each: its last two positions (with their change
/// ticks), its body, its `Transform`, and whether it opted out.
type ShownSphere = (
    Ref<'static, SpherePosition>,
    Ref<'static, PreviousSpherePosition>,
    &'static SphereHandle,
    &'static mut Transform,
    Has<NoInterpolation>,
);

/// The spheres shown, those that are children of another entity apart (each sphere's
/// `Transform` is written through its parent's frame, read from the `Transform`s of its
/// ancestors, the third query).
type ShownSpheres<'w, 's> = ParamSet<
    'w,
    's,
    (
        Query<'static, 'static, ShownSphere, (Shown, Without<ChildOf>)>,
        Query<'static, 'static, (Entity, ShownSphere, &'static ChildOf), Shown>,
        Query<'static, 'static, (&'static Transform, Option<&'static ChildOf>), Allow<Disabled>>,
    ),
>;

/// Where a sphere is shown this frame: between its last two positions, `fraction` of the way
/// (the fixed clock's overstep), unless interpolation is off, it opted out, or the game moved
/// it since `Writeback`.
struct Showing<'a> {
    fraction: f64,
    interpolate: bool,
    physics: &'a SpherePhysicsWorld,
    this_run: Tick,
}

impl Showing<'_> {
    fn at(
        &self,
        position: &Ref<SpherePosition>,
        previous: &Ref<PreviousSpherePosition>,
        handle: &SphereHandle,
        opted_out: bool,
    ) -> DVec3 {
        // `Writeback` sets both at once, the position to its body's; a position written later
        // to another place was the game's (a teleport): shown where it was put, not slid to
        // from where the sphere was. Written back unchanged (a clamp that held), it is no
        // teleport (until the fifty-sixth session it was, and the sphere jumped).
        let teleported = position
            .last_changed()
            .is_newer_than(previous.last_changed(), self.this_run)
            && self
                .physics
                .world
                .body(handle.0)
                .is_none_or(|body| body.position() != position.0);
        if self.interpolate && !opted_out && !teleported {
            previous.0.lerp(position.0, self.fraction)
        } else {
            position.0
        }
    }

    /// Writes the `Transform` of each sphere that is a child of another entity, through its
    /// parent's frame as the `Transform`s are now: those nearer the root first, so that a
    /// sphere whose ancestor is a sphere is placed through that sphere's new `Transform`.
    /// `order` is scratch space.
    fn place_children(&self, spheres: &mut ShownSpheres, order: &mut Vec<(usize, Entity, DVec3)>) {
        order.clear();
        {
            let children = spheres.p1();
            for (entity, (position, previous, handle, _, opted_out), _) in &children {
                order.push((0, entity, self.at(&position, &previous, handle, opted_out)));
            }
        }
        if order.is_empty() {
            return;
        }
        {
            let hierarchy = spheres.p2();
            for (depth, entity, _) in order.iter_mut() {
                let mut up = hierarchy.get(*entity).ok().and_then(|(_, parent)| parent);
                while let Some(parent) = up
                    && *depth < MAX_DEPTH
                {
                    *depth += 1;
                    up = hierarchy.get(parent.parent()).ok().and_then(|(_, p)| p);
                }
            }
        }
        order.sort_unstable_by_key(|&(depth, entity, _)| (depth, entity));
        for &(_, entity, at) in order.iter() {
            let frame = {
                let hierarchy = spheres.p2();
                let Ok((_, Some(parent))) = hierarchy.get(entity) else {
                    continue;
                };
                frame_of(parent.parent(), |e| {
                    let (transform, up) = hierarchy.get(e).ok()?;
                    Some((*transform, up.map(ChildOf::parent)))
                })
            };
            let Some(local) = local_translation(&frame, at) else {
                continue;
            };
            if let Ok((_, (_, _, _, mut transform, _), _)) = spheres.p1().get_mut(entity)
                && transform.translation != local
            {
                transform.translation = local;
            }
        }
    }
}

/// After the fixed steps of a frame: each sphere's `Transform` between its last two physics
/// positions, by how far the fixed clock has run into the next step (and the simulated time
/// that shows, in [`SphereShownTime`]).
#[allow(clippy::too_many_arguments)]
pub(crate) fn interpolate(
    time: Res<Time<Fixed>>,
    options: Res<PluginOptions>,
    stepped: Res<Stepped>,
    diagnostics: Res<SpherePhysicsDiagnostics>,
    physics: Res<SpherePhysicsWorld>,
    mut shown: ResMut<SphereShownTime>,
    mut spheres: ShownSpheres,
    mut order: Local<Vec<(usize, Entity, DVec3)>>,
    ticks: SystemChangeTick,
) {
    let fraction = time.overstep_fraction_f64();
    // The previous positions are the last step's start (or, when it did not step, its end).
    let time_shown = if options.interpolate && stepped.0 {
        diagnostics.time - (1.0 - fraction) * diagnostics.last.dt
    } else {
        diagnostics.time
    };
    shown.set_if_neq(SphereShownTime(time_shown));
    let showing = Showing {
        fraction,
        interpolate: options.interpolate,
        physics: &physics,
        this_run: ticks.this_run(),
    };
    for (position, previous, handle, mut transform, opted_out) in &mut spheres.p0() {
        let at = translation(showing.at(&position, &previous, handle, opted_out));
        if transform.translation != at {
            transform.translation = at;
        }
    }
    showing.place_children(&mut spheres, &mut order);
}

/// In `PostUpdate`, before Bevy propagates the `Transform`s: each sphere that is a child of
/// another entity placed again, through its parent's frame as the game's `Update` left it
/// (a parent moved there would otherwise carry its spheres along on screen for a frame), and
/// each that stopped being one since the last frame placed in the world (its `Transform`
/// was still relative to its old parent).
pub(crate) fn place_children(
    time: Res<Time<Fixed>>,
    options: Res<PluginOptions>,
    physics: Res<SpherePhysicsWorld>,
    mut spheres: ShownSpheres,
    mut unparented: RemovedComponents<ChildOf>,
    mut order: Local<Vec<(usize, Entity, DVec3)>>,
    ticks: SystemChangeTick,
) {
    let showing = Showing {
        fraction: time.overstep_fraction_f64(),
        interpolate: options.interpolate,
        physics: &physics,
        this_run: ticks.this_run(),
    };
    let mut roots = spheres.p0();
    for entity in unparented.read() {
        if let Ok((position, previous, handle, mut transform, opted_out)) = roots.get_mut(entity) {
            let at = translation(showing.at(&position, &previous, handle, opted_out));
            if transform.translation != at {
                transform.translation = at;
            }
        }
    }
    showing.place_children(&mut spheres, &mut order);
}
