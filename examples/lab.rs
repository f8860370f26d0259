//! The sphere lab: the scene chooser opens at start; every scene in `assets/scenes/` is listed.
//!
//! Keys: Enter opens the chooser (Up/Down select, Enter loads), P pauses, N steps once while
//! paused, R restarts, Space saves a screenshot with the simulated time on it (into
//! `screenshots/`, or `--screenshot-dir DIR`). Drag with the left mouse button to orbit,
//! scroll to zoom.

fn main() -> bevy::app::AppExit {
    sphere_lab::lab_app(None).run()
}
