//! The tutorial's scene 3, without strings: shock propagation through a row of four touching balls
//! struck by a fifth (one ball in, one ball out) and a ball striking two touching balls at the same
//! instant, with the momentum shared as the impulses of both contacts solved together give it (the
//! tutorial's admitted flaw was to get this wrong). No gravity.
//!
//! Keys: P pauses, N steps once while paused, R restarts, Space saves a screenshot with the
//! simulated time on it, Enter opens the scene chooser (Up/Down select, Enter loads, Escape
//! closes it). Orbit by dragging with the left mouse button or with the arrow keys; zoom with
//! the wheel or `-`/`=` (the keypad's `-`/`+` too).

fn main() -> bevy::app::AppExit {
    sphere_lab::lab_app(Some("touching_cradle")).run()
}
