//! Narrow phase: how two spheres stand relative to each other right now.

use glam::DVec3;

use crate::Tolerance;

/// The motion state of a sphere needed to classify a contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematics {
    /// Centre position.
    pub position: DVec3,
    /// Linear velocity.
    pub velocity: DVec3,
    /// Linear acceleration (gravity plus applied force over mass).
    pub acceleration: DVec3,
    /// Radius.
    pub radius: f64,
}

/// How two spheres stand relative to each other (the tutorial's `CollisionType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactKind {
    /// Not touching: the gap between the surfaces is larger than the tolerance.
    Apart,
    /// Touching, and moving apart (or at rest and pulled apart).
    Separating,
    /// Touching and approaching: an impulse is due.
    Colliding,
    /// Touching, no relative normal velocity, and not pulled apart: resting contact.
    Resting,
    /// Overlapping by more than the tolerance.
    Intersecting {
        /// Whether the centres are approaching (a collision that was missed or not yet resolved).
        approaching: bool,
    },
}

impl ContactKind {
    /// Whether this contact calls for a collision response.
    pub fn needs_response(self) -> bool {
        matches!(
            self,
            ContactKind::Colliding | ContactKind::Intersecting { approaching: true }
        )
    }
}

/// Whether two spheres whose centres are `distance` apart, with radii summing to `contact`, are
/// touching (or overlapping).
pub(crate) fn touching_or_overlapping(distance: f64, contact: f64, tol: Tolerance) -> bool {
    distance <= contact || tol.eq(distance, contact)
}

/// Whether a normal speed (positive = separating) means approaching, beyond the tolerance.
pub(crate) fn approaching(normal_speed: f64, tol: Tolerance) -> bool {
    tol.lt(normal_speed, 0.0)
}

/// Classifies the contact between spheres `a` and `b`.
///
/// Coincident centres (no normal defined) are reported as intersecting and not approaching.
pub fn classify(a: &Kinematics, b: &Kinematics, tol: Tolerance) -> ContactKind {
    let d = b.position - a.position;
    let distance = d.length();
    let contact = a.radius + b.radius;
    if !touching_or_overlapping(distance, contact, tol) {
        return ContactKind::Apart;
    }
    if distance == 0.0 {
        return ContactKind::Intersecting { approaching: false };
    }
    let n = d / distance;
    let normal_speed = (b.velocity - a.velocity).dot(n);
    if !tol.eq(distance, contact) {
        return ContactKind::Intersecting {
            approaching: approaching(normal_speed, tol),
        };
    }
    if approaching(normal_speed, tol) {
        ContactKind::Colliding
    } else if !tol.is_zero(normal_speed) || (b.acceleration - a.acceleration).dot(n) > 0.0 {
        ContactKind::Separating
    } else {
        ContactKind::Resting
    }
}
