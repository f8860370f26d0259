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
/// `restitution` is 1; a pair that is not approaching is left unchanged. `restitution` is taken
/// within `[0, 1]` (above 1 as 1, below 0 or NaN as 0), so energy is never gained.
pub fn resolve(
    inverse_mass_a: f64,
    inverse_mass_b: f64,
    velocity_a: DVec3,
    velocity_b: DVec3,
    normal: DVec3,
    restitution: f64,
) -> Resolution {
    resolve_at(
        inverse_mass_a,
        inverse_mass_b,
        velocity_a,
        velocity_b,
        normal,
        restitution,
        0.0,
    )
}

/// [`resolve`] for a pair whose speed along `normal` at the instant of impact differs from its
/// velocities' by `lag` (bodies under different accelerations, drifting at their velocities at
/// the middle of the step: a ball striking a fixed floor under gravity). The impulse answers
/// that instant's speed (restitution times it, reversed), and is at least what stops the
/// velocities closing. Applied to the drifts, it leaves the pair's velocities at the step's
/// end where the same bounce at the instant of impact would: an elastic ball dropped on the
/// floor bounces back to its height, where one answering the drift's speed gained up to
/// `g·dt` at each bounce and, its bounces in step with the steps, kept gaining (regression
/// test `regression_bouncing_ball_energy.rs`). With `lag` 0, [`resolve`] bit for bit.
pub(crate) fn resolve_at(
    inverse_mass_a: f64,
    inverse_mass_b: f64,
    velocity_a: DVec3,
    velocity_b: DVec3,
    normal: DVec3,
    restitution: f64,
    lag: f64,
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
    let restitution = clamped(restitution);
    // With no lag the first is the larger (restitution is not negative), exactly.
    let impulse = (-(1.0 + restitution) * (normal_speed + lag)).max(-normal_speed) / inverse_sum;
    Resolution {
        velocity_a: velocity_a - normal * (impulse * inverse_mass_a),
        velocity_b: velocity_b + normal * (impulse * inverse_mass_b),
        impulse,
    }
}

/// A restitution as the responses take it: within `[0, 1]`, NaN as 0.
fn clamped(restitution: f64) -> f64 {
    if restitution >= 0.0 {
        restitution.min(1.0)
    } else {
        0.0
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
    /// The contact's restitution, taken within `[0, 1]` (NaN as 0), as [`resolve`] takes it.
    pub restitution: f64,
    /// The separating speed the compression impulse aims for, `>= 0` (a negative or non-finite
    /// one counts as 0): 0 for a plain contact
    /// (just stop approaching); a resting pair that overlaps too deeply is given enough to
    /// undo the excess over a step. The restitution impulse, `restitution` times the whole
    /// compression impulse, comes on top of it (so scales the bias's share too; the engine
    /// gives a bias only to resting contacts, whose restitution is 0).
    pub bias: f64,
    /// A string rather than a contact: `b` is its anchor (inverse mass 0, at rest) and `normal`
    /// points from the anchor side outward, so "not approaching" means "not stretching". It
    /// gets no restitution and is enforced again after the restitution impulses.
    pub string: bool,
}

impl GroupContact {
    /// A contact between bodies `a` and `b` along `normal` (unit, from `a` to `b`) with
    /// `restitution`, no bias.
    pub fn new(a: usize, b: usize, normal: DVec3, restitution: f64) -> Self {
        GroupContact {
            a,
            b,
            normal,
            restitution,
            bias: 0.0,
            string: false,
        }
    }

    /// The same contact, asked to separate at `bias` (see [`GroupContact::bias`]; one that is
    /// negative or not finite counts as 0).
    pub fn with_bias(self, bias: f64) -> Self {
        GroupContact { bias, ..self }
    }

    /// The bias [`resolve_simultaneous`] aims for: `bias`, or 0 if it is negative or not finite
    /// (a negative one would let the pair approach, an infinite one push it apart without end).
    fn aimed_bias(&self) -> f64 {
        if self.bias > 0.0 && self.bias.is_finite() {
            self.bias
        } else {
            0.0
        }
    }
}

/// The most sweeps [`resolve_simultaneous`] makes over its contacts.
pub const MAX_GROUP_SWEEPS: u32 = 256;

/// Resolves several contacts that happen at the same instant, all at once: a ball striking two
/// touching balls symmetrically sends them off symmetrically (where one contact after the other
/// would not).
///
/// First the compression impulses `λ ≥ 0` are found that just stop every contact approaching
/// (or, with a [`GroupContact::bias`], make it separate at that speed): exactly for up to
/// [`MAX_EXACT_CONTACTS`] contacts (the linear complementarity problem, solved by pivoting on
/// which contacts push, and for up to [`MAX_SEARCHED_CONTACTS`] by trying every set of them
/// if that does not settle), otherwise (or if rounding lets no set fit) by projected
/// Gauss–Seidel on the contacts until it converges to the last bit, at most
/// [`MAX_GROUP_SWEEPS`] sweeps. Then each contact gets
/// `restitution · λ` more. Momentum is conserved, and without biases kinetic energy is never
/// gained: with a common restitution `e` it changes by `(e² − 1)/2 · λᵀAλ`, so it is conserved
/// exactly when `e = 1` (a bias pushes a pair apart on purpose, and may add energy). With
/// restitutions that differ, the restitution impulses could gain energy (a ball striking a line
/// of two at one instant, restitution 1 where it strikes and 0 between them, would leave them
/// 11/9 of its energy): where they would, they are all scaled by the one factor that leaves
/// the group's kinetic energy what it was before (or after the compression, if that is more),
/// measured in the frame of its fixed bodies (not judged when fixed bodies in it move apart).
/// A single contact gives the same answer as [`resolve`].
///
/// `velocities` are updated in place; `impulses` receives each contact's total impulse.
///
/// # Panics
/// If a contact names a body (`a` or `b`) beyond `inverse_masses` or `velocities`: the
/// contacts index those two slices.
pub fn resolve_simultaneous(
    inverse_masses: &[f64],
    velocities: &mut [DVec3],
    contacts: &[GroupContact],
    impulses: &mut Vec<f64>,
) {
    let apply = |velocities: &mut [DVec3], c: &GroupContact, impulse: f64| {
        velocities[c.a] -= c.normal * (impulse * inverse_masses[c.a]);
        velocities[c.b] += c.normal * (impulse * inverse_masses[c.b]);
    };
    let scale = contacts
        .iter()
        .map(|c| {
            let speed = (velocities[c.b] - velocities[c.a]).dot(c.normal).abs();
            speed.max(c.aimed_bias())
        })
        .fold(0.0f64, f64::max);
    let n = contacts.len();
    // Contacts of several restitutions: their restitution impulses may gain energy (below),
    // measured in the frame of the group's fixed bodies (a moving fixed sphere, kinematic,
    // gives energy on purpose), unless they move apart (then there is no frame to judge in).
    let mut restitutions = contacts
        .iter()
        .filter(|c| !c.string)
        .map(|c| clamped(c.restitution));
    let first = restitutions.next();
    let mut mixed = restitutions.any(|e| Some(e) != first);
    // The velocity of the group's fixed bodies, and whether they all move at it (energies are
    // judged only then), found when needed: for mixed restitutions, and after sweeps that
    // stop short of the answer (below).
    let mut fixed = None;
    if mixed {
        let found = fixed_frame(inverse_masses, velocities, contacts);
        mixed = found.1;
        fixed = Some(found);
    }
    // With no fixed body in the group, mixed restitutions' energies are judged in the world's
    // frame (its allowance for rounding, 1e-12 of the whole energy, may hide a gain that
    // small); those of sweeps that stop short, below, in the centre of mass's frame, which
    // the impulses keep.
    let mut frame = fixed
        .and_then(|(velocity, _)| velocity)
        .unwrap_or(DVec3::ZERO);
    // Whether sweeps that stop short have their energies judged (see below).
    let mut short_judged = false;
    let mut units = if mixed {
        energy_units(inverse_masses, velocities, frame)
    } else {
        (1.0, 1.0)
    };
    let mut energy_before = if mixed {
        kinetic_energy(inverse_masses, velocities, frame, units)
    } else {
        0.0
    };
    // Whether the compression impulses found are the answer (the iterative ones may stop
    // short of it, see below).
    let mut converged = true;
    // `impulses` is the exact solve's scratch too: its answer is left in the first `n`.
    if compress_exactly(
        inverse_masses,
        velocities,
        contacts,
        scale,
        false,
        None,
        impulses,
    ) {
        impulses.truncate(n);
        for (c, impulse) in contacts.iter().zip(impulses.iter_mut()) {
            if *impulse > 0.0 {
                apply(velocities, c, *impulse);
            } else {
                *impulse = 0.0;
            }
        }
    } else {
        // The impulses, then four scratch values a contact and six a body.
        impulses.clear();
        impulses.resize(5 * n + 6 * velocities.len(), 0.0);
        let (own, rest) = impulses.split_at_mut(n);
        let (per_contact, per_body) = rest.split_at_mut(4 * n);
        let (saved, work) = per_body.split_at_mut(3 * velocities.len());
        // What rounding leaves in a contact's speed: a few hundred units in the last place of
        // the group's fastest velocity (a group moving at 10 m/s, struck at 1 m/s, could not
        // meet a bound of 1e-14 of the strike alone, and its sweeps ran to their cap).
        let rounding = 1e-12
            * velocities
                .iter()
                .map(|v| v.abs().max_element())
                .fold(0.0f64, f64::max);
        for (v, keep) in velocities.iter().zip(saved.chunks_exact_mut(3)) {
            keep.copy_from_slice(&v.to_array());
        }
        converged = compress_by_gradients(
            inverse_masses,
            velocities,
            contacts,
            own,
            per_contact,
            work,
            (scale, rounding),
        );
        if !converged {
            // Back to the start, and swept.
            for (v, keep) in velocities.iter_mut().zip(saved.chunks_exact(3)) {
                *v = DVec3::from_slice(keep);
            }
            let (fixed_velocity, one_frame) =
                *fixed.get_or_insert_with(|| fixed_frame(inverse_masses, velocities, contacts));
            short_judged = one_frame;
            if one_frame && !mixed {
                frame = fixed_velocity
                    .unwrap_or_else(|| centre_of_mass_velocity(inverse_masses, velocities));
                units = energy_units(inverse_masses, velocities, frame);
                energy_before = kinetic_energy(inverse_masses, velocities, frame, units);
            }
            own.fill(0.0);
            let (before, rest) = per_contact.split_at_mut(n);
            let (direction, rest) = rest.split_at_mut(n);
            let (kept, _) = rest.split_at_mut(n);
            converged = compress_iteratively(
                inverse_masses,
                velocities,
                contacts,
                own,
                (before, direction, kept),
                (scale, rounding),
            );
        }
        impulses.truncate(n);
    }
    // The restitution impulses, `restitution · λ` each. With one restitution for all they
    // never gain energy (see above); with several they may (a contact of restitution 1 beside
    // one of 0 takes back more than its share), and so may impulses short of the answer
    // (sweeps stopped at their cap), so then they are scaled down together to where the
    // group's kinetic energy is no more than before (or than after the compression, when
    // biases pushed on purpose). The energy is quadratic in the scale: its values at 0, 1/2
    // and 1 give it.
    let judged = mixed || (!converged && short_judged);
    let energy = |velocities: &[DVec3]| kinetic_energy(inverse_masses, velocities, frame, units);
    let (compressed, allowed) = if judged {
        let compressed = energy(velocities);
        (compressed, compressed.max(energy_before))
    } else {
        (0.0, 0.0)
    };
    let restitute = |velocities: &mut [DVec3], scale: f64| {
        for (c, &impulse) in contacts.iter().zip(impulses.iter()) {
            if !c.string {
                apply(velocities, c, scale * clamped(c.restitution) * impulse);
            }
        }
    };
    restitute(velocities, 1.0);
    let mut kept = 1.0;
    if judged {
        let whole = energy(velocities);
        // (An energy that overflows is left to the world's check of every drift.)
        if whole.is_finite() && whole > allowed * (1.0 + 1e-12) {
            restitute(velocities, -0.5);
            let half = energy(velocities);
            // energy(s) = compressed + β·s + α·s², from its values at 0, 1/2 and 1.
            let alpha = 2.0 * (whole + compressed - 2.0 * half);
            let beta = whole - compressed - alpha;
            let gamma = compressed - allowed;
            // The largest s in [0, 1] with α·s² + β·s + γ <= 0 (γ <= 0: at s = 0 it holds),
            // in the form without cancellation for β >= 0 (right as α goes to 0, too).
            let root = (beta * beta - 4.0 * alpha * gamma).max(0.0).sqrt();
            let s = if beta >= 0.0 && beta + root > 0.0 {
                -2.0 * gamma / (beta + root)
            } else if beta < 0.0 && alpha > 0.0 {
                (-beta + root) / (2.0 * alpha)
            } else {
                1.0
            };
            kept = s.clamp(0.0, 1.0);
            restitute(velocities, kept - 0.5);
        }
    }
    for (c, impulse) in contacts.iter().zip(impulses.iter_mut()) {
        if !c.string {
            *impulse += kept * clamped(c.restitution) * *impulse;
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

/// The velocity of a group's fixed bodies (`None` if it has none), and whether they all move
/// at it.
fn fixed_frame(
    inverse_masses: &[f64],
    velocities: &[DVec3],
    contacts: &[GroupContact],
) -> (Option<DVec3>, bool) {
    let mut frame = None;
    for c in contacts {
        for k in [c.a, c.b].into_iter().filter(|&k| inverse_masses[k] == 0.0) {
            match frame {
                None => frame = Some(velocities[k]),
                Some(v) if v != velocities[k] => return (frame, false),
                Some(_) => {}
            }
        }
    }
    (frame, true)
}

/// The velocity of the centre of mass of a group's dynamic bodies (those of inverse mass
/// above 0), weighed relative to the heaviest so that huge masses do not overflow.
fn centre_of_mass_velocity(inverse_masses: &[f64], velocities: &[DVec3]) -> DVec3 {
    // The heaviest body's inverse mass: each body weighs its mass over the heaviest's.
    let heaviest = inverse_masses
        .iter()
        .copied()
        .filter(|&w| w > 0.0)
        .fold(f64::INFINITY, f64::min);
    let (mut sum, mut weight) = (DVec3::ZERO, 0.0);
    for (v, &w) in velocities.iter().zip(inverse_masses) {
        if w > 0.0 {
            let share = heaviest / w;
            sum += *v * share;
            weight += share;
        }
    }
    if weight > 0.0 && sum.is_finite() {
        sum / weight
    } else {
        DVec3::ZERO
    }
}

/// The units of speed and mass a group's kinetic energies are measured in (see
/// [`kinetic_energy`]): 1 and 1 (joules), unless that could overflow an f64 (a group's energy
/// near 1e200 J or more, within the documented limits of mass and speed: 1e200 kg at 1e60
/// m/s); then its largest speed component (in the frame) and its largest mass, so that the
/// energies compared stay finite. (Before the fifty-seventh session an energy that overflowed
/// skipped the check, and a strike on a line of two with mixed restitutions kept 11/9 of its
/// energy.)
fn energy_units(inverse_masses: &[f64], velocities: &[DVec3], frame: DVec3) -> (f64, f64) {
    let (mut speed, mut mass) = (0.0f64, 0.0f64);
    for (v, im) in velocities.iter().zip(inverse_masses) {
        if *im > 0.0 {
            speed = speed.max((*v - frame).abs().max_element());
            mass = mass.max(1.0 / im);
        }
    }
    // Room for the speeds the impulses give (a light sphere struck by a heavy one leaves at
    // up to twice its speed, along a chain more).
    if speed * speed * mass * (velocities.len() as f64) < 1e200 || speed == 0.0 {
        (1.0, 1.0)
    } else {
        (speed, mass)
    }
}

/// The kinetic energy of a group's dynamic bodies (those of inverse mass above 0) in the
/// frame moving at `frame`, in `units` of speed and mass (see [`energy_units`]).
fn kinetic_energy(
    inverse_masses: &[f64],
    velocities: &[DVec3],
    frame: DVec3,
    (speed, mass): (f64, f64),
) -> f64 {
    let bodies = velocities
        .iter()
        .zip(inverse_masses)
        .filter(|(_, im)| **im > 0.0);
    if speed == 1.0 && mass == 1.0 {
        bodies
            .map(|(v, im)| 0.5 * (*v - frame).length_squared() / im)
            .sum()
    } else {
        bodies
            .map(|(v, im)| 0.5 * ((*v - frame) / speed).length_squared() / (im * mass))
            .sum()
    }
}

/// The most contacts [`resolve_simultaneous`] solves exactly, by block principal pivoting;
/// larger groups are swept. Sweeps converge slowly, or not within
/// [`MAX_GROUP_SWEEPS`], where contacts are nearly dependent (five spheres touching pairwise):
/// a ball pit's landing solves thousands of groups of 9 to 64 contacts, which took 150 sweeps
/// each on average.
pub const MAX_EXACT_CONTACTS: usize = 64;

/// The most contacts whose every set of active contacts [`resolve_simultaneous`] tries when
/// pivoting does not settle (at most 2ⁿ − 1 small linear solves, a few microseconds at 8):
/// up to this many contacts the answer is exact whenever rounding lets one pass.
pub const MAX_SEARCHED_CONTACTS: usize = 8;

/// The compression impulses of a group of at most [`MAX_EXACT_CONTACTS`] contacts, exactly:
/// the `λ ≥ 0` that leave every contact's normal speed `w = Aλ + b` at or above its bias,
/// with `λᵢ = 0` wherever contact `i` ends up separating faster (the linear complementarity
/// problem that the sweeps converge to). A guess at the active contacts is corrected a few
/// times first; if that does not settle, every set is tried, smallest first (up to
/// [`MAX_SEARCHED_CONTACTS`]). Contacts that duplicate one another have several answers (the
/// velocities they leave are the same): any is kept. Leaves `λ` in `work`'s first `n` and
/// returns true; false for larger groups, or when no set passes (rounding, or pivoting that
/// does not settle in a group too large to search). With a `guess` (a bit per contact), the
/// pivoting starts from it, and no set is searched. `work` is scratch, kept by the caller.
#[allow(clippy::too_many_arguments)]
fn compress_exactly(
    inverse_masses: &[f64],
    velocities: &[DVec3],
    contacts: &[GroupContact],
    scale: f64,
    signed: bool,
    guess: Option<u64>,
    work: &mut Vec<f64>,
) -> bool {
    let n = contacts.len();
    if n > MAX_EXACT_CONTACTS {
        return false;
    }
    work.clear();
    work.resize(2 * n + n * n + n * (n + 1), 0.0);
    let (lambda, rest) = work.split_at_mut(n);
    let (b, rest) = rest.split_at_mut(n);
    let (a, matrix) = rest.split_at_mut(n * n);
    // b: each contact's normal speed now, less its bias (negative: it must be pushed).
    // A (row by row): how an impulse on contact j changes contact i's normal speed.
    let sign = |c: &GroupContact, k: usize| -> f64 {
        if k == c.b {
            1.0
        } else if k == c.a {
            -1.0
        } else {
            0.0
        }
    };
    for (i, ci) in contacts.iter().enumerate() {
        let bias = if signed && ci.bias.is_finite() {
            ci.bias
        } else {
            ci.aimed_bias()
        };
        b[i] = (velocities[ci.b] - velocities[ci.a]).dot(ci.normal) - bias;
        for (j, cj) in contacts.iter().enumerate() {
            let coupling: f64 = [cj.a, cj.b]
                .into_iter()
                .map(|k| sign(ci, k) * sign(cj, k) * inverse_masses[k])
                .sum();
            a[i * n + j] = coupling * ci.normal.dot(cj.normal);
        }
    }
    let (a, b) = (&*a, &*b);
    if b.iter().all(|&w| w >= 0.0) {
        lambda.fill(0.0);
        return true;
    }
    let tolerance = 1e-12 * scale;
    // The contacts whose normal speed `lambda` leaves below its bias (beyond rounding of the
    // sum that makes it, relative to its largest term: a light sphere between heavy ones sums
    // large terms to a small speed). Only the contacts of `set` push (`solve_active` leaves
    // the rest at 0): the sums run over those, in order, and both at once. (The terms left
    // out are zeros, the couplings being finite, which leave a sum as it was but for the sign
    // of a zero sum: no comparison below tells the two zeros apart. A coupling is infinite
    // only for an inverse mass near the largest f64, whose answers are no answers anyway.)
    let short = |lambda: &[f64], set: u64| -> u64 {
        (0..n)
            .filter(|&i| {
                let row = &a[i * n..(i + 1) * n];
                let (mut sum, mut size) = (-0.0f64, -0.0f64);
                let mut bits = set;
                while bits != 0 {
                    let j = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let term = row[j] * lambda[j];
                    sum += term;
                    size += term.abs();
                }
                let w = b[i] + sum;
                let size = b[i].abs() + size;
                w < -(tolerance + 1e-12 * size)
            })
            .fold(0, |bits, i| bits | 1 << i)
    };
    let pulling = |lambda: &[f64]| -> u64 {
        (0..n)
            .filter(|&i| lambda[i] < 0.0)
            .fold(0, |bits, i| bits | 1 << i)
    };
    // First a guess and its corrections (block principal pivoting): every contact active that
    // is not separating beyond rounding; then, while the answer pulls on active contacts or
    // leaves inactive ones approaching, those pulled dropped and those approaching added. In a
    // pile, where a resting impact joins the contacts it presses on (at rest, each pressed
    // already at this instant), nearly all of them push: guessing only the approaching ones
    // took 2.8 solves a group in a landing pit of 1000 and this guess 1.07, where the search
    // below tries dozens. It may cycle, so it gets a few tries. Contacts at rest that
    // duplicate one another (a sphere pressed between two fixed ones on a line) make that
    // guess singular: then the approaching ones are guessed instead.
    let mut set = guess.unwrap_or_else(|| {
        (0..n)
            .filter(|&i| b[i] < tolerance)
            .fold(0u64, |bits, i| bits | 1 << i)
    });
    let approaching = (0..n)
        .filter(|&i| b[i] < 0.0)
        .fold(0u64, |bits, i| bits | 1 << i);
    let mut first = true;
    for _ in 0..=n + 1 {
        if !solve_active(a, b, set, matrix, lambda) {
            if first && set != approaching {
                first = false;
                set = approaching;
                continue;
            }
            break;
        }
        first = false;
        let (pulling, short) = (pulling(lambda), short(lambda, set));
        if pulling == 0 && short == 0 {
            return true;
        }
        let next = (set & !pulling) | short;
        if next == set || next == 0 {
            break;
        }
        set = next;
    }
    if n > MAX_SEARCHED_CONTACTS || guess.is_some() {
        return false;
    }
    // Every active set, by size, then by bit pattern: deterministic, smallest first.
    let sets =
        (1..=n as u32).flat_map(|size| (1..1u64 << n).filter(move |s| s.count_ones() == size));
    for set in sets {
        if solve_active(a, b, set, matrix, lambda)
            && pulling(lambda) == 0
            && short(lambda, set) == 0
        {
            return true;
        }
    }
    false
}

/// The compression impulses of a group of at most [`MAX_EXACT_CONTACTS`] contacts, exactly, as
/// [`resolve_simultaneous`] finds them but with each contact's [`GroupContact::bias`] taken as
/// it is, negative ones too (a contact allowed to close that fast: the resting solve's guards
/// and the fallback's pairs still apart), and no restitution: `impulses` gets each contact's
/// impulse, and `velocities` are left as they were. False (and nothing found) for a larger
/// group, or when no answer passes (see `compress_exactly`).
///
/// With a `guess` (a bit per contact), the pivoting starts from those contacts pushing, and
/// false comes back if it does not settle (no search of every set).
pub(crate) fn compress_with_signed_biases(
    inverse_masses: &[f64],
    velocities: &[DVec3],
    contacts: &[GroupContact],
    guess: Option<u64>,
    impulses: &mut Vec<f64>,
) -> bool {
    let scale = contacts
        .iter()
        .map(|c| {
            let speed = (velocities[c.b] - velocities[c.a]).dot(c.normal).abs();
            let bias = if c.bias.is_finite() {
                c.bias.abs()
            } else {
                0.0
            };
            speed.max(bias)
        })
        .fold(0.0f64, f64::max);
    if compress_exactly(
        inverse_masses,
        velocities,
        contacts,
        scale,
        true,
        guess,
        impulses,
    ) {
        impulses.truncate(contacts.len());
        true
    } else {
        false
    }
}

/// Solves `A_SS λ_S = -b_S` for the contacts in `set` (the others get 0) into `lambda`, by
/// Gaussian elimination with partial pivoting in `matrix` (scratch, at least `n·(n + 1)`);
/// false when that block is singular (contacts that duplicate one another). `a` is `n × n`,
/// row by row, for the `n` contacts of `b`.
fn solve_active(a: &[f64], b: &[f64], set: u64, matrix: &mut [f64], lambda: &mut [f64]) -> bool {
    let n = b.len();
    let mut index = [0usize; MAX_EXACT_CONTACTS];
    let mut m = 0;
    for i in (0..n).filter(|&i| set & (1 << i) != 0) {
        index[m] = i;
        m += 1;
    }
    // Row r of the augmented block: `matrix[r·w .. r·w + w]`.
    let w = m + 1;
    let matrix = &mut matrix[..m * w];
    let mut largest = 0.0f64;
    for r in 0..m {
        for c in 0..m {
            let value = a[index[r] * n + index[c]];
            matrix[r * w + c] = value;
            largest = largest.max(value.abs());
        }
        matrix[r * w + m] = -b[index[r]];
    }
    for col in 0..m {
        let pivot = (col..m)
            .max_by(|&x, &y| {
                matrix[x * w + col]
                    .abs()
                    .total_cmp(&matrix[y * w + col].abs())
            })
            .unwrap_or(col);
        let size = matrix[pivot * w + col].abs();
        if size.is_nan() || size <= 1e-12 * largest {
            return false;
        }
        if pivot != col {
            for c in 0..w {
                matrix.swap(col * w + c, pivot * w + c);
            }
        }
        let (upper, lower) = matrix.split_at_mut((col + 1) * w);
        let pivot_row = &upper[col * w..];
        for row in lower.chunks_exact_mut(w) {
            let factor = row[col] / pivot_row[col];
            for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                *x -= factor * p;
            }
        }
    }
    lambda.fill(0.0);
    for r in (0..m).rev() {
        let mut value = matrix[r * w + m];
        for c in r + 1..m {
            value -= matrix[r * w + c] * lambda[index[c]];
        }
        lambda[index[r]] = value / matrix[r * w + r];
    }
    lambda.iter().all(|l| l.is_finite())
}

/// Nonsmooth nonlinear conjugate gradients (Silcowitz, Niebe and Erleben, 2010), for a
/// projected Gauss–Seidel solve: each sweep's change of the impulses is a descent direction,
/// and adding the last direction again, in proportion to how little the change shrank, carries
/// a wedged bed's load through in far fewer sweeps. After a sweep that moved the impulses by
/// `moved` (squared), against `last` the sweep before: the factor to add the last direction
/// with, or `None` to restart (the change grew, or there is no last direction).
pub(crate) fn conjugate_factor(moved: f64, last: f64) -> Option<f64> {
    let beta = if last > 0.0 { moved / last } else { 0.0 };
    (beta > 0.0 && beta < 1.0).then_some(beta)
}

/// One contact's part of [`conjugate_factor`]'s acceleration: its `impulse` with `beta` times
/// its `direction` added (never below 0), and the direction updated with the sweep's `step`.
pub(crate) fn conjugate_step(
    impulse: f64,
    step: f64,
    direction: &mut f64,
    beta: Option<f64>,
) -> f64 {
    match beta {
        Some(beta) => {
            let next = (impulse + beta * *direction).max(0.0);
            *direction = beta * *direction + step;
            next
        }
        None => {
            *direction = step;
            impulse
        }
    }
}

/// The most iterations [`compress_by_gradients`] makes before a group is swept instead.
const MAX_GRADIENT_STEPS: u32 = 16;

/// The compression impulses of a large group by gradient projection with conjugate gradients
/// (Dostál's MPRGP, on the contacts scaled to unit diagonal): conjugate gradients over the
/// contacts that push, steps that free contacts held at zero while their gradient outweighs
/// the free ones', and projected steps where a contact would go below zero. A group whose
/// contacts all share one body (a ring of balls striking one ball at one instant) couples
/// every contact to every other, which sweeps converge on only in thousands; this takes a few
/// iterations. Returns whether it converged (no contact's speed more than 1e-14 of `scale`
/// and what `rounding` leaves from its aim) within [`MAX_GRADIENT_STEPS`]; `impulses` (`λ`)
/// and `velocities` then hold the answer. `scratch` has four values a contact and `work` three a body.
fn compress_by_gradients(
    inverse_masses: &[f64],
    velocities: &mut [DVec3],
    contacts: &[GroupContact],
    impulses: &mut [f64],
    scratch: &mut [f64],
    work: &mut [f64],
    (scale, rounding): (f64, f64),
) -> bool {
    let n = contacts.len();
    let (sizes, rest) = scratch.split_at_mut(n);
    let (gradient, rest) = rest.split_at_mut(n);
    let (direction, rest) = rest.split_at_mut(n);
    let (pushed, _) = rest.split_at_mut(n);
    // Contact `i`'s impulse is `x_i / sizes_i`, `sizes_i = √(w_a + w_b)`: in `x` the problem's
    // matrix has a unit diagonal. `impulses` holds `x` until the end.
    for (c, size) in contacts.iter().zip(sizes.iter_mut()) {
        *size = (inverse_masses[c.a] + inverse_masses[c.b]).sqrt();
    }
    // The step of the projected steps, `1 / ‖A‖`, bounded by Gershgorin's row sums: each
    // body's contacts' `1 / size` summed first.
    work.fill(0.0);
    for (c, &size) in contacts.iter().zip(sizes.iter()) {
        if size > 0.0 {
            work[c.a] += 1.0 / size;
            work[c.b] += 1.0 / size;
        }
    }
    let mut norm = 0.0f64;
    for (c, &size) in contacts.iter().zip(sizes.iter()) {
        if size > 0.0 {
            let row = (inverse_masses[c.a] * work[c.a] + inverse_masses[c.b] * work[c.b]) / size;
            norm = norm.max(row);
        }
    }
    if !(norm > 0.0 && norm.is_finite()) {
        return false;
    }
    let step = 1.0 / norm;
    let apply = |velocities: &mut [DVec3], c: &GroupContact, impulse: f64| {
        velocities[c.a] -= c.normal * (impulse * inverse_masses[c.a]);
        velocities[c.b] += c.normal * (impulse * inverse_masses[c.b]);
    };
    // Sets every `x_i` to `to(i, x_i)` (never below 0), the velocities with them.
    let move_to = |velocities: &mut [DVec3], x: &mut [f64], to: &dyn Fn(usize, f64) -> f64| {
        for (i, (c, &size)) in contacts.iter().zip(sizes.iter()).enumerate() {
            if size > 0.0 {
                let next = to(i, x[i]).max(0.0);
                if next != x[i] {
                    apply(velocities, c, (next - x[i]) / size);
                    x[i] = next;
                }
            }
        }
    };
    let gradient_of = |velocities: &[DVec3], gradient: &mut [f64]| {
        for ((c, &size), g) in contacts.iter().zip(sizes.iter()).zip(gradient.iter_mut()) {
            *g = if size > 0.0 {
                ((velocities[c.b] - velocities[c.a]).dot(c.normal) - c.aimed_bias()) / size
            } else {
                0.0
            };
        }
    };
    // `A·p` into `pushed`, through each body's velocity change (`work`, three values a body);
    // returns `pᵀ·A·p`.
    let times_matrix = |p: &[f64], pushed: &mut [f64], work: &mut [f64]| -> f64 {
        work.fill(0.0);
        for ((c, &size), &p) in contacts.iter().zip(sizes.iter()).zip(p) {
            if size > 0.0 && p != 0.0 {
                let impulse = c.normal * (p / size);
                for (k, sign) in [(c.a, -1.0), (c.b, 1.0)] {
                    let change = impulse * (sign * inverse_masses[k]);
                    work[3 * k] += change.x;
                    work[3 * k + 1] += change.y;
                    work[3 * k + 2] += change.z;
                }
            }
        }
        let mut total = 0.0;
        for (((c, &size), &p), out) in contacts.iter().zip(sizes.iter()).zip(p).zip(pushed) {
            *out = if size > 0.0 {
                let at = |k: usize| DVec3::new(work[3 * k], work[3 * k + 1], work[3 * k + 2]);
                (at(c.b) - at(c.a)).dot(c.normal) / size
            } else {
                0.0
            };
            total += p * *out;
        }
        total
    };
    let tolerance = 1e-14 * scale + rounding;
    impulses.fill(0.0);
    // Whether the next conjugate step starts afresh, and the last one's `pᵀ·A·p`.
    let (mut fresh, mut curvature) = (true, 0.0);
    for iteration in 0..=MAX_GRADIENT_STEPS {
        gradient_of(velocities, gradient);
        // The largest speed off its aim; the chopped gradient's square (contacts at zero that
        // would grow), and the reduced free gradient times the free one.
        let (mut largest, mut chopped, mut reduced) = (0.0f64, 0.0f64, 0.0f64);
        for ((&x, &g), &size) in impulses.iter().zip(gradient.iter()).zip(sizes.iter()) {
            if size == 0.0 {
                continue;
            }
            if x > 0.0 {
                largest = largest.max(g.abs() * size);
                reduced += (x / step).min(g) * g;
            } else if g < 0.0 {
                largest = largest.max(-g * size);
                chopped += g * g;
            }
        }
        if largest <= tolerance {
            for (impulse, &size) in impulses.iter_mut().zip(sizes.iter()) {
                *impulse = if size > 0.0 { *impulse / size } else { 0.0 };
            }
            return true;
        }
        if iteration == MAX_GRADIENT_STEPS || !largest.is_finite() {
            return false;
        }
        let free = |x: f64, g: f64| if x > 0.0 { g } else { 0.0 };
        if chopped <= reduced {
            // A conjugate gradient step among the free contacts.
            let gamma = if fresh {
                0.0
            } else {
                let mut along = 0.0;
                for ((&x, &g), &ap) in impulses.iter().zip(gradient.iter()).zip(pushed.iter()) {
                    along += free(x, g) * ap;
                }
                along / curvature
            };
            for ((p, &x), &g) in direction
                .iter_mut()
                .zip(impulses.iter())
                .zip(gradient.iter())
            {
                *p = free(x, g) - gamma * *p;
            }
            curvature = times_matrix(direction, pushed, work);
            if !(curvature > 0.0 && curvature.is_finite()) {
                return false;
            }
            let mut downhill = 0.0;
            let mut feasible = f64::INFINITY;
            for ((&p, &g), &x) in direction.iter().zip(gradient.iter()).zip(impulses.iter()) {
                downhill += g * p;
                if p > 0.0 {
                    feasible = feasible.min(x / p);
                }
            }
            let length = downhill / curvature;
            if length <= feasible {
                move_to(velocities, impulses, &|i, x| x - length * direction[i]);
                fresh = false;
            } else {
                // As far as the first contact reaching zero, then a projected gradient step.
                move_to(velocities, impulses, &|i, x| x - feasible * direction[i]);
                gradient_of(velocities, gradient);
                move_to(velocities, impulses, &|i, x| {
                    x - step * free(x, gradient[i])
                });
                fresh = true;
            }
        } else {
            // Contacts held at zero that would push: along the chopped gradient.
            for ((p, &x), &g) in direction
                .iter_mut()
                .zip(impulses.iter())
                .zip(gradient.iter())
            {
                *p = if x > 0.0 { 0.0 } else { g.min(0.0) };
            }
            curvature = times_matrix(direction, pushed, work);
            if !(curvature > 0.0 && curvature.is_finite()) {
                return false;
            }
            let length = chopped / curvature;
            move_to(velocities, impulses, &|i, x| x - length * direction[i]);
            fresh = true;
        }
    }
    false
}

/// The compression impulses by projected Gauss–Seidel, accelerated: sweeps over the contacts
/// until no impulse changes a speed by more than 1e-15 of `scale` and what `rounding` leaves,
/// at most [`MAX_GROUP_SWEEPS`];
/// returns whether they converged. An accelerated step that would raise the problem's
/// objective (`½ λᵀAλ + bᵀλ`, the kinetic energy less the biases' work, which each sweep
/// lowers) is taken back, and the acceleration starts again (until the sixty-fourth session
/// it was kept: around a ball struck by a ring of 80 the impulses wandered off, and the group
/// left with 8.6 times its energy). `before`, `direction` and `kept` are scratch, one value a
/// contact.
fn compress_iteratively(
    inverse_masses: &[f64],
    velocities: &mut [DVec3],
    contacts: &[GroupContact],
    impulses: &mut [f64],
    (before, direction, kept): (&mut [f64], &mut [f64], &mut [f64]),
    (scale, rounding): (f64, f64),
) -> bool {
    let apply = |velocities: &mut [DVec3], c: &GroupContact, impulse: f64| {
        velocities[c.a] -= c.normal * (impulse * inverse_masses[c.a]);
        velocities[c.b] += c.normal * (impulse * inverse_masses[c.b]);
    };
    before.copy_from_slice(impulses);
    let mut last_moved = 0.0f64;
    for _ in 0..MAX_GROUP_SWEEPS {
        let mut largest_change = 0.0f64;
        // How far the sweep moved the impulses (squared), for the acceleration below.
        let mut moved = 0.0f64;
        for ((c, impulse), b) in contacts.iter().zip(impulses.iter_mut()).zip(&*before) {
            let inverse_sum = inverse_masses[c.a] + inverse_masses[c.b];
            if inverse_sum == 0.0 {
                continue;
            }
            let normal_speed = (velocities[c.b] - velocities[c.a]).dot(c.normal) - c.aimed_bias();
            let next = (*impulse - normal_speed / inverse_sum).max(0.0);
            let change = next - *impulse;
            if change != 0.0 {
                apply(velocities, c, change);
                *impulse = next;
                largest_change = largest_change.max((change * inverse_sum).abs());
            }
            moved += (*impulse - b) * (*impulse - b);
        }
        if largest_change <= 1e-15 * scale + rounding {
            return true;
        }
        // Accelerated as the step's resting solve is (a group of wedged contacts in a ball pit
        // took the whole 256 sweeps in one solve in two).
        let beta = conjugate_factor(moved, last_moved);
        last_moved = moved;
        if beta.is_some() {
            kept.copy_from_slice(impulses);
        }
        // How much the accelerated step raises the objective: each contact's change `δ`
        // raises it by `δ·w + ½ δ² (w_a + w_b)`, `w` its speed off its aim as it is reached.
        let mut rise = 0.0f64;
        for (((c, impulse), b), d) in contacts
            .iter()
            .zip(impulses.iter_mut())
            .zip(before.iter_mut())
            .zip(direction.iter_mut())
        {
            let next = conjugate_step(*impulse, *impulse - *b, d, beta);
            if next != *impulse {
                let change = next - *impulse;
                let off_aim = (velocities[c.b] - velocities[c.a]).dot(c.normal) - c.aimed_bias();
                let inverse_sum = inverse_masses[c.a] + inverse_masses[c.b];
                rise += change * (off_aim + 0.5 * change * inverse_sum);
                apply(velocities, c, change);
                *impulse = next;
            }
            *b = *impulse;
        }
        if rise > 0.0 || rise.is_nan() {
            // Taken back, in the reverse order.
            for ((c, impulse), &kept) in contacts
                .iter()
                .zip(impulses.iter_mut())
                .zip(kept.iter())
                .rev()
            {
                if *impulse != kept {
                    apply(velocities, c, kept - *impulse);
                    *impulse = kept;
                }
            }
            before.copy_from_slice(impulses);
            last_moved = 0.0;
        }
    }
    false
}
