//! [`SpherePhysicsPlugin`] and its system sets.

use bevy::app::{RunFixedMainLoop, RunFixedMainLoopSystems};
use bevy::math::DVec3;
use bevy::prelude::*;
use sphere_physics::{IntegratorKind, Settings, Sleep, ToiMethod, Tolerance, World};

use crate::components::*;
use crate::events::{SphereCollision, SphereRejected};
use crate::resources::{
    SpherePhysicsClock, SpherePhysicsDiagnostics, SpherePhysicsWorld, SphereShownTime,
};
use crate::systems::{
    self, PluginOptions, PreparedAt, RemovedSpheres, RescanSpheres, RunawaySpheres, Stepped,
};

/// The plugin's stages in [`FixedUpdate`], chained in this order. Put a game's systems
/// `.before(..)` or `.after(..)` any of them, e.g. apply thrust before `Prepare` or read
/// positions after `Writeback`.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SpherePhysicsSystems {
    /// Component changes go into the core: new spheres, despawned ones, velocities, radii,
    /// forces and teleports set by game systems; invalid spheres are rejected.
    Prepare,
    /// One core step: integration, collision detection and response. They happen together,
    /// because the core resolves collisions in time order between the integrator's kicks.
    Step,
    /// Positions and velocities come back into [`SpherePosition`] and [`SphereVelocity`].
    Writeback,
    /// [`SphereCollision`] messages and [`SphereHit`](crate::SphereHit) entity events.
    Notify,
}

/// The plugin's system after the fixed steps of every frame (in
/// [`RunFixedMainLoopSystems::AfterFixedMainLoop`]): it sets each sphere's `Transform` between
/// its last two physics positions and updates [`SphereShownTime`]. A game system there that
/// also writes `Transform`s or reads the spheres' (a camera following a sphere, say) goes
/// `.after(SphereInterpolation)`. The set is also in `PostUpdate`, before
/// `TransformSystems::Propagate`: there the plugin writes again the `Transform`s of spheres
/// that are children of other entities, through their parents as `Update` left them (and of
/// those that stopped being children since the last frame). A game system that moves such a
/// parent in `PostUpdate` (an animation's, say: Bevy's `AnimationSystems`) goes
/// `.before(SphereInterpolation)` there.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SphereInterpolation;

/// Sphere physics as ordered [`FixedUpdate`] system sets. Needs no window, renderer or egui:
/// it runs with `MinimalPlugins`.
///
/// ```no_run
/// use bevy::prelude::*;
/// use bevy_sphere_physics::prelude::*;
///
/// App::new()
///     .add_plugins((MinimalPlugins, SpherePhysicsPlugin::default().gravity(DVec3::NEG_Y * 9.81)))
///     .add_systems(Startup, |mut commands: Commands| {
///         commands.spawn((SphereBody::new(0.5), Transform::from_xyz(0.0, 2.0, 0.0)));
///     })
///     .run();
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SpherePhysicsPlugin {
    /// The core's settings (gravity, time-of-impact method, integrator, tolerance, ...).
    pub settings: Settings,
    /// Restitution of spheres spawned without a [`Restitution`] component.
    pub restitution: f64,
    /// Interpolate transforms between fixed steps (per sphere: [`NoInterpolation`]).
    pub interpolate: bool,
}

impl Default for SpherePhysicsPlugin {
    fn default() -> Self {
        Self {
            settings: Settings::default(),
            restitution: 1.0,
            interpolate: true,
        }
    }
}

impl SpherePhysicsPlugin {
    /// Sets gravity.
    pub fn gravity(mut self, gravity: DVec3) -> Self {
        self.settings.gravity = gravity;
        self
    }

    /// Sets the time-of-impact method (exact by default).
    pub fn method(mut self, method: ToiMethod) -> Self {
        self.settings.method = method;
        self
    }

    /// Sets the integrator (semi-implicit Euler by default).
    pub fn integrator(mut self, integrator: IntegratorKind) -> Self {
        self.settings.integrator = integrator;
        self
    }

    /// Sets the tolerance of every equality test.
    pub fn tolerance(mut self, tolerance: Tolerance) -> Self {
        self.settings.tolerance = tolerance;
        self
    }

    /// Sets the restitution of spheres spawned without a [`Restitution`] component (1 by
    /// default). Outside `[0, 1]` it is invalid for every such sphere: each is rejected, with a
    /// [`SphereRejected`](crate::SphereRejected) naming its restitution.
    pub fn restitution(mut self, restitution: f64) -> Self {
        self.restitution = restitution;
        self
    }

    /// Sets how many substeps each fixed step takes (0 is taken as 1).
    pub fn substeps(mut self, substeps: u32) -> Self {
        self.settings.substeps = substeps.max(1);
        self
    }

    /// Lets spheres at rest fall asleep (off by default): see the core's
    /// [`Settings::sleep`]. A sleeping sphere costs next to nothing, is still struck exactly,
    /// and wakes when anything disturbs it, a change to its components included.
    pub fn sleep(mut self, sleep: Sleep) -> Self {
        self.settings.sleep = Some(sleep);
        self
    }

    /// Turns transform interpolation on or off for every sphere.
    pub fn interpolate(mut self, interpolate: bool) -> Self {
        self.interpolate = interpolate;
        self
    }
}

impl Plugin for SpherePhysicsPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(SpherePhysicsWorld::new(World::new(self.settings.clone())))
            .insert_resource(PluginOptions {
                restitution: self.restitution,
                interpolate: self.interpolate,
            })
            .init_resource::<SpherePhysicsClock>()
            .init_resource::<SpherePhysicsDiagnostics>()
            .init_resource::<SphereShownTime>()
            .init_resource::<Stepped>()
            .init_resource::<RemovedSpheres>()
            .init_resource::<RunawaySpheres>()
            .init_resource::<RescanSpheres>()
            .init_resource::<PreparedAt>()
            .add_observer(systems::record_removal)
            .add_observer(systems::record_part_removal)
            .add_message::<SphereCollision>()
            .add_message::<SphereRejected>()
            .register_type::<SphereBody>()
            .register_type::<SpherePosition>()
            .register_type::<PreviousSpherePosition>()
            .register_type::<SphereVelocity>()
            .register_type::<Density>()
            .register_type::<Restitution>()
            .register_type::<AppliedForce>()
            .register_type::<FixedSphere>()
            .register_type::<NeverSleeps>()
            .register_type::<Tethered>()
            .register_type::<NoInterpolation>()
            .register_type::<SphereOrder>()
            .register_type::<SpherePhysicsClock>()
            .register_type::<SpherePhysicsDiagnostics>()
            .register_type::<SphereShownTime>()
            .configure_sets(
                FixedUpdate,
                (
                    SpherePhysicsSystems::Prepare,
                    SpherePhysicsSystems::Step,
                    SpherePhysicsSystems::Writeback,
                    SpherePhysicsSystems::Notify,
                )
                    .chain(),
            )
            .add_systems(
                FixedUpdate,
                (
                    systems::prepare.in_set(SpherePhysicsSystems::Prepare),
                    systems::step.in_set(SpherePhysicsSystems::Step),
                    systems::writeback.in_set(SpherePhysicsSystems::Writeback),
                    systems::notify.in_set(SpherePhysicsSystems::Notify),
                ),
            )
            .configure_sets(
                RunFixedMainLoop,
                SphereInterpolation.in_set(RunFixedMainLoopSystems::AfterFixedMainLoop),
            )
            .add_systems(
                RunFixedMainLoop,
                systems::interpolate.in_set(SphereInterpolation),
            )
            .configure_sets(
                PostUpdate,
                SphereInterpolation.before(bevy::transform::TransformSystems::Propagate),
            )
            .add_systems(
                PostUpdate,
                systems::place_children.in_set(SphereInterpolation),
            );
    }
}
