//! Reference scenarios with known answers, for the speed-against-error report: each one builds
//! a scene, steps an [`Engine`] through it and measures its error against the analytic answer.
//!
//! An engine that ends a scenario with a position or velocity that is not finite scores `NaN`
//! (a failure, never a small error).

use std::f64::consts::PI;

use sphere_physics::glam::DVec3;
use sphere_physics::{IntegratorKind, SceneDesc, Settings, SphereDesc, ToiMethod, World};

/// What a scenario needs from an engine. Reads are of one sphere, so that scenarios that
/// watch a sphere every step allocate nothing in their timed loop.
pub trait Engine {
    /// One step of the engine's time step.
    fn step(&mut self);
    /// Number of spheres.
    fn count(&self) -> usize;
    /// Sphere `i`'s centre (the scene's order).
    fn position(&self, i: usize) -> DVec3;
    /// Sphere `i`'s velocity (the scene's order).
    fn velocity(&self, i: usize) -> DVec3;
    /// Every sphere's velocity, in the scene's order.
    fn velocities(&self) -> Vec<DVec3> {
        (0..self.count()).map(|i| self.velocity(i)).collect()
    }
}

/// `value`, or `NaN` if any sphere's position or velocity is not finite.
fn unless_broken(value: f64, engine: &dyn Engine) -> f64 {
    let finite = (0..engine.count())
        .all(|i| engine.position(i).is_finite() && engine.velocity(i).is_finite());
    if finite { value } else { f64::NAN }
}

/// Our engine at one setting.
pub struct Ours {
    world: World,
    dt: f64,
}

impl Ours {
    /// The scene's world with `method`, stepped at `dt`.
    pub fn new(scene: &Scene, method: ToiMethod, dt: f64) -> Self {
        let mut settings = Settings {
            gravity: scene.gravity,
            method,
            integrator: scene.integrator,
            ..Settings::default()
        };
        settings.substeps = scene.substeps;
        let mut world = World::new(settings);
        for d in &scene.spheres {
            world
                .add_sphere(d.clone())
                .expect("reference scenes are valid");
        }
        Self { world, dt }
    }
}

impl Engine for Ours {
    fn step(&mut self) {
        self.world.step(self.dt).expect("valid dt");
    }
    fn count(&self) -> usize {
        self.world.len()
    }
    fn position(&self, i: usize) -> DVec3 {
        self.world.bodies()[i].position()
    }
    fn velocity(&self, i: usize) -> DVec3 {
        self.world.bodies()[i].velocity()
    }
}

/// A scene as plain sphere descriptions and world settings.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Gravity.
    pub gravity: DVec3,
    /// Integrator for our engine.
    pub integrator: IntegratorKind,
    /// Substeps for our engine.
    pub substeps: u32,
    /// The spheres.
    pub spheres: Vec<SphereDesc>,
}

impl Scene {
    fn new(gravity: DVec3, spheres: Vec<SphereDesc>) -> Self {
        Self {
            gravity,
            integrator: IntegratorKind::SemiImplicitEuler,
            substeps: 1,
            spheres,
        }
    }
}

/// A reference scenario.
pub trait Scenario {
    /// Short name.
    fn name(&self) -> &'static str;
    /// What the error measures.
    fn error_measure(&self) -> &'static str;
    /// The scene.
    fn scene(&self) -> Scene;
    /// Simulated seconds to run.
    fn duration(&self) -> f64;
    /// Steps `engine`, built from `scene` (this scenario's [`Scenario::scene`], made before
    /// the clock starts), for `steps` steps of `dt` and returns the error.
    fn run(&self, scene: &Scene, engine: &mut dyn Engine, dt: f64, steps: u64) -> f64 {
        self.run_with_extra(scene, engine, dt, steps).0
    }
    /// Like [`Scenario::run`], with the scenario's second measure if it has one.
    fn run_with_extra(
        &self,
        scene: &Scene,
        engine: &mut dyn Engine,
        dt: f64,
        steps: u64,
    ) -> (f64, Option<f64>) {
        (self.run(scene, engine, dt, steps), None)
    }
    /// Like [`Scenario::run_with_extra`], with the wall time in seconds the scenario spent
    /// on its own checks between the engine's steps, which is not the engine's cost (the
    /// report takes it off). A scenario implements [`Scenario::run`],
    /// [`Scenario::run_with_extra`] or this one, and with this one `run_with_extra` too (each
    /// default calls another).
    fn run_checked(
        &self,
        scene: &Scene,
        engine: &mut dyn Engine,
        dt: f64,
        steps: u64,
    ) -> (f64, Option<f64>, f64) {
        let (error, extra) = self.run_with_extra(scene, engine, dt, steps);
        (error, extra, 0.0)
    }
    /// What the second measure is, if any.
    fn extra_measure(&self) -> Option<&'static str> {
        None
    }
    /// Whether the scene uses tethers (which the rapier peer does not model).
    fn tethered(&self) -> bool {
        false
    }
    /// Whether the error is the drift of a quantity every pairwise elastic impulse keeps
    /// (energy, momentum): it says the response is exact, not that no collision was missed.
    fn conserved_measure(&self) -> bool {
        false
    }
}

fn mass(radius: f64, density: f64) -> f64 {
    density * 4.0 / 3.0 * PI * radius.powi(3)
}

/// Two spheres of masses 1 : 3 meeting at 60° off their line of motion: the velocity error
/// after 1 s against the analytic impulse.
pub struct Oblique;

impl Scenario for Oblique {
    fn name(&self) -> &'static str {
        "oblique two-body"
    }
    fn error_measure(&self) -> &'static str {
        "largest velocity error after 1 s (m/s)"
    }
    fn scene(&self) -> Scene {
        // b sits so the line of centres at contact is 60° from a's motion.
        let normal = DVec3::new(0.5, 0.75f64.sqrt(), 0.0);
        let contact = DVec3::new(0.3, 0.0, 0.0);
        Scene::new(
            DVec3::ZERO,
            vec![
                SphereDesc::new(0.5)
                    .at(contact - DVec3::X * 0.37)
                    .moving(DVec3::X),
                SphereDesc::new(0.5).at(contact + normal).with_density(3.0),
            ],
        )
    }
    fn duration(&self) -> f64 {
        1.0
    }
    fn run(&self, _scene: &Scene, engine: &mut dyn Engine, _dt: f64, steps: u64) -> f64 {
        for _ in 0..steps {
            engine.step();
        }
        let (m1, m2) = (mass(0.5, 1.0), mass(0.5, 3.0));
        let normal = DVec3::new(0.5, 0.75f64.sqrt(), 0.0);
        let impulse = 2.0 * DVec3::X.dot(normal) / (1.0 / m1 + 1.0 / m2);
        let expected = [DVec3::X - normal * impulse / m1, normal * impulse / m2];
        let v = engine.velocities();
        let error = (v[0] - expected[0])
            .length()
            .max((v[1] - expected[1]).length());
        unless_broken(error, engine)
    }
}

/// Five touching balls, the first struck at 1 m/s: the L2 error of the velocities against
/// "one in, one out" after 1 s.
pub struct Cradle;

impl Scenario for Cradle {
    fn name(&self) -> &'static str {
        "touching 5-ball cradle"
    }
    fn error_measure(&self) -> &'static str {
        "L2 velocity error against one in, one out (m/s)"
    }
    fn scene(&self) -> Scene {
        let mut spheres = vec![
            SphereDesc::new(0.5)
                .at(DVec3::new(-1.5, 0.0, 0.0))
                .moving(DVec3::X),
        ];
        spheres.extend((0..4).map(|i| SphereDesc::new(0.5).at(DVec3::new(i as f64, 0.0, 0.0))));
        Scene::new(DVec3::ZERO, spheres)
    }
    fn duration(&self) -> f64 {
        1.0
    }
    fn run(&self, _scene: &Scene, engine: &mut dyn Engine, _dt: f64, steps: u64) -> f64 {
        for _ in 0..steps {
            engine.step();
        }
        let v = engine.velocities();
        let expected = [DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, DVec3::X];
        let error = v
            .iter()
            .zip(expected)
            .map(|(v, e)| (*v - e).length_squared())
            .sum::<f64>()
            .sqrt();
        unless_broken(error, engine)
    }
}

/// A light ball (1/12 500 of the mass) resting on a heavy one, both dropped 1 m onto a fixed
/// floor: the light ball's apex against the analytic one (it leaves at (3M − m)/(M + m) times
/// the impact speed, nearly 3x, so it rises nearly 9x as high).
pub struct LightOnHeavy;

impl LightOnHeavy {
    const DROP: f64 = 1.0;
}

impl Scenario for LightOnHeavy {
    fn name(&self) -> &'static str {
        "light ball on a heavy one"
    }
    fn error_measure(&self) -> &'static str {
        "relative error of the light ball's apex height (the answer takes the impacts one \
         after another, the heavy ball's on the floor first, as the limit of two balls a \
         hair apart: an engine that solves touching contacts together, as rapier does, \
         shares the momentum otherwise)"
    }
    fn scene(&self) -> Scene {
        let heavy_y = 0.5 + Self::DROP;
        Scene::new(
            DVec3::new(0.0, -9.81, 0.0),
            vec![
                SphereDesc::new(0.5)
                    .at(DVec3::new(0.0, heavy_y, 0.0))
                    .with_density(100.0),
                SphereDesc::new(0.1).at(DVec3::new(0.0, heavy_y + 0.6, 0.0)),
                SphereDesc::new(1000.0)
                    .at(DVec3::new(0.0, -1000.0, 0.0))
                    .fixed(),
            ],
        )
    }
    fn duration(&self) -> f64 {
        3.0
    }
    fn run(&self, _scene: &Scene, engine: &mut dyn Engine, _dt: f64, steps: u64) -> f64 {
        let mut apex = f64::NEG_INFINITY;
        for _ in 0..steps {
            engine.step();
            let y = engine.position(1).y;
            if !y.is_finite() {
                return f64::NAN;
            }
            apex = apex.max(y);
        }
        let (big, small) = (mass(0.5, 100.0), mass(0.1, 1.0));
        let v = (2.0 * 9.81 * Self::DROP).sqrt();
        let out = v * (3.0 * big - small) / (big + small);
        // Contact happens with the heavy ball on the floor: the light one's centre at 1.1.
        let expected = 1.1 + out * out / (2.0 * 9.81);
        unless_broken((apex - expected).abs() / expected, engine)
    }
}

/// A ball (restitution 0.9) dropped 1 m onto a fixed sphere: the time it comes to rest against
/// the Zeno time t₁(1 + e)/(1 − e).
pub struct Bounce;

impl Scenario for Bounce {
    fn name(&self) -> &'static str {
        "bouncing ball, e = 0.9"
    }
    fn error_measure(&self) -> &'static str {
        "relative error of the time it comes to rest (Zeno time 8.58 s; at rest: after the \
         last step it ends faster than 1 mm/s). Ours ends the bounces with the first impact \
         closing slower than `Settings::resting_factor` (1.5) times what gravity gives in a \
         step, as a resting contact: the bounces that would follow, 24 to 27 steps of the \
         Zeno series, are cut off, about 5% of it at 60 steps/s, halving as the step halves. \
         That rule, not the time of impact, is most of our error here. rapier's sleeping is \
         on (its default): its ball may come to rest by falling asleep"
    }
    fn scene(&self) -> Scene {
        Scene::new(
            DVec3::new(0.0, -9.81, 0.0),
            vec![
                SphereDesc::new(0.1)
                    .at(DVec3::new(0.0, 1.1, 0.0))
                    .with_restitution(0.9),
                SphereDesc::new(1000.0)
                    .at(DVec3::new(0.0, -1000.0, 0.0))
                    .fixed(),
            ],
        )
    }
    fn duration(&self) -> f64 {
        12.0
    }
    fn extra_measure(&self) -> Option<&'static str> {
        Some("largest overlap with the floor (m)")
    }
    fn run_with_extra(
        &self,
        _scene: &Scene,
        engine: &mut dyn Engine,
        dt: f64,
        steps: u64,
    ) -> (f64, Option<f64>) {
        let t1 = (2.0 / 9.81f64).sqrt();
        let zeno = t1 * 1.9 / 0.1;
        // At rest: after the last step on which it moved faster than 1 mm/s.
        let mut last_moving = 0.0;
        let mut overlap = 0.0f64;
        let floor = DVec3::new(0.0, -1000.0, 0.0);
        for k in 1..=steps {
            engine.step();
            let (p, v) = (engine.position(0), engine.velocity(0));
            if !(p.is_finite() && v.is_finite()) {
                return (f64::NAN, Some(f64::NAN));
            }
            if v.length() > 1e-3 {
                last_moving = k as f64 * dt;
            }
            overlap = overlap.max(1000.1 - (p - floor).length());
        }
        let error = unless_broken((last_moving - zeno).abs() / zeno, engine);
        (error, Some(unless_broken(overlap, engine)))
    }
}

/// 1000 spheres at 1 m/s in a box of six fixed walls, elastic, 10 s: the drift of the kinetic
/// energy.
pub struct Gas;

impl Scenario for Gas {
    fn name(&self) -> &'static str {
        "gas of 1000 in a box"
    }
    fn error_measure(&self) -> &'static str {
        "relative kinetic energy drift over 10 s (elastic impacts keep it whether or not they \
         are the right ones: a collision missed, or a sphere through a wall, would not show \
         here, but in the deepest overlap beside it)"
    }
    fn extra_measure(&self) -> Option<&'static str> {
        Some(
            "the deepest overlap of two spheres, or of a sphere with a wall, at the end of any \
             step, over the spheres' radius (checked between steps, off the clock)",
        )
    }
    fn conserved_measure(&self) -> bool {
        true
    }
    fn scene(&self) -> Scene {
        let scene = SceneDesc::from_ron(
            "(name: \"gas\", generate: [Gas(count: 1000, seed: 5, min: (-1.2, -1.2, -1.2),
              max: (1.2, 1.2, 1.2), radius: 0.05, speed: 1.0)])",
        )
        .expect("valid scene");
        Scene::new(DVec3::ZERO, scene.sphere_descs().expect("valid scene"))
    }
    fn duration(&self) -> f64 {
        10.0
    }
    fn run_with_extra(
        &self,
        scene: &Scene,
        engine: &mut dyn Engine,
        dt: f64,
        steps: u64,
    ) -> (f64, Option<f64>) {
        let (error, extra, _) = self.run_checked(scene, engine, dt, steps);
        (error, extra)
    }
    fn run_checked(
        &self,
        scene: &Scene,
        engine: &mut dyn Engine,
        _dt: f64,
        steps: u64,
    ) -> (f64, Option<f64>, f64) {
        let fixed: Vec<bool> = scene.spheres.iter().map(|d| d.fixed).collect();
        let energy = |v: &[DVec3]| -> f64 {
            v.iter()
                .zip(&fixed)
                .filter(|(_, f)| !**f)
                .map(|(v, _)| v.length_squared())
                .sum()
        };
        let before = energy(&engine.velocities());
        let mut overlaps = Overlaps::new(scene);
        let (mut deepest, mut checking) = (0.0f64, 0.0);
        for _ in 0..steps {
            engine.step();
            let started = std::time::Instant::now();
            deepest = deepest.max(overlaps.deepest(engine));
            checking += started.elapsed().as_secs_f64();
        }
        let v = engine.velocities();
        let radius = overlaps.radius;
        (
            unless_broken((energy(&v) - before).abs() / before, engine),
            Some(unless_broken(deepest / radius, engine)),
            checking,
        )
    }
}

/// The deepest overlap among a scene's spheres, at a moment: the moving ones among
/// themselves (swept along x) and with each fixed one.
struct Overlaps {
    radii: Vec<f64>,
    fixed: Vec<usize>,
    moving: Vec<usize>,
    /// The largest moving sphere's radius.
    radius: f64,
    /// Scratch: the moving spheres' (x, index), sorted.
    order: Vec<(f64, usize)>,
}

impl Overlaps {
    fn new(scene: &Scene) -> Self {
        let radii: Vec<f64> = scene.spheres.iter().map(|d| d.radius).collect();
        let (fixed, moving) = (0..radii.len()).partition(|&i| scene.spheres[i].fixed);
        let radius = scene
            .spheres
            .iter()
            .filter(|d| !d.fixed)
            .map(|d| d.radius)
            .fold(0.0, f64::max);
        Self {
            radii,
            fixed,
            moving,
            radius,
            order: Vec::new(),
        }
    }

    /// The deepest overlap now (0 if none; infinite if a position is not finite).
    fn deepest(&mut self, engine: &dyn Engine) -> f64 {
        let mut deepest = 0.0f64;
        let overlap = |i: usize, j: usize, radii: &[f64]| {
            let gap = (engine.position(i) - engine.position(j)).length();
            if gap.is_finite() {
                radii[i] + radii[j] - gap
            } else {
                f64::INFINITY
            }
        };
        self.order.clear();
        self.order
            .extend(self.moving.iter().map(|&i| (engine.position(i).x, i)));
        self.order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        for (k, &(x, i)) in self.order.iter().enumerate() {
            for &(other_x, j) in &self.order[k + 1..] {
                if other_x - x > 2.0 * self.radius {
                    break;
                }
                deepest = deepest.max(overlap(i, j, &self.radii));
            }
            for &f in &self.fixed {
                deepest = deepest.max(overlap(i, f, &self.radii));
            }
        }
        deepest
    }
}

/// 1000 spheres at 1 m/s in random directions with no walls: they collide, then fly apart.
/// Momentum has nothing to leave through: its drift over 10 s, relative to Σ m|v|.
pub struct GasCloud;

impl Scenario for GasCloud {
    fn name(&self) -> &'static str {
        "open gas cloud of 1000"
    }
    fn error_measure(&self) -> &'static str {
        "momentum drift over 10 s, relative to the sum of m|v|"
    }
    fn extra_measure(&self) -> Option<&'static str> {
        Some("relative kinetic energy drift")
    }
    fn conserved_measure(&self) -> bool {
        true
    }
    fn scene(&self) -> Scene {
        let scene = SceneDesc::from_ron(
            "(name: \"cloud\", generate: [Gas(count: 1000, seed: 9, min: (-1.2, -1.2, -1.2),
              max: (1.2, 1.2, 1.2), radius: 0.05, speed: 1.0, walls: false)])",
        )
        .expect("valid scene");
        Scene::new(DVec3::ZERO, scene.sphere_descs().expect("valid scene"))
    }
    fn duration(&self) -> f64 {
        10.0
    }
    fn run_with_extra(
        &self,
        _scene: &Scene,
        engine: &mut dyn Engine,
        _dt: f64,
        steps: u64,
    ) -> (f64, Option<f64>) {
        // Equal masses: compare velocity sums.
        let momentum = |v: &[DVec3]| v.iter().copied().sum::<DVec3>();
        let energy = |v: &[DVec3]| v.iter().map(|v| v.length_squared()).sum::<f64>();
        let v0 = engine.velocities();
        let scale: f64 = v0.iter().map(|v| v.length()).sum();
        for _ in 0..steps {
            engine.step();
        }
        let v = engine.velocities();
        (
            unless_broken((momentum(&v) - momentum(&v0)).length() / scale, engine),
            Some(unless_broken(
                (energy(&v) - energy(&v0)).abs() / energy(&v0),
                engine,
            )),
        )
    }
}

/// The swinging Newton's cradle (strings, first ball raised 30°) for 60 s, one substep a
/// step (the scene file asks for two): the worst error of an end ball's swing, its peak
/// height against the release height over the swing's span (release height above the
/// hanging balls). Each peak is the ball's height plus v²/2g at its highest sample, which is
/// where it turns, free of the sampling's dip below the true turning point. An end ball that
/// stops swinging out past half the span (fewer than half the swings a pendulum of the
/// string's length makes) scores 1, as does a run shorter than a period (it is meant to run
/// for a minute, some thirty periods).
pub struct TetheredCradle;

impl Scenario for TetheredCradle {
    fn name(&self) -> &'static str {
        "tethered cradle, 60 s"
    }
    fn error_measure(&self) -> &'static str {
        "worst error of a swing's peak height over the swing's span (one substep a step); \
         1 means an end ball stopped swinging out (fewer than half the swings a pendulum \
         makes), a failure, as does NaN"
    }
    fn scene(&self) -> Scene {
        let scene = SceneDesc::from_ron(include_str!("../../../assets/scenes/newtons_cradle.ron"))
            .expect("valid scene");
        Scene {
            gravity: DVec3::from(scene.gravity),
            integrator: IntegratorKind::Leapfrog,
            substeps: 1,
            spheres: scene.sphere_descs().expect("valid scene"),
        }
    }
    fn duration(&self) -> f64 {
        60.0
    }
    fn tethered(&self) -> bool {
        true
    }
    fn run(&self, scene: &Scene, engine: &mut dyn Engine, dt: f64, steps: u64) -> f64 {
        let g = -scene.gravity.y;
        let first = &scene.spheres[0];
        let tether = first.tether.expect("the cradle's balls hang on strings");
        let release = first.position.y;
        let rest = tether.anchor.y - tether.length;
        let span = release - rest;
        let ends = [0, scene.spheres.len() - 1];
        let mut last = ends.map(|ball| scene.spheres[ball].position.y);
        let mut last_height = last;
        let mut rising = [false; 2];
        let (mut swings, mut worst) = (0u32, 0.0f64);
        for _ in 0..steps {
            engine.step();
            for (k, ball) in ends.into_iter().enumerate() {
                let (p, v) = (engine.position(ball), engine.velocity(ball));
                if !(p.is_finite() && v.is_finite()) {
                    return f64::NAN;
                }
                if rising[k] && p.y < last[k] && last[k] > rest + 0.5 * span {
                    swings += 1;
                    worst = worst.max((last_height[k] - release).abs() / span);
                }
                rising[k] = p.y > last[k];
                last[k] = p.y;
                last_height[k] = p.y + v.length_squared() / (2.0 * g);
            }
        }
        // Each end swings out once a period of the pendulum (the amplitude's first correction
        // to the period included).
        let amplitude = ((tether.anchor.y - release) / tether.length).acos();
        let period = 2.0 * PI * (tether.length / g).sqrt() * (1.0 + amplitude.powi(2) / 16.0);
        let expected = 2.0 * steps as f64 * dt / period;
        assert!(
            expected.is_finite(),
            "the first ball hangs within its string's reach"
        );
        if f64::from(swings) < 0.5 * expected {
            return 1.0;
        }
        unless_broken(worst, engine)
    }
}

/// The speeds [`tunnelling_speed`] tries: 1, 2, 5, 10, 20, 50, ... 5×10⁶ m/s.
pub fn tunnelling_speeds() -> impl Iterator<Item = f64> {
    (0..=6).flat_map(|e| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(e)))
}

/// A sphere of radius 0.01 fired at another fixed one of radius 0.01 from 1 m away (elastic):
/// the lowest of [`tunnelling_speeds`] at which the engine fails to bounce it back, if any. It
/// must come back out on its own side, moving away, and get halfway back to where it started
/// (0.5 m from the target) within 20 m of travel at its speed (twenty times the time it needs
/// to reach the target; at least 20 steps): a sphere that passes through the target, or stays
/// caught in it, or whose state stops being finite, has missed.
pub fn tunnelling_speed(make: &mut dyn FnMut(&Scene) -> Box<dyn Engine>, dt: f64) -> Option<f64> {
    for speed in tunnelling_speeds() {
        let scene = Scene::new(
            DVec3::ZERO,
            vec![
                SphereDesc::new(0.01)
                    .at(DVec3::new(-1.0, 0.0, 0.0))
                    .moving(DVec3::X * speed),
                SphereDesc::new(0.01).fixed(),
            ],
        );
        let mut engine = make(&scene);
        let limit = ((20.0 / speed) / dt).ceil() as u64 + 20;
        let mut back = false;
        for _ in 0..limit {
            engine.step();
            let (p, v) = (engine.position(0), engine.velocity(0));
            if !(p.is_finite() && v.is_finite()) {
                break;
            }
            if p.x < -0.5 && v.x < 0.0 {
                back = true;
                break;
            }
        }
        if !back {
            return Some(speed);
        }
    }
    None
}

/// All scenarios of the report.
pub fn scenarios() -> Vec<Box<dyn Scenario>> {
    vec![
        Box::new(Oblique),
        Box::new(Cradle),
        Box::new(LightOnHeavy),
        Box::new(Bounce),
        Box::new(Gas),
        Box::new(GasCloud),
        Box::new(TetheredCradle),
    ]
}
