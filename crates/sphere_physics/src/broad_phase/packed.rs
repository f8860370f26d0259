//! Boxes packed into 16-bit integers in a frame around the grid's block, so that the grid's
//! scans read 16 bytes per box and compare a box with a query in one instruction.
//!
//! A box is mapped into the frame (an affine map per axis, the same for every box) and each
//! side rounded to an integer: the low corner down (its floor), the high corner to no less than
//! its floor (up, but for a rounding tie in `2·BIAS - v` below the frame's middle, which lands
//! it on the floor). The map never decreases, so
//! boxes that meet still meet when packed: the scans find a superset of the overlapping pairs,
//! which is all they must find. A packed box is `[lo.x, lo.y, lo.z, 0, -hi.x, -hi.y, -hi.z, 0]`
//! and a query `[hi.x, hi.y, hi.z, 0, -lo.x, -lo.y, -lo.z, 0]`: they meet exactly when no lane
//! of the box exceeds the query's.

use glam::DVec3;

use super::Aabb;

/// The largest magnitude of a packed coordinate: [`Packed::empty`] lies beyond it.
const LIMIT: i32 = 32_766;

/// Steps of the frame across the block and its border: packed coordinates of the block lie
/// within `±SPAN / 2`, well inside [`LIMIT`].
const SPAN: f64 = 32_000.0;

/// The finest step: a 256th of a cell (boxes grow by less than that on each side).
const PER_CELL: f64 = 256.0;

/// Added before rounding, so that every value rounded is positive (truncation is then the
/// floor), and taken off after.
const BIAS: i32 = 32_768;

/// The map from space into the frame: `v · scale + offset - BIAS` per axis (a fourth lane maps
/// everything to 0).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Frame {
    scale: [f64; 4],
    offset: [f64; 4],
}

impl Frame {
    /// The frame for a block of `dims` cells of side `cell` whose lowest cell starts at
    /// `lo`, with two cells more on every side: 256 steps per cell, or [`SPAN`] steps along
    /// the block if that is coarser.
    pub fn new(lo: DVec3, cell: DVec3, dims: [usize; 3]) -> Frame {
        let mut frame = Frame {
            scale: [0.0; 4],
            offset: [0.0, 0.0, 0.0, f64::from(BIAS)],
        };
        for a in 0..3 {
            let per_cell = (SPAN / (dims[a] as f64 + 4.0)).min(PER_CELL);
            let scale = per_cell / cell[a];
            let start = lo[a] - 2.0 * cell[a];
            frame.scale[a] = scale;
            frame.offset[a] = f64::from(BIAS) - SPAN / 2.0 - start * scale;
        }
        frame
    }
}

/// A grid body's box in the frame (see the module docs).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Packed(lanes::Lanes);

/// A query's box in the frame, as the boxes it is compared with see it (see the module docs).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Query(lanes::Lanes);

impl Packed {
    /// `b` in `frame`, each side rounded to an integer (see the module docs).
    #[inline]
    pub fn new(frame: &Frame, b: &Aabb) -> Packed {
        Packed(lanes::Lanes::pack(frame, b))
    }

    /// Meets nothing (its low corner lies beyond any query's high one): the box of a body that
    /// left the grid, and the padding after the last body.
    pub fn empty() -> Packed {
        let out = (LIMIT + 1) as i16;
        Packed(lanes::Lanes::new([out, out, out, 0, out, out, out, 0]))
    }

    /// Whether the box meets `q` (touching counts, and a little more: both are rounded to
    /// integers). No branch.
    #[inline(always)]
    pub fn meets(&self, q: &Query) -> bool {
        self.0.at_most(&q.0)
    }

    /// The same box as a query.
    #[inline]
    pub fn as_query(&self) -> Query {
        Query(self.0.turned())
    }
}

impl Query {
    /// `b` in `frame`, each side rounded to an integer (see the module docs).
    #[inline]
    pub fn new(frame: &Frame, b: &Aabb) -> Query {
        Packed::new(frame, b).as_query()
    }
}

/// Eight 16-bit lanes in one SSE2 register, mapped, rounded and compared in a handful of
/// instructions.
#[cfg(all(target_arch = "x86_64", not(feature = "portable")))]
mod lanes {
    use std::arch::x86_64::{
        __m128d, __m128i, _mm_add_pd, _mm_cmpgt_epi16, _mm_cvttpd_epi32, _mm_max_pd, _mm_min_pd,
        _mm_movemask_epi8, _mm_mul_pd, _mm_packs_epi32, _mm_set_epi16, _mm_set_pd, _mm_set1_epi32,
        _mm_set1_pd, _mm_setzero_si128, _mm_shuffle_epi32, _mm_sub_epi16, _mm_sub_epi32,
        _mm_sub_pd, _mm_unpacklo_epi64,
    };

    use super::{Aabb, BIAS, Frame, LIMIT};

    #[derive(Clone, Copy, Debug)]
    pub struct Lanes(__m128i);

    // SAFETY (every `unsafe` below): the intrinsics need SSE2, which every x86-64 processor
    // has (it is part of the target's baseline); they touch nothing but registers.
    impl Lanes {
        pub fn new(v: [i16; 8]) -> Self {
            Lanes(unsafe { _mm_set_epi16(v[7], v[6], v[5], v[4], v[3], v[2], v[1], v[0]) })
        }

        /// `[lo, 0, -hi, 0]` for `b` in `frame`, each side rounded (see the module docs).
        #[inline(always)]
        pub fn pack(frame: &Frame, b: &Aabb) -> Self {
            let (s, o) = (&frame.scale, &frame.offset);
            unsafe {
                let least = _mm_set1_pd(f64::from(BIAS - LIMIT));
                let most = _mm_set1_pd(f64::from(BIAS + LIMIT));
                // Into the frame, biased, and clamped to BIAS ± LIMIT (a NaN to the least).
                let map = |x: f64, y: f64, lanes: usize| -> __m128d {
                    let v = _mm_set_pd(y, x);
                    let v = _mm_add_pd(
                        _mm_mul_pd(v, _mm_set_pd(s[lanes + 1], s[lanes])),
                        _mm_set_pd(o[lanes + 1], o[lanes]),
                    );
                    _mm_min_pd(_mm_max_pd(v, least), most)
                };
                let (lo_xy, lo_zw) = (map(b.lo.x, b.lo.y, 0), map(b.lo.z, 0.0, 2));
                // 2·BIAS - floor(2·BIAS - v) is ceil(v), or floor(v) after a rounding tie in the
                // subtraction (v < BIAS): never below floor(v), which is all a scan needs.
                // 2·BIAS - v is positive.
                let twice = _mm_set1_pd(f64::from(2 * BIAS));
                let up_xy = _mm_sub_pd(twice, map(b.hi.x, b.hi.y, 0));
                let up_zw = _mm_sub_pd(twice, map(b.hi.z, 0.0, 2));
                // Truncation of positive values is the floor.
                let bias = _mm_set1_epi32(BIAS);
                let lo = _mm_unpacklo_epi64(_mm_cvttpd_epi32(lo_xy), _mm_cvttpd_epi32(lo_zw));
                let up = _mm_unpacklo_epi64(_mm_cvttpd_epi32(up_xy), _mm_cvttpd_epi32(up_zw));
                // lo - BIAS, and floor(2·BIAS - hi) - BIAS = -(2·BIAS - floor(2·BIAS - hi) - BIAS).
                Lanes(_mm_packs_epi32(
                    _mm_sub_epi32(lo, bias),
                    _mm_sub_epi32(up, bias),
                ))
            }
        }

        /// `[a, 0, b, 0]` to `[-b, 0, -a, 0]`: a box to its query.
        #[inline(always)]
        pub fn turned(self) -> Self {
            unsafe {
                Lanes(_mm_sub_epi16(
                    _mm_setzero_si128(),
                    _mm_shuffle_epi32::<0b01_00_11_10>(self.0),
                ))
            }
        }

        /// Whether no lane exceeds `other`'s: one comparison and a mask.
        #[inline(always)]
        pub fn at_most(&self, other: &Self) -> bool {
            unsafe { _mm_movemask_epi8(_mm_cmpgt_epi16(self.0, other.0)) == 0 }
        }
    }
}

/// The same lanes as plain integers, for other processors (and on x86-64 with the `portable`
/// feature, so that the tests run this code too).
#[cfg(any(not(target_arch = "x86_64"), feature = "portable"))]
mod lanes {
    use super::{Aabb, BIAS, Frame, LIMIT};

    #[derive(Clone, Copy, Debug)]
    pub struct Lanes([i16; 8]);

    impl Lanes {
        pub fn new(v: [i16; 8]) -> Self {
            Lanes(v)
        }

        pub fn pack(frame: &Frame, b: &Aabb) -> Self {
            let (least, most) = (f64::from(BIAS - LIMIT), f64::from(BIAS + LIMIT));
            let map = |v: f64, a: usize| {
                let v = v * frame.scale[a] + frame.offset[a];
                if v.is_nan() {
                    least
                } else {
                    v.clamp(least, most)
                }
            };
            let twice = f64::from(2 * BIAS);
            let down = |v: f64, a: usize| (map(v, a) as i32 - BIAS) as i16;
            let up = |v: f64, a: usize| ((twice - map(v, a)) as i32 - BIAS) as i16;
            Lanes([
                down(b.lo.x, 0),
                down(b.lo.y, 1),
                down(b.lo.z, 2),
                0,
                up(b.hi.x, 0),
                up(b.hi.y, 1),
                up(b.hi.z, 2),
                0,
            ])
        }

        pub fn turned(self) -> Self {
            let v = self.0;
            Lanes([-v[4], -v[5], -v[6], 0, -v[0], -v[1], -v[2], 0])
        }

        pub fn at_most(&self, other: &Self) -> bool {
            self.0.iter().zip(&other.0).all(|(a, b)| a <= b)
        }
    }
}
