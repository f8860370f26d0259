//! Real windows: the lab and the Newton's cradle example run under `xvfb-run` with Mesa's CPU
//! Vulkan driver, save a screenshot once the simulated time passes 1 s, and quit. The PNGs must
//! show the scene's colours and the simulated time written on them. Needs `xvfb-run` and
//! `mesa-vulkan-drivers`: `scripts/install-window-deps.sh` installs them (the README's test
//! command runs it).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use image::RgbaImage;
use sphere_lab::stamp::read_time_stamp;

use scratch::Scratch;

mod scratch;

/// Runs `program` under a virtual X server, killing it (and its X server) after `limit`.
/// Output goes to files, so a chatty program never blocks on a full pipe.
fn run_in_window(program: &Path, args: &[&str], limit: Duration) -> Output {
    use std::os::unix::process::CommandExt;
    let xvfb = Command::new("xvfb-run").arg("--help").output();
    assert!(
        xvfb.is_ok(),
        "xvfb-run is missing: run scripts/install-window-deps.sh (the README's test command does)"
    );
    let logs = temp_dir(&format!(
        "logs_{}",
        program.file_name().unwrap().to_string_lossy()
    ));
    std::fs::create_dir_all(&logs).unwrap();
    let (out_path, err_path) = (logs.join("stdout"), logs.join("stderr"));
    let mut child = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x720x24"])
        .arg(program)
        .args(args)
        .env("RUST_LOG", "warn")
        .stdout(std::fs::File::create(&out_path).unwrap())
        .stderr(std::fs::File::create(&err_path).unwrap())
        .process_group(0)
        .spawn()
        .expect("start xvfb-run");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if start.elapsed() > limit {
            let group = format!("-{}", child.id());
            let _ = Command::new("kill").args(["-KILL", "--", &group]).status();
            let _ = child.wait();
            panic!(
                "{} did not finish within {limit:?}:\n{}",
                program.display(),
                std::fs::read_to_string(&err_path).unwrap_or_default()
            );
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    Output {
        status,
        stdout: std::fs::read(&out_path).unwrap_or_default(),
        stderr: std::fs::read(&err_path).unwrap_or_default(),
    }
}

fn temp_dir(name: &str) -> Scratch {
    Scratch::new("sphere_lab_window", name)
}

/// The saved screenshot: the path the app printed.
fn screenshot(out: &Output) -> RgbaImage {
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "exit {:?}\nstdout: {stdout}\nstderr: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    let path = stdout
        .lines()
        .find_map(|l| l.strip_prefix("screenshot "))
        .unwrap_or_else(|| panic!("no screenshot line in {stdout}"));
    image::open(path).expect("open the PNG").to_rgba8()
}

/// Pixels whose colour is clearly of one hue: `(blue, green, red, brown)`.
fn hue_counts(image: &RgbaImage) -> (usize, usize, usize, usize) {
    let mut counts = (0, 0, 0, 0);
    for p in image.pixels() {
        let [r, g, b, _] = p.0.map(i32::from);
        if b > r + 60 && b > g + 40 {
            counts.0 += 1;
        } else if g > r + 50 && g > b + 50 {
            counts.1 += 1;
        } else if r > g + 70 && r > b + 70 {
            counts.2 += 1;
        } else if r > g + 8 && g > b + 4 && r > 40 && r < 160 && r - b > 20 {
            counts.3 += 1;
        }
    }
    counts
}

/// `cargo test` builds the examples into `target/<profile>/examples/`, next to the test
/// binaries' folder: as `name`, or as `name-<hash>` (the newest is taken).
fn example(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let folder = exe
        .parent()
        .and_then(Path::parent)
        .unwrap()
        .join("examples");
    let plain = folder.join(name);
    if plain.exists() {
        return plain;
    }
    let prefix = format!("{name}-");
    std::fs::read_dir(&folder)
        .into_iter()
        .flatten()
        .filter_map(|e| e.ok())
        .filter(|e| {
            let file = e.file_name().to_string_lossy().into_owned();
            file.strip_prefix(&prefix)
                .is_some_and(|hash| hash.chars().all(|c| c.is_ascii_hexdigit()))
        })
        .max_by_key(|e| e.metadata().and_then(|m| m.modified()).ok())
        .map_or(plain, |e| e.path())
}

/// The scene the app said it showed when it quit.
fn scene_shown(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .find_map(|l| l.strip_prefix("scene ").map(str::to_owned))
        .unwrap_or_default()
}

fn unattended(program: &Path, extra: &[&str], at: &str, dir: &Path) -> Output {
    let mut args = extra.to_vec();
    args.extend(["--screenshot-at", at, "--exit", "--screenshot-dir"]);
    args.push(dir.to_str().unwrap());
    run_in_window(program, &args, Duration::from_secs(300))
}

#[test]
fn lab_and_examples_in_a_real_window() {
    let shots = temp_dir("shots");
    std::fs::create_dir_all(&shots).unwrap();
    // The lab opened on the tutorial's scene 2: blue, green and red spheres, the time on it.
    let lab = Path::new(env!("CARGO_BIN_EXE_sphere_lab"));
    let out = unattended(
        lab,
        &["--scene", "density_collisions"],
        "1",
        &shots.join("density"),
    );
    let image = screenshot(&out);
    assert_eq!(scene_shown(&out), "density_collisions");
    assert_eq!((image.width(), image.height()), (1280, 720));
    let time = read_time_stamp(&image).expect("the time is written on the screenshot");
    // Stamped at the first frame at or past 1 s: the clock is held until the picture has
    // settled (as the screenshot waits), then moves at most Bevy's 0.25 s a frame (1.196
    // seen here; a frame more allowed).
    assert!((1.0..1.6).contains(&time), "{time}");
    let (blue, green, red, _) = hue_counts(&image);
    assert!(
        blue > 1000 && green > 1000 && red > 1000,
        "blue {blue}, green {green}, red {red}"
    );

    // The Newton's cradle example: blue balls on a wooden frame.
    let cradle = example("newtons_cradle");
    assert!(
        cradle.exists(),
        "{} is built by cargo test",
        cradle.display()
    );
    let out = unattended(&cradle, &[], "1", &shots.join("cradle"));
    let image = screenshot(&out);
    assert_eq!(scene_shown(&out), "newtons_cradle");
    assert!(read_time_stamp(&image).is_some_and(|t| t >= 1.0));
    let (blue, green, red, brown) = hue_counts(&image);
    assert!(blue > 3000, "blue {blue}");
    assert!(brown > 2000, "frame {brown}");
    assert!(green < 100 && red < 100, "green {green}, red {red}");

    // Every other example opens its own scene and draws it; `lab` opens the chooser.
    for (name, scene) in [
        ("density_collisions", "density_collisions"),
        ("applied_forces", "applied_forces"),
        ("sphere_shower", "sphere_shower"),
        ("touching_cradle", "touching_cradle"),
        ("lab", ""),
    ] {
        let program = example(name);
        let out = unattended(&program, &[], "0.2", &shots.join(name));
        let image = screenshot(&out);
        assert_eq!(scene_shown(&out), scene, "{name}");
        assert!(read_time_stamp(&image).is_some(), "{name}");
        if !scene.is_empty() {
            let (blue, ..) = hue_counts(&image);
            assert!(blue > 500, "{name}: blue {blue}");
        }
    }

    // A ball that falls onto a planet-sized floor sphere is still in the picture once it has
    // come to rest (the camera framed its starting place only, and the ball left the picture).
    let out = unattended(
        lab,
        &["--scene", "settling_ball"],
        "2.5",
        &shots.join("settling"),
    );
    let image = screenshot(&out);
    assert_eq!(scene_shown(&out), "settling_ball");
    let (blue, ..) = hue_counts(&image);
    assert!(blue > 2000, "the resting ball: blue {blue}");

    // A folder that cannot be made: the failure is reported (exit code 1 with --exit).
    let blocker = shots.join("blocked");
    std::fs::write(&blocker, b"a file").unwrap();
    let out = unattended(&cradle, &[], "0.5", &blocker.join("shots"));
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("screenshot failed"), "{stderr}");
}
