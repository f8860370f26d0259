//! Overlaps with nothing accelerating: spheres placed overlapping in a world with no gravity
//! and no applied force are moved apart, a little each step, by their positions alone.
//!
//! Under any acceleration the resting solve undoes an overlap by a push that moves its bodies
//! within the step and is taken off at its end. With none there is no resting solve (nothing
//! presses a contact, so nothing is a resting contact), and two spheres left overlapping at
//! rest, or parting slower than they overlap, stayed so for ever. Here such pairs are moved
//! apart at the step's end, each body along the pair's normal in proportion to its inverse
//! mass: the pair's centre of mass stays where it is (unless one of them is fixed, and is not
//! moved, or on a string, which holds it within its length), and no velocity changes, so
//! momentum and kinetic energy are kept exactly. Spheres on strings in such a world are pressed
//! together by their swings, which curve into each other; moving them apart here is what keeps
//! them from sinking into each other step after step. Under gravity too, where a sphere on a
//! string pressed out along it by a heavier one is whipped round its anchor and its swing
//! curves back into the heavier one between impacts (solved on the swing's tangent, each leaves
//! the pair parting): the resting solve undoes overlaps only between resting contacts, so such
//! pairs deeper than [`STRUNG_OVERLAP`] of the smaller radius are moved back to that depth
//! here, and any pair such a move takes deeper than the step left it is moved back to where the
//! step left it (with nothing accelerating, any pair a move that kept no centre of mass did).
//! Part of [`Solver`]: these are its methods.

use glam::DVec3;

use super::{
    MAX_CORRECTION, STRUNG_OVERLAP, Solver, StepContext, Strung, at_length, bit, contact_band,
};
use crate::Body;
use crate::broad_phase::Aabb;

/// How many times the separation goes over its pairs at most in a step (Gauss–Seidel, each
/// pair moved apart in turn with what the pairs before it did; they stop once nothing moves):
/// a lone pair needs one, a crowd's pairs undo each other's moves in part. A light sphere
/// caged between heavy ones that overlap it from nearly opposite sides is freed only as they
/// move apart, by a share as small as the mass ratio each sweep: with 8 sweeps such a cage
/// (a ratio of 290) took 289 steps, with 32 it takes 71.
const SEPARATION_SWEEPS: u32 = 32;

/// The cosine of the largest angle between a move and a taut string's outward direction for
/// which the string holds its sphere against the move (30°: the sphere, free only to slide
/// round its swing, would weigh at least four times its mass along the move).
const HELD_WITHIN: f64 = 0.866_025_403_784_438_6;

impl Solver {
    /// Moves apart the pairs that end the step overlapping by more than their contact band,
    /// when nothing accelerates, and under an acceleration those with a sphere on a string by
    /// more than [`STRUNG_OVERLAP`] of the smaller radius (see
    /// [`Solver::separation_allowance`]; call after the write-back, with the bodies' final
    /// positions). Each pair is moved to touching (to that depth, under an acceleration), its
    /// bodies in proportion to their inverse masses; a body moves at most [`MAX_CORRECTION`] of
    /// its radius in a step, as a push under gravity does, so a sphere placed deep inside
    /// others comes out over a few steps and one caught between fixed spheres cannot be flung
    /// (the cap is a substep's, and apart from the pushes of a step that falls back). Fixed
    /// spheres are not moved. A sphere on a string is kept within its length: a move that would
    /// take it past it puts it on the string's sphere instead (so a taut string's sphere moves
    /// along its swing), and one its string holds against the move (see
    /// [`Solver::held_by_string`]) is not moved: the other sphere of the pair takes all of it.
    /// In a pair with a sphere on a string (whose string holds it, so the pair's centre of mass
    /// is not kept anyway), what one body's cap leaves undone the other takes, within its own
    /// cap, and a body's cap is as far as it drifted in the step if that is farther (see
    /// [`Solver::strung_pair_cap`]). A pair without a string that the separation's moves take
    /// deeper than the step left it (under an acceleration any; with nothing accelerating, one
    /// pushed in by a move that kept no centre of mass: against a fixed sphere, a string, or a
    /// cap made up for) is carried: moved back to that depth, the sphere pushed as far as the
    /// larger cap of the two, what one body's cap leaves undone the other taking. Before,
    /// spheres on strings were not moved, and two of them pressed together by their swings sank
    /// 2 cm into each other (`regression_strung_spheres_pressed_zero_g`). Two spheres at the
    /// same point part along x. Returns how many bodies moved.
    ///
    /// The pairs come from those the step tested (a superset of those that can end it
    /// overlapping) and from the broad phase, asked for every pair within reach of a body that
    /// moves, so a move into a sphere not overlapped before is moved apart by the sweeps that
    /// follow (within the caps), and [`crate::StepStats::max_overlap`] sees every pair the
    /// moves bring together. A dynamic body within reach of a moving one may move too (it
    /// joins the sweeps, and moves if a pair of its comes to overlap), so a clump of touching
    /// spheres joins whole while any pair in it overlaps.
    pub(super) fn separate(&mut self, bodies: &mut [Body], ctx: &StepContext<'_>) -> u32 {
        let dt = ctx.dt;
        let n = self.segments.len();
        self.separate_bits.clear();
        self.separate_bits.resize(n.div_ceil(64), 0);
        self.separate_unkept.clear();
        self.separate_unkept.resize(n.div_ceil(64), 0);
        self.separating.clear();
        self.separate_pairs.clear();
        if self.separate_at.len() < n {
            self.separate_at.resize(n, DVec3::ZERO);
            self.separate_moves.resize(n, DVec3::ZERO);
        }
        for t in 0..self.tested.len() {
            let (i, j) = self.tested[t];
            let (i, j) = (i as usize, j as usize);
            // Under an acceleration only a pair with a sphere on a string starts a separation
            // (any other is allowed as deep as the step left it).
            if !self.nothing_accelerates && self.strung(i).is_none() && self.strung(j).is_none() {
                continue;
            }
            let (allowed, _) = self.separation_allowance(i, j, ctx);
            let (a, b) = (&self.segments[i], &self.segments[j]);
            let reach = a.radius() + b.radius();
            let distance = (self.final_position(j, dt) - self.final_position(i, dt)).length();
            if reach - distance > allowed {
                self.may_separate(i, dt);
                self.may_separate(j, dt);
            }
        }
        if self.separating.is_empty() {
            return 0;
        }
        // Every pair a move can bring into touch. A moving body's box is its sphere grown by
        // its cap; every other body's still holds its sphere at the step's end. A dynamic body
        // within reach of a moving one may move too (so the moves keep the centre of mass), and
        // its own neighbours are sought in turn.
        let mut found = std::mem::take(&mut self.candidates);
        let mut s = 0;
        while s < self.separating.len() {
            let k = self.separating[s] as usize;
            s += 1;
            found.clear();
            self.broad.collect_overlapping(k, &self.boxes, &mut found);
            for &m in &found {
                let m = m as usize;
                if m == k || !self.boxes[k].overlaps(&self.boxes[m]) {
                    continue;
                }
                let reach = self.segments[k].radius()
                    + self.segments[m].radius()
                    + self.reach_cap(k, dt)
                    + self.reach_cap(m, dt);
                if (self.final_position(m, dt) - self.separate_at[k]).length() >= reach {
                    continue;
                }
                self.may_separate(m, dt);
                self.separate_pairs.push((k.min(m) as u32, k.max(m) as u32));
            }
        }
        self.candidates = found;
        // Each pair once (two moving bodies find each other), in an order that does not
        // depend on the broad phase's.
        self.separate_pairs.sort_unstable();
        self.separate_pairs.dedup();
        let at = |solver: &Self, k: usize| {
            if bit(&solver.separate_bits, k) {
                solver.separate_at[k]
            } else {
                solver.final_position(k, dt)
            }
        };
        let weight = |solver: &Self, k: usize| {
            if bit(&solver.separate_bits, k) {
                solver.extra(k).inverse_mass
            } else {
                0.0
            }
        };
        for _ in 0..SEPARATION_SWEEPS {
            let mut moved = false;
            for p in 0..self.separate_pairs.len() {
                let (i, j) = self.separate_pairs[p];
                let (i, j) = (i as usize, j as usize);
                let (wi, wj) = (weight(self, i), weight(self, j));
                let (allowed, kept) = self.separation_allowance(i, j, ctx);
                let (a, b) = (&self.segments[i], &self.segments[j]);
                let reach = a.radius() + b.radius();
                let (pi, pj) = (at(self, i), at(self, j));
                let apart = pj - pi;
                let distance = apart.length();
                let overlap = reach - distance;
                if overlap <= allowed {
                    continue;
                }
                let normal = if distance > 0.0 {
                    apart / distance
                } else {
                    DVec3::X
                };
                // A sphere held by its string against the move gives no way (see
                // `Solver::held_by_string`): the other sphere takes all of it.
                let wi = if self.held_by_string(i, -normal) {
                    0.0
                } else {
                    wi
                };
                let wj = if self.held_by_string(j, normal) {
                    0.0
                } else {
                    wj
                };
                // The shares, from the weights over the larger (their sum can overflow).
                let larger = wi.max(wj);
                if larger == 0.0 {
                    continue;
                }
                // A pair without a string that this separation's moves took deeper than the
                // step left it (under an acceleration, any such pair it moves; with nothing
                // accelerating, one whose sphere a move that kept no centre of mass pushed in)
                // is carried: moved back to where the step left it (or its band), the sphere
                // pushed as far as the larger cap of the two, what one's cap leaves undone the
                // other taking. Its own overlap, if any, is moved apart as any pair's is.
                let unkept = |solver: &Self, k: usize| bit(&solver.separate_unkept, k);
                let strung = self.strung(i).is_some() || self.strung(j).is_some();
                let carried_to = if strung {
                    None
                } else if !self.nothing_accelerates {
                    Some(kept)
                } else if unkept(self, i) || unkept(self, j) {
                    let left = self.step_left(i, j, dt).max(allowed);
                    (overlap > left).then_some(left)
                } else {
                    None
                };
                let carried = carried_to.is_some();
                let overlap = overlap - carried_to.unwrap_or(kept);
                let (ri, rj) = (wi / larger, wj / larger);
                // The shares first: an inverse mass times an overlap can overflow.
                let (move_i, move_j) = (
                    -normal * (ri / (ri + rj) * overlap),
                    normal * (rj / (ri + rj) * overlap),
                );
                // How much of its move each body may take within its cap in the step (a move
                // back towards where it was is free); 1 for a body that does not move.
                let pair_cap = self.separation_cap(i).max(self.separation_cap(j));
                let within = |solver: &Self, k: usize, m: DVec3| {
                    if bit(&solver.separate_bits, k) {
                        let cap = if carried {
                            pair_cap
                        } else if strung {
                            solver.strung_pair_cap(k, dt)
                        } else {
                            solver.separation_cap(k)
                        };
                        within_cap(solver.separate_moves[k], m, cap)
                    } else {
                        1.0
                    }
                };
                let (ci, cj) = (within(self, i, move_i), within(self, j, move_j));
                // A NaN means no move.
                if ci.is_nan() || cj.is_nan() {
                    continue;
                }
                let make_up = carried || (strung && ci.min(cj) < 1.0);
                let (move_i, move_j) = if make_up {
                    // A pair with a sphere on a string, whose string holds it anyway (the
                    // pair's centre of mass is not kept), or one carried: what one body's cap
                    // leaves undone, the other takes, within its own. A sphere of 1.5 cm
                    // pressed out along its string by one of 10 kg, 2 cm into it, moved its
                    // tenth of a radius (1.5 mm) and the other its share by the masses,
                    // nothing. With no gravity a free sphere of 128 kg, moved out of a
                    // kinematic one (which gives no way) into a free one of 0.8 mg, which its
                    // own cap let move 1 mm and the pair's centre of mass kept the large one
                    // from taking the rest, was left 11.5 of the small one's radii deep
                    // (`sphere-fuzz --strings fast`, seed 48 581).
                    if ci <= cj {
                        let rest = move_j - move_i * (1.0 - ci);
                        (move_i * ci, rest * within(self, j, rest))
                    } else {
                        let rest = move_i - move_j * (1.0 - cj);
                        (rest * within(self, i, rest), move_j * cj)
                    }
                } else {
                    // One scale for both, so the pair's centre of mass stays.
                    let scale = ci.min(cj);
                    (move_i * scale, move_j * scale)
                };
                if !(move_i.is_finite() && move_j.is_finite())
                    || (move_i == DVec3::ZERO && move_j == DVec3::ZERO)
                {
                    continue;
                }
                let com_lost = make_up || wi == 0.0 || wj == 0.0;
                for (k, m) in [(i, move_i), (j, move_j)] {
                    if !bit(&self.separate_bits, k) {
                        continue;
                    }
                    let mut to = self.separate_at[k] + m;
                    if let Some(&Strung { tether, .. }) = self.strung(k) {
                        // Kept within its string's length. On it, the move loses its part
                        // outward along the string (none is left of a move straight out); a
                        // move past the length is put back on the string's sphere, at the
                        // nearest point (no farther from where it was than the move asked).
                        let r = self.separate_at[k] - tether.anchor;
                        let distance = r.length();
                        if at_length(distance, tether) && distance > 0.0 {
                            let outward = r / distance;
                            to = self.separate_at[k] + m - outward * m.dot(outward).max(0.0);
                        }
                        let r = to - tether.anchor;
                        let distance = r.length();
                        if distance > tether.length {
                            to = tether.anchor + r * (tether.length / distance);
                        }
                    }
                    let step = to - self.separate_at[k];
                    if step != DVec3::ZERO {
                        self.separate_at[k] = to;
                        self.separate_moves[k] += step;
                        moved = true;
                        if com_lost || self.strung(k).is_some() {
                            self.separate_unkept[k / 64] |= 1 << (k % 64);
                        }
                    }
                }
            }
            if !moved {
                break;
            }
        }
        let mut count = 0;
        for s in 0..self.separating.len() {
            let k = self.separating[s] as usize;
            let shift = self.separate_moves[k];
            if shift == DVec3::ZERO {
                continue;
            }
            // The body is written where its segment now ends, so the step's deepest overlap
            // is read from the same numbers. A move lost to rounding next to the position (a
            // cap far below its size) is not counted.
            self.segments[k].position += shift;
            let body = &mut bodies[self.order[k] as usize];
            let before = body.desc.position;
            body.desc.position = self.final_position(k, dt);
            count += u32::from(body.desc.position != before);
        }
        // The step's deepest overlap is sought among the tested pairs: these join them.
        self.tested.extend_from_slice(&self.separate_pairs);
        count
    }
}

impl Solver {
    /// How deep pair `(i, j)` may end the step before the separation moves it, and how deep
    /// it leaves it: with nothing accelerating, its contact band, and moved to touching;
    /// under an acceleration, [`STRUNG_OVERLAP`] of the smaller radius (or the band if
    /// larger) for a pair with a sphere on a string, and moved back to that depth; for any
    /// other pair, whose own overlaps the resting solve undoes, as deep as the step left it
    /// (or the band): it is moved only back from where another pair's move took it. Such
    /// pairs were never moved: a free sphere of 634 kg moved back out of a strung one of 0.1 g
    /// (which its string held) was moved 35% of its radius into a free sphere of 0.7 g
    /// beside it, and left there (`sphere-fuzz --strings fast`, seed 21 002).
    fn separation_allowance(&self, i: usize, j: usize, ctx: &StepContext<'_>) -> (f64, f64) {
        let (a, b) = (&self.segments[i], &self.segments[j]);
        let band = contact_band(a, b, ctx.settings);
        if self.nothing_accelerates {
            (band, 0.0)
        } else if self.strung(i).is_some() || self.strung(j).is_some() {
            let allowed = band.max(STRUNG_OVERLAP * a.radius().min(b.radius()));
            (allowed, allowed)
        } else {
            let allowed = band.max(self.step_left(i, j, ctx.dt));
            (allowed, allowed)
        }
    }

    /// How deep pair `(i, j)` ended the step, before the separation (negative if apart).
    fn step_left(&self, i: usize, j: usize, dt: f64) -> f64 {
        let reach = self.segments[i].radius() + self.segments[j].radius();
        reach - (self.final_position(j, dt) - self.final_position(i, dt)).length()
    }

    /// Whether segment `k` (moving in this separation) is held by its string against a move
    /// along `direction`: at its string's length, and the move within 30° of straight out
    /// along the string. Such a sphere could only slide round its swing, which parts the pair
    /// by the sine of the angle and, curving back towards the anchor, closes it again. By the
    /// masses alone it took nearly all of each move and lost it to its string: a sphere of
    /// 65 mg on a string of 24 cm pressed by one of 1 kg, with no gravity, stayed 1.1 of its
    /// radii into it for a step, and one of 11 g on a string of 18 cm pressed by one of 19 kg
    /// 20% for three steps (`sphere-fuzz --strings fast`, seeds 1213 and 9000).
    fn held_by_string(&self, k: usize, direction: DVec3) -> bool {
        let Some(&Strung { tether, .. }) = self.strung(k) else {
            return false;
        };
        let r = self.separate_at[k] - tether.anchor;
        let distance = r.length();
        distance > 0.0 && at_length(distance, tether) && direction.dot(r / distance) > HELD_WITHIN
    }

    /// How far segment `k` may be moved apart from others in a step: [`MAX_CORRECTION`] of
    /// its radius, or 0 for a fixed sphere.
    fn separation_cap(&self, k: usize) -> f64 {
        if self.segments[k].is_fixed() {
            0.0
        } else {
            MAX_CORRECTION * self.segments[k].radius()
        }
    }

    /// How far segment `k` may be moved apart from the other sphere of a pair with a sphere on
    /// a string in a step: its cap, or as far as it drifted in the step if farther (such a move
    /// is no larger than what the step itself did to it). A sphere that swallows a small one's
    /// anchor at tens of m/s and presses it out along its string ended steps deeper in it than
    /// its cap could undo: a sphere of 11 kg at 36 m/s, 1.3 of the small one's radii, and one
    /// of 294 kg at 41 m/s, 1.25 (`sphere-fuzz --strings fast`, seeds 26 555 and 33 838).
    fn strung_pair_cap(&self, k: usize, dt: f64) -> f64 {
        let cap = self.separation_cap(k);
        if cap == 0.0 {
            0.0
        } else {
            cap.max(self.segments[k].velocity.length() * dt)
        }
    }

    /// How far segment `k` may be moved in this step's separation by any pair: its cap, and
    /// in a world with strings as far as [`Solver::strung_pair_cap`] lets it.
    fn reach_cap(&self, k: usize, dt: f64) -> f64 {
        if self.strings {
            self.strung_pair_cap(k, dt)
        } else {
            self.separation_cap(k)
        }
    }

    /// Lets segment `k` move in this step's separation, unless it may not (fixed) or already
    /// does: its box is grown by its reach (see [`Solver::reach_cap`]) in the broad phase, and
    /// its neighbours are to be sought.
    fn may_separate(&mut self, k: usize, dt: f64) {
        if bit(&self.separate_bits, k) || self.separation_cap(k) == 0.0 {
            return;
        }
        self.separate_bits[k / 64] |= 1 << (k % 64);
        self.separating.push(k as u32);
        let at = self.final_position(k, dt);
        self.separate_at[k] = at;
        self.separate_moves[k] = DVec3::ZERO;
        let grow = DVec3::splat(self.segments[k].radius() + self.reach_cap(k, dt));
        self.boxes[k] = Aabb {
            lo: at - grow,
            hi: at + grow,
        };
        self.broad.update(k, &self.boxes[k]);
    }
}

/// The largest `s` in `[0, 1]` for which `so_far + s * step` is no longer than `cap` (`so_far`
/// being no longer than it): 0 if `step` points out of the ball where `so_far` is on its edge.
/// Worked out along `step`'s direction in units of the cap, so that nothing overflows at any
/// radius, nor for a step far longer than the cap.
fn within_cap(so_far: DVec3, step: DVec3, cap: f64) -> f64 {
    let length = step.length();
    if length == 0.0 {
        return 1.0;
    }
    let (a, u) = (so_far / cap, step / length);
    // How far along u, in caps, before |a + t u| = 1: the positive root of
    // t² + 2 p t - q, in the form without cancellation.
    let (p, q) = (a.dot(u), (1.0 - a.length_squared()).max(0.0));
    let root = (p * p + q).sqrt();
    let t = if p <= 0.0 { root - p } else { q / (root + p) };
    if t <= 0.0 {
        // On the cap's edge, pointing out (and no 0 times an overflowed ratio).
        return 0.0;
    }
    (t * (cap / length)).clamp(0.0, 1.0)
}
