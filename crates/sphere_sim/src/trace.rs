//! Per-step traces for plotting: CSV with a header, or one JSON object per line.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use serde::Serialize;
use sphere_physics::StepStats;

use crate::cli::TraceFormat;

/// One line of a trace.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TraceRow {
    /// Step number, from 1.
    pub step: u64,
    /// Simulated time at the end of the step.
    pub time: f64,
    /// The step's length.
    pub dt: f64,
    /// Collisions resolved in the step, as `StepStats::collisions` counts them (one per
    /// collision record).
    pub collisions: u32,
    /// Of those, resting contacts.
    pub resting_contacts: u32,
    /// Impacts deferred to the next step (`StepStats::collisions_deferred`).
    pub collisions_deferred: u32,
    /// Kinetic energy.
    pub kinetic_energy: f64,
    /// Potential energy.
    pub potential_energy: f64,
    /// Total energy.
    pub total_energy: f64,
    /// Momentum, x.
    pub momentum_x: f64,
    /// Momentum, y.
    pub momentum_y: f64,
    /// Momentum, z.
    pub momentum_z: f64,
    /// Largest overlap at the end of the step.
    pub max_overlap: f64,
}

impl TraceRow {
    /// The row for step number `step`.
    pub fn new(step: u64, stats: &StepStats) -> Self {
        Self {
            step,
            time: stats.time,
            dt: stats.dt,
            collisions: stats.collisions,
            resting_contacts: stats.resting_contacts,
            collisions_deferred: stats.collisions_deferred,
            kinetic_energy: stats.kinetic_energy,
            potential_energy: stats.potential_energy,
            total_energy: stats.total_energy(),
            momentum_x: stats.momentum.x,
            momentum_y: stats.momentum.y,
            momentum_z: stats.momentum.z,
            max_overlap: stats.max_overlap,
        }
    }
}

const CSV_HEADER: &str = "step,time,dt,collisions,resting_contacts,collisions_deferred,\
kinetic_energy,potential_energy,total_energy,momentum_x,momentum_y,momentum_z,max_overlap";

/// Writes trace rows to a file.
pub struct TraceWriter {
    out: BufWriter<File>,
    format: TraceFormat,
    rows: u64,
}

impl TraceWriter {
    /// Creates the file (and writes the CSV header).
    pub fn create(path: &Path, format: TraceFormat) -> io::Result<Self> {
        let mut out = BufWriter::new(File::create(path)?);
        if format == TraceFormat::Csv {
            writeln!(out, "{CSV_HEADER}")?;
        }
        Ok(Self {
            out,
            format,
            rows: 0,
        })
    }

    /// Appends one row.
    pub fn write(&mut self, row: &TraceRow) -> io::Result<()> {
        self.rows += 1;
        match self.format {
            TraceFormat::Csv => writeln!(
                self.out,
                "{},{:?},{:?},{},{},{},{:?},{:?},{:?},{:?},{:?},{:?},{:?}",
                row.step,
                row.time,
                row.dt,
                row.collisions,
                row.resting_contacts,
                row.collisions_deferred,
                row.kinetic_energy,
                row.potential_energy,
                row.total_energy,
                row.momentum_x,
                row.momentum_y,
                row.momentum_z,
                row.max_overlap
            ),
            TraceFormat::JsonLines => {
                serde_json::to_writer(&mut self.out, row).map_err(io::Error::other)?;
                writeln!(self.out)
            }
        }
    }

    /// How many rows were written (or attempted).
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Flushes what is buffered.
    pub fn finish(mut self) -> io::Result<()> {
        self.out.flush()
    }
}
