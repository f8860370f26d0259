//! The fallback solve of a step whose collision budget runs out: the rest of the step solved
//! at once, in rounds, as the resting contacts are (see [`Solver::fall_back`]).

use super::*;

impl Solver {
    /// When the step's collision budget runs out at time `t` (a crowd landing at once, where
    /// each collision brings on more): every dynamic body is moved to `t`, and the crowds that
    /// spent the budget are taken (see [`Solver::choose_crowd`]; every dynamic body if
    /// `last`). Every pair of theirs that could meet in the rest of the step is solved at
    /// once, as resting contacts are, each allowed to close no further than half the contact
    /// band short of touching by the step's end (an overlapping one to part as a resting
    /// contact does): restitution 0, momentum kept, no energy gained beyond a stack's creep
    /// (a deep overlap is undone by a push taken off at the step's end, see below). The solve
    /// goes in rounds, each adding the pairs the last one's changes bring together (the first
    /// also those within [`FALLBACK_MARGIN`] of that, which spares most later rounds), until a
    /// round adds none; after [`FALLBACK_ROUNDS`] the pairs still added are left unsolved and
    /// counted as deferred. Each round sweeps until the impulses settle as the step's resting
    /// solve does (the first at most [`RESTING_SWEEPS`] times, later ones
    /// [`FALLBACK_LATER_SWEEPS`]), and after the last round up to [`FALLBACK_FINISH_SWEEPS`]
    /// more while a pair still closes well past its allowance (a long chain, see
    /// `fallback_excess`); the deep pushes held back then go on top, each of their rounds
    /// finished the same way (see [`Solver::push_on`]). The taken bodies' impacts left in the
    /// queue are then stale, and they drift to the step's end. Bodies on strings are left out
    /// (the solve holds no string): their pairs that could meet are left to the budget's
    /// deferral and counted as deferred, and their own impacts and bends stay queued.
    ///
    /// The groups left out that the crowds' drifts may reach are taken with them (see
    /// [`Solver::take_reached`]). Those the solve's new drifts may reach are solved in turn
    /// (see [`Solver::reached_groups`]), each such follow-up together with every body the
    /// earlier solves took, up to [`FALLBACK_FOLLOW_UPS`] times, after which every body not
    /// yet taken is. The bodies taken, and those a solve changes, are marked fallen: their
    /// later impacts are deferred. The others go on meeting exactly in the event loop, their
    /// pairs changed at `t` (dirty ones, those whose push ended) tested again here. Returns
    /// how many more collisions the others may take: what is left of their shares of the
    /// budget (0 if every body was taken).
    pub(super) fn fall_back(
        &mut self,
        t: f64,
        last: bool,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) -> u32 {
        // The bodies changed at `t` whose pairs are not yet tested: tested at the end if the
        // fallback leaves them to the event loop.
        self.crowd_found = false;
        self.fallback_requery.clear();
        self.fallback_requery.extend_from_slice(&self.dirty);
        self.drop_dirty();
        if t >= ctx.dt {
            return 0;
        }
        let rest = ctx.dt - t;
        // The pushes end (see `Solver::end_pushes`): the solve below answers the velocities
        // without them. After an earlier fallback of the step, the pushes left are its deep
        // pushes, on bodies it took: they stay, to be taken off at the step's end, unless
        // this is the `last` fallback, which takes those bodies again. The bodies
        // `end_pushes` touches are tested again at the end if left out; those touched before
        // were tested already.
        self.clear_touched();
        if self.fallen.is_empty() || last {
            self.end_pushes(t, ctx);
        }
        self.fallback_requery.extend_from_slice(&self.touched);
        for segment in &mut self.segments {
            segment.advance_to(t);
        }
        // Every dynamic body not on a string; unless `last`, not those an earlier fallback
        // of the step took either (their drifts are final: they join no group, as fixed
        // bodies do not, and a solve takes them again only if it presses them).
        let mut bodies = std::mem::take(&mut self.local_bodies);
        bodies.clear();
        bodies.extend((0..self.segments.len() as u32).filter(|&k| {
            !self.segments[k as usize].is_fixed()
                && self.string_of(k as usize).is_none()
                && (last || !bit(&self.fallen_bits, k as usize))
        }));
        let mut candidates = std::mem::take(&mut self.candidates);
        let mut left = if last {
            0
        } else {
            self.choose_crowd(&mut bodies, &mut candidates, rest, ctx)
        };
        // The bodies this fallback takes are listed as fallen from here on, and the pushes its
        // solves give are listed from here on.
        let (taken_from, pushes_from) = (self.fallen.len(), self.pushes.len());
        if left > 0 {
            left = self.take_reached(&mut bodies, &mut candidates, rest, ctx);
        }
        // The crowds are solved, then every group left out that the solve's drifts may now
        // reach (see `Solver::reached_groups`), and so on; after `FALLBACK_FOLLOW_UPS` such
        // solves every body not yet taken is.
        let mut solves = 0;
        loop {
            for &k in &bodies {
                self.mark_fallen(k);
            }
            self.solve_fallback(t, &mut bodies, &mut candidates, ctx, stats);
            solves += 1;
            if left == 0 {
                break;
            }
            left = self.reached_groups(&mut bodies, &mut candidates, rest, ctx);
            if bodies.is_empty() {
                break;
            }
            if solves > FALLBACK_FOLLOW_UPS {
                bodies.clear();
                bodies.extend((0..self.segments.len() as u32).filter(|&k| {
                    !self.segments[k as usize].is_fixed() && !self.is_fallen(k as usize)
                }));
                left = 0;
            }
            // A follow-up solve takes again every body this fallback's solves took: what the
            // bodies it adds press passes through the crowd they meet, which its rounds
            // would otherwise take in one layer of contacts a round (a follow-up of the
            // landing pit of 10 000 spread over 5800 of its crowd's bodies and ran out of
            // rounds, leaving hundreds of pairs to close unsolved, step after step). It solves
            // them from their drifts without the deep pushes those solves gave (see
            // `Solver::end_pushes`), and gives its own: solved again with its push in its
            // velocity, then the push taken off at the step's end, a body took the push's
            // answer as its own (an overlapping crowd's energy went from 1.3 kJ to 6.1 kJ in
            // a step). Given at `t`, the pushes have spent nothing yet. A body left out can
            // hold one, if a push's sweeps undid the impulse its contact took: its pairs are
            // tested again at the end if this fallback still leaves it out.
            self.clear_touched();
            self.end_pushes_from(pushes_from, t, t, ctx);
            self.fallback_requery.extend_from_slice(&self.touched);
            self.clear_touched();
            bodies.extend_from_slice(&self.fallen[taken_from..]);
        }
        self.local_bodies = bodies;
        self.candidates = candidates;
        stats.fell_back = true;
        if left > 0 {
            // A new instant: an impact left to the event loop at `t` is not solved together
            // with the contacts of bodies the fallback took (their drifts are final).
            self.instant.start(t, self.segments.len());
            // The bodies left to the event loop that changed at `t` (dirty, or a push ended):
            // their pairs tested in full from here.
            for i in 0..self.fallback_requery.len() {
                let k = self.fallback_requery[i];
                if !self.is_fallen(k as usize) {
                    self.touch(k);
                }
            }
            self.caching = false;
            self.requery_full(t, ctx, stats);
            self.clear_touched();
        }
        left
    }

    /// One solve of [`Solver::fall_back`] at time `t`: from `bodies` (each dynamic), in
    /// rounds, then its finishing sweeps, exact solves and deep pushes, its contacts recorded
    /// and the bodies it changed given their drifts to the step's end.
    fn solve_fallback(
        &mut self,
        t: f64,
        bodies: &mut Vec<u32>,
        candidates: &mut Vec<u32>,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) {
        let rest = ctx.dt - t;
        self.resting.clear();
        self.fallback_pairs.clear();
        self.fallback_pushes.clear();
        // The solve changes velocities, which may bring other pairs together: rounds, each
        // adding the pairs the last one's changes could bring within the band, until none
        // does. The finishing sweeps and exact solves after the rounds change velocities
        // too: the bodies they leave pressed are checked again, and any pair they bring
        // together starts the rounds again (at most `FALLBACK_PASSES` passes in all).
        let (mut round, mut passes) = (0, 0);
        loop {
            let pass_start = self.resting.len();
            self.fallback_rounds(&mut round, bodies, candidates, rest, ctx, stats);
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
            // leave the excess (summed over the contacts) no smaller, by a thousandth, than the
            // batch before, with no new least between them (a long chain's rises at first,
            // then falls batch after batch; see `Solver::finish_sweeps`): a set of contacts no
            // velocities satisfy (a sphere pressed between fixed ones) would otherwise take
            // every sweep, its impulses growing all the while, its excess creeping down or
            // swinging.
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
            self.pressed_bodies(bodies, ctx);
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
        self.record_resting(t, ctx, stats);
        self.resting.clear();
        for ti in 0..self.touched.len() {
            let k = self.touched[ti] as usize;
            self.mark_fallen(k as u32);
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
            self.broad.collect_overlapping(k, &self.boxes, candidates);
            for &m in candidates.iter() {
                let m = m as usize;
                let reach = self.segments[k].radius() + self.segments[m].radius();
                let apart = (self.final_position(m, ctx.dt) - self.final_position(k, ctx.dt))
                    .length_squared();
                if m != k && apart < reach * reach {
                    self.tested.push((k.min(m) as u32, k.max(m) as u32));
                }
            }
        }
        self.clear_touched();
    }

    /// Keeps in `bodies` (every dynamic body not on a string) only the crowds that spent their
    /// share of the step's collision budget (and the groups taken for reaching too far, see
    /// [`Group::too_far_reaching`]), and returns what is left of the others' shares (0, with
    /// every body kept, if it takes them all).
    ///
    /// The groups are the dynamic bodies joined by pairs that may come within the band over
    /// the `rest` of the step (as the fallback's first round takes them: fixed bodies join
    /// nothing), and the groups not spent joined in turn while they may meet at the fastest
    /// their kinetic energy allows (see [`Group::speed`]). A group spent its share when its
    /// bodies' drift changes this step (their versions) reach `max_collisions_per_body` for
    /// each, or when a kinematic sphere may reach it. None may have spent its share when the
    /// budget counted impacts that changed nothing, or bodies left out of the step (see
    /// `crate::dormant`): then every body is kept. So too in a world with strings (a strung
    /// body's bends are not bounded by its energy), or if the groups still grow after
    /// [`CROWD_PASSES`] passes.
    fn choose_crowd(
        &mut self,
        bodies: &mut Vec<u32>,
        candidates: &mut Vec<u32>,
        rest: f64,
        ctx: &StepContext<'_>,
    ) -> u32 {
        if self.strings {
            return 0;
        }
        let n = self.segments.len();
        let mut parent = std::mem::take(&mut self.crowd_parent);
        parent.clear();
        parent.extend(0..n as u32);
        // Each body's candidates are kept for the solve's first round (see
        // `Solver::fallback_rounds`).
        self.crowd_candidates.clear();
        self.crowd_ranges.clear();
        self.crowd_ranges.resize(n, (0, 0));
        self.crowd_found = true;
        for &k in bodies.iter() {
            let k = k as usize;
            self.collect_within(k, self.grown_box(k, FALLBACK_MARGIN), candidates);
            self.crowd_ranges[k] = (self.crowd_candidates.len() as u32, candidates.len() as u32);
            self.crowd_candidates.extend_from_slice(candidates);
            for &m in candidates.iter() {
                let m = m as usize;
                if m == k || self.segments[m].is_fixed() || bit(&self.fallen_bits, m) {
                    continue;
                }
                if union_root(&mut parent, k) != union_root(&mut parent, m)
                    && self.may_close(k, m, FALLBACK_MARGIN, rest, ctx)
                {
                    union_join(&mut parent, k, m);
                }
            }
        }
        let mut groups = std::mem::take(&mut self.crowd_groups);
        groups.clear();
        groups.resize(n, Group::default());
        let share = u64::from(ctx.settings.max_collisions_per_body);
        self.crowd_radius = 0.0;
        for &k in bodies.iter() {
            let k = k as usize;
            let root = union_root(&mut parent, k);
            let segment = &self.segments[k];
            self.crowd_radius = self.crowd_radius.max(segment.radius());
            let extra = self.extra(k);
            groups[root].join(&Group::of(
                segment,
                extra.inverse_mass,
                extra.acceleration.length(),
                self.versions[k],
            ));
        }
        let mut crowd = 0;
        for &k in bodies.iter() {
            let group = &mut groups[k as usize];
            // A group whose reach is not finite (a speed or a mass out of range) is taken:
            // the queries below need finite boxes.
            if group.count > 0
                && (group.versions >= share * u64::from(group.count)
                    || !group.speed(ctx.dt).is_finite())
            {
                group.crowd = true;
            }
        }
        for &k in bodies.iter() {
            crowd += usize::from(groups[union_root(&mut parent, k as usize)].crowd);
        }
        let mut taken_all = crowd == 0 || crowd == bodies.len();
        // The groups left out, joined while they may meet.
        let mut pass = 0;
        while !taken_all {
            let mut joined = false;
            for &k in bodies.iter() {
                let k = k as usize;
                let root = union_root(&mut parent, k);
                if groups[root].crowd {
                    continue;
                }
                let speed = groups[root].speed(ctx.dt);
                if groups[root].too_far_reaching(2.0 * speed * rest, self.crowd_radius) {
                    groups[root].crowd = true;
                    continue;
                }
                self.query_reach(k, 2.0 * speed * rest, candidates, ctx);
                for &m in candidates.iter() {
                    let m = m as usize;
                    let sm = &self.segments[m];
                    let root = union_root(&mut parent, k);
                    if sm.is_fixed() {
                        // A kinematic sphere may bring it any energy.
                        groups[root].crowd |= sm.velocity != DVec3::ZERO;
                        continue;
                    }
                    if bit(&self.fallen_bits, m) {
                        // Taken by an earlier fallback: checked after the solve.
                        continue;
                    }
                    let other = union_root(&mut parent, m);
                    if other == root || groups[other].crowd {
                        continue;
                    }
                    let reach = (groups[root].speed(ctx.dt) + groups[other].speed(ctx.dt)) * rest;
                    if self.within_reach(k, m, reach, ctx) {
                        union_join(&mut parent, root, other);
                        let (low, high) = (root.min(other), root.max(other));
                        let merged = groups[high];
                        groups[low].join(&merged);
                        groups[low].crowd |= !groups[low].speed(ctx.dt).is_finite();
                        joined = true;
                    }
                }
            }
            pass += 1;
            if !joined {
                break;
            }
            taken_all = pass == CROWD_PASSES;
        }
        let mut left = 0u64;
        self.crowd_left.clear();
        if !taken_all {
            for &k in bodies.iter() {
                let root = union_root(&mut parent, k as usize);
                parent[k as usize] = root as u32;
                let group = &groups[root];
                if !group.crowd {
                    self.crowd_left.push(k);
                    if root == k as usize {
                        left += (share * u64::from(group.count)).saturating_sub(group.versions);
                    }
                }
            }
            taken_all = self.crowd_left.is_empty() || self.crowd_left.len() == bodies.len();
            bodies.retain(|&k| groups[parent[k as usize] as usize].crowd);
        }
        self.crowd_parent = parent;
        self.crowd_groups = groups;
        if taken_all {
            self.crowd_left.clear();
            return 0;
        }
        u32::try_from(left).unwrap_or(u32::MAX).max(1)
    }

    /// Before the first solve of a fallback: adds to `bodies` (the crowds, see
    /// [`Solver::choose_crowd`]) the groups left out that the crowds' drifts now may reach
    /// (see [`Solver::reached_groups`]), and those theirs may reach in turn, up to
    /// [`FALLBACK_FOLLOW_UPS`] times, and marks them all fallen. Solved with the crowds, they
    /// spare a follow-up solve, which takes the crowds again (most of a landing's rain, still
    /// falling onto the bed, is taken so). Returns what is left of the shares of the groups
    /// still left out (0 if none is).
    fn take_reached(
        &mut self,
        bodies: &mut Vec<u32>,
        candidates: &mut Vec<u32>,
        rest: f64,
        ctx: &StepContext<'_>,
    ) -> u32 {
        for &k in bodies.iter() {
            self.mark_fallen(k);
        }
        let mut reached = std::mem::take(&mut self.crowd_reached);
        let mut left = 1;
        for _ in 0..FALLBACK_FOLLOW_UPS {
            left = self.reached_groups(&mut reached, candidates, rest, ctx);
            for &k in &reached {
                self.mark_fallen(k);
            }
            bodies.extend_from_slice(&reached);
            if reached.is_empty() || left == 0 {
                break;
            }
        }
        self.crowd_reached = reached;
        left
    }

    /// After a solve of the fallback (and before the first, see [`Solver::take_reached`]):
    /// sets `bodies` to the bodies left out (see [`Solver::choose_crowd`]) of each group that
    /// may reach a body the fallback took (along its drift) at the fastest its energy allows
    /// (or that reaches too far to look, see [`Group::too_far_reaching`]), or that lost a body
    /// to the solve, and returns what is left of the shares of the groups still left out.
    fn reached_groups(
        &mut self,
        bodies: &mut Vec<u32>,
        candidates: &mut Vec<u32>,
        rest: f64,
        ctx: &StepContext<'_>,
    ) -> u32 {
        bodies.clear();
        let left_out = std::mem::take(&mut self.crowd_left);
        let mut groups = std::mem::take(&mut self.crowd_groups);
        for &k in &left_out {
            if self.is_fallen(k as usize) {
                groups[self.crowd_parent[k as usize] as usize].crowd = true;
            }
        }
        for &k in &left_out {
            let k = k as usize;
            let root = self.crowd_parent[k] as usize;
            if groups[root].crowd {
                continue;
            }
            let reach = groups[root].speed(ctx.dt) * rest;
            if groups[root].too_far_reaching(reach, self.crowd_radius) {
                groups[root].crowd = true;
                continue;
            }
            self.query_reach(k, reach, candidates, ctx);
            let at = self.segments[k].position;
            for &m in candidates.iter() {
                let m = m as usize;
                if m == k || !self.is_fallen(m) {
                    continue;
                }
                // The nearest the taken body's drift comes to where this one is now.
                let sm = &self.segments[m];
                let speed = sm.velocity.length_squared();
                let s = if speed > 0.0 {
                    ((at - sm.position).dot(sm.velocity) / speed).clamp(0.0, rest)
                } else {
                    0.0
                };
                let nearest = sm.position + sm.velocity * s;
                let within = CROWD_REACH_FACTOR * reach
                    + self.segments[k].radius()
                    + sm.radius()
                    + contact_band(&self.segments[k], sm, ctx.settings);
                if (nearest - at).length_squared() <= within * within {
                    groups[root].crowd = true;
                    break;
                }
            }
        }
        let share = u64::from(ctx.settings.max_collisions_per_body);
        let mut left = 0u64;
        let mut kept = left_out;
        kept.retain(|&k| {
            let root = self.crowd_parent[k as usize] as usize;
            let group = &groups[root];
            if group.crowd {
                if !self.is_fallen(k as usize) {
                    bodies.push(k);
                }
                return false;
            }
            if root == k as usize {
                left += (share * u64::from(group.count)).saturating_sub(group.versions);
            }
            true
        });
        let none_left = kept.is_empty();
        self.crowd_left = kept;
        self.crowd_groups = groups;
        if none_left {
            return 0;
        }
        u32::try_from(left).unwrap_or(u32::MAX).max(1)
    }

    /// Sets `candidates` to the bodies whose boxes may hold a body within `reach` (times
    /// [`CROWD_REACH_FACTOR`]) of touching segment `k` where it is now, give or take the
    /// contact band.
    fn query_reach(
        &mut self,
        k: usize,
        reach: f64,
        candidates: &mut Vec<u32>,
        ctx: &StepContext<'_>,
    ) {
        let segment = &self.segments[k];
        let r = segment.radius();
        let band = 2e-6 * r + ctx.settings.tolerance.epsilon() * (1.0 + r + self.crowd_radius);
        let grow = DVec3::splat(r + CROWD_REACH_FACTOR * reach + band);
        let query = Aabb {
            lo: segment.position - grow,
            hi: segment.position + grow,
        };
        self.collect_within(k, query, candidates);
    }

    /// Segment `k`'s box grown on every side by `margin` of its diameter.
    fn grown_box(&self, k: usize, margin: f64) -> Aabb {
        let grow = DVec3::splat(margin * 2.0 * self.segments[k].radius());
        let b = self.boxes[k];
        Aabb {
            lo: b.lo - grow,
            hi: b.hi + grow,
        }
    }

    /// Sets `candidates` to the bodies whose boxes overlap `query`, asked for as segment `k`
    /// (whose own box is put back after).
    fn collect_within(&mut self, k: usize, query: Aabb, candidates: &mut Vec<u32>) {
        candidates.clear();
        let swept = std::mem::replace(&mut self.boxes[k], query);
        self.broad.collect_overlapping(k, &self.boxes, candidates);
        self.boxes[k] = swept;
    }

    /// Whether segments `a` and `b`, where they are now, lie within `reach` (times
    /// [`CROWD_REACH_FACTOR`]) of touching, give or take the contact band.
    fn within_reach(&self, a: usize, b: usize, reach: f64, ctx: &StepContext<'_>) -> bool {
        let (sa, sb) = (&self.segments[a], &self.segments[b]);
        let within = CROWD_REACH_FACTOR * reach
            + sa.radius()
            + sb.radius()
            + contact_band(sa, sb, ctx.settings);
        (sb.position - sa.position).length_squared() <= within * within
    }

    /// Whether segments `a` and `b`, each at its position now, may come within half their
    /// contact band of touching over the `rest` of the step, at their velocities now, or
    /// within `margin` of their reach beyond that (as the fallback's rounds take pairs in).
    fn may_close(&self, a: usize, b: usize, margin: f64, rest: f64, ctx: &StepContext<'_>) -> bool {
        let (sa, sb) = (&self.segments[a], &self.segments[b]);
        let d = sb.position - sa.position;
        let distance = d.length();
        if distance == 0.0 {
            return true;
        }
        let normal = d / distance;
        let reach = sa.radius() + sb.radius();
        let band = contact_band(sa, sb, ctx.settings);
        let approach = -(sb.velocity - sa.velocity).dot(normal);
        approach * rest + margin * reach >= distance - reach - 0.5 * band
    }

    /// Whether segment `k` was taken by a fallback of this step, or is on a string (the
    /// fallback holds no string: such a body's impacts after one are deferred).
    pub(super) fn is_fallen(&self, k: usize) -> bool {
        bit(&self.fallen_bits, k) || self.string_of(k).is_some()
    }

    /// Whether either of `event`'s bodies [`Solver::is_fallen`].
    pub(super) fn has_fallen(&self, event: &Event) -> bool {
        self.is_fallen(event.a as usize) || self.is_fallen(event.b as usize)
    }

    /// Marks segment `k` taken by a fallback of this step.
    fn mark_fallen(&mut self, k: u32) {
        let (word, bit) = (k as usize / 64, 1u64 << (k % 64));
        if self.fallen_bits.len() <= word {
            self.fallen_bits.resize(word + 1, 0);
        }
        if self.fallen_bits[word] & bit == 0 {
            self.fallen_bits[word] |= bit;
            self.fallen.push(k);
        }
    }

    /// Forgets the bodies the last step's fallbacks took.
    pub(super) fn clear_fallen(&mut self) {
        for &k in &self.fallen {
            self.fallen_bits[k as usize / 64] = 0;
        }
        self.fallen.clear();
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
            // The first round of a fallback's first solve finds the candidates
            // `Solver::choose_crowd` found (the same boxes, nothing moved since).
            let found = *round == 0 && self.crowd_found;
            for &k in bodies.iter() {
                let k = k as usize;
                candidates.clear();
                if found {
                    let (start, len) = self.crowd_ranges[k];
                    let (start, len) = (start as usize, len as usize);
                    candidates.extend_from_slice(&self.crowd_candidates[start..start + len]);
                } else if margin > 0.0 {
                    self.collect_within(k, self.grown_box(k, margin), candidates);
                } else {
                    self.broad.collect_overlapping(k, &self.boxes, candidates);
                }
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
            self.crowd_found = false;
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

/// How much farther than their energy allows (see [`Group::speed`]) the bodies left out of a
/// fallback are taken to reach: the event loop's impacts add no energy but rounding's.
const CROWD_REACH_FACTOR: f64 = 1.25;

/// How far (in radii of the largest dynamic sphere) a group of [`CROWD_CAP_BODIES`] or more
/// may reach and still be left out of a fallback (see [`Group::too_far_reaching`]). Without
/// it the rain above a landing pit of 10 000, joined into groups by their energy, looked each
/// step over boxes metres across, one for each sphere (its slowest step 439 ms, against 250 to
/// 330 with the cap).
const CROWD_REACH_CAP: f64 = 4.0;

/// The fewest bodies of a group that [`CROWD_REACH_CAP`] applies to.
const CROWD_CAP_BODIES: u32 = 8;

/// The most passes of [`Solver::choose_crowd`] joining the groups left out that may meet;
/// past them the fallback takes every body.
const CROWD_PASSES: u32 = 4;

/// The most solves of [`Solver::fall_back`] after its first for the groups its drifts may
/// reach; past them it takes every body still left out. (Also the most passes of
/// [`Solver::take_reached`], before the first.)
const FALLBACK_FOLLOW_UPS: u32 = 3;

/// A group of dynamic bodies of [`Solver::choose_crowd`], as kept at its root.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Group {
    /// Its dynamic bodies.
    count: u32,
    /// The sum of their versions: the changes to their drifts this step.
    versions: u64,
    /// Their kinetic energy at the fallback's time.
    energy: f64,
    /// The largest inverse mass among them.
    lightest: f64,
    /// The largest acceleration among them (an impact between bodies accelerated unlike
    /// answers the drifts' lag behind the kicks, see `Solver::resolve_at`: up to that
    /// acceleration times the step in speed).
    accelerated: f64,
    /// Solved by the fallback: it spent its share of the budget, something taken may reach
    /// it, or it reaches too far to look around (see [`Group::too_far_reaching`]).
    crowd: bool,
}

impl Group {
    /// A group of one: `segment`, of `inverse_mass` and `acceleration`, at `version`.
    fn of(segment: &Segment, inverse_mass: f64, acceleration: f64, version: u32) -> Self {
        Group {
            count: 1,
            versions: u64::from(version),
            energy: 0.5 * segment.velocity.length_squared() / inverse_mass,
            lightest: inverse_mass,
            accelerated: acceleration,
            crowd: false,
        }
    }

    /// The fastest any of its bodies may go over the rest of a step of `dt` while it meets
    /// nothing outside the group: all its kinetic energy in its lightest body (no impact adds
    /// energy, and a fixed sphere that does not move gives none), and what impacts between
    /// bodies accelerated unlike may add to answer the drifts' lag (at most twice its largest
    /// acceleration times the step, for each of a few impacts: four times, allowed). Infinite
    /// if that is not a number.
    fn speed(&self, dt: f64) -> f64 {
        let speed = (2.0 * self.energy * self.lightest).sqrt() + 4.0 * self.accelerated * dt;
        if speed.is_nan() { f64::INFINITY } else { speed }
    }

    /// Whether this group is taken with the crowd rather than looked around at `reach` (its
    /// reach in the rest of the step, see [`Group::speed`]), `radius` being the largest
    /// dynamic one: a group of at least [`CROWD_CAP_BODIES`] bodies whose reach (times
    /// [`CROWD_REACH_FACTOR`]) is more than [`CROWD_REACH_CAP`] such radii. Each of its many
    /// bodies would look over a box of many cells, and such a group (a rain still falling as
    /// the crowd lands, joined by its energy) nearly always meets the crowd anyway. A few
    /// bodies look however far: their queries cost little, and taken, they would meet one
    /// another at restitution 0 in the solve.
    fn too_far_reaching(&self, reach: f64, radius: f64) -> bool {
        self.count >= CROWD_CAP_BODIES && CROWD_REACH_FACTOR * reach > CROWD_REACH_CAP * radius
    }

    /// Adds `other`'s bodies to this group.
    fn join(&mut self, other: &Group) {
        self.count += other.count;
        self.versions += other.versions;
        self.energy += other.energy;
        self.lightest = self.lightest.max(other.lightest);
        self.accelerated = self.accelerated.max(other.accelerated);
        self.crowd |= other.crowd;
    }
}
