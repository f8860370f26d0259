//! Testing pairs again after impacts changed bodies' drifts: each changed (touched) body's
//! box moved in the broad phase and queried (or, struck again at the instant of its last
//! query, its candidates of then reused, and its full query left to the instant's end), and
//! each candidate glanced at and, unless dismissed, given its time of impact.

use super::*;

/// How many pairs ahead the one-pass re-query asks for the bodies of the pair it will test (see
/// `Solver::requery_in_one_pass`).
const PAIRS_AHEAD: usize = 8;

impl Solver {
    /// Starts the step's stamps: no segment has been queried at any instant of it.
    pub(super) fn start_stamps(&mut self) {
        let n = self.segments.len();
        if self.query_stamps.len() < n {
            self.query_stamps.resize(n, 0);
            self.cache_ranges.resize(n, (0, 0));
        }
        let words = n.div_ceil(64);
        if self.dirty_bits.len() < words {
            self.dirty_bits.resize(words, 0);
        }
        // (A step refused midway may leave some.)
        self.forget_dirty();
        self.new_stamp(f64::NAN);
    }

    /// Clears the dirty segments' marks and list.
    pub(super) fn forget_dirty(&mut self) {
        for &k in &self.dirty {
            self.dirty_bits[k as usize / 64] &= !(1 << (k % 64));
        }
        self.dirty.clear();
    }

    #[inline(always)]
    pub(super) fn new_stamp(&mut self, t: f64) {
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.query_stamps.fill(0);
            self.stamp = 1;
        }
        self.stamp_time = t;
        self.candidate_cache.clear();
    }

    pub(super) fn is_dirty(&self, m: usize) -> bool {
        bit(&self.dirty_bits, m)
    }

    /// Tests every pair involving a body in `touched` (all dynamic, all just changed) from
    /// time `t`.
    ///
    /// A body queried in full at this same instant already (in a pile, a resting impact's
    /// bodies are solved again and again at its instant as the load spreads: seven re-queries
    /// in ten in a landing pit) is only tested against its candidates of then for impacts at
    /// this instant, the only ones that can change what happens at it: any pair touching it
    /// now was among them (every box holds its sphere at this instant). It is marked dirty,
    /// and queried in full once, when the instant ends ([`Solver::flush_dirty`]). A pair with
    /// a dirty body is likewise tested only for impacts at this instant.
    #[inline(always)]
    pub(super) fn requery_touched(&mut self, t: f64, ctx: &StepContext<'_>, stats: &mut StepStats) {
        if self.strings || ctx.toi.is_some() {
            self.requery_full(t, ctx, stats);
            return;
        }
        if t != self.stamp_time {
            debug_assert!(
                self.dirty.is_empty(),
                "dirty segments left at a past instant"
            );
            self.new_stamp(t);
        }
        let (stamps, stamp) = (&self.query_stamps, self.stamp);
        if self.touched.iter().any(|&k| stamps[k as usize] == stamp) {
            self.requery_again(t, ctx, stats);
        } else {
            self.requery_full(t, ctx, stats);
        }
    }

    /// [`Solver::requery_touched`] when some touched bodies were queried in full at this
    /// instant already.
    #[inline(never)]
    pub(super) fn requery_again(&mut self, t: f64, ctx: &StepContext<'_>, stats: &mut StepStats) {
        let (stamps, stamp) = (&self.query_stamps, self.stamp);
        let mut repeats = std::mem::take(&mut self.repeats);
        repeats.clear();
        self.touched.retain(|&k| {
            let repeat = stamps[k as usize] == stamp;
            if repeat {
                repeats.push(k);
            }
            !repeat
        });
        for &k in &repeats {
            if !self.is_dirty(k as usize) {
                self.dirty_bits[k as usize / 64] |= 1 << (k % 64);
                self.dirty.push(k);
            }
        }
        self.requery_full(t, ctx, stats);
        let until = std::mem::replace(&mut self.queue_until, t);
        for &k in &repeats {
            let k = k as usize;
            let (start, len) = self.touching_candidates(k, t, ctx);
            for at in start..start + len {
                let m = self.candidate_cache[at] as usize;
                // Touched bodies queried in full test their pairs with this one; of two
                // dirty ones, the first.
                if self.is_touched(m) && (!self.is_dirty(m) || m < k) {
                    continue;
                }
                self.test_pair(k.min(m), k.max(m), t, ctx, stats);
            }
        }
        self.queue_until = until;
        // Back in the list, so that their marks are cleared with the others'.
        self.touched.extend_from_slice(&repeats);
        self.repeats = repeats;
    }

    /// Body `k`'s candidates kept at this instant that touch it now, as a range of
    /// [`Solver::candidate_cache`]: only a pair touching now can meet now (one missed near
    /// the margin is found when the instant ends). Sifted from all its candidates the first
    /// time they are asked for (positions at the instant do not change within it).
    pub(super) fn touching_candidates(
        &mut self,
        k: usize,
        t: f64,
        ctx: &StepContext<'_>,
    ) -> (usize, usize) {
        const SIFTED: u32 = 1 << 31;
        let (start, len) = self.cache_ranges[k];
        let (start, mut len) = (start as usize, len as usize);
        if len & SIFTED as usize != 0 {
            return (start, len & !(SIFTED as usize));
        }
        let sk = self.segments[k];
        let at = sk.position_at(t);
        let mut kept = 0;
        for i in start..start + len {
            let m = self.candidate_cache[i] as usize;
            let sm = &self.segments[m];
            let near = (sk.radius() + sm.radius() + 4.0 * contact_band(&sk, sm, ctx.settings))
                * (1.0 + 1e-6);
            if m != k && (sm.position_at(t) - at).length_squared() <= near * near {
                self.candidate_cache[start + kept] = m as u32;
                kept += 1;
            }
        }
        len = kept;
        self.cache_ranges[k] = (start as u32, len as u32 | SIFTED);
        (start, len)
    }

    /// Queries the dirty segments in full (see [`Solver::requery_touched`]), at the instant
    /// they were changed.
    pub(super) fn flush_dirty(&mut self, ctx: &StepContext<'_>, stats: &mut StepStats) {
        self.clear_touched();
        for i in 0..self.dirty.len() {
            self.touch(self.dirty[i]);
        }
        self.forget_dirty();
        let t = self.stamp_time;
        self.caching = true;
        self.requery_full(t, ctx, stats);
    }

    /// Puts the dirty segments' boxes in the broad phase and forgets them, their pairs not
    /// tested in full (the collision budget has run out: see the event loop).
    pub(super) fn drop_dirty(&mut self) {
        for &k in &self.dirty {
            self.broad.update(k as usize, &self.boxes[k as usize]);
        }
        self.forget_dirty();
    }

    /// Tests every pair involving a body in `touched` once, from time `t`, after moving their
    /// boxes in the broad phase; keeps each body's candidates for the instant.
    pub(super) fn requery_full(&mut self, t: f64, ctx: &StepContext<'_>, stats: &mut StepStats) {
        for ti in 0..self.touched.len() {
            let k = self.touched[ti] as usize;
            self.broad.update(k, &self.boxes[k]);
        }
        let mut candidates = std::mem::take(&mut self.candidates);
        let mut partner_candidates = std::mem::take(&mut self.partner_candidates);
        let mut ti = 0;
        while ti < self.touched.len() {
            let k = self.touched[ti] as usize;
            candidates.clear();
            // Two bodies that just struck each other (next to each other in `touched`) lie side
            // by side, so their queries read nearly the same grid rows: one scan finds the
            // candidates of both (the 10k shower runs 2% fewer instructions, and each
            // benchmark 1% to 10% faster).
            let partner = self
                .touched
                .get(ti + 1)
                .map(|&l| l as usize)
                .filter(|&l| self.boxes[k].overlaps(&self.boxes[l]));
            if let Some(l) = partner {
                partner_candidates.clear();
                self.broad.collect_overlapping_both(
                    (k, l),
                    &self.boxes,
                    &mut candidates,
                    &mut partner_candidates,
                );
                self.keep_candidates(k, &candidates);
                self.keep_candidates(l, &partner_candidates);
                self.test_candidates(k, &candidates, t, ctx, stats);
                self.test_candidates(l, &partner_candidates, t, ctx, stats);
                ti += 2;
            } else {
                self.broad
                    .collect_overlapping(k, &self.boxes, &mut candidates);
                self.keep_candidates(k, &candidates);
                self.test_candidates(k, &candidates, t, ctx, stats);
                ti += 1;
            }
        }
        self.candidates = candidates;
        self.partner_candidates = partner_candidates;
    }

    /// [`Solver::requery_touched`] at the step's start, after the resting solve, when it
    /// changed at least a third of the segments (a bed, or spheres resting on a floor, all
    /// given their loads): one pass over the broad phase's pairs, keeping those with a touched
    /// segment, instead of a query for each touched segment, which reads its neighbourhood of
    /// cells for itself (spheres resting on a floor took three to four times the first pass's
    /// time in those queries). Every pair whose boxes overlap is tested, each once, as the
    /// queries would test it (the grid's pass may offer a few more, whose boxes meet only in
    /// its rounded comparison, as the first pass does: they cannot meet), and each touched
    /// segment keeps its candidates of the instant (in another order, without itself, and with
    /// or without such pairs): the same results, bit for bit.
    /// Returns false, having done nothing but move the boxes, unless candidates are kept
    /// ([`Solver::caching`]: no strings, no custom method), and every touched segment stays
    /// where the broad phase's pass finds its pairs (see [`BroadPhase::update_kept`]).
    pub(super) fn requery_in_one_pass(
        &mut self,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) -> bool {
        if !self.caching
            || self.touched.len() < ONE_PASS_MIN
            || 3 * self.touched.len() < self.segments.len()
        {
            return false;
        }
        let mut kept = true;
        for ti in 0..self.touched.len() {
            let k = self.touched[ti] as usize;
            kept &= self.broad.update_kept(k, &self.boxes[k]);
        }
        if !kept {
            return false;
        }
        self.new_stamp(0.0);
        let mut found = std::mem::take(&mut self.touched_pairs);
        let mut batch = std::mem::take(&mut self.pairs);
        found.clear();
        batch.clear();
        let mut keep = |batch: &mut Vec<(u32, u32)>| {
            found.extend(
                batch
                    .iter()
                    .filter(|&&(i, j)| self.is_touched(i as usize) || self.is_touched(j as usize)),
            );
            batch.clear();
        };
        self.broad
            .pairs_batched(&self.boxes, &mut batch, 64, &mut keep);
        keep(&mut batch);
        self.pairs = batch;
        // Each touched segment's candidates, as its query would keep them: counted into
        // `cache_ranges`, then placed.
        for &k in &self.touched {
            self.query_stamps[k as usize] = self.stamp;
            self.cache_ranges[k as usize] = (0, 0);
        }
        for &(i, j) in &found {
            for k in [i, j] {
                if self.is_touched(k as usize) {
                    self.cache_ranges[k as usize].1 += 1;
                }
            }
        }
        let mut start = 0;
        for &k in &self.touched {
            let range = &mut self.cache_ranges[k as usize];
            let count = range.1;
            *range = (start, 0);
            start += count;
        }
        self.candidate_cache.clear();
        self.candidate_cache.resize(start as usize, 0);
        for &(i, j) in &found {
            for (k, m) in [(i, j), (j, i)] {
                if self.is_touched(k as usize) {
                    let range = &mut self.cache_ranges[k as usize];
                    self.candidate_cache[(range.0 + range.1) as usize] = m;
                    range.1 += 1;
                }
            }
        }
        for (n, &(i, j)) in found.iter().enumerate() {
            // Ask ahead for the bodies' `Extra`s (a pair's test reads them for its press), kept
            // in the bodies' order, not the grid's (the 100k table's resting contacts, this
            // pass among them: 397 to 472 ns a sphere a step against 422 to 472, six turns).
            if let Some(&(a, b)) = found.get(n + PAIRS_AHEAD) {
                prefetch(self.extra(a as usize));
                prefetch(self.extra(b as usize));
            }
            self.test_pair(i as usize, j as usize, 0.0, ctx, stats);
        }
        self.touched_pairs = found;
        true
    }

    /// Keeps `candidates` as body `k`'s at the current instant (see
    /// [`Solver::requery_touched`]), when [`Solver::caching`]: at an instant where a resting
    /// contact took an impulse (a pile's loads spread through such instants; a shower's rain
    /// seldom meets anything twice at one instant, and is spared the copies), after the
    /// resting solve, and in the queries of dirty segments at their instant's end.
    pub(super) fn keep_candidates(&mut self, k: usize, candidates: &[u32]) {
        if !self.caching {
            return;
        }
        self.query_stamps[k] = self.stamp;
        self.cache_ranges[k] = (self.candidate_cache.len() as u32, candidates.len() as u32);
        self.candidate_cache.extend_from_slice(candidates);
    }

    /// Tests touched body `k` against each of its `candidates` (a pair of touched bodies once;
    /// `k` itself, touched, is skipped with them).
    pub(super) fn test_candidates(
        &mut self,
        k: usize,
        candidates: &[u32],
        t: f64,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) {
        for &m in candidates {
            // Ask for the segment now, so the tests below find it loaded: the event
            // loop's reads are random, and waiting for each in turn dominated them.
            prefetch(&self.segments[m as usize]);
        }
        // Pairs with a sphere on a string take the full test (see `Solver::bent_pair`): all of
        // `k`'s if it hangs on one, else those of its candidates that do.
        if ctx.toi.is_some() || self.on_string(k) {
            for &m in candidates {
                let m = m as usize;
                if m <= k && self.is_touched(m) {
                    continue;
                }
                self.test_pair(k.min(m), k.max(m), t, ctx, stats);
            }
            return;
        }
        // The glance as `test_pair` takes it, but from `k`'s side whichever body comes first:
        // `k`'s part of it is worked out once for all its candidates (the compiler cannot
        // hoist it, the full test between the glances being free to change any segment).
        let side = Side::of(&self.segments[k], t, ctx.dt);
        if candidates.len() < FEW_CANDIDATES {
            for &m in candidates {
                let bent = self.on_string(m as usize);
                self.glance_from(k, m as usize, &side, bent, ctx, stats);
            }
            return;
        }
        // The glances' outcomes first, without a branch on any (see `kept_by_glances`): a
        // bit for each candidate not dismissed, 64 candidates at a time. Then the rest of the
        // test for those, one by one.
        for candidates in candidates.chunks(64) {
            let mut kept = kept_by_glances(&side, &self.segments, candidates, self.apart);
            // Debug builds check each outcome against the glance one by one, and each
            // dismissal against the full test (`test_glanced`).
            #[cfg(debug_assertions)]
            for (at, &m) in candidates.iter().enumerate() {
                let dismissed = kept >> at & 1 == 0;
                assert_eq!(
                    dismissed,
                    side.glance(&self.segments[m as usize])
                        .dismisses(self.apart),
                    "the glances side by side differ from body {k}'s glance at candidate {m}"
                );
                if dismissed && !self.on_string(m as usize) {
                    self.glance_from(k, m as usize, &side, false, ctx, stats);
                }
            }
            if self.strings {
                for (at, &m) in candidates.iter().enumerate() {
                    if self.on_string(m as usize) {
                        kept |= 1 << at;
                    }
                }
            }
            while kept != 0 {
                let at = kept.trailing_zeros() as usize;
                kept &= kept - 1;
                self.glance_from(k, candidates[at] as usize, &side, true, ctx, stats);
            }
        }
    }

    /// Tests the pair of body `k` and its candidate `m` from `k`'s [`Side`], unless `m` is
    /// touched and comes first (the pair is tested from `m`'s side). With `kept`, the glance
    /// is known not to dismiss the pair (`kept_by_glances` said so), or must not (a sphere on
    /// a string): it goes straight to the full test. A dirty `m` is tested only for an impact
    /// at this instant (see [`Solver::requery_touched`]).
    #[inline(always)]
    pub(super) fn glance_from(
        &mut self,
        k: usize,
        m: usize,
        side: &Side,
        kept: bool,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) {
        let t = side.t;
        if !self.dirty.is_empty() && self.is_dirty(m) {
            // Only for an impact at this instant (see `requery_touched`).
            let until = std::mem::replace(&mut self.queue_until, t);
            self.test_pair(k.min(m), k.max(m), t, ctx, stats);
            self.queue_until = until;
            return;
        }
        if m <= k && self.is_touched(m) {
            return;
        }
        let (i, j) = (k.min(m), k.max(m));
        let glance = side.glance(&self.segments[m]);
        // Seen from the first body of the pair: the same numbers, negated if `k` is the
        // second (negation is exact, and every quantity the glance compares is even in
        // the relative drift, so its outcome is the same either way, bit for bit).
        let glance = if m < k { glance.turned() } else { glance };
        #[cfg(debug_assertions)]
        {
            assert!(
                glance.same_as(&Glance::of(&self.segments[i], &self.segments[j], t, ctx.dt)),
                "the glance from body {k}'s side differs from the pair's ({i}, {j})"
            );
        }
        if kept {
            debug_assert!(
                !glance.dismisses(self.apart) || self.bent_pair(i, j),
                "pair ({i}, {j}) kept, but dismissed"
            );
            self.test_pair_fully(i, j, t, &glance, ctx, stats);
        } else {
            self.test_glanced(i, j, t, &glance, ctx, stats);
        }
    }

    pub(super) fn is_touched(&self, m: usize) -> bool {
        match self.touched_bits.get(m / 64) {
            Some(word) => word >> (m % 64) & 1 != 0,
            None => false,
        }
    }

    /// Starts a new set of touched bodies.
    pub(super) fn clear_touched(&mut self) {
        for &k in &self.touched {
            self.touched_bits[k as usize / 64] &= !(1 << (k % 64));
        }
        self.touched.clear();
        let words = self.segments.len().div_ceil(64);
        if self.touched_bits.len() < words {
            self.touched_bits.resize(words, 0);
        }
    }

    pub(super) fn touch(&mut self, k: u32) {
        if !self.segments[k as usize].is_fixed() && !self.is_touched(k as usize) {
            self.touched_bits[k as usize / 64] |= 1 << (k % 64);
            self.touched.push(k);
        }
    }
}
