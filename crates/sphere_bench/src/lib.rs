//! Benchmarks of [`sphere_physics`] at scale: the shower and gas scenes at any size, timed
//! stepping, and (with the `rapier` feature) the same scenes stepped by rapier3d 0.36.
#![warn(missing_docs)]

pub mod accuracy;
#[cfg(feature = "rapier")]
pub mod rapier_peer;
pub mod scenes;
pub mod svg;

use std::time::Instant;

use sphere_physics::{SceneDesc, StepProfile, World};

/// What one engine did on one scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// Bodies stepped (fixed ones included).
    pub bodies: usize,
    /// Steps timed.
    pub steps: u32,
    /// Wall seconds spent stepping.
    pub seconds: f64,
    /// Wall seconds of the slowest timed step: the longest a game's frame would wait.
    pub slowest: f64,
    /// Kinetic energy before the first step.
    pub kinetic_before: f64,
    /// Kinetic energy after the last.
    pub kinetic_after: f64,
    /// Kinetic energy after each timed step, averaged (read outside the timing): for a bed
    /// that should lie still, how much it jiggles.
    pub kinetic_mean: f64,
    /// Collisions resolved (0 when the engine does not count them).
    pub collisions: u64,
    /// Pairs handed to the time-of-impact method (our engine only; 0 for rapier).
    pub toi_tests: u64,
    /// Largest overlap left after the last step (for rapier, measured by our broad phase).
    pub max_overlap: Option<f64>,
    /// Collisions left to a later step because a step's budget ran out (our engine only; a
    /// run that defers any did less than the scene asked).
    pub deferred: u64,
    /// Our step's phases, summed over the timed steps (when measured with profiling on).
    pub phases: Option<StepProfile>,
    /// Each timed step of our engine, in order (empty for rapier).
    pub per_step: Vec<StepRecord>,
    /// Dynamic bodies asleep after the last step (ours with `Settings::sleep` on; rapier's
    /// sleeping is on by default).
    pub asleep: usize,
}

/// What one timed step of our engine did, and how long it took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepRecord {
    /// Wall seconds the step took.
    pub seconds: f64,
    /// Collisions resolved, resting contacts included.
    pub collisions: u32,
    /// Of those, resting contacts.
    pub resting: u32,
    /// Pairs handed to the time-of-impact method.
    pub toi_tests: u64,
    /// Wall seconds of the step's event loop (when measured with profiling on).
    pub events: Option<f64>,
}

impl Measurement {
    /// Collisions and time-of-impact tests per body per step: the work the scene asks of an
    /// event-driven engine, which grows with a pile's depth.
    pub fn work_per_body_step(&self) -> (f64, f64) {
        let body_steps = self.bodies as f64 * f64::from(self.steps);
        (
            self.collisions as f64 / body_steps,
            self.toi_tests as f64 / body_steps,
        )
    }

    /// Nanoseconds per body per step.
    pub fn ns_per_body_step(&self) -> f64 {
        self.seconds * 1e9 / (self.bodies as f64 * f64::from(self.steps))
    }

    /// Nanoseconds per body per step in each of our step's phases, named, if profiled.
    pub fn phases_per_body_step(&self) -> Option<[(&'static str, f64); 9]> {
        let p = self.phases?;
        let body_steps = self.bodies as f64 * f64::from(self.steps);
        let ns = |d: std::time::Duration| d.as_secs_f64() * 1e9 / body_steps;
        Some([
            ("integrate", ns(p.integrate)),
            ("sort", ns(p.sort)),
            ("build", ns(p.build)),
            ("first pass", ns(p.first_pass)),
            ("resting", ns(p.resting)),
            ("events", ns(p.events)),
            ("write-back", ns(p.write_back)),
            ("overlap", ns(p.overlap)),
            ("all", ns(p.total())),
        ])
    }

    /// Steps per second.
    pub fn steps_per_second(&self) -> f64 {
        f64::from(self.steps) / self.seconds
    }
}

/// Steps `scene` with our engine: `settle` steps of `dt` untimed (at least one, warming up,
/// as for rapier), then `steps` steps, each timed, and with `profile` each step's phases too
/// (a few clock reads per step).
pub fn measure_ours(
    scene: &SceneDesc,
    settle: u32,
    steps: u32,
    dt: f64,
    profile: bool,
) -> Measurement {
    let mut world: World = scene.build().expect("bench scenes are valid");
    world.set_profiling(profile);
    let kinetic_before = world.kinetic_energy();
    for _ in 0..settle.max(1) {
        world.step(dt).expect("dt is valid");
    }
    let (mut collisions, mut deferred, mut toi_tests) = (0u64, 0u64, 0u64);
    let mut seconds = 0.0;
    let mut phases = profile.then(StepProfile::default);
    let mut per_step = Vec::with_capacity(steps as usize);
    let (mut kinetic_sum, mut slowest) = (0.0, 0.0f64);
    for _ in 0..steps {
        let started = Instant::now();
        let stats = *world.step(dt).expect("dt is valid");
        let elapsed = started.elapsed().as_secs_f64();
        seconds += elapsed;
        slowest = slowest.max(elapsed);
        kinetic_sum += world.kinetic_energy();
        collisions += u64::from(stats.collisions);
        deferred += u64::from(stats.collisions_deferred);
        toi_tests += stats.toi_tests;
        let mut events = None;
        if let (Some(sum), Some(step)) = (&mut phases, world.profile()) {
            *sum += *step;
            events = Some(step.events.as_secs_f64());
        }
        per_step.push(StepRecord {
            seconds: elapsed,
            collisions: stats.collisions,
            resting: stats.resting_contacts,
            toi_tests: stats.toi_tests,
            events,
        });
    }
    Measurement {
        bodies: world.len(),
        steps,
        seconds,
        slowest,
        kinetic_before,
        kinetic_after: world.kinetic_energy(),
        kinetic_mean: kinetic_sum / f64::from(steps.max(1)),
        collisions,
        toi_tests,
        max_overlap: Some(world.max_overlap()),
        deferred,
        phases,
        per_step,
        asleep: world.bodies().iter().filter(|b| b.is_asleep()).count(),
    }
}

/// How rapier is set up for a run.
#[cfg(feature = "rapier")]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RapierSetting {
    /// Continuous collision detection: rapier's default, bullets, or off.
    pub ccd: rapier_peer::RapierCcd,
    /// Solver iterations (rapier's default is 4; its docs suggest 1 or 2 where speed matters
    /// more than accuracy).
    pub iterations: usize,
    /// `length_unit`. rapier 0.36's docs describe it as how many world units make a metre
    /// (1.0 for scenes in metres, like these); it scales rapier's tolerances, and the
    /// spheres' diameter (0.1) made rapier 2.3x to 2.7x faster on these scenes than 1.0.
    pub length_unit: f64,
    /// The gas's wall spheres as rapier half-spaces (see
    /// [`rapier_peer::RapierConfig::flat_walls`]).
    pub flat_walls: bool,
}

/// Steps `scene` with rapier3d 0.36: `settle` steps of `dt` untimed (at least one), then
/// `steps` steps, each timed, single-threaded, as `setting` says.
#[cfg(feature = "rapier")]
pub fn measure_rapier(
    scene: &SceneDesc,
    settle: u32,
    steps: u32,
    dt: f64,
    setting: RapierSetting,
) -> Measurement {
    use rapier_peer::{RapierConfig, RapierSphere, RapierWorld};
    let descs = scene.sphere_descs().expect("bench scenes are valid");
    let spheres: Vec<RapierSphere> = descs.iter().map(RapierSphere::from).collect();
    let config = RapierConfig {
        gravity: scene.gravity,
        dt,
        ccd: setting.ccd,
        length_unit: setting.length_unit,
        solver_iterations: setting.iterations,
        flat_walls: setting.flat_walls,
    };
    let mut world = RapierWorld::new(&spheres, &config);
    let kinetic_before = world.kinetic_energy();
    // The first step builds rapier's broad-phase tree and every contact pair from nothing:
    // untimed, as ours is.
    for _ in 0..settle.max(1) {
        world.step();
    }
    let (mut seconds, mut kinetic_sum, mut slowest) = (0.0, 0.0, 0.0f64);
    for _ in 0..steps {
        let started = Instant::now();
        world.step();
        let elapsed = started.elapsed().as_secs_f64();
        seconds += elapsed;
        slowest = slowest.max(elapsed);
        kinetic_sum += world.kinetic_energy();
    }
    Measurement {
        bodies: world.len(),
        steps,
        seconds,
        slowest,
        kinetic_before,
        kinetic_after: world.kinetic_energy(),
        kinetic_mean: kinetic_sum / f64::from(steps.max(1)),
        collisions: 0,
        toi_tests: 0,
        max_overlap: Some(overlap_left(scene, descs, &world.positions())),
        deferred: 0,
        phases: None,
        per_step: Vec::new(),
        asleep: world.asleep(),
    }
}

/// The largest overlap between two spheres of `scene`, the dynamic ones placed at
/// `positions` (rapier's, after its run) and the fixed ones where the scene puts them, at least
/// one of them dynamic, found by our engine's broad phase; NaN if rapier left a sphere where
/// ours would not take it (not finite). The fixed ones keep the scene's places because rapier
/// gives some of them back changed: a wall far from the origin rounded to single precision
/// (about half a millimetre at 1e4 m), or a wall made a half-space placed at its tangent point
/// (`--rapier-flat-walls`).
#[cfg(feature = "rapier")]
fn overlap_left(
    scene: &SceneDesc,
    descs: Vec<sphere_physics::SphereDesc>,
    positions: &[[f64; 3]],
) -> f64 {
    let mut world = World::new(scene.settings().expect("bench scenes are valid"));
    for (mut desc, &position) in descs.into_iter().zip(positions) {
        if !desc.fixed {
            desc.position = sphere_physics::glam::DVec3::from_array(position);
        }
        // Placed where rapier left it: an overlap is what this measures, not an error.
        if world.add_sphere(desc).is_err() {
            return f64::NAN;
        }
    }
    world.max_overlap()
}
