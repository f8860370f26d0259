//! Avian 0.7 (`avian3d`, `f64` + `parry-f64`) as a peer for the overhead benchmark: the same
//! spheres as avian rigid bodies in a headless Bevy app, stepped once per [`App::update`].
//!
//! Choices, each checked against the avian3d 0.7.0 and Bevy 0.19.1 sources:
//! - **Plugins**: [`MinimalPlugins`] + [`PhysicsPlugins::default()`] and nothing else. Avian
//!   needs no assets, mesh, scene or render plugin without its `collider-from-mesh`,
//!   `bevy_scene` and `debug-plugin` features, and no `TransformPlugin`: its
//!   `PhysicsTransformPlugin` initialises `StaticTransformOptimizations` itself and runs Bevy's
//!   transform propagation in `FixedPostUpdate` before each step.
//! - **Precision**: with `f64`, avian's `Scalar` is `f64` and `Position`, `LinearVelocity` and
//!   [`Gravity`] hold [`DVec3`]. Mass properties are `f32` in avian 0.7 ([`ColliderDensity`] is
//!   `f32`, and the collider mass is rounded to `f32`), so masses carry `f32` rounding.
//! - **Stepping**: avian runs its `PhysicsSchedule` from `FixedPostUpdate` (the default of
//!   [`PhysicsPlugins`]) and advances `Time<Physics>` by the delta of the generic `Time`, which
//!   is `Time<Fixed>` inside the fixed loop. [`TimeUpdateStrategy::ManualDuration`] and
//!   [`Time<Fixed>::from_duration`] get the same `dt`, so every update adds exactly `dt` of
//!   virtual time (integer nanoseconds, no drift) and runs the fixed loop exactly once. The
//!   first update only starts Bevy's clock (zero delta, no step), so [`build_app`] runs it.
//! - **Bodies**: [`Collider::sphere`] with [`ColliderDensity`], [`Restitution`] with
//!   [`CoefficientCombine::Min`], [`Friction::ZERO`], [`LockedAxes::ROTATION_LOCKED`],
//!   [`RigidBody::Dynamic`] or [`RigidBody::Static`]; `Position` is set directly in `f64`
//!   (avian writes the `f32` `Transform` from it at spawn and after each step).
//! - **Avian defaults kept**: sleeping, `Transform` ↔ `Position` sync, speculative contacts,
//!   the restitution threshold (`SolverConfig::restitution_threshold`, 1 m/s: slower impacts
//!   are inelastic), tree optimisation settings, and the default length unit (1 m).
//! - **Caveats**: without avian's `parallel` feature Bevy is single-threaded, and avian's
//!   "async" tree optimisation runs inline on a cloned tree. The `Transform` → `Position` sync
//!   copies the `f32` transform back when it differs from `Position` by more than 10 µm, which
//!   `f32` rounding can reach beyond 256 m from the origin; keep scenes within that.

use std::time::Duration;

use avian3d::prelude::{
    CoefficientCombine, Collider, ColliderDensity, ComputedMass, Friction, Gravity, LinearVelocity,
    LockedAxes, PhysicsPlugins, Position, Restitution, RigidBody, SubstepCount,
};
use bevy::math::DVec3;
use bevy::prelude::{App, Fixed, MinimalPlugins, Time, Virtual};
use bevy::time::TimeUpdateStrategy;

/// One sphere of a benchmark scene, in SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre in metres.
    pub position: [f64; 3],
    /// Velocity in metres per second (ignored for fixed spheres).
    pub velocity: [f64; 3],
    /// Radius in metres.
    pub radius: f64,
    /// Density in kilograms per cubic metre (avian stores it as `f32`).
    pub density: f64,
    /// Coefficient of restitution, combined with the other body's by taking the minimum.
    pub restitution: f64,
    /// A static body that never moves.
    pub fixed: bool,
}

/// Builds a headless Bevy app ([`MinimalPlugins`] + avian's [`PhysicsPlugins`]) holding
/// `spheres` as avian rigid bodies under `gravity` (m/s²), so that each later
/// [`App::update`] takes exactly one physics step of `dt` with `substeps` substeps.
///
/// Each sphere is a ball [`Collider`] of its radius with its [`ColliderDensity`], a
/// [`Restitution`] with [`CoefficientCombine::Min`], [`Friction::ZERO`] and
/// [`LockedAxes::ROTATION_LOCKED`], and is [`RigidBody::Dynamic`] or, if `fixed`,
/// [`RigidBody::Static`]. Time is manual: [`TimeUpdateStrategy::ManualDuration`] and
/// [`Time<Fixed>::from_duration`] with the same `dt` (and `Time<Virtual>`'s maximum delta
/// raised to `dt` if needed), so each update runs `FixedPostUpdate`, where avian steps,
/// exactly once. The app is finished, cleaned up (avian creates its diagnostics resources in
/// `Plugin::finish`) and updated once before it is returned: that first update only starts
/// Bevy's clock and takes no physics step.
///
/// # Panics
///
/// If `dt` is zero or `substeps` is zero.
pub fn build_app(spheres: &[Sphere], gravity: [f64; 3], dt: Duration, substeps: u32) -> App {
    assert!(!dt.is_zero(), "the physics step must be longer than zero");
    assert!(substeps > 0, "avian needs at least one substep");

    let mut app = App::new();
    app.add_plugins((MinimalPlugins, PhysicsPlugins::default()));

    // Inserted after the plugins so they replace the resources the plugins initialised.
    app.insert_resource(TimeUpdateStrategy::ManualDuration(dt))
        .insert_resource(Time::<Fixed>::from_duration(dt))
        .insert_resource(Gravity(DVec3::from_array(gravity)))
        .insert_resource(SubstepCount(substeps));
    {
        // `Time<Virtual>` clamps each frame's delta (250 ms by default); a longer step
        // would otherwise be cut short and no fixed step would run.
        let mut virtual_time = app.world_mut().resource_mut::<Time<Virtual>>();
        if dt > virtual_time.max_delta() {
            virtual_time.set_max_delta(dt);
        }
    }

    // `App::update` does not finish plugins itself (only `App::run` does), and avian's
    // physics systems need the diagnostics resources its plugins insert in `finish`.
    app.finish();
    app.cleanup();

    let world = app.world_mut();
    for sphere in spheres {
        let (body, velocity) = if sphere.fixed {
            (RigidBody::Static, DVec3::ZERO)
        } else {
            (RigidBody::Dynamic, DVec3::from_array(sphere.velocity))
        };
        world.spawn((
            body,
            Position(DVec3::from_array(sphere.position)),
            LinearVelocity(velocity),
            Collider::sphere(sphere.radius),
            ColliderDensity(sphere.density as f32),
            Restitution::new(sphere.restitution).with_combine_rule(CoefficientCombine::Min),
            Friction::ZERO,
            LockedAxes::ROTATION_LOCKED,
        ));
    }

    // The first update only records the start of Bevy's real clock: zero delta, so no fixed
    // step and no physics step. Every update after this one takes exactly one step of `dt`.
    app.update();
    app
}

/// Total kinetic energy `Σ ½ m v²` of the dynamic bodies, in joules, read from avian's
/// [`ComputedMass`] and [`LinearVelocity`]. Rotation is locked, so there is no rotational
/// energy; static bodies are left out.
pub fn kinetic_energy(app: &mut App) -> f64 {
    let world = app.world_mut();
    let mut bodies = world.query::<(&RigidBody, &ComputedMass, &LinearVelocity)>();
    bodies
        .iter(world)
        .filter(|(body, _, _)| body.is_dynamic())
        .map(|(_, mass, velocity)| 0.5 * mass.value() * velocity.0.length_squared())
        .sum()
}
