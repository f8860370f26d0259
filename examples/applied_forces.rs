//! The tutorial's scene 1: spheres moving under applied forces and gravity.
//!
//! Keys: P pauses, N steps once while paused, R restarts, Space saves a screenshot with the
//! simulated time on it, Enter opens the scene chooser (Up/Down select, Enter loads, Escape
//! closes it). Orbit by dragging with the left mouse button or with the arrow keys; zoom with
//! the wheel or `-`/`=` (the keypad's `-`/`+` too).

fn main() -> bevy::app::AppExit {
    sphere_lab::lab_app(Some("applied_forces")).run()
}
