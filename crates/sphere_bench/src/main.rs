//! `sphere-bench`: steps per second and ns per sphere per step on the shower and the gas at
//! several sizes, ours against rapier3d 0.36 (with `--features rapier`), as a markdown table.
//!
//!     cargo run --release -p sphere_bench --features rapier -- [--sizes 1000,10000,100000]
//!         [--steps 60] [--settle 1] [--scenes shower,gas,pile,showers,apart,sparse,table] [--repeat 1] [--phases]
//!         [--per-step] [--rapier-iterations 4] [--rapier-length-unit 0.1] [--rapier-flat-walls] [--rapier-bullets] [--sleep]
//!         [--bouncer]
//!
//! Each run steps once untimed (both engines build their structures on the first step; with
//! `--settle N`, N times: the pile's bed at rest, say, rather than its landing), then times
//! each of `--steps` steps. With `--repeat N` each engine runs each scene N times, the
//! engines taking turns (ours, rapier with CCD, rapier without, then again), and the fastest
//! run of each is reported: on a shared machine the least disturbed run is the best estimate
//! of the cost, and taking turns spreads any drift of the machine over all three. Beside the
//! mean, each engine's slowest timed step in that run is given in milliseconds: a step is a
//! game's frame, and a crowd landing at once can make a few steps cost many times the mean.
//!
//! With `--phases` our engine also times its step's phases (`World::set_profiling`), and a
//! second table gives each phase's ns per sphere per step in the fastest run. With
//! `--per-step`, a last table follows our fastest run of each scene step by step (every fifth
//! timed step, and the first and last): its time, collisions, resting contacts and times of
//! impact per collision, and with `--phases` its event loop's time per collision. The shower's
//! cost is in its last steps, as its rain piles up on the dome.
//!
//! rapier's solver iterations (default 4, rapier's own default) and `length_unit` (default
//! 0.1, the spheres' diameter: 1.0, rapier's default for metres, made it 2.3x to 2.7x
//! slower here) can be changed to look for its fastest setting, and `--rapier-flat-walls`
//! gives rapier the gas's six wall spheres as half-spaces, its own shape for a wall. rapier's
//! "CCD" column is its default (every fast body swept against the fixed colliders), its
//! "no CCD" none at all; `--rapier-bullets` makes every sphere a bullet in the CCD column
//! instead, as the tables did until the fifty-sixth session: the same sweeps here (rapier
//! sweeps no bullet against another), dearer (see `rapier_peer::RapierCcd`).
//!
//! rapier's bodies fall asleep at rest (its default); ours do with `--sleep` (sleeping is off
//! by default in our engine; `--sleep` turns on `Settings::sleep` with `Sleep::default()`),
//! and a last table then gives how many of each engine's spheres are asleep after the run.
//! `--bouncer` adds to each scene a ball that never sleeps (see `scenes::add_bouncer`): what a
//! bed asleep costs while something else in the world moves.

use std::io::Write;

use sphere_bench::{Measurement, measure_ours, scenes};
use sphere_physics::Sleep;

const DT: f64 = 1.0 / 60.0;

struct Options {
    sizes: Vec<u32>,
    steps: u32,
    /// Untimed steps before the timed ones (at least 1).
    settle: u32,
    scenes: Vec<String>,
    repeat: u32,
    phases: bool,
    /// Our fastest run's steps, one by one.
    per_step: bool,
    /// rapier's solver iterations.
    #[cfg_attr(not(feature = "rapier"), allow(dead_code))]
    rapier_iterations: usize,
    /// rapier's `length_unit`.
    #[cfg_attr(not(feature = "rapier"), allow(dead_code))]
    rapier_length_unit: f64,
    /// The gas's walls as rapier half-spaces.
    #[cfg_attr(not(feature = "rapier"), allow(dead_code))]
    rapier_flat_walls: bool,
    /// rapier's CCD column with every sphere a bullet, not rapier's default.
    #[cfg_attr(not(feature = "rapier"), allow(dead_code))]
    rapier_bullets: bool,
    /// Our engine with sleeping on (`Sleep::default()`), as rapier's is by default.
    sleep: bool,
    /// A ball bouncing for ever above each scene (`scenes::add_bouncer`).
    bouncer: bool,
}

/// `value` as a positive integer, or an error naming `flag`.
fn positive<T: std::str::FromStr + PartialOrd + Default>(
    value: &str,
    flag: &str,
) -> Result<T, String> {
    value
        .parse()
        .ok()
        .filter(|n| *n > T::default())
        .ok_or(format!("{flag} needs a positive integer"))
}

fn parse() -> Result<Options, String> {
    let mut options = Options {
        sizes: vec![1_000, 10_000, 100_000],
        steps: 60,
        settle: 1,
        scenes: vec!["shower".into(), "gas".into()],
        repeat: 1,
        phases: false,
        per_step: false,
        rapier_iterations: 4,
        rapier_length_unit: 2.0 * scenes::RADIUS,
        rapier_flat_walls: false,
        rapier_bullets: false,
        sleep: false,
        bouncer: false,
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        match flag.as_str() {
            "--sizes" => {
                options.sizes = value()?
                    .split(',')
                    .map(|s| s.parse().map_err(|_| format!("bad size '{s}'")))
                    .collect::<Result<_, _>>()?
            }
            "--steps" => options.steps = positive(value()?, flag)?,
            "--repeat" => options.repeat = positive(value()?, flag)?,
            "--settle" => options.settle = positive(value()?, flag)?,
            "--scenes" => {
                options.scenes = value()?.split(',').map(str::to_owned).collect();
                if let Some(bad) = options.scenes.iter().find(|s| {
                    ![
                        "shower", "gas", "pile", "showers", "apart", "sparse", "table",
                    ]
                    .contains(&s.as_str())
                }) {
                    return Err(format!(
                        "unknown scene '{bad}' (shower, gas, pile, showers, apart, sparse, table)"
                    ));
                }
            }
            "--phases" => options.phases = true,
            "--per-step" => options.per_step = true,
            "--rapier-iterations" => options.rapier_iterations = positive(value()?, flag)?,
            "--rapier-length-unit" => {
                options.rapier_length_unit = value()?
                    .parse()
                    .ok()
                    .filter(|&u: &f64| u.is_finite() && u > 0.0)
                    .ok_or("--rapier-length-unit needs a positive number")?
            }
            "--rapier-flat-walls" => options.rapier_flat_walls = true,
            "--rapier-bullets" => options.rapier_bullets = true,
            "--sleep" => options.sleep = true,
            "--bouncer" => options.bouncer = true,
            "--help" | "-h" => {
                println!(
                    "sphere-bench [--sizes 1000,10000,100000] [--steps 60] [--settle 1] [--scenes shower,gas,pile,showers,apart,sparse,table] [--repeat 1] [--phases] [--per-step] [--rapier-iterations 4] [--rapier-length-unit 0.1] [--rapier-flat-walls] [--rapier-bullets] [--sleep] [--bouncer]"
                );
                std::process::exit(0);
            }
            other => return Err(format!("unknown flag '{other}'")),
        }
    }
    Ok(options)
}

/// Keeps in `best` the faster of it and `next`.
fn keep_faster(best: &mut Option<Measurement>, next: Measurement) {
    if best.as_ref().is_none_or(|b| next.seconds < b.seconds) {
        *best = Some(next);
    }
}

/// A ratio of times: one decimal from 1 up, three below (where rapier wins, 0.057x says
/// more than 0.1x).
#[cfg(feature = "rapier")]
fn ratio(x: f64) -> String {
    if x >= 1.0 {
        format!("{x:.1}x")
    } else {
        format!("{x:.3}x")
    }
}

fn cell(m: &Measurement) -> String {
    format!(
        "{:.0} ns ({:.1} steps/s)",
        m.ns_per_body_step(),
        m.steps_per_second()
    )
}

fn main() {
    let options = match parse() {
        Ok(o) => o,
        Err(e) => {
            eprintln!("sphere-bench: error: {e}");
            std::process::exit(2);
        }
    };
    let rapier = cfg!(feature = "rapier");
    println!(
        "{} steps of 1/60 s per run after {} untimed step(s), single-threaded, fastest of {} \
         run(s). Cost is wall time per sphere per step.\n",
        options.steps, options.settle, options.repeat
    );
    if rapier {
        println!(
            "rapier: {} solver iterations, length_unit {}, walls as {}; CCD: {} (no CCD: \
             none at all).\n",
            options.rapier_iterations,
            options.rapier_length_unit,
            if options.rapier_flat_walls {
                "half-spaces"
            } else {
                "balls"
            },
            if options.rapier_bullets {
                "every sphere a bullet (the same sweeps as rapier's default here, through \
                 the whole tree)"
            } else {
                "rapier's default (fast bodies swept against fixed colliders; making every \
                 sphere a bullet adds no sweep, as rapier sweeps no bullet against another)"
            }
        );
        println!(
            "| scene | N | ours (exact) | rapier CCD | rapier no CCD | vs CCD | vs no CCD | our KE after/before (or mean) | rapier KE after/before (or mean) | overlap left (m): ours / CCD / no CCD | our collisions, tests /sphere/step | slowest step (ms): ours / CCD / no CCD |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    } else {
        println!(
            "| scene | N | ours (exact) | collisions/step | KE after/before (or mean) | overlap left | collisions, tests /sphere/step | slowest step (ms) |"
        );
        println!("|---|---|---|---|---|---|---|---|");
    }
    let mut phase_rows = Vec::new();
    let mut step_rows = Vec::new();
    let mut asleep_rows = Vec::new();
    for scene_name in &options.scenes {
        for &n in &options.sizes {
            let mut scene = match scene_name.as_str() {
                "shower" => scenes::shower(n, 1),
                "showers" => scenes::showers(n, 1),
                "apart" => scenes::apart(n, 1),
                "sparse" => scenes::sparse(n, 1),
                "pile" => scenes::pile(n, 1),
                "table" => scenes::table(n, 1),
                _ => scenes::gas(n, 1),
            };
            // Read by our engine only: rapier's sleeping is always on.
            scene.sleep = options.sleep.then(Sleep::default);
            if options.bouncer {
                scenes::add_bouncer(&mut scene);
            }
            let mut ours = None;
            #[cfg(feature = "rapier")]
            let (mut ccd, mut plain) = (None, None);
            for _ in 0..options.repeat.max(1) {
                keep_faster(
                    &mut ours,
                    measure_ours(&scene, options.settle, options.steps, DT, options.phases),
                );
                #[cfg(feature = "rapier")]
                {
                    use sphere_bench::rapier_peer::RapierCcd;
                    let rapier = |ccd| {
                        sphere_bench::measure_rapier(
                            &scene,
                            options.settle,
                            options.steps,
                            DT,
                            sphere_bench::RapierSetting {
                                ccd,
                                iterations: options.rapier_iterations,
                                length_unit: options.rapier_length_unit,
                                flat_walls: options.rapier_flat_walls,
                            },
                        )
                    };
                    let on = if options.rapier_bullets {
                        RapierCcd::Bullets
                    } else {
                        RapierCcd::Default
                    };
                    keep_faster(&mut ccd, rapier(on));
                    keep_faster(&mut plain, rapier(RapierCcd::Off));
                }
            }
            let ours = ours.expect("at least one run");
            if let Some(phases) = ours.phases_per_body_step() {
                let cells: Vec<String> = phases.iter().map(|(_, ns)| format!("{ns:.0}")).collect();
                phase_rows.push(format!("| {scene_name} | {n} | {} |", cells.join(" | ")));
            }
            if options.per_step {
                step_rows.extend(step_table_rows(scene_name, n, &ours));
            }
            let asleep = format!("| {scene_name} | {n} | {}", ours.asleep);
            if ours.deferred > 0 {
                eprintln!(
                    "sphere-bench: warning: {scene_name} {n}: {} collisions deferred to later \
                     steps (a body's share of a step's collision budget ran out)",
                    ours.deferred
                );
            }
            // Kinetic energy after over before: the gas keeps it if exact. The shower and the
            // pile start at rest, so there is no ratio: the mean over the timed steps instead,
            // in joules (for a pile at rest, how much it still jiggles).
            let ke = |m: &Measurement| {
                if m.kinetic_before > 0.0 {
                    format!("{:.4}", m.kinetic_after / m.kinetic_before)
                } else {
                    format!("mean {:.1e} J", m.kinetic_mean)
                }
            };
            #[cfg(feature = "rapier")]
            let overlap = |m: &Measurement| format!("{:.1e}", m.max_overlap.unwrap_or(0.0));
            // The slowest timed step, in milliseconds: a step is a game's frame, and the
            // mean hides a crowd's landing in a few of them.
            let slowest = |m: &Measurement| format!("{:.1}", m.slowest * 1e3);
            let work = |m: &Measurement| {
                let (collisions, tests) = m.work_per_body_step();
                format!("{collisions:.3}, {tests:.2}")
            };
            #[cfg(feature = "rapier")]
            {
                let (ccd, plain) = (ccd.expect("one run"), plain.expect("one run"));
                asleep_rows.push(format!("{asleep} / {} / {} |", ccd.asleep, plain.asleep));
                println!(
                    "| {scene_name} | {n} | {} | {} | {} | {} | {} | {} | {} / {} | {} / {} / {} | {} | {} / {} / {} |",
                    cell(&ours),
                    cell(&ccd),
                    cell(&plain),
                    ratio(ccd.seconds / ours.seconds),
                    ratio(plain.seconds / ours.seconds),
                    ke(&ours),
                    ke(&ccd),
                    ke(&plain),
                    overlap(&ours),
                    overlap(&ccd),
                    overlap(&plain),
                    work(&ours),
                    slowest(&ours),
                    slowest(&ccd),
                    slowest(&plain),
                );
            }
            if !rapier {
                asleep_rows.push(format!("{asleep} |"));
                println!(
                    "| {scene_name} | {n} | {} | {:.0} | {} | {:.2e} | {} | {} |",
                    cell(&ours),
                    ours.collisions as f64 / f64::from(options.steps),
                    ke(&ours),
                    ours.max_overlap.unwrap_or(0.0),
                    work(&ours),
                    slowest(&ours),
                );
            }
            let _ = std::io::stdout().flush();
        }
    }
    if options.sleep {
        println!("\nSpheres asleep after the last step (ours with `--sleep`; rapier's always):\n");
        println!(
            "| scene | N | asleep: ours{} |",
            if rapier { " / CCD / no CCD" } else { "" }
        );
        println!("|---|---|---|");
        for row in asleep_rows {
            println!("{row}");
        }
    }
    if !phase_rows.is_empty() {
        println!("\nOur step's phases, ns per sphere per step (fastest run):\n");
        println!(
            "| scene | N | integrate | sort | build | first pass | resting | events | write-back | overlap | all |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|");
        for row in phase_rows {
            println!("{row}");
        }
    }
    if !step_rows.is_empty() {
        println!(
            "\nOur fastest run step by step (every fifth timed step, the first and the last):\n"
        );
        println!(
            "| scene | N | step | ms | collisions | resting | tests/collision | events us/collision |"
        );
        println!("|---|---|---|---|---|---|---|---|");
        for row in step_rows {
            println!("{row}");
        }
    }
}

/// The `--per-step` table's rows for our run `m` of `scene` at `n` spheres.
fn step_table_rows(scene: &str, n: u32, m: &Measurement) -> Vec<String> {
    let last = m.per_step.len().saturating_sub(1);
    m.per_step
        .iter()
        .enumerate()
        .filter(|&(i, _)| i == 0 || i == last || (i + 1) % 5 == 0)
        .map(|(i, r)| {
            let per = |x: f64| {
                if r.collisions > 0 {
                    format!("{:.2}", x / f64::from(r.collisions))
                } else {
                    "-".to_owned()
                }
            };
            let events = r.events.map_or("-".to_owned(), |e| per(e * 1e6));
            format!(
                "| {scene} | {n} | {} | {:.2} | {} | {} | {} | {events} |",
                i + 1,
                r.seconds * 1e3,
                r.collisions,
                r.resting,
                per(r.toi_tests as f64),
            )
        })
        .collect()
}
