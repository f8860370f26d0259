//! The tutorial's scene 4: thousands of small spheres fall onto a large fixed sphere, bounce, and
//! slide off its frictionless sides, every collision found exactly (no tunnelling): the grid broad
//! phase finds the pairs whose swept paths may meet, and the exact swept test finds when they do.
//!
//! Keys: P pauses, N steps once while paused, R restarts, Space saves a screenshot with the
//! simulated time on it, Enter opens the scene chooser (Up/Down select, Enter loads, Escape
//! closes it). Orbit by dragging with the left mouse button or with the arrow keys; zoom with
//! the wheel or `-`/`=` (the keypad's `-`/`+` too).

fn main() -> bevy::app::AppExit {
    sphere_lab::lab_app(Some("sphere_shower")).run()
}
