//! Resources: the core world, the physics clock (pause, single step) and diagnostics.

use bevy::ecs::entity::EntityHashMap;
use bevy::ecs::entity_disabling::Disabled;
use bevy::ecs::query::Allow;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use sphere_physics::{BodyId, StepStats, World};

/// The core world and which entity each body belongs to. The core is the single source of the
/// physics: the plugin only copies components in and results out.
#[derive(Resource, Debug)]
pub struct SpherePhysicsWorld {
    /// The core world: its settings, profiling, custom integrator or time-of-impact method,
    /// queries (energy, momentum, the last step's collisions and statistics), and bodies a
    /// game adds without an entity.
    ///
    /// A sphere entity's components are its source of truth: at every `Prepare` its
    /// position, velocity, force, radius, density, restitution, fixedness and tether are set
    /// from them, so a change made here to such a body (`set_velocity`, `set_position`, ...)
    /// is undone. Change its components instead.
    pub world: World,
    pub(crate) bodies: EntityHashMap<BodyId>,
    /// Each body's entity (a map: body ids are never reused, so a table indexed by id would
    /// grow with every sphere ever spawned). Hashed by Bevy's fixed, fast hasher rather than
    /// the standard library's: `Notify` looks up both spheres of every collision, and until
    /// sphere handles named their entities `Prepare` looked up every sphere at every step.
    /// (Never iterated, so its order reaches nothing.)
    pub(crate) entities: HashMap<BodyId, Entity>,
}

impl SpherePhysicsWorld {
    pub(crate) fn new(world: World) -> Self {
        Self {
            world,
            bodies: EntityHashMap::default(),
            entities: HashMap::default(),
        }
    }

    /// The body of a sphere entity, if it is in the simulation.
    pub fn body(&self, entity: Entity) -> Option<BodyId> {
        self.bodies.get(&entity).copied()
    }

    /// The entity of a body.
    pub fn entity(&self, body: BodyId) -> Option<Entity> {
        self.entities.get(&body).copied()
    }
}

/// The physics clock: pause, and single steps while paused.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
#[reflect(Resource)]
pub struct SpherePhysicsClock {
    /// No steps while paused (Bevy's fixed clock keeps running; the steps it asks for are
    /// skipped, not queued).
    pub paused: bool,
    /// Steps still to take while paused (each fixed step takes one).
    pub pending_steps: u32,
}

impl SpherePhysicsClock {
    /// Pauses or resumes.
    pub fn toggle(&mut self) {
        self.paused = !self.paused;
    }

    /// While paused, takes one more step at the next fixed step.
    pub fn step_once(&mut self) {
        self.pending_steps += 1;
    }

    /// Whether the next fixed step should step the physics (and uses up a pending step).
    pub(crate) fn take_step(&mut self) -> bool {
        if !self.paused {
            // Steps asked for while paused are not kept for the next pause.
            self.pending_steps = 0;
            return true;
        }
        if self.pending_steps > 0 {
            self.pending_steps -= 1;
            return true;
        }
        false
    }
}

/// The core's statistics of the last step, and totals since start. Reflected (for inspectors)
/// but for `last`, the core's own type.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Reflect)]
#[reflect(Resource)]
pub struct SpherePhysicsDiagnostics {
    /// The last step's statistics: collisions, energies, momentum, largest overlap.
    #[reflect(ignore)]
    pub last: StepStats,
    /// Simulated seconds.
    pub time: f64,
    /// Steps taken.
    pub steps: u64,
    /// Collisions since start.
    pub collisions: u64,
    /// Wall-clock seconds the last core step took.
    pub step_seconds: f64,
    /// Spheres in the simulation.
    pub bodies: usize,
    /// Fixed steps the core refused for a reason no one sphere could be blamed for (settings
    /// out of range, a zero time step): skipped, and logged once per distinct reason.
    pub refused_steps: u64,
}

/// The simulated time the spheres' `Transform`s show this frame: between the last two steps'
/// times when they are interpolated (see `SpherePhysicsPlugin::interpolate`), else the last
/// step's. What a screenshot of this frame should be stamped with. (A sphere with
/// [`NoInterpolation`](crate::NoInterpolation) is drawn at the last step's time instead.)
/// Its own resource, written after the fixed steps of every frame, so that
/// [`SpherePhysicsDiagnostics`] changes only when the physics steps.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Reflect)]
#[reflect(Resource)]
pub struct SphereShownTime(pub f64);

/// A command that empties the simulation and restarts its clock: the core world is replaced by
/// a new one with `settings`, diagnostics start again from zero, and spheres still spawned
/// join the new world at the next `Prepare`. Scene switches use it, so a new scene starts at
/// simulated time 0 with its own gravity, method and integrator. Profiling
/// ([`World::set_profiling`]) stays on if it was; a custom integrator or time-of-impact method
/// set on the old world is dropped for the settings' own.
///
/// ```
/// # use bevy::prelude::*;
/// # use bevy_sphere_physics::{ResetSpherePhysics, sphere_physics::Settings};
/// fn restart(mut commands: Commands) {
///     commands.queue(ResetSpherePhysics::new(Settings::default()));
/// }
/// ```
#[derive(Clone, Debug)]
pub struct ResetSpherePhysics {
    /// The new world's settings.
    pub settings: sphere_physics::Settings,
    /// A new default restitution for spheres without [`Restitution`](crate::Restitution), or
    /// `None` to keep the plugin's.
    pub restitution: Option<f64>,
}

impl ResetSpherePhysics {
    /// A reset to `settings`, keeping the default restitution.
    pub fn new(settings: sphere_physics::Settings) -> Self {
        Self {
            settings,
            restitution: None,
        }
    }

    /// Also sets the default restitution.
    pub fn restitution(mut self, restitution: f64) -> Self {
        self.restitution = Some(restitution);
        self
    }
}

impl Command for ResetSpherePhysics {
    type Out = ();

    fn apply(self, world: &mut bevy::prelude::World) {
        // Every sphere joins the new world afresh at the next `Prepare`: disabled ones too
        // (their handles would name bodies of the new world), and rejected ones, checked
        // again (a runaway may be fine under the new settings).
        let handles: Vec<Entity> = world
            .query_filtered::<Entity, (
                Or<(With<crate::SphereHandle>, With<crate::RejectedSphere>)>,
                Allow<Disabled>,
            )>()
            .iter(world)
            .collect();
        for entity in handles {
            world
                .entity_mut(entity)
                .remove::<(crate::SphereHandle, crate::RejectedSphere)>();
        }
        // Removals `Prepare` has not handled yet: an entity that lives on without its
        // `SphereBody` gets its `Transform` back, as `Prepare` would have done.
        let removed = world
            .get_resource_mut::<crate::systems::RemovedSpheres>()
            .map(|mut removed| std::mem::take(&mut removed.0))
            .unwrap_or_default();
        for entity in removed {
            if let Ok(mut entity) = world.get_entity_mut(entity) {
                entity.remove::<(
                    crate::SphereHandle,
                    crate::SpherePosition,
                    crate::PreviousSpherePosition,
                )>();
            }
        }
        // Profiling stays as it was; a custom integrator or time-of-impact method does not
        // (the settings' own are used).
        let profiling = world
            .get_resource::<SpherePhysicsWorld>()
            .is_some_and(|physics| physics.world.profile().is_some());
        let mut core = World::new(self.settings);
        core.set_profiling(profiling);
        world.insert_resource(SpherePhysicsWorld::new(core));
        if let Some(mut stepped) = world.get_resource_mut::<crate::systems::Stepped>() {
            stepped.0 = false;
        }
        world.insert_resource(SpherePhysicsDiagnostics::default());
        world.insert_resource(SphereShownTime::default());
        if let Some(mut runaways) = world.get_resource_mut::<crate::systems::RunawaySpheres>() {
            // Spheres of the old world: not to be reported after the reset.
            runaways.0.clear();
        }
        if let (Some(restitution), Some(mut options)) = (
            self.restitution,
            world.get_resource_mut::<crate::systems::PluginOptions>(),
        ) {
            options.restitution = restitution;
        }
    }
}
