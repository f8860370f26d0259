//! `sphere-sim run SCENE.ron --duration SECONDS`: see `sphere-sim --help`.
//!
//! Exit codes: 0 success; 2 bad input (usage, scene file, invalid sphere), with one line on
//! standard error and no JSON written; 1 when writing the output fails.

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use sphere_physics::{SceneDesc, SceneError};
use sphere_sim::cli::{self, Command, Output, RunArgs};
use sphere_sim::progress::Progress;
use sphere_sim::run::{PlayError, Playback, Prepared, play_prepared};
use sphere_sim::trace::{TraceRow, TraceWriter};

/// A failure and the exit code it maps to.
struct Failure {
    code: u8,
    message: String,
}

fn bad_input(message: impl ToString) -> Failure {
    Failure {
        code: 2,
        message: message.to_string(),
    }
}

fn io_failure(message: impl ToString) -> Failure {
    Failure {
        code: 1,
        message: message.to_string(),
    }
}

/// Whether two paths name the same file, whether or not it exists yet: each is resolved as far
/// as it exists (the file, or else its folder and its name in it). A path whose folder does
/// not exist names no file this run could write.
fn same_file(a: &Path, b: &Path) -> bool {
    fn resolve(path: &Path) -> Option<PathBuf> {
        if let Ok(full) = path.canonicalize() {
            return Some(full);
        }
        let name = path.file_name()?;
        let folder = match path.parent() {
            Some(folder) if !folder.as_os_str().is_empty() => folder,
            _ => Path::new("."),
        };
        Some(folder.canonicalize().ok()?.join(name))
    }
    a == b || resolve(a).is_some_and(|a| resolve(b) == Some(a))
}

fn main() -> ExitCode {
    // `args()` would panic on an argument that is not UTF-8: bad input, said as such.
    let args: Result<Vec<String>, Failure> = std::env::args_os()
        .skip(1)
        .enumerate()
        .map(|(i, a)| {
            a.into_string().map_err(|a| {
                bad_input(format!(
                    "argument {} is not valid UTF-8: {}",
                    i + 1,
                    a.to_string_lossy()
                ))
            })
        })
        .collect();
    let result = args
        .and_then(|args| cli::parse(&args).map_err(bad_input))
        .and_then(|command| match command {
            Command::Help => print(&format!("{}\n", cli::USAGE), "the help"),
            Command::Version => print(
                &format!("sphere-sim {}\n", env!("CARGO_PKG_VERSION")),
                "the version",
            ),
            Command::Run(run) => run_command(&run),
        });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            // One line, whatever the message holds: a line break is a space, and any other
            // control character (a carriage return in a sphere's name would overwrite the line
            // on a terminal) is written as its escape.
            let line: String = failure
                .message
                .chars()
                .map(|c| match c {
                    '\n' => " ".to_string(),
                    c if c.is_control() => c.escape_default().to_string(),
                    c => c.to_string(),
                })
                .collect();
            // Not `eprintln!`, which panics when standard error is closed.
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "sphere-sim: error: {line}");
            ExitCode::from(failure.code)
        }
    }
}

/// Writes `text` (`what` it is) to standard output: a reader that stopped early (`| head`,
/// `| true`) is not an error, and no panic (`println!` panics on a closed pipe).
fn print(text: &str, what: &str) -> Result<(), Failure> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other.map_err(|e| io_failure(format!("writing {what}: {e}"))),
    }
}

fn run_command(args: &RunArgs) -> Result<(), Failure> {
    let scene = SceneDesc::load(&args.scene).map_err(bad_input)?;
    let playback = Playback {
        duration: args.duration,
        dt: args.dt,
        method: args.method,
    };
    // Check the whole scene, the overrides and the number of steps before creating any file;
    // errors found after parsing name the file too (parse errors already say where).
    let prepared = Prepared::new(&scene, playback).map_err(|e| match e {
        PlayError::Scene(SceneError::Io { .. } | SceneError::Parse { .. })
        | PlayError::TooManySteps { .. }
        | PlayError::LastStepTooShort { .. } => bad_input(e),
        e => bad_input(format!("{}: {e}", args.scene.display())),
    })?;
    // An output that is the scene or the trace would overwrite it.
    let output = match &args.output {
        Output::File(path) => Some(path.as_path()),
        Output::Stdout => None,
    };
    let trace = args.trace.as_ref().map(|(path, _)| path.as_path());
    let scene_file = Some(args.scene.as_path());
    for (flag, file, other, what) in [
        ("--output", output, scene_file, "is the scene file itself"),
        ("--output", output, trace, "is the --trace file too"),
        ("--trace", trace, scene_file, "is the scene file itself"),
    ] {
        if let (Some(a), Some(b)) = (file, other)
            && same_file(a, b)
        {
            return Err(bad_input(format!("{flag} {}: {what}", a.display())));
        }
    }
    if let Output::File(path) = &args.output
        && path.is_dir()
    {
        return Err(bad_input(format!(
            "--output {}: is a folder, not a file",
            path.display()
        )));
    }
    if let Output::File(path) = &args.output
        && let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
        && !dir.is_dir()
    {
        return Err(bad_input(format!(
            "--output {}: folder {} does not exist",
            path.display(),
            dir.display()
        )));
    }
    let mut trace = match &args.trace {
        Some((path, format)) => Some(
            TraceWriter::create(path, *format)
                .map_err(|e| bad_input(format!("{}: {e}", path.display())))?,
        ),
        None => None,
    };
    let mut trace_error = None;
    let mut progress = Progress::new(args.progress);
    let mut observer = |stats: &sphere_physics::StepStats, world: &sphere_physics::World, total| {
        if let Some(writer) = trace.as_mut()
            && let Err(e) = writer.write(&TraceRow::new(world.steps(), stats))
        {
            // The run stops here: its trace is what was asked for.
            trace_error = Some(e);
            return ControlFlow::Break(());
        }
        progress.update(world.steps(), total, world.time());
        ControlFlow::Continue(())
    };
    let report = match play_prepared(prepared, &mut observer) {
        Ok(report) => report,
        Err(PlayError::Stopped { step }) => {
            progress.finish();
            let e = trace_error.expect("only a failed trace stops the run");
            let path = args.trace.as_ref().map_or(Path::new(""), |(p, _)| p);
            return Err(io_failure(format!(
                "writing the trace {}: {e} (the run was stopped at step {step}; no report)",
                path.display()
            )));
        }
        Err(e) => {
            progress.finish();
            // Keep what was traced up to the failure (it shows how the run got there), and
            // say so.
            let mut message = e.to_string();
            if let (Some(writer), Some((path, _))) = (trace, &args.trace) {
                let rows = writer.rows();
                match (trace_error, writer.finish()) {
                    (None, Ok(())) => message.push_str(&format!(
                        "; the trace {} holds the {rows} step(s) before it",
                        path.display()
                    )),
                    (Some(w), _) | (None, Err(w)) => {
                        message.push_str(&format!("; writing the trace also failed: {w}"))
                    }
                }
            }
            return Err(bad_input(message));
        }
    };
    progress.finish();
    if let (Some(writer), Some((path, _))) = (trace, &args.trace) {
        writer.finish().map_err(|e| {
            io_failure(format!(
                "writing the trace {}: {e} (at its end; no report)",
                path.display()
            ))
        })?;
    }
    let mut json = serde_json::to_string_pretty(&report)
        .map_err(|e| io_failure(format!("encoding the report: {e}")))?;
    json.push('\n');
    match &args.output {
        Output::Stdout => print(&json, "the report"),
        Output::File(path) => {
            std::fs::write(path, json).map_err(|e| io_failure(format!("{}: {e}", path.display())))
        }
    }
}
