//! Components a game spawns: one line, `(SphereBody::new(0.5), Transform::from_xyz(..))`.
//!
//! Physics state is `f64`, as in the core ([`SpherePosition`], [`SphereVelocity`]); the
//! plugin writes Bevy's `f32` [`Transform`] from it, interpolated between fixed steps.

use bevy::ecs::lifecycle::HookContext;
use bevy::ecs::world::DeferredWorld;
use bevy::math::DVec3;
use bevy::prelude::*;
use sphere_physics::BodyError;

/// A sphere in the simulation. Spawning it with a [`Transform`] is enough: every other physics
/// component is filled in with a default (at rest, density 1, no force), and without a
/// [`Restitution`] it takes the plugin's ([`SpherePhysicsPlugin::restitution`](crate::SpherePhysicsPlugin::restitution),
/// 1 unless set, or a [`ResetSpherePhysics`](crate::ResetSpherePhysics)'s).
///
/// The sphere starts where its [`SpherePosition`] says if one is spawned with it (a place in
/// the world), else where its `Transform` puts it in the world (through its parent's, if it
/// is a child). Changing `radius` later re-validates the body; see the crate docs for what
/// changes mid-simulation do, and for spheres that are children of other entities.
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq)]
#[reflect(Component)]
#[require(
    Transform,
    SphereVelocity,
    Density,
    AppliedForce,
    PreviousSpherePosition
)]
pub struct SphereBody {
    /// Radius, `> 0`.
    pub radius: f64,
}

impl SphereBody {
    /// A sphere of this radius.
    pub fn new(radius: f64) -> Self {
        Self { radius }
    }
}

/// Where the sphere's centre is in the physics world (`f64`). Written by the plugin every step;
/// writing it from a game system teleports the sphere. Inserting it (at spawn, say) also moves
/// the entity's `Transform` there at once (through its parent's frame, if it is a child), so
/// the sphere is drawn where it is before its first step (and where it was put if it is
/// rejected).
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Deref, DerefMut)]
#[reflect(Component)]
#[component(on_insert = SpherePosition::show)]
pub struct SpherePosition(pub DVec3);

impl SpherePosition {
    /// The insert hook: the `Transform`'s translation follows the inserted position.
    fn show(mut world: DeferredWorld, context: HookContext) {
        let Some(&SpherePosition(at)) = world.get::<SpherePosition>(context.entity) else {
            return;
        };
        // A child's `Transform` is relative to its parent (see `crate::hierarchy`).
        let at = match world.get::<ChildOf>(context.entity) {
            Some(child_of) => {
                let frame = crate::hierarchy::frame_of(child_of.parent(), |e| {
                    let transform = *world.get::<Transform>(e)?;
                    Some((transform, world.get::<ChildOf>(e).map(ChildOf::parent)))
                });
                match crate::hierarchy::local_translation(&frame, at) {
                    Some(local) => local,
                    None => return,
                }
            }
            None => translation(at),
        };
        if let Some(mut transform) = world.get_mut::<Transform>(context.entity)
            && transform.translation != at
        {
            transform.translation = at;
        }
    }
}

/// A physics position as a `Transform`'s translation (`f32`): beyond `f32`'s range (3.4e38 m,
/// where the core goes on to 1e308) it stays at the range's edge, not infinite (an infinite
/// translation turns a `GlobalTransform`, and what is worked out from it, to NaN). A position
/// that is not finite (a game's, rejected) is converted as it is.
pub(crate) fn translation(at: DVec3) -> Vec3 {
    let edge = DVec3::splat(f64::from(f32::MAX));
    if at.is_finite() {
        at.clamp(-edge, edge).as_vec3()
    } else {
        at.as_vec3()
    }
}

/// The physics position at the previous fixed step, for interpolation.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Deref, DerefMut)]
#[reflect(Component)]
pub struct PreviousSpherePosition(pub DVec3);

/// Linear velocity (`f64`). Written by the plugin every step; writing it from a game system
/// sets the sphere's velocity for the next step.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Deref, DerefMut)]
#[reflect(Component)]
pub struct SphereVelocity(pub DVec3);

/// Density (default 1): mass is density times volume.
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq, Deref, DerefMut)]
#[reflect(Component)]
pub struct Density(pub f64);

impl Default for Density {
    fn default() -> Self {
        Self(1.0)
    }
}

/// Coefficient of restitution in `[0, 1]`. A sphere without one uses the plugin's default
/// ([`SpherePhysicsPlugin::restitution`](crate::SpherePhysicsPlugin::restitution), 1 unless set).
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq, Deref, DerefMut)]
#[reflect(Component)]
pub struct Restitution(pub f64);

impl Default for Restitution {
    fn default() -> Self {
        Self(1.0)
    }
}

/// A constant force on the sphere, on top of gravity (default none).
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Deref, DerefMut)]
#[reflect(Component)]
pub struct AppliedForce(pub DVec3);

/// Makes a sphere fixed: infinite mass, moved by nothing (a velocity moves it kinematically).
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq)]
#[reflect(Component)]
pub struct FixedSphere;

/// Keeps a sphere, and every sphere touching it, from falling asleep when sleeping is on (see
/// [`SpherePhysicsPlugin::sleep`](crate::SpherePhysicsPlugin::sleep)): for a sphere the game
/// pushes with a small force or steers slowly, which would otherwise fall asleep where it is
/// once it has been slower than the sleeping speed for the sleeping time. The core's
/// `SphereDesc::never_sleeps`.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq)]
#[reflect(Component)]
pub struct NeverSleeps;

/// Hangs a sphere on an inextensible string of `length` from `anchor` (pulls, never pushes).
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq)]
#[reflect(Component)]
pub struct Tethered {
    /// The fixed anchor point.
    pub anchor: DVec3,
    /// The string's length, `> 0`.
    pub length: f64,
}

/// Optional: the order in which spheres that join the simulation at the same fixed step get
/// their bodies (lower first; spheres without it follow, in entity order). Body ids decide the
/// order in which contacts at one instant are listed, so give it to spheres spawned together
/// when a run must repeat bit for bit whatever entities Bevy hands out (a restart reuses freed
/// entities in another order).
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[reflect(Component)]
pub struct SphereOrder(pub u64);

/// Opts one sphere out of interpolation: its `Transform` jumps from fixed step to fixed step.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq)]
#[reflect(Component)]
pub struct NoInterpolation;

/// Put on a sphere whose components are invalid (radius ≤ 0, NaN, ...), or whose motion would
/// have left the finite range: it is left out of the simulation until its components change
/// (or, if it was refused for its force's sum with the world's gravity, until the gravity
/// does; if it is a child placed by its `Transform` and was refused for its place, beyond
/// its string say, until its parent moves it too). The error names the field and the value.
#[derive(Component, Clone, Debug, PartialEq)]
pub struct RejectedSphere {
    /// What is wrong.
    pub error: BodyError,
    /// The description that was refused (tried again only once it changes, or, if `gravity`
    /// is set, once the world's gravity does).
    pub(crate) desc: sphere_physics::SphereDesc,
    /// For a child placed by its `Transform`: the description with its own translation for
    /// its position (`desc` has where its parent put it). While that stays the same, a
    /// refusal not of its place (its position or its string) is not tried again as the
    /// parent moves, and one of its place is tried again but not reported again.
    pub(crate) own: Option<sphere_physics::SphereDesc>,
    /// The world's gravity when it was refused, if the refusal was its (the sphere would be
    /// taken without gravity, and is not under this one): tried again once it changes. (Until
    /// the sixty-first session a sphere refused under a gravity the game then mended stayed
    /// out.)
    pub(crate) gravity: Option<bevy::math::DVec3>,
}

/// The core body of a sphere in the simulation, put on it by the plugin (read-only for games),
/// and the entity it was put on (a handle cloned onto another entity is not that entity's).
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct SphereHandle(pub sphere_physics::BodyId, pub(crate) Entity);
