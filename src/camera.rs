//! A camera that orbits a target: drag with the left mouse button (or the arrow keys) to orbit,
//! scroll (or `-` / `=`, or the keypad's `-` / `+`) to zoom; the keys only while the chooser is
//! closed. Each scene is framed when it is entered.

use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll, MouseScrollUnit};
use bevy::prelude::*;
use bevy::state::state::StateTransitionEvent;
use bevy_egui::EguiContexts;

use crate::controls::LabUi;
use crate::render::{SphereExtent, scene_bounds_of};
use crate::scenes::{ActiveScene, LabPersistent, LabScenes};

/// Where the camera looks from: `distance` from `target`, turned `yaw` radians about the
/// vertical and `pitch` radians above the horizontal.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at.
    pub target: Vec3,
    /// Radians about the vertical axis.
    pub yaw: f32,
    /// Radians above the horizontal, within ±1.5.
    pub pitch: f32,
    /// Distance from the target.
    pub distance: f32,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        Self {
            target: Vec3::ZERO,
            yaw: 0.0,
            pitch: 0.25,
            distance: 12.0,
        }
    }
}

impl OrbitCamera {
    /// The camera's transform.
    pub fn transform(&self) -> Transform {
        let rotation = Quat::from_euler(EulerRot::YXZ, self.yaw, -self.pitch, 0.0);
        Transform::from_translation(self.target + rotation * Vec3::Z * self.distance)
            .looking_at(self.target, Vec3::Y)
    }
}

/// Spawns the orbiting camera and moves it.
pub struct OrbitCameraPlugin;

impl Plugin for OrbitCameraPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Startup, spawn_camera).add_systems(
            Update,
            (
                frame_scene.run_if(on_message::<StateTransitionEvent<ActiveScene>>),
                orbit,
            )
                .chain(),
        );
    }
}

fn spawn_camera(mut commands: Commands) {
    let orbit = OrbitCamera::default();
    commands.spawn((LabPersistent, Camera3d::default(), orbit.transform(), orbit));
}

/// Frames the spheres (and anchors) of a scene just entered, and its `view` box if it has one.
fn frame_scene(
    spheres: Query<SphereExtent>,
    state: Res<State<ActiveScene>>,
    scenes: Res<LabScenes>,
    mut cameras: Query<(&mut OrbitCamera, &Projection)>,
) {
    let view = state
        .get()
        .id()
        .and_then(|id| scenes.get(id))
        .and_then(|scene| scene.view)
        .map(|(low, high)| (low.as_vec3(), high.as_vec3()))
        // A box beyond single precision (finite as checked, but past 3e38) is not framed.
        .filter(|(low, high)| (*high - *low).is_finite());
    let bounds = match (scene_bounds_of(&spheres), view) {
        (Some((low, high)), Some((view_low, view_high))) => {
            Some((low.min(view_low), high.max(view_high)))
        }
        (bounds, view) => bounds.or(view),
    };
    let Some((low, high)) = bounds else {
        // Nothing to frame: the default view, not the last scene's.
        for (mut orbit, _) in &mut cameras {
            *orbit = OrbitCamera::default();
        }
        return;
    };
    for (mut orbit, projection) in &mut cameras {
        let fov = match projection {
            Projection::Perspective(p) => p.fov,
            _ => std::f32::consts::FRAC_PI_4,
        };
        let radius = ((high - low) / 2.0).length().max(0.5);
        *orbit = OrbitCamera {
            target: (low + high) / 2.0,
            yaw: 0.0,
            pitch: 0.2,
            distance: radius / (fov / 2.0).tan() * 1.05,
        };
    }
}

#[allow(clippy::too_many_arguments)]
fn orbit(
    mut cameras: Query<(&mut OrbitCamera, &mut Transform, &mut Projection)>,
    motion: Res<AccumulatedMouseMotion>,
    scroll: Res<AccumulatedMouseScroll>,
    buttons: Res<ButtonInput<MouseButton>>,
    keys: Res<ButtonInput<KeyCode>>,
    time: Res<Time<Real>>,
    ui: Res<LabUi>,
    mut egui: EguiContexts,
) {
    let (egui_wants_pointer, egui_wants_keys) = egui.ctx_mut().map_or((false, false), |ctx| {
        (
            ctx.egui_wants_pointer_input() || ctx.is_pointer_over_egui(),
            ctx.egui_wants_keyboard_input(),
        )
    });
    let mut turn = Vec2::ZERO;
    let mut zoom = 0.0;
    if !egui_wants_pointer {
        if buttons.pressed(MouseButton::Left) {
            turn += motion.delta * 0.005;
        }
        zoom += match scroll.unit {
            MouseScrollUnit::Line => scroll.delta.y * 0.1,
            MouseScrollUnit::Pixel => scroll.delta.y * 0.002,
        };
    }
    // The keys wait while the chooser is open or an egui text field has the keyboard.
    if !ui.chooser_open && !egui_wants_keys {
        // By the wall clock: the virtual time's frames are capped at a few steps' time in a
        // scene of very short steps (`MAX_FIXED_STEPS_PER_FRAME`), and stand still while the
        // lab waits for its shaders; the keys then moved the camera at a crawl, or not at all.
        // (A frame held up for long, a shader compiled, turns it no more than a tenth of a
        // second's worth.)
        let rate = time.delta_secs().min(0.1) * 1.5;
        let axis = |neg, pos| f32::from(keys.pressed(pos)) - f32::from(keys.pressed(neg));
        turn.x -= axis(KeyCode::ArrowLeft, KeyCode::ArrowRight) * rate;
        turn.y -= axis(KeyCode::ArrowDown, KeyCode::ArrowUp) * rate;
        let keys_zoom = axis(KeyCode::Minus, KeyCode::Equal)
            + axis(KeyCode::NumpadSubtract, KeyCode::NumpadAdd);
        zoom += keys_zoom.clamp(-1.0, 1.0) * rate;
    }
    for (mut orbit, mut transform, mut projection) in &mut cameras {
        if turn != Vec2::ZERO || zoom != 0.0 {
            orbit.yaw -= turn.x;
            orbit.pitch = (orbit.pitch + turn.y).clamp(-1.5, 1.5);
            orbit.distance = (orbit.distance * (1.0 - zoom).clamp(0.5, 1.5)).max(0.05);
        }
        let wanted = orbit.transform();
        if *transform != wanted {
            *transform = wanted;
        }
        // Everything framed stays in front of the far plane (Bevy's 1000 m would cut off a
        // scene hundreds of metres across, framed from farther away than that, or one zoomed
        // out on): a scene framed at `distance` lies within about 1.4 times it.
        let far = (orbit.distance * 4.0).max(1000.0);
        if matches!(&*projection, Projection::Perspective(p) if p.far != far)
            && let Projection::Perspective(perspective) = &mut *projection
        {
            perspective.far = far;
        }
    }
}
