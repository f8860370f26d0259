//! What a step did and the state it left: collisions, energy, momentum, overlap.

use std::time::Duration;

use glam::DVec3;

use crate::BodyId;

/// Statistics of one step, as returned by [`World::step`](crate::World::step).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepStats {
    /// Simulated time at the end of the step.
    pub time: f64,
    /// Length of the step.
    pub dt: f64,
    /// Contacts resolved, resting contacts included: one per record in
    /// [`World::collisions`](crate::World::collisions). A contact of a simultaneous group that
    /// needed no impulse counts (its record's impulse is 0), and a resting contact solved again
    /// at the same instant, together with a later impact it joins, counts again. Not
    /// counted: a squeeze's contacts (its impacts, and the touching contacts solved with them)
    /// that took no impulse (none, or one too small to change a velocity), a squeeze being
    /// how an inelastic collapse, or a light sphere bouncing between heavier ones, is ended
    /// (see [`Settings::max_collisions_per_body`](crate::Settings::max_collisions_per_body)).
    pub collisions: u32,
    /// Of those, collisions slower than the relative acceleration gains in
    /// [`Settings::resting_factor`](crate::Settings::resting_factor) steps, resolved with
    /// restitution 0 so that bodies at rest stay at rest.
    pub resting_contacts: u32,
    /// Impacts found but not resolved because a body's share of the step's budget
    /// ([`Settings::max_collisions_per_body`](crate::Settings::max_collisions_per_body)) ran out,
    /// or between bodies the fallback solve left alone once the whole budget did, or pairs its
    /// rounds ran out before, or pairs with a body on a string that it found could meet (it
    /// holds no string); an impact found again after one of its bodies changed counts again.
    /// Non-zero means the step was cut short: bodies may be left overlapping until the next
    /// step.
    pub collisions_deferred: u32,
    /// The step's collision budget ran out and the rest of the step was solved at once,
    /// restitution 0 (see
    /// [`Settings::max_collisions_per_body`](crate::Settings::max_collisions_per_body)).
    pub fell_back: bool,
    /// Pairs handed to the time-of-impact method. A pair closing all along the step and still
    /// apart at its end (beyond contact by the tolerance and a millionth of the reach) is not
    /// handed to a built-in method, which would report no impact (unless it moves more than a
    /// million reaches in the step).
    pub toi_tests: u64,
    /// Iterations the time-of-impact method spent (bisection steps; 0 for the exact method).
    pub toi_iterations: u64,
    /// Kinetic energy of the dynamic bodies at the end of the step.
    pub kinetic_energy: f64,
    /// Potential energy of the dynamic bodies in gravity and their constant applied forces,
    /// `-(m g + F) . x`, at the end of the step.
    pub potential_energy: f64,
    /// Total momentum of the dynamic bodies at the end of the step.
    pub momentum: DVec3,
    /// Largest overlap (sum of radii minus centre distance) between any two bodies, at least one
    /// of them dynamic, at the end of the step; 0 if none overlap.
    pub max_overlap: f64,
    /// Spheres moved apart by their positions at the end of the step, from overlaps left
    /// with nothing accelerating (no gravity, no applied force), or from pairs with a sphere
    /// on a string left more than 2% of a radius deep: see
    /// [`World::step`](crate::World::step). Summed over the step's substeps.
    pub separated: u32,
    /// Bodies asleep at the end of the step (see [`Settings::sleep`](crate::Settings::sleep)).
    pub asleep: u32,
    /// The step moved nothing: every dynamic body was asleep, no fixed one moving, and
    /// nothing had been changed through the world since the last step (see
    /// [`Settings::sleep`](crate::Settings::sleep)). Every body's position and velocity are
    /// as they were before it, to the bit.
    pub quiet: bool,
}

impl StepStats {
    /// Kinetic plus potential energy.
    pub fn total_energy(&self) -> f64 {
        self.kinetic_energy + self.potential_energy
    }
}

/// One resolved collision, as listed by [`World::collisions`](crate::World::collisions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Collision {
    /// The body with the smaller id.
    pub a: BodyId,
    /// The body with the larger id.
    pub b: BodyId,
    /// Simulated time of the impact.
    pub time: f64,
    /// Unit normal from `a`'s centre to `b`'s at impact.
    pub normal: DVec3,
    /// The contact point on `a`'s surface.
    pub point: DVec3,
    /// Magnitude of the impulse applied along the normal (momentum transferred).
    pub impulse: f64,
    /// Whether this was treated as a resting contact (restitution 0).
    pub resting: bool,
}

/// Wall time of one step's phases, from [`World::profile`](crate::World::profile) once
/// [`World::set_profiling`](crate::World::set_profiling) is on (summed over the step's
/// substeps). Timing costs a few clock reads per step (well under a microsecond); the physics
/// is the same, bit for bit, with it on or off.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepProfile {
    /// Forces and the integrator's kicks, each body's drift and swept box.
    pub integrate: Duration,
    /// The broad phase's sort into cells, and gathering the bodies into that order.
    pub sort: Duration,
    /// Laying out the grid and rebuilding the hierarchy.
    pub build: Duration,
    /// Every pair whose boxes meet: resting contacts found, first impacts queued.
    pub first_pass: Duration,
    /// Solving the resting contacts together, and re-testing the bodies that moved.
    pub resting: Duration,
    /// The impacts in time order, each followed by re-testing its bodies' pairs.
    pub events: Duration,
    /// Positions and velocities written back, energies and momentum summed.
    pub write_back: Duration,
    /// The largest overlap left at the end of the step, and with nothing accelerating the
    /// moves apart of overlapping spheres (see [`World::step`](crate::World::step)).
    pub overlap: Duration,
}

impl StepProfile {
    /// The phases' sum: the solver's whole step.
    pub fn total(&self) -> Duration {
        self.integrate
            + self.sort
            + self.build
            + self.first_pass
            + self.resting
            + self.events
            + self.write_back
            + self.overlap
    }
}

impl std::ops::AddAssign for StepProfile {
    /// Adds each phase's time (to sum the profiles of many steps).
    fn add_assign(&mut self, other: Self) {
        self.integrate += other.integrate;
        self.sort += other.sort;
        self.build += other.build;
        self.first_pass += other.first_pass;
        self.resting += other.resting;
        self.events += other.events;
        self.write_back += other.write_back;
        self.overlap += other.overlap;
    }
}
