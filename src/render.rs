//! Drawing the lab: lit spheres in the tutorial's colours (blue 1x, green 2x, red 3x the
//! scene's lightest density, each darker while the sphere is asleep; fixed spheres grey), strings and a frame for tethered spheres, a
//! ground under each scene, lights, and capturing frames for screenshots.

use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::state::state::StateTransitionEvent;
use bevy_sphere_physics::prelude::*;

use crate::LabSystems;
use crate::scenes::{ActiveScene, LabPersistent, LabScenes};
use crate::screenshot::{FrameCaptured, RenderReady, ScreenshotRequested, ScreenshotStatus};
use bevy::render::render_resource::PipelineCache;
use bevy::render::{MainWorld, RenderApp};

/// Spheres larger than this are walls (the gas box's): not drawn.
pub const WALL_RADIUS: f64 = 1000.0;

/// The tutorial's colours.
pub mod colours {
    use bevy::color::Color;
    /// Density 1x the scene's lightest.
    pub const BLUE: Color = Color::srgb(0.12, 0.32, 0.95);
    /// Density 2x.
    pub const GREEN: Color = Color::srgb(0.12, 0.78, 0.22);
    /// Density 3x.
    pub const RED: Color = Color::srgb(0.92, 0.12, 0.10);
    /// The same three while asleep: darker.
    pub const BLUE_ASLEEP: Color = Color::srgb(0.06, 0.12, 0.36);
    /// Density 2x, asleep.
    pub const GREEN_ASLEEP: Color = Color::srgb(0.05, 0.30, 0.09);
    /// Density 3x, asleep.
    pub const RED_ASLEEP: Color = Color::srgb(0.36, 0.05, 0.04);
    /// Fixed spheres.
    pub const GREY: Color = Color::srgb(0.55, 0.56, 0.58);
    /// Strings.
    pub const STRING: Color = Color::srgb(0.85, 0.85, 0.80);
    /// The cradle's frame.
    pub const FRAME: Color = Color::srgb(0.30, 0.22, 0.16);
    /// The ground.
    pub const GROUND: Color = Color::srgb(0.20, 0.21, 0.23);
    /// The background.
    pub const SKY: Color = Color::srgb(0.05, 0.06, 0.08);
}

/// Draws spheres, strings, frames and the ground; captures frames for screenshots.
pub struct LabRenderPlugin;

impl Plugin for LabRenderPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<RenderReady>()
            .sub_app_mut(RenderApp)
            .add_systems(ExtractSchedule, count_ready_frames);
        app.insert_resource(ClearColor(colours::SKY))
            .add_systems(Startup, setup)
            .add_systems(
                Update,
                (
                    dress_spheres,
                    dress_strings,
                    place_strings,
                    tint_sleepers,
                    build_stage.run_if(on_message::<StateTransitionEvent<ActiveScene>>),
                )
                    .chain(),
            )
            // In the frame the request is made, so the stamped time is the frame's.
            .add_systems(Update, capture_frames.after(LabSystems::Act))
            .add_systems(PreUpdate, hold_until_drawn);
    }
}

/// Meshes and materials every scene shares.
#[derive(Resource)]
struct LabAssets {
    /// Unit spheres by detail: `(sectors, mesh)`, made as a scene needs them.
    spheres: Vec<(u32, Handle<Mesh>)>,
    rod: Handle<Mesh>,
    ground: Handle<Mesh>,
    blue: Handle<StandardMaterial>,
    green: Handle<StandardMaterial>,
    red: Handle<StandardMaterial>,
    /// `blue`, `green` and `red` while asleep.
    asleep: [Handle<StandardMaterial>; 3],
    grey: Handle<StandardMaterial>,
    string: Handle<StandardMaterial>,
    frame: Handle<StandardMaterial>,
    floor: Handle<StandardMaterial>,
}

fn setup(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let mut shiny = |colour: Color, roughness: f32| {
        materials.add(StandardMaterial {
            base_color: colour,
            perceptual_roughness: roughness,
            ..default()
        })
    };
    commands.insert_resource(LabAssets {
        spheres: vec![(32, meshes.add(unit_sphere(32)))],
        rod: meshes.add(Cylinder::new(1.0, 1.0)),
        ground: meshes.add(Plane3d::default().mesh().size(1.0, 1.0)),
        blue: shiny(colours::BLUE, 0.3),
        green: shiny(colours::GREEN, 0.3),
        red: shiny(colours::RED, 0.3),
        asleep: [
            shiny(colours::BLUE_ASLEEP, 0.5),
            shiny(colours::GREEN_ASLEEP, 0.5),
            shiny(colours::RED_ASLEEP, 0.5),
        ],
        grey: shiny(colours::GREY, 0.5),
        string: shiny(colours::STRING, 0.9),
        frame: shiny(colours::FRAME, 0.6),
        floor: shiny(colours::GROUND, 0.95),
    });
    commands.insert_resource(GlobalAmbientLight {
        brightness: 250.0,
        ..default()
    });
    commands.spawn((
        LabPersistent,
        DirectionalLight {
            illuminance: 9000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_xyz(4.0, 10.0, 6.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
}

/// A unit sphere of `sectors` around and about half as many bands from pole to pole.
fn unit_sphere(sectors: u32) -> Mesh {
    Sphere::new(1.0).mesh().uv(sectors, sectors / 2 + 2)
}

/// The detail a sphere of `radius` needs so that its flat facets sit within 1% of the smallest
/// moving sphere's radius (`smallest`) of its true surface: a big fixed sphere used as ground
/// drawn with the small spheres' 32 sectors would sink its facets' middles far below where the
/// spheres resting on it touch (0.4 m for a ground of radius 100). Sectors `n` leave a facet
/// `R (1 - cos(π/n))` inside, about `R π² / (2 n²)`; a power of two from 32 to 512.
fn sectors_for(radius: f64, smallest: f64) -> u32 {
    if !(smallest.is_finite() && smallest > 0.0) {
        return 32;
    }
    let needed = std::f64::consts::PI * (radius / (0.02 * smallest)).sqrt();
    (needed.clamp(32.0, 512.0).ceil() as u32)
        .next_power_of_two()
        .min(512)
}

/// The sphere's visual: a child scaled to the radius, so the physics owns the parent's
/// transform.
#[derive(Component)]
struct SphereVisual;

/// A sphere the renderer has seen (walls get no visual).
#[derive(Component)]
struct Dressed;

/// A tethered sphere's string: a child rod from the sphere to the anchor.
#[derive(Component)]
struct StringVisual;

#[allow(clippy::type_complexity)]
fn dress_spheres(
    mut commands: Commands,
    mut assets: ResMut<LabAssets>,
    mut meshes: ResMut<Assets<Mesh>>,
    new: Query<(Entity, &SphereBody, &Density, Has<FixedSphere>), Without<Dressed>>,
    all: Query<(&SphereBody, &Density, Has<FixedSphere>)>,
) {
    if new.is_empty() {
        return;
    }
    let moving = || {
        all.iter()
            .filter(|(b, _, fixed)| !fixed && b.radius <= WALL_RADIUS)
    };
    let lightest = moving().map(|(_, d, _)| d.0).fold(f64::INFINITY, f64::min);
    let smallest = moving()
        .map(|(b, _, _)| b.radius)
        .fold(f64::INFINITY, f64::min);
    for (entity, body, density, fixed) in &new {
        commands.entity(entity).insert(Dressed);
        if body.radius > WALL_RADIUS || !body.radius.is_finite() {
            continue;
        }
        let (material, tints) = if fixed {
            (assets.grey.clone(), None)
        } else {
            let ratio = density.0 / lightest;
            let (awake, k) = if ratio < 1.5 {
                (&assets.blue, 0)
            } else if ratio < 2.5 {
                (&assets.green, 1)
            } else {
                (&assets.red, 2)
            };
            let asleep = assets.asleep[k].clone();
            let tints = Tints {
                awake: awake.clone(),
                asleep,
            };
            (awake.clone(), Some(tints))
        };
        let sectors = sectors_for(body.radius, smallest);
        let mesh = match assets.spheres.iter().find(|(n, _)| *n == sectors) {
            Some((_, mesh)) => mesh.clone(),
            None => {
                let mesh = meshes.add(unit_sphere(sectors));
                assets.spheres.push((sectors, mesh.clone()));
                mesh
            }
        };
        let mut sphere = commands.entity(entity);
        sphere.insert(Visibility::default()).with_child((
            SphereVisual,
            Mesh3d(mesh),
            MeshMaterial3d(material),
            Transform::from_scale(Vec3::splat(body.radius as f32)),
        ));
        if let Some(tints) = tints {
            sphere.insert(SphereTints(tints));
        }
    }
}

/// A moving sphere's materials, awake and asleep.
#[derive(Clone, Debug)]
struct Tints {
    awake: Handle<StandardMaterial>,
    asleep: Handle<StandardMaterial>,
}

/// On a sphere that may fall asleep: its [`Tints`].
#[derive(Component)]
struct SphereTints(Tints);

/// Draws each sphere in its asleep colour while it is asleep (scenes with sleeping on).
fn tint_sleepers(
    physics: Res<SpherePhysicsWorld>,
    spheres: Query<(&SphereHandle, &SphereTints, &Children)>,
    mut visuals: Query<&mut MeshMaterial3d<StandardMaterial>, With<SphereVisual>>,
) {
    for (handle, tints, children) in &spheres {
        let asleep = physics
            .world
            .body(handle.0)
            .is_some_and(|body| body.is_asleep());
        let want = if asleep {
            &tints.0.asleep
        } else {
            &tints.0.awake
        };
        for child in children.iter() {
            if let Ok(mut material) = visuals.get_mut(child)
                && material.0 != *want
            {
                material.0 = want.clone();
            }
        }
    }
}

/// The spheres whose strings are drawn: tethered and not fixed (the physics ignores a fixed
/// sphere's string).
type StrungSpheres = (With<Tethered>, Without<FixedSphere>, Without<StringVisual>);

fn dress_strings(
    mut commands: Commands,
    assets: Res<LabAssets>,
    tethered: Query<(Entity, &Children), StrungSpheres>,
    strings: Query<(), With<StringVisual>>,
) {
    for (entity, children) in &tethered {
        if children.iter().any(|c| strings.contains(c)) {
            continue;
        }
        commands.entity(entity).with_child((
            StringVisual,
            Mesh3d(assets.rod.clone()),
            MeshMaterial3d(assets.string.clone()),
            Transform::default(),
        ));
    }
}

/// Strings run from the sphere's centre to its anchor (the part inside the sphere is hidden).
fn place_strings(
    spheres: Query<(&Transform, &Tethered, &SphereBody, &Children), StrungSpheres>,
    mut strings: Query<&mut Transform, With<StringVisual>>,
) {
    for (transform, tether, body, children) in &spheres {
        let to_anchor = tether.anchor.as_vec3() - transform.translation;
        let length = to_anchor.length();
        let width = (body.radius as f32 * 0.04).max(0.002);
        for child in children.iter() {
            if let Ok(mut string) = strings.get_mut(child) {
                *string = Transform {
                    translation: to_anchor / 2.0,
                    rotation: Quat::from_rotation_arc(Vec3::Y, to_anchor.normalize_or(Vec3::Y)),
                    scale: Vec3::new(width, length, width),
                };
            }
        }
    }
}

/// A sphere as the stage reads it: centre, radius, fixed, and its string's anchor if it hangs
/// on one.
pub type StageSphere = (Vec3, f32, bool, Option<Vec3>);

/// How a scene's ground is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ground {
    /// The floor the spheres fall onto is a fixed sphere small enough to draw: it is the
    /// ground, its top under the scene at this height; no plane.
    FloorSphere(f32),
    /// A plane at this height: on the floor the spheres fall onto when that is too large to
    /// draw (a wall), or a little below the spheres when nothing falls freely.
    Plane(f32),
    /// No ground: spheres fall freely (under gravity, not on strings) with no floor under them,
    /// and would pass through a drawn one.
    Open,
}

/// Where a scene is framed and how its ground is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stage {
    /// The box the camera frames: the moving spheres and the anchors of their strings, the
    /// fixed spheres no larger than twice that box (a dome, not a planet used as the ground,
    /// nor the walls of a box), and down to the top of the floor under them.
    pub low: Vec3,
    /// The box's upper corner.
    pub high: Vec3,
    /// The floor under the scene (see [`floor_under`]): its top's height and its radius.
    pub floor: Option<(f32, f32)>,
    /// How the ground is drawn.
    pub ground: Ground,
}

impl Stage {
    /// The height a frame's legs stand at: the ground's, or a little below the spheres.
    pub fn ground_height(&self) -> f32 {
        match self.ground {
            Ground::FloorSphere(y) | Ground::Plane(y) => y,
            Ground::Open => self.low.y - 0.25 * (self.high - self.low).max_element().max(1.0),
        }
    }
}

/// The stage of a scene's spheres; `gravity` says whether anything falls. `None` without
/// spheres.
pub fn scene_stage(
    spheres: impl Iterator<Item = StageSphere> + Clone,
    gravity: bool,
) -> Option<Stage> {
    let (low, high) = bounds_above_floor(spheres.clone())?;
    let floor = floor_under(spheres.clone(), low, high);
    let falls = gravity
        && spheres
            .clone()
            .any(|(_, _, fixed, anchor)| !fixed && anchor.is_none());
    let extent = (high - low).max_element().max(1.0);
    let ground = match floor {
        Some((top, r)) if f64::from(r) <= WALL_RADIUS => Ground::FloorSphere(top),
        Some((top, _)) => Ground::Plane(top),
        None if falls => Ground::Open,
        None => Ground::Plane(low.y - 0.25 * extent),
    };
    let mut framed_low = low;
    if let Some((top, _)) = floor {
        framed_low.y = framed_low.y.min(top);
    }
    Some(Stage {
        low: framed_low,
        high,
        floor,
        ground,
    })
}

/// The box a scene's camera is fitted to ([`Stage::low`], [`Stage::high`]). `None` without
/// spheres.
pub fn scene_bounds(spheres: impl Iterator<Item = StageSphere> + Clone) -> Option<(Vec3, Vec3)> {
    scene_stage(spheres, false).map(|stage| (stage.low, stage.high))
}

/// The floor under a scene's box `low`..`high` (the box of its moving spheres, before the
/// floor is added), as its top's height under the box's centre and its radius: the highest
/// fixed sphere too large to be framed (a planet used as the ground) that lies below the box
/// and at most four box sizes under it. A scene's spheres fall onto it, so the camera frames
/// it, and it is the ground.
pub fn floor_under(
    spheres: impl Iterator<Item = StageSphere>,
    low: Vec3,
    high: Vec3,
) -> Option<(f32, f32)> {
    let extent = (high - low).max_element().max(1.0);
    let limit = 2.0 * extent;
    let centre = (low + high) / 2.0;
    spheres
        .filter(|&(c, r, fixed, _)| fixed && r > limit && r.is_finite() && c.is_finite())
        .filter_map(|(c, r, _, _)| {
            let across = Vec2::new(centre.x - c.x, centre.z - c.z).length_squared();
            let top = c.y + (r * r - across).max(0.0).sqrt();
            (across < r * r && top <= low.y + 1e-3 * extent && top >= low.y - 4.0 * extent)
                .then_some((top, r))
        })
        .reduce(|a, b| if b.0 > a.0 { b } else { a })
}

/// The framed box without the floor.
fn bounds_above_floor(spheres: impl Iterator<Item = StageSphere> + Clone) -> Option<(Vec3, Vec3)> {
    let mut low = Vec3::splat(f32::INFINITY);
    let mut high = Vec3::splat(f32::NEG_INFINITY);
    for (centre, r, fixed, anchor) in spheres.clone() {
        if !fixed {
            low = low.min(centre - r);
            high = high.max(centre + r);
        }
        // A fixed sphere's string is ignored by the physics, and not drawn.
        if let Some(anchor) = anchor.filter(|_| !fixed) {
            low = low.min(anchor);
            high = high.max(anchor);
        }
    }
    let limit = if low.is_finite() {
        2.0 * (high - low).max_element().max(1.0)
    } else {
        WALL_RADIUS as f32
    };
    for (centre, r, fixed, _) in spheres {
        if fixed && r <= limit {
            low = low.min(centre - r);
            high = high.max(centre + r);
        }
    }
    low.is_finite().then_some((low, high))
}

/// What [`scene_bounds_of`] reads of a sphere.
pub type SphereExtent = (
    &'static Transform,
    &'static SphereBody,
    Has<FixedSphere>,
    Option<&'static Tethered>,
);

/// The spheres of a query as the stage reads them.
fn stage_spheres(spheres: &Query<SphereExtent>) -> impl Iterator<Item = StageSphere> + Clone {
    spheres.iter().map(|(t, b, fixed, tether)| {
        (
            t.translation,
            b.radius as f32,
            fixed,
            tether.map(|t| t.anchor.as_vec3()),
        )
    })
}

/// [`scene_bounds`] of the spheres in a query.
pub fn scene_bounds_of(spheres: &Query<SphereExtent>) -> Option<(Vec3, Vec3)> {
    scene_bounds(stage_spheres(spheres))
}

/// A rod between two points.
fn rod(assets: &LabAssets, from: Vec3, to: Vec3, width: f32) -> impl Bundle {
    let along = to - from;
    (
        Mesh3d(assets.rod.clone()),
        MeshMaterial3d(assets.frame.clone()),
        Transform {
            translation: (from + to) / 2.0,
            rotation: Quat::from_rotation_arc(Vec3::Y, along.normalize_or(Vec3::Y)),
            scale: Vec3::new(width, along.length(), width),
        },
    )
}

/// On entering a scene: the ground under its spheres (see [`Ground`]) and, if it has
/// tethers, a frame that holds the anchors.
fn build_stage(
    mut commands: Commands,
    assets: Res<LabAssets>,
    state: Res<State<ActiveScene>>,
    scenes: Res<LabScenes>,
    spheres: Query<SphereExtent>,
) {
    if *state.get() == ActiveScene::None {
        return;
    }
    let scope = DespawnOnExit(state.get().clone());
    let gravity = state
        .get()
        .id()
        .and_then(|id| scenes.get(id))
        .is_some_and(|scene| scene.settings.gravity != DVec3::ZERO);
    let Some(stage) = scene_stage(stage_spheres(&spheres), gravity) else {
        return;
    };
    let mut anchors = Vec::new();
    let mut smallest = f32::INFINITY;
    // How far a tethered sphere swings out sideways beyond its anchor (as far as it starts).
    let mut reach = 0.0f32;
    for (transform, body, fixed, tether) in &spheres {
        let r = body.radius as f32;
        smallest = smallest.min(r);
        if let Some(t) = tether.filter(|_| !fixed) {
            anchors.push(t.anchor.as_vec3());
            reach = reach.max((transform.translation.x - t.anchor.x as f32).abs() + r);
        }
    }

    let (low, high) = (stage.low, stage.high);
    let extent = (high - low).max_element().max(1.0);
    let ground = stage.ground_height();
    let centre = (low + high) / 2.0;
    if let Ground::Plane(y) = stage.ground {
        commands.spawn((
            scope.clone(),
            Mesh3d(assets.ground.clone()),
            MeshMaterial3d(assets.floor.clone()),
            Transform::from_xyz(centre.x, y, centre.z).with_scale(Vec3::splat(extent * 8.0)),
        ));
    }
    if anchors.is_empty() {
        return;
    }
    // A gallows frame: a top bar through the anchors, two legs, two feet.
    let a_low = anchors.iter().fold(Vec3::INFINITY, |a, b| a.min(*b));
    let a_high = anchors.iter().fold(Vec3::NEG_INFINITY, |a, b| a.max(*b));
    let width = (smallest * 0.25).max(0.005);
    let margin = (smallest * 2.0).max(reach * 1.15);
    let top = a_high.y;
    let left = Vec3::new(a_low.x - margin, top, (a_low.z + a_high.z) / 2.0);
    let right = Vec3::new(a_high.x + margin, top, (a_low.z + a_high.z) / 2.0);
    let foot = (top - ground) * 0.3;
    for end in [left, right] {
        let base = Vec3::new(end.x, ground, end.z);
        commands.spawn((scope.clone(), rod(&assets, end, base, width)));
        commands.spawn((
            scope.clone(),
            rod(&assets, base - Vec3::Z * foot, base + Vec3::Z * foot, width),
        ));
    }
    commands.spawn((scope, rod(&assets, left, right, width)));
}

/// Turns screenshot requests into window captures, and captures into [`FrameCaptured`].
fn capture_frames(mut commands: Commands, mut requests: MessageReader<ScreenshotRequested>) {
    // One capture per frame: Bevy drops a second capture of the same window in a frame (with
    // only a log line), and it would be the same picture anyway.
    if let Some(request) = requests.read().last() {
        let time = request.time;
        commands.spawn(Screenshot::primary_window()).observe(
            move |captured: On<ScreenshotCaptured>,
                  mut frames: MessageWriter<FrameCaptured>,
                  mut status: ResMut<ScreenshotStatus>| {
                match captured.image.clone().try_into_dynamic() {
                    Ok(image) => {
                        let mut image = image.to_rgba8();
                        // The alpha channel may hold HDR brightness: the saved picture is opaque.
                        image.pixels_mut().for_each(|p| p.0[3] = 255);
                        frames.write(FrameCaptured { image, time });
                    }
                    Err(e) => {
                        let e = format!("cannot read the captured frame: {e}");
                        error!("screenshot failed: {e}");
                        status.failed += 1;
                        status.last = Some(Err(e));
                    }
                }
            },
        );
    }
}

/// Holds Bevy's virtual clock (so the physics) while shaders compile: a scene starts moving
/// when it can be seen, not seconds earlier on a slow (or software) renderer. It only ever
/// undoes its own hold: a clock the game paused stays paused.
fn hold_until_drawn(
    ready: Res<RenderReady>,
    mut time: ResMut<Time<Virtual>>,
    mut holding: Local<bool>,
) {
    let drawing = ready.settled();
    if drawing && *holding {
        *holding = false;
        if time.is_paused() {
            time.unpause();
        }
    } else if !drawing && !*holding && !time.is_paused() {
        *holding = true;
        time.pause();
    }
}

/// Counts frames drawn with no pipeline still compiling (in the render world, at extraction).
fn count_ready_frames(mut main_world: ResMut<MainWorld>, pipelines: Res<PipelineCache>) {
    if let Some(mut ready) = main_world.get_resource_mut::<RenderReady>() {
        if pipelines.waiting_pipelines().count() == 0 {
            ready.frames = ready.frames.saturating_add(1);
        } else {
            ready.frames = 0;
        }
    }
}
