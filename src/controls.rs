//! What the user can do, from the keyboard or the panel's buttons: the same [`LabAction`]s.
//!
//! | Key | Action |
//! |---|---|
//! | Enter | open the scene chooser; in the chooser, load the selected scene |
//! | Up / Down | in the chooser, select the previous / next scene |
//! | Escape | close the chooser (when a scene is loaded) |
//! | P | pause / resume |
//! | N | one step, while paused |
//! | R | restart the scene |
//! | Space | save a screenshot with the simulated time written on it |

use bevy::app::AppExit;
use bevy::prelude::*;
use bevy_sphere_physics::prelude::*;

use crate::scenes::{ActiveScene, LabScenes};
use crate::screenshot::{RenderReady, ScreenshotRequested, ScreenshotStatus};

/// Something the user asked for.
#[derive(Message, Clone, Debug, PartialEq, Eq)]
pub enum LabAction {
    /// Show the scene chooser.
    OpenChooser,
    /// Hide the scene chooser (ignored while no scene is loaded).
    CloseChooser,
    /// Select the chooser's next (`+1`) or previous (`-1`) scene.
    Select(i32),
    /// Load the scene the chooser has selected.
    LoadSelected,
    /// Load the scene with this id.
    Load(String),
    /// Start the current scene again.
    Restart,
    /// Pause or resume the physics.
    TogglePause,
    /// Take one step while paused.
    StepOnce,
    /// Save a screenshot.
    Screenshot,
}

/// The chooser's state.
#[derive(Resource, Clone, Debug, Default, PartialEq, Eq)]
pub struct LabUi {
    /// Whether the scene chooser is shown.
    pub chooser_open: bool,
    /// The chooser's selected scene (index into [`LabScenes`]).
    pub selected: usize,
}

/// Turns key presses into actions.
pub(crate) fn keyboard_actions(
    keys: Res<ButtonInput<KeyCode>>,
    ui: Res<LabUi>,
    mut actions: MessageWriter<LabAction>,
) {
    let pressed = |k| keys.just_pressed(k);
    if pressed(KeyCode::Enter) || pressed(KeyCode::NumpadEnter) {
        actions.write(if ui.chooser_open {
            LabAction::LoadSelected
        } else {
            LabAction::OpenChooser
        });
    }
    if ui.chooser_open {
        if pressed(KeyCode::ArrowDown) {
            actions.write(LabAction::Select(1));
        }
        if pressed(KeyCode::ArrowUp) {
            actions.write(LabAction::Select(-1));
        }
        if pressed(KeyCode::Escape) {
            actions.write(LabAction::CloseChooser);
        }
    }
    // The scene's keys wait while the chooser covers it (its buttons still work).
    if ui.chooser_open {
        if pressed(KeyCode::Space) {
            actions.write(LabAction::Screenshot);
        }
        return;
    }
    if pressed(KeyCode::KeyP) {
        actions.write(LabAction::TogglePause);
    }
    if pressed(KeyCode::KeyN) {
        actions.write(LabAction::StepOnce);
    }
    if pressed(KeyCode::KeyR) {
        actions.write(LabAction::Restart);
    }
    if pressed(KeyCode::Space) {
        actions.write(LabAction::Screenshot);
    }
}

/// Carries out the actions.
#[allow(clippy::too_many_arguments)]
pub(crate) fn apply_actions(
    mut actions: MessageReader<LabAction>,
    mut ui: ResMut<LabUi>,
    scenes: Res<LabScenes>,
    state: Res<State<ActiveScene>>,
    mut next: ResMut<NextState<ActiveScene>>,
    mut clock: ResMut<SpherePhysicsClock>,
    shown: Res<SphereShownTime>,
    mut shots: MessageWriter<ScreenshotRequested>,
) {
    for action in actions.read() {
        match action {
            LabAction::OpenChooser => {
                ui.chooser_open = true;
                if let Some(i) = state.get().id().and_then(|id| scenes.position(id)) {
                    ui.selected = i;
                }
            }
            LabAction::CloseChooser => {
                if *state.get() != ActiveScene::None {
                    ui.chooser_open = false;
                }
            }
            LabAction::Select(step) => {
                if !scenes.is_empty() {
                    let n = scenes.len() as i64;
                    ui.selected = (ui.selected as i64 + *step as i64).rem_euclid(n) as usize;
                }
            }
            LabAction::LoadSelected => {
                if let Some(scene) = scenes.at(ui.selected) {
                    next.set(ActiveScene::scene(scene.id.clone()));
                    ui.chooser_open = false;
                }
            }
            LabAction::Load(id) => match scenes.position(id) {
                Some(i) => {
                    next.set(ActiveScene::scene(id.clone()));
                    ui.selected = i;
                    ui.chooser_open = false;
                }
                None => warn!("no scene with id {id:?}"),
            },
            LabAction::Restart => {
                if *state.get() != ActiveScene::None {
                    next.set(state.get().clone());
                }
            }
            LabAction::TogglePause => clock.toggle(),
            LabAction::StepOnce => {
                if clock.paused {
                    clock.step_once();
                }
            }
            LabAction::Screenshot => {
                // The time the spheres are drawn at (interpolated between the last two steps),
                // not the last step's.
                shots.write(ScreenshotRequested { time: shown.0 });
            }
        }
    }
}

/// Unattended runs (`--screenshot-at`, `--exit`): take a screenshot once the simulated time
/// reaches a mark, and quit once it is saved or has failed, printing `scene ID` and
/// `screenshot PATH` on standard output (or the error on standard error).
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct Autopilot {
    /// Take a screenshot once the simulated time of the scene reaches this many seconds (with
    /// no scene loaded: at once if `exit_after_screenshot`, else once one is).
    pub screenshot_at: Option<f64>,
    /// Quit after that screenshot was saved (exit code 0) or failed (exit code 1).
    pub exit_after_screenshot: bool,
    /// Screenshots saved and failed when the autopilot asked for its own; `None` before.
    requested: Option<u32>,
}

impl Autopilot {
    /// Screenshot at `time`, then quit if `exit`.
    pub fn new(screenshot_at: Option<f64>, exit_after_screenshot: bool) -> Self {
        Self {
            screenshot_at,
            exit_after_screenshot,
            requested: None,
        }
    }
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn autopilot(
    mut pilot: ResMut<Autopilot>,
    state: Res<State<ActiveScene>>,
    shown: Res<SphereShownTime>,
    status: Res<ScreenshotStatus>,
    mut actions: MessageWriter<LabAction>,
    mut exit: MessageWriter<AppExit>,
    ready: Option<Res<RenderReady>>,
    mut frames: Local<u32>,
) {
    let Some(at) = pilot.screenshot_at else {
        return;
    };
    *frames += 1;
    let outcomes = status.saved + status.failed;
    let Some(before) = pilot.requested else {
        // A few frames first, so the window and the panels have been drawn. Without a scene,
        // an unattended run (`--exit`) captures the chooser at once (its time stays 0); one
        // run by hand waits for the scene the user chooses (until the sixty-first session it
        // captured the chooser, and took no picture in the scene chosen after).
        let ready = ready.is_none_or(|r| r.settled());
        let due = if *state.get() == ActiveScene::None {
            pilot.exit_after_screenshot
        } else {
            shown.0 >= at
        };
        if ready && *frames > 3 && due {
            pilot.requested = Some(outcomes);
            actions.write(LabAction::Screenshot);
        }
        return;
    };
    // Quit on this screenshot's outcome, not on an earlier one.
    if pilot.exit_after_screenshot && outcomes > before {
        println!("scene {}", state.get().id().unwrap_or(""));
        match &status.last {
            Some(Ok(path)) => {
                println!("screenshot {}", path.display());
                exit.write(AppExit::Success);
            }
            Some(Err(e)) => {
                eprintln!("screenshot failed: {e}");
                exit.write(AppExit::error());
            }
            None => {}
        }
    }
}
