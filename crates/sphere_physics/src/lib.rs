//! Exact sphere physics, without Bevy.
//!
//! Spheres with radius, density (so mass), restitution and an optional constant force, fixed
//! (infinite mass) or hanging on a string ([`Tether`]), move under gravity with a
//! kick-drift-kick integrator ([`SemiImplicitEuler`] by default). Within each step, collisions
//! are found by a time-of-impact method ([`ExactToi`], a closed-form swept test, by default; or
//! the classic [`Bisection`]) and resolved in time order with impulses along the lines of
//! centres that conserve momentum, and kinetic energy when elastic. Touching chains propagate
//! contact by contact, so a Newton's cradle with no gaps sends exactly one ball out; impacts
//! at one instant are solved together. Resting contacts (pairs pressed together, closing no
//! faster than a few steps of their acceleration) are solved together at the step's start,
//! with restitution 0, and so is the rest of a step whose collision budget runs out
//! ([`Settings::max_collisions_per_body`]). Overlaps are undone by moving the spheres, never
//! by giving them speed (see [`World::step`]).
//!
//! The parts, each in its own module:
//! - [`body`]: bodies and their validation ([`SphereDesc`], [`Body`], [`BodyError`]);
//! - [`integrator`]: time integration behind the [`Integrator`] trait;
//! - [`contact`]: the narrow phase, [`classify`] two spheres;
//! - [`toi`]: time of impact behind the [`TimeOfImpact`] trait;
//! - [`response`]: the impulse, [`resolve`];
//! - [`world`]: the [`World`] and its [`Settings`];
//! - [`stats`]: what a step did ([`StepStats`], [`Collision`], [`StepProfile`]);
//! - [`tolerance`]: the [`Tolerance`] of every equality test;
//! - [`scene`]: scene files ([`SceneDesc`]);
//! - [`sleep`]: bodies at rest falling asleep ([`Sleep`]);
//! - [`generate`]: seeded generators of many spheres ([`generate::Generator`]).
//!
//! ```
//! use sphere_physics::{glam::DVec3, Settings, SphereDesc, World};
//!
//! // A 5-ball Newton's cradle, balls touching, one striker.
//! let mut world = World::new(Settings::default());
//! let balls: Vec<_> = (0..5)
//!     .map(|i| {
//!         let v = if i == 0 { DVec3::X } else { DVec3::ZERO };
//!         world.add_sphere(SphereDesc::new(0.5).at(DVec3::new(i as f64, 0.0, 0.0)).moving(v))
//!     })
//!     .collect::<Result<_, _>>()?;
//! world.step(1.0 / 60.0)?;
//! assert_eq!(world.body(balls[4]).unwrap().velocity(), DVec3::X);
//! assert!(balls[..4].iter().all(|&b| world.body(b).unwrap().velocity() == DVec3::ZERO));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod body;
mod broad_phase;
pub mod contact;
mod disturbed;
mod dormant;
pub mod generate;
mod instant;
pub mod integrator;
mod queue;
pub mod readable;
pub mod response;
pub mod scene;
pub mod sleep;
mod solver;
pub mod stats;
pub mod toi;
pub mod tolerance;
pub mod world;

pub use body::{
    Body, BodyError, BodyId, Field, MAX_MASS, MAX_RADIUS, MIN_MASS, SphereDesc, Tether,
};
pub use contact::{ContactKind, Kinematics, classify};
pub use glam;
pub use integrator::{Integrator, IntegratorKind, Kicks, Leapfrog, SemiImplicitEuler};
pub use readable::Readable;
pub use response::{CombineRule, GroupContact, Resolution, resolve, resolve_simultaneous};
pub use scene::{MAX_LISTED, MAX_SCENE_BYTES, SceneDesc, SceneError, SphereSpec};
pub use sleep::Sleep;
pub use stats::{Collision, StepProfile, StepStats};
pub use toi::{Bisection, ExactToi, TimeOfImpact, ToiMethod, ToiOutcome};
pub use tolerance::Tolerance;
pub use world::{
    MAX_BISECTION_ITERATIONS, MAX_COLLISIONS_PER_BODY, MAX_SUBSTEPS, Settings, World, WorldError,
};
