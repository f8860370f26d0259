//! Sleeping: a group of touching bodies at rest on a fixed sphere stops being stepped until
//! something wakes it (see [`Settings::sleep`](crate::Settings::sleep)).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::Body;
use crate::disturbed::Disturbed;
use crate::solver::Solver;

/// How near two spheres must be to count as touching when bodies are grouped to fall asleep
/// together (this fraction of the smaller radius apart, or closer), or to be woken (and,
/// awake, made calm from then on only) by a fixed sphere added, changed or removed near them
/// (this fraction of their own radius).
pub const SLEEP_CONTACT: f64 = 0.05;

/// When bodies fall asleep: see [`Settings::sleep`](crate::Settings::sleep).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Sleep {
    /// A body is calm while its speed at the end of each step stays below this (default 0.2,
    /// in the world's units of length per second: a little more than what Earth's gravity
    /// gives in a step of 1/60 s, the scale at which a large bed of frictionless spheres
    /// jiggles; at 0.1 a bed of 10 000 had not fallen asleep after 24 s).
    pub speed: f64,
    /// How long every body of a group must have stayed calm for the group to fall asleep
    /// (default 1 s).
    pub time: f64,
}

impl Default for Sleep {
    fn default() -> Self {
        Sleep {
            speed: 0.2,
            time: 1.0,
        }
    }
}

/// A body touching a fixed sphere added, changed or removed (see [`Sleeper::wake_around`]):
/// asleep, its island is to wake; awake, it is calm from now on only.
fn disturbed_by_fixed(body: &Body, state: &mut SleepState, wake: &mut Vec<u64>) {
    if body.asleep {
        wake.push(state.island);
    } else {
        state.calm = 0.0;
    }
}

/// How many fixed bodies removed together [`Sleeper::wake_around_all`] looks at one by one.
const FEW_FIXED: usize = 8;

/// A body's flags while groups are formed.
const GROUNDED: u8 = 1;
const BLOCKED: u8 = 2;
const AWAKE: u8 = 4;

/// A body's sleeping state beyond whether it is asleep ([`Body`] holds that), kept by the
/// [`Sleeper`] beside the world's bodies, at the same index: the passes over every body each
/// step then read and write less.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct SleepState {
    /// While awake, how long its speed has stayed below the sleeping speed (seconds).
    calm: f64,
    /// While asleep, the group it fell asleep with (woken together).
    island: u64,
    /// While asleep, where it fell asleep: moved from there, it wakes.
    rest: DVec3,
}

impl SleepState {
    /// While asleep, the group it fell asleep with.
    pub fn island(&self) -> u64 {
        self.island
    }
}

/// The world's sleeping state between steps, and its buffers.
#[derive(Debug, Default)]
pub(crate) struct Sleeper {
    /// Each body's [`SleepState`], at its index in the world.
    states: Vec<SleepState>,
    /// Union-find over body indices: the groups of touching dynamic bodies.
    parent: Vec<u32>,
    /// Per body, then per group (at its root): `GROUNDED`, `BLOCKED`, `AWAKE`.
    flags: Vec<u8>,
    /// Per group (at its root), the island it falls asleep as (0: not yet given one).
    new_island: Vec<u64>,
    /// The last island given out.
    last_island: u64,
    /// Islands to wake.
    wake: Vec<u64>,
    /// The gravity of the last step taken with sleeping on: a change wakes every body.
    gravity: Option<DVec3>,
    /// The earliest time at which groups are formed again.
    next_check: f64,
    /// Changes whenever a body falls asleep or wakes: what `Dormant` keeps of the bodies
    /// asleep holds while it does not. (A fixed body added, changed or removed that touches a
    /// body asleep wakes it; a dynamic one wakes its own island, and one added touching a body
    /// asleep joins the step through the islands within its reach.)
    generation: u64,
    /// Every dynamic body asleep and no fixed one moving since the last step, and nothing
    /// changed since through the world: the next step has nothing to do.
    quiet: bool,
    /// Bodies asleep.
    asleep: usize,
    /// What `before_step` changed, to be put back if the step is refused (see
    /// [`Sleeper::refused`]).
    before: Before,
    /// Where bodies were added, changed or removed through the world since the last step:
    /// the awake bodies touching one of those places are calm from then on only (see
    /// [`Sleeper::disturbed_at`]).
    disturbed: Disturbed,
}

/// The sleeper as it was before `before_step` woke every body.
#[derive(Debug, Default)]
struct Before {
    /// Whether `before_step` woke every body (and the rest below is what was).
    changed: bool,
    gravity: Option<DVec3>,
    quiet: bool,
    asleep: usize,
    /// The bodies asleep, by index.
    asleep_bodies: Vec<u32>,
    /// Each body's calm.
    calm: Vec<f64>,
}

impl Sleeper {
    /// A body was added (the world's last): its state is new.
    pub fn added(&mut self) {
        self.states.push(SleepState::default());
    }

    /// The body at `index` was removed: those after it move down one place.
    pub fn removed(&mut self, index: usize) {
        self.states.remove(index);
    }

    /// The bodies at the indices `gone` marks were removed: those after each move down.
    pub fn removed_all(&mut self, gone: &[bool]) {
        let mut k = 0;
        self.states.retain(|_| {
            k += 1;
            !gone[k - 1]
        });
    }

    /// The body at `index` was replaced by a new one, or given a calm it must gather anew (it
    /// was changed, and may be where it would never have come to rest).
    pub fn reset(&mut self, index: usize) {
        self.states[index] = SleepState::default();
    }

    /// Each body's state, at its index in the world.
    pub fn states(&self) -> &[SleepState] {
        &self.states
    }

    /// A sphere of `radius` at `centre` was added there, changed, or removed from there (in
    /// a world of `bodies` bodies; a dynamic one, or a fixed one, whose neighbours asleep
    /// [`Sleeper::wake_around`] wakes at once): the awake bodies touching it (see
    /// [`SLEEP_CONTACT`]) are calm from the next step on only. One resting on a ball removed,
    /// moved or struck away had kept the calm it gathered on it, and fell asleep in the air a
    /// step later (near enough to a fixed sphere to seem to rest on it, or on the shoulder of
    /// a ball it was sliding off). Looked at in [`Sleeper::after_step`], by each awake body
    /// calm in that step (which a calm body leaves by less than the sleeping speed carries
    /// it), for every place since the last step at once: a game may set many bodies'
    /// velocities between two steps. Kept with sleeping off too, for a step after it is
    /// turned on again.
    pub fn disturbed_at(&mut self, bodies: usize, centre: DVec3, radius: f64) {
        self.disturbed.add(bodies, centre, radius);
    }

    /// A step was taken with sleeping off: its bodies' calms start again once it is on (see
    /// [`Sleeper::before_step`]), so the places of [`Sleeper::disturbed_at`] are done with.
    /// (Not at the step's start: a refused step keeps them.)
    pub fn stepped_without_sleeping(&mut self) {
        self.disturbed.clear();
    }

    /// Before a step: wakes every body if sleeping is off or gravity changed. Returns whether
    /// the step has nothing to do (see `quiet`). If the step is then refused,
    /// [`Sleeper::refused`] puts back what this changed.
    pub fn before_step(
        &mut self,
        bodies: &mut [Body],
        sleep: Option<Sleep>,
        gravity: DVec3,
    ) -> bool {
        self.before.changed = false;
        let changes = match sleep {
            None => self.gravity.is_some(),
            Some(_) => self.gravity != Some(gravity),
        };
        if changes {
            self.keep_before(bodies);
        }
        if sleep.is_none() {
            // Turned off (nothing can be asleep if it was never on: no scan then).
            if self.gravity.take().is_some() {
                self.wake_all(bodies);
            }
            return false;
        }
        if self.gravity != Some(gravity) {
            self.wake_all(bodies);
            self.gravity = Some(gravity);
        }
        self.quiet
    }

    /// Keeps what `before_step` is about to change (see `Before`).
    fn keep_before(&mut self, bodies: &[Body]) {
        let before = &mut self.before;
        before.changed = true;
        before.gravity = self.gravity;
        before.quiet = self.quiet;
        before.asleep = self.asleep;
        before.asleep_bodies.clear();
        before
            .asleep_bodies
            .extend((0..bodies.len() as u32).filter(|&i| bodies[i as usize].asleep));
        before.calm.clear();
        before.calm.extend(self.states.iter().map(|s| s.calm));
    }

    /// The step was refused: puts back what `before_step` changed, if it woke every body
    /// (each body asleep or calm as it was).
    pub fn refused(&mut self, bodies: &mut [Body]) {
        if !std::mem::take(&mut self.before.changed) {
            return;
        }
        let before = &self.before;
        self.gravity = before.gravity;
        self.quiet = before.quiet;
        self.asleep = before.asleep;
        for &i in &before.asleep_bodies {
            bodies[i as usize].asleep = true;
        }
        for (state, &calm) in self.states.iter_mut().zip(&before.calm) {
            state.calm = calm;
        }
        // What is kept about the bodies asleep (see `generation`) is worked out again.
        self.generation += 1;
    }

    /// Bodies asleep.
    pub fn asleep(&self) -> usize {
        self.asleep
    }

    /// Wakes every body, and starts every body's calm again (gravity changed, or sleeping was
    /// turned off).
    fn wake_all(&mut self, bodies: &mut [Body]) {
        self.generation += 1;
        debug_assert_eq!(bodies.len(), self.states.len(), "a state per body");
        for (body, state) in bodies.iter_mut().zip(&mut self.states) {
            body.asleep = false;
            state.calm = 0.0;
        }
        self.asleep = 0;
        self.quiet = false;
    }

    /// See `generation`.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Something was changed through the world (a body added, removed or changed): the next
    /// step is not quiet.
    pub fn disturbed(&mut self) {
        self.quiet = false;
    }

    /// After a step of `dt` ending at `now`: wakes the islands of sleeping bodies the step
    /// moved or gave a speed, times each awake body's calm, and puts to sleep each group of
    /// touching bodies that has stayed calm long enough and rests on a still fixed sphere.
    /// Returns whether any body fell asleep. With `only`, the step took only the bodies of
    /// those indices (every fixed one and every one awake among them), and left out that many
    /// dynamic ones, all asleep: only those it took are looked at.
    pub fn after_step(
        &mut self,
        bodies: &mut [Body],
        only: Option<(&[u32], u32)>,
        solver: &mut Solver,
        sleep: Sleep,
        (gravity, dt, now): (DVec3, f64, f64),
    ) -> bool {
        self.wake.clear();
        let mut ready = false;
        let (mut moving, mut dynamic) = (false, only.map_or(0, |(_, left_out)| left_out as usize));
        let disturbed = !self.disturbed.is_empty();
        if disturbed {
            // A body calm in this step moved by less than the sleeping speed carries it.
            self.disturbed.prepare(SLEEP_CONTACT, sleep.speed * dt);
        }
        let all = only.is_none().then_some(0..bodies.len());
        let taken = only.map(|(indices, _)| indices.iter().map(|&i| i as usize));
        for index in all.into_iter().flatten().chain(taken.into_iter().flatten()) {
            let (body, state) = (&mut bodies[index], &mut self.states[index]);
            if body.is_fixed() {
                moving |= body.desc.velocity != DVec3::ZERO;
                continue;
            }
            dynamic += 1;
            if body.asleep {
                if body.desc.velocity != DVec3::ZERO || body.desc.position != state.rest {
                    self.wake.push(state.island);
                }
            } else if body.tether().is_none()
                && !body.desc.never_sleeps
                && body.desc.velocity.length() < sleep.speed
                // Resting needs something to rest against: with no acceleration a body at
                // rest costs next to nothing, and one being moved out of an overlap (without
                // speed) is not at rest.
                && body.acceleration(gravity) != DVec3::ZERO
            {
                // Touching a body changed through the world: calm from the next step on. (A
                // calm of 0, a body new or changed itself, has nothing to lose: its calm
                // starts with this step, as it did before the sixty-third session.)
                if disturbed
                    && state.calm > 0.0
                    && self.disturbed.touches(body.position(), body.radius())
                {
                    state.calm = 0.0;
                } else {
                    // Calm this step: `calm > 0` from here on (see `ready_to_sleep`).
                    state.calm += dt;
                    ready |= ready_to_sleep(state, sleep);
                }
            } else {
                state.calm = 0.0;
            }
        }
        if disturbed {
            self.disturbed.clear();
        }
        self.wake_islands(bodies);
        let before = self.asleep;
        // A check set for a longer `sleep.time` than now is brought nearer.
        self.next_check = self.next_check.min(now + sleep.time / 4.0);
        if ready && now >= self.next_check {
            // Forming the groups reads every body: done at most four times per `sleep.time`
            // (a group may fall asleep up to a quarter of it late).
            self.next_check = now + sleep.time / 4.0;
            self.fall_asleep(bodies, solver, sleep);
        }
        debug_assert_eq!(
            self.asleep,
            bodies.iter().filter(|b| b.asleep).count(),
            "the count of bodies asleep"
        );
        self.quiet = !moving && self.asleep > 0 && self.asleep == dynamic;
        self.asleep > before
    }

    /// Wakes the islands in `self.wake`.
    fn wake_islands(&mut self, bodies: &mut [Body]) {
        if self.wake.is_empty() {
            return;
        }
        self.quiet = false;
        self.generation += 1;
        self.wake.sort_unstable();
        self.wake.dedup();
        for (body, state) in bodies.iter_mut().zip(&mut self.states) {
            if body.asleep && self.wake.binary_search(&state.island).is_ok() {
                body.asleep = false;
                state.calm = 0.0;
                self.asleep -= 1;
            }
        }
        self.wake.clear();
    }

    /// Wakes the island of `body`, if it is asleep.
    pub fn wake_island_of(&mut self, bodies: &mut [Body], index: usize) {
        self.mark_to_wake(bodies, index);
        self.wake_now(bodies);
    }

    /// Marks the island of the body at `index`, if it is asleep, to be woken by
    /// [`Sleeper::wake_now`].
    pub fn mark_to_wake(&mut self, bodies: &[Body], index: usize) {
        if bodies[index].asleep {
            self.wake.push(self.states[index].island);
        }
    }

    /// Wakes the islands marked by [`Sleeper::mark_to_wake`].
    pub fn wake_now(&mut self, bodies: &mut [Body]) {
        self.wake_islands(bodies);
    }

    /// Wakes the islands of the sleeping bodies touching (see [`SLEEP_CONTACT`]) a sphere of
    /// `radius` at `centre`: a fixed sphere added, removed or changed there. With `sleeping`
    /// on, the awake bodies touching it are calm from now on only: one resting on a floor
    /// moved away, or removed, had kept the calm it gathered on it, and fell asleep in the
    /// air, near enough to the floor's new place to seem to rest on it.
    pub fn wake_around(&mut self, bodies: &mut [Body], centre: DVec3, radius: f64, sleeping: bool) {
        if self.asleep == 0 && !sleeping {
            return;
        }
        for (body, state) in bodies.iter().zip(&mut self.states) {
            if gap(body, centre, radius) <= SLEEP_CONTACT * body.radius() {
                disturbed_by_fixed(body, state, &mut self.wake);
            }
        }
        self.wake_islands(bodies);
    }

    /// [`Sleeper::wake_around`] for each fixed body `gone` marks (removed together, with the
    /// other bodies it marks). Past [`FEW_FIXED`] of them, each one's neighbours are found
    /// through the broad phase instead of every body being looked at for each (a level of
    /// 40 000 fixed spheres cleared at once would have looked at 1.6e9 pairs).
    pub fn wake_around_all(
        &mut self,
        bodies: &mut [Body],
        solver: &mut Solver,
        gone: &[bool],
        sleeping: bool,
    ) {
        let fixed = |i: &usize| gone[*i] && bodies[*i].is_fixed();
        if (0..bodies.len()).filter(fixed).nth(FEW_FIXED).is_none() {
            let few: Vec<usize> = (0..bodies.len()).filter(fixed).collect();
            for i in few {
                let (centre, radius) = (bodies[i].position(), bodies[i].radius());
                self.wake_around(bodies, centre, radius, sleeping);
            }
            return;
        }
        if self.asleep == 0 && !sleeping {
            return;
        }
        let view: &[Body] = bodies;
        let (states, wake) = (&mut self.states, &mut self.wake);
        solver.pairs_near(
            view,
            |b| {
                if b.is_fixed() {
                    0.0
                } else {
                    SLEEP_CONTACT * b.radius()
                }
            },
            |i, j| {
                for (f, d) in [(i, j), (j, i)] {
                    let (by, body) = (&view[f], &view[d]);
                    if gone[f]
                        && by.is_fixed()
                        && gap(body, by.position(), by.radius()) <= SLEEP_CONTACT * body.radius()
                    {
                        disturbed_by_fixed(body, &mut states[d], wake);
                    }
                }
            },
        );
        self.wake_islands(bodies);
    }

    /// Puts to sleep each group of touching dynamic bodies that is ready: every body asleep
    /// or calm for `sleep.time` (none on a string), one at least awake, one at least touching
    /// a fixed sphere that does not move, none touching one that does, and no pair deeper
    /// into each other than [`SLEEP_CONTACT`] of the smaller radius.
    fn fall_asleep(&mut self, bodies: &mut [Body], solver: &mut Solver, sleep: Sleep) {
        let n = bodies.len();
        self.parent.clear();
        self.parent.extend(0..n as u32);
        self.flags.clear();
        self.flags.resize(n, 0);
        let (parent, flags) = (&mut self.parent, &mut self.flags);
        let view: &[Body] = bodies;
        solver.pairs_near(
            view,
            |b| SLEEP_CONTACT * b.radius(),
            |i, j| {
                let (a, b) = (&view[i], &view[j]);
                let near = SLEEP_CONTACT * a.radius().min(b.radius());
                let gap = gap(a, b.position(), b.radius());
                if gap > near {
                    return;
                }
                if gap < -near {
                    // Deeper than that, the pair is still being moved apart (without speed):
                    // not at rest.
                    flags[i] |= BLOCKED;
                    flags[j] |= BLOCKED;
                }
                // A body touching a fixed one rests on it, or is kept awake if it moves.
                let on = |fixed: &Body| {
                    if fixed.velocity() == DVec3::ZERO {
                        GROUNDED
                    } else {
                        BLOCKED
                    }
                };
                match (a.is_fixed(), b.is_fixed()) {
                    (false, false) => union(parent, i, j),
                    (true, false) => flags[j] |= on(a),
                    (false, true) => flags[i] |= on(b),
                    (true, true) => {}
                }
            },
        );
        // Each group's flags gathered at its root, a body not ready blocking it. A group's
        // root is its smallest index (see `union`), so it is met before its other bodies.
        for (i, (body, state)) in bodies.iter().zip(&self.states).enumerate() {
            if body.is_fixed() {
                continue;
            }
            let mut own = self.flags[i];
            if !body.asleep {
                own |= AWAKE;
                if !ready_to_sleep(state, sleep) {
                    own |= BLOCKED;
                }
            }
            let root = find(&mut self.parent, i);
            if root != i {
                self.flags[root] |= own;
            } else {
                self.flags[i] = own;
            }
        }
        self.new_island.clear();
        self.new_island.resize(n, 0);
        for (i, (body, state)) in bodies.iter_mut().zip(&mut self.states).enumerate() {
            if body.is_fixed() {
                continue;
            }
            let root = find(&mut self.parent, i);
            if self.flags[root] != GROUNDED | AWAKE {
                continue;
            }
            if self.new_island[root] == 0 {
                self.last_island += 1;
                self.new_island[root] = self.last_island;
            }
            self.asleep += usize::from(!body.asleep);
            self.generation += 1;
            body.asleep = true;
            state.island = self.new_island[root];
            body.desc.velocity = DVec3::ZERO;
            state.rest = body.desc.position;
            state.calm = 0.0;
        }
    }
}

/// Whether a body awake, in `state`, has been calm long enough to fall asleep: calm in the
/// last step (so `calm > 0`: with a sleeping time of 0, calm in that step alone), and for
/// `sleep.time`.
fn ready_to_sleep(state: &SleepState, sleep: Sleep) -> bool {
    state.calm > 0.0 && state.calm >= sleep.time
}

/// How far apart `body` and a sphere of `radius` at `centre` are (negative when they overlap).
fn gap(body: &Body, centre: DVec3, radius: f64) -> f64 {
    (body.position() - centre).length() - body.radius() - radius
}

fn find(parent: &mut [u32], mut i: usize) -> usize {
    while parent[i] as usize != i {
        let up = parent[parent[i] as usize];
        parent[i] = up;
        i = up as usize;
    }
    i
}

/// Joins the groups of `i` and `j`, the smaller root index becoming the root.
fn union(parent: &mut [u32], i: usize, j: usize) {
    let (a, b) = (find(parent, i), find(parent, j));
    let (low, high) = (a.min(b), a.max(b));
    parent[high] = low as u32;
}
