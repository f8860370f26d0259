//! Which bodies a step may leave out: with sleeping on, the islands asleep beyond the reach of
//! everything that moves. A step then costs what its moving bodies and the islands near them
//! cost, not what the whole world does: a bed of thousands asleep while one ball bounces
//! elsewhere costs next to nothing, as it does when every sphere sleeps.
//!
//! A step's bodies are every fixed body, every dynamic one awake, and every island asleep
//! that any of those could reach within the step, and what those islands' bodies could reach
//! in turn (an island struck moves as one: the impulse runs through its contacts). How far a
//! body can go is bounded by energy: no impact adds kinetic energy (with restitution at most 1
//! and no body moving while fixed), so no body of the step goes faster than its own speed plus
//! what its acceleration adds in the step, or than all the kinetic energy of the step's bodies
//! given to the lightest of them. The bound holds only where every impact is of free or still
//! bodies: a world with a kinematic sphere (fixed, moving), a sphere on a string or a custom
//! integrator, or stepped in substeps, takes every body.
//!
//! The islands left out do not move and are not moved in the step; their part of the step's
//! statistics is worked out here, once for as long as the same islands are left out: no
//! kinetic energy or momentum (they are at rest), their potential energy (added to the
//! step's own: equal to `World::potential_energy` to rounding, summed in another order), and
//! the deepest overlap among them and the still fixed bodies (unchanged while they sleep:
//! kept island by island, worked out once for as long as the same bodies sleep), which the
//! step's own deepest overlap is taken together with. The step's scales and
//! collision budget count them as a step of every body would (see `StepContext`).
//!
//! What it costs: the bodies not asleep, listed as bodies come and go, are looked at once a
//! step; the islands asleep within reach of each along x (the bodies asleep are indexed by
//! their centres' x and by island whenever a body falls asleep or wakes), and from each
//! island taken, by its box, those within its reach; past 8 looks a body in all, the choice
//! gives up and every body steps.

use glam::DVec3;

use crate::sleep::SleepState;
use crate::{Body, Settings};

/// The fewest bodies asleep for a step to leave any out: fewer cost less to step than to sort
/// out.
const FEWEST_ASLEEP: usize = 64;

/// How many times the choice starts again with a lighter body among the step's (the speed
/// bound grows with it) before it gives up and takes every body.
const RESTARTS: u32 = 8;

/// An island asleep, as the choice looks at it.
#[derive(Clone, Copy, Debug)]
struct IslandBox {
    island: u64,
    /// The box of its spheres (their surfaces).
    lo: DVec3,
    hi: DVec3,
    largest: f64,
    lightest: f64,
    /// The deepest overlap of a pair with one of its spheres and a sphere asleep or fixed (at
    /// least 0), once worked out (see `known`).
    deepest: f64,
    /// Whether `deepest` is worked out (see [`Dormant::deepest_known`]).
    known: bool,
    /// How many spheres it holds.
    count: u32,
}

/// The choice of a step's bodies, and what the bodies left out add to its statistics.
#[derive(Debug, Default)]
pub(crate) struct Dormant {
    /// The step's bodies, as world indices in world order (when [`Dormant::choose`] says so).
    pub in_step: Vec<u32>,
    /// Dynamic bodies left out of the step (all asleep).
    pub left_out_dynamic: u32,
    /// The largest component of any acceleration of a body asleep (the step's scales take the
    /// bodies left out as if they were in).
    pub left_out_acceleration: f64,
    /// Swap space: the step's bodies are moved here for the step, and back.
    pub bodies: Vec<Body>,
    /// Whether the last step left bodies out, and which it took then: the solver keeps some
    /// marks by index from one step to the next (see `Solver::forget_indices`).
    last_left_out: bool,
    last: Vec<u32>,
    /// `last_left_out` and `last` as the world's step began, if the step changed them (put
    /// back if it is refused: see [`Dormant::refused`]).
    before: Option<bool>,
    last_before: Vec<u32>,
    /// The generation of the bodies asleep (see `Sleeper`) the index below was made for.
    key: Option<u64>,
    /// The bodies asleep, by their centres' x: `(x, index)`.
    by_x: Vec<(f64, u32)>,
    /// The bodies asleep, by island: `(island, index)`.
    by_island: Vec<(u64, u32)>,
    /// The largest radius among the bodies asleep.
    largest_radius: f64,
    /// Each island asleep: the box of its spheres, its largest radius and its lightest mass,
    /// by island.
    boxes: Vec<IslandBox>,
    /// The islands taken into the step, sorted.
    islands: Vec<u64>,
    /// The same, as places in `boxes`, in the order they were taken.
    taken: Vec<u32>,
    /// The dynamic bodies awake.
    frontier: Vec<u32>,
    /// Every body not asleep (fixed or awake), as world indices in world order: made with
    /// the index, and kept as bodies are added and removed (a body falls asleep or wakes only
    /// with a new generation).
    awake: Vec<u32>,
    /// The deepest overlap of a pair with a body left out, and the generation and the
    /// islands taken into the step it was worked out for (the same bodies left out: a fixed
    /// body added, changed or removed that would change it touches one of them, and wakes it;
    /// a dynamic one is within the reach of the bodies taken, or in their islands).
    overlap: f64,
    overlap_for: Option<(u64, Vec<u64>)>,
    /// The potential energy of the bodies left out (for the same choice as `overlap`).
    potential: f64,
    /// Each body's place in `boxes` if it is asleep (else `u32::MAX`), by world index.
    box_of: Vec<u32>,
    /// Whether every island's `deepest` is worked out.
    all_known: bool,
    /// Whether a body indexed was removed since the index was brought up to date.
    stale: bool,
    /// The island each body is indexed under (0: none), by world index.
    indexed: Vec<u64>,
    /// Buffers of [`Dormant::index_asleep`]: which bodies' entries stay, the entries new to the
    /// index, and the lists merged.
    stays: Vec<bool>,
    fresh: Vec<(u64, u32)>,
    fresh_x: Vec<(f64, u32)>,
    merged_x: Vec<(f64, u32)>,
    merged_island: Vec<(u64, u32)>,
    old_boxes: Vec<IslandBox>,
}

impl Dormant {
    /// Chooses the bodies of a step of `dt` (the bodies as they stand, sleeping on, one
    /// substep, the built-in integrator), into [`Dormant::in_step`]; `generation` changes
    /// whenever a body falls asleep or wakes.
    /// Returns whether the step should leave bodies out (false: take every body).
    pub fn choose(
        &mut self,
        bodies: &[Body],
        states: &[SleepState],
        settings: &Settings,
        dt: f64,
        generation: u64,
    ) -> bool {
        let n = bodies.len();
        if self.key != Some(generation) {
            self.key = Some(generation);
            self.index_asleep(bodies, states, settings);
        }
        if self.by_x.len() < FEWEST_ASLEEP {
            return false;
        }
        // Every fixed body (all still) and every dynamic one awake.
        self.in_step.clear();
        self.frontier.clear();
        let (mut energy, mut fastest, mut lightest, mut accelerated) =
            (0.0f64, 0.0f64, f64::INFINITY, 0.0f64);
        for &i in &self.awake {
            let body = &bodies[i as usize];
            debug_assert!(!body.asleep, "a body asleep among those awake");
            if body.is_fixed() {
                if body.velocity() != DVec3::ZERO {
                    return false;
                }
                self.in_step.push(i);
            } else {
                if body.tether().is_some() {
                    return false;
                }
                let a = body.acceleration(settings.gravity).length();
                let v = body.velocity().length() + a * dt;
                energy += 0.5 * body.mass() * v * v;
                fastest = fastest.max(v);
                lightest = lightest.min(body.mass());
                accelerated = accelerated.max(a);
                self.in_step.push(i);
                self.frontier.push(i);
            }
        }
        // (With none awake, a step changed through the world: only the fixed bodies step.)
        if !energy.is_finite() {
            return false;
        }
        let base = self.in_step.len();
        let epsilon = settings.tolerance.epsilon();
        let mut restarts = 0;
        'choose: loop {
            self.in_step.truncate(base);
            self.islands.clear();
            self.taken.clear();
            let speed = fastest.max((2.0 * energy / lightest).sqrt()) + accelerated * dt;
            // How far beyond touching a body of the step and one asleep, of radii `r` and `s`,
            // may be and still meet in the step: twice the farthest either could go, a quarter
            // of their radii for the pushes out of overlaps and resting contacts' reach, and
            // the tolerances.
            let pad = |r: f64, s: f64| {
                2.0 * speed * dt
                    + 2.0 * accelerated * dt * dt
                    + 0.25 * (r + s)
                    + 8.0 * epsilon * (1.0 + r + s)
            };
            // The islands within reach of a sphere, or of an island taken (its box, which
            // holds its spheres), are taken in turn; so many looked at that the choice would
            // cost more than it saves, and every body steps.
            let mut looked_at = 0usize;
            let budget = 8 * n + 1024;
            let (mut next_body, mut next_island) = (0, 0);
            loop {
                let (lo, hi, r) = if next_body < self.frontier.len() {
                    let body = &bodies[self.frontier[next_body] as usize];
                    next_body += 1;
                    let (p, r) = (body.position(), body.radius());
                    (p, p, r)
                } else if next_island < self.taken.len() {
                    let island = &self.boxes[self.taken[next_island] as usize];
                    next_island += 1;
                    (island.lo, island.hi, island.largest)
                } else {
                    break;
                };
                let wide = r + self.largest_radius + pad(r, self.largest_radius);
                let from = self.by_x.partition_point(|e| e.0 < lo.x - wide);
                let to = self.by_x.partition_point(|e| e.0 <= hi.x + wide);
                // With fewer islands than bodies to look at, the islands' boxes first: a body
                // lies in its island's box, and is no larger than its largest, so none of an
                // island whose box is out of reach is within reach (a ball bouncing above a
                // bed of 10 000 looked at up to 1435 under it each step, to take none).
                if self.boxes.len() < to - from {
                    looked_at += self.boxes.len();
                    let islands = &self.islands;
                    let within = self.boxes.iter().any(|b| {
                        let gap = (b.lo - hi).max(lo - b.hi).max(DVec3::ZERO);
                        let near = r + b.largest + pad(r, b.largest);
                        gap.length_squared() <= near * near
                            && islands.binary_search(&b.island).is_err()
                    });
                    if !within {
                        continue;
                    }
                }
                looked_at += to - from;
                if looked_at > budget {
                    return false;
                }
                for e in from..to {
                    let index = self.by_x[e].1 as usize;
                    let (b, island) = (&bodies[index], states[index].island());
                    let Err(at) = self.islands.binary_search(&island) else {
                        continue;
                    };
                    let p = b.position();
                    let near = r + b.radius() + pad(r, b.radius());
                    let gap = (lo - p).max(p - hi).max(DVec3::ZERO);
                    if gap.length_squared() > near * near {
                        continue;
                    }
                    // Its island comes into the step.
                    self.islands.insert(at, island);
                    let k = self.boxes.partition_point(|x| x.island < island);
                    let taken = &self.boxes[k];
                    if taken.lightest < lightest {
                        // A lighter body: the bound on the speed grows.
                        lightest = taken.lightest;
                        restarts += 1;
                        if restarts > RESTARTS {
                            return false;
                        }
                        continue 'choose;
                    }
                    self.taken.push(k as u32);
                    let from = self.by_island.partition_point(|e| e.0 < island);
                    for &(of, m) in &self.by_island[from..] {
                        if of != island {
                            break;
                        }
                        self.in_step.push(m);
                    }
                    if 2 * self.in_step.len() > n {
                        return false;
                    }
                }
            }
            break;
        }
        if 2 * self.in_step.len() > n {
            return false;
        }
        self.in_step.sort_unstable();
        self.left_out_dynamic = (self.by_x.len() - (self.in_step.len() - base)) as u32;
        true
    }

    /// The body at world index `index` was removed: those after it move down one place.
    pub fn removed(&mut self, index: usize) {
        if let Ok(at) = self.awake.binary_search(&(index as u32)) {
            self.awake.remove(at);
        }
        for i in self.awake.iter_mut() {
            if *i as usize > index {
                *i -= 1;
            }
        }
        // Its own entries go (see `removed_all`).
        self.stale |= self.indexed.get(index).is_some_and(|&island| island != 0);
        self.by_x.retain(|e| e.1 as usize != index);
        self.by_island.retain(|e| e.1 as usize != index);
        for (_, i) in self.by_x.iter_mut() {
            if *i as usize > index {
                *i -= 1;
            }
        }
        for (_, i) in self.by_island.iter_mut() {
            if *i as usize > index {
                *i -= 1;
            }
        }
        if index < self.box_of.len() {
            self.box_of.remove(index);
        }
        if index < self.indexed.len() {
            self.indexed.remove(index);
        }
    }

    /// The bodies at the world indices `gone` marks were removed: those after each move down.
    /// An index kept up to date then must be brought up to date before the next choice,
    /// which must not find it unchanged: an island of a removed body alone would keep its
    /// box (found by review in the fifty-eighth session).
    pub fn removed_all(&mut self, gone: &[bool]) {
        // Each old index's new one: the old less the bodies removed before it.
        let mut below = 0u32;
        let new_index: Vec<u32> = gone
            .iter()
            .map(|&g| {
                let at = below;
                below += u32::from(!g);
                at
            })
            .collect();
        let stays = |i: u32| !gone[i as usize];
        self.awake.retain(|&i| stays(i));
        for i in &mut self.awake {
            *i = new_index[*i as usize];
        }
        self.by_x.retain(|e| stays(e.1));
        for e in &mut self.by_x {
            e.1 = new_index[e.1 as usize];
        }
        self.by_island.retain(|e| stays(e.1));
        for e in &mut self.by_island {
            e.1 = new_index[e.1 as usize];
        }
        self.stale |= self
            .indexed
            .iter()
            .zip(gone)
            .any(|(&island, &g)| g && island != 0);
        // (Both as long as the world when the index was last brought up to date.)
        retain_by_index(&mut self.box_of, gone);
        retain_by_index(&mut self.indexed, gone);
    }

    /// A body was added, at world index `index` (the last): awake.
    pub fn added(&mut self, index: usize) {
        self.awake.push(index as u32);
    }

    /// Indexes the bodies asleep (by x and by island), and lists those awake.
    ///
    /// The index is brought up to date, not made anew: a body asleep under the island it was
    /// indexed under has not moved (a body asleep moves only once woken, and falls asleep
    /// again under a new island), so its entries stay where they are, and only the bodies
    /// that fell asleep since are sorted, and merged in. So does each island's box with its
    /// deepest overlap, worked out again only for the islands new to the index (see
    /// [`Dormant::deepest_known`]). The index is the same as if made anew: the same entries in
    /// the same order, and the same boxes. (Until the fifty-eighth session it was made anew:
    /// with 10 000 marbles asleep apart, each step after one woke took 1.47 ms.)
    fn index_asleep(&mut self, bodies: &[Body], states: &[SleepState], settings: &Settings) {
        let n = bodies.len();
        self.awake.clear();
        self.largest_radius = 0.0;
        self.left_out_acceleration = 0.0;
        self.indexed.resize(n, 0);
        self.stays.clear();
        self.stays.resize(n, false);
        self.fresh.clear();
        let mut gone = std::mem::take(&mut self.stale);
        for (i, (body, state)) in bodies.iter().zip(states).enumerate() {
            let was = self.indexed[i];
            if !body.asleep || body.is_fixed() {
                if !body.asleep {
                    self.awake.push(i as u32);
                }
                gone |= was != 0;
                self.indexed[i] = 0;
                continue;
            }
            self.largest_radius = self.largest_radius.max(body.radius());
            let a = body.acceleration(settings.gravity).abs().max_element();
            self.left_out_acceleration = self.left_out_acceleration.max(a);
            let island = state.island();
            if was == island {
                self.stays[i] = true;
            } else {
                gone |= was != 0;
                self.fresh.push((island, i as u32));
                self.indexed[i] = island;
            }
        }
        if !gone && self.fresh.is_empty() {
            return;
        }
        let stays = &self.stays;
        self.by_x.retain(|e| stays[e.1 as usize]);
        self.by_island.retain(|e| stays[e.1 as usize]);
        // The new entries sorted, then merged in (the order a sort of all of them gives).
        self.fresh.sort_unstable();
        self.fresh_x.clear();
        self.fresh_x.extend(
            self.fresh
                .iter()
                .map(|&(_, i)| (bodies[i as usize].position().x, i)),
        );
        let by_x_order = |a: &(f64, u32), b: &(f64, u32)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
        self.fresh_x.sort_unstable_by(by_x_order);
        merge(&mut self.by_x, &self.fresh_x, &mut self.merged_x, |a, b| {
            by_x_order(a, b) == std::cmp::Ordering::Greater
        });
        merge(
            &mut self.by_island,
            &self.fresh,
            &mut self.merged_island,
            |a, b| a > b,
        );
        // Each island's box: kept if none of its spheres is new to the index and it holds
        // as many as before (an island keeps its spheres while it sleeps, all of them).
        std::mem::swap(&mut self.boxes, &mut self.old_boxes);
        self.boxes.clear();
        self.all_known = true;
        self.box_of.clear();
        self.box_of.resize(n, u32::MAX);
        let (mut at, mut next_old) = (0, 0);
        while at < self.by_island.len() {
            let island = self.by_island[at].0;
            let end = at
                + self.by_island[at..]
                    .iter()
                    .take_while(|e| e.0 == island)
                    .count();
            let members = &self.by_island[at..end];
            let kept = members.iter().all(|e| self.stays[e.1 as usize]);
            // (Both in the islands' order: the old boxes are walked once.)
            while self
                .old_boxes
                .get(next_old)
                .is_some_and(|b| b.island < island)
            {
                next_old += 1;
            }
            let old = self
                .old_boxes
                .get(next_old)
                .filter(|b| b.island == island && kept && b.count as usize == members.len())
                .copied();
            let b = old.unwrap_or_else(|| {
                let mut b = IslandBox {
                    island,
                    lo: DVec3::INFINITY,
                    hi: DVec3::NEG_INFINITY,
                    largest: 0.0,
                    lightest: f64::INFINITY,
                    deepest: 0.0,
                    known: false,
                    count: members.len() as u32,
                };
                for &(_, i) in members {
                    let body = &bodies[i as usize];
                    let (p, r) = (body.position(), body.radius());
                    b.lo = b.lo.min(p - r);
                    b.hi = b.hi.max(p + r);
                    b.largest = b.largest.max(r);
                    b.lightest = b.lightest.min(body.mass());
                }
                b
            });
            for &(_, i) in members {
                self.box_of[i as usize] = self.boxes.len() as u32;
            }
            self.all_known &= b.known;
            self.boxes.push(b);
            at = end;
        }
    }

    /// Whether the solver's marks kept by index from the last step still fit this one (the
    /// same bodies, in the same places); records this step's choice (`in_step` if it leaves
    /// bodies out).
    pub fn same_indices(&mut self, leaves_out: bool) -> bool {
        let same = self.last_left_out == leaves_out && (!leaves_out || self.last == self.in_step);
        if !same {
            if self.before.is_none() {
                self.before = Some(self.last_left_out);
                std::mem::swap(&mut self.last, &mut self.last_before);
            }
            self.last_left_out = leaves_out;
            if leaves_out {
                self.last.clone_from(&self.in_step);
            }
        }
        same
    }

    /// A world's step begins: what [`Dormant::same_indices`] records is kept as it stands
    /// until the step is taken.
    pub fn begin_step(&mut self) {
        self.before = None;
    }

    /// The world's step was refused: puts back the last step's choice (see
    /// [`Dormant::same_indices`]).
    pub fn refused(&mut self) {
        if let Some(left_out) = self.before.take() {
            self.last_left_out = left_out;
            std::mem::swap(&mut self.last, &mut self.last_before);
        }
    }

    /// The deepest overlap of a pair with a body left out of the step and the potential
    /// energy of those bodies (the bodies as they stand), or `None` if they must be worked
    /// out again (then give them to [`Dormant::set_left_out`]).
    pub fn left_out(&self) -> Option<(f64, f64)> {
        match &self.overlap_for {
            Some((key, islands)) if Some(*key) == self.key && *islands == self.islands => {
                Some((self.overlap, self.potential))
            }
            _ => None,
        }
    }

    /// Whether each island's deepest overlap is worked out for the bodies asleep as they are
    /// indexed (once for each island: the bodies asleep and the fixed ones stay where they
    /// are while it sleeps). Until the fifty-seventh session every change of the islands
    /// taken looked at every pair of the world again: a ball rolling among 10 000 marbles
    /// asleep apart, each its own island, paid 16 ns a marble a step for it.
    pub fn deepest_known(&self) -> bool {
        self.all_known
    }

    /// The bodies of the islands whose deepest overlap is not worked out, if their pairs
    /// among themselves and with the `fixed` bodies are few enough (at most `limit`) to be
    /// looked at one by one, into `out`, island after island. A pair of spheres asleep in
    /// two islands does not overlap (touching, they would have fallen asleep as one), so
    /// those pairs are all an island's deepest overlap needs.
    pub fn unknown_if_few(&self, fixed: usize, limit: usize, out: &mut Vec<u32>) -> bool {
        out.clear();
        let mut pairs = 0usize;
        for b in self.boxes.iter().filter(|b| !b.known) {
            let count = b.count as usize;
            pairs = pairs.saturating_add(count.saturating_mul(count / 2 + fixed));
            if pairs > limit {
                return false;
            }
        }
        for (island, i) in &self.by_island {
            let k = self.box_of[*i as usize] as usize;
            debug_assert_eq!(self.boxes[k].island, *island);
            if !self.boxes[k].known {
                out.push(*i);
            }
        }
        true
    }

    /// Whether the bodies at world indices `i` and `j`, asleep, are of one island.
    pub fn same_island(&self, i: usize, j: usize) -> bool {
        self.box_of.get(i) == self.box_of.get(j)
    }

    /// Raises the deepest overlap of a pair with the body at world index `index`, asleep, to
    /// `overlap` (its island's), unless its island's is worked out.
    pub fn raise_deepest(&mut self, index: usize, overlap: f64) {
        if let Some(&k) = self.box_of.get(index).filter(|&&k| k != u32::MAX) {
            let b = &mut self.boxes[k as usize];
            if !b.known {
                b.deepest = b.deepest.max(overlap);
            }
        }
    }

    /// Every island's deepest overlap is worked out (see [`Dormant::raise_deepest`]).
    pub fn set_deepest_known(&mut self) {
        for b in &mut self.boxes {
            b.known = true;
        }
        self.all_known = true;
    }

    /// Each island's deepest overlap, in the index's order (a check in debug builds).
    #[cfg(debug_assertions)]
    pub fn deepest_each(&self) -> Vec<f64> {
        self.boxes.iter().map(|b| b.deepest).collect()
    }

    /// Forgets every island's deepest overlap (a check in debug builds works them out anew).
    #[cfg(debug_assertions)]
    pub fn forget_deepest(&mut self) {
        for b in &mut self.boxes {
            b.known = false;
            b.deepest = 0.0;
        }
        self.all_known = false;
    }

    /// The deepest overlap of a pair with a body left out of the step (at least 0): the
    /// deepest of the islands not taken. (A pair of such a body and one awake cannot overlap:
    /// its island would be within the awake one's reach, and taken.)
    pub fn deepest_left_out(&self) -> f64 {
        self.boxes
            .iter()
            .filter(|b| self.islands.binary_search(&b.island).is_err())
            .fold(0.0f64, |deepest, b| deepest.max(b.deepest))
    }

    /// Records the deepest overlap of a pair with a body left out, and their potential
    /// energy, for this choice.
    pub fn set_left_out(&mut self, overlap: f64, potential: f64) {
        self.overlap = overlap;
        self.potential = potential;
        let key = self.key.expect("chosen");
        match &mut self.overlap_for {
            Some((k, islands)) => {
                *k = key;
                islands.clone_from(&self.islands);
            }
            None => self.overlap_for = Some((key, self.islands.clone())),
        }
    }
}

/// Merges the sorted `extra` into the sorted `list` (`after(a, b)`: `a` goes after `b`), through
/// `scratch`: an entry of `list` before an equal one of `extra`.
fn merge<T: Copy>(
    list: &mut Vec<T>,
    extra: &[T],
    scratch: &mut Vec<T>,
    after: impl Fn(&T, &T) -> bool,
) {
    if extra.is_empty() {
        return;
    }
    scratch.clear();
    scratch.reserve(list.len() + extra.len());
    let (mut i, mut j) = (0, 0);
    while i < list.len() && j < extra.len() {
        if after(&list[i], &extra[j]) {
            scratch.push(extra[j]);
            j += 1;
        } else {
            scratch.push(list[i]);
            i += 1;
        }
    }
    scratch.extend_from_slice(&list[i..]);
    scratch.extend_from_slice(&extra[j..]);
    std::mem::swap(list, scratch);
}

/// Keeps the entries of `list` (by world index) whose bodies `gone` does not mark.
fn retain_by_index<T>(list: &mut Vec<T>, gone: &[bool]) {
    let mut k = 0;
    list.retain(|_| {
        k += 1;
        !gone.get(k - 1).copied().unwrap_or(false)
    });
}
