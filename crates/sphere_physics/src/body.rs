//! Sphere bodies: their description, validation and the read-only view the world hands out.

use std::f64::consts::PI;
use std::fmt;

use glam::DVec3;

/// The largest radius a sphere may have, 1e150 m: the squared distances the collision tests
/// use would overflow an f64 for larger spheres (and a sphere that large resolves nothing
/// smaller than some 1e134 m on its surface anyway).
pub const MAX_RADIUS: f64 = 1e150;

/// The largest mass a moving sphere may have, 1e200 kg: the impulse between two such spheres
/// (mass times speed) stays within an f64 for any speed below 1e108 m/s. Heavier spheres
/// overflowed it, and the world refused every step from then on. A fixed sphere has no mass
/// and no limit.
pub const MAX_MASS: f64 = 1e200;

/// The smallest mass a moving sphere may have, 1e-300 kg: its inverse, at most 1e300, leaves
/// the sums of a few inverse masses that every impulse divides by within an f64. Lighter
/// spheres (below about 1.1e-308 kg) overflowed that sum to infinity: two of them met with no
/// impulse and passed through each other, and their resting contacts carried no load.
pub const MIN_MASS: f64 = 1e-300;

/// Stable identifier of a body in a [`World`](crate::World). Ids are never reused (64 bits: a
/// world adding a million spheres a second runs out after half a million years). Ties between
/// simultaneous events are broken by a deterministic order (ids in small scenes, the broad
/// phase's spatial order in large ones), so results never depend on hash order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct BodyId(pub(crate) u64);

impl BodyId {
    /// The id as a number: bodies are numbered 0, 1, 2, ... in the order they were added, and
    /// a removed body's number is never given again. Not an index into
    /// [`World::bodies`](crate::World::bodies) once a body has been removed: look bodies up
    /// with [`World::body`](crate::World::body).
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Display for BodyId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}", self.0)
    }
}

/// Everything needed to add a sphere to a world. Build one with [`SphereDesc::new`] and the
/// builder methods ([`SphereDesc::at`], [`SphereDesc::moving`], [`SphereDesc::with_density`],
/// [`SphereDesc::fixed`], ...); [`World::add_sphere`](crate::World::add_sphere) validates it.
#[derive(Clone, Debug, PartialEq)]
pub struct SphereDesc {
    /// Optional name, used in error messages and by scene files.
    pub name: Option<String>,
    /// Centre position.
    pub position: DVec3,
    /// Linear velocity.
    pub velocity: DVec3,
    /// Radius, `> 0`.
    pub radius: f64,
    /// Density, `> 0`; mass is density times volume.
    pub density: f64,
    /// Coefficient of restitution in `[0, 1]`: 1 is perfectly elastic.
    pub restitution: f64,
    /// Constant applied force (on top of gravity).
    pub force: DVec3,
    /// Fixed bodies have infinite mass: collisions never move them, gravity and forces do not act
    /// on them. A fixed body with a velocity moves at that constant velocity (a kinematic body).
    pub fixed: bool,
    /// An inextensible string to a fixed anchor (pulls, never pushes). Ignored on fixed bodies.
    pub tether: Option<Tether>,
    /// Never falls asleep, nor lets the group of bodies it touches fall asleep (see
    /// [`Settings::sleep`](crate::Settings::sleep)). For a sphere a game pushes with a small
    /// force, or steers slowly: with sleeping on, one moving slower than the sleeping speed for
    /// the sleeping time falls asleep where it is, though its force may not be balanced.
    /// Default false.
    pub never_sleeps: bool,
}

/// An inextensible, massless string from a fixed anchor point to a sphere's centre: the sphere
/// can move anywhere within `length` of the anchor, and the string pulls it back when taut.
///
/// Integrated with RATTLE: at the start of every step (and again after a collision changes the
/// sphere's velocity) the drift over the rest of the step is bent so that it ends exactly at the
/// string's length (the SHAKE correction), and the outward radial velocity is removed at the
/// end. With the [`Leapfrog`](crate::Leapfrog) integrator this is symplectic: a pendulum's energy
/// oscillates within a relative `~(ω·dt)²/8` and does not drift. A string slack when the step
/// begins (its sphere more than a hundredth of its radius inside the length) bends nothing until
/// the sphere's straight free path reaches the length: the sphere moves freely until then, and
/// from that instant the string holds it (its outward velocity removed) and bends its drift.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tether {
    /// The fixed anchor point.
    pub anchor: DVec3,
    /// The string's length, `> 0`.
    pub length: f64,
}

impl SphereDesc {
    /// A sphere of the given radius at the origin, at rest, density 1, restitution 1.
    pub fn new(radius: f64) -> Self {
        SphereDesc {
            name: None,
            position: DVec3::ZERO,
            velocity: DVec3::ZERO,
            radius,
            density: 1.0,
            restitution: 1.0,
            force: DVec3::ZERO,
            fixed: false,
            tether: None,
            never_sleeps: false,
        }
    }

    /// Sets the name.
    pub fn named(mut self, name: impl Into<String>) -> Self {
        self.name = Some(name.into());
        self
    }

    /// Sets the position.
    pub fn at(mut self, position: DVec3) -> Self {
        self.position = position;
        self
    }

    /// Sets the velocity.
    pub fn moving(mut self, velocity: DVec3) -> Self {
        self.velocity = velocity;
        self
    }

    /// Sets the density.
    pub fn with_density(mut self, density: f64) -> Self {
        self.density = density;
        self
    }

    /// Sets the restitution.
    pub fn with_restitution(mut self, restitution: f64) -> Self {
        self.restitution = restitution;
        self
    }

    /// Sets the constant applied force.
    pub fn with_force(mut self, force: DVec3) -> Self {
        self.force = force;
        self
    }

    /// Hangs the sphere on a string of `length` from `anchor`.
    pub fn tethered(mut self, anchor: DVec3, length: f64) -> Self {
        self.tether = Some(Tether { anchor, length });
        self
    }

    /// Makes the body fixed (infinite mass).
    pub fn fixed(mut self) -> Self {
        self.fixed = true;
        self
    }

    /// Keeps the body, and the group of bodies it touches, from falling asleep (see
    /// [`SphereDesc::never_sleeps`]).
    pub fn never_sleeping(mut self) -> Self {
        self.never_sleeps = true;
        self
    }

    /// [`SphereDesc::validate`], and the acceleration with the world's `gravity` finite (a
    /// force and gravity each within range may still sum past it: every step was then
    /// refused, blaming the velocity). A gravity that is not finite is the settings' fault,
    /// not the sphere's: [`World::step`](crate::World::step) refuses it, naming the setting
    /// (until the sixty-first session such a world refused every sphere, blaming its force).
    pub(crate) fn validate_under(
        &self,
        gravity: DVec3,
        label: impl Fn() -> String,
    ) -> Result<(), BodyError> {
        self.validate(&label)?;
        if !self.fixed && gravity.is_finite() {
            // As `Body::acceleration` has it.
            let acceleration = gravity + self.force * (1.0 / mass_of(self.density, self.radius));
            if !acceleration.is_finite() {
                let k = (0..3).find(|&k| !acceleration[k].is_finite()).unwrap_or(0);
                return Err(BodyError {
                    body: label(),
                    id: None,
                    field: Field::Force,
                    value: self.force[k],
                    reason: "with gravity must give a finite acceleration",
                });
            }
        }
        Ok(())
    }

    /// Checks every field; `label` names the body in the error.
    pub(crate) fn validate(&self, label: impl Fn() -> String) -> Result<(), BodyError> {
        let err = |field, value: f64, reason| BodyError {
            body: label(),
            id: None,
            field,
            value,
            reason,
        };
        for (field, v) in [
            (Field::Position, self.position),
            (Field::Velocity, self.velocity),
            (Field::Force, self.force),
        ] {
            if let Some(bad) = v.to_array().into_iter().find(|c| !c.is_finite()) {
                return Err(err(field, bad, "must be finite"));
            }
        }
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return Err(err(Field::Radius, self.radius, "must be finite and > 0"));
        }
        if self.radius > MAX_RADIUS {
            return Err(err(
                Field::Radius,
                self.radius,
                "must be at most 1e150 (squared distances to the sphere would overflow)",
            ));
        }
        if !(self.density.is_finite() && self.density > 0.0) {
            return Err(err(Field::Density, self.density, "must be finite and > 0"));
        }
        if !(0.0..=1.0).contains(&self.restitution) {
            return Err(err(
                Field::Restitution,
                self.restitution,
                "must be in [0, 1]",
            ));
        }
        // A fixed body ignores its tether (see `SphereDesc::tether`), so nothing to check.
        if let Some(tether) = self.tether.filter(|_| !self.fixed) {
            if let Some(bad) = tether
                .anchor
                .to_array()
                .into_iter()
                .find(|c| !c.is_finite())
            {
                return Err(err(Field::Tether, bad, "anchor must be finite"));
            }
            if !(tether.length.is_finite() && tether.length > 0.0) {
                return Err(err(
                    Field::Tether,
                    tether.length,
                    "length must be finite and > 0",
                ));
            }
            let distance = (self.position - tether.anchor).length();
            // A billionth of the length, and the rounding of coordinates as far out as these
            // (the world puts a sphere back on its string at `anchor + normal · length`,
            // rounded there: a string of a centimetre a kilometre out failed a billionth).
            let far = self.position.abs().max(tether.anchor.abs()).max_element();
            if distance > tether.length * (1.0 + 1e-9) + 4.0 * f64::EPSILON * far {
                return Err(err(
                    Field::Tether,
                    distance,
                    "leaves the sphere farther from its anchor than the string's length",
                ));
            }
        }
        // The mass `Body::new` will use: from `MIN_MASS` to `MAX_MASS`. The radius is to blame
        // when its volume alone (at density 1) is out of range.
        let mass_ok = |density| (MIN_MASS..=MAX_MASS).contains(&mass_of(density, self.radius));
        if !(self.fixed || mass_ok(self.density)) {
            return Err(if mass_ok(1.0) {
                err(
                    Field::Density,
                    self.density,
                    "gives a mass below 1e-300 kg or above 1e200 kg",
                )
            } else {
                err(
                    Field::Radius,
                    self.radius,
                    "gives a volume, and so a mass, below 1e-300 kg or above 1e200 kg",
                )
            });
        }
        // The acceleration the force gives (a finite force on a light sphere may overflow it:
        // every step was then refused, blaming the velocity).
        if !self.fixed {
            let inverse_mass = 1.0 / mass_of(self.density, self.radius);
            if let Some(bad) = self
                .force
                .to_array()
                .into_iter()
                .find(|f| !(f * inverse_mass).is_finite())
            {
                return Err(err(
                    Field::Force,
                    bad,
                    "over the sphere's mass must be a finite acceleration",
                ));
            }
        }
        Ok(())
    }
}

/// The mass of a sphere of `density` and `radius` (one formula for validation and bodies).
fn mass_of(density: f64, radius: f64) -> f64 {
    // r·r·r, not powi: its precision is the platform's to choose.
    let mass = density * 4.0 / 3.0 * PI * (radius * radius * radius);
    if mass.is_normal() {
        return mass;
    }
    // A huge density and a tiny radius (or the reverse) overflow (or underflow) the product
    // in that order though the mass is in range (a radius of 1e-100 at a density of 5e307
    // weighs 2e8 kg): the radius taken in one factor at a time. (Only here, so that every
    // mass the order above gives stays the same to the bit.)
    density * radius * radius * radius * (4.0 / 3.0 * PI)
}

/// Which field of a body an error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// [`SphereDesc::position`].
    Position,
    /// [`SphereDesc::velocity`].
    Velocity,
    /// [`SphereDesc::radius`].
    Radius,
    /// [`SphereDesc::density`].
    Density,
    /// [`SphereDesc::restitution`].
    Restitution,
    /// [`SphereDesc::force`].
    Force,
    /// [`SphereDesc::tether`].
    Tether,
}

impl Field {
    /// The field's name, as scene files spell it.
    pub fn name(self) -> &'static str {
        match self {
            Field::Position => "position",
            Field::Velocity => "velocity",
            Field::Radius => "radius",
            Field::Density => "density",
            Field::Restitution => "restitution",
            Field::Force => "force",
            Field::Tether => "tether",
        }
    }
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An invalid body: which one, which field, the offending value and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("sphere {body}: {field} {reason}, got {}", crate::Readable(*.value))]
pub struct BodyError {
    /// The body: `'name' (#id)` if it has a name, else `#id`, with its [`BodyId`] (for a sphere
    /// being added, the id it would get: in a scene built into a new world, its index in the
    /// scene's spheres).
    pub body: String,
    /// The body's id when it is in a world (a change to it, or a step it would overflow);
    /// `None` for a sphere being added.
    pub id: Option<crate::BodyId>,
    /// The offending field.
    pub field: Field,
    /// The offending value (one component for vectors).
    pub value: f64,
    /// What the value must be.
    pub reason: &'static str,
}

/// A body in a world: read-only; change it through the world's setters so it stays valid.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub(crate) id: BodyId,
    pub(crate) desc: SphereDesc,
    pub(crate) inverse_mass: f64,
    /// Asleep (see [`Settings::sleep`](crate::Settings::sleep)): at rest, no force acting.
    pub(crate) asleep: bool,
    // The rest of its sleeping state is kept beside the bodies (`crate::sleep::SleepState`):
    // every step reads and writes every body, at 192 bytes a body instead of 232.
}

impl Body {
    pub(crate) fn new(id: BodyId, desc: SphereDesc) -> Self {
        let inverse_mass = if desc.fixed {
            0.0
        } else {
            1.0 / mass_of(desc.density, desc.radius)
        };
        Body {
            id,
            desc,
            inverse_mass,
            asleep: false,
        }
    }

    /// The body's id.
    pub fn id(&self) -> BodyId {
        self.id
    }
    /// The body's name, if it has one.
    pub fn name(&self) -> Option<&str> {
        self.desc.name.as_deref()
    }
    /// Centre position.
    pub fn position(&self) -> DVec3 {
        self.desc.position
    }
    /// Linear velocity.
    pub fn velocity(&self) -> DVec3 {
        self.desc.velocity
    }
    /// Radius.
    pub fn radius(&self) -> f64 {
        self.desc.radius
    }
    /// Density.
    pub fn density(&self) -> f64 {
        self.desc.density
    }
    /// Mass: density times volume; infinite for fixed bodies.
    pub fn mass(&self) -> f64 {
        if self.desc.fixed {
            f64::INFINITY
        } else {
            1.0 / self.inverse_mass
        }
    }
    /// Inverse mass: 0 for fixed bodies.
    pub fn inverse_mass(&self) -> f64 {
        self.inverse_mass
    }
    /// Coefficient of restitution.
    pub fn restitution(&self) -> f64 {
        self.desc.restitution
    }
    /// Constant applied force.
    pub fn force(&self) -> DVec3 {
        self.desc.force
    }
    /// Whether the body is fixed (infinite mass).
    pub fn is_fixed(&self) -> bool {
        self.desc.fixed
    }
    /// What acts on the body under `gravity`, per unit mass: gravity plus its force over its
    /// mass (a fixed body's is not used: nothing moves it).
    pub(crate) fn acceleration(&self, gravity: DVec3) -> DVec3 {
        gravity + self.desc.force * self.inverse_mass
    }
    /// Whether the body is asleep: at rest with every body it touches, neither stepped nor
    /// acted on until something wakes it (see [`Settings::sleep`](crate::Settings::sleep)).
    pub fn is_asleep(&self) -> bool {
        self.asleep
    }
    /// The string the body hangs on, if any (never for fixed bodies).
    pub fn tether(&self) -> Option<Tether> {
        if self.desc.fixed {
            None
        } else {
            self.desc.tether
        }
    }
    /// The description this body would be re-created from.
    pub fn desc(&self) -> &SphereDesc {
        &self.desc
    }
    /// Kinetic energy (0 for fixed bodies).
    pub fn kinetic_energy(&self) -> f64 {
        if self.desc.fixed {
            0.0
        } else {
            0.5 * self.mass() * self.desc.velocity.length_squared()
        }
    }
    /// Momentum (zero for fixed bodies, whose momentum is not defined).
    pub fn momentum(&self) -> DVec3 {
        if self.desc.fixed {
            DVec3::ZERO
        } else {
            self.mass() * self.desc.velocity
        }
    }
}
