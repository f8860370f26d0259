//! The glance at a pair of drifts: whether a pair cannot meet within the rest of the step, nor
//! end it overlapping, worked out from a few products and compared without a branch each. Most
//! pairs tested are dismissed by it; the rest go to the full test (`Solver::test_pair_fully`).

use glam::DVec3;

use super::Segment;

/// How far apart two spheres must be not to touch within the tolerance: farther than
/// `(reach + epsilon) · scale`. Touching within the tolerance means
/// `|distance - reach| <= ε (1 + distance)`, so the bound is `(reach + ε) / (1 - ε)`, here
/// with a margin of a millionth (the division done once per step, not once per pair).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Apart {
    epsilon: f64,
    scale: f64,
}

impl Apart {
    pub(super) fn new(epsilon: f64) -> Self {
        Apart {
            epsilon,
            scale: (1.0 + 1e-6) / (1.0 - epsilon),
        }
    }
}

/// Whether a pair whose relative motion is `d + w·τ` (closing now), `end_squared` = `|d + w·rest|²`
/// apart at the end of the step, surely does not touch within `rest`: it is still closing then
/// (so it was farther apart all along) and farther apart than contact within the tolerance,
/// with a margin of a millionth of the reach, which either time-of-impact method's rounding
/// stays well within unless the pair moves more than a million reaches in the step (not
/// skipped). Either method then reports no impact; skipping it changes nothing.
#[inline]
// `!(a >= b)`, not `a < b`: for a NaN (drifts that overflow) it answers as an early return
// on `a >= b` would.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub(super) fn cannot_touch_by(
    rest: f64,
    d: DVec3,
    w: DVec3,
    end_squared: f64,
    reach: f64,
    apart: Apart,
) -> bool {
    let ww = w.length_squared();
    let far = (reach + apart.epsilon) * apart.scale;
    // Every condition worked out, then combined without a branch: in the glance, whose
    // outcome is a coin toss, one branch on it instead of one on each condition made the 10k
    // shower 9% faster.
    !(d.dot(w) + ww * rest >= 0.0)
        & !(ww * rest * rest > 1e12 * reach * reach)
        & (end_squared > far * far)
}

/// A pair's [`Relative`] drifts and how far apart they end the step, against how near counts
/// as overlapping then: worked out by the glance, and handed on to the full test.
#[derive(Clone, Copy)]
pub(super) struct Glance {
    pub(super) relative: Relative,
    /// `|d + w·rest|²`.
    pub(super) end_squared: f64,
    /// See [`end_allowance`].
    pub(super) allowance: f64,
}

impl Glance {
    #[inline(always)]
    pub(super) fn of(si: &Segment, sj: &Segment, t: f64, dt: f64) -> Self {
        let relative = Relative::of(si, sj, t, dt);
        let Relative { d, w, reach, rest } = relative;
        Glance {
            relative,
            end_squared: (d + w * rest).length_squared(),
            allowance: end_allowance(si, sj, w, reach, rest),
        }
    }

    /// Whether the pair is dismissed at a glance: parting, or closing but still apart at the
    /// step's end, so no impact; nor ending overlapping (as `test_pair_fully` reckons it): it
    /// would only return. The conditions are combined without branches (`|`, `&`): one
    /// branch, on the outcome.
    #[inline(always)]
    pub(super) fn dismisses(&self, apart: Apart) -> bool {
        let Glance {
            relative: Relative { d, w, reach, rest },
            end_squared,
            allowance,
        } = *self;
        let passed = (d.dot(w) >= 0.0) | cannot_touch_by(rest, d, w, end_squared, reach, apart);
        passed & (end_squared >= allowance * allowance)
    }

    /// The same glance seen from the other body: the relative drifts negated.
    #[inline(always)]
    pub(super) fn turned(self) -> Self {
        Glance {
            relative: Relative {
                d: -self.relative.d,
                w: -self.relative.w,
                ..self.relative
            },
            ..self
        }
    }

    /// Whether two glances hold the same numbers, taking any NaN as the same (drifts that
    /// overflow; debug checks).
    #[cfg(debug_assertions)]
    pub(super) fn same_as(&self, other: &Glance) -> bool {
        let same = |x: f64, y: f64| x == y || (x.is_nan() && y.is_nan());
        let (a, b) = (&self.relative, &other.relative);
        (0..3).all(|k| same(a.d[k], b.d[k]) && same(a.w[k], b.w[k]))
            && same(a.reach, b.reach)
            && same(a.rest, b.rest)
            && same(self.end_squared, other.end_squared)
            && same(self.allowance, other.allowance)
    }
}

/// One body's part of the glances at its pairs from time `t` (see [`Side::glance`]).
#[derive(Clone, Copy)]
pub(super) struct Side {
    /// Where it is at `t`.
    position: DVec3,
    velocity: DVec3,
    radius: f64,
    /// Its largest coordinate at the start of its drift (see [`end_allowance`]).
    magnitude: f64,
    /// The time the glances look from.
    pub(super) t: f64,
    /// The time left in the step.
    rest: f64,
}

impl Side {
    #[inline(always)]
    pub(super) fn of(segment: &Segment, t: f64, dt: f64) -> Self {
        Side {
            position: segment.position_at(t),
            velocity: segment.velocity,
            radius: segment.radius(),
            magnitude: segment.position.abs().max_element(),
            t,
            rest: dt - t,
        }
    }

    /// [`Glance::of`] this body and `other`, seen from this one: the same numbers as
    /// `Glance::of(this, other, ..)`, worked out in the same order (sums whose terms are
    /// swapped are the same, addition being commutative).
    #[inline(always)]
    pub(super) fn glance(&self, other: &Segment) -> Glance {
        let d = other.position_at(self.t) - self.position;
        let w = other.velocity - self.velocity;
        let (reach, rest) = (self.radius + other.radius(), self.rest);
        let magnitude = self.magnitude + other.position.abs().max_element();
        Glance {
            relative: Relative { d, w, reach, rest },
            end_squared: (d + w * rest).length_squared(),
            allowance: allowance_for(reach, magnitude, w, rest),
        }
    }
}

/// The glances from `side` at each of `candidates` (at most 64, indices into `segments`):
/// bit `i` set for each candidate [`Glance::dismisses`] does not dismiss. Without a branch on
/// any outcome (each a coin toss): four glances side by side where the processor has AVX,
/// otherwise one after the other. Either way the same operations on the same numbers in the
/// same order as [`Side::glance`] and [`Glance::dismisses`], so the same bits.
#[inline(always)]
pub(super) fn kept_by_glances(
    side: &Side,
    segments: &[Segment],
    candidates: &[u32],
    apart: Apart,
) -> u64 {
    debug_assert!(candidates.len() <= 64);
    #[cfg(all(target_arch = "x86_64", not(feature = "portable")))]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the processor has AVX (just checked).
        return unsafe { avx::kept_by_four(side, segments, candidates, apart) };
    }
    let mut kept = 0u64;
    for (at, &m) in candidates.iter().enumerate() {
        let dismissed = side.glance(&segments[m as usize]).dismisses(apart);
        kept |= u64::from(!dismissed) << at;
    }
    kept
}

/// What the first pass's filter needs besides the drifts (see [`first_pass_kept`]).
#[derive(Clone, Copy)]
pub(super) struct FirstPass {
    /// The step's length.
    pub(super) dt: f64,
    /// How near a pair must be to be looked at as a resting contact, beyond the reach and the
    /// contact band (`Solver::near_reach`); `None` when nothing rests this step.
    pub(super) near_reach: Option<f64>,
    /// The tolerance's epsilon (the contact band's part, see `contact_band`).
    pub(super) epsilon: f64,
    pub(super) apart: Apart,
}

impl FirstPass {
    /// Whether the first pass may skip pair `(si, sj)` (`si` first), one pair at a time: not
    /// both fixed, not near enough to rest (`Solver::may_rest` says no at once), and dismissed
    /// at a glance from the step's start. Such a pair needs nothing: the first pass would
    /// find it no resting contact and its full test would return at the glance.
    #[inline(always)]
    pub(super) fn skips(&self, si: &Segment, sj: &Segment) -> bool {
        if si.is_fixed() && sj.is_fixed() {
            return false;
        }
        if let Some(near_reach) = self.near_reach {
            let reach = si.radius() + sj.radius();
            let band = 2e-6 * si.radius().min(sj.radius()) + self.epsilon * (1.0 + reach);
            let near = reach + band + near_reach;
            // `!(a > b)`, as `Solver::may_rest` asks it (a NaN is near).
            #[allow(clippy::neg_cmp_op_on_partial_ord)]
            if !((sj.position - si.position).length_squared() > near * near) {
                return false;
            }
        }
        Glance::of(si, sj, 0.0, self.dt).dismisses(self.apart)
    }
}

/// The first pass's filter over `pairs` (at most 64, `(i, j)` with `i < j`, indices into
/// `segments`): bit `k` set for each pair [`FirstPass::skips`] does not skip, the same bits
/// either way. Without a branch on any outcome: four pairs side by side where the processor
/// has AVX, otherwise one after the other.
#[inline(always)]
pub(super) fn first_pass_kept(segments: &[Segment], pairs: &[(u32, u32)], pass: &FirstPass) -> u64 {
    debug_assert!(pairs.len() <= 64);
    #[cfg(all(target_arch = "x86_64", not(feature = "portable")))]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the processor has AVX (just checked).
        return unsafe { avx::first_pass_kept_by_four(segments, pairs, pass) };
    }
    let mut kept = 0u64;
    for (at, &(i, j)) in pairs.iter().enumerate() {
        let skips = pass.skips(&segments[i as usize], &segments[j as usize]);
        kept |= u64::from(!skips) << at;
    }
    kept
}

/// A pair of drifts seen from the first, from time `t` to the step's end.
#[derive(Clone, Copy)]
pub(super) struct Relative {
    /// Where the second is from the first at `t`.
    pub(super) d: DVec3,
    /// How fast it moves from it.
    pub(super) w: DVec3,
    /// The sum of their radii.
    pub(super) reach: f64,
    /// The time left in the step.
    pub(super) rest: f64,
}

impl Relative {
    #[inline(always)]
    fn of(si: &Segment, sj: &Segment, t: f64, dt: f64) -> Self {
        Relative {
            d: sj.position_at(t) - si.position_at(t),
            w: sj.velocity - si.velocity,
            reach: si.radius() + sj.radius(),
            rest: dt - t,
        }
    }
}

/// The distance within which a pair's ends count as overlapping (kept for the end-of-step
/// overlap), allowing for rounding: each body's end position is reckoned on its own, from
/// where it is, so far from the origin the two differ by more than a billionth of their reach.
#[inline(always)]
fn end_allowance(si: &Segment, sj: &Segment, w: DVec3, reach: f64, rest: f64) -> f64 {
    let magnitudes = si.position.abs().max_element() + sj.position.abs().max_element();
    allowance_for(reach, magnitudes, w, rest)
}

/// [`end_allowance`] from the sum of the two bodies' largest coordinates.
#[inline(always)]
fn allowance_for(reach: f64, magnitudes: f64, w: DVec3, rest: f64) -> f64 {
    reach * (1.0 + 1e-9) + 1e-12 * (magnitudes + w.abs().max_element() * rest)
}

/// The glances four at a time, one in each lane of AVX's registers: the same operations on
/// the same numbers in the same order as [`Side::glance`], [`Glance::of`] and
/// [`Glance::dismisses`] (so the same outcomes, bit for bit). An odd last few are worked out
/// again as the last one, and their bits dropped.
#[cfg(all(target_arch = "x86_64", not(feature = "portable")))]
mod avx {
    use std::arch::x86_64::{
        __m256d, _CMP_GE_OQ, _CMP_GT_OQ, _CMP_NGE_UQ, _CMP_NGT_UQ, _mm256_add_pd, _mm256_and_pd,
        _mm256_andnot_pd, _mm256_castsi256_pd, _mm256_cmp_pd, _mm256_loadu_pd, _mm256_max_pd,
        _mm256_min_pd, _mm256_movemask_pd, _mm256_mul_pd, _mm256_or_pd, _mm256_permute2f128_pd,
        _mm256_set1_epi64x, _mm256_set1_pd, _mm256_setzero_pd, _mm256_sub_pd, _mm256_unpackhi_pd,
        _mm256_unpacklo_pd,
    };

    use super::{Apart, FirstPass, Segment, Side};

    /// Three lanes of four: a vector per lane.
    type Vector = (__m256d, __m256d, __m256d);

    macro_rules! add {
        ($x:expr, $y:expr) => {
            _mm256_add_pd($x, $y)
        };
    }
    macro_rules! sub {
        ($x:expr, $y:expr) => {
            _mm256_sub_pd($x, $y)
        };
    }
    macro_rules! mul {
        ($x:expr, $y:expr) => {
            _mm256_mul_pd($x, $y)
        };
    }
    macro_rules! one {
        ($x:expr) => {
            _mm256_set1_pd($x)
        };
    }
    // glam's `max_element`: max(x, max(y, z)), each `if p > q { p } else { q }`, as MAXPD.
    macro_rules! max_element {
        ($v:expr) => {
            _mm256_max_pd($v.0, _mm256_max_pd($v.1, $v.2))
        };
    }
    macro_rules! dot {
        ($a:expr, $b:expr) => {
            add!(add!(mul!($a.0, $b.0), mul!($a.1, $b.1)), mul!($a.2, $b.2))
        };
    }

    /// Four drifts, one per lane.
    struct Drifts {
        position: Vector,
        velocity: Vector,
        t0: __m256d,
        signed_radius: __m256d,
    }

    #[inline]
    #[target_feature(enable = "avx")]
    fn abs(x: __m256d) -> __m256d {
        _mm256_and_pd(x, _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX)))
    }

    #[inline]
    #[target_feature(enable = "avx")]
    fn abs3(v: Vector) -> Vector {
        (abs(v.0), abs(v.1), abs(v.2))
    }

    /// The drifts of `segments[bodies[k]]` in lane `k`: each read as two rows of four
    /// (`[x, y, z, vx]`, `[vy, vz, t0, signed radius]`) and the four rows transposed.
    #[inline]
    #[target_feature(enable = "avx")]
    fn load(segments: &[Segment], bodies: [usize; 4]) -> Drifts {
        let rows = |lane: usize| {
            let start = std::ptr::from_ref(&segments[bodies[lane]]).cast::<f64>();
            // SAFETY: a `Segment` is eight `f64`s in a row (`repr(C)`: a position and a
            // velocity of three each, `t0`, `signed_radius`): both loads lie within it.
            unsafe { (_mm256_loadu_pd(start), _mm256_loadu_pd(start.add(4))) }
        };
        let ((a0, a1), (b0, b1), (c0, c1), (d0, d1)) = (rows(0), rows(1), rows(2), rows(3));
        let (lo_ab, hi_ab) = (_mm256_unpacklo_pd(a0, b0), _mm256_unpackhi_pd(a0, b0));
        let (lo_cd, hi_cd) = (_mm256_unpacklo_pd(c0, d0), _mm256_unpackhi_pd(c0, d0));
        let position = (
            _mm256_permute2f128_pd::<0x20>(lo_ab, lo_cd),
            _mm256_permute2f128_pd::<0x20>(hi_ab, hi_cd),
            _mm256_permute2f128_pd::<0x31>(lo_ab, lo_cd),
        );
        let vx = _mm256_permute2f128_pd::<0x31>(hi_ab, hi_cd);
        let (lo_ab, hi_ab) = (_mm256_unpacklo_pd(a1, b1), _mm256_unpackhi_pd(a1, b1));
        let (lo_cd, hi_cd) = (_mm256_unpacklo_pd(c1, d1), _mm256_unpackhi_pd(c1, d1));
        Drifts {
            position,
            velocity: (
                vx,
                _mm256_permute2f128_pd::<0x20>(lo_ab, lo_cd),
                _mm256_permute2f128_pd::<0x20>(hi_ab, hi_cd),
            ),
            t0: _mm256_permute2f128_pd::<0x31>(lo_ab, lo_cd),
            signed_radius: _mm256_permute2f128_pd::<0x31>(hi_ab, hi_cd),
        }
    }

    /// Where the drifts are at time `t` (`Segment::position_at`).
    #[inline]
    #[target_feature(enable = "avx")]
    fn position_at(drifts: &Drifts, t: __m256d) -> Vector {
        let (p, v) = (drifts.position, drifts.velocity);
        let since = sub!(t, drifts.t0);
        (
            add!(p.0, mul!(v.0, since)),
            add!(p.1, mul!(v.1, since)),
            add!(p.2, mul!(v.2, since)),
        )
    }

    /// [`super::Glance::dismisses`] in each lane, for the pair whose relative drift is
    /// `d + w·τ` over `rest`, with `reach` and `magnitudes` (the two bodies' largest
    /// coordinates, summed): all ones where dismissed.
    #[inline]
    #[target_feature(enable = "avx")]
    fn dismissed(
        (d, w): (Vector, Vector),
        reach: __m256d,
        magnitudes: __m256d,
        rest: __m256d,
        apart: Apart,
    ) -> __m256d {
        let end = (
            add!(d.0, mul!(w.0, rest)),
            add!(d.1, mul!(w.1, rest)),
            add!(d.2, mul!(w.2, rest)),
        );
        let end_squared = dot!(end, end);
        let allowance = add!(
            mul!(reach, one!(1.0 + 1e-9)),
            mul!(
                one!(1e-12),
                add!(magnitudes, mul!(max_element!(abs3(w)), rest))
            )
        );
        let (dw, ww) = (dot!(d, w), dot!(w, w));
        let far = mul!(add!(reach, one!(apart.epsilon)), one!(apart.scale));
        let zero = _mm256_setzero_pd();
        let cannot_touch = _mm256_and_pd(
            _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_NGE_UQ>(add!(dw, mul!(ww, rest)), zero),
                _mm256_cmp_pd::<_CMP_NGT_UQ>(
                    mul!(mul!(ww, rest), rest),
                    mul!(mul!(one!(1e12), reach), reach),
                ),
            ),
            _mm256_cmp_pd::<_CMP_GT_OQ>(end_squared, mul!(far, far)),
        );
        let passed = _mm256_or_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(dw, zero), cannot_touch);
        _mm256_and_pd(
            passed,
            _mm256_cmp_pd::<_CMP_GE_OQ>(end_squared, mul!(allowance, allowance)),
        )
    }

    /// Bits `at..at + 4` of a kept mask: the lanes not in `dropped`.
    #[inline]
    #[target_feature(enable = "avx")]
    fn kept_bits(dropped: __m256d, at: usize) -> u64 {
        u64::from(!_mm256_movemask_pd(dropped) as u32 & 0b1111) << at
    }

    /// [`super::kept_by_glances`] four candidates at a time. This replaced two glances side
    /// by side in SSE2's lanes: the 10k shower's step then executed 2.5% fewer instructions
    /// (callgrind), the same collisions.
    #[target_feature(enable = "avx")]
    pub(super) fn kept_by_four(
        side: &Side,
        segments: &[Segment],
        candidates: &[u32],
        apart: Apart,
    ) -> u64 {
        let (t, rest) = (one!(side.t), one!(side.rest));
        let (sp, sv) = (side.position, side.velocity);
        let n = candidates.len();
        let mut kept = 0u64;
        let mut at = 0;
        while at < n {
            let bodies = [0, 1, 2, 3].map(|lane| candidates[(at + lane).min(n - 1)] as usize);
            let drifts = load(segments, bodies);
            let p = position_at(&drifts, t);
            let v = drifts.velocity;
            let d = (
                sub!(p.0, one!(sp.x)),
                sub!(p.1, one!(sp.y)),
                sub!(p.2, one!(sp.z)),
            );
            let w = (
                sub!(v.0, one!(sv.x)),
                sub!(v.1, one!(sv.y)),
                sub!(v.2, one!(sv.z)),
            );
            let reach = add!(one!(side.radius), abs(drifts.signed_radius));
            let magnitudes = add!(one!(side.magnitude), max_element!(abs3(drifts.position)));
            kept |= kept_bits(dismissed((d, w), reach, magnitudes, rest, apart), at);
            at += 4;
        }
        if n < 64 {
            kept &= (1 << n) - 1;
        }
        kept
    }

    /// [`super::first_pass_kept`] four pairs at a time: [`FirstPass::skips`] in each lane.
    #[target_feature(enable = "avx")]
    pub(super) fn first_pass_kept_by_four(
        segments: &[Segment],
        pairs: &[(u32, u32)],
        pass: &FirstPass,
    ) -> u64 {
        let (zero, rest) = (_mm256_setzero_pd(), one!(pass.dt));
        let n = pairs.len();
        let mut kept = 0u64;
        let mut at = 0;
        while at < n {
            let pair = |lane: usize| pairs[(at + lane).min(n - 1)];
            let first = load(segments, [0, 1, 2, 3].map(|lane| pair(lane).0 as usize));
            let second = load(segments, [0, 1, 2, 3].map(|lane| pair(lane).1 as usize));
            let (ri, rj) = (abs(first.signed_radius), abs(second.signed_radius));
            let reach = add!(ri, rj);
            // Both fixed (both radii negative): never skipped. (Radii are finite and positive,
            // checked when bodies are made, so `0 > signed radius` is `is_sign_negative`.)
            let both_fixed = _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_GT_OQ>(zero, first.signed_radius),
                _mm256_cmp_pd::<_CMP_GT_OQ>(zero, second.signed_radius),
            );
            // Near enough to rest (`Solver::may_rest`), from the positions as they stand.
            let near = match pass.near_reach {
                Some(near_reach) => {
                    let band = add!(
                        mul!(one!(2e-6), _mm256_min_pd(ri, rj)),
                        mul!(one!(pass.epsilon), add!(one!(1.0), reach))
                    );
                    let near = add!(add!(reach, band), one!(near_reach));
                    let (pi, pj) = (first.position, second.position);
                    let gap = (sub!(pj.0, pi.0), sub!(pj.1, pi.1), sub!(pj.2, pi.2));
                    // `!(a > b)`, as `Solver::may_rest` asks it (a NaN is near).
                    _mm256_cmp_pd::<_CMP_NGT_UQ>(dot!(gap, gap), mul!(near, near))
                }
                None => zero,
            };
            // The glance from the step's start (`Glance::of(si, sj, 0, dt)`).
            let (qi, qj) = (position_at(&first, zero), position_at(&second, zero));
            let (vi, vj) = (first.velocity, second.velocity);
            let d = (sub!(qj.0, qi.0), sub!(qj.1, qi.1), sub!(qj.2, qi.2));
            let w = (sub!(vj.0, vi.0), sub!(vj.1, vi.1), sub!(vj.2, vi.2));
            let magnitudes = add!(
                max_element!(abs3(first.position)),
                max_element!(abs3(second.position))
            );
            let dismissed = dismissed((d, w), reach, magnitudes, rest, pass.apart);
            let skips = _mm256_andnot_pd(_mm256_or_pd(both_fixed, near), dismissed);
            kept |= kept_bits(skips, at);
            at += 4;
        }
        if n < 64 {
            kept &= (1 << n) - 1;
        }
        kept
    }
}
