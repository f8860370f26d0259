//! The sphere lab: the tutorial's app in Bevy. Scenes are Bevy [`States`]
//! ([`ActiveScene`]) listed in a registry ([`LabScenes`]) that games add to with one call
//! ([`LabAppExt::add_lab_scene`]); every scene file in `assets/scenes/` appears too.
//!
//! [`LabPlugin`] is the headless part: scenes, the keys ([`controls`]), and saving stamped
//! screenshots. With the `render` feature (on by default), [`render::LabRenderPlugin`] draws the
//! spheres, strings and frames, [`ui::LabUiPlugin`] shows the chooser and the panel in egui, and
//! [`lab_app`] builds the whole windowed app.
#![warn(missing_docs)]

pub mod controls;
pub mod scenes;
pub mod screenshot;
pub mod stamp;

#[cfg(feature = "render")]
pub mod camera;
#[cfg(feature = "render")]
pub mod render;
#[cfg(feature = "render")]
pub mod ui;

use std::path::PathBuf;

use bevy::input::InputPlugin;
use bevy::prelude::*;
use bevy::state::app::StatesPlugin;
use bevy_sphere_physics::SpherePhysicsPlugin;

pub use controls::{Autopilot, LabAction, LabUi};
pub use scenes::{
    ActiveScene, LabAppExt, LabPersistent, LabScene, LabSceneSystems, LabScenes,
    MAX_FIXED_STEPS_PER_FRAME,
};
pub use screenshot::{
    FrameCaptured, RenderReady, ScreenshotRequested, ScreenshotSettings, ScreenshotStatus,
};

/// The lab without a window: scene states and registry, keys and actions, screenshot saving.
/// Adds `StatesPlugin`, `InputPlugin` and [`SpherePhysicsPlugin`] if the app has none yet: a
/// game's own `SpherePhysicsPlugin` goes in before this one (after it, Bevy refuses it as
/// added twice). Each scene then brings its own physics settings, gravity, method,
/// integrator, default restitution and step (see [`LabScene`]), replacing the plugin's
/// whenever a scene is entered.
#[derive(Clone, Debug)]
pub struct LabPlugin {
    /// The scene to open at start; `None` opens the chooser.
    pub start: Option<String>,
    /// The folder whose `*.ron` scene files are added to the chooser; `None` adds none.
    pub scene_folder: Option<PathBuf>,
    /// Where screenshots go.
    pub screenshots: ScreenshotSettings,
    /// Unattended screenshot and exit.
    pub autopilot: Autopilot,
}

impl Default for LabPlugin {
    fn default() -> Self {
        Self {
            start: None,
            scene_folder: Some(default_scene_folder()),
            screenshots: ScreenshotSettings::default(),
            autopilot: Autopilot::default(),
        }
    }
}

/// `assets/scenes` under this package (found through `CARGO_MANIFEST_DIR` at run time under
/// `cargo run` of this package, else at build time), or relative to the working directory.
pub fn default_scene_folder() -> PathBuf {
    scene_folder_given(std::env::var_os("CARGO_MANIFEST_DIR").map(PathBuf::from))
}

/// The folder [`default_scene_folder`] picks when `CARGO_MANIFEST_DIR` is `manifest_dir` at
/// run time: under it only if it is this package's (under `cargo run` of a game that uses
/// the lab it is the game's, whose own `assets/scenes`, Bevy's place for its scenes, was read
/// as the lab's until the fifty-seventh session).
pub fn scene_folder_given(manifest_dir: Option<PathBuf>) -> PathBuf {
    let under = |root: PathBuf| root.join("assets").join("scenes");
    let this_package = |dir: &PathBuf| {
        std::fs::read_to_string(dir.join("Cargo.toml")).is_ok_and(|manifest| {
            manifest.contains(&format!("name = \"{}\"", env!("CARGO_PKG_NAME")))
        })
    };
    manifest_dir
        .filter(this_package)
        .map(under)
        .filter(|p| p.is_dir())
        .or_else(|| Some(under(PathBuf::from(env!("CARGO_MANIFEST_DIR")))).filter(|p| p.is_dir()))
        .unwrap_or_else(|| under(PathBuf::from(".")))
}

impl LabPlugin {
    /// Opens straight into the scene `id`.
    pub fn start_with(mut self, id: impl Into<String>) -> Self {
        self.start = Some(id.into());
        self
    }

    /// Reads the command line: `--scene ID`, `--screenshot-dir DIR`, `--screenshot-at SECONDS`
    /// and `--exit` (quit after that screenshot). Returns an error naming a bad argument.
    pub fn with_args(mut self, args: impl IntoIterator<Item = String>) -> Result<Self, String> {
        let mut args = args.into_iter();
        while let Some(arg) = args.next() {
            let mut value = |name: &str| args.next().ok_or(format!("{name} needs a value"));
            match arg.as_str() {
                "--scene" => self.start = Some(value("--scene")?),
                "--screenshot-dir" => self.screenshots.folder = value("--screenshot-dir")?.into(),
                "--screenshot-at" => {
                    let v = value("--screenshot-at")?;
                    let t: f64 = v
                        .parse()
                        .ok()
                        .filter(|t: &f64| t.is_finite() && *t >= 0.0)
                        .ok_or(format!("--screenshot-at: {v:?} is not a time in seconds"))?;
                    self.autopilot.screenshot_at = Some(t);
                }
                "--exit" => self.autopilot.exit_after_screenshot = true,
                other => {
                    return Err(format!(
                        "unknown argument {other:?} (expected --scene ID, --screenshot-dir DIR, \
                         --screenshot-at SECONDS, --exit)"
                    ));
                }
            }
        }
        if self.autopilot.exit_after_screenshot && self.autopilot.screenshot_at.is_none() {
            return Err("--exit quits after the --screenshot-at screenshot: give both".into());
        }
        Ok(self)
    }
}

/// The order of the lab's per-frame systems in `Update`.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LabSystems {
    /// Keys and buttons become [`LabAction`]s.
    Input,
    /// The keyboard's part of `Input` (skipped while egui takes text input, with the
    /// `render` feature's UI).
    Keys,
    /// Actions are carried out.
    Act,
    /// Captured frames are handed to the I/O task pool to be saved, and the outcomes of
    /// those saved since are recorded.
    Save,
}

impl Plugin for LabPlugin {
    fn build(&self, app: &mut App) {
        if !app.is_plugin_added::<StatesPlugin>() {
            app.add_plugins(StatesPlugin);
        }
        if !app.is_plugin_added::<InputPlugin>() {
            app.add_plugins(InputPlugin);
        }
        if !app.is_plugin_added::<SpherePhysicsPlugin>() {
            app.add_plugins(SpherePhysicsPlugin::default());
        }
        app.init_resource::<LabScenes>()
            .insert_resource(self.screenshots.clone())
            .insert_resource(self.autopilot.clone())
            .init_resource::<ScreenshotStatus>()
            .init_resource::<screenshot::SavingScreenshots>()
            .init_resource::<scenes::FixedStepsThisFrame>()
            .add_systems(First, scenes::start_frame_steps)
            .add_systems(FixedLast, scenes::end_frame_steps_at_most)
            .add_message::<LabAction>()
            .add_message::<ScreenshotRequested>()
            .add_message::<FrameCaptured>()
            .init_state::<ActiveScene>()
            .add_observer(scenes::scope_new_entity::<Transform>)
            .configure_sets(
                Update,
                (LabSystems::Input, LabSystems::Act, LabSystems::Save).chain(),
            )
            .configure_sets(Update, LabSystems::Keys.in_set(LabSystems::Input))
            .add_systems(
                Update,
                (
                    controls::keyboard_actions.in_set(LabSystems::Keys),
                    controls::autopilot.in_set(LabSystems::Input),
                    controls::apply_actions.in_set(LabSystems::Act),
                    (
                        screenshot::record_saved_screenshots,
                        screenshot::save_captured_frames,
                    )
                        .chain()
                        .in_set(LabSystems::Save),
                ),
            );
        #[cfg(feature = "render")]
        app.add_observer(scenes::scope_new_entity::<Node>);
        let mut folder_note = None;
        if let Some(folder) = &self.scene_folder {
            let files = scenes::scene_files(folder);
            if files.is_empty() {
                // Said in the chooser if no scene is registered at all (see
                // `open_start_scene`), which would otherwise be empty with no word why.
                let why = match std::fs::read_dir(folder) {
                    Err(e) => e.to_string(),
                    Ok(_) => "no scene files (*.ron) there".to_owned(),
                };
                folder_note = Some(format!("scene folder {}: {why}", folder.display()));
            }
            for file in files {
                app.add_lab_scene_file(file);
            }
        }
        app.insert_resource(LabUi {
            chooser_open: true,
            selected: 0,
        })
        .insert_resource(StartScene(self.start.clone()))
        .insert_resource(SceneFolderNote(folder_note))
        .add_systems(Startup, open_start_scene);
    }
}

/// The scene to open at start.
#[derive(Resource)]
struct StartScene(Option<String>);

/// Why the scene folder gave no scenes, if it gave none: listed among the errors at start if
/// no scene was registered at all (a game whose own scenes are there, run away from this
/// repository's folder, is not told).
#[derive(Resource)]
struct SceneFolderNote(Option<String>);

/// Opens the start scene, once every plugin has registered its scenes; the chooser stays open
/// if there is none or it is unknown.
fn open_start_scene(
    start: Res<StartScene>,
    mut scenes: ResMut<LabScenes>,
    mut ui: ResMut<LabUi>,
    mut next: ResMut<NextState<ActiveScene>>,
    pilot: Res<Autopilot>,
    mut exit: MessageWriter<AppExit>,
    mut folder_note: ResMut<SceneFolderNote>,
) {
    if let Some(note) = folder_note.0.take()
        && scenes.is_empty()
    {
        warn!("{note}");
        scenes.errors.push(note);
    }
    let Some(id) = &start.0 else {
        return;
    };
    match scenes.position(id) {
        Some(i) => {
            next.set(ActiveScene::scene(id.clone()));
            ui.selected = i;
            ui.chooser_open = false;
        }
        None => {
            // A scene by that name that failed to load (its file, or its settings) says why;
            // else list the ids there are.
            let error = match scenes.failure(id) {
                Some(failed) => format!("--scene {id:?}: {failed}"),
                None => {
                    let known: Vec<&str> = scenes.iter().map(|s| s.id.as_str()).collect();
                    let known = if known.is_empty() {
                        "none: there are no scenes".to_owned()
                    } else {
                        known.join(", ")
                    };
                    format!(
                        "--scene {id:?}: no such scene (a scene file's name without .ron, one \
                         of: {known})"
                    )
                }
            };
            if pilot.screenshot_at.is_some() && pilot.exit_after_screenshot {
                // Unattended: a screenshot of the chooser would pass for the scene's. (Run by
                // hand, the screenshot waits for the scene chosen; until the sixty-first session
                // `--screenshot-at` without `--exit` quit here too.)
                eprintln!("{error}");
                exit.write(AppExit::from_code(2));
            } else {
                warn!("{error}: opening the chooser");
            }
            scenes.errors.push(error);
        }
    }
}

/// The whole windowed lab for a program's `main`: [`lab_window_app`] with [`LabPlugin`]
/// configured from the process's command line (see [`LabPlugin::with_args`]). `start` opens
/// straight into that scene; `--scene` overrides it.
///
/// # Exits
/// On an argument it does not know (or one that is not UTF-8) it prints the error and ends
/// the process with exit code 2: meant for `main` and the examples. A game or test with its
/// own command line builds its [`LabPlugin`] and calls [`lab_window_app`].
#[cfg(feature = "render")]
pub fn lab_app(start: Option<&str>) -> App {
    let lab = LabPlugin {
        start: start.map(str::to_owned),
        ..default()
    };
    let args: Result<Vec<String>, _> = std::env::args_os()
        .skip(1)
        .map(|a| {
            a.into_string()
                .map_err(|a| format!("argument {a:?} is not UTF-8"))
        })
        .collect();
    match args.and_then(|args| lab.with_args(args)) {
        Ok(lab) => lab_window_app(lab),
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    }
}

/// The whole windowed lab: Bevy's default plugins (window titled "Sphere lab"), egui, the
/// renderer, the chooser and panel, and `lab`. Reads no command line.
#[cfg(feature = "render")]
pub fn lab_window_app(lab: LabPlugin) -> App {
    let mut app = App::new();
    app.add_plugins(DefaultPlugins.set(WindowPlugin {
        primary_window: Some(Window {
            title: "Sphere lab".into(),
            resolution: (1280, 720).into(),
            ..default()
        }),
        ..default()
    }))
    .add_plugins(bevy_egui::EguiPlugin::default())
    .add_plugins((
        lab,
        render::LabRenderPlugin,
        camera::OrbitCameraPlugin,
        ui::LabUiPlugin,
    ));
    app
}
