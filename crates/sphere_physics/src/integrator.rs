//! Time integration: how a step's velocity change is split around the drift.
//!
//! Every integrator here is a *kick-drift-kick* scheme: within a step of length `dt` a body
//! receives a velocity change (`before`), then drifts in a straight line at constant velocity for
//! the whole step, then receives a second velocity change (`after`). Collision detection only ever
//! sees the drift, a straight line, so the exact time-of-impact test is a closed-form quadratic
//! whatever integrator is chosen, and collision code never depends on integration.
//!
//! The drift's velocity is taken as the body's velocity at the middle of the step (so it is for
//! both integrators here: leapfrog's exactly, semi-implicit Euler's as its staggered velocity).
//! An impact at time `t` of the step between bodies under different accelerations (a ball
//! striking a fixed floor under gravity) answers their speed at that instant: the drifts'
//! relative speed plus their relative acceleration times `t − dt/2`. So an elastic ball
//! bounces back to the height it fell from, whenever in the step it strikes.

use std::fmt::Debug;

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// The velocity changes a body receives around its drift in one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kicks {
    /// Velocity change applied at the start of the step, before the drift.
    pub before: DVec3,
    /// Velocity change applied at the end of the step, after the drift.
    pub after: DVec3,
}

/// A time integrator for bodies under constant acceleration within a step.
pub trait Integrator: Debug + Send + Sync {
    /// The kicks for a body with `velocity` under `acceleration` over a step of `dt`.
    ///
    /// The solver takes the drift's velocity (`velocity + before`) as the body's velocity at
    /// the middle of the step, as both built-in integrators' is, when it answers an impact
    /// between bodies under different accelerations (see the module docs): an integrator whose
    /// drift stands for another instant gets bounces off a fixed floor wrong by up to
    /// `acceleration · dt / 2`.
    fn kicks(&self, velocity: DVec3, acceleration: DVec3, dt: f64) -> Kicks;
}

/// Semi-implicit (symplectic) Euler: `v += a dt; x += v dt`. The whole kick comes first.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SemiImplicitEuler;

impl Integrator for SemiImplicitEuler {
    fn kicks(&self, _velocity: DVec3, acceleration: DVec3, dt: f64) -> Kicks {
        Kicks {
            before: acceleration * dt,
            after: DVec3::ZERO,
        }
    }
}

/// Leapfrog (velocity Verlet): half the kick before the drift, half after. Exact at step ends for
/// constant acceleration (free fall lands on the parabola), still a straight drift within a step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Leapfrog;

impl Integrator for Leapfrog {
    fn kicks(&self, _velocity: DVec3, acceleration: DVec3, dt: f64) -> Kicks {
        let half = acceleration * (0.5 * dt);
        Kicks {
            before: half,
            after: half,
        }
    }
}

/// The built-in integrators, as chosen in [`Settings`](crate::Settings) and scene files.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum IntegratorKind {
    /// [`SemiImplicitEuler`], the default.
    #[default]
    SemiImplicitEuler,
    /// [`Leapfrog`].
    Leapfrog,
}

impl Integrator for IntegratorKind {
    fn kicks(&self, velocity: DVec3, acceleration: DVec3, dt: f64) -> Kicks {
        match self {
            IntegratorKind::SemiImplicitEuler => {
                SemiImplicitEuler.kicks(velocity, acceleration, dt)
            }
            IntegratorKind::Leapfrog => Leapfrog.kicks(velocity, acceleration, dt),
        }
    }
}
