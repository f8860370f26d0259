//! The resting contacts: which touching pairs rest and how hard they are pressed, the guards
//! beside them, and the solve that keeps them all from closing at the step's start (projected
//! Gauss–Seidel, accelerated, warm-started), whose sweeps the fallback solve of a step whose
//! collision budget runs out (`fallback.rs`) runs too. Part of [`Solver`]: these are its
//! methods, kept apart from the event loop.

use glam::DVec3;

use super::*;
use crate::response::{MAX_EXACT_CONTACTS, compress_with_signed_biases};

/// The share of the smaller radius a contact may close beyond half its band (see
/// `Solver::excess`).
const DEEP: f64 = 0.01;

/// How many contacts ahead a sweep asks for their bodies (see `sweep_resting_once`), and the
/// warm start and the loads kept after the solve for their places in the table of loads (see
/// `warm_start`, `keep_resting_loads`).
const SWEEP_AHEAD: usize = 8;

/// A group of at most this many resting contacts (connected through dynamic bodies) that the
/// sweeps leave closing is solved exactly, however shallow (see
/// [`Solver::solve_small_groups_exactly`]).
const SMALL_GROUP: usize = 8;

impl Solver {
    /// Whether [`Solver::resting_contact`] may act on `(i, j)`: resting contacts are sought,
    /// and the pair touches (or both are fixed), or is near (see [`Solver::near`]) with a body
    /// that rested in the last step. A glance, inlined into the first pass, which spares most
    /// pairs the call.
    #[inline(always)]
    pub(super) fn may_rest(&self, i: usize, j: usize, ctx: &StepContext<'_>) -> bool {
        let (si, sj) = (&self.segments[i], &self.segments[j]);
        if si.is_fixed() && sj.is_fixed() {
            return true;
        }
        if self.resting_scale == 0.0 {
            return false;
        }
        let reach = si.radius() + sj.radius();
        let band = contact_band(si, sj, ctx.settings);
        let distance_squared = (sj.position - si.position).length_squared();
        let near = reach + band + self.near_reach;
        if distance_squared > near * near {
            return false;
        }
        distance_squared <= (reach + band) * (reach + band)
            || bit(&self.rested_here, i)
            || bit(&self.rested_here, j)
    }

    /// If `(i, j)` touch (within [`contact_band`]) and approach no faster than the
    /// resting speed, records them as a resting contact. A touching pair that is not one, or
    /// a near one, is listed in [`Solver::near`] for [`Solver::add_guards`].
    /// A pair overlapping deeper than half the creep distance also gets a separating speed
    /// that undoes the excess over the step: the resting solve converges only so far, and
    /// without it a leftover approach below the creep speed would sink a stack for ever.
    pub(super) fn resting_contact(&mut self, i: usize, j: usize, ctx: &StepContext<'_>) -> bool {
        let settings = ctx.settings;
        let (si, sj) = (&self.segments[i], &self.segments[j]);
        if si.is_fixed() && sj.is_fixed() {
            return true;
        }
        if self.resting_scale == 0.0 {
            return false;
        }
        let d = sj.position - si.position;
        let reach = si.radius() + sj.radius();
        let band = contact_band(si, sj, settings);
        let distance_squared = d.length_squared();
        let near = if bit(&self.rested_here, i) || bit(&self.rested_here, j) {
            reach + band + self.near_reach
        } else {
            reach + band
        };
        if distance_squared > near * near {
            return false;
        }
        let distance = distance_squared.sqrt();
        // Two spheres at the same point (spawned together) have no normal: they part along x,
        // as where nothing accelerates (see `separate.rs`).
        let normal = if distance_squared == 0.0 {
            DVec3::X
        } else {
            d / distance
        };
        if distance > reach + band {
            self.near.push((i as u32, j as u32, normal, distance));
            return false;
        }
        let approach = -(sj.velocity - si.velocity).dot(normal);
        // Separating as slowly as a resting pair may approach counts too: in a stack all fall
        // together at the start of the step, and only the solve shows which contacts hold.
        let smaller = si.radius().min(sj.radius());
        let rests = |press: f64| {
            let bias = self.correction(reach - distance, band, press, smaller, ctx);
            let window = self.resting_scale * press;
            let out = approach < -(window + bias) || approach > window;
            (!(out || (window == 0.0 && bias == 0.0)), bias)
        };
        let mut press = pressing(self.extra(i), self.extra(j), normal);
        let (mut resting, mut bias) = rests(press);
        if !resting && self.sustained(i, j) {
            // A contact that took a load in the last step is pressed by the weight whichever
            // way it points: in a pile the weight pushes sideways too, through the neighbours.
            press = self.start_press(i, j, normal);
            (resting, bias) = rests(press);
        }
        if !resting {
            // Not resting: if the solve would push it together, a guard (see `add_guards`).
            self.near.push((i as u32, j as u32, normal, distance));
            return false;
        }
        self.tested.push((i as u32, j as u32));
        self.push_resting(i as u32, j as u32, normal, bias, press, false);
        true
    }

    /// Adds pair `(a, b)` (solver indices, `a < b`) to the resting contacts, with no impulse
    /// yet.
    pub(super) fn push_resting(
        &mut self,
        a: u32,
        b: u32,
        normal: DVec3,
        bias: f64,
        press: f64,
        speculative: bool,
    ) {
        let (inverse_mass_a, inverse_mass_b) = (
            self.extra(a as usize).inverse_mass,
            self.extra(b as usize).inverse_mass,
        );
        self.resting.push(RestingContact {
            a,
            b,
            normal,
            impulse: 0.0,
            inverse_mass_a,
            inverse_mass_b,
            mass: 1.0 / (inverse_mass_a + inverse_mass_b),
            bias,
            press,
            speculative,
            before: 0.0,
            direction: 0.0,
        });
    }

    /// Whether touching pair `(i, j)` took an impulse in the last step's resting solve.
    pub(super) fn sustained(&self, i: usize, j: usize) -> bool {
        let rested = |k: usize| self.segments[k].is_fixed() || bit(&self.rested_here, k);
        if self.warm.is_empty() || !(rested(i) && rested(j)) {
            return false;
        }
        let (a, b) = (self.extra(i).id, self.extra(j).id);
        self.warm.get(a.min(b), a.max(b)).is_some()
    }

    /// Adds to the resting contacts, as guards, the pairs that are not resting contacts but
    /// touch or nearly touch (see [`Solver::near`]) and have a body in a resting contact: each
    /// may approach as fast as it does now, or as fast as ends the step half the contact band
    /// apart, whichever is faster. A guard takes an impulse only if the solve itself pushes
    /// its pair together (in a pile, a sphere pushed sideways by the spheres it rests on,
    /// towards a wall a hair away), never against a pair meeting of its own accord (two balls
    /// rolling into each other on a floor meet with their restitution), unless it closes at
    /// a resting speed for its pair's press and is against a fixed sphere, or contacts push
    /// against overlaps (see [`Solver::hold_guards`]).
    pub(super) fn add_guards(&mut self, ctx: &StepContext<'_>) {
        if self.near.is_empty() {
            return;
        }
        self.clear_touched();
        for k in 0..self.resting.len() {
            let c = self.resting[k];
            self.touch(c.a);
            self.touch(c.b);
        }
        for n in 0..self.near.len() {
            let (i, j, normal, distance) = self.near[n];
            let (a, b) = (i as usize, j as usize);
            if !(self.is_touched(a) || self.is_touched(b)) {
                continue;
            }
            let (sa, sb) = (&self.segments[a], &self.segments[b]);
            let reach = sa.radius() + sb.radius();
            let band = contact_band(sa, sb, ctx.settings);
            let approach = -(sb.velocity - sa.velocity).dot(normal);
            let allowed = approach.max(((distance - reach - 0.5 * band) / ctx.dt).max(0.0));
            let press = self.start_press(a, b, normal);
            if allowed > self.resting_scale * press {
                continue;
            }
            self.push_resting(i, j, normal, -allowed, press, distance > reach + band);
        }
        self.clear_touched();
    }

    /// The separating speed that undoes, over a step, the part of a resting pair's `overlap`
    /// deeper than a quarter of the creep distance (plus the contact `band`), at most
    /// [`MAX_CORRECTION`] of the `smaller` radius a step: an overlap as deep as a sphere (one
    /// placed inside others) is undone over steps, and one that no velocity can undo (a sphere
    /// overlapping fixed ones on opposite sides) cannot fling its sphere away.
    pub(super) fn correction(
        &self,
        overlap: f64,
        band: f64,
        press: f64,
        smaller: f64,
        ctx: &StepContext<'_>,
    ) -> f64 {
        let slop = 0.25 * self.creep_scale * press * ctx.dt + band;
        ((overlap - slop).max(0.0) / ctx.dt).min(MAX_CORRECTION * smaller / ctx.dt)
    }

    /// Whether a contact's push against its overlap, `bias`, is a deep overlap's, not a
    /// stack's creep: faster than the resting speed, or than half its cap (see
    /// [`Solver::correction`]; `smaller` is the smaller radius). Such a push is solved apart
    /// from the contacts' load, within the bodies' budgets (see [`Solver::push_left`]), by the
    /// resting solve, by impacts solved together, and by the fallback; the resting solve's
    /// and the fallback's are taken off at the step's end, leaving no speed.
    pub(super) fn deep_push(&self, bias: f64, smaller: f64, ctx: &StepContext<'_>) -> bool {
        bias > self
            .resting_speed
            .min(0.5 * MAX_CORRECTION * smaller / ctx.dt)
    }

    /// What is left this step of segment `k`'s push budget: the most its velocity may still
    /// be changed by pushes against overlaps, a speed. A body may be pushed
    /// [`MAX_CORRECTION`] of its radius a step in all by the pushes solved apart from the load
    /// (the resting solve's and the fallback's, less what a push ended early did not use),
    /// single resting impacts' pushes and the deep pushes of impacts solved together. A
    /// stack's creep, solved with the load (in the resting solve and in a group of impacts),
    /// is not counted, nor the resting solve's pushes in a step with strings (they stay in
    /// the velocities).
    pub(super) fn push_left(&self, k: usize, ctx: &StepContext<'_>) -> f64 {
        let cap = MAX_CORRECTION * self.segments[k].radius() / ctx.dt;
        if bit(&self.spent_bits, k) {
            (cap - self.spent[k]).max(0.0)
        } else {
            cap
        }
    }

    /// Counts a push of `speed` on segment `k` against its budget (see [`Solver::push_left`]).
    pub(super) fn spend_push(&mut self, k: usize, speed: f64) {
        if speed <= 0.0 {
            return;
        }
        let (word, mask) = (k / 64, 1u64 << (k % 64));
        if self.spent_bits[word] & mask == 0 {
            self.spent_bits[word] |= mask;
            self.spent[k] = 0.0;
        }
        self.spent[k] += speed;
    }

    /// Resolves a group of impacts (in [`Solver::local_contacts`]) some of whose resting
    /// contacts push against deep overlaps (see [`Solver::deep_push`]; a stack's creep is
    /// solved with the load), as [`resolve_simultaneous`] does, in two parts:
    /// first without the pushes, then the pushes alone on top (restitution 0), scaled down
    /// until no body is pushed faster than what is left of its push budget (see
    /// [`Solver::push_left`]). Contacts on nearly opposite sides (a ball fallen into a gap
    /// narrower than it) part at their pushes only along their normals' small difference, many
    /// times faster: solved whole, a ball of radius 0.5 dropped at 2 m/s between two fixed
    /// spheres of radius 3 that it overlapped left at 28 m/s. Momentum is kept: the pushes'
    /// impulses are scaled together.
    pub(super) fn resolve_pushing_group(&mut self, ctx: &StepContext<'_>) {
        self.local_biases.clear();
        for c in &mut self.local_contacts {
            self.local_biases.push(c.bias);
            c.bias = 0.0;
        }
        resolve_simultaneous(
            &self.local_inverse_masses,
            &mut self.local_velocities,
            &self.local_contacts,
            &mut self.local_impulses,
        );
        self.local_shifts.clear();
        self.local_shifts.extend_from_slice(&self.local_velocities);
        for (c, &bias) in self.local_contacts.iter_mut().zip(&self.local_biases) {
            c.bias = bias;
        }
        self.resolve_local_again();
        // The largest scale that keeps every body within its budget.
        let mut scale = 1.0f64;
        for (i, &k) in self.local_bodies.iter().enumerate() {
            let push = (self.local_velocities[i] - self.local_shifts[i]).length();
            if push > 0.0 {
                scale = scale.min(self.push_left(k as usize, ctx) / push);
            }
        }
        if scale < 1.0 {
            for (velocity, &unpushed) in self.local_velocities.iter_mut().zip(&self.local_shifts) {
                *velocity = unpushed + (*velocity - unpushed) * scale;
            }
        }
        for (impulse, &first) in self
            .local_impulses
            .iter_mut()
            .zip(&self.local_first_impulses)
        {
            *impulse = first + *impulse * scale;
        }
        for i in 0..self.local_bodies.len() {
            let push = (self.local_velocities[i] - self.local_shifts[i]).length();
            self.spend_push(self.local_bodies[i] as usize, push);
        }
    }

    /// The fallback's finishing sweeps (see [`Solver::fall_back`]): on while any contact
    /// would end the `rest` of the step deeper than it is allowed (see `fallback_excess`), up
    /// to [`FALLBACK_FINISH_SWEEPS`], and until four batches leave that no smaller, by
    /// [`FINISH_PROGRESS`] of it, than the batch before. A batch that leaves it that much below
    /// the least yet starts the count again; one that leaves it that much below the batch
    /// before, but not below the least, neither counts nor starts it again (a long chain's
    /// rises at first, then falls, and may swing). Returns whether it swept at all.
    pub(super) fn finish_sweeps(
        &mut self,
        threshold: f64,
        rest: f64,
        ctx: &StepContext<'_>,
    ) -> bool {
        let (mut finishing, mut stalled) = (0, 0);
        let mut excess = self.fallback_excess(rest, ctx);
        let mut least = excess;
        let keep = 1.0 - FINISH_PROGRESS;
        while finishing < FALLBACK_FINISH_SWEEPS && excess > 0.0 && stalled < 4 {
            self.sweep_resting(threshold, FALLBACK_LATER_SWEEPS, rest, ctx);
            finishing += FALLBACK_LATER_SWEEPS;
            let left = self.fallback_excess(rest, ctx);
            if left < least * keep {
                stalled = 0;
            } else if left >= excess * keep {
                stalled += 1;
            }
            least = least.min(left);
            excess = left;
        }
        finishing > 0
    }

    /// When the resting contacts' sweeps have converged: no impulse changes a relative speed
    /// by more than a billionth of the largest resting speed among them.
    pub(super) fn sweep_threshold(&self) -> f64 {
        1e-9 * self
            .resting
            .iter()
            .map(|c| self.resting_scale * c.press)
            .fold(0.0, f64::max)
    }

    /// After the sweeps: each connected group of resting contacts (through dynamic bodies) of
    /// 2 to [`MAX_EXACT_CONTACTS`] contacts that the sweeps leave closing deeper than tolerated
    /// over the `rest` of the step (half the band and a hundredth of the smaller radius: see
    /// [`Solver::excess`]) is solved exactly instead, by pivoting, from the velocities
    /// before the sweeps' impulses. Gauss–Seidel converges at a rate set by the masses' ratio:
    /// a ball of 100 kg resting on a pebble of 3 g on a floor sank through it (a sweep carries
    /// the load on by a share of the order of the ratio, 3e-5 there), and a pebble squeezed
    /// between two such balls closing on it ended the fallback's solve 1.2 cm into one and was
    /// pushed all the way in by later steps. In the fallback with nothing accelerating (no
    /// resting solve in the steps after it), a group is solved once any of its contacts would
    /// close by more than half its band: the sweeps left that pebble's balls closing at 0.9
    /// mm/s, so it bounced between them again in every step, each spending the budget.
    /// Larger groups (a pile) keep the sweeps' answer, as does a
    /// group whose exact solve finds none (rounding). With `pushes`, the contacts' pushes
    /// against overlaps are met in full (the resting solve then checks that none sent a body
    /// off too fast, and solves them apart if one did: `pushed_too_fast`); without (the
    /// fallback, which has no such check), only their allowed approaches are: pushes met in
    /// full on nearly opposite sides of a sphere part it many times faster than either. Not
    /// run where the resting solve solves its pushes apart (a deep overlap somewhere, or
    /// pushes that sent a body off too fast: see `solve_pushes`). Returns whether it solved
    /// any group.
    pub(super) fn solve_deep_groups_exactly(
        &mut self,
        rest: f64,
        pushes: bool,
        ctx: &StepContext<'_>,
    ) -> bool {
        // With nothing accelerating, no resting solve stops what the fallback leaves closing
        // in the steps after: close by more than half the band, and the group is solved.
        let deep_fraction = if pushes || !self.nothing_accelerates {
            DEEP
        } else {
            0.0
        };
        let deep =
            |solver: &Self, c: &RestingContact| solver.excess(c, rest, deep_fraction, ctx) > 0.0;
        if !self.resting.iter().any(|c| deep(self, c)) {
            return false;
        }
        let mut events = std::mem::take(&mut self.exact.events);
        let mut ranges = std::mem::take(&mut self.exact.ranges);
        let mut solved = false;
        events.clear();
        events.extend(self.resting.iter().enumerate().map(|(i, c)| Event {
            time: 0.0,
            a: c.a,
            b: c.b,
            version_a: i as u32,
            version_b: 0,
        }));
        sort_into_components(
            &mut events,
            &mut ranges,
            &mut self.components,
            moving(&self.segments),
        );
        for range in ranges.iter().cloned() {
            let group = &events[range];
            if (2..=MAX_EXACT_CONTACTS).contains(&group.len())
                && group
                    .iter()
                    .any(|e| deep(self, &self.resting[e.version_a as usize]))
            {
                self.solve_resting_group_exactly(group, pushes);
                solved = true;
            }
        }
        self.exact.events = events;
        self.exact.ranges = ranges;
        solved
    }

    /// After the sweeps and [`Solver::solve_deep_groups_exactly`]: each connected group of 2
    /// to [`SMALL_GROUP`] resting contacts that the sweeps leave closing by more than half a
    /// contact's band over the step, and in which no contact pushes against an overlap, is
    /// solved exactly (from the velocities before the sweeps' impulses). Gauss–Seidel carries
    /// a load through a light sphere by a share of the order of the masses' ratio a sweep: a
    /// ball of 0.1 to 0.3 kg on a pebble of 3 g (and on a column of up to five) sank a
    /// hundredth of its radius into it, just short of what calls for the solve of
    /// [`Solver::solve_deep_groups_exactly`], and stayed there. Small groups only: a bed's
    /// sweeps stay as they are. Groups whose contacts push are left to that trigger (solved
    /// with their pushes at this one, a pit of 50 with densities from 1 to 10 000 sank 98.6 mm
    /// into itself), and so is the fallback (where this trigger sent a ball sliding into a gap
    /// it overlaps up at 0.48 m/s). The groups are found by a union–find over the bodies,
    /// without sorting every contact (a sort of the pile of 1000's 3700 contacts each step cost
    /// it 7%), or taken from [`Solver::order_resting`] when it found them (`joined`).
    pub(super) fn solve_small_groups_exactly(
        &mut self,
        rest: f64,
        joined: bool,
        ctx: &StepContext<'_>,
    ) {
        let mut g = std::mem::take(&mut self.small_groups);
        if !joined {
            g.join(&self.resting, self.segments.len());
        }
        let group_of = SmallGroups::group_of;
        let mut any = false;
        for c in &self.resting {
            let r = group_of(&mut g.parent, c);
            let closing = self.excess(c, rest, 0.0, ctx) > 0.0;
            let tally = &mut g.tally[r];
            tally.count += 1;
            tally.pushing |= c.bias > 0.0;
            tally.closing |= closing;
            any |= closing;
        }
        if !any {
            self.small_groups = g;
            return;
        }
        g.events.clear();
        for (i, c) in self.resting.iter().enumerate() {
            let r = group_of(&mut g.parent, c);
            let tally = g.tally[r];
            if (2..=SMALL_GROUP).contains(&(tally.count as usize))
                && tally.closing
                && !tally.pushing
            {
                // The contact in `version_a` (as `solve_resting_group_exactly` takes it), its
                // group's root in `version_b`, to sort by.
                g.events.push(Event {
                    time: 0.0,
                    a: c.a,
                    b: c.b,
                    version_a: i as u32,
                    version_b: r as u32,
                });
            }
        }
        g.events
            .sort_unstable_by_key(|e| (e.version_b, e.version_a));
        let mut start = 0;
        while start < g.events.len() {
            let group = g.events[start].version_b;
            let end = start
                + g.events[start..]
                    .iter()
                    .take_while(|e| e.version_b == group)
                    .count();
            self.solve_resting_group_exactly(&g.events[start..end], true);
            start = end;
        }
        self.small_groups = g;
    }

    /// [`Solver::solve_deep_groups_exactly`] for one group (its contacts are the resting
    /// contacts `e.version_a` of `group`), in scratch of its own (the resting solve's pushes
    /// keep their bodies' places in `local_index` meanwhile).
    fn solve_resting_group_exactly(&mut self, group: &[Event], pushes: bool) {
        self.exact.gather(
            &self.resting,
            &self.segments,
            group.iter().map(|e| e.version_a as usize),
            |c| if pushes { c.bias } else { c.bias.min(0.0) },
        );
        let x = &mut self.exact;
        if compress_with_signed_biases(
            &x.inverse_masses,
            &x.velocities,
            &x.contacts,
            None,
            &mut x.impulses,
        ) {
            apply_impulses(
                &x.contacts,
                &x.impulses,
                &x.inverse_masses,
                &mut x.velocities,
            );
            for (i, e) in group.iter().enumerate() {
                self.resting[e.version_a as usize].impulse = x.impulses[i].max(0.0);
            }
            for (i, &k) in x.bodies.iter().enumerate() {
                if x.inverse_masses[i] > 0.0 {
                    self.segments[k as usize].velocity = x.velocities[i];
                }
            }
        }
    }

    /// How much deeper than allowed the fallback's contacts would end the `rest` of the step,
    /// beyond half their band and a hundredth of the smaller radius: the sum over those that
    /// would (0 when none does).
    fn fallback_excess(&self, rest: f64, ctx: &StepContext<'_>) -> f64 {
        self.resting
            .iter()
            .map(|c| self.excess(c, rest, DEEP, ctx))
            .sum()
    }

    /// How much deeper than allowed contact `c` would end the `rest` of the step, beyond half
    /// its band and `deep` of the smaller radius (0 if it would not).
    fn excess(&self, c: &RestingContact, rest: f64, deep: f64, ctx: &StepContext<'_>) -> f64 {
        let (sa, sb) = (&self.segments[c.a as usize], &self.segments[c.b as usize]);
        let speed = (sb.velocity - sa.velocity).dot(c.normal) - c.bias;
        let tolerated =
            0.5 * contact_band(sa, sb, ctx.settings) + deep * sa.radius().min(sb.radius());
        (-speed * rest - tolerated).max(0.0)
    }

    /// Touches the bodies of every resting contact that took an impulse, and records those
    /// that touch (not the guards still apart) as resting collisions at time `t` of the step.
    pub(super) fn record_resting(&mut self, t: f64, ctx: &StepContext<'_>, stats: &mut StepStats) {
        self.clear_touched();
        let resting = std::mem::take(&mut self.resting);
        for c in resting.iter().filter(|c| c.impulse > 0.0) {
            self.touch(c.a);
            self.touch(c.b);
            if c.speculative {
                continue;
            }
            stats.collisions = stats.collisions.saturating_add(1);
            stats.resting_contacts = stats.resting_contacts.saturating_add(1);
            let ends = (c.a as usize, c.b as usize);
            self.record_collision(ends, t, c.normal, c.impulse, true, ctx);
        }
        self.resting = resting;
    }

    /// Orders the resting contacts by group (connected through dynamic bodies; see
    /// [`SmallGroups`]), each group's lowest first along gravity: a forward sweep carries a
    /// bed's weight down to its floor, the backward one after it carries the floor's push back
    /// up. Groups share no body whose velocity a sweep changes, so their order among one
    /// another changes nothing in any group's solve but the rounding of the sweeps' sums; in
    /// the order of their lowest body, which is the bodies' order in memory (spheres lying on
    /// a floor each rest alone: ordered by height, their contacts reached their bodies
    /// anywhere in memory, in every pass over them). Returns whether it ordered them, and so
    /// left their groups in [`Solver::small_groups`].
    pub(super) fn order_resting(&mut self, ctx: &StepContext<'_>) -> bool {
        if ctx.settings.gravity == DVec3::ZERO {
            return false;
        }
        let up = -ctx.settings.gravity;
        let mut g = std::mem::take(&mut self.small_groups);
        g.join(&self.resting, self.segments.len());
        // Sorted as small keys (each contact's group, its height worked out once, in
        // `f64::total_cmp`'s order, its pair, then its place) and gathered once, not moved
        // about whole (104 bytes) by the sort.
        self.resting_keys.clear();
        for (n, c) in self.resting.iter().enumerate() {
            let group = SmallGroups::group_of(&mut g.parent, c) as u32;
            let a = &self.segments[c.a as usize];
            let bits = (a.position + c.normal * a.radius()).dot(up).to_bits() as i64;
            let height = bits ^ (((bits >> 63) as u64) >> 1) as i64;
            let pair = (u64::from(c.a) << 32) | u64::from(c.b);
            self.resting_keys.push((group, height, pair, n as u32));
        }
        self.small_groups = g;
        self.sort_resting_keys();
        self.resting_sorted.clear();
        self.resting_sorted.extend(
            self.resting_keys
                .iter()
                .map(|&(_, _, _, n)| self.resting[n as usize]),
        );
        std::mem::swap(&mut self.resting, &mut self.resting_sorted);
        true
    }

    /// Sorts [`Solver::resting_keys`] (unique: each ends with its contact's place). Where the
    /// contacts are many for the bodies (a quarter as many or more), placed by group first (a
    /// counting sort over the bodies, in O(contacts + bodies)), then each group of more than
    /// one sorted on its own: the same order as one sort of all (on a table of 1000, whose
    /// spheres each rest in a group of one to three contacts, the sort was a tenth of the
    /// step).
    fn sort_resting_keys(&mut self) {
        let (keys, bodies) = (self.resting_keys.len(), self.segments.len());
        if keys < 64 || 4 * keys < bodies {
            self.resting_keys.sort_unstable();
            return;
        }
        place_by_bucket(
            &self.resting_keys,
            |key| key.0 as usize,
            bodies,
            &mut self.group_start,
            &mut self.resting_keys_placed,
        );
        let placed = &mut self.resting_keys_placed;
        let mut from = 0;
        while from < keys {
            let to = self.group_start[placed[from].0 as usize + 1] as usize;
            if to - from > 1 {
                placed[from..to].sort_unstable();
            }
            from = to;
        }
        std::mem::swap(&mut self.resting_keys, &mut self.resting_keys_placed);
    }

    /// Finds the resting sweeps' blocks: a body much lighter than a dynamic one it rests
    /// against ([`BLOCK_RATIO`]) has its contacts solved together, exactly, in each block
    /// sweep (those not owned by a lighter such body). Returns whether there are any.
    fn find_blocks(&mut self) -> bool {
        // A strung sphere's contacts stay in the plain sweeps: its string bends its velocity
        // after the solve, which holds no string.
        let free = |solver: &Self, c: &RestingContact| {
            !solver.strings
                || (solver.string_of(c.a as usize).is_none()
                    && solver.string_of(c.b as usize).is_none())
        };
        let light = |solver: &Self, c: &RestingContact| much_lighter(c) && free(solver, c);
        let mut x = std::mem::take(&mut self.exact);
        x.block_of.clear();
        x.block_starts.clear();
        x.block_members.clear();
        if !self.resting.iter().any(|c| light(self, c)) {
            self.exact = x;
            return false;
        }
        if x.owner_block.len() < self.segments.len() {
            x.owner_block.resize(self.segments.len(), NOT_LOCAL);
        }
        // Owners get a mark first (u32::MAX - 1), then a block each as their contacts come.
        const OWNER: u32 = NOT_LOCAL - 1;
        for c in self.resting.iter().filter(|c| light(self, c)) {
            let owner = if c.inverse_mass_a > c.inverse_mass_b {
                c.a
            } else {
                c.b
            };
            x.owner_block[owner as usize] = OWNER;
        }
        let mut blocks = 0u32;
        for c in &self.resting {
            let (oa, ob) = if free(self, c) {
                (
                    x.owner_block[c.a as usize] != NOT_LOCAL,
                    x.owner_block[c.b as usize] != NOT_LOCAL,
                )
            } else {
                (false, false)
            };
            let owner = match (oa, ob) {
                (false, false) => {
                    x.block_of.push(NOT_LOCAL);
                    continue;
                }
                (true, false) => c.a,
                (false, true) => c.b,
                (true, true) if c.inverse_mass_b > c.inverse_mass_a => c.b,
                (true, true) => c.a,
            };
            let slot = &mut x.owner_block[owner as usize];
            if *slot == OWNER {
                *slot = blocks;
                blocks += 1;
            }
            x.block_of.push(*slot);
        }
        // Each block's members, in the sweep's order (a counting sort).
        x.block_starts.resize(blocks as usize + 1, 0);
        for &b in x.block_of.iter().filter(|&&b| b != NOT_LOCAL) {
            x.block_starts[b as usize + 1] += 1;
        }
        for b in 0..blocks as usize {
            x.block_starts[b + 1] += x.block_starts[b];
        }
        x.block_members
            .resize(x.block_starts[blocks as usize] as usize, 0);
        // Each member to its block's next place (`block_starts[b]` counts up to block `b + 1`'s
        // start as it fills, and is moved back after).
        for (k, &b) in x.block_of.iter().enumerate() {
            if b != NOT_LOCAL {
                let at = &mut x.block_starts[b as usize];
                x.block_members[*at as usize] = k as u32;
                *at += 1;
            }
        }
        x.block_starts.rotate_right(1);
        x.block_starts[0] = 0;
        for c in &self.resting {
            x.owner_block[c.a as usize] = NOT_LOCAL;
            x.owner_block[c.b as usize] = NOT_LOCAL;
        }
        self.exact = x;
        true
    }

    /// Solves block `b`'s contacts (see [`Solver::find_blocks`]) together, exactly, from the
    /// velocities without their impulses; point by point if the exact solve finds no answer.
    /// Returns the largest change of a relative speed and the impulses' squared change since
    /// `before`, as a sweep counts them.
    #[inline(never)]
    fn sweep_block(&mut self, b: usize, restarted: bool, threshold: f64) -> (f64, f64) {
        let members = self.exact.block_starts[b] as usize..self.exact.block_starts[b + 1] as usize;
        if restarted {
            for &m in &self.exact.block_members[members.clone()] {
                let c = &mut self.resting[m as usize];
                c.direction = c.impulse - c.before;
                c.before = c.impulse;
            }
        }
        let x = &self.exact;
        // Nothing to do where no contact of the block would move by more than `threshold`
        // on its own (a bed at rest, after its first sweeps).
        let settled = members.clone().all(|m| {
            let c = &self.resting[x.block_members[m] as usize];
            let speed = (self.segments[c.b as usize].velocity
                - self.segments[c.a as usize].velocity)
                .dot(c.normal)
                - c.bias;
            let next = (c.impulse - speed * c.mass).max(0.0);
            ((next - c.impulse) * (c.inverse_mass_a + c.inverse_mass_b)).abs() <= threshold
        });
        if settled {
            let change = members
                .map(|m| {
                    let c = &self.resting[x.block_members[m] as usize];
                    (c.impulse - c.before) * (c.impulse - c.before)
                })
                .sum();
            return (0.0, change);
        }
        // (The block's list out of the scratch while the scratch is filled.)
        let listed = std::mem::take(&mut self.exact.block_members);
        self.exact.gather(
            &self.resting,
            &self.segments,
            listed[members.clone()].iter().map(|&m| m as usize),
            |c| c.bias,
        );
        self.exact.block_members = listed;
        let x = &mut self.exact;
        // Pivoting from the contacts pushing now (a block's set changes little from sweep to
        // sweep).
        let exact = members.len() <= MAX_EXACT_CONTACTS && {
            let guess = x.block_members[members.clone()]
                .iter()
                .enumerate()
                .filter(|&(_, &m)| self.resting[m as usize].impulse > 0.0)
                .fold(0u64, |bits, (i, _)| bits | 1 << i);
            compress_with_signed_biases(
                &x.inverse_masses,
                &x.velocities,
                &x.contacts,
                Some(guess),
                &mut x.impulses,
            )
        };
        let (mut largest, mut change) = (0.0f64, 0.0f64);
        for (i, m) in members.enumerate() {
            let c = &mut self.resting[x.block_members[m] as usize];
            let (a, bb) = (c.a as usize, c.b as usize);
            let (ima, imb) = (c.inverse_mass_a, c.inverse_mass_b);
            // (The sweep's own update, written out again: shared through a helper, the pit of
            // 1000 at rest took 1% to 2% longer, five alternating runs of five.)
            let next = if exact {
                x.impulses[i].max(0.0)
            } else {
                let speed =
                    (self.segments[bb].velocity - self.segments[a].velocity).dot(c.normal) - c.bias;
                (c.impulse - speed * c.mass).max(0.0)
            };
            let step = next - c.impulse;
            c.impulse = next;
            if ima != 0.0 {
                self.segments[a].velocity -= c.normal * (step * ima);
            }
            if imb != 0.0 {
                self.segments[bb].velocity += c.normal * (step * imb);
            }
            largest = largest.max((step * (ima + imb)).abs());
            let moved = c.impulse - c.before;
            change += moved * moved;
        }
        (largest, change)
    }

    /// Sweeps over the resting contacts (projected Gauss–Seidel, accelerated) until no
    /// impulse changes a relative speed by more than `threshold`, or `sweeps` times; then, if
    /// a contact would still close deeper than tolerated over the `rest` of the step (see
    /// [`Solver::excess`]) and some sphere is much lighter than one it rests against (see
    /// [`Solver::find_blocks`]), up to [`BLOCK_SWEEPS`] sweeps more with such spheres'
    /// contacts solved together. (Where the plain sweeps hold, as in a bed of one density,
    /// they cost nothing more: with blocks in every sweep, a pit of 400 with densities from 1
    /// to 100 took 1.5 to 2 times as long, for overlaps 0.5 to 0.6 mm instead of 0.5 to 0.9.)
    pub(super) fn sweep_resting(
        &mut self,
        threshold: f64,
        sweeps: u32,
        rest: f64,
        ctx: &StepContext<'_>,
    ) {
        self.sweep_resting_once::<false>(threshold, sweeps);
        // (The masses first: a bed of one density has no block, and is not asked for its
        // excess.)
        if self.resting.iter().any(much_lighter)
            && self
                .resting
                .iter()
                .any(|c| self.excess(c, rest, DEEP, ctx) > 0.0)
            && self.find_blocks()
        {
            self.sweep_resting_once::<true>(threshold, sweeps.min(BLOCK_SWEEPS));
        }
    }

    /// [`Solver::sweep_resting`]'s sweeps, with `BLOCKS` (found) or without (a loop of its
    /// own, as fast as before blocks: with a test per contact the pit of 1000 at rest took 4%
    /// longer).
    fn sweep_resting_once<const BLOCKS: bool>(&mut self, threshold: f64, sweeps: u32) {
        let count = self.resting.len();
        for c in &mut self.resting {
            c.before = c.impulse;
        }
        let mut last_change = 0.0f64;
        // The acceleration restarted after the last sweep (see below): each contact's
        // direction is its last change, and its start the impulse now, set as the sweep
        // reaches it. No velocity changes, so the sweep is the same as after a pass of its
        // own over every contact (a pit at rest restarts after a third of its sweeps).
        let mut restarted = false;
        for sweep in 0..sweeps {
            let mut largest = 0.0f64;
            // How far the sweep moved the impulses (squared), for the acceleration below.
            let mut change = 0.0f64;
            // Forward and backward in turn (symmetric Gauss–Seidel): a load carried down a
            // stack reaches its base in one pair of sweeps whichever way the stack is listed.
            for k in 0..count {
                let k = if sweep % 2 == 0 { k } else { count - 1 - k };
                // Ask for the bodies of the contact a few ahead in the sweep's order: ordered
                // by height within their group, a large bed's contacts reach their bodies
                // anywhere in memory.
                let ahead = if sweep % 2 == 0 {
                    k + SWEEP_AHEAD
                } else {
                    k.wrapping_sub(SWEEP_AHEAD)
                };
                if let Some(c) = self.resting.get(ahead) {
                    prefetch(&self.segments[c.a as usize]);
                    prefetch(&self.segments[c.b as usize]);
                }
                if BLOCKS {
                    let b = self.exact.block_of[k];
                    if b != NOT_LOCAL {
                        // At its first contact in the sweep's order.
                        let first = if sweep % 2 == 0 {
                            self.exact.block_members[self.exact.block_starts[b as usize] as usize]
                        } else {
                            self.exact.block_members
                                [self.exact.block_starts[b as usize + 1] as usize - 1]
                        };
                        if first as usize == k {
                            let (l, m) = self.sweep_block(b as usize, restarted, threshold);
                            largest = largest.max(l);
                            change += m;
                        }
                        continue;
                    }
                }
                let c = &mut self.resting[k];
                if restarted {
                    c.direction = c.impulse - c.before;
                    c.before = c.impulse;
                }
                let (a, b) = (c.a as usize, c.b as usize);
                let (ima, imb) = (c.inverse_mass_a, c.inverse_mass_b);
                let speed =
                    (self.segments[b].velocity - self.segments[a].velocity).dot(c.normal) - c.bias;
                let next = (c.impulse - speed * c.mass).max(0.0);
                let step = next - c.impulse;
                // Applied even when 0 (a contact held at no impulse, or unchanged): whether it
                // is is a coin toss the branch predictor lost, and adding a zero leaves the
                // velocities' values as they were, a zero's sign aside (the pit of 1000 at
                // rest 7% faster, the benchmarks' digests the same).
                // A fixed body's is never written: its contacts would wait on one another.
                c.impulse = next;
                if ima != 0.0 {
                    self.segments[a].velocity -= c.normal * (step * ima);
                }
                if imb != 0.0 {
                    self.segments[b].velocity += c.normal * (step * imb);
                }
                largest = largest.max((step * (ima + imb)).abs());
                let moved = c.impulse - c.before;
                change += moved * moved;
            }
            if largest <= threshold {
                break;
            }
            // Accelerated (nonsmooth nonlinear conjugate gradients, see `conjugate_factor`):
            // Gauss–Seidel alone crawls on a wedged bed (a pit of 1000 spheres still moved by
            // 1e-3 m/s a sweep after 4096 sweeps).
            let beta = conjugate_factor(change, last_change);
            last_change = change;
            restarted = beta.is_none();
            if restarted {
                continue;
            }
            for c in &mut self.resting {
                let next = conjugate_step(c.impulse, c.impulse - c.before, &mut c.direction, beta);
                let extra = next - c.impulse;
                c.impulse = next;
                let (a, b) = (c.a as usize, c.b as usize);
                if c.inverse_mass_a != 0.0 {
                    self.segments[a].velocity -= c.normal * (extra * c.inverse_mass_a);
                }
                if c.inverse_mass_b != 0.0 {
                    self.segments[b].velocity += c.normal * (extra * c.inverse_mass_b);
                }
                c.before = c.impulse;
            }
        }
    }

    /// Solves all resting contacts at once (projected Gauss–Seidel, restitution 0), then marks
    /// the bodies it changed as touched.
    pub(super) fn solve_resting(&mut self, ctx: &StepContext<'_>, stats: &mut StepStats) {
        let threshold = self.sweep_threshold();
        let joined = self.order_resting(ctx);
        self.push_saved.clear();
        let pushing = self.resting.iter().any(|c| c.bias > 0.0);
        if pushing {
            self.save_push_bodies();
        }
        // A guard closing at a resting speed of its own accord is held as a resting contact
        // (against a fixed sphere always, any guard while contacts push): its meeting would
        // stop it a moment later. (A small ball pushed out of one large sphere towards
        // another a hair away sank back as much as it rose, every other step; resting on one
        // side of a narrow gap a hair from the other, a ball rocked between the two, each
        // meeting a resting impact on its own.)
        self.hold_guards(pushing, ctx);
        // A push faster than a resting speed or half its cap (a deep overlap, not a stack's
        // creep) is solved apart and leaves no speed; so are slower ones that sent a body off
        // faster than a push may (contacts on nearly opposite sides). (Solved with the load,
        // pushes on nearly opposite sides of a small sphere, each below the resting speed,
        // took impulses that cancelled, and the next step's warm start from them, its normals
        // turned a little, sent it off.)
        // (Only a contact that pushes can push deeply: the others' bodies are not read.)
        if pushing
            && self.resting.iter().any(|c| {
                c.bias > 0.0 && {
                    let smaller = self.segments[c.a as usize]
                        .radius()
                        .min(self.segments[c.b as usize].radius());
                    self.deep_push(c.bias, smaller, ctx)
                }
            })
        {
            self.solve_pushes(threshold, ctx);
        } else {
            self.warm_start(ctx);
            self.sweep_resting(threshold, RESTING_SWEEPS, ctx.dt, ctx);
            self.solve_deep_groups_exactly(ctx.dt, true, ctx);
            self.solve_small_groups_exactly(ctx.dt, joined, ctx);
            if pushing && self.pushed_too_fast(ctx) {
                self.solve_pushes(threshold, ctx);
            }
        }
        if pushing {
            for &(k, _) in &self.push_bodies {
                self.local_index[k as usize] = NOT_LOCAL;
            }
        }
        self.record_resting(0.0, ctx, stats);
        self.keep_resting_loads(ctx);
    }

    /// Starts the resting contacts from the last solve's impulses: a bed at rest needs the
    /// same ones step after step, and a wedged bed's load takes Gauss–Seidel far more sweeps
    /// to find than one.
    fn warm_start(&mut self, ctx: &StepContext<'_>) {
        let count = self.resting.len();
        if !self.warm.is_empty() {
            for k in 0..count {
                // Ask for the bodies' ids two looks ahead and, once they are near, the pair's
                // place in the table one look ahead: the table is reached at random, and the
                // ids too where the bodies' order in memory is not their ids' (with the loads
                // kept after the solve asking ahead as well, the 100k table's resting
                // contacts took 0.94x the time; the 1k table's step the same).
                if let Some(c) = self.resting.get(k + 2 * SWEEP_AHEAD) {
                    prefetch(self.extra(c.a as usize));
                    prefetch(self.extra(c.b as usize));
                }
                if let Some(c) = self.resting.get(k + SWEEP_AHEAD) {
                    let (a, b) = (self.extra(c.a as usize).id, self.extra(c.b as usize).id);
                    self.warm.prefetch(a.min(b), a.max(b));
                }
                let c = &self.resting[k];
                let (a, b) = (self.extra(c.a as usize).id, self.extra(c.b as usize).id);
                if let Some(load) = self.warm.get(a.min(b), a.max(b)) {
                    let impulse = load * ctx.dt;
                    let c = &mut self.resting[k];
                    c.impulse = impulse;
                    let (a, b, normal) = (c.a as usize, c.b as usize, c.normal);
                    let (ima, imb) = (c.inverse_mass_a, c.inverse_mass_b);
                    self.segments[a].velocity -= normal * (impulse * ima);
                    self.segments[b].velocity += normal * (impulse * imb);
                }
            }
        }
    }

    /// Lists the resting contacts' dynamic bodies, for [`Solver::solve_pushes`] (each one's
    /// [`Solver::local_index`] its place in the list, until the resting solve ends).
    pub(super) fn save_push_bodies(&mut self) {
        self.clear_touched();
        for k in 0..self.resting.len() {
            let c = self.resting[k];
            self.touch(c.a);
            self.touch(c.b);
        }
        self.push_bodies.clear();
        if self.local_index.len() < self.segments.len() {
            self.local_index.resize(self.segments.len(), NOT_LOCAL);
        }
        for &k in &self.touched {
            self.local_index[k as usize] = self.push_bodies.len() as u32;
            self.push_bodies
                .push((k, self.segments[k as usize].velocity));
        }
        self.clear_touched();
    }

    /// Whether a body of the resting contacts left their solve faster, against its velocity
    /// before it (in [`Solver::push_bodies`]), than that velocity's speed and a push's cap
    /// together: then the solve's pushes, not the load, sent it off.
    fn pushed_too_fast(&self, ctx: &StepContext<'_>) -> bool {
        self.push_bodies.iter().any(|&(k, before)| {
            let most = self.push_left(k as usize, ctx) + before.length();
            (self.segments[k as usize].velocity - before).length_squared() > most * most
        })
    }

    /// Solves the resting contacts (again, from the velocities in [`Solver::push_bodies`]) in
    /// two parts when a contact's push against its overlap (see [`Solver::correction`]) is a
    /// deep overlap's (see [`Solver::deep_push`]), or slower ones sent a body off too fast
    /// (see [`Solver::pushed_too_fast`]); a stack's creep is undone by pushes that stay in the
    /// velocities, as a resting speed does. First without the pushes, then the pushes on top,
    /// scaled down until no body moves faster than its budget (see [`Solver::push_left`]; at
    /// the step's start, [`MAX_CORRECTION`] of its radius a step) against the first part's
    /// velocity (at most [`PUSH_ROUNDS`] times, see [`Solver::push_on`]). What the pushes add
    /// to each body's velocity is kept in [`Solver::pushes`]: it moves the body within the
    /// step and is taken off at the step's end (unless an impact in the step met one of the
    /// bodies pushed), so a push undoes an overlap without leaving a speed behind.
    ///
    /// Each contact's push is capped on its own, but a sphere overlapping fixed ones on nearly
    /// opposite sides (a spawn in a gap too narrow for it) parts from both only along their
    /// normals' small difference, many times faster; and a push left in the velocity was
    /// pushed on again the next step: a ball placed a fifth of its radius above the middle of
    /// such a gap squirted out at 31 m/s. Momentum is kept, as by any of the solve's impulses.
    fn solve_pushes(&mut self, threshold: f64, ctx: &StepContext<'_>) {
        self.push_saved.clear();
        for c in &mut self.resting {
            self.push_saved.push((c.bias, 0.0, 1.0));
            c.bias = c.bias.min(0.0);
            c.impulse = 0.0;
        }
        for &(k, before) in &self.push_bodies {
            self.segments[k as usize].velocity = before;
        }
        self.warm_start(ctx);
        self.sweep_resting(threshold, RESTING_SWEEPS, ctx.dt, ctx);
        self.push_on(threshold, None, ctx);
    }

    /// The closing speed that brings guard `c` (see [`Solver::add_guards`]) to half the
    /// contact band apart by the step's end, as a bias (0 or negative); `None` when the
    /// step has ended.
    fn gap_bias(&self, c: &RestingContact, ctx: &StepContext<'_>) -> Option<f64> {
        let (sa, sb) = (&self.segments[c.a as usize], &self.segments[c.b as usize]);
        let now = sa.t0.max(sb.t0);
        let gap = (sb.position_at(now) - sa.position_at(now)).length() - sa.radius() - sb.radius();
        let band = contact_band(sa, sb, ctx.settings);
        let rest = ctx.dt - now;
        (rest > 0.0).then(|| -(gap - 0.5 * band).max(0.0) / rest)
    }

    /// Holds each guard (see [`Solver::add_guards`]) that closes no faster than a resting
    /// speed for its pair's press within the step (see [`Solver::press`]) to its gap, as a
    /// resting contact: its meeting would be a resting impact, restitution 0, a moment later
    /// (two balls rolling into each other on a floor are pressed by nothing, and keep their
    /// restitution). Every such guard while contacts push against overlaps (`all`), and
    /// otherwise those against a fixed sphere.
    fn hold_guards(&mut self, all: bool, ctx: &StepContext<'_>) {
        for k in 0..self.resting.len() {
            let c = self.resting[k];
            if c.bias >= 0.0 {
                continue;
            }
            let (a, b) = (c.a as usize, c.b as usize);
            if !(all || self.segments[a].is_fixed() || self.segments[b].is_fixed())
                || -c.bias > self.resting_scale * self.press(a, b, c.normal)
            {
                continue;
            }
            if let Some(held) = self.gap_bias(&c, ctx) {
                self.resting[k].bias = c.bias.max(held);
            }
        }
    }

    /// The second part of [`Solver::solve_pushes`]: the contacts solved without their pushes
    /// (kept in [`Solver::push_saved`]), the pushes on top, scaled down until no body is
    /// pushed faster than what is left of its budget; what they add to each velocity is kept
    /// in [`Solver::pushes`]. For the fallback, `finish` is the rest of the step: each round
    /// then sweeps on as its finishing sweeps do (see [`Solver::finish_sweeps`]), since a
    /// long chain passes a push on about one contact a sweep.
    pub(super) fn push_on(&mut self, threshold: f64, finish: Option<f64>, ctx: &StepContext<'_>) {
        for (k, velocity) in &mut self.push_bodies {
            *velocity = self.segments[*k as usize].velocity;
        }
        for (c, saved) in self.resting.iter().zip(&mut self.push_saved) {
            saved.1 = c.impulse;
        }
        // A guard may close as fast as its pair does of its own accord (see `add_guards`);
        // with the pushes, no faster than the faster of that and what its gap allows: a ball
        // pushed out of a fixed sphere it overlaps, a hair from another, met that one at once,
        // which ended its pushes (see `end_pushes`) step after step, and it never rose out of
        // the gap. (Whatever closing the pushes would have to stop stays theirs to stop.)
        for k in 0..self.resting.len() {
            let c = self.resting[k];
            if c.bias < 0.0 {
                let (va, vb) = (
                    self.segments[c.a as usize].velocity,
                    self.segments[c.b as usize].velocity,
                );
                let own = (vb - va).dot(c.normal);
                if let Some(held) = self.gap_bias(&c, ctx) {
                    self.resting[k].bias = c.bias.max(own.min(held));
                }
            }
        }
        for round in 1..=PUSH_ROUNDS {
            for (c, &(push, _, scale)) in self.resting.iter_mut().zip(&self.push_saved) {
                if push > 0.0 {
                    c.bias = push * scale;
                }
            }
            self.sweep_resting(threshold, RESTING_SWEEPS, finish.unwrap_or(ctx.dt), ctx);
            if let Some(rest) = finish {
                self.finish_sweeps(threshold, rest, ctx);
            }
            // Each body's push against what is left of its budget (its cap, at the step's
            // start).
            self.push_ratios.clear();
            for &(k, unpushed) in &self.push_bodies {
                let push = (self.segments[k as usize].velocity - unpushed).length();
                let ratio = if push > 0.0 {
                    push / self.push_left(k as usize, ctx)
                } else {
                    0.0
                };
                self.push_ratios.push(ratio);
            }
            if self.push_ratios.iter().all(|&r| r <= 1.0) || round == PUSH_ROUNDS {
                break;
            }
            // The pushes on a body pushed too fast are scaled down by as much (a crowd of
            // overlaps keeps its other pushes whole).
            for (c, saved) in self.resting.iter().zip(&mut self.push_saved) {
                let ratio = |k: u32| match self.local_index[k as usize] {
                    NOT_LOCAL => 0.0,
                    at => self.push_ratios[at as usize],
                };
                let most = ratio(c.a).max(ratio(c.b));
                if saved.0 > 0.0 && most > 1.0 {
                    saved.2 /= most;
                }
            }
            for &(k, unpushed) in &self.push_bodies {
                self.segments[k as usize].velocity = unpushed;
            }
            for (c, &(_, impulse, _)) in self.resting.iter_mut().zip(&self.push_saved) {
                c.impulse = impulse;
            }
        }
        if self.strings {
            // A body on a string keeps its push: its drift is bent to the string afterwards.
            self.push_saved.clear();
            return;
        }
        for n in 0..self.push_bodies.len() {
            let (k, unpushed) = self.push_bodies[n];
            let push = self.segments[k as usize].velocity - unpushed;
            if push != DVec3::ZERO {
                self.spend_push(k as usize, push.length());
                self.pushes.push((k, push));
                self.pushed_bits[k as usize / 64] |= 1 << (k % 64);
            }
        }
    }

    /// Takes the resting solve's pushes off their bodies' drifts at time `t` of the step (a
    /// pushed body meets another there): each pushed body is moved to `t`, drifts on at its
    /// velocity without its push, and is touched, for its pairs to be tested again. What each
    /// push would have spent of its body's budget over the rest of the step is given back
    /// (see [`Solver::push_left`]).
    pub(super) fn end_pushes(&mut self, t: f64, ctx: &StepContext<'_>) {
        self.end_pushes_from(0, 0.0, t, ctx);
    }

    /// As [`Solver::end_pushes`], for the pushes from the `from`th on (those given since there
    /// were `from`, at time `since` of the step); the earlier ones stay. What each would have
    /// spent from `t` on, of what it spent from `since`, is given back (all of it if `t` is
    /// `since`).
    pub(super) fn end_pushes_from(
        &mut self,
        from: usize,
        since: f64,
        t: f64,
        ctx: &StepContext<'_>,
    ) {
        let pushes = std::mem::take(&mut self.pushes);
        let left = ctx.dt - since;
        for &(k, push) in &pushes[from.min(pushes.len())..] {
            let k = k as usize;
            self.pushed_bits[k / 64] &= !(1 << (k % 64));
            // What the push would have spent over the rest of the step is left to spend.
            if bit(&self.spent_bits, k) && left > 0.0 {
                let unused = push.length() * ((ctx.dt - t) / left).clamp(0.0, 1.0);
                self.spent[k] = (self.spent[k] - unused).max(0.0);
            }
            let segment = &mut self.segments[k];
            segment.advance_to(t);
            segment.velocity -= push;
            self.versions[k] += 1;
            self.boxes[k] = swept_box(&self.segments[k], ctx.dt, ctx.settings);
            self.broad.update(k, &self.boxes[k]);
            self.touch(k as u32);
            self.queue_bend_again(k, t, ctx.dt);
        }
        self.pushes = pushes;
        self.pushes.truncate(from);
        // A body may have a push left among the earlier ones.
        for &(k, _) in &self.pushes {
            self.pushed_bits[k as usize / 64] |= 1 << (k % 64);
        }
    }

    /// After the resting solve: keeps its impulses for the next step's warm start (each at
    /// most [`WARM_LOADS`] times the largest acceleration, as a load), its loads for this
    /// step's presses and the bodies that rested, and gives the bodies it changed
    /// their new drifts.
    fn keep_resting_loads(&mut self, ctx: &StepContext<'_>) {
        let resting = std::mem::take(&mut self.resting);
        self.next_warm.clear();
        self.loads_unplaced.clear();
        self.keep_rested_before();
        self.rested.clear();
        self.rested.resize(self.order.len().div_ceil(64), 0);
        for (n, c) in resting.iter().enumerate().filter(|(_, c)| c.impulse > 0.0) {
            let (a, b) = (self.extra(c.a as usize).id, self.extra(c.b as usize).id);
            // The next solve starts from the impulses without this step's pushes, which leave
            // no speed (see `solve_pushes`): started from the pushes, two contacts on nearly
            // opposite sides do not undo them within the sweeps.
            let warm = self.push_saved.get(n).map_or(c.impulse, |saved| saved.1);
            let warm = warm.min(self.warm_cap * ctx.dt * c.mass);
            if warm > 0.0 {
                self.next_warm.push((a.min(b), a.max(b), warm / ctx.dt));
            }
            let load = c.impulse * (c.inverse_mass_a + c.inverse_mass_b) / ctx.dt;
            self.loads_unplaced.push((c.a, c.b, load));
            // Each body loaded, and each dynamic one (its inverse mass not 0) rested, by its
            // index in the world.
            for (k, inverse_mass) in [(c.a, c.inverse_mass_a), (c.b, c.inverse_mass_b)] {
                let k = k as usize;
                self.loaded[k / 64] |= 1 << (k % 64);
                if inverse_mass != 0.0 {
                    let i = self.order[k] as usize;
                    self.rested[i / 64] |= 1 << (i % 64);
                }
            }
        }
        self.keep_warm_before();
        self.warm.start(self.next_warm.len());
        for (n, &(a, b, load)) in self.next_warm.iter().enumerate() {
            if let Some(&(a, b, _)) = self.next_warm.get(n + SWEEP_AHEAD) {
                self.warm.prefetch(a, b);
            }
            self.warm.insert(a, b, load);
        }
        // Grouped by lower index (stable: a press finds the pair's load among its lower
        // index's few, whatever their order).
        let n = self.segments.len();
        place_by_bucket(
            &self.loads_unplaced,
            |l| l.0 as usize,
            n,
            &mut self.load_start,
            &mut self.loads,
        );
        debug_assert!(
            (0..n).all(|a| {
                let group =
                    &self.loads[self.load_start[a] as usize..self.load_start[a + 1] as usize];
                group.iter().all(|l| l.0 as usize == a)
                    && group
                        .iter()
                        .enumerate()
                        .all(|(at, l)| group[..at].iter().all(|m| m.1 != l.1))
            }),
            "the loads misplaced, or a pair loaded twice"
        );
        self.resting = resting;
        for ti in 0..self.touched.len() {
            let k = self.touched[ti] as usize;
            let velocity = self.segments[k].velocity;
            self.set_velocity(k, velocity, 0.0, ctx);
        }
    }

    /// A contact's restitution, and whether it is a resting contact (approaching no faster
    /// than the resting speed: restitution 0).
    pub(super) fn restitution(
        &self,
        a: usize,
        b: usize,
        normal: DVec3,
        settings: &Settings,
    ) -> (f64, bool) {
        let (sa, sb) = (&self.segments[a], &self.segments[b]);
        let (ea, eb) = (self.extra(a), self.extra(b));
        let approach_speed = -(sb.velocity - sa.velocity).dot(normal);
        if approach_speed <= self.resting_scale * self.press(a, b, normal) {
            (0.0, true)
        } else {
            let combined = settings
                .restitution_combine
                .combine(ea.restitution, eb.restitution);
            (combined, false)
        }
    }

    /// Whether body `a` or `b` has bounced [`COLLAPSE_BOUNCES`] times at this instant.
    pub(super) fn collapsing(&self, a: usize, b: usize) -> bool {
        let instant = &self.instant;
        let collapsing = |k: usize| {
            (COLLAPSE_BOUNCES..COLLAPSE_BOUNCES + SQUEEZES).contains(&instant.bounces(k as u32))
        };
        instant.most_bounces() >= COLLAPSE_BOUNCES && (collapsing(a) || collapsing(b))
    }

    /// Counts a bounce of pair `(a, b)` at this instant, approaching at `speed` (see
    /// [`COLLAPSE_BOUNCES`]).
    pub(super) fn count_bounce(&mut self, a: usize, b: usize, speed: f64) {
        self.instant
            .bounced(a as u32, b as u32, speed, moving(&self.segments));
    }

    /// Whether the impacts of `component` end an inelastic collapse at their instant (see
    /// [`COLLAPSE_BOUNCES`]): a body of one of them has bounced that often there, and every
    /// one of them approaches at under [`COLLAPSE_SPEED`] of the instant's fastest bounce (a
    /// squeeze takes every impact of its component, whatever its direction: a fast one would
    /// lose its bounce).
    pub(super) fn ends_collapse(&self, component: &[Event]) -> bool {
        let slow = COLLAPSE_SPEED * self.instant.fastest();
        component
            .iter()
            .any(|e| self.collapsing(e.a as usize, e.b as usize))
            && component.iter().all(|e| {
                let (sa, sb) = (&self.segments[e.a as usize], &self.segments[e.b as usize]);
                let d = sb.position_at(e.time) - sa.position_at(e.time);
                -(sb.velocity - sa.velocity).dot(d.normalize_or_zero()) < slow
            })
    }

    /// The acceleration pressing touching pair `(i, j)` together along `normal` at the start
    /// of the step, when the resting solve picks its contacts: the larger of the two bodies'
    /// whole accelerations, unless one hangs on a string (then only along the normal, see
    /// [`pressing`]). In a pile the weight pushes sideways too, through the neighbours; a
    /// contact that touched before the step began is a loaded one, not a first meeting.
    pub(super) fn start_press(&self, i: usize, j: usize, normal: DVec3) -> f64 {
        let (a, b) = (self.extra(i), self.extra(j));
        let own = pressing(a, b, normal);
        if self.strings && (self.string_of(i).is_some() || self.string_of(j).is_some()) {
            return own;
        }
        own.max(a.acceleration.length().max(b.acceleration.length()))
    }

    /// The acceleration pressing pair `(a, b)` together along `normal` within the step: the
    /// bodies' own (see [`pressing`]), or the load this step's resting solve put on their
    /// contact, whichever is larger.
    pub(super) fn press(&self, a: usize, b: usize, normal: DVec3) -> f64 {
        let own = pressing(self.extra(a), self.extra(b), normal);
        if !(bit(&self.loaded, a) && bit(&self.loaded, b)) {
            return own;
        }
        // The lower index's few loads (a pair has at most one), among them the pair's if
        // loaded.
        let (low, high) = (a.min(b), a.max(b) as u32);
        let loads = &self.loads[self.load_start[low] as usize..self.load_start[low + 1] as usize];
        match loads.iter().find(|l| l.1 == high) {
            Some(l) => own.max(l.2),
            None => own,
        }
    }
}

/// Applies each of `contacts`' `impulses` (those above 0) to `velocities`, as the group's
/// solves do: `a` pushed back along the normal, `b` forward, each by its inverse mass.
impl ExactScratch {
    /// Fills the scratch for an exact solve of the resting contacts `members` of `resting`:
    /// each of their bodies once, with its velocity in `segments` less those contacts'
    /// impulses, and each contact with its bias from `bias` (restitution 0).
    fn gather(
        &mut self,
        resting: &[RestingContact],
        segments: &[Segment],
        members: impl Iterator<Item = usize>,
        bias: impl Fn(&RestingContact) -> f64,
    ) {
        if self.index.len() < segments.len() {
            self.index.resize(segments.len(), NOT_LOCAL);
        }
        self.bodies.clear();
        self.inverse_masses.clear();
        self.velocities.clear();
        self.contacts.clear();
        for n in members {
            let c = &resting[n];
            for (k, inverse_mass) in [(c.a, c.inverse_mass_a), (c.b, c.inverse_mass_b)] {
                let slot = &mut self.index[k as usize];
                if *slot == NOT_LOCAL {
                    *slot = self.bodies.len() as u32;
                    self.bodies.push(k);
                    self.inverse_masses.push(inverse_mass);
                    self.velocities.push(segments[k as usize].velocity);
                }
            }
            let (a, b) = (
                self.index[c.a as usize] as usize,
                self.index[c.b as usize] as usize,
            );
            self.velocities[a] += c.normal * (c.impulse * c.inverse_mass_a);
            self.velocities[b] -= c.normal * (c.impulse * c.inverse_mass_b);
            self.contacts.push(GroupContact {
                a,
                b,
                normal: c.normal,
                restitution: 0.0,
                bias: bias(c),
                string: false,
            });
        }
        for &k in &self.bodies {
            self.index[k as usize] = NOT_LOCAL;
        }
    }
}

/// Whether one body of contact `c` is dynamic and more than [`BLOCK_RATIO`] times heavier than
/// the other (see `Solver::find_blocks`).
fn much_lighter(c: &RestingContact) -> bool {
    (c.inverse_mass_b != 0.0 && c.inverse_mass_a > BLOCK_RATIO * c.inverse_mass_b)
        || (c.inverse_mass_a != 0.0 && c.inverse_mass_b > BLOCK_RATIO * c.inverse_mass_a)
}

fn apply_impulses(
    contacts: &[GroupContact],
    impulses: &[f64],
    inverse_masses: &[f64],
    velocities: &mut [DVec3],
) {
    for (c, &impulse) in contacts.iter().zip(impulses) {
        let impulse = impulse.max(0.0);
        velocities[c.a] -= c.normal * (impulse * inverse_masses[c.a]);
        velocities[c.b] += c.normal * (impulse * inverse_masses[c.b]);
    }
}
