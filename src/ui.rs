//! The egui windows: the scene chooser (name, description, OK) and the panel (simulated time,
//! collisions, energy, momentum, step time; pause, step, restart, scenes, screenshot; the last
//! screenshot's outcome, errors in red).

use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};
use bevy_sphere_physics::{
    SpherePhysicsClock, SpherePhysicsDiagnostics, SpherePhysicsWorld, SphereShownTime,
};

use crate::controls::{LabAction, LabUi};
use crate::scenes::{ActiveScene, LabScenes};
use crate::screenshot::ScreenshotStatus;

/// Shows the chooser and the panel.
pub struct LabUiPlugin;

impl Plugin for LabUiPlugin {
    fn build(&self, app: &mut App) {
        // Keys typed into an egui text field (a game's own UI) are not the lab's.
        app.add_systems(EguiPrimaryContextPass, (panel, chooser).chain())
            .configure_sets(
                Update,
                crate::LabSystems::Keys
                    .run_if(not(bevy_egui::input::egui_wants_any_keyboard_input)),
            );
    }
}

fn chooser(
    mut contexts: EguiContexts,
    mut ui_state: ResMut<LabUi>,
    scenes: Res<LabScenes>,
    state: Res<State<ActiveScene>>,
    mut actions: MessageWriter<LabAction>,
    mut shown_selection: Local<Option<usize>>,
) -> Result {
    if !ui_state.chooser_open {
        *shown_selection = None;
        return Ok(());
    }
    // Up and Down move the selection: the list scrolls to keep it in view (once per change,
    // so the wheel still scrolls freely).
    let follow = *shown_selection != Some(ui_state.selected);
    *shown_selection = Some(ui_state.selected);
    let ctx = contexts.ctx_mut()?;
    egui::Window::new("Choose a scene")
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
        .default_width(460.0)
        .show(ctx, |ui| {
            egui::ScrollArea::vertical()
                .max_height(260.0)
                .show(ui, |ui| {
                    for (i, scene) in scenes.iter().enumerate() {
                        let selected = ui_state.selected == i;
                        let label = ui.selectable_label(selected, &scene.name);
                        if selected && follow {
                            label.scroll_to_me(None);
                        }
                        if label.clicked() {
                            ui_state.selected = i;
                        }
                        if label.double_clicked() {
                            actions.write(LabAction::LoadSelected);
                        }
                    }
                });
            ui.separator();
            if let Some(scene) = scenes.at(ui_state.selected) {
                ui.strong(&scene.name);
                ui.label(&scene.description);
            }
            for error in &scenes.errors {
                ui.colored_label(egui::Color32::LIGHT_RED, error);
            }
            ui.separator();
            ui.horizontal(|ui| {
                if ui.button("OK").clicked() {
                    actions.write(LabAction::LoadSelected);
                }
                if *state.get() != ActiveScene::None && ui.button("Cancel").clicked() {
                    actions.write(LabAction::CloseChooser);
                }
                ui.weak("Up/Down select, Enter loads");
            });
        });
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn panel(
    mut contexts: EguiContexts,
    scenes: Res<LabScenes>,
    state: Res<State<ActiveScene>>,
    physics: Res<SpherePhysicsWorld>,
    diagnostics: Res<SpherePhysicsDiagnostics>,
    shown: Res<SphereShownTime>,
    clock: Res<SpherePhysicsClock>,
    status: Res<ScreenshotStatus>,
    mut actions: MessageWriter<LabAction>,
) -> Result {
    let ctx = contexts.ctx_mut()?;
    let name = state
        .get()
        .id()
        .and_then(|id| scenes.get(id))
        .map_or("no scene", |s| s.name.as_str());
    let world = &physics.world;
    egui::Window::new("Sphere lab")
        .anchor(egui::Align2::LEFT_TOP, [8.0, 8.0])
        .resizable(false)
        .show(ctx, |ui| {
            ui.strong(name);
            egui::Grid::new("stats").num_columns(2).show(ui, |ui| {
                let mut row = |label: &str, value: String| {
                    ui.label(label);
                    ui.monospace(value);
                    ui.end_row();
                };
                row(
                    "time",
                    format!(
                        "{:.3} s{}",
                        shown.0,
                        if clock.paused { " (paused)" } else { "" }
                    ),
                );
                // With sleeping on (the ball pit's), how many are asleep.
                let asleep = if world.settings().sleep.is_some() {
                    format!(" ({} asleep)", diagnostics.last.asleep)
                } else {
                    String::new()
                };
                row("spheres", format!("{}{asleep}", world.len()));
                row(
                    "collisions",
                    format!(
                        "{} ({} last step)",
                        diagnostics.collisions, diagnostics.last.collisions
                    ),
                );
                let kinetic = world.kinetic_energy() + 0.0;
                let potential = world.potential_energy() + 0.0;
                row(
                    "energy",
                    format!(
                        "{:.6} J (kinetic {kinetic:.4}, potential {potential:.4})",
                        kinetic + potential
                    ),
                );
                let p = world.momentum();
                row(
                    "momentum",
                    format!("({:.4}, {:.4}, {:.4}) kg m/s", p.x, p.y, p.z),
                );
                row(
                    "step time",
                    format!("{:.3} ms", diagnostics.step_seconds * 1e3),
                );
            });
            ui.horizontal(|ui| {
                let pause = if clock.paused {
                    "Resume (P)"
                } else {
                    "Pause (P)"
                };
                if ui.button(pause).clicked() {
                    actions.write(LabAction::TogglePause);
                }
                if ui
                    .add_enabled(clock.paused, egui::Button::new("Step (N)"))
                    .clicked()
                {
                    actions.write(LabAction::StepOnce);
                }
                if ui.button("Restart (R)").clicked() {
                    actions.write(LabAction::Restart);
                }
            });
            ui.horizontal(|ui| {
                if ui.button("Scenes (Enter)").clicked() {
                    actions.write(LabAction::OpenChooser);
                }
                if ui.button("Screenshot (Space)").clicked() {
                    actions.write(LabAction::Screenshot);
                }
            });
            if status.saving > 0 {
                ui.weak("saving screenshot…");
            }
            match &status.last {
                Some(Ok(path)) => {
                    ui.colored_label(
                        egui::Color32::LIGHT_GREEN,
                        format!("saved {}", path.display()),
                    );
                }
                Some(Err(e)) => {
                    ui.colored_label(
                        egui::Color32::from_rgb(255, 90, 90),
                        format!("screenshot failed: {e}"),
                    );
                }
                None => {}
            }
            ui.weak("orbit: drag or arrows · zoom: wheel or -/=");
        });
    Ok(())
}
