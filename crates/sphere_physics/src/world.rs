//! The world: bodies, settings, and the step.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::body::Field;
use crate::contact::{ContactKind, Kinematics, classify};
use crate::dormant::Dormant;
use crate::sleep::{Sleep, Sleeper};
use crate::solver::{Solver, StepContext, overlap};
use crate::{
    Body, BodyError, BodyId, Collision, CombineRule, Integrator, IntegratorKind, SphereDesc,
    StepProfile, StepStats, TimeOfImpact, ToiMethod, Tolerance,
};

/// World settings. Plain data: change them between steps through [`World::settings_mut`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Settings {
    /// Gravitational acceleration applied to every dynamic body.
    pub gravity: DVec3,
    /// Time-of-impact method (unless replaced with [`World::set_time_of_impact`]).
    pub method: ToiMethod,
    /// Integrator (unless replaced with [`World::set_integrator`]).
    pub integrator: IntegratorKind,
    /// Tolerance for every equality test (touching, zero normal speed).
    pub tolerance: Tolerance,
    /// How two bodies' restitutions combine.
    pub restitution_combine: CombineRule,
    /// A collision whose approach speed is at most this many steps' worth of the acceleration
    /// pressing the pair together is a resting contact and is resolved with restitution 0: a
    /// ball at rest on another, or in a pile, stays at rest instead of jittering, and a
    /// bouncing ball comes to rest instead of bouncing ever lower forever. What presses a pair:
    /// the larger component of either body's own acceleration (gravity plus applied force over
    /// mass) along their line of centres; for a contact that took a load in the last step's
    /// resting solve, the larger of the two whole accelerations (in a pile the weight pushes
    /// sideways too, through the neighbours); and within a step, a contact's load from that
    /// step's resting solve. A ball on a floor under Earth gravity at 60 Hz: 0.25 m/s (the
    /// step here is each substep's: with 4 substeps, 0.06 m/s). Balls side by side (a cradle,
    /// hanging or on a floor) press each other only if something pushes them together, so
    /// their meetings keep their restitution. Default 1.5; 0 disables it.
    pub resting_factor: f64,
    /// Within a step, two touching bodies closing slower than this fraction of the resting
    /// speed (see `resting_factor`) are left to creep into each other until the next step's
    /// resting solve, instead of being resolved one contact at a time: in a pile that would take
    /// thousands of ever smaller collisions. The overlap this allows is at most
    /// `creep_fraction · resting_factor · acceleration · dt²` (4e-5 m at 60 Hz under Earth
    /// gravity; `dt` is each substep's) beyond the band within which spheres count as touching
    /// (a millionth of the smaller diameter, plus the tolerance); at the bottom of a pile,
    /// pressed by the spheres above harder than by its own weight (the creep grows with a
    /// contact's load), a few times that (3.1 times in the README's example pile of 2000),
    /// undone over the next steps; never past 1% of the smaller radius (a pair that would end
    /// the step deeper is met as an impact). Default 0.01; 0 disables it. Without gravity or
    /// forces it never applies.
    pub creep_fraction: f64,
    /// Each [`World::step`] is taken as this many equal substeps (default 1). Integration error
    /// that grows with the step, such as a tethered pendulum's energy error at each impact
    /// (which falls as dt²), falls as `1/substeps²` at `substeps` times the cost. The resting
    /// speed and the creep distance (`resting_factor`, `creep_fraction`) are each substep's.
    pub substeps: u32,
    /// The step's collision budget is this times the number of dynamic bodies. When it runs out
    /// (a crowd landing at once, each collision bringing on more: a thousand spheres dropped
    /// together into a box), the rest of the step is solved at once instead of one collision at
    /// a time: every pair that could meet is kept from closing past touching, restitution 0, as
    /// the resting contacts are, in rounds until the pairs each round's changes bring together
    /// are solved too (at most 32; any left after them are counted as deferred), sweeping on
    /// while a pair would still end the step more than a hundredth of the smaller radius past
    /// touching (up to 1024 more sweeps: a long line of spheres struck hard passes its impulses
    /// on one contact a sweep) ([`StepStats::fell_back`]; bodies on strings are left out of
    /// that solve, which holds no string: their pairs are deferred to the next step instead).
    /// No body takes more than 256 times this in one step (in a world with strings, a quarter
    /// of the budget, but from 64 to 256 times this), so that a sphere caught between fixed
    /// ones, which bounces between them without end, cannot spend the whole budget of a large
    /// world: a body past that share is solved at once (without strings, and before any
    /// fallback of the step) with every contact touching it through dynamic bodies,
    /// restitution 0 (a light sphere squeezed between heavy ones bounces faster and faster,
    /// without end before the squeeze does; this is how those bounces end), a few times in a
    /// step, and its collisions after that are deferred to the next step and counted in
    /// [`StepStats::collisions_deferred`]. (Every contact such a squeeze solves counts
    /// against the budget, those it reports as collisions or not.) The shower and gas
    /// benchmarks take under 0.3 collisions per sphere per step in their first second, and a
    /// sphere sliding down the dome in the 100k shower's film at its climax up to 2228. With substeps, each substep
    /// has this budget (and records its collisions): a wedged sphere may take `substeps` times
    /// as many in one [`World::step`]. Default 16 (64 until 2026-12-01, when the budget's end
    /// deferred the rest: a landing crowd then sank 4.5 cm into itself), at most
    /// [`MAX_COLLISIONS_PER_BODY`]. Lowering it makes a landing crowd's steps cheaper (a pit of
    /// 1000 dropped together: 6.7 µs a sphere a step at 4 against 12.9 at 16, no deeper), but
    /// not a crowd of hundreds of thousands of contacts, whose fallback solve costs more than
    /// the collisions it replaces (the 100k shower benchmark's worst step: 5.2 s at 4, 2.2 s at
    /// 16).
    pub max_collisions_per_body: u32,
    /// Sleeping (off by default): `Some` lets bodies at rest fall asleep, so that a settled
    /// pile costs next to nothing. A body is calm while its speed at each step's end stays
    /// below [`Sleep::speed`]. A group of dynamic bodies touching one another (within
    /// [`SLEEP_CONTACT`](crate::sleep::SLEEP_CONTACT) of the smaller radius) falls asleep
    /// together once every one of them has stayed calm for [`Sleep::time`] (checked a few times
    /// in that time), provided it rests on a fixed sphere that does not move, every one of them
    /// is accelerated (gravity, or its force), none hangs on a string, none is
    /// [`SphereDesc::never_sleeps`](crate::SphereDesc::never_sleeps), none touches a fixed
    /// sphere that moves, and no two are deeper into each other than `SLEEP_CONTACT` of the
    /// smaller radius (such a pair is still being moved apart): a body drifting slowly through
    /// space, or anything in zero gravity with no force, never falls asleep. Falling asleep
    /// sets the bodies' velocities to zero (that, and a sphere struck while asleep going
    /// without its acceleration for the rest of that substep, are what sleeping changes in the
    /// motion). An asleep body is not accelerated (neither gravity nor its force acts on it:
    /// its neighbours' support is what it no longer needs) but is still a sphere of its mass,
    /// so whatever strikes it is answered exactly. It wakes, with its whole group, after a step
    /// that moved it or gave it any speed (an impact, or a body coming to rest on it; with
    /// substeps, a sphere given a speed moves as an awake one from the next substep on), when
    /// it is changed or removed through the world ([`World::set_desc`],
    /// [`World::set_velocity`], [`World::set_position`], [`World::set_force`],
    /// [`World::remove_body`], or [`World::wake`]), when a fixed sphere touching it is added,
    /// changed or removed (a force set on a fixed sphere, which no force moves, is no change),
    /// and at the next step after gravity changes or sleeping is turned
    /// off (until then [`Body::is_asleep`] still tells of the last step). A body changed
    /// through the world, and an awake body touching one added, changed or removed (dynamic
    /// or fixed: the ball under it taken away, say), is calm from then on only. A world whose
    /// dynamic bodies are all asleep, with no fixed body moving, takes its steps without work
    /// ([`StepStats::quiet`]). [`Body::is_asleep`] and [`StepStats::asleep`] tell.
    pub sleep: Option<Sleep>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            gravity: DVec3::ZERO,
            method: ToiMethod::Exact,
            integrator: IntegratorKind::SemiImplicitEuler,
            tolerance: Tolerance::DEFAULT,
            restitution_combine: CombineRule::Min,
            resting_factor: 1.5,
            creep_fraction: 0.01,
            substeps: 1,
            max_collisions_per_body: 16,
            sleep: None,
        }
    }
}

/// The most substeps a step may be split into.
pub const MAX_SUBSTEPS: u32 = 65_536;

/// The largest [`Settings::max_collisions_per_body`]: a sphere wedged between fixed ones then
/// takes at most about 17 million collisions in a substep (each one recorded: over a gigabyte
/// of [`World::collisions`]), not billions.
pub const MAX_COLLISIONS_PER_BODY: u32 = 65_536;

/// The most bisection iterations: after 64 halvings an f64 interval cannot shrink further.
pub const MAX_BISECTION_ITERATIONS: u32 = 64;

impl Settings {
    /// Checks every field (the fields are public, and settings also come from files): gravity
    /// finite, tolerance finite in `[0, 0.5)`, `resting_factor` finite and `>= 0`,
    /// `creep_fraction` in `[0, 1]`, `substeps` from 1 to [`MAX_SUBSTEPS`],
    /// `max_collisions_per_body` from 1 to [`MAX_COLLISIONS_PER_BODY`], bisection at most
    /// [`MAX_BISECTION_ITERATIONS`] iterations, and the sleeping speed and time finite and
    /// `>= 0`. [`World::step`] checks them first and changes nothing if one is wrong.
    pub fn validate(&self) -> Result<(), WorldError> {
        let bad = |field, value: String, reason| {
            Err(WorldError::InvalidSetting {
                field,
                value,
                reason,
            })
        };
        if !self.gravity.is_finite() {
            let [x, y, z] = self.gravity.to_array().map(crate::Readable);
            return bad("gravity", format!("[{x}, {y}, {z}]"), "must be finite");
        }
        let eps = self.tolerance.epsilon();
        if !(eps.is_finite() && (0.0..0.5).contains(&eps)) {
            return bad(
                "tolerance",
                format!("{}", crate::Readable(eps)),
                "must be finite and in [0, 0.5)",
            );
        }
        if !(self.resting_factor.is_finite() && self.resting_factor >= 0.0) {
            let value = format!("{}", crate::Readable(self.resting_factor));
            return bad("resting_factor", value, "must be finite and >= 0");
        }
        if !(0.0..=1.0).contains(&self.creep_fraction) {
            let value = format!("{}", crate::Readable(self.creep_fraction));
            return bad("creep_fraction", value, "must be in [0, 1]");
        }
        if self.substeps == 0 {
            return bad("substeps", "0".into(), "must be at least 1");
        }
        if self.substeps > MAX_SUBSTEPS {
            let value = format!("{}", self.substeps);
            return bad("substeps", value, "must be at most 65536");
        }
        if self.max_collisions_per_body == 0 {
            return bad("max_collisions_per_body", "0".into(), "must be at least 1");
        }
        if self.max_collisions_per_body > MAX_COLLISIONS_PER_BODY {
            let value = format!("{}", self.max_collisions_per_body);
            return bad("max_collisions_per_body", value, "must be at most 65536");
        }
        if let Some(sleep) = self.sleep {
            if !(sleep.speed.is_finite() && sleep.speed >= 0.0) {
                let value = format!("{}", crate::Readable(sleep.speed));
                return bad("sleep.speed", value, "must be finite and >= 0");
            }
            if !(sleep.time.is_finite() && sleep.time >= 0.0) {
                let value = format!("{}", crate::Readable(sleep.time));
                return bad("sleep.time", value, "must be finite and >= 0");
            }
        }
        if let ToiMethod::Bisection { max_iterations } = self.method
            && max_iterations > MAX_BISECTION_ITERATIONS
        {
            return bad(
                "method",
                format!("{max_iterations}"),
                "bisection iterations must be at most 64",
            );
        }
        Ok(())
    }

    /// Settings with the given gravity, defaults otherwise.
    pub fn with_gravity(gravity: DVec3) -> Self {
        Settings {
            gravity,
            ..Default::default()
        }
    }

    /// Sets the time-of-impact method.
    pub fn method(mut self, method: ToiMethod) -> Self {
        self.method = method;
        self
    }
}

/// What can go wrong when changing or stepping a world.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum WorldError {
    /// A body's field is invalid.
    #[error(transparent)]
    Body(#[from] BodyError),
    /// No body has this id (never added, or removed).
    #[error("no body {0}")]
    UnknownBody(BodyId),
    /// The time step is not finite and > 0 (or is subnormal: dividing by it overflows), or
    /// would take the world's clock ([`World::time`]) past the largest finite time, or is too
    /// small against the clock to advance it (the spheres would move while it stood still).
    #[error(
        "time step must be finite, normal and > 0, and keep the clock finite and advancing, got {}",
        crate::Readable(*.0)
    )]
    InvalidTimeStep(f64),
    /// A field of [`Settings`] is invalid (see [`Settings::validate`]).
    #[error("settings: {field} {reason}, got {value}")]
    InvalidSetting {
        /// The offending field of [`Settings`].
        field: &'static str,
        /// The offending value, as text.
        value: String,
        /// What the value must be.
        reason: &'static str,
    },
}

/// A world of spheres.
///
/// ```
/// use sphere_physics::{glam::DVec3, Settings, SphereDesc, World};
///
/// let mut world = World::new(Settings::default());
/// let a = world.add_sphere(SphereDesc::new(0.5).moving(DVec3::X))?;
/// let b = world.add_sphere(SphereDesc::new(0.5).at(DVec3::new(2.0, 0.0, 0.0)))?;
/// for _ in 0..120 {
///     world.step(1.0 / 60.0)?;
/// }
/// // Equal masses, elastic: the velocities are exchanged.
/// assert_eq!(world.body(a).unwrap().velocity(), DVec3::ZERO);
/// assert_eq!(world.body(b).unwrap().velocity(), DVec3::X);
/// # Ok::<(), sphere_physics::WorldError>(())
/// ```
#[derive(Debug, Default)]
pub struct World {
    settings: Settings,
    integrator: Option<Box<dyn Integrator>>,
    toi: Option<Box<dyn TimeOfImpact>>,
    /// Live bodies, sorted by id.
    bodies: Vec<Body>,
    next_id: u64,
    time: f64,
    steps: u64,
    stats: StepStats,
    /// The last step's collision records (the solver's buffer is swapped in when a step is
    /// taken, so a refused step leaves these as they were).
    collisions: Vec<Collision>,
    /// The last step's phase timings (kept the same way).
    profile: StepProfile,
    solver: Solver,
    /// Every body's position and velocity before a step of several substeps: a later
    /// substep that is refused puts them back (kept to reuse its buffer).
    rollback: Vec<(DVec3, DVec3)>,
    /// Who sleeps, and the buffers that decide it.
    sleeper: Sleeper,
    /// Which islands asleep a step may leave out.
    dormant: Dormant,
    /// Which bodies the step takes (a buffer for the deepest overlap of those it leaves out).
    taken: Vec<bool>,
    /// Buffers of body indices: the fixed bodies, and the bodies of the islands whose deepest
    /// overlap is worked out.
    fixed_indices: Vec<u32>,
    scratch_indices: Vec<u32>,
    /// The bodies the last step took, if it left any out or was quiet (see
    /// [`World::last_step_bodies`]).
    last_step: Vec<BodyId>,
    last_step_left_out: bool,
}

impl World {
    /// An empty world.
    pub fn new(settings: Settings) -> Self {
        World {
            settings,
            ..Default::default()
        }
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The settings, to change between steps.
    pub fn settings_mut(&mut self) -> &mut Settings {
        &mut self.settings
    }

    /// Turns timing of each step's phases on or off (off by default): see
    /// [`World::profile`].
    pub fn set_profiling(&mut self, on: bool) {
        self.solver.profiling = on;
        self.profile = StepProfile::default();
    }

    /// Wall time of the last step's phases, while profiling is on (see
    /// [`World::set_profiling`]); `None` when it is off.
    pub fn profile(&self) -> Option<&StepProfile> {
        self.solver.profiling.then_some(&self.profile)
    }

    /// Replaces the integrator chosen in the settings with a custom one.
    pub fn set_integrator(&mut self, integrator: Box<dyn Integrator>) {
        self.integrator = Some(integrator);
    }

    /// Replaces the time-of-impact method chosen in the settings with a custom one.
    pub fn set_time_of_impact(&mut self, toi: Box<dyn TimeOfImpact>) {
        self.toi = Some(toi);
    }

    /// Adds a sphere; on invalid input nothing is added and the error names the body and field.
    pub fn add_sphere(&mut self, desc: SphereDesc) -> Result<BodyId, BodyError> {
        let id = BodyId(self.next_id);
        desc.validate_under(self.settings.gravity, || label(desc.name.as_deref(), id))?;
        self.next_id += 1;
        self.bodies.push(Body::new(id, desc));
        self.sleeper.added();
        self.dormant.added(self.bodies.len() - 1);
        self.woken_by(self.bodies.len() - 1);
        Ok(id)
    }

    /// Removes a body, returning it (waking what rests on it: see [`Settings::sleep`]). The
    /// bodies after it move down one place: to remove many, [`World::remove_bodies`] moves
    /// each body once.
    pub fn remove_body(&mut self, id: BodyId) -> Option<Body> {
        let index = self.index(id).ok()?;
        self.solver.forget_indices();
        self.woken_by(index);
        self.dormant.removed(index);
        self.sleeper.removed(index);
        Some(self.bodies.remove(index))
    }

    /// Removes the bodies with these ids (ids of no body, or given twice, are passed over),
    /// returning them in id order, and wakes what rests on them (see [`Settings::sleep`]): the
    /// same as removing them one by one with [`World::remove_body`], in one pass over the
    /// world. Removed one at a time, each moves every body after it: a level of 40 000
    /// cleared from its first body took 7.8 s, from its last 0.2 s, and at once 5 ms.
    pub fn remove_bodies(&mut self, ids: &[BodyId]) -> Vec<Body> {
        if ids.is_empty() {
            return Vec::new();
        }
        let mut gone = vec![false; self.bodies.len()];
        let mut any = false;
        for &id in ids {
            if let Ok(index) = self.index(id) {
                gone[index] = true;
                any = true;
            }
        }
        if !any {
            return Vec::new();
        }
        self.solver.forget_indices();
        // What they disturb wakes (as each removed alone would wake it).
        self.sleeper.disturbed();
        let sleeping = self.settings.sleep.is_some();
        for index in (0..gone.len()).filter(|&i| gone[i]) {
            if !self.bodies[index].is_fixed() {
                self.sleeper.mark_to_wake(&self.bodies, index);
            }
            self.disturbed_at(index);
        }
        self.sleeper.wake_now(&mut self.bodies);
        self.sleeper
            .wake_around_all(&mut self.bodies, &mut self.solver, &gone, sleeping);
        // The bodies after each move down.
        self.dormant.removed_all(&gone);
        self.sleeper.removed_all(&gone);
        let mut k = 0;
        self.bodies
            .extract_if(.., |_| {
                k += 1;
                gone[k - 1]
            })
            .collect()
    }

    /// Wakes a body and every body asleep with it (see [`Settings::sleep`]); nothing if it is
    /// awake.
    pub fn wake(&mut self, id: BodyId) -> Result<(), WorldError> {
        let index = self.index(id)?;
        self.sleeper.wake_island_of(&mut self.bodies, index);
        Ok(())
    }

    /// Wakes what a change to the body at `index` (added, changed or about to be removed)
    /// disturbs: its own island, or for a fixed body the islands touching it.
    fn woken_by(&mut self, index: usize) {
        self.sleeper.disturbed();
        let body = &self.bodies[index];
        if body.is_fixed() {
            let (centre, radius) = (body.position(), body.radius());
            let sleeping = self.settings.sleep.is_some();
            self.sleeper
                .wake_around(&mut self.bodies, centre, radius, sleeping);
            // And, with sleeping off now but on by the next step, the awake bodies touching it
            // are calm from then on only.
            self.disturbed_at(index);
        } else {
            self.sleeper.wake_island_of(&mut self.bodies, index);
            // Awake, it is calm from now on only (moved, say, near a floor it would never
            // reach before falling asleep with a calm it had gathered elsewhere), and so are
            // the awake bodies touching it (one resting on it, say).
            self.sleeper.reset(index);
            self.disturbed_at(index);
        }
    }

    /// Marks where the body at `index` is as disturbed (see `Sleeper::disturbed_at`).
    fn disturbed_at(&mut self, index: usize) {
        let body = &self.bodies[index];
        let (centre, radius) = (body.position(), body.radius());
        self.sleeper.disturbed_at(self.bodies.len(), centre, radius);
    }

    /// The body with this id.
    pub fn body(&self, id: BodyId) -> Option<&Body> {
        self.index(id).ok().map(|i| &self.bodies[i])
    }

    /// All bodies, in id order (the order they were added).
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.bodies.len()
    }

    /// Whether the world has no bodies.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// Replaces a body's description (position, velocity, radius, ...), validated as on adding.
    pub fn set_desc(&mut self, id: BodyId, desc: SphereDesc) -> Result<(), WorldError> {
        let index = self.index(id)?;
        desc.validate_under(self.settings.gravity, || label(desc.name.as_deref(), id))
            .map_err(|e| BodyError { id: Some(id), ..e })?;
        self.woken_by(index);
        self.bodies[index] = Body::new(id, desc);
        self.sleeper.reset(index);
        self.woken_by(index);
        Ok(())
    }

    /// Sets a body's velocity.
    pub fn set_velocity(&mut self, id: BodyId, velocity: DVec3) -> Result<(), WorldError> {
        self.update(id, Field::Velocity, velocity, |d| &mut d.velocity)
    }

    /// Sets a body's position.
    pub fn set_position(&mut self, id: BodyId, position: DVec3) -> Result<(), WorldError> {
        self.update(id, Field::Position, position, |d| &mut d.position)
    }

    /// Sets a body's constant applied force.
    pub fn set_force(&mut self, id: BodyId, force: DVec3) -> Result<(), WorldError> {
        self.update(id, Field::Force, force, |d| &mut d.force)
    }

    fn update(
        &mut self,
        id: BodyId,
        field: Field,
        value: DVec3,
        slot: fn(&mut SphereDesc) -> &mut DVec3,
    ) -> Result<(), WorldError> {
        let index = self.index(id)?;
        if let Some(bad) = value.to_array().into_iter().find(|c| !c.is_finite()) {
            let body = &self.bodies[index];
            return Err(BodyError {
                body: label(body.name(), id),
                id: Some(id),
                field,
                value: bad,
                reason: "must be finite",
            }
            .into());
        }
        let body = &mut self.bodies[index];
        // A force on a fixed body, which no force moves, wakes nothing (it woke everything
        // touching it, until the fifty-seventh session). Any other value set wakes the body's
        // group, even one it already had: setting is how a game says "this changed", as in
        // rapier and avian (and `World::wake` is there to wake a body without changing it).
        let unfelt = field == Field::Force && body.is_fixed();
        // Validate the whole description (a position beyond the body's string is invalid), in
        // place: the old value is put back if it fails (no copy of the description, whose name
        // would be allocated at every call).
        let previous = std::mem::replace(slot(&mut body.desc), value);
        if let Err(e) = body
            .desc
            .validate_under(self.settings.gravity, || label(body.name(), id))
        {
            *slot(&mut body.desc) = previous;
            return Err(BodyError { id: Some(id), ..e }.into());
        }
        if field == Field::Position {
            // What touched it where it was (and, below, what touches it where it is).
            let (radius, sleeping) = (body.radius(), self.settings.sleep.is_some());
            if body.is_fixed() {
                self.sleeper
                    .wake_around(&mut self.bodies, previous, radius, sleeping);
            }
            self.sleeper
                .disturbed_at(self.bodies.len(), previous, radius);
        }
        if !unfelt {
            self.woken_by(index);
        }
        Ok(())
    }

    fn index(&self, id: BodyId) -> Result<usize, WorldError> {
        // Until a body is removed, a body's index is its id: no search.
        if self.bodies.get(id.index()).is_some_and(|b| b.id == id) {
            return Ok(id.index());
        }
        self.bodies
            .binary_search_by_key(&id, |b| b.id)
            .map_err(|_| WorldError::UnknownBody(id))
    }

    /// Simulated time.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Statistics of the last step.
    pub fn stats(&self) -> &StepStats {
        &self.stats
    }

    /// The bodies the last step took, when it left out the islands asleep beyond the reach
    /// of everything that moves (see [`Settings::sleep`]): only these may have moved or
    /// changed velocity in it, every other body stood still, asleep. Empty after a quiet step
    /// ([`StepStats::quiet`]), in which nothing moved; `None` when the step took every body
    /// (or before the first step). A game copying results out of the world (as the Bevy
    /// plugin does) need look only at these.
    pub fn last_step_bodies(&self) -> Option<&[BodyId]> {
        self.last_step_left_out.then_some(&self.last_step[..])
    }

    /// The collisions resolved in the last step, in the order they were resolved (time order).
    pub fn collisions(&self) -> &[Collision] {
        &self.collisions
    }

    /// Advances the world by `dt`. On an invalid `dt` (or one the settings' substeps would cut
    /// into subnormal substeps, or that would take the clock past the largest finite time or
    /// leave it where it is) or invalid settings (see [`Settings::validate`]) nothing changes. A sphere whose position
    /// or velocity would leave the finite range within the step (an absurd `dt` or speed, or
    /// the impulse of a kinematic sphere moving near the largest finite speed) is an error
    /// naming it; the step stops before the substep that would overflow, so no state turns
    /// infinite or NaN. A step refused for any of these changes nothing: the bodies (asleep or
    /// not), the clock, [`World::stats`], [`World::collisions`] and [`World::profile`] still
    /// tell of the last step taken, and the steps after it are those of a world that never
    /// tried it, bit for bit.
    ///
    /// Overlaps are undone without giving speed. Under any acceleration (gravity, or an applied
    /// force on a sphere that is not fixed) the resting solve pushes overlapping spheres apart
    /// within the step, a pair by at most a tenth of the smaller radius a step, and takes the
    /// push off at the step's end.
    /// With none, spheres left overlapping at the step's end (placed so, or parting slower than
    /// they overlap) are moved apart by their positions: each pair to touching, its spheres in
    /// proportion to their inverse masses (so momentum and kinetic energy are kept exactly, and
    /// the centre of mass too but for moves away from a fixed sphere, which is not moved, or
    /// one on a string, which moves only within its string's length, and in a pair with one on
    /// a string the other takes what the first cannot), each sphere at most a tenth of its
    /// radius a step (a substep, with substeps): a crowd placed a radius deep comes apart over
    /// a few dozen steps, and a sphere deep in a bigger one creeps out. Under an acceleration,
    /// a pair with a sphere on a string that ends the step more than 2% of the smaller radius
    /// into each other is moved back to that depth the same way: a string's swing curving into
    /// a sphere that presses its sphere out along it sinks the pair deeper between impacts,
    /// which the resting solve does not see; in such a pair a sphere may be moved as far as it
    /// drifted in the step, if farther than a tenth of its radius. A sphere these moves push
    /// into another is carried along: no pair is left deeper by them than the step left it
    /// (within the caps), and where nothing accelerates the pair's centre of mass is then not
    /// kept. [`StepStats::separated`] counts the spheres moved.
    pub fn step(&mut self, dt: f64) -> Result<&StepStats, WorldError> {
        let next = self.time + dt;
        if !(dt.is_normal() && dt > 0.0 && next.is_finite() && next > self.time) {
            return Err(WorldError::InvalidTimeStep(dt));
        }
        self.settings.validate()?;
        let mut stats = StepStats {
            dt,
            ..Default::default()
        };
        let substeps = self.settings.substeps;
        let sub_dt = dt / f64::from(substeps);
        if !sub_dt.is_normal() {
            // A subnormal substep overflows what is divided by it (a resting contact's
            // correction speed) to infinity.
            return Err(WorldError::InvalidSetting {
                field: "substeps",
                value: format!("{substeps}"),
                reason: "must leave each substep of this time step a normal number",
            });
        }
        let (sleep, gravity) = (self.settings.sleep, self.settings.gravity);
        // From here a step refused part-way puts back what it changed (see `refused` below).
        self.solver.begin_step();
        self.dormant.begin_step();
        if self.sleeper.before_step(&mut self.bodies, sleep, gravity) {
            self.quiet_step(dt);
            return Ok(&self.stats);
        }
        self.solver.collisions.clear();
        self.solver.profile = StepProfile::default();
        self.rollback.clear();
        if substeps > 1 {
            self.rollback
                .extend(self.bodies.iter().map(|b| (b.position(), b.velocity())));
        }
        let mut left_out = false;
        for k in 0..substeps {
            // With sleeping on, a step of one substep may leave out the islands asleep beyond
            // the reach of everything that moves (see `dormant.rs`).
            let leaves_out = substeps == 1
                && self.integrator.is_none()
                && self.sleeper.asleep() > 0
                && self.dormant.choose(
                    &self.bodies,
                    self.sleeper.states(),
                    &self.settings,
                    sub_dt,
                    self.sleeper.generation(),
                );
            left_out = leaves_out;
            if !self.dormant.same_indices(leaves_out) {
                self.solver.forget_indices();
            }
            let ctx = StepContext {
                settings: &self.settings,
                integrator: self.integrator.as_deref(),
                toi: self.toi.as_deref(),
                dt: sub_dt,
                start_time: self.time + f64::from(k) * sub_dt,
                sleeping: self.sleeper.asleep() > 0,
                left_out: if leaves_out {
                    (
                        self.dormant.left_out_dynamic,
                        self.dormant.left_out_acceleration,
                    )
                } else {
                    (0, 0.0)
                },
            };
            let result = if leaves_out {
                let dormant = &mut self.dormant;
                let (left_out_overlap, left_out_potential) = match dormant.left_out() {
                    Some(left_out) => left_out,
                    None => {
                        // The deepest overlap of a pair with a body left out, and their
                        // potential energy: such a body stays where it is in the step, as
                        // does every fixed one.
                        let bodies = &self.bodies;
                        let mut taken = std::mem::take(&mut self.taken);
                        taken.clear();
                        taken.resize(bodies.len(), false);
                        for &i in &dormant.in_step {
                            taken[i as usize] = true;
                        }
                        if !dormant.deepest_known() {
                            // Each island's deepest overlap with a sphere asleep or fixed,
                            // once for as long as it sleeps.
                            work_out_deepest(
                                dormant,
                                &mut self.solver,
                                bodies,
                                (&mut self.fixed_indices, &mut self.scratch_indices),
                            );
                        }
                        let deepest = dormant.deepest_left_out();
                        let potential = bodies
                            .iter()
                            .zip(&taken)
                            .filter(|(b, taken)| !**taken && !b.is_fixed())
                            .map(|(b, _)| potential_of(b, &self.settings))
                            .sum();
                        self.taken = taken;
                        dormant.set_left_out(deepest, potential);
                        (deepest, potential)
                    }
                };
                // The step's bodies moved out of the world for the step, and back.
                let m = dormant.in_step.len();
                while dormant.bodies.len() < m {
                    dormant
                        .bodies
                        .push(Body::new(BodyId(0), SphereDesc::new(1.0)));
                }
                for (k, &i) in dormant.in_step.iter().enumerate() {
                    std::mem::swap(&mut self.bodies[i as usize], &mut dormant.bodies[k]);
                }
                let result = self.solver.step(&mut dormant.bodies[..m], &ctx, &mut stats);
                for (k, &i) in dormant.in_step.iter().enumerate() {
                    std::mem::swap(&mut self.bodies[i as usize], &mut dormant.bodies[k]);
                }
                if result.is_ok() {
                    // (The potential energy summed in another order than
                    // `World::potential_energy`'s: the same to rounding.)
                    stats.max_overlap = stats.max_overlap.max(left_out_overlap);
                    stats.potential_energy += left_out_potential;
                }
                result.map_err(|index| dormant.in_step[index] as usize)
            } else {
                self.solver.step(&mut self.bodies, &ctx, &mut stats)
            };
            if let Err(index) = result {
                // The refused substep wrote nothing back; undo the substeps before it, and
                // drop the step's records. What the step changed for the steps after it (each
                // body's sleep, the solver's warm start and marks) is put back too: the next
                // step is as if this one had never been tried.
                for (body, &(position, velocity)) in self.bodies.iter_mut().zip(&self.rollback) {
                    body.desc.position = position;
                    body.desc.velocity = velocity;
                }
                self.sleeper.refused(&mut self.bodies);
                self.solver.refused();
                self.dormant.refused();
                let body = &self.bodies[index];
                // Its fastest component (as `BodyError::value` says: one component; the speed
                // was given until the sixty-first session, infinite past about 1.3e154 m/s).
                let velocity = body.velocity();
                return Err(WorldError::Body(BodyError {
                    body: label(body.desc.name.as_deref(), body.id),
                    id: Some(body.id),
                    field: Field::Velocity,
                    value: velocity[velocity.abs().max_position()],
                    reason: "would take the sphere beyond the finite range within this step",
                }));
            }
        }
        self.steps += 1;
        self.time += dt;
        std::mem::swap(&mut self.collisions, &mut self.solver.collisions);
        self.profile = self.solver.profile;
        self.last_step_left_out = left_out;
        self.last_step.clear();
        if left_out {
            let bodies = &self.bodies;
            self.last_step
                .extend(self.dormant.in_step.iter().map(|&i| bodies[i as usize].id));
        }
        if let Some(sleep) = sleep {
            let step = (self.settings.gravity, dt, self.time);
            // Only the step's bodies can have moved, woken or been calm.
            let only =
                left_out.then_some((&self.dormant.in_step[..], self.dormant.left_out_dynamic));
            let fell_asleep =
                self.sleeper
                    .after_step(&mut self.bodies, only, &mut self.solver, sleep, step);
            if fell_asleep {
                // The solver summed them as it wrote the bodies back: now without the speeds
                // of the bodies that fell asleep.
                stats.kinetic_energy = self.kinetic_energy();
                stats.momentum = self.momentum();
            }
            stats.asleep = self.sleeper.asleep() as u32;
        } else {
            self.sleeper.stepped_without_sleeping();
        }
        stats.time = self.time;
        self.stats = stats;
        Ok(&self.stats)
    }

    /// A step with every dynamic body asleep and no fixed one moving, and nothing changed
    /// since the last step: nothing moves, and the last step's energies and overlap stand.
    fn quiet_step(&mut self, dt: f64) {
        self.steps += 1;
        self.time += dt;
        self.last_step_left_out = true;
        self.last_step.clear();
        self.collisions.clear();
        if self.solver.profiling {
            self.profile = StepProfile::default();
        }
        let last = self.stats;
        self.stats = StepStats {
            time: self.time,
            dt,
            potential_energy: last.potential_energy,
            max_overlap: last.max_overlap,
            asleep: last.asleep,
            quiet: true,
            ..Default::default()
        };
    }

    /// Kinetic energy of the dynamic bodies.
    pub fn kinetic_energy(&self) -> f64 {
        self.bodies.iter().map(Body::kinetic_energy).sum()
    }

    /// Potential energy of the dynamic bodies in gravity and their constant forces.
    pub fn potential_energy(&self) -> f64 {
        self.bodies
            .iter()
            .filter(|b| !b.is_fixed())
            .map(|b| potential_of(b, &self.settings))
            .sum()
    }

    /// Total momentum of the dynamic bodies.
    pub fn momentum(&self) -> DVec3 {
        self.bodies.iter().map(Body::momentum).sum()
    }

    /// Largest overlap between two bodies, at least one of them dynamic (0 if none). It takes
    /// `&mut self` to reuse the step's broad-phase buffers (no allocation once warmed up); the
    /// last step's answer is also in [`StepStats::max_overlap`], through `&self`.
    pub fn max_overlap(&mut self) -> f64 {
        self.solver.max_overlap(&self.bodies)
    }

    /// How bodies `a` and `b` stand relative to each other right now.
    pub fn classify(&self, a: BodyId, b: BodyId) -> Result<ContactKind, WorldError> {
        let kin = |id| -> Result<Kinematics, WorldError> {
            let body = self.body(id).ok_or(WorldError::UnknownBody(id))?;
            Ok(Kinematics {
                position: body.position(),
                velocity: body.velocity(),
                acceleration: if body.is_fixed() {
                    DVec3::ZERO
                } else {
                    body.acceleration(self.settings.gravity)
                },
                radius: body.radius(),
            })
        };
        Ok(classify(&kin(a)?, &kin(b)?, self.settings.tolerance))
    }
}

/// How errors name a body: its name in quotes, else its id.
fn label(name: Option<&str>, id: BodyId) -> String {
    match name {
        Some(name) => format!("'{name}' ({id})"),
        None => id.to_string(),
    }
}

/// Potential energy of dynamic `body` in the settings' gravity and its constant force.
pub(crate) fn potential_of(body: &Body, settings: &Settings) -> f64 {
    -(body.mass() * settings.gravity + body.force()).dot(body.position())
}

/// Works out the deepest overlap of each island asleep whose deepest overlap is not known
/// (see [`Dormant::deepest_known`]): its pairs among themselves and with the fixed bodies one
/// by one when they are few (an island or two fell asleep), else every pair of the world
/// through the broad phase. Debug builds check the first against the second.
fn work_out_deepest(
    dormant: &mut crate::dormant::Dormant,
    solver: &mut Solver,
    bodies: &[Body],
    scratch: (&mut Vec<u32>, &mut Vec<u32>),
) {
    let (fixed, unknown) = scratch;
    fixed.clear();
    fixed.extend((0..bodies.len() as u32).filter(|&i| bodies[i as usize].is_fixed()));
    if dormant.unknown_if_few(fixed.len(), 8 * bodies.len() + 1024, unknown) {
        for (k, &i) in unknown.iter().enumerate() {
            let a = &bodies[i as usize];
            // (An island's bodies come one after another.)
            for &j in &unknown[k + 1..] {
                if !dormant.same_island(i as usize, j as usize) {
                    break;
                }
                dormant.raise_deepest(i as usize, overlap(a, &bodies[j as usize]));
            }
            for &j in fixed.iter() {
                dormant.raise_deepest(i as usize, overlap(a, &bodies[j as usize]));
            }
        }
        #[cfg(debug_assertions)]
        {
            let found = dormant.deepest_each();
            dormant.forget_deepest();
            every_pair_deepest(dormant, solver, bodies);
            assert_eq!(
                found,
                dormant.deepest_each(),
                "the islands' deepest overlaps pair by pair differ from the broad phase's"
            );
        }
    } else {
        every_pair_deepest(dormant, solver, bodies);
    }
    dormant.set_deepest_known();
}

/// [`work_out_deepest`] through every pair of the world near each other.
fn every_pair_deepest(dormant: &mut crate::dormant::Dormant, solver: &mut Solver, bodies: &[Body]) {
    solver.pairs_near(
        bodies,
        |_| 0.0,
        |i, j| {
            let (a, b) = (&bodies[i], &bodies[j]);
            let still = |x: &Body| x.asleep || x.is_fixed();
            if !(a.asleep || b.asleep) || !still(a) || !still(b) {
                return;
            }
            let deep = overlap(a, b);
            for (k, body) in [(i, a), (j, b)] {
                if body.asleep {
                    dormant.raise_deepest(k, deep);
                }
            }
        },
    );
}
