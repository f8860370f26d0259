//! Exact sphere physics for Bevy 0.19: [`sphere_physics`] as ordered
//! [`FixedUpdate`](bevy::app::FixedUpdate) system
//! sets ([`SpherePhysicsSystems`]), then, once a frame after the fixed steps, the spheres'
//! `Transform`s ([`SphereInterpolation`]).
//!
//! Add [`SpherePhysicsPlugin`] and spawn spheres with one line,
//! `(SphereBody::new(0.5), Transform::from_xyz(0.0, 2.0, 0.0))`. Physics state is `f64`
//! ([`SpherePosition`], [`SphereVelocity`]); the `f32` `Transform` is written from it after
//! the fixed steps of each frame, interpolated between the last two steps (opt out per sphere
//! with [`NoInterpolation`], or globally with [`SpherePhysicsPlugin::interpolate`]).
//!
//! What game systems may do, and what happens:
//! - **Despawn a sphere** (or remove [`SphereBody`]): it leaves the simulation at the next fixed
//!   step (or at this one's `Step`, if done between its `Prepare` and `Step`); collisions
//!   already reported stay reported. An entity kept without its `SphereBody` gets its
//!   `Transform` back: the plugin stops writing it.
//! - **Disable a sphere** (Bevy's `Disabled`): it leaves the simulation at the next fixed step
//!   (or at this one's `Step`, if disabled between its `Prepare` and `Step`) and joins again,
//!   from where it was, once enabled. Only `Disabled` does this; a disabling
//!   component of the game's own (`World::register_disabling_component`) is not supported: it
//!   hides the sphere from the plugin, but its body stays in the simulation (struck, and not
//!   reported). Despawn the sphere, or remove its `SphereBody`, to take it out.
//! - **Remove a component a sphere was spawned with**: [`Density`] or [`AppliedForce`] then
//!   mean their defaults (density 1, no force); without [`SphereVelocity`] or
//!   [`SpherePosition`] the sphere keeps moving as the core has it (a removed `SpherePosition`
//!   is put back, as is a removed [`PreviousSpherePosition`]).
//! - **Change a component** ([`SphereVelocity`], [`SphereBody::radius`], [`Density`],
//!   [`Restitution`], [`AppliedForce`], [`SpherePosition`] to teleport, [`FixedSphere`],
//!   [`Tethered`], [`NeverSleeps`]): applied at the next fixed step's `Prepare`. Writing
//!   `Transform` does nothing: it is the plugin's output. A velocity or position set by a system
//!   that ran after `Prepare` in the same fixed step (a system in `FixedUpdate` with no order
//!   against the plugin's sets may) is kept, not overwritten with the step's result, and applied at
//!   the next step; order such a system `.before(SpherePhysicsSystems::Prepare)` to have it applied
//!   in the step it runs in. (One exception: in the step in which a sphere placed by its
//!   `Transform` joins, a position set after `Prepare` to exactly where it joined is taken for
//!   the plugin's own, and overwritten.)
//! - **Parent a sphere** (Bevy's `ChildOf`): it is simulated at its place in the world, and
//!   its `Transform` is written relative to its parent, so it is drawn there whatever the
//!   parent's translation, rotation and scale. A sphere placed by its `Transform` joins where
//!   that puts it through its ancestors' `Transform`s as they are then. The parent does not
//!   carry it: moving the parent moves no sphere (spheres have no joints), and the sphere's
//!   `Transform` is written again in `PostUpdate`, before Bevy propagates transforms, through
//!   the parent's frame as the game left it. A parent's scale scales the mesh drawn, not the
//!   sphere's radius; under a parent scaled to zero (no inverse) the sphere's `Transform` is
//!   left as it is.
//! - **Invalid values** (radius ≤ 0, NaN, restitution outside `[0, 1]`, a sphere beyond its
//!   string): the sphere is left out of the simulation, a [`SphereRejected`] message and a
//!   warning name the entity, the field and the value, and [`RejectedSphere`] is put on it;
//!   it joins once its components are valid (a sphere refused for its force's sum with gravity
//!   is tried again when the gravity changes). Nothing panics. A sphere whose motion would
//!   leave the finite range within a step (1e308 m/s) is rejected the same way, and the step
//!   taken without it. A step the core refuses for any other reason (settings out of range,
//!   such as a gravity that is not finite) is skipped, logged and counted in
//!   [`SpherePhysicsDiagnostics::refused_steps`].
//! - **Place a tethered sphere by its `Transform`** at its string's length: `f32` rounding that
//!   puts it a hair outside the string is undone.
//! - **Spawn into an occupied place**: spheres that overlap and approach are pushed apart by
//!   the collision response at once. Overlapping spheres are also moved apart by their
//!   positions, without gaining speed (see [`sphere_physics::World::step`]): under gravity or
//!   an applied force by the core's resting solve, a pair by at most a tenth of the smaller
//!   radius a step; with nothing accelerating at each step's end, each sphere by at most a
//!   tenth of its own radius a step, fixed spheres not at all, spheres on strings only within
//!   their strings' lengths. A crowd spawned a radius deep into itself comes apart over a few
//!   dozen steps.
//!
//! Collisions come as [`SphereCollision`] messages and as [`SphereHit`] entity events that
//! observers on either sphere receive, once per collision (a global observer, watching no
//! entity, sees each collision twice, once for each sphere: count collisions with
//! [`SphereCollision`]). [`SpherePhysicsDiagnostics`] holds
//! the core's per-step statistics; [`SpherePhysicsClock`] pauses and single-steps.
#![warn(missing_docs)]

pub mod components;
pub mod events;
mod hierarchy;
mod plugin;
pub mod resources;
mod systems;

pub use components::*;
pub use events::{SphereCollision, SphereHit, SphereRejected};
pub use plugin::{SphereInterpolation, SpherePhysicsPlugin, SpherePhysicsSystems};
pub use resources::{
    ResetSpherePhysics, SpherePhysicsClock, SpherePhysicsDiagnostics, SpherePhysicsWorld,
    SphereShownTime,
};
pub use sphere_physics;

/// Everything a game needs: `use bevy_sphere_physics::prelude::*;`.
pub mod prelude {
    pub use crate::components::*;
    pub use crate::events::{SphereCollision, SphereHit, SphereRejected};
    pub use crate::plugin::{SphereInterpolation, SpherePhysicsPlugin, SpherePhysicsSystems};
    pub use crate::resources::{
        ResetSpherePhysics, SpherePhysicsClock, SpherePhysicsDiagnostics, SpherePhysicsWorld,
        SphereShownTime,
    };
    pub use bevy::math::DVec3;
    pub use sphere_physics::Sleep;
}
