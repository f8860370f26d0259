//! The tutorial's scene 3, on strings: Newton's cradle, five steel balls hanging from a frame,
//! touching at rest; the first is raised by 30 degrees and let go. Exactly one ball flies out
//! on the far side, back and forth (RATTLE-integrated strings, leapfrog, 2 substeps: the
//! swing keeps its energy to about 0.2% a minute). The scene's other half, a ball striking
//! two at once, is `cargo run --example touching_cradle`.
//!
//! Keys: P pauses, N steps once while paused, R restarts, Space saves a screenshot with the
//! simulated time on it, Enter opens the scene chooser (Up/Down select, Enter loads, Escape
//! closes it). Orbit by dragging with the left mouse button or with the arrow keys; zoom with
//! the wheel or `-`/`=` (the keypad's `-`/`+` too).

fn main() -> bevy::app::AppExit {
    sphere_lab::lab_app(Some("newtons_cradle")).run()
}
