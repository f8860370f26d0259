//! One step: kick, then drift with collisions resolved one at a time in time order, then kick.
//!
//! Every pair's first impact in the step is put in a priority queue keyed by (time, lower
//! index, higher index), indices being body ids in small scenes and the broad phase's spatial
//! order in large ones: deterministic either way. The earliest is resolved: both bodies are
//! moved to that instant, an impulse is applied, and only the pairs involving those two bodies
//! are tested again for the rest of the step. Touching chains therefore propagate one contact
//! at a time, exactly as a sequence of collisions separated by vanishing gaps would: one ball
//! in, one ball out.
//!
//! Impacts at one instant that share a dynamic body are solved together
//! ([`resolve_simultaneous`]), and so is a resting impact (restitution 0) on a body that took
//! a resting impulse earlier at that instant, with that contact ([`InstantContacts`]): a
//! sphere wedged between a fixed sphere and one pressing on it takes the load at once.
//! An impact with a sphere on a taut string is solved with the string (a contact to its
//! anchor that pulls but never pushes), and with a strut that holds the other sphere off the
//! anchor where it squeezes the strung one against its string's length with next to no room
//! left ([`STRUT_MARGIN`](strings::STRUT_MARGIN)).
//! Touching pairs closing slowly at the start of the step are resting contacts, solved
//! together before any impact (projected Gauss–Seidel, swept lowest first, warm-started from
//! the last step's impulses and accelerated by nonsmooth nonlinear conjugate gradients).
//!
//! What counts as pressed: a pair is pressed by the bodies' own accelerations along its
//! normal (a ball on a floor by its weight; balls side by side on a floor not at all, so
//! their meetings keep their restitution), and a contact that took a load in the last step's
//! resting solve by their whole accelerations (in a pile the weight pushes sideways too,
//! through the neighbours: a sphere wedged against a wall). Pairs that touch or nearly touch
//! but are not resting contacts join the solve as guards, each allowed to close as fast as it
//! already does: the solve may not push them together itself. Within the step a contact's
//! load from the solve counts as its press, for its restitution and its creep.

use std::cmp::Ordering;

use glam::DVec3;

use crate::broad_phase::{Aabb, BroadPhase};
use crate::contact::touching_or_overlapping;
use crate::instant::InstantContacts;
use crate::queue::{EventQueue, Timed};
use crate::response::{
    GroupContact, conjugate_factor, conjugate_step, resolve_at, resolve_simultaneous,
};
use crate::{
    Body, Collision, ExactToi, Integrator, Settings, StepProfile, StepStats, Tether, TimeOfImpact,
};

mod fallback;
mod glance;
mod impacts;
mod requery;
mod resting;
mod separate;
mod strings;
mod warm;

use glance::{
    Apart, FirstPass, Glance, Relative, Side, cannot_touch_by, first_pass_kept, kept_by_glances,
};
use strings::{STRUNG_OVERLAP, Strung, at_length, bend, taut};
use warm::WarmLoads;

/// A body's drift within the current step: at `t0` it is at `position`, moving at `velocity`.
/// Only what pair tests read, in one cache line, so the event loop's random reads stay small;
/// the rest of a body's step state (its inverse mass among it) is its [`Extra`].
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Segment {
    position: DVec3,
    velocity: DVec3,
    t0: f64,
    /// The radius, negated for a fixed body: pair tests skip fixed pairs without reading the
    /// body's [`Extra`], and the flag costs no byte.
    signed_radius: f64,
}

const _: () = assert!(size_of::<Segment>() == 64, "a Segment is one cache line");

/// The rest of a body's step state, kept in body order (read at impacts and at the end):
/// one cache line. A body on a string has its string's state apart, in a [`Strung`].
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Extra {
    acceleration: DVec3,
    inverse_mass: f64,
    restitution: f64,
    /// The body's id (records name bodies without reading the body array).
    id: crate::BodyId,
    /// Asleep (see `Settings::sleep`): at rest, not accelerated.
    asleep: bool,
}

const _: () = assert!(size_of::<Extra>() == 64, "an Extra is one cache line");

impl Segment {
    fn position_at(&self, t: f64) -> DVec3 {
        self.position + self.velocity * (t - self.t0)
    }

    fn advance_to(&mut self, t: f64) {
        self.position = self.position_at(t);
        self.t0 = t;
    }

    fn is_fixed(&self) -> bool {
        self.signed_radius.is_sign_negative()
    }

    fn radius(&self) -> f64 {
        self.signed_radius.abs()
    }
}

/// A pair whose impact gave no impulse (see `Solver::settled`): `a < b`, and their versions.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Settled {
    a: u32,
    b: u32,
    version_a: u32,
    version_b: u32,
}

impl Settled {
    /// Pair `(a, b)` (either order) as its bodies' `versions` stand now.
    fn now(versions: &[u32], a: usize, b: usize) -> Self {
        let (a, b) = (a.min(b), a.max(b));
        Settled {
            a: a as u32,
            b: b as u32,
            version_a: versions[a],
            version_b: versions[b],
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct Event {
    time: f64,
    a: u32,
    b: u32,
    version_a: u32,
    version_b: u32,
}

impl Event {
    fn key(&self) -> (f64, u32, u32, u32, u32) {
        (self.time, self.a, self.b, self.version_a, self.version_b)
    }
}

impl Timed for Event {
    fn time(&self) -> f64 {
        self.time
    }
}

impl PartialEq for Event {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Event {}
impl PartialOrd for Event {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Event {
    fn cmp(&self, other: &Self) -> Ordering {
        let (s, o) = (self.key(), other.key());
        s.0.total_cmp(&o.0)
            .then(s.1.cmp(&o.1))
            .then(s.2.cmp(&o.2))
            .then(s.3.cmp(&o.3))
            .then(s.4.cmp(&o.4))
    }
}

/// Below this many candidates, a re-query glances at them one by one: the glances side by
/// side (see `Solver::test_candidates`) pay for their setup only with more (at four a time,
/// from three on: the 10k shower and gas execute as many instructions with 3 as with 6,
/// with fewer branches on the glances' outcomes).
const FEW_CANDIDATES: usize = 3;

/// How many of the first pass's pairs (at least) are found before the batch before them is
/// tested (see `Solver::step`).
const PAIR_BATCH: usize = 16;

/// The fewest segments the resting solve must change for their pairs to be tested again in
/// one pass over the broad phase (see [`Solver::requery_in_one_pass`]).
const ONE_PASS_MIN: usize = 64;

/// How many times [`Settings::max_collisions_per_body`] one body may take in a step (the
/// world's budget is that setting times the dynamic bodies): 4096 by default. In the
/// 100k-sphere shower benchmark's climax (about 1.4 s in), spheres sliding down the dome in
/// its film take up to 2228 collisions in a step; at 64 times (1024, until 2026-12-06)
/// dozens of them ran out of their shares in a step, and their deferred impacts left pairs
/// 6.4 mm deep. In a world of fewer than 256 dynamic bodies the world's budget runs out first,
/// and the fallback solves the rest of the step for the crowd that spent it.
const BODY_SHARE: u32 = 256;

/// The least share in a world with strings: there a body's share is a quarter of the world's
/// budget, from this to [`BODY_SHARE`] times (1024 to 4096 collisions by default). The
/// fallback leaves strung bodies out (their pairs are deferred), and where strings are it
/// takes every body, so there a body's share should run out before the world's budget does,
/// leaving only that body's impacts deferred (`sphere-fuzz --strings fast` seed 223 414,
/// 119 dynamic spheres: at 4096 the world's budget ran out in two steps, each fallback
/// deferred 91 to 93 pairs, and a sphere of 0.66 g ended a step 5.9% of its radius into one
/// of 0.59 kg).
const BODY_SHARE_STRUNG: u32 = 64;

/// How far past its share of collisions a body of an impact may be for the impact to be
/// squeezed (see [`Solver::squeeze`]; each squeeze changes each of its bodies' drifts once):
/// past that, unless the other body is still within it, its impacts are deferred. A body that
/// cannot be kept out of both sides (a kinematic sphere pressing it against a fixed one) is
/// squeezed a few times a step, not without end.
const SQUEEZES: u32 = 8;

/// How many bounces (impacts with a restitution between 0 and 1) a dynamic body takes at one
/// instant before slow impacts of its there may end an inelastic collapse. A ball striking a
/// row of touching spheres with restitution 0.5 sets one off at the instant: the spheres behind
/// catch up with those ahead again and again, each bounce slower, without end (a row of 10
/// took 186 impacts, past the budget; a row of 40 spent the whole budget in each of two steps).
/// Impacts taken together at one instant, one of them on such a body, each approaching at
/// under [`COLLAPSE_SPEED`] of the instant's fastest bounce, are squeezed (see
/// [`Solver::squeeze`]): solved at once, restitution 0, with the contacts along the first one's
/// line that are as slow (closing or parting), where the bounces lead; if a contact along that
/// line still closes faster, the collapse is not over and the impacts are taken as usual. A
/// sequence of bounces that ends by itself (a row of 40 at restitution 0.9, about 1100
/// bounces taken one by one) is left to end: its slow contacts are squeezed at most, which
/// takes next to nothing of its energy (3.55% of it left, as the bounces leave). Bodies'
/// bounces are counted from an instant's [`InstantContacts::COUNT_FROM`]th on, so a body
/// qualifies once it has taken 16 to 31 bounces at one instant, and while fewer than
/// [`SQUEEZES`] collapses' squeezes have taken it there (each counts as a bounce: it
/// qualifies with 16 to 23 counted). Not a body past its share of the budget (its impacts are
/// deferred unless its share's squeeze takes them), nor in a world with strings, after a
/// fallback, or with the budget spent (as any squeeze). Elastic bounces (restitution 1) are
/// not counted: they end by themselves, and a squeeze would take their energy.
const COLLAPSE_BOUNCES: u32 = 16;

/// How slowly, against the fastest bounce of its instant, an impact on a body past
/// [`COLLAPSE_BOUNCES`] must approach to be squeezed, and how slowly the contacts its squeeze
/// takes must close or part (see [`Solver::squeeze`]). At 0.01 a row of 40 at restitution 0.5
/// was squeezed in small pieces, eight times a sphere, and spent the budget; 0.03 and 0.1 gave
/// the same results on rows of 10 to 40 at restitutions 0.5 to 0.95.
const COLLAPSE_SPEED: f64 = 0.03;

/// The cosine of the widest angle a contact's normal may make with a collapse's line to join
/// its squeeze (30°: see [`Solver::squeeze`]). At 60° the neighbours of a hexagonal packing
/// (a rack of balls) joined it, and a rack of 210 at restitution 0.9 took 7 ms where it had
/// taken 2.9 before the squeeze; at 30°, 4.7 ms, and racks of 55 to 465 balls at restitutions
/// 0.5 to 0.95 from 0.48 to 1.17 times their time before.
const ALONG_COS: f64 = 0.866;

/// The most contacts [`Solver::squeeze`] gathers into one solve.
const SQUEEZE_CONTACTS: usize = 256;

/// Half the largest f64: two numbers below it in size add to a finite one.
const HALF_RANGE: f64 = f64::MAX / 2.0;

/// What the solver kept from the last step taken, while a step that may yet be refused
/// changes it (see [`Solver::begin_step`]).
#[derive(Debug, Default)]
struct Before {
    /// [`Solver::rested`] as it was, if `rested_kept`.
    rested: Vec<u64>,
    /// [`Solver::warm`] as it was, if `warm_kept`.
    warm: WarmLoads,
    rested_kept: bool,
    warm_kept: bool,
}

/// Scratch space for stepping, kept between steps so a warmed-up step does not allocate.
#[derive(Debug, Default)]
pub(crate) struct Solver {
    segments: Vec<Segment>,
    /// Each body's [`Extra`], in body order: segment `k`'s is `extras[order[k]]`.
    extras: Vec<Extra>,
    /// Each body's velocity kick after the drift, in body order (read only at the end); empty
    /// while every one is zero (semi-implicit Euler's), so that such a step neither writes
    /// nor reads them.
    kicks_after: Vec<DVec3>,
    /// The largest component of any kick after the drift: when it is below half the largest
    /// f64, a velocity below that half cannot overflow when its kick is added.
    largest_kick_after: f64,
    /// [`Solver::solve_deep_groups_exactly`]'s scratch.
    exact: ExactScratch,
    /// Every contact of the group being solved has restitution 0 and no push against its
    /// overlap (see [`Solver::squeeze`]).
    inelastic: bool,
    /// [`Solver::squeeze`]'s search: the dynamic bodies it reached, in order, one bit per
    /// segment reached and one per segment looked at (both cleared after it).
    squeeze_cluster: Vec<u32>,
    squeeze_bits: Vec<u64>,
    squeeze_done: Vec<u64>,
    /// The string states of the bodies on strings (see [`Solver::string_of`]).
    strung: Vec<Strung>,
    /// One bit per segment on a string (see [`Solver::bent_pair`]).
    strung_bits: Vec<u64>,
    /// Whether any body hangs on a string this step.
    strings: bool,
    /// Each segment's version (bumped when its drift changes; older events are stale). Apart
    /// from the segments so the event loop's checks read a small, dense array.
    versions: Vec<u32>,
    boxes: Vec<Aabb>,
    queue: EventQueue<Event>,
    broad: BroadPhase,
    candidates: Vec<u32>,
    partner_candidates: Vec<u32>,
    /// The first pass's pairs: the batch being found, and the one before it (its segments
    /// asked for), to be tested next.
    pairs: Vec<(u32, u32)>,
    asked_pairs: Vec<(u32, u32)>,
    /// A collision approaching no faster than this times the acceleration pressing the pair
    /// together is a resting contact (restitution 0); 0 when nothing accelerates.
    resting_scale: f64,
    /// Touching pairs closing slower than this times their pressing acceleration are left
    /// alone until the next step.
    creep_scale: f64,
    /// The resting speed of the largest acceleration (a component's): the scale of what
    /// counts as resting this step.
    resting_speed: f64,
    /// The most load a contact's warm start carries into the next step, an acceleration:
    /// [`WARM_LOADS`] times the largest (a component's), or infinite if nothing accelerates.
    warm_cap: f64,
    /// The distance within which a pair counts as touching, as [`cannot_touch_by`] reckons
    /// it, worked out once per step from the tolerance.
    apart: Apart,
    resting: Vec<RestingContact>,
    /// Scratch for `Solver::order_resting`: each resting contact's sort key and place (twice:
    /// the keys placed by group), where each group's keys start, and the contacts in their new
    /// order.
    resting_keys: Vec<(u32, i64, u64, u32)>,
    resting_keys_placed: Vec<(u32, i64, u64, u32)>,
    group_start: Vec<u32>,
    resting_sorted: Vec<RestingContact>,
    /// Scratch for [`Solver::fall_back`]: the pairs it has solved or left to a string's body,
    /// sorted.
    fallback_pairs: Vec<(u32, u32)>,
    /// Scratch for [`Solver::fall_back`]: a round's pairs with a body on a string, left alone.
    fallback_strung: Vec<(u32, u32)>,
    /// Scratch for [`Solver::fall_back`]: the deep pushes it holds back, `(a, b, push)`.
    fallback_pushes: Vec<(u32, u32, f64)>,
    /// Scratch for `Solver::choose_crowd`: union–find over the segments, then each dynamic
    /// one's root; and per root its dynamic segments and the sum of their versions.
    crowd_parent: Vec<u32>,
    crowd_groups: Vec<fallback::Group>,
    /// Scratch for `Solver::choose_crowd`: the bodies a fallback leaves out, and the largest
    /// dynamic radius.
    crowd_left: Vec<u32>,
    crowd_radius: f64,
    /// Scratch for `Solver::take_reached`: the bodies of the groups a crowd's drifts reach.
    crowd_reached: Vec<u32>,
    /// Scratch for `Solver::choose_crowd`: each body's candidates as it found them (its range
    /// of `crowd_candidates` by segment), and whether they still stand for the first round of
    /// the fallback's first solve.
    crowd_candidates: Vec<u32>,
    crowd_ranges: Vec<(u32, u32)>,
    crowd_found: bool,
    /// Scratch for [`Solver::fall_back`]: the segments changed at its time whose pairs it must
    /// test again if it leaves them to the event loop (dirty ones, and those it ended a push
    /// of).
    fallback_requery: Vec<u32>,
    /// The segments a fallback of this step took (one bit each), and their list: their drifts
    /// are final, and the event loop defers their later impacts.
    fallen_bits: Vec<u64>,
    fallen: Vec<u32>,
    /// Pairs touching but not resting, or apart by less than [`Solver::near_reach`] beyond the
    /// contact band with a body that rested in the last step, at the start of the step:
    /// `(a, b, normal, distance)`. Those with a body in a resting contact join the resting
    /// solve as guards (see [`Solver::add_guards`]).
    near: Vec<(u32, u32, DVec3, f64)>,
    /// How far beyond the contact band a pair may be and still close within the step at the
    /// resting speed of the largest acceleration.
    near_reach: f64,
    /// One bit per body (in body order) that took a resting impulse in the last step: its box
    /// is grown by how far a resting speed carries it in a step, so that the first pass finds
    /// its near pairs (see [`Solver::near`]).
    rested: Vec<u64>,
    /// [`Solver::rested`] in solver order, for this step's first pass: only pairs with such a
    /// body are sought as near pairs.
    rested_here: Vec<u64>,
    /// One bit per segment that carries a load from this step's resting solve (see
    /// [`Solver::loads`]): other pairs are spared the search.
    loaded: Vec<u64>,
    /// The loads this step's resting solve put on its contacts, `(a, b, load)` with `a < b`
    /// solver indices, grouped by `a` (in the solve's order within a group): each pair's
    /// impulse as a change of relative speed per second. A loaded contact is pressed by at
    /// least its load for the rest of the step.
    loads: Vec<(u32, u32, f64)>,
    /// Scratch: the loads as the solve leaves them, before they are grouped.
    loads_unplaced: Vec<(u32, u32, f64)>,
    /// Where each solver index's loads begin in [`Solver::loads`] (as its contacts' lower
    /// index; one more entry for the end), so that a press looks among a body's few contacts
    /// instead of searching them all.
    load_start: Vec<u32>,
    /// The last resting solve's impulses per second, by the pair's body ids (smaller first):
    /// the next solve starts from them (a warm start).
    warm: WarmLoads,
    /// Scratch: the loads for the next warm start, as the solve leaves them.
    next_warm: Vec<(crate::BodyId, crate::BodyId, f64)>,
    /// What [`Solver::rested`] and [`Solver::warm`] held when the world's step began, kept for
    /// a step that is refused (see [`Solver::begin_step`]).
    before: Before,
    /// Solver index `p` is body index `order[p]` (the broad phase's spatial order).
    order: Vec<u32>,
    /// Body `i` is solver index `position_of[i]` (the inverse of `order`).
    position_of: Vec<u32>,
    scratch_segments: Vec<Segment>,
    scratch_boxes: Vec<Aabb>,
    /// The pairs tested this step whose drifts could end the step overlapping (or that had an
    /// impact queued): a superset of the pairs that can overlap at its end.
    tested: Vec<(u32, u32)>,
    /// One bit per segment, set while it is in `touched`: a bit set stays in the core's
    /// caches at any size (a word per segment, marked with an epoch, missed them at 100k).
    touched_bits: Vec<u64>,
    /// The first segment an impulse sent beyond the finite range within the step (a sphere
    /// struck by a kinematic one moving near the largest finite speed, say): the step stops
    /// and is refused before anything is written back.
    unbounded: Option<usize>,
    pub collisions: Vec<Collision>,
    /// Whether to time the step's phases into `profile`.
    pub profiling: bool,
    /// The phases' wall time, summed over the world step's substeps (while `profiling`).
    pub profile: StepProfile,
    /// Pairs whose impact at `settled_time` gave no impulse, with both bodies' versions after
    /// it: at that instant they do not approach, though a string's bent drift may say they do
    /// (it is a chord; at an impact a sphere moves freely or along its swing). A new impact of
    /// theirs at that same instant, neither body having changed since, is not queued: it would
    /// give no impulse again, for ever.
    settled: Vec<Settled>,
    settled_time: f64,
    /// Resting contacts that took an impulse at the current instant (within the simultaneity
    /// window of its first event): a later resting impact at that instant on one of their
    /// bodies is solved together with them (see [`InstantContacts`]).
    instant: InstantContacts,
    /// Scratch: a group of impacts together with the instant's contacts they join.
    joined: Vec<Event>,
    /// Scratch for simultaneous groups.
    group: Vec<Event>,
    ranges: Vec<std::ops::Range<usize>>,
    components: Components,
    /// The resting contacts' groups, found by [`Solver::order_resting`], and scratch for
    /// [`Solver::solve_small_groups_exactly`].
    small_groups: SmallGroups,
    touched: Vec<u32>,
    local_resting: Vec<bool>,
    /// Each of a group's contacts that is a bounce, its approach (see [`COLLAPSE_BOUNCES`]).
    local_bounces: Vec<Option<f64>>,
    local_taut: Vec<bool>,
    local_bodies: Vec<u32>,
    /// Each segment's index in `local_bodies` while a group is solved ([`NOT_LOCAL`] otherwise):
    /// a group of thousands of impacts finds its bodies in O(1), not by a search.
    local_index: Vec<u32>,
    local_inverse_masses: Vec<f64>,
    local_velocities: Vec<DVec3>,
    local_contacts: Vec<GroupContact>,
    local_impulses: Vec<f64>,
    /// Each local body's velocity at the instant of a group's impacts less its drift's (see
    /// `resolve_group`), and the impulses of the group's first solve when a second is needed;
    /// or, for [`Solver::resolve_pushing_group`], the velocities and impulses of its solve
    /// without the pushes.
    local_shifts: Vec<DVec3>,
    local_first_impulses: Vec<f64>,
    /// Scratch for [`Solver::resolve_pushing_group`]: the group's contacts' pushes.
    local_biases: Vec<f64>,
    /// Scratch for [`Solver::solve_pushes`] and [`Solver::push_on`]: the resting contacts'
    /// dynamic bodies with their velocities before the solve, then as the solve without
    /// pushes leaves them (each body's index here is its [`Solver::local_index`] meanwhile),
    /// each body's push against what is left of its budget (see [`Solver::push_left`]), and
    /// each contact's push, impulse from that solve, and the scale its push is given.
    push_bodies: Vec<(u32, DVec3)>,
    push_ratios: Vec<f64>,
    push_saved: Vec<(f64, f64, f64)>,
    /// What the pushes against overlaps solved apart from the load (the resting solve's, and
    /// the fallback's) added to segments' velocities this step: taken off at its end, or when
    /// a pushed body meets another (see [`Solver::end_pushes`]).
    pushes: Vec<(u32, DVec3)>,
    /// One bit per segment in [`Solver::pushes`].
    pushed_bits: Vec<u64>,
    /// How much of its push budget each segment has spent this step (see
    /// [`Solver::push_left`]), valid where its bit in [`Solver::spent_bits`] is set.
    spent: Vec<f64>,
    /// One bit per segment that has spent some of its push budget this step.
    spent_bits: Vec<u64>,
    /// Scratch for [`Solver::separate`]: the bodies it may move (one bit per segment, and
    /// their list), each one's position as moved so far and its move (valid where its bit is
    /// set), and the pairs within reach of them.
    separate_bits: Vec<u64>,
    /// One bit per segment a move of this separation has taken with its pair's centre of mass
    /// not kept (against a fixed sphere, a string, or a cap the other body made up for).
    separate_unkept: Vec<u64>,
    separating: Vec<u32>,
    separate_at: Vec<DVec3>,
    separate_moves: Vec<DVec3>,
    separate_pairs: Vec<(u32, u32)>,
    /// Whether no dynamic body accelerates this step (no gravity, no applied force; an asleep
    /// body counts with what would act on it): then overlaps left at its end are moved apart
    /// (see [`Solver::separate`]).
    nothing_accelerates: bool,
    /// Whether any body is asleep this step (see `Settings::sleep`).
    any_asleep: bool,
    /// Re-queries within one instant (see [`Solver::requery_touched`]): the instant's stamp,
    /// and each segment's stamp when it was last queried in full while [`Solver::caching`]
    /// (its candidates then are `candidate_cache[range]`, valid while the stamps match).
    stamp: u32,
    stamp_time: f64,
    query_stamps: Vec<u32>,
    cache_ranges: Vec<(u32, u32)>,
    candidate_cache: Vec<u32>,
    /// Segments changed again at the instant after their query in full there: their pairs
    /// have been tested only for impacts at that instant, the rest waits for
    /// [`Solver::flush_dirty`] (one bit per segment, and their list).
    dirty: Vec<u32>,
    dirty_bits: Vec<u64>,
    /// Scratch: the touched segments queried in full at the instant already.
    repeats: Vec<u32>,
    /// Scratch: the pairs with a touched segment found in one pass over the broad phase (see
    /// [`Solver::requery_in_one_pass`]).
    touched_pairs: Vec<(u32, u32)>,
    /// While testing a pair with a dirty body: impacts after this are not queued (its query
    /// in full will find them), else infinite.
    queue_until: f64,
    /// Whether queries in full keep their candidates (see [`Solver::keep_candidates`]).
    caching: bool,
}

/// Scratch for [`Solver::solve_deep_groups_exactly`]: the resting contacts as events (for
/// grouping) and the groups' ranges; then one group's bodies, each segment's place among them
/// ([`NOT_LOCAL`] otherwise), their inverse masses and velocities, its contacts and their
/// impulses.
#[derive(Debug, Default)]
struct ExactScratch {
    events: Vec<Event>,
    ranges: Vec<std::ops::Range<usize>>,
    bodies: Vec<u32>,
    index: Vec<u32>,
    inverse_masses: Vec<f64>,
    velocities: Vec<DVec3>,
    contacts: Vec<GroupContact>,
    impulses: Vec<f64>,
    /// The resting sweeps' blocks (see `Solver::find_blocks`): each resting contact's block
    /// (`NOT_LOCAL` for one swept alone), each block's contacts (`block_members`, from
    /// `block_starts[b]` to `block_starts[b + 1]`), and each body's block while they are found.
    block_of: Vec<u32>,
    block_starts: Vec<u32>,
    block_members: Vec<u32>,
    owner_block: Vec<u32>,
}

/// Marks a segment that is not in the group being solved (see `Solver::local_index`).
const NOT_LOCAL: u32 = u32::MAX;

/// The resting contacts' groups (connected through dynamic bodies), for
/// [`Solver::order_resting`] and [`Solver::solve_small_groups_exactly`]: a union–find over the
/// bodies of the resting contacts (by solver index), each root's count of contacts, and
/// whether any of them closes or pushes; then the small groups' contacts, as events sorted by
/// group.
#[derive(Debug, Default)]
struct SmallGroups {
    parent: Vec<u32>,
    /// Each root's tally (one place per body, so a body's is one read).
    tally: Vec<GroupTally>,
    events: Vec<Event>,
}

impl SmallGroups {
    /// Joins the bodies of `resting` (of `segments` bodies in all) into groups, through their
    /// dynamic bodies (a fixed body's inverse mass is 0: the contact says so, without reading
    /// the body), and clears their tallies.
    fn join(&mut self, resting: &[RestingContact], segments: usize) {
        if self.parent.len() < segments {
            self.parent.resize(segments, 0);
            self.tally.resize(segments, GroupTally::default());
        }
        for c in resting {
            for k in [c.a, c.b] {
                self.parent[k as usize] = k;
                self.tally[k as usize] = GroupTally::default();
            }
        }
        for c in resting {
            if c.inverse_mass_a != 0.0 && c.inverse_mass_b != 0.0 {
                union_join(&mut self.parent, c.a as usize, c.b as usize);
            }
        }
    }

    /// Contact `c`'s group, once joined (see [`SmallGroups::join`]): the root of its dynamic
    /// end, the group's lowest index.
    fn group_of(parent: &mut [u32], c: &RestingContact) -> usize {
        union_root(
            parent,
            if c.inverse_mass_a != 0.0 { c.a } else { c.b } as usize,
        )
    }
}

/// A group's count of resting contacts, and whether any of them closes or pushes (see
/// [`SmallGroups`]).
#[derive(Clone, Copy, Debug, Default)]
struct GroupTally {
    count: u32,
    closing: bool,
    pushing: bool,
}

/// Places `items` in `placed` grouped by `bucket` (each below `buckets`), keeping their order
/// within a bucket (a counting sort), and leaves in `starts` where each bucket's items start
/// (`buckets + 1` places, the last the count of all).
fn place_by_bucket<T: Copy>(
    items: &[T],
    bucket: impl Fn(&T) -> usize,
    buckets: usize,
    starts: &mut Vec<u32>,
    placed: &mut Vec<T>,
) {
    starts.clear();
    starts.resize(buckets + 1, 0);
    for item in items {
        starts[bucket(item) + 1] += 1;
    }
    let mut sum = 0;
    for start in starts.iter_mut() {
        sum += *start;
        *start = sum;
    }
    // Placed from the last back, each at the end of its bucket's range, which leaves
    // `starts[b + 1]` at the start of bucket `b`'s: shifted down by one after.
    placed.clear();
    placed.extend_from_slice(items);
    for &item in items.iter().rev() {
        let end = &mut starts[bucket(&item) + 1];
        *end -= 1;
        placed[*end as usize] = item;
    }
    starts.rotate_left(1);
    starts[buckets] = sum;
}

/// The root of `i` in a union–find forest (`parent[r] == r` at a root), halving the path on
/// the way.
fn union_root(parent: &mut [u32], mut i: usize) -> usize {
    while parent[i] as usize != i {
        parent[i] = parent[parent[i] as usize];
        i = parent[i] as usize;
    }
    i
}

/// Joins the trees of `i` and `j` in a union–find forest, under the smaller root (so each
/// root is its tree's smallest index).
fn union_join(parent: &mut [u32], i: usize, j: usize) {
    let (x, y) = (union_root(parent, i), union_root(parent, j));
    parent[x.max(y)] = x.min(y) as u32;
}

/// Scratch for [`sort_into_components`], kept so that grouping allocates nothing.
#[derive(Debug, Default)]
struct Components {
    label: Vec<usize>,
    /// Union–find over the events: each event's parent (see [`union_root`]).
    parent: Vec<u32>,
    /// Each event's two bodies, as (body, event), sorted so that events sharing a body meet.
    ends: Vec<(u32, usize)>,
    /// Each component root's smallest event.
    first: Vec<usize>,
    keyed: Vec<(usize, usize)>,
    sorted: Vec<Event>,
}

/// Orders `events` so that events connected by shared bodies are contiguous, and fills `ranges`
/// with each connected group's range (events keep their time-then-id order within a group).
/// Only bodies that `moves` can join events: a fixed body's velocity never changes, so impacts
/// that share only fixed bodies (a shell of spheres landing on one fixed sphere at one instant)
/// are independent.
fn sort_into_components(
    events: &mut [Event],
    ranges: &mut Vec<std::ops::Range<usize>>,
    scratch: &mut Components,
    moves: impl Fn(u32) -> bool,
) {
    ranges.clear();
    let n = events.len();
    if n <= 1 {
        ranges.push(0..n);
        return;
    }
    // Label each event with the smallest index it is connected to (through shared bodies):
    // union–find over the events, joining those that share a body, in O(n log n). Groups are
    // usually small, but a sheet of spheres landing flat at one instant makes tens of
    // thousands of events at once.
    let parent = &mut scratch.parent;
    parent.clear();
    parent.extend(0..n as u32);
    let ends = &mut scratch.ends;
    ends.clear();
    ends.extend(
        events
            .iter()
            .enumerate()
            .flat_map(|(i, e)| [(e.a, i), (e.b, i)])
            .filter(|&(k, _)| moves(k)),
    );
    ends.sort_unstable();
    for pair in ends.windows(2) {
        if pair[0].0 == pair[1].0 {
            union_join(parent, pair[0].1, pair[1].1);
        }
    }
    let first = &mut scratch.first;
    first.clear();
    first.resize(n, usize::MAX);
    let label = &mut scratch.label;
    label.clear();
    for i in 0..n {
        let r = union_root(parent, i);
        // Events are visited in order: the first to reach a root is its smallest.
        if first[r] == usize::MAX {
            first[r] = i;
        }
        label.push(first[r]);
    }
    let keyed = &mut scratch.keyed;
    keyed.clear();
    keyed.extend(label.iter().copied().zip(0..n));
    keyed.sort_unstable();
    scratch.sorted.clear();
    scratch.sorted.extend(keyed.iter().map(|&(_, i)| events[i]));
    events.copy_from_slice(&scratch.sorted);
    let mut start = 0;
    for i in 1..=n {
        if i == n || keyed[i].0 != keyed[start].0 {
            ranges.push(start..i);
            start = i;
        }
    }
}

/// A touching pair approaching slowly, solved with the others at the start of the step.
#[derive(Clone, Copy, Debug)]
struct RestingContact {
    a: u32,
    b: u32,
    normal: DVec3,
    impulse: f64,
    /// The bodies' inverse masses (kept here: the solve sweeps over the contacts many times).
    inverse_mass_a: f64,
    inverse_mass_b: f64,
    /// `1 / (inverse_mass_a + inverse_mass_b)`, the pair's effective mass along
    /// the normal (a division kept off the sweeps' chain of dependent updates).
    mass: f64,
    /// The separating speed to reach: enough to undo, over the step, an overlap deeper than
    /// the creep allowance (0 for the usual contact, within it).
    bias: f64,
    /// The acceleration pressing the pair (see `Solver::start_press`).
    press: f64,
    /// Apart at the start of the step (see [`Solver::add_guards`]): not a collision.
    speculative: bool,
    /// The impulse before the current sweep, and the solve's search direction (see
    /// `Solver::solve_resting`).
    before: f64,
    direction: f64,
}

/// Whether segment `k` of `segments` is a dynamic body's (fixed ones join nothing).
fn moving(segments: &[Segment]) -> impl Fn(u32) -> bool + Copy + '_ {
    |k| !segments[k as usize].is_fixed()
}

/// How many bodies ahead the write-back asks for a body's segment.
const WRITE_BACK_AHEAD: usize = 16;

/// The most fallbacks in one step (see [`Solver::fall_back`]): each takes the crowds that
/// spent their share of the collision budget and leaves the rest to the event loop, with what
/// is left of their shares; the last takes every dynamic body.
const MAX_FALLBACKS: u32 = 4;

/// The most rounds of [`Solver::fall_back`]'s solve (each adds the pairs the last brought
/// together; a pit of 1000 or 10 000 landing needs two or three, with [`FALLBACK_MARGIN`],
/// and 8 and 18 on average without). Pairs the last round
/// would still add are counted as deferred.
const FALLBACK_ROUNDS: usize = 32;

/// How much farther apart than the rest of the step's drifts bring them (as a fraction of
/// their reach) [`Solver::fall_back`]'s first round takes pairs in: each round's velocity
/// changes bring more pairs together, and the pairs a round adds cost every body a query and
/// every contact more sweeps, while a pair taken early that stays apart costs one contact in
/// the sweeps (its impulse stays 0). A tenth cut the 10k landing pit's rounds from 18 to 3
/// per fallback and its step from 42 to 29-32 µs a sphere (1k: 8 rounds to 2.5), the same
/// deepest overlap.
const FALLBACK_MARGIN: f64 = 0.1;

/// The most sweeps [`Solver::fall_back`] adds after its rounds while a pair still closes past
/// its allowance (a long chain: a line of 100 spheres struck at 1 km/s was left 2 cm into
/// itself by the rounds' sweeps), and as many again in each round of its deep pushes (see
/// `Solver::push_on`).
const FALLBACK_FINISH_SWEEPS: u32 = 1024;

/// How much smaller a batch of the fallback's finishing sweeps must leave what its contacts
/// close past their allowance, than the batch before or the least yet, to count as progress
/// (see `Solver::finish_sweeps`: four batches without it end the sweeps). Contacts that
/// cannot all be met (a sphere held between fixed ones deeper into it than it may part in a
/// step) leave the sum creeping down by less than a thousandth a batch, or swinging between
/// two values, for all 1024 sweeps, in each of the deep pushes' rounds: 60 balls in a pit, a
/// fixed sphere of radius 1e4 put over them (its centre just above the pit), fell back at
/// every step and took 12.6 to 13.4 ms a step, 8.9 to 10.2 ms since (the criterion bench
/// `held/60`, three runs of each in turns). (Until the sixty-second session any decrease
/// counted.)
const FINISH_PROGRESS: f64 = 1e-3;

/// The most passes of the fallback (each its rounds, then its finishing sweeps and exact
/// solves; a pass after the first only if the one before changed velocities and brought a new
/// pair together: see `Solver::fall_back`).
const FALLBACK_PASSES: u32 = 4;

/// The most Gauss–Seidel sweeps over the resting contacts in one step.
const RESTING_SWEEPS: u32 = 64;

/// How many times heavier a dynamic body must be than one resting against it for the lighter
/// one's contacts to be solved together in the resting sweeps (see `Solver::find_blocks`).
const BLOCK_RATIO: f64 = 10.0;

/// The most sweeps with blocks after the plain ones (see `Solver::sweep_resting`). A pit of 400
/// dropped from 4 m, densities log-uniform from 1 to 10 000, its deepest overlap over the last
/// 6 of 12 s, four seeds: with 64, 0.9 to 17.8 mm; 32, 0.9 to 2.5 mm; 16, 0.5 to 4.1 mm. From 1
/// to 100: 64 took 1.2 to 1.4 times as long as 32, for the same overlaps (0.5 mm).
const BLOCK_SWEEPS: u32 = 32;

/// The most of an overlap a resting contact's push undoes in one step, as a fraction of the
/// smaller radius (see `Solver::correction`).
const MAX_CORRECTION: f64 = 0.1;

/// The deepest a touching pair may end the step, past its contact band, and still be left to
/// creep (as a fraction of the smaller radius; see `Solver::test_pair_fully`). The creep speed
/// grows with a contact's load, and the loads of a jammed ring of contacts (a bed's bottom
/// layer wedged between two walls) grew step after step: at 6000 m/s², 1.5 m/s of creep let a
/// pair sink 6% of a radius into each other in a step.
const CREEP_DEPTH: f64 = 0.01;

/// The most load a contact's warm start carries into the next step, in multiples of the
/// step's largest acceleration (see `Solver::keep_resting_loads`); the step's sweeps find any
/// more it needs. A jammed ring of contacts (a bed's bottom layer wedged between two walls, a
/// column zig-zagging up a chimney) has overlaps no velocities can undo: the sweeps' pushes
/// against them cancel round the ring, and carried on whole, its loads grew without bound
/// (to 5800 m/s² in 1.6 s in `regression_creep_under_jammed_loads.rs`'s pit).
const WARM_LOADS: f64 = 64.0;

/// How many times [`Solver::solve_pushes`] solves the resting contacts' pushes at most, each
/// time with the pushes on a body pushed too fast scaled down by as much (a lone body's speed
/// is linear in its pushes while the same contacts hold: it is at its cap after one).
const PUSH_ROUNDS: u32 = 4;

/// The most sweeps of each of [`Solver::fall_back`]'s rounds after the first, which start
/// from the impulses the rounds before found (a landing pit of 10 000: 48 µs a sphere a step
/// instead of 62 with 64 sweeps, the same deepest overlap, 0.76 mm).
const FALLBACK_LATER_SWEEPS: u32 = 16;

/// What the solver needs to know besides the bodies.
pub(crate) struct StepContext<'a> {
    pub settings: &'a Settings,
    /// A custom integrator, or `None` for the settings' (called directly, not through a
    /// vtable: it runs once per body per step).
    pub integrator: Option<&'a dyn Integrator>,
    /// A custom time-of-impact method, or `None` for the settings' (called directly: it runs
    /// for every pair tested).
    pub toi: Option<&'a dyn TimeOfImpact>,
    pub dt: f64,
    pub start_time: f64,
    /// Whether any body may be asleep (see `Settings::sleep`): when not, the step reads no
    /// body's sleeping state.
    pub sleeping: bool,
    /// How many dynamic bodies (all asleep) the step leaves out, and the largest component
    /// of any acceleration among them (see `dormant.rs`): the step's scales and its collision
    /// budget count them as a step of every body would.
    pub left_out: (u32, f64),
}

/// Times a step's phases one after the other, when asked to (a clock read per phase).
struct Laps(Option<std::time::Instant>);

impl Laps {
    fn start(on: bool) -> Self {
        Laps(on.then(std::time::Instant::now))
    }

    /// Adds the time since the last lap to `phase`.
    #[inline]
    fn lap(&mut self, phase: &mut std::time::Duration) {
        if let Some(last) = &mut self.0 {
            let now = std::time::Instant::now();
            *phase += now - *last;
            *last = now;
        }
    }
}

impl Solver {
    /// Advances `bodies` (all live, in id order) by `ctx.dt`, filling the collision counters,
    /// energies and momentum of `stats`, and `self.collisions`. If a body's drift would leave
    /// the finite range within the step (an absurd time step or speed, from the start or after
    /// an impulse), returns its index before changing any body.
    pub fn step(
        &mut self,
        bodies: &mut [Body],
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) -> Result<(), usize> {
        let mut laps = Laps::start(self.profiling);
        let dynamic = self.integrate(bodies, ctx)?;
        // The broad phase and the boxes are out of the solver while the first pass walks them
        // (each pair it finds is tested by the solver).
        let (mut broad, mut boxes) = (
            std::mem::take(&mut self.broad),
            std::mem::take(&mut self.boxes),
        );
        laps.lap(&mut self.profile.integrate);
        self.sort_spatially(&mut broad, &mut boxes, ctx);
        laps.lap(&mut self.profile.sort);
        broad.build(&boxes);
        laps.lap(&mut self.profile.build);
        self.first_pass(&mut broad, &boxes, ctx, stats);
        (self.broad, self.boxes) = (broad, boxes);
        laps.lap(&mut self.profile.first_pass);
        self.start_stamps();
        if !self.resting.is_empty() {
            self.add_guards(ctx);
            self.solve_resting(ctx, stats);
            self.caching = !self.strings && ctx.toi.is_none();
            if !self.requery_in_one_pass(ctx, stats) {
                self.requery_touched(0.0, ctx, stats);
            }
        } else {
            self.keep_warm_before();
            self.warm.clear();
            self.keep_rested_before();
            self.rested.clear();
        }
        laps.lap(&mut self.profile.resting);
        self.run_events(dynamic, ctx, stats);
        laps.lap(&mut self.profile.events);
        if let Some(k) = self.unbounded {
            return Err(self.order[k] as usize);
        }
        self.write_back(bodies, ctx, stats);
        laps.lap(&mut self.profile.write_back);
        self.find_max_overlap(bodies, ctx, stats);
        laps.lap(&mut self.profile.overlap);
        Ok(())
    }

    /// Starts the step: each body's kick before its drift, its segment (bent along its string
    /// if it hangs on one), swept box and [`Extra`], and the step's scales from the largest
    /// acceleration. Returns how many bodies are dynamic, or the index of a body whose drift
    /// would leave the finite range.
    fn integrate(&mut self, bodies: &[Body], ctx: &StepContext<'_>) -> Result<u32, usize> {
        let dt = ctx.dt;
        let settings = ctx.settings;
        self.tested.clear();
        self.settled.clear();
        self.settled_time = f64::NAN;
        self.unbounded = None;
        self.queue_until = f64::INFINITY;
        // Four events a bucket, expecting one per body or as many as the last step pushed,
        // whichever is more (a ball pit's landing crowd pushes dozens per body).
        let expected = bodies.len().max(self.queue.pushed());
        self.queue.reset(dt, expected, 4);
        self.segments.clear();
        self.extras.clear();
        self.kicks_after.clear();
        self.strung.clear();
        self.boxes.clear();
        let mut dynamic = 0u32;
        // Whether anything accelerates: the largest component of any acceleration (no square
        // root per body; and a tiny acceleration whose length would underflow still counts),
        // those of the bodies left out of the step among them.
        let mut largest_acceleration = ctx.left_out.1;
        self.strings = false;
        self.any_asleep = false;
        self.largest_kick_after = 0.0;
        let mut overflow = None;
        for (index, body) in bodies.iter().enumerate() {
            // An asleep body given a speed in an earlier substep moves as an awake one until
            // the step's end wakes it.
            let asleep = ctx.sleeping && body.asleep && body.velocity() == DVec3::ZERO;
            let (acceleration, kicks) = if body.is_fixed() {
                (DVec3::ZERO, Default::default())
            } else if asleep {
                // Asleep: at rest, and nothing acts on it until something wakes it (see
                // `Settings::sleep`); it still has its mass in every impact. What would act on
                // it still sets the step's scales, as if it were awake: with nothing
                // accelerating, overlaps are moved apart at the step's end, and asleep spheres
                // press into one another as they settled.
                dynamic += 1;
                self.any_asleep = true;
                let a = body.acceleration(settings.gravity);
                largest_acceleration = largest_acceleration.max(a.abs().max_element());
                (DVec3::ZERO, Default::default())
            } else {
                dynamic += 1;
                let a = body.acceleration(settings.gravity);
                largest_acceleration = largest_acceleration.max(a.abs().max_element());
                let k = match ctx.integrator {
                    Some(custom) => custom.kicks(body.velocity(), a, dt),
                    None => settings.integrator.kicks(body.velocity(), a, dt),
                };
                (a, (k.before, k.after))
            };
            let mut velocity = body.velocity() + kicks.0;
            if let Some(tether) = body.tether() {
                let free_velocity = velocity;
                let distance = (body.position() - tether.anchor).length();
                let slack = !at_length(distance, tether);
                let (taut, sag, until);
                (velocity, taut, sag, until) = bend(
                    body.position(),
                    velocity,
                    tether,
                    slack,
                    body.radius(),
                    0.0,
                    dt,
                );
                self.strung.push(Strung {
                    body: index as u32,
                    tether,
                    taut,
                    free_velocity,
                    sag,
                    until,
                    slack,
                });
            }
            let segment = Segment {
                t0: 0.0,
                position: body.position(),
                velocity,
                signed_radius: if body.is_fixed() {
                    -body.radius()
                } else {
                    body.radius()
                },
            };
            if !(segment.position_at(dt).is_finite() && (velocity + kicks.1).is_finite()) {
                overflow = overflow.or(Some(index));
            }
            self.boxes.push(swept_box(&segment, dt, settings));
            self.segments.push(segment);
            // Compared bit for bit: a kick of -0.0 must be added as one (it keeps a velocity
            // of -0.0 negative).
            let zero = kicks.1.to_array().map(f64::to_bits) == [0; 3];
            if !zero || !self.kicks_after.is_empty() {
                // The first kick after that is not zero: the zeros before it written now.
                self.kicks_after.resize(index, DVec3::ZERO);
                self.kicks_after.push(kicks.1);
            }
            self.largest_kick_after = self.largest_kick_after.max(kicks.1.abs().max_element());
            self.extras.push(Extra {
                inverse_mass: body.inverse_mass(),
                acceleration,
                restitution: body.restitution(),
                id: body.id(),
                asleep,
            });
        }
        self.strings = !self.strung.is_empty();

        if let Some(index) = overflow {
            return Err(index);
        }
        self.nothing_accelerates = largest_acceleration == 0.0;
        self.resting_scale = if largest_acceleration > 0.0 {
            settings.resting_factor * dt
        } else {
            0.0
        };
        self.creep_scale = settings.creep_fraction * self.resting_scale;
        self.near_reach = self.resting_scale * 3f64.sqrt() * largest_acceleration * dt;
        self.resting_speed = self.resting_scale * largest_acceleration;
        self.warm_cap = if largest_acceleration > 0.0 {
            WARM_LOADS * largest_acceleration
        } else {
            f64::INFINITY
        };
        self.apart = Apart::new(settings.tolerance.epsilon());
        Ok(dynamic + ctx.left_out.0)
    }

    /// Puts the segments (and `boxes`) in `broad`'s spatial order, where neighbours in space
    /// are neighbours in memory, and readies the per-segment marks for that order.
    fn sort_spatially(
        &mut self,
        broad: &mut BroadPhase,
        boxes: &mut Vec<Aabb>,
        ctx: &StepContext<'_>,
    ) {
        let (dt, settings) = (ctx.dt, ctx.settings);
        // Work in the broad phase's spatial order: neighbours in space are neighbours in memory.
        self.order.clear();
        match broad.sort(boxes) {
            Some(permutation) => {
                self.order.extend_from_slice(permutation);
                self.scratch_segments.clear();
                self.scratch_segments
                    .extend(self.order.iter().map(|&i| self.segments[i as usize]));
                std::mem::swap(&mut self.segments, &mut self.scratch_segments);
                // The boxes worked out again from the segments just gathered (the same
                // numbers): cheaper than a second gather from memory at 100k spheres.
                self.scratch_boxes.clear();
                self.scratch_boxes.extend(
                    self.segments
                        .iter()
                        .map(|segment| swept_box(segment, dt, settings)),
                );
                std::mem::swap(boxes, &mut self.scratch_boxes);
            }
            None => self.order.extend(0..self.segments.len() as u32),
        }
        self.position_of.clear();
        self.position_of.resize(self.order.len(), 0);
        for (p, &i) in self.order.iter().enumerate() {
            self.position_of[i as usize] = p as u32;
        }
        let words = self.segments.len().div_ceil(64);
        self.strung_bits.clear();
        self.strung_bits.resize(words, 0);
        for s in &self.strung {
            let p = self.position_of[s.body as usize] as usize;
            self.strung_bits[p / 64] |= 1 << (p % 64);
        }
        self.rested_here.clear();
        self.rested_here.resize(words, 0);
        self.loaded.clear();
        self.loaded.resize(words, 0);
        self.pushes.clear();
        self.pushed_bits.clear();
        self.pushed_bits.resize(words, 0);
        self.spent_bits.clear();
        self.spent_bits.resize(words, 0);
        if self.spent.len() < self.segments.len() {
            self.spent.resize(self.segments.len(), 0.0);
        }
        if self.rested.len() == words && self.resting_scale > 0.0 {
            for (w, &word) in self.rested.iter().enumerate() {
                let mut word = word;
                while word != 0 {
                    let i = w * 64 + word.trailing_zeros() as usize;
                    word &= word - 1;
                    let grow = self.resting_scale * dt * self.extras[i].acceleration.length();
                    let p = self.position_of[i] as usize;
                    self.rested_here[p / 64] |= 1 << (p % 64);
                    let b = &mut boxes[p];
                    b.lo -= DVec3::splat(grow);
                    b.hi += DVec3::splat(grow);
                }
            }
        }
    }

    /// The first pass: every pair whose boxes meet in `broad` is a resting contact or gets its
    /// time of impact queued (after each segment's version is set to 0 and each string's first
    /// bend queued).
    fn first_pass(
        &mut self,
        broad: &mut BroadPhase,
        boxes: &[Aabb],
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) {
        let (dt, settings) = (ctx.dt, ctx.settings);
        self.versions.clear();
        self.versions.resize(self.segments.len(), 0);
        for s in 0..self.strung.len() {
            let (body, until) = (self.strung[s].body, self.strung[s].until);
            self.queue_bend(self.position_of[body as usize] as usize, until, dt);
        }
        // Touching pairs that approach no faster than the resting speed are resting contacts,
        // solved together below; every other pair gets its time of impact.
        self.resting.clear();
        self.near.clear();
        self.loads.clear();
        // A pair the first pass keeps: a resting contact, or its time of impact.
        let mut first_pass_pair = |solver: &mut Self, i: usize, j: usize| {
            if solver.any_asleep && solver.asleep_beside_still(i, j) {
                // Neither moves nor presses the other (nor is moved apart, if they settled
                // pressed together); counted for the deepest overlap.
                solver.tested.push((i as u32, j as u32));
                return;
            }
            let rests = if solver.may_rest(i, j, ctx) {
                solver.resting_contact(i, j, ctx)
            } else {
                // The glance must not miss a resting pair (checked in debug builds).
                debug_assert!(!solver.resting_contact(i, j, ctx), "resting pair missed");
                false
            };
            if !rests {
                solver.test_pair(i, j, 0.0, ctx, stats);
            }
        };
        // Most pairs need nothing: apart, not near enough to rest, and dismissed at a glance.
        // A filter finds those first, four at a time and without a branch on any (see
        // `first_pass_kept`); the rest are kept, one by one. Not with a custom time-of-impact
        // method: then every pair goes to the full test, as `test_pair` says (a custom method is
        // asked about every pair that closes); nor for a pair with a sphere on a string (a
        // string bends drifts the glance knows nothing of), kept after the filter.
        let filter = ctx.toi.is_none();
        let pass = FirstPass {
            dt,
            near_reach: (self.resting_scale != 0.0).then_some(self.near_reach),
            epsilon: settings.tolerance.epsilon(),
            apart: self.apart,
        };
        let mut test_batch = |solver: &mut Self, batch: &[(u32, u32)]| {
            for batch in batch.chunks(64) {
                let mut kept = if filter {
                    first_pass_kept(&solver.segments, batch, &pass)
                } else {
                    u64::MAX >> (64 - batch.len())
                };
                // Debug builds check each outcome against the filter one pair at a time, and
                // each pair skipped against what the first pass would have made of it.
                #[cfg(debug_assertions)]
                for (at, &(i, j)) in batch.iter().enumerate().filter(|_| filter) {
                    let (i, j) = (i as usize, j as usize);
                    let (si, sj) = (&solver.segments[i], &solver.segments[j]);
                    let skips = pass.skips(si, sj);
                    assert_eq!(
                        kept >> at & 1 == 0,
                        skips,
                        "the first pass's filter, ({i}, {j})"
                    );
                    if skips {
                        let dismissed = Glance::of(si, sj, 0.0, dt).dismisses(solver.apart);
                        assert!(
                            !solver.may_rest(i, j, ctx) && dismissed,
                            "pair ({i}, {j}) skipped, but it may rest or is not dismissed"
                        );
                    }
                }
                if filter && solver.strings {
                    for (at, &(i, j)) in batch.iter().enumerate() {
                        if solver.bent_pair(i as usize, j as usize) {
                            kept |= 1 << at;
                        }
                    }
                }
                while kept != 0 {
                    let at = kept.trailing_zeros() as usize;
                    kept &= kept - 1;
                    let (i, j) = batch[at];
                    first_pass_pair(solver, i as usize, j as usize);
                }
            }
        };
        // Pairs are tested in batches: a batch's second bodies' segments are asked for when it
        // comes, and read when the next has come (rows of cells lie far apart in memory).
        let (mut pairs, mut asked) = (
            std::mem::take(&mut self.pairs),
            std::mem::take(&mut self.asked_pairs),
        );
        pairs.clear();
        asked.clear();
        // Room for the most a scan may hold (once: a step then never grows them).
        let room = BroadPhase::pairs_room(boxes.len(), PAIR_BATCH);
        pairs.reserve(room);
        asked.reserve(room);
        broad.pairs_batched(boxes, &mut pairs, PAIR_BATCH, |batch| {
            for &(_, j) in batch.iter() {
                prefetch(&self.segments[j as usize]);
            }
            test_batch(self, &asked);
            asked.clear();
            std::mem::swap(batch, &mut asked);
        });
        test_batch(self, &asked);
        test_batch(self, &pairs);
        (self.pairs, self.asked_pairs) = (pairs, asked);
    }

    /// The event loop: the queued impacts taken in time order and solved, each changed body's
    /// pairs tested again, until the queue is empty; within the collision budget of
    /// `max_collisions_per_body` for each of the `dynamic` bodies, past which the rest of the
    /// step is solved at once for the crowds that spent it (see `Solver::fall_back`), and the
    /// other bodies go on with what is left of their shares.
    fn run_events(&mut self, dynamic: u32, ctx: &StepContext<'_>, stats: &mut StepStats) {
        let (dt, settings) = (ctx.dt, ctx.settings);
        self.instant.start(f64::NEG_INFINITY, self.segments.len());
        let mut budget = settings
            .max_collisions_per_body
            .saturating_mul(dynamic.max(1));
        let mut events = 0u32;
        let mut fallbacks = 0u32;
        self.clear_fallen();
        // One body's share: a sphere caught between fixed ones (wedged between two it
        // overlaps, or pressed by a kinematic one) bounces between them without end, and
        // would otherwise spend the whole budget, leaving every other sphere's collisions to
        // the next step. A body's version counts the changes to its drift: its collisions.
        let share = settings
            .max_collisions_per_body
            .saturating_mul(if self.strings {
                (dynamic / 4).clamp(BODY_SHARE_STRUNG, BODY_SHARE)
            } else {
                BODY_SHARE
            });
        // Events closer in time than this are one simultaneous group.
        let simultaneity = settings.tolerance.epsilon() * dt;
        loop {
            // The instant of the dirty segments ends: their pairs are tested in full now,
            // before any later impact is taken (the gathering below stops short of later
            // impacts while any body is dirty). When the budget has run out, a fallback
            // takes the crowds' pairs from here (their boxes must be in place for it) and
            // tests the other dirty bodies' pairs in full, or, if the last has run already,
            // the rest is deferred: their impacts are not sought again. (It must start
            // here, not at the next impact taken: there may be none queued, and the dirty
            // bodies' later impacts were never sought. A pit of 23 landing ended a step
            // with two spheres 7% of a radius into each other, unseen.)
            if !self.dirty.is_empty() {
                if events >= budget {
                    if fallbacks < MAX_FALLBACKS {
                        fallbacks += 1;
                        let t = self.stamp_time;
                        let left = self.fall_back(t, fallbacks == MAX_FALLBACKS, ctx, stats);
                        budget = events.saturating_add(left);
                    } else {
                        self.drop_dirty();
                    }
                } else if self
                    .queue
                    .peek()
                    .is_none_or(|next| next.time != self.stamp_time)
                {
                    self.flush_dirty(ctx, stats);
                }
            }
            let Some(event) = self.queue.pop() else {
                break;
            };
            if self.unbounded.is_some() {
                break;
            }
            if !self.is_current(&event) {
                continue;
            }
            if event.a == event.b {
                self.bend_again(event.a as usize, event.time, ctx, stats);
                continue;
            }
            if events >= budget && fallbacks < MAX_FALLBACKS {
                fallbacks += 1;
                let left = self.fall_back(event.time, fallbacks == MAX_FALLBACKS, ctx, stats);
                budget = events.saturating_add(left);
                // The impacts still queued between bodies the fallback took (or of a body on
                // a string) are counted as deferred below; those it changed are stale now.
                if !self.is_current(&event) {
                    continue;
                }
            }
            if events >= budget || (fallbacks > 0 && self.has_fallen(&event)) {
                stats.collisions_deferred = stats.collisions_deferred.saturating_add(1);
                continue;
            }
            self.group.clear();
            self.group.push(event);
            while let Some(next) = self.queue.peek() {
                if next.time > event.time + simultaneity
                    || (next.time != event.time && !self.dirty.is_empty())
                    || next.a == next.b
                {
                    break;
                }
                self.queue.pop();
                if !self.is_current(&next) {
                    continue;
                }
                if fallbacks > 0 && self.has_fallen(&next) {
                    stats.collisions_deferred = stats.collisions_deferred.saturating_add(1);
                } else {
                    self.group.push(next);
                }
            }
            self.clear_touched();
            if event.time != self.settled_time {
                self.settled.clear();
                self.settled_time = event.time;
            }
            if event.time > self.instant.time() + simultaneity {
                self.instant.start(event.time, self.segments.len());
            }
            let mut group = std::mem::take(&mut self.group);
            let mut ranges = std::mem::take(&mut self.ranges);
            let segments = &self.segments;
            sort_into_components(&mut group, &mut ranges, &mut self.components, |k| {
                !segments[k as usize].is_fixed()
            });
            let mut joined_any = false;
            for range in ranges.iter().cloned() {
                let component = &group[range];
                if joined_any && component.iter().any(|e| !self.is_current(e)) {
                    // A join above reached one of these bodies: its pairs are tested again
                    // from now (it is touched). The impacts still current stay queued.
                    for e in component {
                        if self.is_current(e) {
                            self.queue.push(*e);
                        }
                    }
                    continue;
                }
                let versions = &self.versions;
                let over_share = component
                    .iter()
                    .any(|e| versions[e.a as usize] >= share || versions[e.b as usize] >= share);
                // A few squeezes a body (each changes its drift once): a body that cannot be
                // kept out of both sides (a kinematic sphere pressing it against a fixed one)
                // would take them without end, and the world's budget with them.
                let squeezable = over_share
                    && component.iter().any(|e| {
                        [e.a, e.b].iter().any(|&k| {
                            (share..share.saturating_add(SQUEEZES)).contains(&versions[k as usize])
                        })
                    });
                // Not after a fallback: a squeeze ends every push, the fallback's on the
                // bodies it took among them, and its cluster may reach those bodies.
                // An inelastic collapse at this instant (see `COLLAPSE_BOUNCES`) is ended by
                // a squeeze too, as the bounces would end in the limit; not on a body past its
                // share (its impacts are deferred unless squeezed as above, and a collapse's
                // squeeze may find the collapse not over).
                let collapsing = !over_share
                    && self.instant.most_bounces() >= COLLAPSE_BOUNCES
                    && self.ends_collapse(component);
                let squeeze = (squeezable || collapsing)
                    && events < budget
                    && !self.strings
                    && fallbacks == 0;
                if events >= budget || (over_share && !squeeze) {
                    stats.collisions_deferred = stats
                        .collisions_deferred
                        .saturating_add(component.len() as u32);
                    // Not queued again at this instant while neither body changes (a dirty
                    // body's query in full would find them again, and count them twice).
                    for e in component {
                        self.settled
                            .push(Settled::now(&self.versions, e.a as usize, e.b as usize));
                    }
                    continue;
                }
                if !self.pushes.is_empty()
                    && (squeeze
                        || component.iter().any(|e| {
                            bit(&self.pushed_bits, e.a as usize)
                                || bit(&self.pushed_bits, e.b as usize)
                        }))
                {
                    // A pushed body meets another: the pushes end here (all of them, so
                    // momentum stays kept), and the pushed bodies' impacts are sought again
                    // on their velocities without them (a push's speed is not the body's).
                    // So too before a squeeze, whose cluster may reach pushed bodies.
                    self.end_pushes(event.time, ctx);
                    for e in component {
                        if self.is_current(e) {
                            self.queue.push(*e);
                        }
                    }
                    joined_any = true;
                    continue;
                }
                if squeeze {
                    // (A collapse is never `squeezable`: that asks for a body past its share.)
                    let along = collapsing.then(|| {
                        let e = &component[0];
                        let (a, b) = (&self.segments[e.a as usize], &self.segments[e.b as usize]);
                        let line = (b.position_at(event.time) - a.position_at(event.time))
                            .normalize_or_zero();
                        (line, COLLAPSE_SPEED * self.instant.fastest())
                    });
                    if self.squeeze(component, event.time, along, ctx, stats) {
                        if collapsing {
                            for e in component {
                                self.count_bounce(e.a as usize, e.b as usize, 0.0);
                            }
                        }
                        events = events.saturating_add(self.joined.len() as u32);
                        joined_any = true;
                        continue;
                    }
                }
                events = events.saturating_add(component.len() as u32);
                if self.join_instant(component, event.time) {
                    let joined = std::mem::take(&mut self.joined);
                    events = events.saturating_add((joined.len() - component.len()) as u32);
                    self.resolve_group(&joined, event.time, ctx, stats);
                    self.joined = joined;
                    joined_any = true;
                    continue;
                }
                match component {
                    [single] => self.resolve_event(single, ctx, stats),
                    _ => self.resolve_group(component, event.time, ctx, stats),
                }
                for e in component.iter() {
                    self.touch(e.a);
                    self.touch(e.b);
                }
            }
            self.group = group;
            self.ranges = ranges;
            // Ask for the next event's bodies now: events come in time order, so their bodies
            // lie anywhere in memory, and their loads overlap this event's re-queries.
            if let Some(next) = self.queue.peek() {
                self.prefetch_event(&next);
            }
            self.caching = !self.strings && ctx.toi.is_none() && !self.instant.is_empty();
            self.requery_touched(event.time, ctx, stats);
        }
    }

    /// Writes each body's position and velocity at the step's end, and the step's energies
    /// and momentum into `stats`.
    fn write_back(&mut self, bodies: &mut [Body], ctx: &StepContext<'_>, stats: &mut StepStats) {
        let (dt, settings) = (ctx.dt, ctx.settings);
        // Write back in body order (bodies and extras read in order, segments gathered),
        // summing the energies and momentum while each body is at hand.
        let (mut kinetic, mut potential, mut momentum) = (0.0, 0.0, DVec3::ZERO);
        let mut strung = self.strung.iter().peekable();
        let kicks_after = !self.kicks_after.is_empty();
        for (index, (body, &p)) in bodies.iter_mut().zip(&self.position_of).enumerate() {
            // The segments are gathered in spatial order: ask for one a little ahead, so the
            // reads overlap instead of each waiting for memory in turn.
            if let Some(&ahead) = self.position_of.get(index + WRITE_BACK_AHEAD) {
                prefetch(&self.segments[ahead as usize]);
            }
            let segment = &self.segments[p as usize];
            let mut position = segment.position_at(dt);
            let kick_after = if kicks_after {
                self.kicks_after[index]
            } else {
                DVec3::ZERO
            };
            let mut velocity = segment.velocity + kick_after;
            if let Some(string) = strung.next_if(|s| s.body as usize == index) {
                (position, velocity) = taut(position, velocity, string.tether);
            }
            body.desc.position = position;
            body.desc.velocity = velocity;
            if !body.is_fixed() {
                let mass = body.mass();
                kinetic += 0.5 * mass * velocity.length_squared();
                potential -= (mass * settings.gravity + body.force()).dot(position);
                momentum += mass * velocity;
            }
        }
        // The resting solve's pushes moved their bodies within the step; they leave no speed.
        for &(k, push) in &self.pushes {
            bodies[self.order[k as usize] as usize].desc.velocity -= push;
        }
        if !self.pushes.is_empty() {
            // Summed again, in the same order as `World::kinetic_energy` and `World::momentum`:
            // taken off as differences, the pushes would leave the sums exact only to the
            // rounding of what the pushed bodies had before (a body pushed out of a deep
            // overlap keeps next to none of its speed).
            kinetic = bodies.iter().map(Body::kinetic_energy).sum();
            momentum = bodies.iter().map(Body::momentum).sum();
        }
        stats.kinetic_energy = kinetic;
        stats.potential_energy = potential;
        stats.momentum = momentum;
    }

    /// Puts the deepest overlap left at the step's end in `stats`, moving overlapping pairs
    /// apart first where nothing else will (see `Solver::separate`).
    fn find_max_overlap(
        &mut self,
        bodies: &mut [Body],
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) {
        let dt = ctx.dt;
        // Two bodies overlapping now had overlapping boxes when either last changed, so they
        // were tested then, with the drifts they ended on, which ended them overlapping (give
        // or take rounding, allowed for generously): the tested pairs are enough to find the
        // largest overlap. Read in solver order, where neighbours in space are neighbours in memory.
        let mut max_overlap = self.deepest_tested(dt);
        // With nothing accelerating there is no resting solve to undo an overlap: the
        // separation moves such pairs apart instead (see `Solver::separate`); so too, under
        // an acceleration, for pairs with a sphere on a string pressed deeper than
        // [`STRUNG_OVERLAP`].
        if (self.nothing_accelerates || self.strings) && max_overlap > 0.0 {
            let moved = self.separate(bodies, ctx);
            if moved > 0 {
                stats.separated = stats.separated.saturating_add(moved);
                max_overlap = self.deepest_tested(dt);
                if !self.nothing_accelerates {
                    // Summed again where the bodies now are (in `write_back` before they were
                    // moved, until the sixty-first session). Nothing accelerating, it is 0
                    // wherever they are.
                    stats.potential_energy = bodies
                        .iter()
                        .filter(|b| !b.is_fixed())
                        .map(|b| crate::world::potential_of(b, ctx.settings))
                        .sum();
                }
            }
        }
        stats.max_overlap = max_overlap;
    }

    /// The deepest overlap at the step's end (`dt`) among the tested pairs, 0 if none.
    fn deepest_tested(&self, dt: f64) -> f64 {
        self.tested
            .iter()
            .map(|&(i, j)| {
                let (i, j) = (i as usize, j as usize);
                let reach = self.segments[i].radius() + self.segments[j].radius();
                reach - (self.final_position(j, dt) - self.final_position(i, dt)).length()
            })
            .fold(0.0, f64::max)
    }

    /// Hints that `event`'s bodies (their versions, drifts, boxes and extras) will be read.
    fn prefetch_event(&self, event: &Event) {
        for k in [event.a as usize, event.b as usize] {
            prefetch(&self.versions[k]);
            prefetch_lines(&self.segments[k]);
            prefetch(&self.boxes[k]);
            prefetch(&self.extras[self.order[k] as usize]);
            self.broad.prefetch(k);
        }
    }

    /// Segment `k`'s [`Extra`].
    /// Whether of segments `i` and `j` one is asleep and the other asleep too or fixed and
    /// still (see `Settings::sleep`).
    fn asleep_beside_still(&self, i: usize, j: usize) -> bool {
        let still = |k: usize| {
            let s = &self.segments[k];
            self.extra(k).asleep || (s.is_fixed() && s.velocity == DVec3::ZERO)
        };
        (self.extra(i).asleep || self.extra(j).asleep) && still(i) && still(j)
    }

    fn extra(&self, k: usize) -> &Extra {
        &self.extras[self.order[k] as usize]
    }

    /// Segment `k`'s position at the end of the step, `dt`, as the write-back gives its body
    /// (worked out again rather than stored: a random write per body at 100k spheres).
    fn final_position(&self, k: usize, dt: f64) -> DVec3 {
        let position = self.segments[k].position_at(dt);
        match self.strung(k) {
            // The position `taut` gives does not depend on the velocity.
            Some(string) => taut(position, DVec3::ZERO, string.tether).0,
            None => position,
        }
    }

    /// Gives segment `k` its velocity after an impulse at time `t`: bent along its string if it
    /// has one, its pending events made stale and its box regrown. Fixed segments never change,
    /// so their other pending events stay valid.
    fn set_velocity(&mut self, k: usize, velocity: DVec3, t: f64, ctx: &StepContext<'_>) {
        if self.segments[k].is_fixed() {
            return;
        }
        let string = self.string_of(k);
        let segment = &mut self.segments[k];
        segment.velocity = velocity;
        let mut until = ctx.dt;
        if let Some(s) = string {
            let strung = &mut self.strung[s];
            strung.free_velocity = velocity;
            (segment.velocity, strung.taut, strung.sag, strung.until) = bend(
                segment.position,
                velocity,
                strung.tether,
                strung.slack,
                segment.radius(),
                t,
                ctx.dt,
            );
            until = strung.until;
        }
        self.versions[k] += 1;
        self.boxes[k] = swept_box(segment, ctx.dt, ctx.settings);
        self.check_bounded(k);
        self.queue_bend(k, until, ctx.dt);
    }

    /// Records segment `k` as [`Solver::unbounded`] if its new drift leaves the finite range.
    #[inline]
    // `x - x` below is the point, not a slip.
    #[allow(clippy::eq_op)]
    fn check_bounded(&mut self, k: usize) {
        // The velocity it will end the step with: its kick after the drift comes on top (looked
        // up only when the sum could overflow, which needs one of them past half the range).
        let mut v = self.segments[k].velocity;
        if !(v.abs().max_element() < HALF_RANGE && self.largest_kick_after < HALF_RANGE)
            && let Some(kick) = self.kicks_after.get(self.order[k] as usize)
        {
            v += *kick;
        }
        let b = &self.boxes[k];
        // `x - x` is 0 for every finite `x` and NaN for an infinite or NaN one: one comparison
        // for all nine values, without a branch each.
        if (b.lo - b.lo) + (b.hi - b.hi) + (v - v) != DVec3::ZERO {
            self.unbounded.get_or_insert(k);
        }
    }

    fn is_current(&self, event: &Event) -> bool {
        self.versions[event.a as usize] == event.version_a
            && self.versions[event.b as usize] == event.version_b
    }

    /// Whether pair `(i, j)` has a sphere on a string, whose drift a string bends: such a pair
    /// is never dismissed at a glance (which takes both drifts as straight lines), and is kept
    /// for the step's deepest overlap whenever tested. Only these pairs: until 2026-12-06 every
    /// pair was, in a world with a string anywhere (one sphere on a string far from the 100k
    /// shower doubled its time).
    #[inline(always)]
    fn bent_pair(&self, i: usize, j: usize) -> bool {
        self.on_string(i) || self.on_string(j)
    }

    /// Whether segment `k` hangs on a string (see [`Solver::bent_pair`]).
    #[inline(always)]
    fn on_string(&self, k: usize) -> bool {
        self.strings && bit(&self.strung_bits, k)
    }

    /// Queues the first impact of pair `(i, j)` (with `i < j`) in `[t, dt]`, if any.
    ///
    /// Most pairs tested can be dismissed at a glance (two spheres closing all through the step
    /// and still apart at its end, or parting, and not ending the step overlapping): that
    /// glance is inlined where pairs are tested, and only the rest pay for the call to
    /// [`Solver::test_pair_fully`], which decides every pair alike. A fixed sphere takes the
    /// glance too (a dome is a candidate of nearly every sphere struck near it, and most of
    /// those pairs are dismissed by it). Debug builds check each dismissal against the full
    /// test: it finds no impact and keeps nothing.
    #[inline(always)]
    fn test_pair(
        &mut self,
        i: usize,
        j: usize,
        t: f64,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) {
        let (si, sj) = (&self.segments[i], &self.segments[j]);
        let glance = Glance::of(si, sj, t, ctx.dt);
        if ctx.toi.is_none() && !self.bent_pair(i, j) {
            self.test_glanced(i, j, t, &glance, ctx, stats);
        } else {
            self.test_pair_fully(i, j, t, &glance, ctx, stats);
        }
    }

    /// [`Solver::test_pair`] with its glance worked out (no strings, a built-in method).
    #[inline(always)]
    fn test_glanced(
        &mut self,
        i: usize,
        j: usize,
        t: f64,
        glance: &Glance,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) {
        if glance.dismisses(self.apart) {
            #[cfg(debug_assertions)]
            {
                let (tested, tests) = (self.tested.len(), stats.toi_tests);
                self.test_pair_fully(i, j, t, glance, ctx, stats);
                // Every impact queued was first sought by the method (counted).
                assert!(
                    self.tested.len() == tested && stats.toi_tests == tests,
                    "pair ({i}, {j}) dismissed at a glance, but the full test acted on it"
                );
            }
            return;
        }
        self.test_pair_fully(i, j, t, glance, ctx, stats);
    }

    /// [`Solver::test_pair`] for any pair, out of line, with what the glance worked out.
    #[inline(never)]
    fn test_pair_fully(
        &mut self,
        i: usize,
        j: usize,
        t: f64,
        glance: &Glance,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) {
        if self.strings {
            self.test_struts(i, j, t, ctx);
        }
        let (si, sj) = (&self.segments[i], &self.segments[j]);
        match (si.is_fixed(), sj.is_fixed()) {
            (true, true) => return,
            // A fixed sphere (a wall, a dome) reaches only part of its box: skip bodies whose
            // boxes its ball misses.
            (true, false) if !ball_meets_box(si, sj, ctx) => return,
            (false, true) if !ball_meets_box(sj, si, ctx) => return,
            _ => {}
        }
        let Glance {
            relative: Relative { d, w, reach, rest },
            end_squared,
            allowance,
        } = *glance;
        // Kept for the end-of-step overlap if the drifts as they stand end it overlapping (or
        // a string bends a drift; an impact found below is kept too): any later change to
        // either drift tests the pair again.
        let ends_overlapping = end_squared < allowance * allowance;
        let bent = self.bent_pair(i, j);
        if bent || ends_overlapping {
            self.tested.push((i as u32, j as u32));
        }
        if d.dot(w) >= 0.0 {
            // Not closing: both drift in straight lines for the rest of the step, so they only
            // move apart (either time-of-impact method would say so, after a square root).
            return;
        }
        let band = contact_band(si, sj, ctx.settings);
        if self.creep_scale > 0.0 && d.length_squared() <= (reach + band) * (reach + band) {
            // Touching and closing slower than the creep speed: left to the next step's resting
            // solve, rather than chased through a pile contact by contact, unless it would end
            // the step deeper than `CREEP_DEPTH` (a body the resting solve pushes out of an
            // overlap is left to its push: met as an impact, the push stays in its speed).
            let distance = d.length();
            if distance > 0.0 {
                let normal = d / distance;
                let creep = self.creep_scale * self.press(i, j, normal);
                let closing = -w.dot(normal);
                let deep = reach - distance + closing * rest;
                if closing <= creep
                    && (deep <= CREEP_DEPTH * si.radius().min(sj.radius()) + band
                        || bit(&self.pushed_bits, i)
                        || bit(&self.pushed_bits, j))
                {
                    return;
                }
            }
        }
        if ctx.toi.is_none() && cannot_touch_by(rest, d, w, end_squared, reach, self.apart) {
            // Neither built-in method would find an impact: spare it the square roots.
            return;
        }
        let outcome = match ctx.toi {
            Some(custom) => custom.time_of_impact(d, w, reach, rest, ctx.settings.tolerance),
            None => ctx
                .settings
                .method
                .time_of_impact(d, w, reach, rest, ctx.settings.tolerance),
        };
        stats.toi_tests += 1;
        stats.toi_iterations += u64::from(outcome.iterations);
        // An answer outside the rest of the step (NaN, negative, or past it: a custom method
        // breaking its contract; the built-in ones never do) is no impact: queued, it would
        // strike the pair wherever it is, in the past or at the step's end.
        if let Some(toi) = outcome.time.filter(|toi| (0.0..=rest).contains(toi)) {
            if !(bent || ends_overlapping) {
                self.tested.push((i as u32, j as u32));
            }
            let mut time = (t + toi).min(ctx.dt);
            if time == self.settled_time
                && !self.settled.is_empty()
                && self.settled.contains(&Settled::now(&self.versions, i, j))
            {
                // Settled now, on the free velocities of a string still slack; but if the
                // string catches its sphere later in the step, the drift it bends closes on
                // the other: look again once it has caught (then the string holds it).
                match [i, j]
                    .into_iter()
                    .filter_map(|k| self.catch_time(k))
                    .filter(|&catch| catch > time && catch <= ctx.dt)
                    .reduce(f64::min)
                {
                    Some(catch) => time = catch,
                    None => return,
                }
            }
            self.queue_pair(i, j, time);
        }
    }

    /// Queues an impact of pair `(i, j)` at `time`, unless it is past what the queue takes.
    #[inline(always)]
    fn queue_pair(&mut self, i: usize, j: usize, time: f64) {
        if time > self.queue_until {
            return;
        }
        self.queue.push(Event {
            time,
            a: i as u32,
            b: j as u32,
            version_a: self.versions[i],
            version_b: self.versions[j],
        });
    }
}

impl Solver {
    /// Forgets what the solver keeps from one step to the next by body index (which bodies
    /// rested): a body was removed, and the indices after it moved down by one.
    pub fn forget_indices(&mut self) {
        self.keep_rested_before();
        self.rested.clear();
    }

    /// A world's step begins (before its first substep): what the solver keeps from one step
    /// to the next for the step after it (the bodies that rested, the warm start) is kept as
    /// it stands until the step is taken, to be put back by [`Solver::refused`] if it is not.
    /// Each is swapped out whole at its first change in the step (no copy).
    pub fn begin_step(&mut self) {
        self.before.rested_kept = false;
        self.before.warm_kept = false;
    }

    /// The world's step was refused: puts back what the solver kept from the last step taken
    /// (see [`Solver::begin_step`]), so that the next step starts as if this one had never
    /// been tried.
    pub fn refused(&mut self) {
        if std::mem::take(&mut self.before.rested_kept) {
            std::mem::swap(&mut self.rested, &mut self.before.rested);
        }
        if std::mem::take(&mut self.before.warm_kept) {
            std::mem::swap(&mut self.warm, &mut self.before.warm);
        }
    }

    /// Before [`Solver::rested`] first changes in a step: keeps it as it was (see
    /// [`Solver::begin_step`]); what is left in its place is to be cleared.
    pub(super) fn keep_rested_before(&mut self) {
        if !self.before.rested_kept {
            self.before.rested_kept = true;
            std::mem::swap(&mut self.rested, &mut self.before.rested);
        }
    }

    /// Before [`Solver::warm`] first changes in a step: keeps it as it was (see
    /// [`Solver::begin_step`]); what is left in its place is to be emptied or started.
    pub(super) fn keep_warm_before(&mut self) {
        if !self.before.warm_kept {
            self.before.warm_kept = true;
            std::mem::swap(&mut self.warm, &mut self.before.warm);
        }
    }

    /// The largest overlap between bodies (at least one dynamic), 0 if none.
    pub fn max_overlap(&mut self, bodies: &[Body]) -> f64 {
        let mut worst = 0.0f64;
        self.pairs_near(
            bodies,
            |_| 0.0,
            |i, j| {
                let (a, b) = (&bodies[i], &bodies[j]);
                if !(a.is_fixed() && b.is_fixed()) {
                    worst = worst.max(overlap(a, b));
                }
            },
        );
        worst
    }

    /// Calls `f(i, j)` (indices into `bodies`, `i != j`, each pair once, in an order fixed by
    /// the bodies) for every pair whose boxes, each grown by `margin(body)`, meet.
    pub fn pairs_near(
        &mut self,
        bodies: &[Body],
        margin: impl Fn(&Body) -> f64,
        mut f: impl FnMut(usize, usize),
    ) {
        self.boxes.clear();
        self.boxes.extend(
            bodies
                .iter()
                .map(|b| Aabb::swept(b.position(), b.position(), b.radius(), margin(b))),
        );
        self.order.clear();
        match self.broad.sort(&self.boxes) {
            Some(permutation) => self.order.extend_from_slice(permutation),
            None => self.order.extend(0..bodies.len() as u32),
        }
        self.scratch_boxes.clear();
        self.scratch_boxes
            .extend(self.order.iter().map(|&i| self.boxes[i as usize]));
        self.broad.build(&self.scratch_boxes);
        let mut pairs = std::mem::take(&mut self.pairs);
        self.broad.pairs(&self.scratch_boxes, &mut pairs, |i, j| {
            f(self.order[i] as usize, self.order[j] as usize);
        });
        self.pairs = pairs;
    }
}

/// How far apart two spheres may be and still touch: a millionth of the smaller diameter, plus
/// the contact tolerance (relative to the sum of the radii). A millionth of the radii's sum,
/// as it was, let a small sphere on a large fixed one (a floor of radius 1e4) count as touching
/// a centimetre above it or below its surface, and sink that far uncorrected.
fn contact_band(a: &Segment, b: &Segment, settings: &Settings) -> f64 {
    let reach = a.radius() + b.radius();
    2e-6 * a.radius().min(b.radius()) + settings.tolerance.epsilon() * (1.0 + reach)
}

/// Whether bit `k` of `bits` is set (false beyond its end).
#[inline(always)]
fn bit(bits: &[u64], k: usize) -> bool {
    bits.get(k / 64)
        .is_some_and(|word| word >> (k % 64) & 1 != 0)
}

/// Hints that `value` will be read soon (a no-op where there is no such instruction).
#[inline(always)]
pub(crate) fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing and cannot fault; the pointer comes from a reference.
    unsafe {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        _mm_prefetch::<_MM_HINT_T0>((value as *const T).cast::<i8>());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

/// [`prefetch`] for both ends of `value` (which spans at most two cache lines).
#[inline(always)]
fn prefetch_lines<T>(value: &T) {
    prefetch(value);
    let last = size_of::<T>().saturating_sub(1);
    // SAFETY: the value's own last byte.
    prefetch(unsafe { &*(value as *const T).cast::<u8>().add(last) });
}

/// The acceleration pressing a pair together along `normal` (from `a` to `b`): the larger
/// component of either body's own acceleration along the line of centres. A ball on another
/// under gravity presses with g; two balls side by side (a cradle) do not press at all.
fn pressing(a: &Extra, b: &Extra, normal: DVec3) -> f64 {
    a.acceleration
        .dot(normal)
        .abs()
        .max(b.acceleration.dot(normal).abs())
}

/// How far two bodies overlap (negative when apart).
pub(crate) fn overlap(a: &Body, b: &Body) -> f64 {
    a.radius() + b.radius() - (b.position() - a.position()).length()
}

/// Whether fixed sphere `fixed`, grown by the contact margin, meets the box `other` sweeps
/// over the rest of the step (a wall or a dome reaches only a small part of its own box).
/// A fixed sphere with a velocity (kinematic) sweeps a capsule, not a ball: always true.
fn ball_meets_box(fixed: &Segment, other: &Segment, ctx: &StepContext<'_>) -> bool {
    if fixed.velocity != DVec3::ZERO {
        return true;
    }
    let b = swept_box(other, ctx.dt, ctx.settings);
    let margin = ctx.settings.tolerance.epsilon() * (1.0 + 2.0 * fixed.radius());
    // A hair larger, so rounding never drops a touching pair.
    let radius = (fixed.radius() + margin) * (1.0 + 1e-12);
    let closest = fixed.position.clamp(b.lo, b.hi);
    (closest - fixed.position).length_squared() <= radius * radius
}

/// Whether an impact gave its pair no impulse: none, or one that changes their speed along
/// the normal by no more than the tolerance's zero (rounding), `inverse_masses` the sum of
/// theirs. Such a pair is settled at its instant (see `Solver::settled`). A pair with a sphere
/// on a taut string, parting on the string's tangent while its chord turned back in, took
/// impulses of 3e-20 kg m/s at one instant again and again, each counted as an impulse, until
/// a body's share of the collision budget ran out (`sphere-fuzz --strings fast` seed 218 317:
/// 688 times, and the step ended with a pair 0.61 of a radius deep).
fn gave_none(impulse: f64, inverse_masses: f64, settings: &Settings) -> bool {
    impulse <= 0.0 || settings.tolerance.is_zero(impulse * inverse_masses)
}

/// The box a segment sweeps over the rest of the step, grown by the contact tolerance.
fn swept_box(segment: &Segment, dt: f64, settings: &Settings) -> Aabb {
    let radius = segment.radius();
    let margin = settings.tolerance.epsilon() * (1.0 + 2.0 * radius);
    Aabb::swept(segment.position, segment.position_at(dt), radius, margin)
}
