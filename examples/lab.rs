//! The sphere lab: the scene chooser opens at start; every scene in `assets/scenes/` is listed.
//!
//! Keys: Enter opens the chooser (Up/Down select, Enter loads, Escape closes it once a scene
//! is loaded), P pauses, N steps once while paused, R restarts, Space saves a screenshot with
//! the simulated time on it (into `screenshots/`, or `--screenshot-dir DIR`). Orbit by dragging
//! with the left mouse button or with the arrow keys; zoom with the wheel or `-`/`=` (the
//! keypad's `-`/`+` too).

fn main() -> bevy::app::AppExit {
    sphere_lab::lab_app(None).run()
}
