//! What the plugin tells a game: collisions as messages and as entity events, and rejected
//! spheres.

use bevy::math::DVec3;
use bevy::prelude::*;
use sphere_physics::BodyError;

/// One collision, written once per collision in
/// [`SpherePhysicsSystems::Notify`](crate::SpherePhysicsSystems::Notify). Read it with
/// `MessageReader<SphereCollision>`. Only collisions between two sphere entities are told:
/// one with a body a game added to the core directly (no entity; see
/// [`SpherePhysicsWorld::world`](crate::SpherePhysicsWorld::world)) is read from
/// `physics.world.collisions()` after the step, as are those of a sphere despawned or disabled
/// after the step (not told here).
#[derive(Message, Clone, Copy, Debug, PartialEq)]
pub struct SphereCollision {
    /// The first sphere.
    pub a: Entity,
    /// The second sphere.
    pub b: Entity,
    /// Simulated time of the impact (within the step, not at its end).
    pub time: f64,
    /// Unit normal from `a` to `b`.
    pub normal: DVec3,
    /// Contact point on `a`'s surface.
    pub point: DVec3,
    /// Impulse transferred along the normal (≥ 0).
    pub impulse: f64,
    /// Resolved as a resting contact (restitution 0).
    pub resting: bool,
}

/// A collision seen from one sphere: triggered on each of the two spheres once per collision,
/// so an observer on either (`commands.spawn(..).observe(|hit: On<SphereHit>| ..)`) sees it.
/// A global observer (`app.add_observer(|hit: On<SphereHit>| ..)`) sees both triggers, so
/// each collision twice: count collisions with [`SphereCollision`].
#[derive(EntityEvent, Clone, Copy, Debug, PartialEq)]
pub struct SphereHit {
    /// The sphere the observer watches.
    pub entity: Entity,
    /// The sphere it collided with. An observer of the other sphere's hit, triggered first,
    /// may have despawned it: the hit on `entity` is still triggered (a bullet that despawns
    /// itself on a hit still hits its target).
    pub other: Entity,
    /// Simulated time of the impact.
    pub time: f64,
    /// Unit normal from `entity` towards `other`.
    pub normal: DVec3,
    /// Impulse transferred (≥ 0).
    pub impulse: f64,
    /// A resting contact (restitution 0), not an impact.
    pub resting: bool,
}

/// A sphere left out of the simulation because a component is invalid (or because its motion
/// would leave the finite range within a step): which entity, which field, which value.
/// Written at `Prepare`, once each time its components are found invalid (and again if, refused
/// for its force's sum with gravity and tried again once the gravity changed, it is refused for
/// another reason).
#[derive(Message, Clone, Debug, PartialEq)]
pub struct SphereRejected {
    /// The sphere.
    pub entity: Entity,
    /// What is wrong: the field, the value and the rule.
    pub error: BodyError,
}
