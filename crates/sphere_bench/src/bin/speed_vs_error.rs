//! `speed-vs-error`: the work-precision report. Runs every reference scenario (known answers)
//! across our methods (exact; bisection with 1 to 24 iterations) and step sizes (1/30 to
//! 1/960 s), and with `--features rapier` rapier3d 0.36 with its step size and solver
//! iterations swept; writes `docs/speed_vs_error.md` (tables) and `docs/speed_vs_error.svg`
//! (error against cost, log-log, one panel per scenario).
//!
//!     cargo run --release -p sphere_bench --features rapier --bin speed-vs-error [-- --quick]
//!
//! Cost is the median wall time of 3 runs per simulated second (1 with `--quick`).

use std::fmt::Write as _;
use std::time::Instant;

use sphere_bench::accuracy::{Engine, Ours, Scenario, Scene, scenarios, tunnelling_speed};
use sphere_bench::svg::{self, Panel, Series};
use sphere_physics::ToiMethod;

const STEPS_PER_SECOND: [u32; 6] = [30, 60, 120, 240, 480, 960];

/// Set when two runs of one setting scored differently (the program fails at the end).
static UNREPEATABLE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
const BISECTION: [u32; 6] = [1, 2, 4, 8, 16, 24];

/// One measured configuration.
struct Point {
    engine: String,
    hz: u32,
    error: f64,
    extra: Option<f64>,
    cost: f64,
    ns_per_sphere_step: f64,
}

/// A scenario's points, and whether its error is a conserved quantity's drift (see
/// `Scenario::conserved_measure`).
struct Outcome {
    name: String,
    points: Vec<Point>,
    conserved: bool,
}

fn measure(
    scenario: &dyn Scenario,
    make: &mut dyn FnMut(&Scene, f64) -> Box<dyn Engine>,
    hz: u32,
    runs: usize,
) -> (f64, Option<f64>, f64, f64) {
    let scene = scenario.scene();
    let dt = 1.0 / f64::from(hz);
    let steps = (scenario.duration() * f64::from(hz)).round() as u64;
    let mut times = Vec::new();
    let mut outcome: Option<(f64, Option<f64>)> = None;
    for _ in 0..runs {
        let mut engine = make(&scene, dt);
        let started = Instant::now();
        let (error, extra, checking) = scenario.run_checked(&scene, engine.as_mut(), dt, steps);
        times.push(started.elapsed().as_secs_f64() - checking);
        let this = (error, extra);
        // Every run of a setting must score the same, to the bit (both engines are
        // deterministic): a difference is a bug, not noise. Reported, and the report written
        // before the program fails.
        let bits = |(e, x): (f64, Option<f64>)| (e.to_bits(), x.map(f64::to_bits));
        if outcome.is_some_and(|first| bits(first) != bits(this)) {
            eprintln!(
                "speed-vs-error: error: {}: runs at {hz} steps/s scored differently",
                scenario.name()
            );
            UNREPEATABLE.store(true, std::sync::atomic::Ordering::Relaxed);
        }
        outcome = Some(this);
    }
    let (error, extra) = outcome.expect("at least one run");
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    let cost = median / scenario.duration();
    let moving = scene.spheres.iter().filter(|d| !d.fixed).count().max(1);
    let ns = median * 1e9 / (steps as f64 * moving as f64);
    (error, extra, cost, ns)
}

#[cfg(feature = "rapier")]
mod peer {
    use sphere_bench::accuracy::{Engine, Scene};
    use sphere_bench::rapier_peer::{RapierConfig, RapierSphere, RapierWorld};
    use sphere_physics::glam::DVec3;

    pub struct Rapier(pub RapierWorld);

    impl Engine for Rapier {
        fn step(&mut self) {
            self.0.step();
        }
        fn count(&self) -> usize {
            self.0.len()
        }
        fn position(&self, i: usize) -> DVec3 {
            DVec3::from(self.0.position(i))
        }
        fn velocity(&self, i: usize) -> DVec3 {
            DVec3::from(self.0.velocity(i))
        }
    }

    pub fn make(scene: &Scene, dt: f64, iterations: usize) -> Rapier {
        let spheres: Vec<RapierSphere> = scene.spheres.iter().map(RapierSphere::from).collect();
        let smallest = scene
            .spheres
            .iter()
            .filter(|d| !d.fixed)
            .map(|d| d.radius)
            .fold(f64::INFINITY, f64::min);
        Rapier(RapierWorld::new(
            &spheres,
            &RapierConfig {
                gravity: scene.gravity.to_array(),
                dt,
                // rapier's default (as in the scale table): making every body a bullet
                // sweeps nothing more in these scenes (rapier 0.36 sweeps no bullet against
                // another), at up to 1.5x the cost.
                ccd: sphere_bench::rapier_peer::RapierCcd::Default,
                length_unit: 2.0 * smallest,
                solver_iterations: iterations,
                flat_walls: false,
            },
        ))
    }
}

/// The summary's sentences, worked out from the results (so they hold for the run they
/// describe): where the time of impact limits the error, how the methods tunnel, and how
/// rapier does on the touching cradle.
fn findings(results: &[Outcome], missed: &[(String, [Option<f64>; 3])]) -> String {
    let mut out = String::from("\nRead off the tables below:\n\n");
    let error = |points: &[Point], engine: &str, hz: u32| {
        points
            .iter()
            .find(|p| p.engine == engine && p.hz == hz)
            .map(|p| p.error)
    };
    // Exact to rounding everywhere, or limited by something other than the time of impact
    // (exact and the deepest bisection within 10% of each other at every step size).
    let (mut exact, mut kept, mut alike, mut apart) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for Outcome {
        name,
        points,
        conserved,
    } in results
    {
        let pairs: Vec<(f64, f64)> = STEPS_PER_SECOND
            .iter()
            .filter_map(|&hz| {
                Some((
                    error(points, "exact", hz)?,
                    error(points, "bisection:24", hz)?,
                ))
            })
            .collect();
        if pairs.is_empty() {
            continue;
        }
        if pairs.iter().all(|(e, _)| *e < 1e-12) {
            if *conserved { &mut kept } else { &mut exact }.push(name.as_str());
        } else if pairs.iter().all(|(e, b)| (e - b).abs() <= 0.1 * e.max(*b)) {
            alike.push(name.as_str());
        } else {
            apart.push(name.as_str());
        }
    }
    let list = |names: &[&str]| {
        if names.is_empty() {
            "none".to_owned()
        } else {
            names.join("; ")
        }
    };
    let _ = writeln!(
        out,
        "- Exact to rounding (below 1e-12) at every step size: {}.",
        list(&exact)
    );
    let _ = writeln!(
        out,
        "- A conserved quantity's drift below 1e-12 at every step size (elastic impacts keep it \
         whether or not they are the right ones: the response is exact, which says nothing of \
         collisions missed): {}.",
        list(&kept)
    );
    // The gas in a box's deepest overlap: what would show a collision missed.
    if let Some(outcome) = results.iter().find(|o| o.name.contains("in a box")) {
        let deepest = |prefix: &str| {
            let extras = outcome
                .points
                .iter()
                .filter(|p| p.engine.starts_with(prefix))
                .filter_map(|p| p.extra);
            let failed = extras.clone().filter(|x| x.is_nan()).count();
            let deepest = extras
                .filter(|x| !x.is_nan())
                .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.max(x))))
                .map_or("-".to_owned(), |x| format!("{x:.1e}"));
            if failed > 0 {
                format!("{deepest} ({failed} runs failed)")
            } else {
                deepest
            }
        };
        let _ = writeln!(
            out,
            "- The {}'s deepest overlap at a step's end over every step size, in radii: exact {}, \
             bisection {}, rapier {}.",
            outcome.name,
            deepest("exact"),
            deepest("bisection"),
            deepest("rapier"),
        );
    }
    let _ = writeln!(
        out,
        "- Exact and bisection with 24 iterations within 10% of each other at every step size, so \
         the time of impact is not what limits the error: {}.",
        list(&alike)
    );
    let _ = writeln!(out, "- The rest: {}.", list(&apart));
    let speed =
        |s: Option<f64>| s.map_or("never (to 5e6 m/s)".to_owned(), |s| format!("from {s} m/s"));
    let at_60: Vec<String> = missed
        .iter()
        .map(|(name, row)| format!("{name} {}", speed(row[0])))
        .collect();
    let _ = writeln!(
        out,
        "- Tunnelling through a thin target at 60 steps/s (bisection only tests the end of its \
         interval): {}.",
        at_60.join("; ")
    );
    if let Some(Outcome { points, .. }) = results.iter().find(|o| o.name.contains("touching")) {
        let rapier: Vec<f64> = points
            .iter()
            .filter(|p| p.engine.starts_with("rapier"))
            .map(|p| p.error)
            .collect();
        let failed = rapier.iter().filter(|e| e.is_nan()).count();
        let finite: Vec<f64> = rapier.iter().copied().filter(|e| !e.is_nan()).collect();
        if !finite.is_empty() {
            let lo = finite.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let _ = writeln!(
                out,
                "- rapier's solver shares momentum among touching balls: on the touching cradle \
                 (striker at 1 m/s) its error is {lo:.2} to {hi:.2} m/s over every step size and \
                 iteration count{}.",
                if failed > 0 {
                    format!(" ({failed} runs failed)")
                } else {
                    String::new()
                }
            );
        }
    }
    out.push('\n');
    out
}

/// The trimmed standard output of `program` run with `args`, if it ran, succeeded and said
/// something.
fn output_of(program: &str, args: &[&str]) -> Option<String> {
    let out = std::process::Command::new(program)
        .args(args)
        .output()
        .ok()?;
    let text = String::from_utf8(out.stdout).ok()?;
    let text = text.trim();
    (out.status.success() && !text.is_empty()).then(|| text.to_owned())
}

/// The commit the report is made at (`git describe --always --dirty`), or "unknown".
fn git_commit() -> String {
    output_of("git", &["describe", "--always", "--dirty"]).unwrap_or_else(|| "unknown".into())
}

/// Today's date (UTC), as `date -u +%F` gives it, or "an unknown date".
fn today() -> String {
    output_of("date", &["-u", "+%F"]).unwrap_or_else(|| "an unknown date".into())
}

fn colour(k: usize) -> &'static str {
    [
        "#1f77b4", "#d62728", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#2ca02c",
        "#17becf", "#bcbd22",
    ][k % 10]
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let runs = if quick { 1 } else { 3 };
    let started = Instant::now();
    let mut methods: Vec<(String, ToiMethod)> = vec![("exact".into(), ToiMethod::Exact)];
    methods.extend(BISECTION.map(|n| {
        (
            format!("bisection:{n}"),
            ToiMethod::Bisection { max_iterations: n },
        )
    }));

    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Speed against error\n\nGenerated by `cargo run --release -p sphere_bench --features rapier --bin speed-vs-error` \
         at commit {commit}, on {date}.\n\
         Cost: median wall time of {runs} run(s) per simulated second (each engine's runs of a setting one after \
         another, not interleaved; a scenario's own checks between steps not counted), and ns per moving sphere \
         per step (fixed spheres not counted). \
         Single-threaded; rapier3d 0.36 in `f32` (ours in `f64`) with its default CCD (fast bodies swept against \
         fixed colliders), `length_unit` the smallest moving sphere's diameter, \
         restitution combined by `Min`, no friction, its sleeping on (its default; ours off). An error of 0 is \
         exact to the last bit; in the \
         plot, errors of 1e-16 or less are drawn hollow on its floor. A run whose state stops \
         being finite scores NaN (in the plot, counted in the legend as failed).\n",
        commit = git_commit(),
        date = today(),
    );
    md.push_str("![error against cost](speed_vs_error.svg)\n\n");
    let header_len = md.len();
    let mut panels = Vec::new();
    let mut results: Vec<Outcome> = Vec::new();
    let mut summary = String::from(
        "## Summary: error at 60 and 960 steps/s\n\n| scenario | exact, 60 | bisection:8, 60 | rapier 4 it., 60 | exact, 960 | bisection:8, 960 | rapier 4 it., 960 |\n|---|---|---|---|---|---|---|\n",
    );
    for scenario in scenarios() {
        eprintln!("{} ...", scenario.name());
        let mut points = Vec::new();
        for (name, method) in &methods {
            for hz in STEPS_PER_SECOND {
                let mut make = |scene: &Scene, dt: f64| -> Box<dyn Engine> {
                    Box::new(Ours::new(scene, *method, dt))
                };
                let (error, extra, cost, ns) = measure(scenario.as_ref(), &mut make, hz, runs);
                points.push(Point {
                    engine: name.clone(),
                    hz,
                    error,
                    extra,
                    cost,
                    ns_per_sphere_step: ns,
                });
            }
        }
        #[cfg(feature = "rapier")]
        if !scenario.tethered() {
            for iterations in [1usize, 4, 8] {
                for hz in STEPS_PER_SECOND {
                    let mut make = |scene: &Scene, dt: f64| -> Box<dyn Engine> {
                        Box::new(peer::make(scene, dt, iterations))
                    };
                    let (error, extra, cost, ns) = measure(scenario.as_ref(), &mut make, hz, runs);
                    points.push(Point {
                        engine: format!("rapier, {iterations} iterations"),
                        hz,
                        error,
                        extra,
                        cost,
                        ns_per_sphere_step: ns,
                    });
                }
            }
        }
        let extra_name = scenario.extra_measure();
        let _ = writeln!(
            md,
            "## {}\n\nError: {}.{}\n\n| engine | steps/s | error |{} wall s per sim s | ns/sphere/step |\n|---|---|---|{}---|---|",
            scenario.name(),
            scenario.error_measure(),
            extra_name.map_or(String::new(), |e| format!(" Also: {e}.")),
            extra_name.map_or("", |_| " also |"),
            extra_name.map_or("", |_| "---|"),
        );
        for p in &points {
            let extra = match (extra_name, p.extra) {
                (Some(_), Some(x)) => format!(" {x:.3e} |"),
                (Some(_), None) => " - |".to_owned(),
                _ => String::new(),
            };
            let _ = writeln!(
                md,
                "| {} | {} | {:.3e} |{extra} {:.3e} | {:.0} |",
                p.engine, p.hz, p.error, p.cost, p.ns_per_sphere_step
            );
        }
        if scenario.tethered() {
            md.push_str("\nrapier is not run here: the peer models no strings.\n");
        }
        let at = |engine: &str, hz: u32| {
            points
                .iter()
                .find(|p| p.engine == engine && p.hz == hz)
                .map_or("-".to_owned(), |p| format!("{:.1e}", p.error))
        };
        let _ = writeln!(
            summary,
            "| {} | {} | {} | {} | {} | {} | {} |",
            scenario.name(),
            at("exact", 60),
            at("bisection:8", 60),
            at("rapier, 4 iterations", 60),
            at("exact", 960),
            at("bisection:8", 960),
            at("rapier, 4 iterations", 960)
        );
        md.push('\n');
        let mut engines: Vec<&str> = points.iter().map(|p| p.engine.as_str()).collect();
        engines.dedup();
        // Plot exact, three bisection depths and rapier, to keep the panels readable.
        let shown = |e: &str| {
            e == "exact"
                || e == "bisection:1"
                || e == "bisection:8"
                || e == "bisection:24"
                || e.starts_with("rapier")
        };
        panels.push(Panel {
            title: scenario.name().to_owned(),
            y_label: "error".to_owned(),
            series: engines
                .iter()
                .filter(|e| shown(e))
                .enumerate()
                .map(|(k, e)| Series {
                    name: (*e).to_owned(),
                    colour: colour(k),
                    points: points
                        .iter()
                        .filter(|p| p.engine == *e)
                        .map(|p| (p.cost.max(1e-9), p.error))
                        .collect(),
                })
                .collect(),
        });
        results.push(Outcome {
            name: scenario.name().to_owned(),
            points,
            conserved: scenario.conserved_measure(),
        });
    }

    // Tunnelling: where each setting starts to miss a thin target.
    let _ = writeln!(
        md,
        "## Tunnelling\n\nA sphere of radius 0.01 fired at a fixed one of radius 0.01: the lowest speed \
         (1, 2, 5, 10, ... 5×10⁶ m/s) at which the collision is missed.\n\n| engine | 60 steps/s | 240 steps/s | 960 steps/s |\n|---|---|---|---|"
    );
    let show = |s: Option<f64>| s.map_or("never (to 5e6 m/s)".to_owned(), |s| format!("{s} m/s"));
    let mut missed: Vec<(String, [Option<f64>; 3])> = Vec::new();
    for (name, method) in &methods {
        let row = [60.0, 240.0, 960.0].map(|hz: f64| {
            let dt = 1.0 / hz;
            let mut make =
                |scene: &Scene| -> Box<dyn Engine> { Box::new(Ours::new(scene, *method, dt)) };
            tunnelling_speed(&mut make, dt)
        });
        missed.push((name.clone(), row));
    }
    #[cfg(feature = "rapier")]
    {
        let row = [60.0, 240.0, 960.0].map(|hz: f64| {
            let dt = 1.0 / hz;
            let mut make =
                |scene: &Scene| -> Box<dyn Engine> { Box::new(peer::make(scene, dt, 4)) };
            tunnelling_speed(&mut make, dt)
        });
        missed.push(("rapier, default CCD, 4 iterations".to_owned(), row));
    }
    for (name, row) in &missed {
        let _ = writeln!(md, "| {name} | {} |", row.map(show).join(" | "));
    }
    summary.push_str(&findings(&results, &missed));
    md.insert_str(header_len, &summary);
    let _ = writeln!(
        md,
        "\nGenerated in {:.0} s.",
        started.elapsed().as_secs_f64()
    );
    std::fs::create_dir_all("docs").expect("docs/ can be created");
    std::fs::write("docs/speed_vs_error.md", md).expect("docs/speed_vs_error.md can be written");
    std::fs::write("docs/speed_vs_error.svg", svg::render(&panels, 3))
        .expect("docs/speed_vs_error.svg can be written");
    eprintln!(
        "wrote docs/speed_vs_error.md and docs/speed_vs_error.svg in {:.0} s",
        started.elapsed().as_secs_f64()
    );
    if UNREPEATABLE.load(std::sync::atomic::Ordering::Relaxed) {
        eprintln!("speed-vs-error: error: some runs were not repeatable (above)");
        std::process::exit(1);
    }
}
