//! Reference scenarios with known answers, for the speed-against-error report: each one builds
//! a scene, steps an [`Engine`] through it and measures its error against the analytic answer.

use std::f64::consts::PI;

use sphere_physics::glam::DVec3;
use sphere_physics::{IntegratorKind, SceneDesc, Settings, SphereDesc, ToiMethod, World};

/// What a scenario needs from an engine.
pub trait Engine {
    /// One step of the engine's time step.
    fn step(&mut self);
    /// Centre positions, in the scene's order.
    fn positions(&self) -> Vec<DVec3>;
    /// Velocities, in the scene's order.
    fn velocities(&self) -> Vec<DVec3>;
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
    fn positions(&self) -> Vec<DVec3> {
        self.world.bodies().iter().map(|b| b.position()).collect()
    }
    fn velocities(&self) -> Vec<DVec3> {
        self.world.bodies().iter().map(|b| b.velocity()).collect()
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
    /// Steps `engine` for `steps` steps of `dt` and returns the error.
    fn run(&self, engine: &mut dyn Engine, dt: f64, steps: u64) -> f64 {
        self.run_with_extra(engine, dt, steps).0
    }
    /// Like [`Scenario::run`], with the scenario's second measure if it has one.
    fn run_with_extra(&self, engine: &mut dyn Engine, dt: f64, steps: u64) -> (f64, Option<f64>) {
        (self.run(engine, dt, steps), None)
    }
    /// What the second measure is, if any.
    fn extra_measure(&self) -> Option<&'static str> {
        None
    }
    /// Whether the scene uses tethers (which the rapier peer does not model).
    fn tethered(&self) -> bool {
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
    fn run(&self, engine: &mut dyn Engine, _dt: f64, steps: u64) -> f64 {
        for _ in 0..steps {
            engine.step();
        }
        let (m1, m2) = (mass(0.5, 1.0), mass(0.5, 3.0));
        let normal = DVec3::new(0.5, 0.75f64.sqrt(), 0.0);
        let impulse = 2.0 * DVec3::X.dot(normal) / (1.0 / m1 + 1.0 / m2);
        let expected = [DVec3::X - normal * impulse / m1, normal * impulse / m2];
        let v = engine.velocities();
        (v[0] - expected[0])
            .length()
            .max((v[1] - expected[1]).length())
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
    fn run(&self, engine: &mut dyn Engine, _dt: f64, steps: u64) -> f64 {
        for _ in 0..steps {
            engine.step();
        }
        let v = engine.velocities();
        let expected = [DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, DVec3::X];
        v.iter()
            .zip(expected)
            .map(|(v, e)| (*v - e).length_squared())
            .sum::<f64>()
            .sqrt()
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
        "relative error of the light ball's apex height"
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
    fn run(&self, engine: &mut dyn Engine, _dt: f64, steps: u64) -> f64 {
        let mut apex = f64::NEG_INFINITY;
        for _ in 0..steps {
            engine.step();
            apex = apex.max(engine.positions()[1].y);
        }
        let (big, small) = (mass(0.5, 100.0), mass(0.1, 1.0));
        let v = (2.0 * 9.81 * Self::DROP).sqrt();
        let out = v * (3.0 * big - small) / (big + small);
        // Contact happens with the heavy ball on the floor: the light one's centre at 1.1.
        let expected = 1.1 + out * out / (2.0 * 9.81);
        (apex - expected).abs() / expected
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
        "relative error of the time it comes to rest (Zeno time 8.58 s)"
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
    fn run_with_extra(&self, engine: &mut dyn Engine, dt: f64, steps: u64) -> (f64, Option<f64>) {
        let t1 = (2.0 / 9.81f64).sqrt();
        let zeno = t1 * 1.9 / 0.1;
        // At rest: after the last step on which it moved faster than 1 mm/s.
        let mut last_moving = 0.0;
        let mut overlap = 0.0f64;
        let floor = DVec3::new(0.0, -1000.0, 0.0);
        for k in 1..=steps {
            engine.step();
            if engine.velocities()[0].length() > 1e-3 {
                last_moving = k as f64 * dt;
            }
            overlap = overlap.max(1000.1 - (engine.positions()[0] - floor).length());
        }
        ((last_moving - zeno).abs() / zeno, Some(overlap))
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
        "relative kinetic energy drift over 10 s"
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
    fn run(&self, engine: &mut dyn Engine, _dt: f64, steps: u64) -> f64 {
        let fixed: Vec<bool> = self.scene().spheres.iter().map(|d| d.fixed).collect();
        let energy = |v: &[DVec3]| -> f64 {
            v.iter()
                .zip(&fixed)
                .filter(|(_, f)| !**f)
                .map(|(v, _)| v.length_squared())
                .sum()
        };
        let before = energy(&engine.velocities());
        for _ in 0..steps {
            engine.step();
        }
        (energy(&engine.velocities()) - before).abs() / before
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
    fn run_with_extra(&self, engine: &mut dyn Engine, _dt: f64, steps: u64) -> (f64, Option<f64>) {
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
            (momentum(&v) - momentum(&v0)).length() / scale,
            Some((energy(&v) - energy(&v0)).abs() / energy(&v0)),
        )
    }
}

/// The swinging Newton's cradle (strings, first ball raised 30°) for 60 s: the worst peak
/// height of an end ball against the release height.
pub struct TetheredCradle;

impl Scenario for TetheredCradle {
    fn name(&self) -> &'static str {
        "tethered cradle, 60 s"
    }
    fn error_measure(&self) -> &'static str {
        "worst relative error of a swing's peak height"
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
    fn run(&self, engine: &mut dyn Engine, _dt: f64, steps: u64) -> f64 {
        let release = self.scene().spheres[0].position.y;
        let (mut last, mut rising, mut worst) = ([0.0f64; 2], [false; 2], 0.0f64);
        for _ in 0..steps {
            engine.step();
            let p = engine.positions();
            for (k, ball) in [0, 4].into_iter().enumerate() {
                let y = p[ball].y;
                if rising[k] && y < last[k] && last[k] > 0.5 * release {
                    worst = worst.max((last[k] - release).abs() / release);
                }
                rising[k] = y > last[k];
                last[k] = y;
            }
        }
        worst
    }
}

/// A sphere of radius 0.01 fired at another fixed one of radius 0.01 from 1 m away: the lowest
/// speed (of 1, 2, 5, 10, ... 10⁶ m/s) at which the engine misses the collision, if any.
pub fn tunnelling_speed(make: &mut dyn FnMut(&Scene) -> Box<dyn Engine>, dt: f64) -> Option<f64> {
    let speeds = (0..=6).flat_map(|e| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(e)));
    for speed in speeds {
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
        // Until it bounces back or is past the target (at most ten times the time it needs).
        let limit = ((20.0 / speed) / dt).ceil() as u64 + 20;
        for _ in 0..limit {
            engine.step();
            let (p, v) = (engine.positions()[0], engine.velocities()[0]);
            if v.x < 0.0 {
                break;
            }
            if p.x > 0.02 {
                return Some(speed);
            }
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
