//! Playing a scene: step the world for a duration and report where everything ended.

use std::ops::ControlFlow;
use std::time::Instant;

use serde::Serialize;
use sphere_physics::{Readable, SceneDesc, SceneError, StepStats, ToiMethod, World, WorldError};

use crate::cli::method_name;

/// How to play a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Playback {
    /// Simulated seconds.
    pub duration: f64,
    /// Time step; `None` means the scene's, else 1/60.
    pub dt: Option<f64>,
    /// Time-of-impact method; `None` means the scene's, else exact.
    pub method: Option<ToiMethod>,
}

/// The default time step: 1/60 s.
pub const DEFAULT_DT: f64 = 1.0 / 60.0;

/// The most steps one run may take.
pub const MAX_STEPS: u64 = 1_000_000_000;

/// Why a scene could not be played.
#[derive(Debug, thiserror::Error)]
pub enum PlayError {
    /// The scene is invalid.
    #[error("{0}")]
    Scene(#[from] SceneError),
    /// The world refused a step.
    #[error("{0}")]
    World(#[from] WorldError),
    /// The world refused a step part-way through the run (a sphere would leave the finite
    /// range, say): which step, and when.
    #[error("step {step} (from t = {} s): {error}", Readable(*.time))]
    Step {
        /// The refused step, counting from 1.
        step: u64,
        /// The simulated time it started from.
        time: f64,
        /// Why it was refused.
        error: WorldError,
    },
    /// The duration ends with a step too short to take: its substeps would not be normal
    /// numbers (the full steps' are).
    #[error(
        "--duration {} ends with a step of {} s, too short to take (each of its {substeps} \
         substep(s) would not be a normal number): ask for a whole number of steps of {} s",
        Readable(*.duration),
        Readable(*.last),
        Readable(*.dt)
    )]
    LastStepTooShort {
        /// Duration asked for.
        duration: f64,
        /// The full steps' length.
        dt: f64,
        /// The last, shorter step's.
        last: f64,
        /// Substeps a step.
        substeps: u32,
    },
    /// The observer stopped the run after this step (see [`Observer::step_done`]).
    #[error("stopped after step {step}")]
    Stopped {
        /// The last step taken, counting from 1.
        step: u64,
    },
    /// The duration needs too many steps.
    #[error(
        "--duration {} at a step of {} s ({step_from}) needs {} steps, more than the limit of \
         {MAX_STEPS}",
        Readable(*.duration),
        Readable(*.dt),
        Readable(*.steps)
    )]
    TooManySteps {
        /// Duration asked for.
        duration: f64,
        /// Step.
        dt: f64,
        /// Where the step came from: `--dt`, the scene's `dt`, or the default.
        step_from: &'static str,
        /// Steps needed.
        steps: f64,
    },
}

/// The step plan for a duration: `full` steps of `dt`, then one of `last` if it is not 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepPlan {
    /// Steps of the full `dt`.
    pub full: u64,
    /// The length of a final shorter step (0 if the duration is a whole number of steps).
    pub last: f64,
}

impl StepPlan {
    /// Splits `duration` into steps of `dt`. A duration within 1e-9 of a step of a whole
    /// number of steps is that number of steps (so 2 s at 1/60 s is 120 steps); for very many
    /// steps, within the rounding of `duration / dt` (a few units in its last place).
    pub fn new(duration: f64, dt: f64) -> Result<Self, PlayError> {
        let ratio = duration / dt;
        if ratio > MAX_STEPS as f64 {
            return Err(PlayError::TooManySteps {
                duration,
                dt,
                step_from: "--dt",
                steps: ratio.ceil(),
            });
        }
        let nearest = ratio.round();
        let slack = 1e-9f64.max(4.0 * f64::EPSILON * ratio);
        if (ratio - nearest).abs() <= slack && nearest >= 1.0 {
            return Ok(Self {
                full: nearest as u64,
                last: 0.0,
            });
        }
        let full = ratio.floor();
        Ok(Self {
            full: full as u64,
            last: duration - full * dt,
        })
    }

    /// Steps in all.
    pub fn total(&self) -> u64 {
        self.full + u64::from(self.last > 0.0)
    }
}

/// One body at the end of a run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BodyReport {
    /// The sphere's name, or its index in the scene as a string. Names need not be unique (two
    /// gases' walls share theirs): `index` tells bodies apart.
    pub name: String,
    /// Its index in the scene's order (listed spheres, then generated ones).
    pub index: usize,
    /// Final position.
    pub position: [f64; 3],
    /// Final velocity.
    pub velocity: [f64; 3],
    /// Radius.
    pub radius: f64,
    /// Mass (`null` when fixed).
    pub mass: Option<f64>,
    /// Fixed.
    pub fixed: bool,
    /// Asleep at the end (only when the scene turns sleeping on: see `Settings::sleep`).
    pub asleep: bool,
}

/// Energy, momentum and the largest overlap at one instant.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Snapshot {
    /// Kinetic energy.
    pub kinetic_energy: f64,
    /// Potential energy in gravity and constant forces.
    pub potential_energy: f64,
    /// Their sum.
    pub total_energy: f64,
    /// Momentum of the dynamic bodies.
    pub momentum: [f64; 3],
    /// Largest overlap between two spheres.
    pub max_overlap: f64,
}

impl Snapshot {
    fn of(world: &mut World) -> Self {
        let (kinetic_energy, potential_energy) = (world.kinetic_energy(), world.potential_energy());
        Self {
            kinetic_energy,
            potential_energy,
            total_energy: kinetic_energy + potential_energy,
            momentum: world.momentum().to_array(),
            max_overlap: world.max_overlap(),
        }
    }
}

/// Statistics of a whole run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RunStats {
    /// Collisions resolved over the run, as `StepStats::collisions` counts them (resting
    /// contacts included).
    pub collisions: u64,
    /// Of those, resolved as resting contacts (restitution 0).
    pub resting_contacts: u64,
    /// Impacts left to the next step by the per-step budget
    /// (`StepStats::collisions_deferred`).
    pub collisions_deferred: u64,
    /// Steps whose collision budget ran out, their rest solved at once
    /// (`StepStats::fell_back`).
    pub steps_fell_back: u64,
    /// Spheres moved apart by their positions from overlaps left with nothing accelerating,
    /// summed over the steps (`StepStats::separated`).
    pub separated: u64,
    /// Time-of-impact tests.
    pub toi_tests: u64,
    /// Bisection iterations (0 for exact).
    pub toi_iterations: u64,
    /// Kinetic energy at the end.
    pub kinetic_energy: f64,
    /// Potential energy at the end.
    pub potential_energy: f64,
    /// Total energy at the end.
    pub total_energy: f64,
    /// Momentum at the end.
    pub momentum: [f64; 3],
    /// Largest overlap at the end.
    pub max_overlap: f64,
    /// Largest overlap at the end of any step.
    pub max_overlap_seen: f64,
    /// Wall-clock seconds spent stepping.
    pub wall_seconds: f64,
    /// Wall-clock nanoseconds per sphere per step.
    pub ns_per_sphere_step: f64,
}

/// The JSON document a run prints.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    /// Scene name.
    pub scene: String,
    /// Method: `exact` or `bisection:N`.
    pub method: String,
    /// Integrator.
    pub integrator: String,
    /// Substeps per step.
    pub substeps: u32,
    /// Time step.
    pub dt: f64,
    /// Duration asked for.
    pub duration: f64,
    /// Simulated time reached.
    pub time: f64,
    /// Steps taken.
    pub steps: u64,
    /// Spheres, in the scene file's order (listed spheres, then generated ones).
    pub bodies: Vec<BodyReport>,
    /// Energy, momentum and the largest overlap before the first step.
    pub initial: Snapshot,
    /// Statistics of the run.
    pub stats: RunStats,
}

/// Called after every step with the step's statistics, the world, and the step count planned.
pub trait Observer {
    /// One step is done: `Break` stops the run there (its trace could not be written, say),
    /// and the run ends with [`PlayError::Stopped`].
    fn step_done(
        &mut self,
        stats: &StepStats,
        world: &World,
        planned_steps: u64,
    ) -> ControlFlow<()>;
}

impl<F: FnMut(&StepStats, &World, u64) -> ControlFlow<()>> Observer for F {
    fn step_done(
        &mut self,
        stats: &StepStats,
        world: &World,
        planned_steps: u64,
    ) -> ControlFlow<()> {
        self(stats, world, planned_steps)
    }
}

/// A scene's world built with a playback's overrides, every check done (the scene, the
/// overrides, the number of steps), ready to play.
pub struct Prepared {
    world: World,
    scene: String,
    dt: f64,
    duration: f64,
    plan: StepPlan,
}

impl Prepared {
    /// Builds `scene`'s world (generating its spheres once) with `playback`'s overrides.
    pub fn new(scene: &SceneDesc, playback: Playback) -> Result<Self, PlayError> {
        // The method and the step asked for replace the scene's before anything is checked (a
        // scene's method out of range, or its bad `dt`, does not matter when it is
        // overridden).
        let overridden;
        let scene = if playback.method.is_some() || playback.dt.is_some() {
            overridden = SceneDesc {
                method: playback.method.or(scene.method),
                dt: playback.dt.or(scene.dt),
                ..scene.clone()
            };
            &overridden
        } else {
            scene
        };
        let world = scene.build()?;
        let (dt, source) = match (playback.dt, scene.dt) {
            (Some(dt), _) => (dt, "--dt"),
            (None, Some(dt)) => (dt, "the scene's dt"),
            (None, None) => (DEFAULT_DT, "the default"),
        };
        let plan = StepPlan::new(playback.duration, dt).map_err(|e| match e {
            PlayError::TooManySteps {
                duration, steps, ..
            } => PlayError::TooManySteps {
                duration,
                dt,
                step_from: source,
                steps,
            },
            other => other,
        })?;
        // Each step's substeps (the full steps', and the last shorter one's) must be normal
        // numbers, as the world checks at each step: checked here, before the run starts.
        let substeps = world.settings().substeps;
        let normal = |step: f64| (step / f64::from(substeps)).is_normal();
        if !normal(dt) {
            return Err(PlayError::World(WorldError::InvalidSetting {
                field: "substeps",
                value: format!("{substeps}"),
                reason: "must leave each substep of this time step a normal number",
            }));
        }
        // (Blamed on the substeps until the fifty-seventh session, though the duration asked
        // for it.)
        if plan.last > 0.0 && !normal(plan.last) {
            return Err(PlayError::LastStepTooShort {
                duration: playback.duration,
                dt,
                last: plan.last,
                substeps,
            });
        }
        Ok(Self {
            world,
            scene: scene.name.clone(),
            dt,
            duration: playback.duration,
            plan,
        })
    }
}

/// Builds the scene's world with `playback`'s overrides and plays it.
pub fn play(
    scene: &SceneDesc,
    playback: Playback,
    observer: &mut dyn Observer,
) -> Result<Report, PlayError> {
    play_prepared(Prepared::new(scene, playback)?, observer)
}

/// Plays a prepared run.
pub fn play_prepared(prepared: Prepared, observer: &mut dyn Observer) -> Result<Report, PlayError> {
    let Prepared {
        mut world,
        scene,
        dt,
        duration,
        plan,
    } = prepared;
    let initial = Snapshot::of(&mut world);
    let planned = plan.total();
    let mut totals = (0u64, 0u64, 0u64, 0u64, 0u64);
    let (mut fell_back, mut separated) = (0u64, 0u64);
    // At the ends of steps; the start's is in `initial`.
    let mut max_overlap_seen = 0.0f64;

    let mut stepping = std::time::Duration::ZERO;
    for index in 0..planned {
        let step_dt = if index < plan.full { dt } else { plan.last };
        let started = Instant::now();
        let time = world.time();
        let stats = *world.step(step_dt).map_err(|error| PlayError::Step {
            step: index + 1,
            time,
            error,
        })?;
        stepping += started.elapsed();
        totals.0 += u64::from(stats.collisions);
        totals.1 += u64::from(stats.resting_contacts);
        totals.2 += u64::from(stats.collisions_deferred);
        fell_back += u64::from(stats.fell_back);
        separated += u64::from(stats.separated);
        totals.3 += stats.toi_tests;
        totals.4 += stats.toi_iterations;
        max_overlap_seen = max_overlap_seen.max(stats.max_overlap);
        if observer.step_done(&stats, &world, planned).is_break() {
            return Err(PlayError::Stopped { step: index + 1 });
        }
    }
    let wall_seconds = stepping.as_secs_f64();

    let end = Snapshot::of(&mut world);
    let max_overlap = end.max_overlap;
    let bodies = world
        .bodies()
        .iter()
        .enumerate()
        .map(|(index, body)| BodyReport {
            name: body.name().map_or_else(|| index.to_string(), str::to_owned),
            index,
            position: body.position().to_array(),
            velocity: body.velocity().to_array(),
            radius: body.radius(),
            mass: (!body.is_fixed()).then(|| body.mass()),
            fixed: body.is_fixed(),
            asleep: body.is_asleep(),
        })
        .collect();
    let sphere_steps = (world.len() as f64) * (world.steps() as f64);
    Ok(Report {
        scene,
        method: method_name(&world.settings().method),
        integrator: format!("{:?}", world.settings().integrator),
        substeps: world.settings().substeps,
        dt,
        duration,
        time: world.time(),
        steps: world.steps(),
        bodies,
        initial,
        stats: RunStats {
            collisions: totals.0,
            resting_contacts: totals.1,
            collisions_deferred: totals.2,
            steps_fell_back: fell_back,
            separated,
            toi_tests: totals.3,
            toi_iterations: totals.4,
            kinetic_energy: end.kinetic_energy,
            potential_energy: end.potential_energy,
            total_energy: end.total_energy,
            momentum: end.momentum,
            max_overlap,
            max_overlap_seen,
            wall_seconds,
            ns_per_sphere_step: if sphere_steps > 0.0 {
                wall_seconds * 1e9 / sphere_steps
            } else {
                0.0
            },
        },
    })
}
