//! Time of impact: when, within an interval, two drifting spheres first touch.
//!
//! Both methods look at the same thing: the relative motion of sphere `b` seen from sphere `a`,
//! a straight line `d + w t` (see [`crate::integrator`]), and the contact distance `R` (the sum of
//! the radii).

use std::fmt::Debug;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::Tolerance;
use crate::contact::{approaching, touching_or_overlapping};

/// The result of a time-of-impact query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToiOutcome {
    /// The time of impact in `[0, t_max]`, or `None` if the pair does not collide in the interval.
    pub time: Option<f64>,
    /// Iterations the method spent (0 for closed-form answers).
    pub iterations: u32,
}

/// A time-of-impact method.
pub trait TimeOfImpact: Debug + Send + Sync {
    /// The first time in `[0, t_max]` at which a sphere at relative position `d + w t` from another
    /// touches it while approaching, with `contact` the sum of the radii.
    ///
    /// A pair already touching (within `tol`) or overlapping at `t = 0` collides at 0 if it is
    /// approaching, and not at all otherwise. An answer outside `[0, t_max]` (or NaN) is taken
    /// as no impact.
    fn time_of_impact(
        &self,
        d: DVec3,
        w: DVec3,
        contact: f64,
        t_max: f64,
        tol: Tolerance,
    ) -> ToiOutcome;
}

/// The answer at `t = 0`, shared by both methods: `Some(outcome)` if the pair is already touching.
fn at_start(d: DVec3, w: DVec3, contact: f64, tol: Tolerance) -> Option<ToiOutcome> {
    let distance = d.length();
    if !touching_or_overlapping(distance, contact, tol) {
        return None;
    }
    // The normal speed. Where speed times distance overflows (past about 1e154), it is taken
    // along the unit normal instead: an overflow to infinity read as not approaching, and a
    // touching pair closing that fast passed through.
    let along = d.dot(w);
    let normal_speed = if along.is_finite() {
        along / distance
    } else {
        (d / distance).dot(w)
    };
    let hit = distance > 0.0 && approaching(normal_speed, tol);
    Some(ToiOutcome {
        time: hit.then_some(0.0),
        iterations: 0,
    })
}

/// Below this product of a pair's relative speed and contact distance (in SI units) the exact
/// method works in units of the pair (see [`ExactToi`]): its square, 1e-280, is still far from
/// where an f64 loses precision to underflow (1e-308).
const TINY_PRODUCT: f64 = 1e-140;

/// The exact swept-sphere test: the first root of `|d + w t|^2 = R^2`, in closed form.
///
/// Written for precision: the discriminant is computed as `|w|^2 R^2 - |d x w|^2` (no
/// cancellation between large terms for fast or distant pairs) and the root as
/// `c / (-b + sqrt(disc))` with `c = (|d| - R)(|d| + R)` (no cancellation for grazing or nearly
/// touching pairs). Where the products of speed and distance overflow an f64 (past about
/// 1e154, as a sphere of 1e100 m met at 1e94 m/s), the same root is taken with the relative
/// velocity scaled to at most 1 a component; where they would underflow (below about 1e-140,
/// as spheres of 1e-80 m closing at 1e-83 m/s), in units of the pair's size and speed. Nothing
/// can tunnel, whatever the speeds or the step length, as long as the squares of distances
/// stay within an f64: distances and radii below about 1e150 m (radii are held to
/// [`MAX_RADIUS`](crate::MAX_RADIUS)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ExactToi;

impl TimeOfImpact for ExactToi {
    fn time_of_impact(
        &self,
        d: DVec3,
        w: DVec3,
        contact: f64,
        t_max: f64,
        tol: Tolerance,
    ) -> ToiOutcome {
        if let Some(outcome) = at_start(d, w, contact, tol) {
            return outcome;
        }
        let none = ToiOutcome {
            time: None,
            iterations: 0,
        };
        // Where products of speed and distance would underflow (spheres 1e-80 m across closing
        // at 1e-83 m/s: the discriminant's 4e-326 is 0 in an f64, and the root came out past
        // the pair's meeting), the same root in units of the pair's size and of its relative
        // velocity's largest component, the time scaled back.
        let speed = w.abs().max_element();
        let (d, w, contact, unit_time) = if speed > 0.0 && speed * contact < TINY_PRODUCT {
            let length = d.abs().max_element().max(contact);
            (d / length, w / speed, contact / length, length / speed)
        } else {
            (d, w, contact, 1.0)
        };
        let half_b = d.dot(w);
        if half_b >= 0.0 {
            return none;
        }
        let discriminant =
            |w: DVec3| w.length_squared() * contact * contact - d.cross(w).length_squared();
        let (mut half_b, mut disc, mut scale) = (half_b, discriminant(w), 1.0);
        if !disc.is_finite() {
            // Speed times distance overflowed: the same root in units where the relative
            // velocity is at most 1 a component, the time scaled back.
            scale = w.abs().max_element();
            let unit = w / scale;
            (half_b, disc) = (d.dot(unit), discriminant(unit));
        }
        if half_b >= 0.0 || disc < 0.0 || disc.is_nan() {
            return none;
        }
        let distance = d.length();
        let c = (distance - contact) * (distance + contact);
        let t = c / (-half_b + disc.sqrt());
        let t = if scale == 1.0 { t } else { t / scale };
        let t = if unit_time == 1.0 { t } else { t * unit_time };
        ToiOutcome {
            time: (t <= t_max).then_some(t),
            iterations: 0,
        }
    }
}

/// The tutorial's method (Bourg, *Physics for Game Developers*): look only at the end of the
/// interval; if the pair intersects there, bisect `max_iterations` times between the last time
/// known apart and the first time known touching, and report the latter.
///
/// Its known weaknesses are kept on purpose, for comparison: a pair that passes through each
/// other within one interval is missed (tunnelling), and the reported time is late by up to
/// `t_max / 2^max_iterations`, leaving the pair overlapping when it is resolved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bisection {
    /// Number of bisection steps, at most [`MAX_BISECTION_ITERATIONS`](crate::MAX_BISECTION_ITERATIONS)
    /// (more are taken as that many: by then the interval is below an f64's resolution).
    pub max_iterations: u32,
}

impl Default for Bisection {
    fn default() -> Self {
        Bisection { max_iterations: 8 }
    }
}

impl TimeOfImpact for Bisection {
    fn time_of_impact(
        &self,
        d: DVec3,
        w: DVec3,
        contact: f64,
        t_max: f64,
        tol: Tolerance,
    ) -> ToiOutcome {
        if let Some(outcome) = at_start(d, w, contact, tol) {
            return outcome;
        }
        let touching_at = |t: f64| touching_or_overlapping((d + w * t).length(), contact, tol);
        if !touching_at(t_max) {
            return ToiOutcome {
                time: None,
                iterations: 0,
            };
        }
        let (mut lo, mut hi) = (0.0, t_max);
        let iterations = self.max_iterations.min(crate::MAX_BISECTION_ITERATIONS);
        for _ in 0..iterations {
            let mid = 0.5 * (lo + hi);
            if touching_at(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        ToiOutcome {
            time: Some(hi),
            iterations,
        }
    }
}

/// The built-in time-of-impact methods, as chosen in [`Settings`](crate::Settings) and scene files.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ToiMethod {
    /// [`ExactToi`]: closed-form swept test. The default.
    #[default]
    Exact,
    /// [`Bisection`] with the given number of iterations (the tutorial used 8).
    Bisection {
        /// Number of bisection steps.
        max_iterations: u32,
    },
}

impl TimeOfImpact for ToiMethod {
    fn time_of_impact(
        &self,
        d: DVec3,
        w: DVec3,
        contact: f64,
        t_max: f64,
        tol: Tolerance,
    ) -> ToiOutcome {
        match *self {
            ToiMethod::Exact => ExactToi.time_of_impact(d, w, contact, t_max, tol),
            ToiMethod::Bisection { max_iterations } => {
                Bisection { max_iterations }.time_of_impact(d, w, contact, t_max, tol)
            }
        }
    }
}
