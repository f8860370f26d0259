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
