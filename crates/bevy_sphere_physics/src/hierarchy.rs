//! Spheres that are children of other entities. A sphere's physics position is its place in
//! the world; its `Transform` is relative to its parent (Bevy's `ChildOf`). The plugin converts
//! between the two through the parent's place, worked out from the `Transform`s of the
//! parent and its ancestors as they are (not their `GlobalTransform`s, which Bevy brings up to
//! date only once a frame, in `PostUpdate`).

use bevy::ecs::entity_disabling::Disabled;
use bevy::ecs::query::Allow;
use bevy::ecs::system::SystemParam;
use bevy::math::{DAffine3, DVec3};
use bevy::prelude::*;

use crate::components::translation;

/// The most ancestors followed up from a sphere: a chain longer than this (or a loop of
/// `ChildOf`s, which Bevy does not forbid) is cut there, rather than followed for ever.
pub(crate) const MAX_DEPTH: usize = 1024;

/// A `Transform` as an `f64` affine map.
fn affine(transform: &Transform) -> DAffine3 {
    DAffine3::from_scale_rotation_translation(
        transform.scale.as_dvec3(),
        transform.rotation.as_dquat(),
        transform.translation.as_dvec3(),
    )
}

/// Where `parent`'s frame lies in the world: the `Transform`s of `parent` and its ancestors,
/// composed in `f64` (a disabled ancestor's too: `Disabled` is not handed down to children).
/// `look_up` gives an entity's `Transform` and its own parent; an ancestor without a
/// `Transform` ends the chain. (Bevy's propagation stops at either, a disabled ancestor or
/// one without a `Transform`: a sphere under one is simulated at its place but not drawn
/// there, whatever the plugin writes.)
pub(crate) fn frame_of(
    parent: Entity,
    mut look_up: impl FnMut(Entity) -> Option<(Transform, Option<Entity>)>,
) -> DAffine3 {
    let mut frame = DAffine3::IDENTITY;
    let mut next = Some(parent);
    for _ in 0..MAX_DEPTH {
        let Some((transform, up)) = next.and_then(&mut look_up) else {
            break;
        };
        frame = affine(&transform) * frame;
        next = up;
    }
    frame
}

/// The translation that puts a child at `at` in the world, in its parent's `frame` (see
/// [`translation`] for positions past `f32`'s range); `None` if the frame has no inverse (a
/// parent scaled to zero), when the child's `Transform` is best left as it is.
pub(crate) fn local_translation(frame: &DAffine3, at: DVec3) -> Option<Vec3> {
    let determinant = frame.matrix3.determinant();
    if determinant == 0.0 || !determinant.is_finite() {
        return None;
    }
    let local = frame.inverse().transform_point3(at);
    local.is_finite().then(|| translation(local))
}

/// The hierarchy as `Prepare` reads it: where a sphere placed by its `Transform` starts.
#[derive(SystemParam)]
pub(crate) struct Places<'w, 's> {
    parents: Query<'w, 's, &'static ChildOf, Allow<Disabled>>,
    transforms: Query<'w, 's, &'static Transform, Allow<Disabled>>,
}

impl Places<'_, '_> {
    /// Where `entity`, whose own `Transform` is `transform`, is in the world: its translation
    /// if it has no parent (as it is, bit for bit), else that translation through its
    /// parent's frame.
    pub(crate) fn place(&self, entity: Entity, transform: &Transform) -> DVec3 {
        let local = transform.translation.as_dvec3();
        match self.parents.get(entity) {
            Ok(child_of) => frame_of(child_of.parent(), |e| {
                let transform = self.transforms.get(e).ok()?;
                Some((*transform, self.parents.get(e).ok().map(ChildOf::parent)))
            })
            .transform_point3(local),
            Err(_) => local,
        }
    }

    /// Whether `entity` is a child of another entity.
    pub(crate) fn is_child(&self, entity: Entity) -> bool {
        self.parents.contains(entity)
    }
}
