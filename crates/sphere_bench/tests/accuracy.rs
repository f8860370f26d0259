//! The speed-against-error report's scenarios score engines against analytic answers: exact
//! answers score (near) zero, broken engines score large or NaN, never a small error.

use sphere_bench::accuracy::{
    Cradle, Engine, LightOnHeavy, Oblique, Ours, Scenario, Scene, TetheredCradle, scenarios,
    tunnelling_speed,
};
use sphere_bench::svg::{Panel, Series, render};
use sphere_physics::ToiMethod;
use sphere_physics::glam::DVec3;

/// Runs `scenario` with our engine at `hz` steps per second, as the report does.
fn score(scenario: &dyn Scenario, method: ToiMethod, hz: u32) -> (f64, Option<f64>) {
    let scene = scenario.scene();
    let dt = 1.0 / f64::from(hz);
    let steps = (scenario.duration() * f64::from(hz)).round() as u64;
    let mut engine = Ours::new(&scene, method, dt);
    scenario.run_with_extra(&scene, &mut engine, dt, steps)
}

/// An engine whose spheres never move.
struct Frozen(Scene);

impl Engine for Frozen {
    fn step(&mut self) {}
    fn count(&self) -> usize {
        self.0.spheres.len()
    }
    fn position(&self, i: usize) -> DVec3 {
        self.0.spheres[i].position
    }
    fn velocity(&self, i: usize) -> DVec3 {
        self.0.spheres[i].velocity
    }
}

/// Our engine, but its readings turn to NaN after `after` steps.
struct Poisoned {
    inner: Ours,
    steps: u64,
    after: u64,
}

impl Engine for Poisoned {
    fn step(&mut self) {
        self.inner.step();
        self.steps += 1;
    }
    fn count(&self) -> usize {
        self.inner.count()
    }
    fn position(&self, i: usize) -> DVec3 {
        if self.steps > self.after {
            DVec3::NAN
        } else {
            self.inner.position(i)
        }
    }
    fn velocity(&self, i: usize) -> DVec3 {
        if self.steps > self.after {
            DVec3::NAN
        } else {
            self.inner.velocity(i)
        }
    }
}

#[test]
fn exact_method_scores_the_oblique_collision_and_the_touching_cradle_exactly() {
    let (oblique, _) = score(&Oblique, ToiMethod::Exact, 60);
    assert!(oblique < 1e-12, "oblique two-body error {oblique:e}");
    for hz in [30, 60, 960] {
        let (cradle, _) = score(&Cradle, ToiMethod::Exact, hz);
        assert_eq!(cradle, 0.0, "touching cradle at {hz} steps/s");
    }
}

#[test]
fn light_on_heavy_apex_matches_the_analytic_rebound_within_a_percent() {
    for hz in [60, 960] {
        let (error, _) = score(&LightOnHeavy, ToiMethod::Exact, hz);
        assert!(error < 1e-2, "light on heavy at {hz} steps/s: {error:e}");
    }
}

#[test]
fn tethered_cradle_peaks_are_scored_from_the_swing_not_the_first_step() {
    // At 30 steps/s the first step's fall from rest was once counted as a peak (1e-2 of error
    // from nothing). The swing itself at 960 steps/s keeps its peaks to a few parts in 1e5.
    let (fine, _) = score(&TetheredCradle, ToiMethod::Exact, 960);
    assert!(fine > 0.0 && fine < 2e-4, "960 steps/s: {fine:e}");
    let (coarse, _) = score(&TetheredCradle, ToiMethod::Exact, 30);
    assert!(coarse.is_finite() && coarse < 0.1, "30 steps/s: {coarse:e}");
}

#[test]
fn an_engine_that_does_nothing_scores_a_failure() {
    let scene = TetheredCradle.scene();
    let mut frozen = Frozen(scene.clone());
    assert_eq!(
        TetheredCradle.run(&scene, &mut frozen, 1.0 / 60.0, 3600),
        1.0
    );
    let scene = Oblique.scene();
    let mut frozen = Frozen(scene.clone());
    assert!(Oblique.run(&scene, &mut frozen, 1.0 / 60.0, 60) > 0.5);
    let scene = Cradle.scene();
    let mut frozen = Frozen(scene.clone());
    assert!(Cradle.run(&scene, &mut frozen, 1.0 / 60.0, 60) > 0.5);
}

#[test]
fn an_engine_whose_state_turns_to_nan_scores_nan_in_every_scenario() {
    for scenario in scenarios() {
        let scene = scenario.scene();
        let dt = 1.0 / 60.0;
        let steps = (scenario.duration() * 60.0).round() as u64;
        let mut engine = Poisoned {
            inner: Ours::new(&scene, ToiMethod::Exact, dt),
            steps: 0,
            after: 5,
        };
        let (error, extra) = scenario.run_with_extra(&scene, &mut engine, dt, steps);
        assert!(error.is_nan(), "{}: {error:e}", scenario.name());
        if let Some(extra) = extra {
            assert!(extra.is_nan(), "{}: also {extra:e}", scenario.name());
        }
    }
}

#[test]
fn scores_are_bit_for_bit_the_same_run_after_run() {
    for scenario in scenarios() {
        let first = score(scenario.as_ref(), ToiMethod::Exact, 60);
        let second = score(scenario.as_ref(), ToiMethod::Exact, 60);
        assert_eq!(
            (first.0.to_bits(), first.1.map(f64::to_bits)),
            (second.0.to_bits(), second.1.map(f64::to_bits)),
            "{}",
            scenario.name()
        );
    }
}

#[test]
fn exact_never_tunnels_and_one_bisection_step_does_at_walking_speed() {
    let dt = 1.0 / 60.0;
    let mut exact =
        |scene: &Scene| -> Box<dyn Engine> { Box::new(Ours::new(scene, ToiMethod::Exact, dt)) };
    assert_eq!(tunnelling_speed(&mut exact, dt), None);
    let mut bisection = |scene: &Scene| -> Box<dyn Engine> {
        Box::new(Ours::new(
            scene,
            ToiMethod::Bisection { max_iterations: 1 },
            dt,
        ))
    };
    // Radius 0.01 spheres, 1/60 s: a sphere moving 1.2 m/s travels their touching distance in
    // a step, so one that only looks at a step's end misses from a few m/s on.
    let missed = tunnelling_speed(&mut bisection, dt).expect("bisection tunnels");
    assert!(missed <= 10.0, "missed from {missed} m/s");
}

/// One panel with one series, "s" in #123456, of `points`.
fn plot(points: Vec<(f64, f64)>) -> String {
    let panel = Panel {
        title: "t".into(),
        y_label: "error".into(),
        series: vec![Series {
            name: "s".into(),
            colour: "#123456",
            points,
        }],
    };
    render(&[panel], 1)
}

#[test]
fn the_plot_leaves_out_failed_runs_and_draws_exact_answers_hollow() {
    let svg = plot(vec![
        (1e-3, 0.0),
        (2e-3, 1e-3),
        (3e-3, f64::NAN),
        (4e-3, f64::INFINITY),
        (0.0, 1e-3),
    ]);
    assert!(svg.contains("s (3 failed, not drawn)"), "{svg}");
    assert_eq!(svg.matches("<circle").count(), 2, "{svg}");
    assert_eq!(svg.matches(r##"fill="white" stroke="#123456""##).count(), 1);
    assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
}

/// A striker (sphere 0) moving freely along x, turned round by `turn` after each step.
struct Striker {
    p: DVec3,
    v: DVec3,
    dt: f64,
    turn: fn(&mut DVec3, &mut DVec3),
}

impl Engine for Striker {
    fn step(&mut self) {
        self.p += self.v * self.dt;
        (self.turn)(&mut self.p, &mut self.v);
    }
    fn count(&self) -> usize {
        2
    }
    fn position(&self, i: usize) -> DVec3 {
        if i == 0 { self.p } else { DVec3::ZERO }
    }
    fn velocity(&self, i: usize) -> DVec3 {
        if i == 0 { self.v } else { DVec3::ZERO }
    }
}

/// Review of 2026-12-01: the tunnelling test took a striker moving back (negative velocity)
/// as caught wherever it was; rapier with CCD pushed a fast striker out on the far side of the
/// target, or left it caught inside, turning round every step, and was reported as catching
/// every speed. A striker must come back out on its own side, moving away.
#[test]
fn a_striker_that_passes_through_or_is_caught_in_the_target_has_missed() {
    let dt = 1.0 / 60.0;
    let engine = |turn: fn(&mut DVec3, &mut DVec3)| {
        move |scene: &Scene| -> Box<dyn Engine> {
            Box::new(Striker {
                p: scene.spheres[0].position,
                v: scene.spheres[0].velocity,
                dt,
                turn,
            })
        }
    };
    // Passes straight through.
    assert_eq!(tunnelling_speed(&mut engine(|_, _| {}), dt), Some(1.0));
    // Caught: turned round whenever it crosses the target's centre.
    let caught = |p: &mut DVec3, v: &mut DVec3| {
        if p.x.signum() == v.x.signum() && p.x.abs() < 0.1 {
            *v = -*v;
        }
    };
    assert_eq!(tunnelling_speed(&mut engine(caught), dt), Some(1.0));
    // Reflected at contact: never missed.
    let bounce = |p: &mut DVec3, v: &mut DVec3| {
        if p.x > -0.02 && v.x > 0.0 {
            p.x = -0.04 - p.x;
            *v = -*v;
        }
    };
    assert_eq!(tunnelling_speed(&mut engine(bounce), dt), None);
}

#[test]
fn the_plot_breaks_a_series_line_at_a_failed_run() {
    let svg = plot(vec![
        (1e-3, 1e-3),
        (2e-3, 1e-4),
        (3e-3, f64::NAN),
        (4e-3, 1e-5),
        (5e-3, 1e-6),
    ]);
    assert_eq!(svg.matches("<polyline").count(), 2, "{svg}");
}

/// An engine whose spheres fly on through one another and through the walls, energy and
/// momentum kept.
struct Ghost(Scene, f64);

impl Engine for Ghost {
    fn step(&mut self) {
        let dt = self.1;
        for s in &mut self.0.spheres {
            s.position += s.velocity * dt;
        }
    }
    fn count(&self) -> usize {
        self.0.spheres.len()
    }
    fn position(&self, i: usize) -> DVec3 {
        self.0.spheres[i].position
    }
    fn velocity(&self, i: usize) -> DVec3 {
        self.0.spheres[i].velocity
    }
}

#[test]
fn the_gas_in_a_box_sees_collisions_missed_where_its_energy_cannot() {
    // Its energy drift, the error, is exact for an engine that misses every collision: the
    // deepest overlap beside it is what shows them (found by review, sixty-third session).
    let gas = scenarios()
        .into_iter()
        .find(|s| s.name().contains("in a box"))
        .expect("the gas in a box");
    let scene = gas.scene();
    let dt = 1.0 / 60.0;
    let mut ghost = Ghost(scene.clone(), dt);
    let (error, deepest, _) = gas.run_checked(&scene, &mut ghost, dt, 60);
    assert_eq!(error, 0.0);
    let deepest = deepest.expect("the deepest overlap");
    assert!(deepest > 0.5, "{deepest}");
    // Ours meets and parts without overlapping.
    let mut ours = Ours::new(&scene, ToiMethod::Exact, dt);
    let (error, deepest, _) = gas.run_checked(&scene, &mut ours, dt, 60);
    assert!(error < 1e-12, "{error:e}");
    assert_eq!(deepest, Some(0.0));
}
