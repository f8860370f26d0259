//! Command-line parsing: arguments to a [`Command`], or a one-line [`UsageError`].

use std::path::PathBuf;

use sphere_physics::ToiMethod;

/// The usage text printed by `sphere-sim help`.
pub const USAGE: &str = "\
sphere-sim: play a sphere_physics scene file headless and print JSON.

Usage:
  sphere-sim run SCENE.ron --duration SECONDS [--dt SECONDS] [--method exact|bisection[:N]]
                 [--output FILE|-] [--trace FILE.csv|FILE.jsonl] [--no-progress]
  sphere-sim help | --help | -h
  sphere-sim --version

run:
  --duration S    simulated seconds to play (required, > 0)
  --dt S          time step (default: the scene's dt, else 1/60)
  --method M      time of impact: exact (closed form) or bisection[:N] (N iterations, default 8);
                  default: the scene's method, else exact
  --output F      where the JSON report goes (default -, standard output)
  --trace F       per-step time, energy, momentum, overlap and collisions, as CSV (.csv)
                  or JSON lines (.jsonl)
  --no-progress   no progress bar (there is none anyway when standard error is not a terminal)

Bad input (a missing or invalid scene file, a bad flag) prints one line on standard error and
exits with code 2, writing no JSON.";

/// What the user asked for.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Play a scene.
    Run(RunArgs),
    /// Print the usage.
    Help,
    /// Print the version.
    Version,
}

/// Where the JSON report goes.
#[derive(Clone, Debug, PartialEq)]
pub enum Output {
    /// Standard output.
    Stdout,
    /// A file, written whole at the end.
    File(PathBuf),
}

/// The format of a trace file, from its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraceFormat {
    /// Comma-separated values with a header line.
    Csv,
    /// One JSON object per line.
    JsonLines,
}

/// Arguments of `sphere-sim run`.
#[derive(Clone, Debug, PartialEq)]
pub struct RunArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// Simulated seconds to play.
    pub duration: f64,
    /// Time step; `None` means the scene's, else 1/60.
    pub dt: Option<f64>,
    /// Time-of-impact method; `None` means the scene's, else exact.
    pub method: Option<ToiMethod>,
    /// Where the report goes.
    pub output: Output,
    /// Per-step trace file and its format.
    pub trace: Option<(PathBuf, TraceFormat)>,
    /// Show a progress bar when standard error is a terminal.
    pub progress: bool,
}

/// A bad command line, said in one line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0} (see sphere-sim --help)")]
pub struct UsageError(pub String);

fn usage(message: impl Into<String>) -> UsageError {
    UsageError(message.into())
}

/// The most bisection iterations accepted: past 64 halvings of a step nothing changes in f64.
pub use sphere_physics::MAX_BISECTION_ITERATIONS;

/// Parses a method name: `exact`, `bisection` (8 iterations) or `bisection:N`.
pub fn parse_method(text: &str) -> Result<ToiMethod, UsageError> {
    match text.split_once(':') {
        None if text == "exact" => Ok(ToiMethod::Exact),
        None if text == "bisection" => Ok(ToiMethod::Bisection { max_iterations: 8 }),
        Some(("bisection", n)) => match n.parse::<u32>() {
            Ok(n) if n <= MAX_BISECTION_ITERATIONS => {
                Ok(ToiMethod::Bisection { max_iterations: n })
            }
            _ => Err(usage(format!(
                "--method bisection:N needs N from 0 to {MAX_BISECTION_ITERATIONS}, got '{n}'"
            ))),
        },
        _ => Err(usage(format!(
            "--method must be exact, bisection or bisection:N, got '{text}'"
        ))),
    }
}

/// The name `parse_method` reads back: `exact` or `bisection:N`.
pub fn method_name(method: &ToiMethod) -> String {
    match method {
        ToiMethod::Exact => "exact".to_owned(),
        ToiMethod::Bisection { max_iterations } => format!("bisection:{max_iterations}"),
    }
}

fn parse_seconds(flag: &str, text: &str) -> Result<f64, UsageError> {
    match text.parse::<f64>() {
        // Normal: a subnormal step (or a last step that short) is refused by the world.
        Ok(v) if v.is_normal() && v > 0.0 => Ok(v),
        _ => Err(usage(format!(
            "{flag} must be a finite, normal number of seconds > 0, got '{text}'"
        ))),
    }
}

fn trace_format(path: &str) -> Result<TraceFormat, UsageError> {
    if path.ends_with(".csv") {
        Ok(TraceFormat::Csv)
    } else if path.ends_with(".jsonl") {
        Ok(TraceFormat::JsonLines)
    } else {
        Err(usage(format!(
            "--trace needs a file ending in .csv or .jsonl, got '{path}'"
        )))
    }
}

/// Parses the arguments after the program name.
pub fn parse(args: &[String]) -> Result<Command, UsageError> {
    let mut args = args.iter().map(String::as_str);
    match args.next() {
        None => Err(usage("no command given")),
        Some(command @ ("help" | "--help" | "-h" | "--version" | "-V")) => {
            if let Some(extra) = args.next() {
                return Err(usage(format!(
                    "unexpected argument '{extra}' after '{command}'"
                )));
            }
            Ok(if command.starts_with("--v") || command == "-V" {
                Command::Version
            } else {
                Command::Help
            })
        }
        Some("run") => parse_run(args).map(Command::Run),
        Some(other) => Err(usage(format!("unknown command '{other}'"))),
    }
}

fn parse_run<'a>(mut args: impl Iterator<Item = &'a str>) -> Result<RunArgs, UsageError> {
    let mut scene = None;
    let mut duration = None;
    let mut dt = None;
    let mut method = None;
    let mut output = Output::Stdout;
    let mut trace = None;
    let mut progress = true;
    let mut given: Vec<&str> = Vec::new();
    while let Some(arg) = args.next() {
        let (flag, inline) = match arg.split_once('=') {
            Some((f, v)) if f.starts_with("--") => (f, Some(v)),
            _ => (arg, None),
        };
        // A flag given twice is a mistake either way: refused rather than one silently kept.
        let canonical = if flag == "-o" { "--output" } else { flag };
        if canonical.starts_with('-') && canonical.len() > 1 {
            if given.contains(&canonical) {
                return Err(usage(format!("{canonical} is given more than once")));
            }
            given.push(canonical);
        }
        let mut value = |flag: &str| -> Result<&'a str, UsageError> {
            match inline {
                Some(v) => Ok(v),
                None => args
                    .next()
                    .ok_or_else(|| usage(format!("{flag} needs a value"))),
            }
        };
        match flag {
            "--duration" => duration = Some(parse_seconds(flag, value(flag)?)?),
            "--dt" => dt = Some(parse_seconds(flag, value(flag)?)?),
            "--method" => method = Some(parse_method(value(flag)?)?),
            "--output" | "-o" => {
                output = match value(flag)? {
                    "-" => Output::Stdout,
                    "" => return Err(usage("--output needs a file name or -")),
                    path => Output::File(path.into()),
                }
            }
            "--trace" => {
                let path = value(flag)?;
                trace = Some((PathBuf::from(path), trace_format(path)?));
            }
            "--no-progress" if inline.is_none() => progress = false,
            _ if flag.starts_with('-') && flag.len() > 1 => {
                return Err(usage(format!("unknown flag '{arg}'")));
            }
            _ if scene.is_none() => scene = Some(PathBuf::from(arg)),
            _ => return Err(usage(format!("unexpected argument '{arg}'"))),
        }
    }
    Ok(RunArgs {
        scene: scene.ok_or_else(|| usage("run needs a scene file"))?,
        duration: duration.ok_or_else(|| usage("run needs --duration SECONDS"))?,
        dt,
        method,
        output,
        trace,
        progress,
    })
}
