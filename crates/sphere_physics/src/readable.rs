//! Numbers as error messages print them.

use std::fmt;

/// A number as error messages print it: as Rust prints an `f64` (the shortest text that reads
/// back the same) between 1e-5 and 1e16 in size, and in exponent form beyond (`1e300`, not
/// three hundred digits; `5e-324`, not three hundred and twenty-four).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Readable(pub f64);

impl fmt::Display for Readable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let size = self.0.abs();
        if size == 0.0 || !size.is_finite() || (1e-5..1e16).contains(&size) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}
