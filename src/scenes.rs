//! Scenes as Bevy states: the registry the chooser lists, scene files, and what happens when a
//! scene is entered (the physics restarts with the scene's settings, its entities are spawned)
//! and left (its entities are despawned).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

use bevy::ecs::system::ScheduleSystem;
use bevy::prelude::*;
use bevy_sphere_physics::prelude::*;
use bevy_sphere_physics::sphere_physics::{Readable, SceneDesc, SceneError, Settings, SphereSpec};

/// The scene being shown: a Bevy state. `None` before the first scene is chosen.
///
/// Entering `Scene(id)` restarts the physics with that scene's settings and spawns its
/// entities; leaving it despawns them.
#[derive(States, Clone, PartialEq, Eq, Hash, Debug, Default)]
pub enum ActiveScene {
    /// No scene yet: the chooser is open.
    #[default]
    None,
    /// The scene registered under this id.
    Scene(String),
}

impl ActiveScene {
    /// The state of the scene `id`.
    pub fn scene(id: impl Into<String>) -> Self {
        Self::Scene(id.into())
    }

    /// The scene's id, if any.
    pub fn id(&self) -> Option<&str> {
        match self {
            Self::None => None,
            Self::Scene(id) => Some(id),
        }
    }
}

/// The most fixed steps the lab runs in one frame. Bevy catches up on at most 0.25 s of time
/// a frame, which with a scene's `dt` of 1e-6 s (the smallest the lab takes) would be 250 000
/// steps in a frame, the window frozen for seconds: for steps shorter than 0.5 ms the lab
/// catches up on no more than this many steps' time a frame, and the scene runs slower than
/// real time. (Until the sixty-second session it froze; until the sixty-third, in the frame
/// a scene was entered in, whose time was worked out under the last scene's catch-up.) The
/// time of a frame's steps past this many is dropped.
pub const MAX_FIXED_STEPS_PER_FRAME: u32 = 500;

/// Fixed steps run in this frame, counted against [`MAX_FIXED_STEPS_PER_FRAME`].
#[derive(Resource, Default)]
pub(crate) struct FixedStepsThisFrame(u32);

/// Starts the frame's count of fixed steps.
pub(crate) fn start_frame_steps(mut steps: ResMut<FixedStepsThisFrame>) {
    steps.0 = 0;
}

/// Counts a fixed step, and once the frame has run [`MAX_FIXED_STEPS_PER_FRAME`] of them drops
/// the time left to step in it, which ends Bevy's loop of fixed steps for the frame.
pub(crate) fn end_frame_steps_at_most(
    mut steps: ResMut<FixedStepsThisFrame>,
    mut fixed: ResMut<Time<Fixed>>,
) {
    steps.0 = steps.0.saturating_add(1);
    if steps.0 >= MAX_FIXED_STEPS_PER_FRAME {
        let left = fixed.overstep();
        fixed.discard_overstep(left);
    }
}

/// A scene's entry in the chooser (the tutorial's `SceneAttribute`) and the physics it runs
/// with.
#[derive(Clone, Debug, PartialEq)]
pub struct LabScene {
    /// Unique id: the state is `ActiveScene::Scene(id)`; file scenes use the file's stem.
    pub id: String,
    /// Shown in the chooser.
    pub name: String,
    /// Shown in the chooser: what the scene shows and what it models.
    pub description: String,
    /// The core's settings: gravity, method, integrator, substeps.
    pub settings: Settings,
    /// Restitution of spheres that do not set their own.
    pub restitution: f64,
    /// The fixed step, in seconds. Bevy's fixed clock counts whole nanoseconds, so the step
    /// the lab runs is this rounded to a nanosecond (1/60 s runs as 0.016666667 s); the
    /// physics integrates over the step it runs.
    pub dt: f64,
    /// A box the camera keeps in view with the spheres when the scene is entered, `(low
    /// corner, high corner)` (a scene file's `view`; default none).
    pub view: Option<(DVec3, DVec3)>,
}

impl LabScene {
    /// Why the lab cannot run this scene, if it cannot: a step outside [1e-6, 1] s, a
    /// restitution outside [0, 1], a view that is not a box, or settings the core refuses.
    fn problem(&self) -> Option<String> {
        if !(self.dt.is_finite() && (1e-6..=1.0).contains(&self.dt)) {
            Some(format!(
                "dt {} is not a step in seconds in [1e-6, 1]",
                Readable(self.dt)
            ))
        } else if !(0.0..=1.0).contains(&self.restitution) {
            Some(format!(
                "restitution {} is outside [0, 1]",
                Readable(self.restitution)
            ))
        } else if let Some((low, high)) = self
            .view
            .filter(|(low, high)| !(low.is_finite() && high.is_finite() && low.cmple(*high).all()))
        {
            Some(format!(
                "view from {low} to {high} is not a box with finite corners, low to high"
            ))
        } else {
            // Settings the core would refuse at every step (the scene would stand still).
            self.settings.validate().err().map(|e| e.to_string())
        }
    }

    /// A scene with Earth's gravity, elastic spheres and a 1/60 s step.
    pub fn new(
        id: impl Into<String>,
        name: impl Into<String>,
        description: impl Into<String>,
    ) -> Self {
        Self {
            id: id.into(),
            name: name.into(),
            description: description.into(),
            settings: Settings::with_gravity(DVec3::new(0.0, -9.81, 0.0)),
            restitution: 1.0,
            dt: 1.0 / 60.0,
            view: None,
        }
    }

    /// With these core settings.
    pub fn settings(mut self, settings: Settings) -> Self {
        self.settings = settings;
        self
    }

    /// With this default restitution.
    pub fn restitution(mut self, restitution: f64) -> Self {
        self.restitution = restitution;
        self
    }

    /// With this fixed step.
    pub fn dt(mut self, dt: f64) -> Self {
        self.dt = dt;
        self
    }

    /// Framing this box too, from `low` to `high`, when the scene is entered.
    pub fn view(mut self, low: DVec3, high: DVec3) -> Self {
        self.view = Some((low, high));
        self
    }

    /// The entry for a scene file's contents, under `id`.
    pub fn from_desc(id: impl Into<String>, desc: &SceneDesc) -> Result<Self, SceneError> {
        let id = id.into();
        Ok(Self {
            name: if desc.name.is_empty() {
                id.clone()
            } else {
                desc.name.clone()
            },
            id,
            description: desc.description.clone(),
            settings: desc.settings()?,
            restitution: desc.restitution,
            dt: desc.dt.unwrap_or(1.0 / 60.0),
            view: desc.view()?,
        })
    }
}

/// Every registered scene, in the chooser's order, and the scene files that failed to load.
#[derive(Resource, Clone, Debug, Default)]
pub struct LabScenes {
    scenes: Vec<LabScene>,
    /// Scenes and scene files left out, each with the reason (a file's path first, then the
    /// line and column, the sphere or generator and its field, or the setting at fault).
    pub errors: Vec<String>,
    /// The ids of the scenes left out, each with its reason (as listed in `errors`).
    failed: Vec<(String, String)>,
}

impl LabScenes {
    /// The scenes in the chooser's order.
    pub fn iter(&self) -> impl Iterator<Item = &LabScene> {
        self.scenes.iter()
    }

    /// The scene `id`.
    pub fn get(&self, id: &str) -> Option<&LabScene> {
        self.scenes.iter().find(|s| s.id == id)
    }

    /// Where the scene `id` is in the chooser.
    pub fn position(&self, id: &str) -> Option<usize> {
        self.scenes.iter().position(|s| s.id == id)
    }

    /// How many scenes there are.
    pub fn len(&self) -> usize {
        self.scenes.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.scenes.is_empty()
    }

    /// The scene at `index` in the chooser's order.
    pub fn at(&self, index: usize) -> Option<&LabScene> {
        self.scenes.get(index)
    }

    /// Why the scene `id` (a scene file's stem, for a file) was left out, if it was.
    pub fn failure(&self, id: &str) -> Option<&str> {
        self.failed
            .iter()
            .find(|(failed, _)| failed == id)
            .map(|(_, error)| error.as_str())
    }

    /// Lists scene `id` as left out, for `error`.
    fn leave_out(&mut self, id: String, error: String) {
        warn!("{error}");
        self.errors.push(error.clone());
        self.failed.push((id, error));
    }
}

/// The order of the systems that run when a scene is entered.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LabSceneSystems {
    /// The physics restarts with the scene's settings.
    Reset,
    /// The scene's own systems spawn its entities.
    Build,
}

/// Entities spawned while a scene is shown that outlive it (a game's own camera, say): never
/// despawned on a scene change. Entities spawned while no scene is shown (at startup) outlive
/// scenes without it.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct LabPersistent;

/// Registering scenes on the [`App`].
pub trait LabAppExt {
    /// Adds a scene to the chooser: `build` (one or more systems) runs when it is entered and
    /// spawns its entities. Every top-level entity with a `Transform` (or a UI `Node`) spawned
    /// while a scene is shown, by `build` or later, belongs to that scene and is despawned when
    /// it is left, unless it is [`LabPersistent`]. A scene whose id is already registered, or
    /// whose step or restitution is invalid, is left out and listed in [`LabScenes::errors`].
    fn add_lab_scene<M>(
        &mut self,
        scene: LabScene,
        build: impl IntoScheduleConfigs<ScheduleSystem, M>,
    ) -> &mut Self;

    /// Adds the scene file at `path` (a `sphere-sim` scene in RON) under the file's stem. A
    /// file that cannot be read or parsed, or whose settings, generators or spheres are
    /// invalid (checked as `sphere-sim` checks them, by building its world), is listed in
    /// [`LabScenes::errors`] instead, with its path.
    fn add_lab_scene_file(&mut self, path: impl AsRef<Path>) -> &mut Self;
}

impl LabAppExt for App {
    fn add_lab_scene<M>(
        &mut self,
        scene: LabScene,
        build: impl IntoScheduleConfigs<ScheduleSystem, M>,
    ) -> &mut Self {
        let mut scenes = self.world_mut().get_resource_or_init::<LabScenes>();
        let problem = if scenes.get(&scene.id).is_some() {
            Some("a scene with this id is already registered".to_owned())
        } else {
            scene.problem()
        };
        if let Some(problem) = problem {
            let error = format!("scene {:?} left out: {problem}", scene.id);
            scenes.leave_out(scene.id.clone(), error);
            return self;
        }
        scenes.scenes.push(scene.clone());
        let schedule = OnEnter(ActiveScene::scene(scene.id.clone()));
        let reset = move |mut commands: Commands,
                          mut fixed: ResMut<Time<Fixed>>,
                          mut virtual_time: ResMut<Time<Virtual>>,
                          mut clock: ResMut<SpherePhysicsClock>| {
            commands.queue(
                ResetSpherePhysics::new(scene.settings.clone()).restitution(scene.restitution),
            );
            fixed.set_timestep_seconds(scene.dt);
            // Nothing of the last scene's time toward its next step is stepped in this one.
            let left = fixed.overstep();
            fixed.discard_overstep(left);
            // At most `MAX_FIXED_STEPS_PER_FRAME` steps a frame (a scene of short steps runs
            // slower than real time rather than freezing the window), and Bevy's default
            // catch-up of 0.25 s a frame for longer steps.
            virtual_time.set_max_delta(Duration::from_secs_f64(
                (MAX_FIXED_STEPS_PER_FRAME as f64 * scene.dt).min(0.25),
            ));
            // A scene (or a restart) starts running, with no single steps left over.
            *clock = SpherePhysicsClock::default();
        };
        self.configure_sets(
            schedule.clone(),
            (LabSceneSystems::Reset, LabSceneSystems::Build).chain(),
        )
        .add_systems(
            schedule,
            (
                reset.in_set(LabSceneSystems::Reset),
                build.in_set(LabSceneSystems::Build),
            ),
        )
    }

    fn add_lab_scene_file(&mut self, path: impl AsRef<Path>) -> &mut Self {
        let path = path.as_ref();
        let id = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let loaded = SceneDesc::load(path).and_then(|desc| {
            let scene = LabScene::from_desc(id.clone(), &desc)?;
            // Every sphere checked now, not one by one as each is spawned (and drawn where
            // it was spawned, never simulated).
            desc.build()?;
            desc.all_spheres().map(|spheres| (scene, spheres))
        });
        match loaded {
            Ok((scene, spheres)) => {
                // A step the lab does not run (valid for `sphere-sim`), named with the file's
                // path (until the sixty-fourth session, by the scene's id only).
                if let Some(problem) = scene.problem() {
                    self.world_mut()
                        .get_resource_or_init::<LabScenes>()
                        .leave_out(
                            id,
                            format!("scene file left out: {}: {problem}", path.display()),
                        );
                    return self;
                }
                let spheres = Arc::new(spheres);
                self.add_lab_scene(scene, move |mut commands: Commands| {
                    spawn_spheres(&mut commands, &spheres);
                })
            }
            Err(e) => {
                // Reading and parsing errors name the file already.
                let error = match e {
                    SceneError::Io { .. } | SceneError::Parse { .. } => e.to_string(),
                    _ => format!("{}: {e}", path.display()),
                };
                self.world_mut()
                    .get_resource_or_init::<LabScenes>()
                    .leave_out(id, format!("scene file left out: {error}"));
                self
            }
        }
    }
}

/// Spawns one entity per sphere of a scene file, named as in the file, joining the simulation
/// in the file's order ([`SphereOrder`]), so a restart repeats the first run exactly.
pub fn spawn_spheres(commands: &mut Commands, spheres: &[SphereSpec]) {
    for (i, s) in spheres.iter().enumerate() {
        let position = DVec3::from_array(s.position);
        let mut entity = commands.spawn((
            Name::new(s.name.clone().unwrap_or_else(|| format!("sphere {i}"))),
            SphereBody::new(s.radius),
            SphereOrder(i as u64),
            SpherePosition(position),
            Transform::from_translation(position.as_vec3()),
            SphereVelocity(DVec3::from_array(s.velocity)),
            Density(s.density),
            AppliedForce(DVec3::from_array(s.force)),
        ));
        if let Some(r) = s.restitution {
            entity.insert(Restitution(r));
        }
        if s.fixed {
            entity.insert(FixedSphere);
        }
        if s.never_sleeps {
            entity.insert(NeverSleeps);
        }
        // A fixed sphere's string is ignored by the core (nothing moves it), so it is neither
        // added nor drawn (until the sixty-fourth session it was drawn, and its anchor framed:
        // one past `f32`'s range put the camera at infinity).
        if let Some(t) = s.tether.as_ref().filter(|_| !s.fixed) {
            entity.insert(Tethered {
                anchor: t.anchor,
                length: t.length,
            });
        }
    }
}

/// Top-level entities that belong to no scene and are not persistent.
type Unscoped = (
    Without<ChildOf>,
    Without<LabPersistent>,
    Without<DespawnOnExit<ActiveScene>>,
);

/// Ties a new top-level entity with a `Transform` or a UI `Node` to the scene being shown (an
/// observer: it sees entities the scene spawns on entering and at any time after).
pub(crate) fn scope_new_entity<C: Component>(
    added: On<Add, C>,
    state: Option<Res<State<ActiveScene>>>,
    entities: Query<(), Unscoped>,
    mut commands: Commands,
) {
    let Some(state) = state else {
        return;
    };
    if *state.get() != ActiveScene::None && entities.contains(added.entity) {
        commands
            .entity(added.entity)
            .try_insert(DespawnOnExit(state.get().clone()));
    }
}

/// The scene files in a folder (`*.ron`), the tutorial's four scenes first, in its order, then
/// the rest by name.
pub fn scene_files(folder: &Path) -> Vec<PathBuf> {
    const FIRST: [&str; 4] = [
        "applied_forces",
        "density_collisions",
        "newtons_cradle",
        "sphere_shower",
    ];
    let mut files: Vec<PathBuf> = std::fs::read_dir(folder)
        .map(|dir| {
            dir.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "ron"))
                .collect()
        })
        .unwrap_or_default();
    files.sort_by_key(|p| {
        let stem = p.file_stem().map(|s| s.to_string_lossy().into_owned());
        let rank = stem
            .as_deref()
            .and_then(|s| FIRST.iter().position(|f| *f == s))
            .unwrap_or(FIRST.len());
        (rank, stem)
    });
    files
}
