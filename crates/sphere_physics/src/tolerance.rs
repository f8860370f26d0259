//! The one tolerance helper behind every floating-point equality test.

use serde::{Deserialize, Serialize};

/// Tolerance for floating-point equality: `a` equals `b` when
/// `|a - b| <= epsilon * (1 + max(|a|, |b|))`, i.e. absolute near zero and relative for large
/// values; an infinity equals only itself.
///
/// Every "are these equal?" question in the engine (are two spheres touching, is a normal speed
/// zero) goes through [`Tolerance::eq`], so there is exactly one knob.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Tolerance {
    epsilon: f64,
}

impl Tolerance {
    /// The default: `1e-9`.
    pub const DEFAULT: Tolerance = Tolerance { epsilon: 1e-9 };

    /// A tolerance of `epsilon`; `None` unless `epsilon` is in `[0, 0.5)`, the range
    /// [`Settings::validate`](crate::Settings::validate) accepts.
    pub fn new(epsilon: f64) -> Option<Self> {
        (0.0..0.5)
            .contains(&epsilon)
            .then_some(Tolerance { epsilon })
    }

    /// The epsilon this tolerance was made with.
    pub fn epsilon(self) -> f64 {
        self.epsilon
    }

    /// Whether `a` and `b` are equal within this tolerance. An infinity equals only itself: it
    /// is not within any tolerance of a finite number (before the fifty-seventh session it was,
    /// as the tolerance scales with the larger: a distance that overflowed counted as touching,
    /// and a normal speed that overflowed as not approaching).
    pub fn eq(self, a: f64, b: f64) -> bool {
        let difference = (a - b).abs();
        a == b
            || (difference < f64::INFINITY
                && difference <= self.epsilon * (1.0 + a.abs().max(b.abs())))
    }

    /// Whether `x` is zero within this tolerance.
    pub fn is_zero(self, x: f64) -> bool {
        self.eq(x, 0.0)
    }

    /// Whether `a < b` by more than the tolerance.
    pub fn lt(self, a: f64, b: f64) -> bool {
        a < b && !self.eq(a, b)
    }
}

impl Default for Tolerance {
    fn default() -> Self {
        Self::DEFAULT
    }
}
