//! The fallback solve of a step whose collision budget runs out: the rest of the step solved
//! at once, in rounds, as the resting contacts are (see [`Solver::fall_back`]).

use super::*;

impl Solver {
    /// When the step's collision budget runs out at time `t` (a crowd landing at once, where
    /// each collision brings on more): every dynamic body is moved to `t`, and every pair that
    /// could meet in the rest of the step is solved at once, as resting contacts are, each
    /// allowed to close no further than half the contact band short of touching by the step's
    /// end (an overlapping one to part as a resting contact does): restitution 0, momentum
    /// kept, no energy gained beyond a stack's creep (a deep overlap is undone by a push taken
    /// off at the step's end, see below). The solve goes in rounds, each
    /// adding the pairs the last one's changes bring together (the first also those within
    /// [`FALLBACK_MARGIN`] of that, which spares most later rounds), until a round adds none; after
    /// [`FALLBACK_ROUNDS`] the pairs still added are left unsolved and counted as deferred.
    /// Each round sweeps until the impulses settle as the step's resting solve does (the first
    /// at most [`RESTING_SWEEPS`] times, later ones [`FALLBACK_LATER_SWEEPS`]), and after the
    /// last round up to [`FALLBACK_FINISH_SWEEPS`] more while a pair still closes well past its
    /// allowance (a long chain, see `fallback_excess`); the deep pushes held back then go on
    /// top, each of their rounds finished the same way (see [`Solver::push_on`]). The impacts
    /// left in the queue are then stale, and the step drifts to its end. Bodies on strings are
    /// left out (the solve holds no string): their pairs that could meet are left to the
    /// budget's deferral and counted as deferred, and their own impacts and bends stay queued.
    pub(super) fn fall_back(&mut self, t: f64, ctx: &StepContext<'_>, stats: &mut StepStats) {
        if t >= ctx.dt {
            return;
        }
        let rest = ctx.dt - t;
        // The pushes end (see `Solver::end_pushes`): the solve below answers the velocities
        // without them.
        self.end_pushes(t, ctx);
        for segment in &mut self.segments {
            segment.advance_to(t);
        }
        self.resting.clear();
        self.fallback_pairs.clear();
        let mut bodies = std::mem::take(&mut self.local_bodies);
        bodies.clear();
        bodies.extend((0..self.segments.len() as u32).filter(|&k| {
            !self.segments[k as usize].is_fixed() && self.string_of(k as usize).is_none()
        }));
        self.fallback_pushes.clear();
        let mut candidates = std::mem::take(&mut self.candidates);
        // The solve changes velocities, which may bring other pairs together: rounds, each
        // adding the pairs the last one's changes could bring within the band, until none
        // does. The finishing sweeps and exact solves after the rounds change velocities
        // too: the bodies they leave pressed are checked again, and any pair they bring
        // together starts the rounds again (at most `FALLBACK_PASSES` passes in all).
        let (mut round, mut passes) = (0, 0);
        loop {
            let pass_start = self.resting.len();
            self.fallback_rounds(&mut round, &mut bodies, &mut candidates, rest, ctx, stats);
            if passes > 0 && self.resting.len() == pass_start {
                break;
            }
            // A long chain (a fast sphere driven into a line of many, each contact closing
            // the next) passes its impulses on about one contact a sweep, and the rounds'
            // sweeps can leave it closing through itself: go on while any pair would end the
            // step deeper than it is allowed by more than a hundredth of the smaller radius (a
            // line of 100 spheres struck at 1 km/s ended 2 cm into itself), up to
            // `FALLBACK_FINISH_SWEEPS` more. A landing pit seldom leaves a pair that deep (its
            // 10 000 never; the 1000 now and then). Stopped, too, when four batches of sweeps
            // in a row each leave the excess (summed over the contacts) no smaller than the
            // batch before (a long chain's rises at first, then falls batch after batch): a
            // set of contacts no velocities satisfy (a sphere pressed between fixed ones)
            // would otherwise take every sweep, its impulses growing all the while.
            let threshold = self.sweep_threshold();
            let swept = self.finish_sweeps(threshold, rest, ctx);
            let solved = self.solve_deep_groups_exactly(rest, false, ctx);
            passes += 1;
            if !(swept || solved) || passes == FALLBACK_PASSES || round > FALLBACK_ROUNDS {
                break;
            }
            // The next pass's rounds start from the bodies pressed now (none takes the first
            // round's margin again).
            round = round.max(1);
            self.pressed_bodies(&mut bodies, ctx);
        }
        let threshold = self.sweep_threshold();
        // The deep pushes held back above go on top, as the step's resting solve's do (see
        // `solve_pushes`), and are finished the same way: undone by the step's end, a long
        // chain's overlaps would come back deeper every step.
        if !self.fallback_pushes.is_empty() {
            self.fallback_pushes.sort_unstable_by_key(|p| (p.0, p.1));
            self.push_saved.clear();
            for c in &self.resting {
                let push = self
                    .fallback_pushes
                    .binary_search_by_key(&(c.a, c.b), |p| (p.0, p.1))
                    .map_or(0.0, |at| self.fallback_pushes[at].2);
                self.push_saved.push((push, 0.0, 1.0));
            }
            self.save_push_bodies();
            self.push_on(threshold, Some(rest), ctx);
            for &(k, _) in &self.push_bodies {
                self.local_index[k as usize] = NOT_LOCAL;
            }
            self.push_saved.clear();
        }
        self.local_bodies = bodies;
        self.record_resting(t, ctx, stats);
        self.resting.clear();
        for ti in 0..self.touched.len() {
            let k = self.touched[ti] as usize;
            self.versions[k] += 1;
            self.boxes[k] = swept_box(&self.segments[k], ctx.dt, ctx.settings);
            self.broad.update(k, &self.boxes[k]);
            self.check_bounded(k);
            self.queue_bend_again(k, t, ctx.dt);
        }
        // The drifts are final now (the step's later impacts are deferred), and the pairs the
        // last changes bring together were tested nowhere: those that end the step overlapping
        // are kept for its deepest overlap (a sphere driven through a line of them when the
        // rounds ran out went unreported).
        for ti in 0..self.touched.len() {
            let k = self.touched[ti] as usize;
            candidates.clear();
            self.broad
                .collect_overlapping(k, &self.boxes, &mut candidates);
            for &m in &candidates {
                let m = m as usize;
                let reach = self.segments[k].radius() + self.segments[m].radius();
                let apart = (self.final_position(m, ctx.dt) - self.final_position(k, ctx.dt))
                    .length_squared();
                if m != k && apart < reach * reach {
                    self.tested.push((k.min(m) as u32, k.max(m) as u32));
                }
            }
        }
        self.candidates = candidates;
        self.clear_touched();
        stats.fell_back = true;
    }

    /// The fallback's rounds (see [`Solver::fall_back`]), from round `round` on, each taking
    /// the pairs of `bodies` that may come within the band over the `rest` of the step and
    /// sweeping, until a round adds none; after [`FALLBACK_ROUNDS`] the pairs still added are
    /// left unsolved and counted as deferred (and `round` is left past it).
    fn fallback_rounds(
        &mut self,
        round: &mut usize,
        bodies: &mut Vec<u32>,
        candidates: &mut Vec<u32>,
        rest: f64,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) {
        while *round <= FALLBACK_ROUNDS {
            let known = self.resting.len();
            self.clear_touched();
            for &k in bodies.iter() {
                self.touch(k);
            }
            // The first round also takes pairs a little farther apart (see
            // `FALLBACK_MARGIN`), found with each body's box grown by that fraction of its
            // diameter: as much for spheres of one size; a pair of unequal ones, which may
            // fall short of the margin from the smaller's side, is taken by a later round if
            // it closes.
            let margin = if *round == 0 { FALLBACK_MARGIN } else { 0.0 };
            self.fallback_strung.clear();
            for &k in bodies.iter() {
                let k = k as usize;
                candidates.clear();
                let swept = self.boxes[k];
                if margin > 0.0 {
                    let grow = DVec3::splat(margin * 2.0 * self.segments[k].radius());
                    self.boxes[k].lo -= grow;
                    self.boxes[k].hi += grow;
                }
                self.broad.collect_overlapping(k, &self.boxes, candidates);
                self.boxes[k] = swept;
                for &m in candidates.iter() {
                    let m = m as usize;
                    // Each pair once: from its first body of this round's.
                    if m == k || (m < k && self.is_touched(m)) {
                        continue;
                    }
                    let (a, b) = (k.min(m), k.max(m));
                    let key = (a as u32, b as u32);
                    if self.fallback_pairs.binary_search(&key).is_ok() {
                        continue;
                    }
                    let (sa, sb) = (&self.segments[a], &self.segments[b]);
                    if sa.is_fixed() && sb.is_fixed() {
                        continue;
                    }
                    let d = sb.position - sa.position;
                    let distance = d.length();
                    if distance == 0.0 {
                        continue;
                    }
                    let normal = d / distance;
                    let reach = sa.radius() + sb.radius();
                    let band = contact_band(sa, sb, ctx.settings);
                    let approach = -(sb.velocity - sa.velocity).dot(normal);
                    let gap = distance - reach;
                    // Pairs that cannot come within half the band by the step's end need
                    // nothing (yet).
                    if approach * rest + margin * reach < gap - 0.5 * band {
                        continue;
                    }
                    if self.string_of(a).is_some() || self.string_of(b).is_some() {
                        // Not solved here (nor, once the budget has run out, anywhere).
                        self.fallback_strung.push(key);
                        continue;
                    }
                    let press = self.start_press(a, b, normal);
                    let smaller = sa.radius().min(sb.radius());
                    let allowed = if gap > 0.0 {
                        (gap - 0.5 * band).max(0.0) / rest
                    } else {
                        -self.correction(-gap, band, press, smaller, ctx)
                    };
                    // A deep overlap's push is held back, for the solve of the pushes after
                    // the rounds, which takes it off at the step's end: against a fixed
                    // sphere, solved with the load, the pushes on nearly opposite sides of a
                    // ball fallen into a gap narrower than it sent it off at 28 m/s; between
                    // dynamic spheres, left in the velocities, they flung an overlapping
                    // crowd apart with no gravity (3 mJ to 1.8 kJ in a step). Held back, it
                    // undoes the overlap over the rest of the step, not a whole one.
                    let bias = if self.deep_push(-allowed, smaller, ctx) {
                        let push =
                            (-allowed * (ctx.dt / rest)).min(MAX_CORRECTION * smaller / ctx.dt);
                        self.fallback_pushes.push((key.0, key.1, push));
                        0.0
                    } else {
                        -allowed
                    };
                    self.tested.push(key);
                    self.push_resting(key.0, key.1, normal, bias, press, gap > band);
                }
            }
            if !self.fallback_strung.is_empty() {
                // Each counted once: seen again by a later round, they are skipped above.
                let left = u32::try_from(self.fallback_strung.len()).unwrap_or(u32::MAX);
                stats.collisions_deferred = stats.collisions_deferred.saturating_add(left);
                self.fallback_pairs.extend_from_slice(&self.fallback_strung);
                self.fallback_pairs.sort_unstable();
            }
            if self.resting.len() == known {
                break;
            }
            if *round == FALLBACK_ROUNDS {
                // Out of rounds: these pairs are left to meet unresolved, and said so.
                let left = self.resting.len() - known;
                stats.collisions_deferred = stats
                    .collisions_deferred
                    .saturating_add(u32::try_from(left).unwrap_or(u32::MAX));
                self.resting.truncate(known);
                *round = FALLBACK_ROUNDS + 1;
                break;
            }
            self.fallback_pairs
                .extend(self.resting[known..].iter().map(|c| (c.a, c.b)));
            self.fallback_pairs.sort_unstable();
            self.order_resting(ctx);
            // Converged as the step's resting solve is (see `solve_resting`), or as far as the
            // round's sweeps go.
            let threshold = self.sweep_threshold();
            let sweeps = if *round == 0 {
                RESTING_SWEEPS
            } else {
                FALLBACK_LATER_SWEEPS
            };
            self.sweep_resting(threshold, sweeps, rest, ctx);
            // Their boxes from now on, for the next round's candidates.
            self.pressed_bodies(bodies, ctx);
            *round += 1;
        }
    }

    /// Sets `bodies` to the bodies of the resting contacts that took an impulse, and gives
    /// them their boxes from now on in the broad phase.
    fn pressed_bodies(&mut self, bodies: &mut Vec<u32>, ctx: &StepContext<'_>) {
        bodies.clear();
        self.clear_touched();
        for k in 0..self.resting.len() {
            let c = self.resting[k];
            if c.impulse > 0.0 {
                self.touch(c.a);
                self.touch(c.b);
            }
        }
        bodies.extend_from_slice(&self.touched);
        for &k in bodies.iter() {
            let k = k as usize;
            self.boxes[k] = swept_box(&self.segments[k], ctx.dt, ctx.settings);
            self.broad.update(k, &self.boxes[k]);
        }
    }
}
