//! `sphere-sim`: play a [`sphere_physics`] scene file headless and report the end state as JSON.
//!
//! The binary is a thin shell over this library: [`cli::parse`] reads the command line,
//! [`run::play`] steps the scene, [`trace`] writes per-step rows and [`progress`] draws a bar.
#![warn(missing_docs)]

pub mod cli;
pub mod progress;
pub mod run;
pub mod trace;
