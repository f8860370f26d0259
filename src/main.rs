//! The sphere lab (main job): opens the scene chooser. Keys: Enter chooser (Up/Down, Enter to
//! load), P pause, N step while paused, R restart, Space screenshot; drag to orbit, scroll to
//! zoom.
//!
//! Flags: `--scene ID` opens a scene directly, `--screenshot-dir DIR` (default `screenshots/`),
//! `--screenshot-at SECONDS` takes a screenshot once the simulated time reaches it, `--exit`
//! quits after that screenshot.

fn main() -> bevy::app::AppExit {
    sphere_lab::lab_app(None).run()
}
