//! The tutorial's scene 2: collisions between spheres of different densities, blue 1x, green
//! 2x, red 3x, head on and oblique, elastic and without gravity.
//!
//! Keys: P pauses, N steps once while paused, R restarts, Space saves a screenshot with the
//! simulated time on it, Enter opens the scene chooser. Drag to orbit, scroll to zoom.

fn main() -> bevy::app::AppExit {
    sphere_lab::lab_app(Some("density_collisions")).run()
}
