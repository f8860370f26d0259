//! Spheres on strings within a step: each string's state, its drift bent into chords of the
//! sphere's swing, the string catching a slack sphere, and the strut that holds a sphere off
//! a strung one's anchor where it would squeeze that sphere against its string's length.

use glam::DVec3;

use super::*;

/// The most a string's bent drift (a chord of the arc it swings along) may cut inside that arc,
/// as a fraction of its sphere's radius: a drift that would cut deeper is bent to reach the
/// string's length sooner, and bent again there (see [`bend`]). A light sphere on a short
/// string, squeezed against it by a heavy one and whipped round at 9.6 m/s (0.6 rad a step at
/// 30 Hz), cut 2.4 cm inside its arc on one chord for the whole step, into the heavy sphere,
/// and ended it 5.8% of its radius deep.
pub(super) const STRING_SAG: f64 = 0.01;

/// A string's drift is bent again at most this many times a step (beyond its sphere's impacts):
/// a piece lasts at least one this-many-th of the step. (With 16, a light sphere pressed out
/// against its string by a heavy ball and whirled round at 122 m/s, 7.7 rad a step, re-struck
/// the ball at every bend and ended a step 15% of its radius into it; 6.2% with 64.) A light
/// sphere whipped round at hundreds of m/s on a short string turns up to a radian a piece, and
/// each bend takes some of its energy: a heavy sphere squeezing one (the scene of
/// `regression_heavy_sphere_squeezes_a_strung_one.rs`, driven at 10 and 30 m/s) rebounds at 35%
/// to 91% of its speed at some angles with 64, and at its speed at every angle tried with 512;
/// not kept: the fuzz is no better with it (over fresh seeds), and such a sphere may then spend
/// half its share of the collision budget on bends (docs/robustness.md).
pub(super) const STRING_PIECES: f64 = 64.0;

/// Under gravity or an applied force, how deep (a fraction of the smaller radius) a pair with
/// a sphere on a string may end a step before the separation moves it apart by the excess
/// (see `Solver::separate`). A light sphere pressed out along its string by a heavier one
/// is held on its swing's tangent at each impact, but its swing curves into the other sphere
/// between impacts: a sphere of 0.2 kg on a string of 0.55 m, pressed by one of 47.5 kg and
/// whipped round at up to 23 m/s, sank 1.1% to 1.6% of its radius deeper each step, 5.3% in
/// all, and nothing undid it.
pub(super) const STRUNG_OVERLAP: f64 = 0.02;

/// A sphere of radius `R` whose centre comes within `R + r − ℓ` of the anchor of a sphere of
/// radius `r` on a string of length `ℓ` leaves that sphere no place on its string outside it.
/// Once the large sphere's centre is within this fraction of `r` of that, an impact between the
/// two with the string taut holds the large sphere off the anchor as a strut would (see
/// [`Solver::add_struts`]), and so does the large sphere's reaching that distance between
/// impacts (see [`Solver::test_struts`]): as near as the strung sphere, on a chord of its
/// swing, may lie inside its string's length ([`STRING_SAG`]). Each impact pushes the small
/// sphere a little off the line through the anchor, round its swing, where it is struck again:
/// without the strut it was whipped round faster and faster while the large sphere crept on
/// towards the anchor, and the string's catches took the large sphere's energy. A sphere of 1.4
/// kg wedged against a fixed one sank 10.6% of a radius into one of 8 mg on a string of 6.8 cm
/// (`sphere-fuzz --strings fast`, seed 81 682), and a sphere of 1.4 kg driven at 3 m/s,
/// elastic, towards the anchor of one of 10 mg whose string lay 20° off its path rebounded at
/// 2.62 m/s after 128 collisions, where the strut sends it back at 3 m/s after 3
/// (`regression_heavy_sphere_squeezes_a_strung_one.rs`). Margins of 2% and 5% did as well on
/// the fuzz, but with 2% the whipped sphere of `regression_light_strung_sphere_whipped.rs` took
/// another path, sliding along the heavy one in hundreds of impacts a step until the collision
/// budget ran out; with none the strut did nothing, and holding the large sphere off as soon as
/// the small one's room was within 30° of the line stopped it 7 mm (2% of its radius) short.
/// Met only at impacts, a large sphere at 100 m/s crossed the margin (0.14 mm there) between
/// two (seed 21 628, 3.2 of the small one's radii deep within the step; 2.3 with the strut's
/// own impacts). Left: faster, the light sphere may be struck before the strut engages and
/// whipped round at hundreds of m/s, and the large sphere loses speed to the string's chords, a
/// 64th of a step each, turning up to a radian (see [`STRING_PIECES`]): driven at 10 m/s, it
/// rebounds at 70% of its speed with the string 120° off its path and 41% at 170° (at 99% or
/// more from 0° to 90°), at 30 m/s at 35% with it 30° off and 84% to 91% at 45°, 120° and 150°
/// (before the strut, at 10 m/s at 12% to 41% from 20° on, and at 30 m/s it kept moving forward
/// at 20°, 45°, 90° and 170°).
pub(super) const STRUT_MARGIN: f64 = STRING_SAG;

/// A string's state for the step, for the few bodies that hang on one: kept out of [`Extra`]
/// so that every other body streams half the bytes.
#[derive(Clone, Copy, Debug)]
pub(super) struct Strung {
    /// The body's index (the strung bodies are listed in body order).
    pub(super) body: u32,
    pub(super) tether: Tether,
    /// The string bent this segment's drift, or catches it within the step: it reaches its
    /// length by the end of the step.
    pub(super) taut: bool,
    /// The velocity before the bend (what the sphere moves at while the string is slack).
    pub(super) free_velocity: DVec3,
    /// How far inside the string's length the bent drift dips (its sagitta).
    pub(super) sag: f64,
    /// When the bent drift reaches the string's length and is bent again (see [`bend`]);
    /// the step's end when it runs on to the end.
    pub(super) until: f64,
    /// The sphere began the step (or, once its drift has been bent again at `until`, that
    /// drift) inside its string's length (not on it, as a string taut at the step's end leaves
    /// it): if `taut`, the string catches it within the step, when its free path reaches the
    /// length.
    pub(super) slack: bool,
}

impl Solver {
    /// Segment `k`'s string state, if it hangs on a string.
    #[inline]
    pub(super) fn strung(&self, k: usize) -> Option<&Strung> {
        self.string_of(k).map(|s| &self.strung[s])
    }

    /// Where segment `k`'s string state is in [`Solver::strung`], if it hangs on a string.
    #[inline]
    pub(super) fn string_of(&self, k: usize) -> Option<usize> {
        if !self.strings {
            return None;
        }
        let body = self.order[k];
        self.strung.binary_search_by_key(&body, |s| s.body).ok()
    }

    /// Queues segment `k`'s string bend at `until` (an event of the segment with itself),
    /// unless that is the step's end `dt`. Whatever instant the queue is held to: the drift is
    /// wrong beyond it.
    #[inline]
    pub(super) fn queue_bend(&mut self, k: usize, until: f64, dt: f64) {
        if until < dt {
            self.queue.push(Event {
                time: until,
                a: k as u32,
                b: k as u32,
                version_a: self.versions[k],
                version_b: self.versions[k],
            });
        }
    }

    /// Queues segment `k`'s pending string bend again (not before `t`) after its version
    /// changed without its drift being bent again (a push taken off, the fallback's solve).
    pub(super) fn queue_bend_again(&mut self, k: usize, t: f64, dt: f64) {
        if let Some(s) = self.string_of(k) {
            self.queue_bend(k, self.strung[s].until.max(t), dt);
        }
    }

    /// A pair settled at `t` (its impact gave no impulse, on a taut string's tangent) whose
    /// drifts still close, as a string's chord turning in towards the other sphere does: each
    /// taut string of the pair bends its drift to reach the length (where it is bent again,
    /// and the pair looked at again) before the chords close by more than [`STRING_SAG`] of
    /// the smaller radius.
    #[inline]
    pub(super) fn bend_sooner_if_closing(
        &mut self,
        a: usize,
        b: usize,
        t: f64,
        ctx: &StepContext<'_>,
    ) {
        if !self.strings {
            return;
        }
        let (sa, sb) = (&self.segments[a], &self.segments[b]);
        let d = sb.position_at(t) - sa.position_at(t);
        let closing = -(sb.velocity - sa.velocity).dot(d) / d.length();
        if closing > 0.0 {
            let by = t + STRING_SAG * sa.radius().min(sb.radius()) / closing;
            self.bend_sooner(a, by, t, ctx);
            self.bend_sooner(b, by, t, ctx);
        }
    }

    /// Bends segment `k`'s drift (taut on its string, from `t`) to reach the string's length
    /// by `by` if that is sooner than it does (but not sooner than the shortest piece).
    pub(super) fn bend_sooner(&mut self, k: usize, by: f64, t: f64, ctx: &StepContext<'_>) {
        let Some(s) = self.string_of(k) else {
            return;
        };
        let strung = &mut self.strung[s];
        let by = by.max(t + ctx.dt / STRING_PIECES);
        if !strung.taut || by >= strung.until {
            return;
        }
        let segment = &mut self.segments[k];
        segment.advance_to(t);
        (segment.velocity, strung.taut, strung.sag) = chord(
            segment.position,
            strung.free_velocity,
            strung.tether,
            by - t,
        );
        strung.until = by;
        self.versions[k] += 1;
        self.boxes[k] = swept_box(segment, ctx.dt, ctx.settings);
        self.check_bounded(k);
        self.queue_bend(k, by, ctx.dt);
    }

    /// Segment `k`'s drift has reached its string's length at `t` (see [`bend`]): it is put on
    /// the string, loses its outward speed (as at a step's end) and is bent again, and its
    /// pairs are sought again.
    pub(super) fn bend_again(
        &mut self,
        k: usize,
        t: f64,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) {
        let Some(s) = self.string_of(k) else {
            return;
        };
        let tether = self.strung[s].tether;
        let segment = &mut self.segments[k];
        segment.advance_to(t);
        let velocity;
        (segment.position, velocity) = taut(segment.position, segment.velocity, tether);
        let distance = (segment.position - tether.anchor).length();
        self.strung[s].slack = !at_length(distance, tether);
        self.clear_touched();
        self.set_velocity(k, velocity, t, ctx);
        self.touch(k as u32);
        self.requery_touched(t, ctx, stats);
    }

    /// Whether segment `k`'s string is at its length at time `t`: its drift was bent, and at
    /// `t` the sphere is no farther inside the length than the bent drift can dip, or the
    /// string has caught it by then (slack when the step began, the sphere's free path has
    /// reached the length by `t`; the bent drift, a chord from inside the length, is still
    /// short of it). A string taut when the step began is not slack there: after an impact
    /// its sphere sets off from inside the length, on the last chord, and is on its string
    /// while no farther inside than that (its free path would say caught at once, and solving
    /// a fast-turning sphere with its string at each such impact made it gain energy: 1.4% in
    /// one of the 626 scenes with strings of `sphere-fuzz --strings fast`).
    #[inline]
    pub(super) fn taut_at(&self, k: usize, t: f64) -> bool {
        if !self.strings {
            return false;
        }
        match self.strung(k) {
            Some(&Strung {
                tether,
                taut: true,
                sag,
                free_velocity,
                slack,
                ..
            }) => {
                let segment = &self.segments[k];
                let distance = (segment.position_at(t) - tether.anchor).length();
                if tether.length - distance <= 1.5 * sag + 1e-12 * tether.length {
                    return true;
                }
                if !slack {
                    // Taut when the step began: on the string still if no farther inside than
                    // where this drift set off (an impact's point, on the last chord).
                    let start = (segment.position - tether.anchor).length();
                    return distance >= start * (1.0 - 1e-12);
                }
                // The free path and the bent drift both start at the segment's position: a
                // straight line, once past the length, stays past it.
                let free = segment.position + free_velocity * (t - segment.t0);
                (free - tether.anchor).length() >= tether.length * (1.0 - 1e-12)
            }
            _ => false,
        }
    }

    /// When segment `k`'s string, slack when the step began, catches it within the step: the
    /// time its free path (from the segment's position, at its free velocity) reaches the
    /// string's length. `None` if it has no string, or the string bends nothing this step, or
    /// was taut when the step began (see [`Solver::taut_at`]).
    #[inline]
    pub(super) fn catch_time(&self, k: usize) -> Option<f64> {
        let &Strung {
            tether,
            taut: true,
            free_velocity: v,
            slack: true,
            ..
        } = self.strung(k)?
        else {
            return None;
        };
        let segment = &self.segments[k];
        catch_after(segment.position - tether.anchor, v, tether.length).map(|s| segment.t0 + s)
    }

    /// Adds to a group's contacts (in [`Solver::local_contacts`], its bodies already local)
    /// a strut for each of `events` between a sphere on a taut string and a dynamic sphere
    /// within [`STRUT_MARGIN`] of leaving it no room: a contact that keeps the other sphere
    /// from closing on the string's anchor, as a fixed body there (see
    /// [`Solver::strut_restitution`]). Where the strung sphere is on the line from the other's centre through
    /// the anchor, the strut is the impact and the string together; off it, it stands for
    /// the string's sphere closing round the strung one.
    pub(super) fn add_struts(&mut self, events: &[Event], settings: &Settings) {
        for event in events {
            let (la, lb) = (
                self.local_index[event.a as usize] as usize,
                self.local_index[event.b as usize] as usize,
            );
            // The impact's contact, among the events' (none for spheres at one point).
            if !self.local_contacts[..self.local_resting.len()]
                .iter()
                .any(|c| c.a == la && c.b == lb)
            {
                continue;
            }
            for (k, m) in [(event.a, event.b), (event.b, event.a)] {
                let (lk, lm) = (
                    self.local_index[k as usize] as usize,
                    self.local_index[m as usize] as usize,
                );
                if !self.local_taut[lk] {
                    continue;
                }
                let position = self.segments[m as usize].position;
                let Some(normal) = self.strut_at(k as usize, m as usize, position, settings) else {
                    continue;
                };
                let closing = self.local_velocities[lm].dot(normal);
                let (restitution, _) =
                    self.strut_restitution(k as usize, m as usize, normal, closing, settings);
                self.local_contacts.push(GroupContact {
                    a: lm,
                    b: self.local_inverse_masses.len(),
                    normal,
                    restitution,
                    bias: 0.0,
                    string: false,
                });
                self.local_inverse_masses.push(0.0);
                self.local_velocities.push(DVec3::ZERO);
            }
        }
    }

    /// How much of `onto` (a move of segment `k`, advanced to `t`, onto its string's sphere)
    /// it may take, from 0 to 1: all of it, unless that would take it deeper into a sphere it
    /// strikes among `events` than it is now (or into it, from touching). The drift it struck
    /// with is a chord, inside the string's length by up to the chord's sagitta; put on its
    /// string straight towards a sphere outside the string's reach, it would sink into that
    /// sphere by as much, and a pair that parts slowly (restitution 0) ended the step so:
    /// a sphere on a string of 0.56 m turning 0.9 rad a step ended one 1.5 cm (15% of its
    /// radius) into a light free sphere it had struck 2.5 ms before the step's end.
    pub(super) fn move_allowed(&self, k: usize, onto: DVec3, events: &[Event], t: f64) -> f64 {
        let segment = &self.segments[k];
        let mut allowed = 1.0f64;
        for e in events {
            let j = match (e.a as usize, e.b as usize) {
                (a, b) if a == k => b,
                (a, b) if b == k => a,
                _ => continue,
            };
            let other = &self.segments[j];
            let d = segment.position - other.position_at(t);
            let along = d.dot(onto);
            if along >= 0.0 {
                continue;
            }
            // |d + s·onto| ≥ m for s up to the smaller root (written without cancellation).
            let reach = segment.radius() + other.radius();
            let dd = d.length_squared();
            let room = dd - dd.min(reach * reach);
            let discriminant = along * along - onto.length_squared() * room;
            if discriminant >= 0.0 {
                allowed = allowed.min(room / (discriminant.sqrt() - along));
            }
        }
        allowed.max(0.0)
    }

    /// Where segment `k`'s string is anchored, and how near segment `m`'s centre may come to
    /// the anchor before a strut holds it off (`R + r − ℓ` and [`STRUT_MARGIN`]), if `k` hangs
    /// on a string short enough for `m` to squeeze it there and `m` is dynamic.
    pub(super) fn strut(&self, k: usize, m: usize) -> Option<(DVec3, f64)> {
        let &Strung { tether, .. } = self.strung(k)?;
        let (sk, sm) = (&self.segments[k], &self.segments[m]);
        let limit = sm.radius() + sk.radius() - tether.length;
        (!sm.is_fixed() && limit > 0.0).then(|| (tether.anchor, limit + STRUT_MARGIN * sk.radius()))
    }

    /// The direction from segment `m` at `position` to the anchor of segment `k`'s string, if
    /// a strut holds `m` off that anchor there (see [`Solver::strut`]): `m` within the strut's
    /// reach, or touching it within the tolerance, as a strut's own impact finds it (see
    /// [`Solver::test_struts`]; that impact, solved in a group or alone, must meet the strut).
    pub(super) fn strut_at(
        &self,
        k: usize,
        m: usize,
        position: DVec3,
        settings: &Settings,
    ) -> Option<DVec3> {
        let (anchor, reach) = self.strut(k, m)?;
        let r = anchor - position;
        let distance = r.length();
        (distance > 0.0 && touching_or_overlapping(distance, reach, settings.tolerance))
            .then(|| r / distance)
    }

    /// Queues pair `(i, j)`'s strut impact (see [`Solver::add_struts`]), if one of them hangs
    /// on a string and the other's drift takes its centre within [`STRUT_MARGIN`] of `R + r −
    /// ℓ` from the string's anchor later in the step: an impact found at no contact between
    /// the two, which the strut alone answers (see [`Solver::resolve_strut`]).
    pub(super) fn test_struts(&mut self, i: usize, j: usize, t: f64, ctx: &StepContext<'_>) {
        for (k, m) in [(i, j), (j, i)] {
            let Some((anchor, reach)) = self.strut(k, m) else {
                continue;
            };
            let sm = &self.segments[m];
            let d = sm.position_at(t) - anchor;
            // Already within: an impact between the two holds it off.
            if d.length_squared() <= reach * reach {
                continue;
            }
            // The anchor as a sphere of radius `reach` that `m`'s centre must not enter: the
            // exact swept test, whatever method the settings choose for pairs (the strut is
            // the solver's own constraint).
            let outcome =
                ExactToi.time_of_impact(d, sm.velocity, reach, ctx.dt - t, ctx.settings.tolerance);
            if let Some(toi) = outcome.time {
                self.queue_pair(i, j, t + toi);
            }
        }
    }

    /// The restitution of a strut holding segment `m` off the anchor of segment `k`'s string,
    /// `m` closing on it at `closing` along `normal`, and whether it is a resting contact: the
    /// pair's restitution, or none if it closes no faster than a resting contact (or the impact
    /// is solved inelastic). Not the impact's own: the strung sphere, whipped round, may be
    /// parting from the other where the other still closes on the anchor (then resting,
    /// restitution 0: a sphere driven at 30 m/s into the squeeze rebounded at 0.59 m/s instead
    /// of 30).
    pub(super) fn strut_restitution(
        &self,
        k: usize,
        m: usize,
        normal: DVec3,
        closing: f64,
        settings: &Settings,
    ) -> (f64, bool) {
        let (em, ek) = (self.extra(m), self.extra(k));
        let resting = closing <= self.resting_scale * em.acceleration.dot(normal).abs();
        let restitution = if self.inelastic || resting {
            0.0
        } else {
            settings
                .restitution_combine
                .combine(em.restitution, ek.restitution)
        };
        (restitution, resting)
    }

    /// Answers `event` by a strut alone, if it is a strut's impact (see
    /// [`Solver::test_struts`]): its two spheres apart, one within [`STRUT_MARGIN`] of `R + r −
    /// ℓ` from the other's anchor and closing on it. That sphere's speed towards the anchor is
    /// turned back, times the pair's restitution (none if it closes no faster than a resting
    /// contact), and the impact is reported as the pair's collision (the strung sphere stands
    /// for the strut). Returns whether it was.
    pub(super) fn resolve_strut(
        &mut self,
        event: &Event,
        ctx: &StepContext<'_>,
        stats: &mut StepStats,
    ) -> bool {
        let (a, b) = (event.a as usize, event.b as usize);
        let t = event.time;
        let (sa, sb) = (&self.segments[a], &self.segments[b]);
        let (pa, pb) = (sa.position_at(t), sb.position_at(t));
        let reach = sa.radius() + sb.radius();
        if (pb - pa).length() <= reach + contact_band(sa, sb, ctx.settings) {
            return false;
        }
        for (k, m, pm) in [(a, b, pb), (b, a, pa)] {
            let Some(normal) = self.strut_at(k, m, pm, ctx.settings) else {
                continue;
            };
            let sm = &self.segments[m];
            let closing = sm.velocity.dot(normal);
            if closing <= 0.0 {
                continue;
            }
            let (restitution, resting) =
                self.strut_restitution(k, m, normal, closing, ctx.settings);
            let velocity = sm.velocity - normal * ((1.0 + restitution) * closing);
            let impulse = (1.0 + restitution) * closing / self.extra(m).inverse_mass;
            self.segments[m].advance_to(t);
            self.set_velocity(m, velocity, t, ctx);
            // Reported as the pair's collision, the strung sphere standing for the strut.
            stats.collisions = stats.collisions.saturating_add(1);
            stats.resting_contacts = stats.resting_contacts.saturating_add(u32::from(resting));
            self.record_collision((m, k), t, normal, impulse, resting, ctx);
            return true;
        }
        false
    }
}

/// The velocity that carries a tethered sphere from `position` over `tau` to where its string
/// allows (the SHAKE correction): unchanged while the string stays slack, otherwise bent along
/// the string's current direction so the drift ends exactly at the string's length.
/// Also says whether the string bent the drift (it will be taut by the end), and how far inside
/// the string's length the straight drift dips on the way (its sagitta, `c²/8L`).
pub(super) fn chord(
    position: DVec3,
    velocity: DVec3,
    tether: Tether,
    tau: f64,
) -> (DVec3, bool, f64) {
    let r = position - tether.anchor;
    if tau <= 0.0 {
        return (velocity, at_length(r.length(), tether), 0.0);
    }
    let q = r + velocity * tau;
    let (length, qq, rr) = (tether.length, q.length_squared(), r.length_squared());
    if qq <= length * length || rr == 0.0 {
        return (velocity, false, 0.0);
    }
    // |q - s r| = L, smaller root, written without cancellation.
    let qr = q.dot(r);
    let excess = (q.length() - length) * (q.length() + length);
    let discriminant = qr * qr - rr * excess;
    let end = if qr > 0.0 && discriminant >= 0.0 {
        q - r * (excess / (qr + discriminant.sqrt()))
    } else {
        q * (length / q.length())
    };
    let chord_length = (end - r).length();
    // A chord between two points at the string's length dips this far inside it; a sphere
    // farther inside than that is not on its string (yet).
    let sag = chord_length * chord_length / (8.0 * length);
    ((end - r) / tau, true, sag)
}

/// [`chord`] over the rest of the step from `t` to `dt`, or over a shorter piece of it if
/// the chord would cut more than [`STRING_SAG`] of the sphere's `radius` inside the arc the
/// string swings it along (a cut grows about as the square of the time), the piece lasting
/// at least 1/[`STRING_PIECES`] of the step. Returns the velocity, whether the string bent
/// it, the chord's dip (see [`chord`]), and when the drift reaches the string's length, to be
/// bent again (`dt` if at the end). A `slack` string whose sphere lies farther inside its length
/// than [`STRING_SAG`] of its radius bends nothing: the drift is the free one, until its
/// straight path reaches the length (the catch), if that is within the step.
pub(super) fn bend(
    position: DVec3,
    velocity: DVec3,
    tether: Tether,
    slack: bool,
    radius: f64,
    t: f64,
    dt: f64,
) -> (DVec3, bool, f64, f64) {
    let from = position - tether.anchor;
    // Slack, and farther inside than a chord dips (nearer, the sphere is on its string), the
    // string bends nothing until it catches the sphere: the drift is free until then, and bent
    // again there (on the string).
    if slack
        && tether.length - from.length() > STRING_SAG * radius
        && let Some(s) = catch_after(from, velocity, tether.length)
        && t + s < dt
    {
        return (velocity, true, 0.0, t + s);
    }
    // The chord over `tau`, and how deep it cuts inside the arc.
    let chord_over = |tau: f64| {
        let (bent, taut, sag) = chord(position, velocity, tether, tau);
        let cut = if taut {
            arc_cut(from, from + bent * tau, tether.length)
        } else {
            0.0
        };
        (bent, taut, sag, cut)
    };
    let rest = dt - t;
    let (bent, taut, sag, cut) = chord_over(rest);
    let limit = STRING_SAG * radius;
    if cut <= limit {
        return (bent, taut, sag, dt);
    }
    // The cut grows as the square of the time only while the chord turns through a small
    // angle (a long drift bent back to the length turns through less than its speed says):
    // the piece is halved until its own chord cuts no deeper than allowed.
    let shortest = dt / STRING_PIECES;
    let mut piece = (rest / (cut / limit).sqrt().ceil()).max(shortest);
    loop {
        if t + piece >= dt {
            return (bent, taut, sag, dt);
        }
        let (bent, taut, sag, cut) = chord_over(piece);
        if cut <= limit || piece <= shortest {
            return (bent, taut, sag, t + piece);
        }
        piece = (0.5 * piece).max(shortest);
    }
}

/// Whether a sphere `distance` from its string's anchor is on the string: at its length, or
/// past it, to within a relative 1e-9 (rounding); nearer, the string is slack.
pub(super) fn at_length(distance: f64, tether: Tether) -> bool {
    distance >= tether.length * (1.0 - 1e-9)
}

/// How long a sphere `r` from its string's anchor, moving at `velocity` in a straight line,
/// takes to reach the string's `length` (0 if it is there or beyond; `None` if it never does,
/// being at rest).
fn catch_after(r: DVec3, velocity: DVec3, length: f64) -> Option<f64> {
    // |r + v s|² = L², for the root s >= 0 (one, with the sphere inside the length).
    let (a, b, c) = (
        velocity.length_squared(),
        r.dot(velocity),
        r.length_squared() - length * length,
    );
    if c >= 0.0 {
        return Some(0.0);
    }
    let root = (b * b - a * c).sqrt();
    let s = if b >= 0.0 {
        -c / (b + root)
    } else {
        (root - b) / a
    };
    s.is_finite().then_some(s)
}

/// How far inside an arc of radius `length` about the origin, from direction `from` to
/// direction `to`, the chord between its ends cuts: `length (1 - cos(θ/2))` for the angle θ
/// between them, worked out from the distance between the unit directions (no cancellation
/// at small angles). 0 for a string swung along itself (a radial drift cuts no arc).
pub(super) fn arc_cut(from: DVec3, to: DVec3, length: f64) -> f64 {
    let (a, b) = (from.normalize_or_zero(), to.normalize_or_zero());
    // 1 - cos θ, and sin²(θ/2) its half.
    let versine = 0.5 * (a - b).length_squared();
    let half = 0.5 * versine;
    length * half / (1.0 + (1.0 - half).max(0.0).sqrt())
}

/// At the end of a step: a sphere at (or, after rounding, past) its string's length is put back
/// on it and loses its outward radial velocity (the RATTLE velocity projection).
pub(super) fn taut(position: DVec3, velocity: DVec3, tether: Tether) -> (DVec3, DVec3) {
    let r = position - tether.anchor;
    let distance = r.length();
    if distance == 0.0 || !at_length(distance, tether) {
        return (position, velocity);
    }
    let normal = r / distance;
    let position = if distance > tether.length {
        tether.anchor + normal * tether.length
    } else {
        position
    };
    let outward = velocity.dot(normal);
    let velocity = if outward > 0.0 {
        velocity - normal * outward
    } else {
        velocity
    };
    (position, velocity)
}
