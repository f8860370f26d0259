//! The sphere lab (main job): opens the scene chooser. Keys: Enter chooser (Up/Down, Enter to
//! load, Escape to close once a scene is loaded), P pause, N step while paused, R restart,
//! Space screenshot; orbit by dragging with the left mouse button or with the arrow keys,
//! zoom with the wheel or `-`/`=` (keypad `-`/`+`).
//!
//! Flags: `--scene ID` opens a scene directly, `--screenshot-dir DIR` (default `screenshots/`),
//! `--screenshot-at SECONDS` takes a screenshot once the simulated time of the scene reaches it
//! (without `--exit`, waiting for a scene to be chosen), `--exit` quits after that screenshot
//! (with no scene, it captures the chooser).

fn main() -> bevy::app::AppExit {
    sphere_lab::lab_app(None).run()
}
