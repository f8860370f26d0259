//! The impacts the event loop takes from its queue, solved: one alone (with a string or a
//! strut where a sphere hangs on one), several at one instant together, a resting impact
//! together with the contacts that took a resting impulse earlier at its instant, and a light
//! sphere squeezed between heavier ones; each recorded as the step's collisions.

use glam::DVec3;

use super::*;

impl Solver {
    /// If every impact of `component` (at time `t`) is a resting one and shares a dynamic body
    /// with a resting contact that took an impulse at this instant, gathers into `joined` the
    /// impacts and every instant contact connected to them through dynamic bodies, touches
    /// their bodies, and says so. Otherwise the group is left to be solved as usual (its
    /// pairs' own earlier contacts at this instant are marked replaced either way: they are
    /// recorded again when solved). Impacts on bodies hanging on strings are left to
    /// [`Solver::resolve_event`] (a contact of the instant may still bring a strung body into
    /// a group: [`Solver::resolve_group`] handles taut strings).
    pub(super) fn join_instant(&mut self, component: &[Event], t: f64) -> bool {
        let instant = &self.instant;
        if instant.is_empty()
            || !component
                .iter()
                .any(|e| instant.involves(e.a) || instant.involves(e.b))
            || !component.iter().all(|e| self.resting_at(e))
        {
            return false;
        }
        let moves = moving(&self.segments);
        for e in component {
            // Solved again below with the impact that replaces it.
            self.instant.replace(e.a, e.b, moves);
        }
        self.joined.clear();
        self.joined.extend_from_slice(component);
        let (joined, versions) = (&mut self.joined, &self.versions);
        self.instant
            .gather(component.iter().flat_map(|e| [e.a, e.b]), moves, |a, b| {
                joined.push(Event {
                    time: t,
                    a,
                    b,
                    version_a: versions[a as usize],
                    version_b: versions[b as usize],
                })
            });
        if self.joined.len() == component.len() {
            return false;
        }
        for i in 0..self.instant.reached().len() {
            let k = self.instant.reached()[i];
            self.touch(k);
        }
        true
    }

    /// Solves `component` (impacts at time `t`, one of whose bodies has taken its share of
    /// collisions this step, or bounced [`COLLAPSE_BOUNCES`] times at `t`) together with every
    /// contact touching at `t` that connects to it through dynamic bodies (up to about
    /// [`SQUEEZE_CONTACTS`]), all with restitution 0, into [`Solver::joined`], and touches
    /// their bodies. A light sphere squeezed between heavier ones closing on it (or against a
    /// fixed one) bounces between them faster and faster: with restitutions below 1 the
    /// bounces have no end before the squeeze does (an inelastic collapse). It took its whole
    /// share (then 1024 collisions), was then deferred and was squeezed into them (2.8 of its
    /// radius in one of the fuzz's scenes). The solve stops every contact of the cluster
    /// closing at once, as the bounces would in the limit (no push against an overlap: it only
    /// stops the contacts closing), keeping momentum.
    ///
    /// With `along` (a collapse's squeeze: the first impact's normal and a speed, see
    /// [`COLLAPSE_BOUNCES`]), only contacts whose normals lie within 30° of that line
    /// ([`ALONG_COS`]) and that close or part no faster than that speed join the cluster
    /// beside `component`'s own impacts (which the caller has found as slow): a
    /// collapse runs along the line of its impacts (a struck row), the contacts across it (the
    /// row's neighbours on either side, a floor under it) would take no impulse from the solve
    /// but fill the cluster's room (taking them, a struck row of 100 in a lattice of marbles
    /// was squeezed 937 times at one instant, each cluster about 105 marbles around one point
    /// of the row), and a fast contact's bounces are not the collapse's to end. If a contact
    /// along the line closes faster, the collapse is not over: nothing is solved, and false is
    /// returned.
    pub(super) fn squeeze(
        &mut self,
        component: &[Event],
        t: f64,
        along: Option<(DVec3, f64)>,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) -> bool {
        let mut joined = std::mem::take(&mut self.joined);
        let mut candidates = std::mem::take(&mut self.candidates);
        let mut cluster = std::mem::take(&mut self.squeeze_cluster);
        let mut over = true;
        let words = self.segments.len().div_ceil(64);
        if self.squeeze_bits.len() < words {
            self.squeeze_bits.resize(words, 0);
            self.squeeze_done.resize(words, 0);
        }
        joined.clear();
        joined.extend_from_slice(component);
        cluster.clear();
        for e in component {
            for k in [e.a, e.b] {
                if !self.segments[k as usize].is_fixed() && !bit(&self.squeeze_bits, k as usize) {
                    self.squeeze_bits[k as usize / 64] |= 1 << (k % 64);
                    cluster.push(k);
                }
            }
        }
        // Breadth first over the dynamic bodies touching at `t`: a pair is added when the
        // first of its bodies is reached (the other not yet looked at, or fixed).
        let mut next = 0;
        while over && next < cluster.len() && joined.len() < SQUEEZE_CONTACTS {
            let k = cluster[next] as usize;
            next += 1;
            self.squeeze_done[k / 64] |= 1 << (k % 64);
            candidates.clear();
            self.broad
                .collect_overlapping(k, &self.boxes, &mut candidates);
            let sk = self.segments[k];
            let at = sk.position_at(t);
            for &m in &candidates {
                let m = m as usize;
                let sm = &self.segments[m];
                if m == k || bit(&self.squeeze_done, m) {
                    continue;
                }
                let touch = (sk.radius() + sm.radius() + contact_band(&sk, sm, ctx.settings))
                    * (1.0 + 1e-9);
                let d = sm.position_at(t) - at;
                if d.length_squared() > touch * touch {
                    continue;
                }
                if let Some((line, slow)) = along {
                    let length = d.length();
                    if d.dot(line).abs() < ALONG_COS * length {
                        continue;
                    }
                    let parting = (sm.velocity - sk.velocity).dot(d);
                    if parting < -slow * length {
                        // Still closing fast: the collapse is not over, its bounces go on.
                        over = false;
                        break;
                    }
                    if parting > slow * length {
                        continue;
                    }
                }
                let (a, b) = (k.min(m) as u32, k.max(m) as u32);
                if !component.iter().any(|e| (e.a, e.b) == (a, b)) {
                    joined.push(Event {
                        time: t,
                        a,
                        b,
                        version_a: self.versions[a as usize],
                        version_b: self.versions[b as usize],
                    });
                }
                if !sm.is_fixed() && !bit(&self.squeeze_bits, m) {
                    self.squeeze_bits[m / 64] |= 1 << (m % 64);
                    cluster.push(m as u32);
                }
            }
        }
        for &k in &cluster {
            self.squeeze_bits[k as usize / 64] &= !(1 << (k % 64));
            self.squeeze_done[k as usize / 64] &= !(1 << (k % 64));
        }
        self.candidates = candidates;
        self.squeeze_cluster = cluster;
        if !over {
            self.joined = joined;
            return false;
        }
        self.inelastic = true;
        self.resolve_group(&joined, t, ctx, stats);
        self.inelastic = false;
        for e in &joined {
            self.touch(e.a);
            self.touch(e.b);
        }
        self.joined = joined;
        true
    }

    /// Whether impact `e` is a resting one (see [`Solver::restitution`]) on bodies without
    /// strings.
    pub(super) fn resting_at(&self, e: &Event) -> bool {
        let (a, b) = (e.a as usize, e.b as usize);
        if self.strung(a).is_some() || self.strung(b).is_some() {
            return false;
        }
        let (sa, sb) = (&self.segments[a], &self.segments[b]);
        let d = sb.position_at(e.time) - sa.position_at(e.time);
        let distance = d.length();
        if distance == 0.0 {
            return false;
        }
        let normal = d / distance;
        let approach_speed = -(sb.velocity - sa.velocity).dot(normal);
        approach_speed <= self.resting_scale * self.press(a, b, normal)
    }

    /// Resolves contacts that happen at one instant together (see [`resolve_simultaneous`]).
    pub(super) fn resolve_group(
        &mut self,
        events: &[Event],
        t: f64,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) {
        let settings = ctx.settings;
        self.local_bodies.clear();
        if self.local_index.len() < self.segments.len() {
            self.local_index.resize(self.segments.len(), NOT_LOCAL);
        }
        for e in events {
            for k in [e.a, e.b] {
                let slot = &mut self.local_index[k as usize];
                if *slot == NOT_LOCAL {
                    *slot = self.local_bodies.len() as u32;
                    self.local_bodies.push(k);
                }
            }
        }
        let local = |index: &[u32], k: u32| index[k as usize] as usize;
        self.local_inverse_masses.clear();
        self.local_velocities.clear();
        self.local_taut.clear();
        for i in 0..self.local_bodies.len() {
            let k = self.local_bodies[i] as usize;
            let taut = self.taut_at(k, t);
            self.local_taut.push(taut);
            let strung = self.strung(k).copied();
            self.segments[k].advance_to(t);
            self.local_inverse_masses
                .push(self.extras[self.order[k] as usize].inverse_mass);
            let mut velocity = match strung {
                // Bent for later, slack now: it moves freely.
                Some(strung) if strung.taut && !taut => strung.free_velocity,
                _ => self.segments[k].velocity,
            };
            if let (Some(Strung { tether, .. }), true) = (strung, taut) {
                // The drift is a chord of the string's sphere; the sphere itself is on that
                // sphere, moving tangent to it. Put it there (a move of at most the chord's
                // sagitta, ~(v·dt)²/8L), but no deeper into a sphere it strikes now than it
                // touches it, and drop the drift's radial part (the string's pull).
                let r = self.segments[k].position - tether.anchor;
                let distance = r.length();
                if distance > 0.0 {
                    let normal = r / distance;
                    let onto = normal * (tether.length - distance);
                    let allowed = self.move_allowed(k, onto, events, t);
                    let segment = &mut self.segments[k];
                    segment.position = if allowed >= 1.0 {
                        tether.anchor + normal * tether.length
                    } else {
                        segment.position + onto * allowed
                    };
                    velocity -= normal * velocity.dot(normal);
                }
            }
            self.local_velocities.push(velocity);
        }
        self.local_contacts.clear();
        self.local_resting.clear();
        self.local_bounces.clear();
        for e in events {
            let (sa, sb) = (&self.segments[e.a as usize], &self.segments[e.b as usize]);
            let d = sb.position - sa.position;
            let distance = d.length();
            if distance == 0.0 {
                continue;
            }
            let normal = d / distance;
            let (a, b) = (e.a as usize, e.b as usize);
            let (la, lb) = (local(&self.local_index, e.a), local(&self.local_index, e.b));
            let (mut restitution, resting) = self.restitution(a, b, normal, settings);
            if self.inelastic {
                restitution = 0.0;
            }
            // As for a single resting impact (see `resolve_event`): keep undoing an overlap
            // deeper than the allowance. (Not in a squeeze, which only stops the contacts
            // closing: its cluster may hold pairs placed deep in each other, whose pushes
            // apart, solved with it, gave it energy.)
            let bias = if resting && !self.inelastic {
                let reach = sa.radius() + sb.radius();
                let press = self.press(a, b, normal);
                let band = contact_band(sa, sb, settings);
                let correction = self.correction(
                    reach - distance,
                    band,
                    press,
                    sa.radius().min(sb.radius()),
                    ctx,
                );
                // A pair on a taut string already parting at half its push is given none: its
                // string's chord, bent from the velocities solved here, closes on the other
                // again at this instant, and each solve's push, taken on the tangent and bent
                // back, fell a little short of the last, so the pair struck again and again
                // until the collision budget ran out (494 times at one instant in the scene of
                // `regression_light_strung_sphere_whipped.rs`). It settles instead, its string
                // bent sooner (see `Solver::bend_sooner_if_closing`), and an overlap left at
                // the step's end is moved apart (see `Solver::separate`).
                let parting = (self.local_velocities[lb] - self.local_velocities[la]).dot(normal);
                if (self.local_taut[la] || self.local_taut[lb]) && parting >= 0.5 * correction {
                    0.0
                } else {
                    correction
                }
            } else {
                0.0
            };
            self.local_resting.push(resting);
            // A bounce's approach (see `COLLAPSE_BOUNCES`), before the solve changes the
            // velocities (and, on top of a shifted solve, every restitution); or none.
            self.local_bounces.push(
                (!resting && restitution > 0.0 && restitution < 1.0)
                    .then(|| -(self.local_velocities[lb] - self.local_velocities[la]).dot(normal)),
            );
            self.local_contacts.push(GroupContact {
                a: la,
                b: lb,
                normal,
                restitution,
                bias,
                string: false,
            });
        }
        // Taut strings of the bodies involved, each to a virtual fixed anchor.
        for (local, &k) in self.local_bodies.iter().enumerate() {
            let segment = &self.segments[k as usize];
            if let (Some(&Strung { tether, .. }), true) =
                (self.strung(k as usize), self.local_taut[local])
            {
                let r = segment.position - tether.anchor;
                let distance = r.length();
                if distance > 0.0 {
                    self.local_contacts.push(GroupContact {
                        a: local,
                        b: self.local_inverse_masses.len(),
                        normal: r / distance,
                        restitution: 0.0,
                        bias: 0.0,
                        string: true,
                    });
                    self.local_inverse_masses.push(0.0);
                    self.local_velocities.push(DVec3::ZERO);
                }
            }
        }
        if self.strings {
            self.add_struts(events, settings);
        }
        // As for a single impact (see `resolve_event`): the impacts answer the speeds at their
        // instant, which differ from the drifts' where the bodies' accelerations differ (a ball
        // landing on two fixed spheres at once). Not with a taut string or a resting contact
        // in the group, whose solves hold the drifts themselves.
        let lag_time = t - 0.5 * ctx.dt;
        // (Without a taut string every contact is between bodies: the string's anchors, past
        // `local_bodies`, are not asked about.)
        let shifted = !self.local_taut.contains(&true)
            && !self.local_resting.contains(&true)
            && self.local_contacts.iter().any(|c| {
                let acceleration = |i: usize| {
                    self.extras[self.order[self.local_bodies[i] as usize] as usize].acceleration
                };
                (acceleration(c.b) - acceleration(c.a)).dot(c.normal) * lag_time != 0.0
            });
        if shifted {
            self.local_shifts.clear();
            for (&k, velocity) in self.local_bodies.iter().zip(&mut self.local_velocities) {
                let shift = self.extras[self.order[k as usize] as usize].acceleration * lag_time;
                *velocity += shift;
                self.local_shifts.push(shift);
            }
        }
        // (A taut string's contact, after the events', pushes nothing.)
        let deep = self.local_contacts.iter().any(|c| {
            c.bias > 0.0 && {
                let radius =
                    |local: usize| self.segments[self.local_bodies[local] as usize].radius();
                self.deep_push(c.bias, radius(c.a).min(radius(c.b)), ctx)
            }
        });
        if deep {
            // (Only resting contacts push: the group is not shifted.)
            self.resolve_pushing_group(ctx);
        } else {
            resolve_simultaneous(
                &self.local_inverse_masses,
                &mut self.local_velocities,
                &self.local_contacts,
                &mut self.local_impulses,
            );
        }
        if shifted {
            for (velocity, shift) in self.local_velocities.iter_mut().zip(&self.local_shifts) {
                *velocity -= *shift;
            }
            // The drifts must not close: a pair the instant's speeds left parting slower than
            // its lag (or closing) is stopped, restitution 0, on top.
            // (Beyond rounding: the shift there and back moves a velocity by an ulp or so.)
            let velocities = &self.local_velocities;
            if self.local_contacts.iter().any(|c| {
                let (va, vb) = (velocities[c.a], velocities[c.b]);
                (vb - va).dot(c.normal) < -1e-12 * (va.length() + vb.length())
            }) {
                self.resolve_local_again();
                for (impulse, first) in self
                    .local_impulses
                    .iter_mut()
                    .zip(&self.local_first_impulses)
                {
                    *impulse += first;
                }
            }
        }
        for i in 0..self.local_bodies.len() {
            let (k, velocity) = (self.local_bodies[i] as usize, self.local_velocities[i]);
            self.set_velocity(k, velocity, t, ctx);
        }
        for &k in &self.local_bodies {
            self.local_index[k as usize] = NOT_LOCAL;
        }
        // The contacts of the events (a taut string's, after them, has no `local_resting`).
        for k in 0..self.local_resting.len() {
            let (c, impulse, resting) = (
                self.local_contacts[k],
                self.local_impulses[k],
                self.local_resting[k],
            );
            let (a, b) = (
                self.local_bodies[c.a] as usize,
                self.local_bodies[c.b] as usize,
            );
            let inverse_masses = self.local_inverse_masses[c.a] + self.local_inverse_masses[c.b];
            if gave_none(impulse, inverse_masses, settings) {
                self.bend_sooner_if_closing(a, b, t, ctx);
                self.settled.push(Settled::now(&self.versions, a, b));
                if self.inelastic {
                    // A squeeze's contact that took no impulse (mostly the cluster's touching
                    // contacts, closing too slowly or parting: four in ten of a struck rack's;
                    // an impact of the squeeze's own the others' impulses stopped) met nothing,
                    // and is not reported as a collision. (The collision budget still counts
                    // it: the squeeze's work grows with its cluster.)
                    continue;
                }
            } else if resting {
                self.instant
                    .record(a as u32, b as u32, moving(&self.segments));
            } else if let Some(speed) = self.local_bounces[k] {
                self.count_bounce(a, b, speed);
            }
            stats.collisions = stats.collisions.saturating_add(1);
            stats.resting_contacts = stats.resting_contacts.saturating_add(u32::from(resting));
            self.record_collision((a, b), t, c.normal, impulse, resting, ctx);
        }
    }

    /// Solves a group's contacts (in [`Solver::local_contacts`]) once more, restitution 0,
    /// from the velocities the last solve left: that solve's impulses are kept in
    /// [`Solver::local_first_impulses`], this one's are in [`Solver::local_impulses`].
    pub(super) fn resolve_local_again(&mut self) {
        self.local_first_impulses.clear();
        self.local_first_impulses
            .extend_from_slice(&self.local_impulses);
        for c in &mut self.local_contacts {
            c.restitution = 0.0;
        }
        resolve_simultaneous(
            &self.local_inverse_masses,
            &mut self.local_velocities,
            &self.local_contacts,
            &mut self.local_impulses,
        );
    }

    pub(super) fn resolve_event(
        &mut self,
        event: &Event,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) {
        let (a, b) = (event.a as usize, event.b as usize);
        let t = event.time;
        if self.strings && self.resolve_strut(event, ctx, stats) {
            return;
        }
        if self.taut_at(a, t) || self.taut_at(b, t) {
            // A taut string takes part in the impact: solve it with the contact.
            self.resolve_group(std::slice::from_ref(event), t, ctx, stats);
            return;
        }
        for k in [a, b] {
            let slack = self.strung(k).filter(|s| s.taut).map(|s| s.free_velocity);
            let segment = &mut self.segments[k];
            segment.advance_to(t);
            if let Some(free_velocity) = slack {
                // Bent for later, slack now: it moves freely.
                segment.velocity = free_velocity;
            }
        }
        let (sa, sb) = (self.segments[a], self.segments[b]);
        let d = sb.position - sa.position;
        let distance = d.length();
        if distance == 0.0 {
            return;
        }
        let normal = d / distance;
        let (restitution, resting) = self.restitution(a, b, normal, ctx.settings);
        let (ea, eb) = (self.extra(a), self.extra(b));
        let (ima, imb) = (ea.inverse_mass, eb.inverse_mass);
        // A drift's velocity is its body's velocity at the middle of the step (both built-in
        // integrators' is): at the impact, at `t`, a body under its own acceleration moves at
        // that plus its acceleration times `t − dt/2`. A bounce answers the pair's speed then.
        // Two spheres under gravity alone have no lag, and a contact brought to rest is held
        // on its drifts.
        let lag = if resting {
            0.0
        } else {
            (eb.acceleration - ea.acceleration).dot(normal) * (t - 0.5 * ctx.dt)
        };
        let mut r = resolve_at(ima, imb, sa.velocity, sb.velocity, normal, restitution, lag);
        if resting {
            // Keep undoing an overlap deeper than the allowance, as the step's resting solve
            // began to: stopping the pair dead here would cancel that and let a pressed pile
            // sink a little every step. A pair already parting (on a string's free velocity,
            // its bent drift closing) parts at least that fast, not that much faster: again
            // and again at one instant, the push would pile up.
            let reach = sa.radius() + sb.radius();
            let band = contact_band(&sa, &sb, ctx.settings);
            let press = self.press(a, b, normal);
            let parting = (sb.velocity - sa.velocity).dot(normal);
            let smaller = sa.radius().min(sb.radius());
            let correction = self.correction(reach - distance, band, press, smaller, ctx);
            let bias = if parting > 0.0 {
                // What is left of the push once the parting counts, unless only rounding is
                // (then the pair takes no impulse, and settles).
                let left = correction - parting;
                if left > 1e-9 * correction { left } else { 0.0 }
            } else {
                correction
            };
            // No more than what is left of either body's push budget this step: impacts
            // against an overlap one after another (a ball bouncing between a fixed sphere it
            // overlaps and one beside it) would otherwise each push it anew.
            let mut extra = bias / (ima + imb);
            for (k, im) in [(a, ima), (b, imb)] {
                if im > 0.0 {
                    extra = extra.min(self.push_left(k, ctx) / im);
                }
            }
            if extra > 0.0 {
                r.velocity_a -= normal * (extra * ima);
                r.velocity_b += normal * (extra * imb);
                r.impulse += extra;
                self.spend_push(a, extra * ima);
                self.spend_push(b, extra * imb);
            }
        }
        self.set_velocity(a, r.velocity_a, t, ctx);
        self.set_velocity(b, r.velocity_b, t, ctx);
        if gave_none(r.impulse, ima + imb, ctx.settings) {
            self.bend_sooner_if_closing(a, b, t, ctx);
            self.settled.push(Settled::now(&self.versions, a, b));
        } else if resting {
            self.instant
                .record(event.a, event.b, moving(&self.segments));
        } else if restitution > 0.0 && restitution < 1.0 {
            self.count_bounce(a, b, -(sb.velocity - sa.velocity).dot(normal));
        }
        stats.collisions = stats.collisions.saturating_add(1);
        stats.resting_contacts = stats.resting_contacts.saturating_add(u32::from(resting));
        self.record_collision((a, b), t, normal, r.impulse, resting, ctx);
    }

    /// Records the collision of bodies `a` and `b` at time `t` of the step, along `normal`
    /// (from `a` to `b`), with the lower id first (the normal turned if that is `b`), at
    /// that body's surface.
    pub(super) fn record_collision(
        &mut self,
        (a, b): (usize, usize),
        t: f64,
        normal: DVec3,
        impulse: f64,
        resting: bool,
        ctx: &StepContext<'_>,
    ) {
        let (id_a, id_b) = (self.extra(a).id, self.extra(b).id);
        let (first, a, b, normal) = if id_a <= id_b {
            (a, id_a, id_b, normal)
        } else {
            (b, id_b, id_a, -normal)
        };
        // On the surface of the body reported first (an overlapping pair's surfaces differ).
        let s = &self.segments[first];
        let point = s.position + normal * s.radius();
        self.collisions.push(Collision {
            a,
            b,
            time: ctx.start_time + t,
            normal,
            point,
            impulse,
            resting,
        });
    }
}
