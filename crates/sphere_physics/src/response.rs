//! Collision response: an impulse along the line of centres.

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// The outcome of resolving one collision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resolution {
    /// Velocity of `a` after the impulse.
    pub velocity_a: DVec3,
    /// Velocity of `b` after the impulse.
    pub velocity_b: DVec3,
    /// Magnitude of the impulse (momentum transferred along the normal), `>= 0`.
    pub impulse: f64,
}

/// Resolves a collision between `a` and `b` with an impulse along `normal` (unit, from `a` to
/// `b`). Inverse masses of 0 mean fixed bodies. Momentum is conserved, kinetic energy too when
/// `restitution` is 1; a pair that is not approaching is left unchanged.
pub fn resolve(
    inverse_mass_a: f64,
    inverse_mass_b: f64,
    velocity_a: DVec3,
    velocity_b: DVec3,
    normal: DVec3,
    restitution: f64,
) -> Resolution {
    let normal_speed = (velocity_b - velocity_a).dot(normal);
    let inverse_sum = inverse_mass_a + inverse_mass_b;
    if normal_speed >= 0.0 || inverse_sum == 0.0 {
        return Resolution {
            velocity_a,
            velocity_b,
            impulse: 0.0,
        };
    }
    let impulse = -(1.0 + restitution) * normal_speed / inverse_sum;
    Resolution {
        velocity_a: velocity_a - normal * (impulse * inverse_mass_a),
        velocity_b: velocity_b + normal * (impulse * inverse_mass_b),
        impulse,
    }
}

/// How the restitutions of two bodies combine into the pair's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum CombineRule {
    /// The smaller of the two: the less bouncy material wins. The default.
    #[default]
    Min,
    /// The larger of the two.
    Max,
    /// The mean of the two.
    Average,
    /// The product of the two.
    Multiply,
}

impl CombineRule {
    /// Combines two restitutions.
    pub fn combine(self, a: f64, b: f64) -> f64 {
        match self {
            CombineRule::Min => a.min(b),
            CombineRule::Max => a.max(b),
            CombineRule::Average => 0.5 * (a + b),
            CombineRule::Multiply => a * b,
        }
    }
}

/// One contact of a group resolved at once by [`resolve_simultaneous`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroupContact {
    /// Index of the first body in the group's arrays.
    pub a: usize,
    /// Index of the second body.
    pub b: usize,
    /// Unit normal from `a` to `b`.
    pub normal: DVec3,
    /// The contact's restitution.
    pub restitution: f64,
    /// The separating speed the compression impulse aims for, `>= 0`: 0 for a plain contact
    /// (just stop approaching); a resting pair that overlaps too deeply is given enough to
    /// undo the excess over a step. The restitution impulse comes on top of it.
    pub bias: f64,
    /// A string rather than a contact: `b` is its anchor (inverse mass 0, at rest) and `normal`
    /// points from the anchor side outward, so "not approaching" means "not stretching". It
    /// gets no restitution and is enforced again after the restitution impulses.
    pub string: bool,
}

/// The most sweeps [`resolve_simultaneous`] makes over its contacts.
pub const MAX_GROUP_SWEEPS: u32 = 256;

/// Resolves several contacts that happen at the same instant, all at once: a ball striking two
/// touching balls symmetrically sends them off symmetrically (where one contact after the other
/// would not).
///
/// First the compression impulses `λ ≥ 0` are found that just stop every contact approaching
/// (or, with a [`GroupContact::bias`], make it separate at that speed) (projected Gauss–Seidel on the contacts until it converges to the last bit, at most
/// [`MAX_GROUP_SWEEPS`] sweeps), then each contact gets `restitution · λ` more. Momentum is
/// conserved, and kinetic energy is never gained: with a common restitution `e` it changes by
/// `(e² − 1)/2 · λᵀAλ`, so it is conserved exactly when `e = 1`. A single contact gives the same
/// answer as [`resolve`].
///
/// `velocities` are updated in place; `impulses` receives each contact's total impulse.
pub fn resolve_simultaneous(
    inverse_masses: &[f64],
    velocities: &mut [DVec3],
    contacts: &[GroupContact],
    impulses: &mut Vec<f64>,
) {
    impulses.clear();
    impulses.resize(contacts.len(), 0.0);
    let apply = |velocities: &mut [DVec3], c: &GroupContact, impulse: f64| {
        velocities[c.a] -= c.normal * (impulse * inverse_masses[c.a]);
        velocities[c.b] += c.normal * (impulse * inverse_masses[c.b]);
    };
    let scale = contacts
        .iter()
        .map(|c| {
            let speed = (velocities[c.b] - velocities[c.a]).dot(c.normal).abs();
            speed.max(c.bias)
        })
        .fold(0.0f64, f64::max);
    for _ in 0..MAX_GROUP_SWEEPS {
        let mut largest_change = 0.0f64;
        for (c, impulse) in contacts.iter().zip(impulses.iter_mut()) {
            let inverse_sum = inverse_masses[c.a] + inverse_masses[c.b];
            if inverse_sum == 0.0 {
                continue;
            }
            let normal_speed = (velocities[c.b] - velocities[c.a]).dot(c.normal) - c.bias;
            let next = (*impulse - normal_speed / inverse_sum).max(0.0);
            let change = next - *impulse;
            if change != 0.0 {
                apply(velocities, c, change);
                *impulse = next;
                largest_change = largest_change.max((change * inverse_sum).abs());
            }
        }
        if largest_change <= 1e-15 * scale {
            break;
        }
    }
    for (c, impulse) in contacts.iter().zip(impulses.iter_mut()) {
        if !c.string {
            let extra = c.restitution * *impulse;
            apply(velocities, c, extra);
            *impulse += extra;
        }
    }
    // The restitution impulses may stretch a string: pull it back (restitution 0), one pass per
    // string, each only ever pulling.
    for _ in 0..MAX_GROUP_SWEEPS {
        let mut largest_change = 0.0f64;
        for (c, impulse) in contacts
            .iter()
            .zip(impulses.iter_mut())
            .filter(|(c, _)| c.string)
        {
            let inverse_sum = inverse_masses[c.a] + inverse_masses[c.b];
            let normal_speed = (velocities[c.b] - velocities[c.a]).dot(c.normal);
            if inverse_sum > 0.0 && normal_speed < 0.0 {
                let change = -normal_speed / inverse_sum;
                apply(velocities, c, change);
                *impulse += change;
                largest_change = largest_change.max(-normal_speed);
            }
        }
        if largest_change <= 1e-15 * scale {
            break;
        }
    }
}
