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
        // Keys typed into an egui text field (a game's own UI) are not the lab's. (Nothing in
        // the lab's own windows takes the keyboard: see `click_only`.)
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
    let loaded = *state.get() != ActiveScene::None;
    chooser_window(
        contexts.ctx_mut()?,
        &mut ui_state,
        &scenes,
        loaded,
        follow,
        &mut |action| {
            actions.write(action);
        },
    );
    Ok(())
}

/// The widgets of the lab's windows take clicks but never the keyboard's focus: egui gives
/// Tab's focus to the first widget that can take it, and while one has it every key is egui's
/// (`egui_wants_any_keyboard_input`), so a Tab, pressed by chance, held the lab's keys until a
/// click elsewhere or Escape, and Space then pressed the focused button instead of saving a
/// screenshot. Each button has its key already. A game's own text fields still take the
/// keyboard.
fn click_only(button: egui::Button<'_>) -> egui::Button<'_> {
    button.sense(egui::Sense::CLICK)
}

/// Whether the lab's button `text` (shown greyed out unless `enabled`) was clicked.
fn clicked(ui: &mut egui::Ui, enabled: bool, text: &str) -> bool {
    ui.add_enabled(enabled, click_only(egui::Button::new(text)))
        .clicked()
}

/// The scene chooser: the scenes (`follow`: scroll to the selected one), the selected one's
/// description, the registry's errors, OK and (with a scene `loaded`) Cancel.
fn chooser_window(
    ctx: &egui::Context,
    ui_state: &mut LabUi,
    scenes: &LabScenes,
    loaded: bool,
    follow: bool,
    actions: &mut impl FnMut(LabAction),
) {
    egui::Window::new("Choose a scene")
        .id(egui::Id::new(CHOOSER))
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
                        let label =
                            ui.add(click_only(egui::Button::selectable(selected, &scene.name)));
                        if selected && follow {
                            label.scroll_to_me(None);
                        }
                        if label.clicked() {
                            ui_state.selected = i;
                        }
                        if label.double_clicked() {
                            actions(LabAction::LoadSelected);
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
                if clicked(ui, true, "OK") {
                    actions(LabAction::LoadSelected);
                }
                if loaded && clicked(ui, true, "Cancel") {
                    actions(LabAction::CloseChooser);
                }
                ui.weak("Up/Down select, Enter loads");
            });
        });
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
    let name = state
        .get()
        .id()
        .and_then(|id| scenes.get(id))
        .map_or("no scene", |s| s.name.as_str());
    let view = PanelView {
        name,
        world: &physics.world,
        diagnostics: &diagnostics,
        shown: shown.0,
        paused: clock.paused,
        status: &status,
    };
    panel_window(contexts.ctx_mut()?, &view, &mut |action| {
        actions.write(action);
    });
    Ok(())
}

/// The panel's egui id.
const PANEL: &str = "sphere_lab panel";

/// The chooser's egui id.
const CHOOSER: &str = "sphere_lab chooser";

/// What the panel shows.
struct PanelView<'a> {
    name: &'a str,
    world: &'a bevy_sphere_physics::sphere_physics::World,
    diagnostics: &'a SpherePhysicsDiagnostics,
    /// The simulated time shown.
    shown: f64,
    paused: bool,
    status: &'a ScreenshotStatus,
}

/// The panel: the scene's name and figures, its buttons and the last screenshot's outcome.
/// Not collapsible: its title bar's triangle would take Tab's focus (see `click_only`).
fn panel_window(ctx: &egui::Context, view: &PanelView<'_>, actions: &mut impl FnMut(LabAction)) {
    let (world, diagnostics, status) = (view.world, view.diagnostics, view.status);
    egui::Window::new("Sphere lab")
        .id(egui::Id::new(PANEL))
        .anchor(egui::Align2::LEFT_TOP, [8.0, 8.0])
        .resizable(false)
        .collapsible(false)
        .show(ctx, |ui| {
            ui.strong(view.name);
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
                        view.shown,
                        if view.paused { " (paused)" } else { "" }
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
                let pause = if view.paused {
                    "Resume (P)"
                } else {
                    "Pause (P)"
                };
                if clicked(ui, true, pause) {
                    actions(LabAction::TogglePause);
                }
                if clicked(ui, view.paused, "Step (N)") {
                    actions(LabAction::StepOnce);
                }
                if clicked(ui, true, "Restart (R)") {
                    actions(LabAction::Restart);
                }
            });
            ui.horizontal(|ui| {
                if clicked(ui, true, "Scenes (Enter)") {
                    actions(LabAction::OpenChooser);
                }
                if clicked(ui, true, "Screenshot (Space)") {
                    actions(LabAction::Screenshot);
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
}

#[cfg(test)]
mod tests {
    use bevy_sphere_physics::sphere_physics::{Settings, World as PhysicsWorld};
    use egui::{
        Event, Id, Key, LayerId, Modifiers, Order, PointerButton, Pos2, RawInput, Rect, Sense, vec2,
    };

    use super::*;
    use crate::scenes::{LabAppExt, LabScene};

    /// The lab's two windows in a bare egui context, as the lab shows them (the chooser open),
    /// one pass at a time.
    struct Lab {
        ctx: egui::Context,
        /// Whether a scene is loaded (the chooser offers Cancel).
        loaded: bool,
        /// Whether the physics is paused (the panel's Step is enabled).
        paused: bool,
        /// The next pass's time, a frame of 60 Hz after the last (from 10 s: egui takes the
        /// first clicks within 0.6 s of its start for the third of three).
        time: f64,
        ui_state: LabUi,
        scenes: LabScenes,
        world: PhysicsWorld,
        status: ScreenshotStatus,
        diagnostics: SpherePhysicsDiagnostics,
    }

    impl Lab {
        fn new() -> Self {
            let mut app = App::new();
            app.add_lab_scene(LabScene::new("one", "One", "The first."), || {})
                .add_lab_scene(LabScene::new("two", "Two", "The second."), || {});
            Lab {
                ctx: egui::Context::default(),
                loaded: true,
                paused: true,
                time: 10.0,
                ui_state: LabUi {
                    chooser_open: true,
                    selected: 0,
                },
                scenes: app.world().resource::<LabScenes>().clone(),
                world: PhysicsWorld::new(Settings::default()),
                status: ScreenshotStatus::default(),
                diagnostics: SpherePhysicsDiagnostics::default(),
            }
        }

        /// One pass with `events`: the actions the windows asked for.
        fn pass(&mut self, events: Vec<Event>) -> Vec<LabAction> {
            self.time += 1.0 / 60.0;
            let input = RawInput {
                events,
                time: Some(self.time),
                screen_rect: Some(Rect::from_min_size(Pos2::ZERO, vec2(1280.0, 720.0))),
                ..Default::default()
            };
            let mut actions = Vec::new();
            let view = PanelView {
                name: "One",
                world: &self.world,
                diagnostics: &self.diagnostics,
                shown: 0.0,
                paused: self.paused,
                status: &self.status,
            };
            let (ui_state, scenes, loaded) = (&mut self.ui_state, &self.scenes, self.loaded);
            self.ctx
                .run_ui(input, |ui| {
                    panel_window(ui.ctx(), &view, &mut |a| actions.push(a));
                    chooser_window(ui.ctx(), ui_state, scenes, loaded, false, &mut |a| {
                        actions.push(a)
                    });
                })
                .drop_without_applying_deltas();
            actions
        }

        /// The buttons of the window with id `title` that the last pass laid out, in order:
        /// its widgets that take clicks (not drags, as text does for its selection), after the
        /// window's own.
        fn buttons(&self, title: &str) -> Vec<Rect> {
            let layer = LayerId::new(Order::Middle, Id::new(title));
            self.ctx.viewport(|v| {
                v.prev_pass
                    .widgets
                    .get_layer(layer)
                    .filter(|w| w.sense == Sense::CLICK)
                    // The window's own area, which takes clicks to come to the front.
                    .skip(1)
                    .map(|w| w.interact_rect)
                    .collect()
            })
        }
    }

    fn key(key: Key, pressed: bool) -> Event {
        Event::Key {
            key,
            physical_key: None,
            pressed,
            repeat: false,
            modifiers: Modifiers::NONE,
        }
    }

    fn click(at: Pos2, pressed: bool) -> Vec<Event> {
        vec![
            Event::PointerMoved(at),
            Event::PointerButton {
                pos: at,
                button: PointerButton::Primary,
                pressed,
                modifiers: Modifiers::NONE,
            },
        ]
    }

    /// Tab gives no widget of the lab's the keyboard (which would hold the lab's keys, see
    /// `click_only`), and Space or Enter then press nothing.
    #[test]
    fn tab_leaves_the_keys_to_the_lab() {
        let mut lab = Lab::new();
        assert!(lab.pass(vec![]).is_empty());
        for pressed in [Key::Tab, Key::Tab, Key::Space, Key::Enter, Key::Tab] {
            let actions = lab.pass(vec![key(pressed, true), key(pressed, false)]);
            assert_eq!(actions, [], "{pressed:?} pressed a button");
            assert_eq!(lab.ctx.memory(|m| m.focused()), None, "after {pressed:?}");
            assert!(!lab.ctx.egui_wants_keyboard_input(), "after {pressed:?}");
        }
    }

    /// The buttons still take clicks: each of the panel's five and the chooser's two scenes,
    /// OK and Cancel, in the order they are laid out.
    #[test]
    fn buttons_take_clicks() {
        let mut lab = Lab::new();
        lab.pass(vec![]);
        let panel = [
            LabAction::TogglePause,
            LabAction::StepOnce,
            LabAction::Restart,
            LabAction::OpenChooser,
            LabAction::Screenshot,
        ]
        .map(|a| vec![a]);
        let chooser = [
            vec![],
            vec![],
            vec![LabAction::LoadSelected],
            vec![LabAction::CloseChooser],
        ];
        for (title, expected) in [(PANEL, &panel[..]), (CHOOSER, &chooser[..])] {
            let buttons = lab.buttons(title);
            assert_eq!(buttons.len(), expected.len(), "{title}: {buttons:?}");
            for (rect, expected) in buttons.iter().zip(expected) {
                lab.pass(vec![Event::PointerMoved(rect.center())]);
                lab.pass(click(rect.center(), true));
                let actions = lab.pass(click(rect.center(), false));
                assert_eq!(&actions, expected, "{title}: clicked at {rect:?}");
                lab.pass(vec![Event::PointerGone]);
            }
        }
        // The second scene's label, clicked, selected it.
        assert_eq!(lab.ui_state.selected, 1);
    }

    /// A scene's label double-clicked loads it; the panel's Step does nothing while the
    /// physics runs; the chooser offers no Cancel before a scene is loaded.
    #[test]
    fn double_click_loads_step_waits_and_cancel_needs_a_scene() {
        let mut lab = Lab::new();
        // (A window is laid out where it stays from its second pass.)
        lab.pass(vec![]);
        lab.pass(vec![]);
        let second = lab.buttons(CHOOSER)[1].center();
        lab.pass(vec![Event::PointerMoved(second)]);
        let mut actions = Vec::new();
        for pressed in [true, false, true, false] {
            actions.extend(lab.pass(click(second, pressed)));
        }
        assert_eq!(actions, [LabAction::LoadSelected]);
        assert_eq!(lab.ui_state.selected, 1);

        let mut lab = Lab::new();
        (lab.loaded, lab.paused) = (false, false);
        lab.pass(vec![]);
        lab.pass(vec![]);
        // The two scenes and OK.
        assert_eq!(lab.buttons(CHOOSER).len(), 3);
        let step = lab.buttons(PANEL)[1].center();
        lab.pass(vec![Event::PointerMoved(step)]);
        lab.pass(click(step, true));
        assert_eq!(lab.pass(click(step, false)), []);
    }
}
