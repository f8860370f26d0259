//! The peer: the same sphere scene stepped by rapier3d 0.36 (ball colliders, no friction,
//! restitution combined with `Min`, rotations locked).
//!
//! Rapier works in `f32` (`rapier3d::math::Real`) with glam vectors (`rapier3d::math::Vector`);
//! this module converts from and to the `f64` arrays the benchmark uses.

use rapier3d::prelude::{
    BroadPhaseBvh, CCDSolver, CoefficientCombineRule, ColliderBuilder, ColliderSet,
    ImpulseJointSet, IntegrationParameters, IslandManager, MultibodyJointSet, NarrowPhase,
    PhysicsPipeline, Real, RigidBodyBuilder, RigidBodyHandle, RigidBodySet, SoftBodySet, Vector,
};

/// How rapier's continuous collision detection is set for a run.
///
/// In rapier 0.36 every dynamic body moving fast for its size is swept within its step;
/// `ccd_enabled` only widens what it is swept against. By default (no body asking) against
/// fixed colliders, from a cached list of them; a body with `ccd_enabled` (a "bullet")
/// against every collider but other bullets, through the whole broad-phase tree. With every
/// sphere a bullet, as here, a bullet is swept against nothing a default body is not: the same
/// protection at a higher price. rapier sweeps no sphere against another in either.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RapierCcd {
    /// Rapier's default: fast bodies swept against fixed colliders.
    Default,
    /// Every dynamic body a bullet (`ccd_enabled`).
    Bullets,
    /// None at all (`max_ccd_substeps: 0`; by default rapier sweeps fast bodies against fixed
    /// colliders even where no body asked for CCD).
    Off,
}

/// One sphere of the scene, as handed to rapier.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RapierSphere {
    /// Initial centre position.
    pub position: [f64; 3],
    /// Initial linear velocity.
    pub velocity: [f64; 3],
    /// Ball radius.
    pub radius: f64,
    /// Density; rapier derives the mass from it and the ball volume.
    pub density: f64,
    /// Coefficient of restitution, combined with the other collider's by `Min`.
    pub restitution: f64,
    /// `true` for a fixed (immovable) body, `false` for a dynamic one.
    pub fixed: bool,
}

impl From<&sphere_physics::SphereDesc> for RapierSphere {
    fn from(d: &sphere_physics::SphereDesc) -> Self {
        Self {
            position: d.position.to_array(),
            velocity: d.velocity.to_array(),
            radius: d.radius,
            density: d.density,
            restitution: d.restitution,
            fixed: d.fixed,
        }
    }
}

/// World-wide settings for the rapier peer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RapierConfig {
    /// Gravity applied to every dynamic body.
    pub gravity: [f64; 3],
    /// Time step of one [`RapierWorld::step`].
    pub dt: f64,
    /// Continuous collision detection (see [`RapierCcd`]).
    pub ccd: RapierCcd,
    /// Rapier's `IntegrationParameters::length_unit`, which scales its tolerances (0.36's docs:
    /// how many world units make a metre; the benches use the spheres' diameter, faster).
    pub length_unit: f64,
    /// Rapier's `IntegrationParameters::num_solver_iterations` (values below 1 are raised to 1).
    pub solver_iterations: usize,
    /// Fixed spheres at least [`WALL_RATIO`] times the smallest dynamic sphere's radius (the
    /// gas's walls) become rapier half-spaces, tangent where the sphere is nearest the dynamic
    /// spheres' centroid: rapier's own shape for a wall, instead of a ball whose centre, 10⁴ m
    /// away, `f32` places only to a millimetre. Any fixed sphere that large counts (a planet
    /// used as a floor too), unless the centroid lies inside it (then it stays a ball).
    pub flat_walls: bool,
}

/// How many times the smallest dynamic sphere a fixed sphere's radius must be to be a wall
/// (see [`RapierConfig::flat_walls`]).
pub const WALL_RATIO: f64 = 1000.0;

/// A rapier3d world holding the sphere scene, with everything `PhysicsPipeline::step` needs.
pub struct RapierWorld {
    /// Gravity passed to each step.
    pub gravity: Vector,
    /// Integration parameters (time step, length unit, solver iterations).
    pub integration_parameters: IntegrationParameters,
    /// The physics pipeline (workspace buffers).
    pub physics_pipeline: PhysicsPipeline,
    /// Island (sleep/activation) manager.
    pub islands: IslandManager,
    /// Broad phase.
    pub broad_phase: BroadPhaseBvh,
    /// Narrow phase.
    pub narrow_phase: NarrowPhase,
    /// All rigid bodies, one per sphere.
    pub bodies: RigidBodySet,
    /// All colliders, one ball per sphere.
    pub colliders: ColliderSet,
    /// Impulse joints (always empty).
    pub impulse_joints: ImpulseJointSet,
    /// Multibody joints (always empty).
    pub multibody_joints: MultibodyJointSet,
    /// Soft bodies (always empty; required by `PhysicsPipeline::step` in 0.36).
    pub soft_bodies: SoftBodySet,
    /// Continuous collision detection solver.
    pub ccd_solver: CCDSolver,
    /// Rigid-body handles in input order.
    pub handles: Vec<RigidBodyHandle>,
}

/// Converts an `f64` triple to a rapier vector.
fn to_vector(v: [f64; 3]) -> Vector {
    Vector::new(v[0] as Real, v[1] as Real, v[2] as Real)
}

/// Converts a rapier vector to an `f64` triple.
fn from_vector(v: Vector) -> [f64; 3] {
    [f64::from(v.x), f64::from(v.y), f64::from(v.z)]
}

impl RapierWorld {
    /// Builds the world: one rigid body with one ball collider per sphere, in input order.
    pub fn new(spheres: &[RapierSphere], config: &RapierConfig) -> Self {
        let mut bodies = RigidBodySet::new();
        let mut colliders = ColliderSet::new();
        let mut handles = Vec::with_capacity(spheres.len());
        let dynamic = || spheres.iter().filter(|s| !s.fixed);
        let smallest = dynamic().map(|s| s.radius).fold(f64::INFINITY, f64::min);
        let count = dynamic().count().max(1) as f64;
        let centroid = dynamic().fold([0.0; 3], |c, s| {
            [0, 1, 2].map(|k| c[k] + s.position[k] / count)
        });

        for sphere in spheres {
            // The plane tangent to a wall sphere where it is nearest the centroid.
            let to_centroid = [0, 1, 2].map(|k| centroid[k] - sphere.position[k]);
            let length = to_centroid.iter().map(|x| x * x).sum::<f64>().sqrt();
            let wall = config.flat_walls
                && sphere.fixed
                && sphere.radius >= WALL_RATIO * smallest
                && length > sphere.radius
                && length.is_finite();
            let (place, shape) = if wall {
                let normal = to_centroid.map(|x| x / length);
                let point = [0, 1, 2].map(|k| sphere.position[k] + normal[k] * sphere.radius);
                let outward = rapier3d::na::Unit::new_unchecked(to_vector(normal).normalize());
                (point, ColliderBuilder::halfspace(outward))
            } else {
                (
                    sphere.position,
                    ColliderBuilder::ball(sphere.radius as Real).density(sphere.density as Real),
                )
            };
            let builder = if sphere.fixed {
                RigidBodyBuilder::fixed()
            } else {
                RigidBodyBuilder::dynamic().ccd_enabled(config.ccd == RapierCcd::Bullets)
            };
            let body = builder
                .translation(to_vector(place))
                .linvel(to_vector(sphere.velocity))
                .lock_rotations()
                .build();
            let handle = bodies.insert(body);

            let collider = shape
                .restitution(sphere.restitution as Real)
                .restitution_combine_rule(CoefficientCombineRule::Min)
                .friction(0.0)
                .friction_combine_rule(CoefficientCombineRule::Min)
                .build();
            colliders.insert_with_parent(collider, handle, &mut bodies);
            handles.push(handle);
        }

        // No speed cap: by default rapier clamps speeds to 400 length units per second (8 m/s
        // at the `length_unit` 0.02 of the accuracy report's tunnelling test, 40 m/s at the
        // scale benches' 0.1), which would slow the fast spheres of a scene rather than
        // simulate them. Its docs: `Real::MAX` disables the cap.
        let integration_parameters = IntegrationParameters {
            dt: config.dt as Real,
            length_unit: config.length_unit as Real,
            num_solver_iterations: config.solver_iterations.max(1),
            normalized_max_linear_velocity: Real::MAX,
            // rapier's global CCD switch: by default (1) fast bodies are swept against fixed
            // colliders even where no body asked for CCD.
            max_ccd_substeps: usize::from(config.ccd != RapierCcd::Off),
            ..IntegrationParameters::default()
        };

        Self {
            gravity: to_vector(config.gravity),
            integration_parameters,
            physics_pipeline: PhysicsPipeline::new(),
            islands: IslandManager::new(),
            broad_phase: BroadPhaseBvh::new(),
            narrow_phase: NarrowPhase::new(),
            bodies,
            colliders,
            impulse_joints: ImpulseJointSet::new(),
            multibody_joints: MultibodyJointSet::new(),
            soft_bodies: SoftBodySet::new(),
            ccd_solver: CCDSolver::new(),
            handles,
        }
    }

    /// Advances the simulation by one `config.dt`, with no hooks and no event handler.
    pub fn step(&mut self) {
        self.physics_pipeline.step(
            self.gravity,
            &self.integration_parameters,
            &mut self.islands,
            &mut self.broad_phase,
            &mut self.narrow_phase,
            &mut self.bodies,
            &mut self.colliders,
            &mut self.impulse_joints,
            &mut self.multibody_joints,
            &mut self.soft_bodies,
            &mut self.ccd_solver,
            &(),
            &(),
        );
    }

    /// Number of spheres.
    pub fn len(&self) -> usize {
        self.handles.len()
    }

    /// Whether the world holds no sphere.
    pub fn is_empty(&self) -> bool {
        self.handles.is_empty()
    }

    /// Sphere `i`'s centre (input order).
    pub fn position(&self, i: usize) -> [f64; 3] {
        from_vector(self.bodies[self.handles[i]].translation())
    }

    /// Sphere `i`'s linear velocity (input order).
    pub fn velocity(&self, i: usize) -> [f64; 3] {
        from_vector(self.bodies[self.handles[i]].linvel())
    }

    /// Sphere centres, in input order.
    pub fn positions(&self) -> Vec<[f64; 3]> {
        self.handles
            .iter()
            .map(|&h| from_vector(self.bodies[h].translation()))
            .collect()
    }

    /// Sphere linear velocities, in input order.
    pub fn velocities(&self) -> Vec<[f64; 3]> {
        self.handles
            .iter()
            .map(|&h| from_vector(self.bodies[h].linvel()))
            .collect()
    }

    /// Dynamic bodies asleep (rapier's sleeping is on, as by default).
    pub fn asleep(&self) -> usize {
        self.handles
            .iter()
            .map(|&h| &self.bodies[h])
            .filter(|body| body.is_dynamic() && body.is_sleeping())
            .count()
    }

    /// Translational kinetic energy `Σ ½ m v²` of the dynamic bodies, with rapier's masses.
    pub fn kinetic_energy(&self) -> f64 {
        self.handles
            .iter()
            .map(|&h| &self.bodies[h])
            .filter(|body| body.is_dynamic())
            .map(|body| {
                let [vx, vy, vz] = from_vector(body.linvel());
                0.5 * f64::from(body.mass()) * (vx * vx + vy * vy + vz * vz)
            })
            .sum()
    }
}
