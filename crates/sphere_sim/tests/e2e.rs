//! End-to-end tests: run the `sphere-sim` binary on scene files and check its JSON against
//! analytic answers, and its handling of bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn sim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sphere-sim"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes")
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sphere_sim_e2e");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn write_scene(name: &str, text: &str) -> PathBuf {
    let path = scratch(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Runs successfully and parses the report.
fn report(args: &[&str]) -> Value {
    let out = sim(args);
    assert!(
        out.status.success(),
        "sphere-sim {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Piped, so no progress bar (nor anything else) on standard error.
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is one JSON document")
}

fn body<'a>(report: &'a Value, name: &str) -> &'a Value {
    report["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["name"] == name)
        .unwrap_or_else(|| panic!("no body {name}"))
}

fn vec3(v: &Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [0, 1, 2].map(|k| a[k].as_f64().unwrap())
}

fn assert_close(actual: [f64; 3], expected: [f64; 3], tol: f64, what: &str) {
    for k in 0..3 {
        assert!(
            (actual[k] - expected[k]).abs() <= tol,
            "{what}: got {actual:?}, expected {expected:?}"
        );
    }
}

/// Fails with exit code 2, one line on stderr and nothing on stdout.
fn assert_bad_input(args: &[&str], needles: &[&str]) {
    let out = sim(args);
    assert_eq!(out.status.code(), Some(2), "args {args:?}");
    assert!(out.stdout.is_empty(), "no JSON on bad input");
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    for needle in needles {
        assert!(
            err.contains(needle),
            "stderr {err:?} should contain {needle:?}"
        );
    }
}

#[test]
fn two_body_collision_matches_the_analytic_answer() {
    // m1 = 1 · V, m2 = 3 · V (same radius): v1' = (m1 - m2)/(m1 + m2) · v1 = -v1/2,
    // v2' = 2 m1/(m1 + m2) · v1 = v1/2. Contact when the gap of 2 closes at speed 2: t = 1.
    let path = write_scene(
        "two_body.ron",
        r#"(
            name: "two body",
            spheres: [
                (name: "light", position: (-2.0, 0.0, 0.0), velocity: (2.0, 0.0, 0.0), radius: 0.5),
                (name: "heavy", position: (1.0, 0.0, 0.0), radius: 0.5, density: 3.0),
            ],
        )"#,
    );
    let r = report(&[
        "run",
        path.to_str().unwrap(),
        "--duration",
        "2.5",
        "--dt",
        "0.125",
    ]);
    assert_eq!(r["scene"], "two body");
    assert_eq!(r["method"], "exact");
    assert_eq!(r["steps"], 20);
    assert_eq!(r["dt"], 0.125);
    assert_eq!(r["time"], 2.5);
    let (light, heavy) = (body(&r, "light"), body(&r, "heavy"));
    assert_close(vec3(&light["velocity"]), [-1.0, 0.0, 0.0], 1e-14, "light v");
    assert_close(vec3(&heavy["velocity"]), [1.0, 0.0, 0.0], 1e-14, "heavy v");
    // At t = 1 the light one is at 0, the heavy one at 1; then 1.5 s apart at -1 and +1.
    assert_close(vec3(&light["position"]), [-1.5, 0.0, 0.0], 1e-12, "light x");
    assert_close(vec3(&heavy["position"]), [2.5, 0.0, 0.0], 1e-12, "heavy x");
    let stats = &r["stats"];
    assert_eq!(stats["collisions"], 1);
    let m = 4.0 / 3.0 * std::f64::consts::PI * 0.125;
    assert_close(
        vec3(&stats["momentum"]),
        [2.0 * m, 0.0, 0.0],
        1e-13,
        "momentum",
    );
    let ke = stats["kinetic_energy"].as_f64().unwrap();
    assert!((ke - 2.0 * m).abs() <= 1e-13, "kinetic energy {ke}");
    assert_eq!(stats["max_overlap"], 0.0);
    // The wall-clock time is reported, a number (its value is the machine's).
    assert!(stats["wall_seconds"].as_f64().is_some_and(f64::is_finite));
}

/// Two spheres placed a radius into each other with no gravity part by their positions, the
/// light one a tenth of its radius a step and the three-times-heavier one a third of that,
/// until they touch at the eighth step; the report counts the moves and gives them no speed.
#[test]
fn overlapping_spheres_with_no_gravity_part_without_speed() {
    let path = write_scene(
        "overlapping.ron",
        r#"(
            name: "overlapping",
            spheres: [
                (name: "light", position: (0.0, 0.0, 0.0), radius: 1.0),
                (name: "heavy", position: (1.0, 0.0, 0.0), radius: 1.0, density: 3.0),
            ],
        )"#,
    );
    let r = report(&[
        "run",
        path.to_str().unwrap(),
        "--duration",
        "1",
        "--dt",
        "0.1",
    ]);
    let (light, heavy) = (body(&r, "light"), body(&r, "heavy"));
    assert_close(
        vec3(&light["position"]),
        [-0.75, 0.0, 0.0],
        1e-12,
        "light x",
    );
    assert_close(vec3(&heavy["position"]), [1.25, 0.0, 0.0], 1e-12, "heavy x");
    assert_eq!(vec3(&light["velocity"]), [0.0; 3]);
    assert_eq!(vec3(&heavy["velocity"]), [0.0; 3]);
    let stats = &r["stats"];
    // Both moved in each of the first eight steps.
    assert_eq!(stats["separated"], 16);
    assert!(stats["max_overlap"].as_f64().unwrap().abs() < 1e-12);
    assert_eq!(stats["kinetic_energy"], 0.0);
    // The overlap at the start is the initial one; `max_overlap_seen` is at the ends of steps
    // (it counted the start's until the fifty-seventh session, against its documentation).
    assert_eq!(r["initial"]["max_overlap"], 1.0);
    let seen = stats["max_overlap_seen"].as_f64().unwrap();
    assert!(seen > 0.5 && seen < 1.0, "{seen}");
}

#[test]
fn bisection_is_selectable_and_reported() {
    let scene = assets().join("two_spheres.ron");
    let r = report(&[
        "run",
        scene.to_str().unwrap(),
        "--duration",
        "2",
        "--method",
        "bisection:12",
    ]);
    assert_eq!(r["method"], "bisection:12");
    assert!(r["stats"]["toi_iterations"].as_u64().unwrap() > 0);
    let r = report(&[
        "run",
        scene.to_str().unwrap(),
        "--duration=1",
        "--method=bisection",
    ]);
    assert_eq!(r["method"], "bisection:8");
}

#[test]
fn touching_cradle_sends_exactly_one_ball_out() {
    let scene = assets().join("touching_cradle.ron");
    let r = report(&["run", scene.to_str().unwrap(), "--duration", "3"]);
    // The striker closes the gap of 2 at speed 2: contact at t = 1; ball 4 then travels 2 s.
    for name in ["striker", "ball 1", "ball 2", "ball 3"] {
        assert_eq!(vec3(&body(&r, name)["velocity"]), [0.0; 3], "{name}");
    }
    let out = body(&r, "ball 4");
    assert_eq!(vec3(&out["velocity"]), [2.0, 0.0, 0.0]);
    assert_close(vec3(&out["position"]), [7.0, 1.5, 0.0], 1e-12, "ball 4");
    assert_close(
        vec3(&body(&r, "ball 1")["position"]),
        [0.0, 1.5, 0.0],
        1e-12,
        "ball 1",
    );
    assert_close(
        vec3(&body(&r, "striker")["position"]),
        [-1.0, 1.5, 0.0],
        1e-12,
        "striker",
    );
}

#[test]
fn the_ball_pit_falls_asleep_and_says_so() {
    // The scene turns sleeping on; its bed is asleep at 7.7 s (over seeds 1 to 16 of its
    // shower, 3.3 to 7.7 s, 5.1 s on average).
    let scene = assets().join("ball_pit.ron");
    let r = report(&["run", scene.to_str().unwrap(), "--duration", "10"]);
    let bodies = r["bodies"].as_array().unwrap();
    let asleep = |b: &&Value| b["asleep"] == true;
    let dynamic = |b: &&Value| b["fixed"] == false;
    assert_eq!(bodies.iter().filter(dynamic).count(), 400);
    assert!(bodies.iter().filter(dynamic).all(|b| asleep(&b)));
    assert!(!bodies.iter().filter(|b| !dynamic(b)).any(|b| asleep(&b)));
    for b in bodies.iter().filter(dynamic) {
        assert_eq!(vec3(&b["velocity"]), [0.0; 3]);
    }
    assert_eq!(r["stats"]["kinetic_energy"], 0.0);
}

#[test]
fn every_scene_file_runs() {
    let mut names = Vec::new();
    for entry in std::fs::read_dir(assets()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "ron") {
            let r = report(&["run", path.to_str().unwrap(), "--duration", "0.05"]);
            assert_eq!(r["steps"], 3, "{}", path.display());
            assert!(!r["bodies"].as_array().unwrap().is_empty());
            names.push(r["scene"].as_str().unwrap().to_owned());
        }
    }
    let files = std::fs::read_dir(assets())
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "ron")
        })
        .count();
    assert!(files >= 12, "{files}");
    assert_eq!(names.len(), files, "scenes: {names:?}");
}

#[test]
fn same_input_gives_bit_identical_output() {
    let scene = assets().join("gas_box.ron");
    let run = || {
        let mut r = report(&["run", scene.to_str().unwrap(), "--duration", "0.25"]);
        r["stats"]["wall_seconds"] = Value::Null;
        r["stats"]["ns_per_sphere_step"] = Value::Null;
        serde_json::to_string(&r).unwrap()
    };
    assert_eq!(run(), run());
}

#[test]
fn numbers_round_trip_exactly() {
    // 0.1 + 0.2 style values survive the JSON unchanged.
    let path = write_scene(
        "round_trip.ron",
        r#"(name: "rt", spheres: [(position: (0.1, 0.2, 0.30000000000000004), radius: 0.7)])"#,
    );
    let r = report(&["run", path.to_str().unwrap(), "--duration", "0.5"]);
    let b = &r["bodies"][0];
    assert_eq!(b["name"], "0", "unnamed spheres are named by index");
    assert_eq!(vec3(&b["position"]), [0.1, 0.2, 0.30000000000000004]);
}

#[test]
fn output_and_trace_files() {
    let scene = assets().join("settling_ball.ron");
    let (json, csv, jsonl) = (
        scratch("out.json"),
        scratch("trace.csv"),
        scratch("trace.jsonl"),
    );
    let out = sim(&[
        "run",
        scene.to_str().unwrap(),
        "--duration",
        "1",
        "--output",
        json.to_str().unwrap(),
        "--trace",
        csv.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    assert!(out.stdout.is_empty(), "the report went to the file");
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(r["steps"], 60);
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 61, "header and one row a step");
    assert!(lines[0].starts_with("step,time,dt,collisions"));
    assert!(lines[60].starts_with("60,"));
    let collisions: u64 = lines[1..]
        .iter()
        .map(|l| l.split(',').nth(3).unwrap().parse::<u64>().unwrap())
        .sum();
    assert_eq!(collisions, r["stats"]["collisions"].as_u64().unwrap());

    let r = report(&[
        "run",
        scene.to_str().unwrap(),
        "--duration",
        "0.5",
        "--trace",
        jsonl.to_str().unwrap(),
    ]);
    let rows: Vec<Value> = std::fs::read_to_string(&jsonl)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(rows.len(), 30);
    assert_eq!(rows[29]["total_energy"], r["stats"]["total_energy"]);
}

#[test]
fn a_duration_that_is_not_a_whole_number_of_steps_ends_on_time() {
    let scene = assets().join("two_spheres.ron");
    let r = report(&[
        "run",
        scene.to_str().unwrap(),
        "--duration",
        "0.3",
        "--dt",
        "0.125",
    ]);
    assert_eq!(r["steps"], 3);
    assert!((r["time"].as_f64().unwrap() - 0.3).abs() < 1e-15);
}

#[test]
fn missing_file() {
    assert_bad_input(
        &["run", "no/such/scene.ron", "--duration", "1"],
        &["no/such/scene.ron"],
    );
}

#[test]
fn parse_error_gives_line_and_column() {
    let path = write_scene(
        "parse_error.ron",
        "(\n  name: \"broken\",\n  spheres: [\n    (position: (0.0, 0.0), radius: 1.0),\n  ],\n)\n",
    );
    assert_bad_input(
        &["run", path.to_str().unwrap(), "--duration", "1"],
        &["parse_error.ron:4:"],
    );
}

#[test]
fn invalid_sphere_is_named_with_its_field() {
    let path = write_scene(
        "invalid_sphere.ron",
        r#"(name: "bad", spheres: [
            (name: "ok", position: (0.0, 0.0, 0.0), radius: 1.0),
            (name: "flat", position: (5.0, 0.0, 0.0), radius: -2.0),
        ])"#,
    );
    let json = scratch("never_written.json");
    let _ = std::fs::remove_file(&json);
    assert_bad_input(
        &[
            "run",
            path.to_str().unwrap(),
            "--duration",
            "1",
            "--output",
            json.to_str().unwrap(),
        ],
        &["flat", "radius", "-2"],
    );
    assert!(!json.exists(), "no partial JSON");
}

#[test]
fn invalid_generator_is_named() {
    let path = write_scene(
        "invalid_generator.ron",
        r#"(name: "crowded", generate: [
            Gas(count: 1000, seed: 1, min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0), radius: 0.1, speed: 1.0),
        ])"#,
    );
    assert_bad_input(
        &["run", path.to_str().unwrap(), "--duration", "1"],
        &["generator 0", "count"],
    );
}

#[test]
fn bad_flag_values() {
    let scene = assets().join("two_spheres.ron");
    let scene = scene.to_str().unwrap();
    assert_bad_input(&["run", scene, "--duration", "-1"], &["--duration", "-1"]);
    assert_bad_input(&["run", scene, "--duration", "abc"], &["--duration"]);
    assert_bad_input(&["run", scene, "--duration", "NaN"], &["--duration"]);
    assert_bad_input(&["run", scene], &["--duration"]);
    assert_bad_input(&["run", scene, "--duration", "1", "--dt", "0"], &["--dt"]);
    assert_bad_input(
        &["run", scene, "--duration", "1", "--method", "euler"],
        &["--method", "euler"],
    );
    assert_bad_input(
        &["run", scene, "--duration", "1", "--method", "bisection:99"],
        &["bisection:N", "99"],
    );
    assert_bad_input(
        &["run", scene, "--duration", "1", "--trace", "x.txt"],
        &["--trace", "x.txt"],
    );
    assert_bad_input(&["run", scene, "--duration", "1", "--fast"], &["--fast"]);
    assert_bad_input(&["run", scene, "--duration"], &["--duration needs a value"]);
    assert_bad_input(&["fly"], &["fly"]);
    assert_bad_input(&[], &["no command"]);
    assert_bad_input(
        &["run", scene, "--duration", "1e12", "--dt", "1e-6"],
        &["steps"],
    );
}

#[test]
fn help_and_version() {
    let out = sim(&["--help"]);
    assert!(out.status.success());
    assert!(
        String::from_utf8(out.stdout)
            .unwrap()
            .contains("--duration")
    );
    let out = sim(&["--version"]);
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8(out.stdout).unwrap(),
        format!("sphere-sim {}\n", env!("CARGO_PKG_VERSION"))
    );
}

/// Review of the fifty-seventh session: the help, the version and the error line were
/// written with `println!` and `eprintln!`, which panic (exit code 101) when the pipe is
/// closed; now a reader gone is no error, as for the report.
#[test]
fn regression_a_closed_pipe_is_no_panic() {
    for args in [
        &["--help"][..],
        &["--version"],
        &["run", "missing.ron", "--duration", "1"],
    ] {
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let (err_reader, err_writer) = std::io::pipe().unwrap();
        drop(err_reader);
        let status = Command::new(env!("CARGO_BIN_EXE_sphere-sim"))
            .args(args)
            .stdout(writer)
            .stderr(err_writer)
            .status()
            .unwrap();
        let expected = if args[0] == "run" { 2 } else { 0 };
        assert_eq!(status.code(), Some(expected), "{args:?}");
    }
}

/// Review of the fifty-seventh session: a duration whose last, shorter step is subnormal was
/// refused blaming the scene's substeps (of which it had one); the duration is to blame.
#[test]
fn regression_a_last_step_too_short_blames_the_duration() {
    let scene = assets().join("two_spheres.ron");
    assert_bad_input(
        &[
            "run",
            scene.to_str().unwrap(),
            "--dt",
            "3e-308",
            "--duration",
            "4e-308",
        ],
        &["--duration 4e-308 ends with a step of", "3e-308"],
    );
}

/// Review of the fifty-seventh session: a scene path that was a device was read to its end:
/// `/dev/zero` until memory ran out. A device or a folder is bad input now; a pipe is read.
#[test]
fn regression_a_scene_that_is_not_a_regular_file_is_bad_input() {
    if Path::new("/dev/zero").exists() {
        assert_bad_input(
            &["run", "/dev/zero", "--duration", "1"],
            &["/dev/zero", "a device, not a scene file"],
        );
    }
    let folder = scratch("a_folder.ron");
    std::fs::create_dir_all(&folder).unwrap();
    assert_bad_input(
        &["run", folder.to_str().unwrap(), "--duration", "1"],
        &["a_folder.ron", "a folder, not a scene file"],
    );
    // A scene piped in (`/dev/stdin`, as `<(make_scene)` gives a pipe) is read.
    use std::io::Write;
    let mut child = Command::new(env!("CARGO_BIN_EXE_sphere-sim"))
        .args(["run", "/dev/stdin", "--duration", "0.1"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let text = std::fs::read(assets().join("two_spheres.ron")).unwrap();
    child.stdin.take().unwrap().write_all(&text).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["steps"], 6);
}

/// Review of the fifty-seventh session: a trace that failed part-way (a full disk) was not
/// written to again, but the run went on to its end, however long, and then wrote no report.
/// Now the run stops at the failing step, and the message says so.
#[test]
fn regression_a_trace_that_fails_stops_the_run() {
    if !Path::new("/dev/full").exists() {
        return;
    }
    let full = scratch("full.csv");
    let _ = std::fs::remove_file(&full);
    std::os::unix::fs::symlink("/dev/full", &full).unwrap();
    // 6000 steps: rows of about 150 bytes fill the trace's 8 KiB buffer within a hundred.
    let scene = assets().join("two_spheres.ron");
    let out = sim(&[
        "run",
        scene.to_str().unwrap(),
        "--duration",
        "100",
        "--trace",
        full.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty(), "no report");
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("writing the trace") && err.contains("full.csv"),
        "{err}"
    );
    let step: u64 = err
        .split("stopped at step ")
        .nth(1)
        .and_then(|rest| rest.split(';').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{err}"));
    assert!((1..200).contains(&step), "{err}");
}

#[test]
fn tethered_cradle_swings_for_a_minute() {
    let scene = assets().join("newtons_cradle.ron");
    let r = report(&["run", scene.to_str().unwrap(), "--duration", "60"]);
    assert_eq!(r["steps"], 3600);
    assert_eq!(r["integrator"], "Leapfrog");
    let e0 = r["initial"]["total_energy"].as_f64().unwrap();
    let e = r["stats"]["total_energy"].as_f64().unwrap();
    assert!((e - e0).abs() <= 0.01 * e0, "energy {e} vs {e0}");
    // At 60 s ball 5 is out (swinging), balls 1 to 4 hang at rest.
    let out = vec3(&body(&r, "ball 5")["velocity"]);
    let speed = out.iter().map(|v| v * v).sum::<f64>().sqrt();
    assert!(speed > 0.5, "ball 5 swings: {speed}");
    for name in ["ball 1", "ball 2", "ball 3", "ball 4"] {
        let v = vec3(&body(&r, name)["velocity"]);
        let s = v.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(s < 1e-6 * speed, "{name} at {s}");
    }
}

/// A scene file `name` with one sphere, 'rocket': its first 1 s step takes it to x = 1e308,
/// and the second would overflow.
fn runaway_scene(name: &str) -> PathBuf {
    write_scene(
        name,
        r#"(name: "runaway", spheres: [
            (name: "rocket", position: (0.0, 0.0, 0.0), velocity: (1e308, 0.0, 0.0), radius: 0.5),
        ])"#,
    )
}

/// Regression (found by review): a subnormal duration was blamed on the time step, an output
/// path naming a folder was found only after the whole run, and a step refused part-way gave
/// no step or time.
#[test]
fn regression_subnormal_flags_output_folders_and_refused_steps_are_named() {
    let scene = assets().join("two_spheres.ron");
    let scene = scene.to_str().unwrap();
    assert_bad_input(
        &["run", scene, "--duration", "1e-310"],
        &["--duration", "1e-310", "normal"],
    );
    assert_bad_input(
        &["run", scene, "--duration", "1", "--dt", "5e-324"],
        &["--dt", "5e-324"],
    );
    let folder = scratch("a_folder");
    std::fs::create_dir_all(&folder).unwrap();
    assert_bad_input(
        &[
            "run",
            scene,
            "--duration",
            "1",
            "--output",
            folder.to_str().unwrap(),
        ],
        &["--output", "is a folder"],
    );
    let runaway = runaway_scene("runaway.ron");
    assert_bad_input(
        &[
            "run",
            runaway.to_str().unwrap(),
            "--duration",
            "3",
            "--dt",
            "1",
        ],
        &["step 2", "t = 1 s", "'rocket'"],
    );
}

/// Regression (found by review): a run whose step was refused part-way left its trace file
/// without a word: the trace keeps the steps before the failure, and the message says so.
#[test]
fn regression_a_refused_step_says_what_the_trace_holds() {
    let runaway = runaway_scene("runaway_traced.ron");
    let trace = scratch("runaway_trace.csv");
    let _ = std::fs::remove_file(&trace);
    let trace_arg = trace.to_str().unwrap();
    assert_bad_input(
        &[
            "run",
            runaway.to_str().unwrap(),
            "--duration",
            "3",
            "--dt",
            "1",
            "--trace",
            trace_arg,
        ],
        &[
            "step 2",
            "the trace",
            trace_arg,
            "holds the 1 step(s) before it",
        ],
    );
    let text = std::fs::read_to_string(&trace).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2, "header and step 1: {text}");
    assert!(lines[1].starts_with("1,1.0,1.0,"), "{}", lines[1]);
}

/// Regression: an argument that is not UTF-8 (a legal file name on Linux) made the runner
/// panic in `std::env::args` instead of saying so and exiting with code 2. Found by review.
#[cfg(unix)]
#[test]
fn regression_an_argument_that_is_not_utf8_is_bad_input() {
    use std::os::unix::ffi::OsStrExt;
    let out = Command::new(env!("CARGO_BIN_EXE_sphere-sim"))
        .arg("run")
        .arg(std::ffi::OsStr::from_bytes(b"scene\xff.ron"))
        .args(["--duration", "1"])
        .output()
        .expect("the binary runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("argument 2 is not valid UTF-8"), "{err}");
}

/// Regressions found by a review of the runner: a duration of too many steps was found after
/// the trace file had been created (and emptied), blaming a `--dt` never given; errors found
/// after parsing did not name the file; a repeated flag silently kept the last value; an
/// `--output` could overwrite the scene file or the trace; two bodies could share a name with
/// nothing to tell them apart; a scene's out-of-range method was refused even when `--method`
/// replaced it.
#[test]
fn regression_runner_review() {
    let scene = assets().join("two_spheres.ron");
    let scene_arg = scene.to_str().unwrap();
    // Too many steps: refused before the trace is touched, naming where the step came from.
    let trace = scratch("kept_trace.csv");
    std::fs::write(&trace, "precious").unwrap();
    assert_bad_input(
        &[
            "run",
            scene_arg,
            "--duration",
            "2e7",
            "--trace",
            trace.to_str().unwrap(),
        ],
        &["20000000", "the default", "1000000000"],
    );
    assert_eq!(std::fs::read_to_string(&trace).unwrap(), "precious");
    // An invalid sphere: the file's path first.
    let bad = write_scene(
        "review_bad_sphere.ron",
        r#"(name: "bad", spheres: [(name: "flat", position: (0.0, 0.0, 0.0), radius: -2.0)])"#,
    );
    assert_bad_input(
        &["run", bad.to_str().unwrap(), "--duration", "1"],
        &["review_bad_sphere.ron: ", "flat", "radius"],
    );
    // Repeated flags, -o and --output alike; arguments after help or --version.
    assert_bad_input(
        &["run", scene_arg, "--duration", "1", "--duration", "100"],
        &["--duration", "more than once"],
    );
    assert_bad_input(
        &[
            "run",
            scene_arg,
            "--duration",
            "1",
            "-o",
            "a.json",
            "--output=b.json",
        ],
        &["--output", "more than once"],
    );
    assert_bad_input(&["--version", "run"], &["unexpected argument 'run'"]);
    // An output that is the scene, or the trace.
    let copy = write_scene("review_copy.ron", &std::fs::read_to_string(&scene).unwrap());
    let copy_arg = copy.to_str().unwrap();
    assert_bad_input(
        &["run", copy_arg, "--duration", "1", "-o", copy_arg],
        &["scene file itself"],
    );
    let both = scratch("review_both.jsonl");
    let both_arg = both.to_str().unwrap();
    assert_bad_input(
        &[
            "run",
            copy_arg,
            "--duration",
            "1",
            "-o",
            both_arg,
            "--trace",
            both_arg,
        ],
        &["--trace file too"],
    );
    assert_eq!(
        std::fs::read_to_string(&copy).unwrap(),
        std::fs::read_to_string(&scene).unwrap(),
        "the scene file is untouched"
    );
    // Regression (found by review): the same file spelled two ways was caught only once it
    // existed (the run then overwrote its trace with the report, and succeeded).
    let fresh = scratch("review_fresh.jsonl");
    let _ = std::fs::remove_file(&fresh);
    let dir = fresh.parent().unwrap();
    let spelled = dir
        .join("..")
        .join(dir.file_name().unwrap())
        .join("review_fresh.jsonl");
    assert_bad_input(
        &[
            "run",
            copy_arg,
            "--duration",
            "1",
            "-o",
            fresh.to_str().unwrap(),
            "--trace",
            spelled.to_str().unwrap(),
        ],
        &["--trace file too"],
    );
    assert!(!fresh.exists(), "nothing written");
    // Regression (found by review): a carriage return in a sphere's name reached the error
    // line as it was (on a terminal, what follows it overwrites the line).
    let named = write_scene(
        "review_return.ron",
        r#"(name: "n", spheres: [
            (name: "ok\rsphere-sim: all fine", position: (0.0, 0.0, 0.0), radius: -1.0)])"#,
    );
    let out = sim(&["run", named.to_str().unwrap(), "--duration", "1"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(!err.contains('\r'), "{err:?}");
    assert!(err.contains("ok\\rsphere-sim: all fine"), "{err:?}");
    // Regression (found by review): a step too short for the scene's substeps was found only
    // at the first step, after the trace file had been made, and the error did not name the
    // scene file.
    let fine = write_scene(
        "review_fine.ron",
        "(name: \"n\", substeps: 65536, spheres: [(position: (0.0, 0.0, 0.0), radius: 1.0)])",
    );
    let fine_trace = scratch("review_fine.csv");
    let _ = std::fs::remove_file(&fine_trace);
    assert_bad_input(
        &[
            "run",
            fine.to_str().unwrap(),
            "--duration",
            "1e-305",
            "--dt",
            "1e-305",
            "--trace",
            fine_trace.to_str().unwrap(),
        ],
        &[fine.to_str().unwrap(), "substeps"],
    );
    assert!(!fine_trace.exists(), "no trace made");
    // Regression (found by review): a scene's bad `dt` was refused even when `--dt` replaced
    // it (a bad `method` replaced by `--method` was not). Both are forgiven when replaced.
    let bad_dt = write_scene(
        "review_bad_dt.ron",
        "(name: \"n\", dt: -1.0, spheres: [(position: (0.0, 0.0, 0.0), radius: 1.0)])",
    );
    let bad_dt_arg = bad_dt.to_str().unwrap();
    assert_bad_input(&["run", bad_dt_arg, "--duration", "1"], &["dt", "-1"]);
    let r = report(&["run", bad_dt_arg, "--duration", "1", "--dt", "0.25"]);
    assert_eq!(r["dt"], 0.25);
    assert_eq!(r["steps"], 4);
    // Regression (found by review): huge and tiny numbers were printed in hundreds of digits.
    assert_bad_input(
        &["run", copy_arg, "--duration", "1e300", "--dt", "1e-300"],
        &["--duration 1e300 at a step of 1e-300 s (--dt) needs inf steps"],
    );
    assert_bad_input(
        &["run", copy_arg, "--duration", "1e20"],
        &["--duration 1e20 at a step of 0.016666666666666666 s (the default) needs 6e21 steps"],
    );
    // Regression (found by review): a scene's bad `view` box, which the lab refuses, was
    // played (a runner does not use it, but the file is bad).
    let bad_view = write_scene(
        "review_bad_view.ron",
        "(name: \"n\", spheres: [(position: (0.0, 0.0, 0.0), radius: 1.0)],
            view: ((0.0, NaN, 0.0), (1.0, 1.0, 1.0)))",
    );
    assert_bad_input(
        &["run", bad_view.to_str().unwrap(), "--duration", "1"],
        &["review_bad_view.ron: ", "view", "finite"],
    );
    // Two gases' walls share names; each body carries its index.
    let gases = write_scene(
        "review_two_gases.ron",
        r#"(name: "two gases", generate: [
            Gas(count: 2, seed: 1, min: (-1.0, -1.0, -1.0), max: (1.0, 1.0, 1.0), radius: 0.1, speed: 1.0),
            Gas(count: 2, seed: 2, min: (99.0, -1.0, -1.0), max: (101.0, 1.0, 1.0), radius: 0.1, speed: 1.0),
        ])"#,
    );
    let r = report(&["run", gases.to_str().unwrap(), "--duration", "0.1"]);
    let bodies = r["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), 16);
    for (i, b) in bodies.iter().enumerate() {
        assert_eq!(b["index"], i);
    }
    assert_eq!(
        bodies.iter().filter(|b| b["name"] == "wall xmin").count(),
        2
    );
    // A scene method out of range does not matter when --method replaces it.
    let slow = write_scene(
        "review_slow_method.ron",
        &std::fs::read_to_string(&scene).unwrap().replacen(
            "(",
            "(method: Bisection(max_iterations: 1000), ",
            1,
        ),
    );
    assert_bad_input(
        &["run", slow.to_str().unwrap(), "--duration", "1"],
        &["review_slow_method.ron: ", "1000"],
    );
    let r = report(&[
        "run",
        slow.to_str().unwrap(),
        "--duration",
        "1",
        "--method",
        "exact",
    ]);
    assert_eq!(r["method"], "exact");
}

/// Regression (review): a duration a hair off a whole number of steps, over very many steps,
/// was rounded to that number by a tolerance that grew with the count (up to a whole step).
#[test]
fn regression_step_rounding_is_within_the_division_rounding() {
    use sphere_sim::run::StepPlan;
    let plan = StepPlan::new(999_999.999_4, 0.001).unwrap();
    assert_eq!(plan.full, 999_999_999);
    assert!((plan.last - 0.0004).abs() < 1e-6, "{plan:?}");
    assert_eq!(StepPlan::new(2.0, 1.0 / 60.0).unwrap().full, 120);
    let plan = StepPlan::new(1e6, 0.001).unwrap();
    assert_eq!((plan.full, plan.last), (1_000_000_000, 0.0));
}

/// The README's promises on the report's edges (found by a review of the tests: none checked
/// them): a quantity that overflows an f64 is printed as `null`, and a report that cannot be
/// written once the run is done exits with code 1.
#[test]
fn an_overflowing_energy_is_null_and_an_unwritable_report_exits_with_code_1() {
    let fast = write_scene(
        "edges_fast.ron",
        "(name: \"n\", spheres: [(name: \"fast\", position: (0.0, 0.0, 0.0),
            velocity: (1e160, 0.0, 0.0), radius: 1.0)])",
    );
    let fast_arg = fast.to_str().unwrap();
    let r = report(&["run", fast_arg, "--duration", "0.1"]);
    assert!(r["stats"]["kinetic_energy"].is_null(), "{}", r["stats"]);
    assert!(r["stats"]["total_energy"].is_null(), "{}", r["stats"]);
    // The momentum does not overflow: 4/3·π·1e160.
    let momentum = r["stats"]["momentum"][0].as_f64().unwrap();
    assert!((momentum / (4.0 / 3.0 * std::f64::consts::PI * 1e160) - 1.0).abs() < 1e-12);
    assert_eq!(body(&r, "fast")["velocity"][0], 1e160);
    // A full disk: every write to /dev/full fails. (A trace must be named .csv or .jsonl.)
    if std::path::Path::new("/dev/full").exists() {
        let out = sim(&[
            "run",
            fast_arg,
            "--duration",
            "0.1",
            "--output",
            "/dev/full",
        ]);
        assert_eq!(out.status.code(), Some(1));
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}
