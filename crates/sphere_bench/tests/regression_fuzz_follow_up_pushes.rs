//! Regression from `sphere-fuzz --overlapping` (seed 940 493, found 2026-12-06): a fallback's
//! follow-up solve (see `regression_fallback_follow_up_takes_the_crowd_again` in the core's
//! tests) takes again the bodies the solves before it took, some of them with the deep pushes
//! those solves gave still in their velocities. Solved again with them, then the pushes taken
//! off at the step's end, the bodies kept the solve's answer to their pushes as their own: at
//! step 23 of that scene the kinetic energy went from 1.25 kJ to 6.09 kJ. A follow-up now
//! takes those pushes off first, and gives its own. The scene is the fuzz's own, so this test
//! runs the fuzz binary on that seed and reads its summary: no check failed.

use std::process::Command;

#[test]
fn regression_a_follow_up_solve_gains_no_energy_from_the_pushes_before_it() {
    let output = Command::new(env!("CARGO_BIN_EXE_sphere-fuzz"))
        .args(["--overlapping", "--from", "940493", "--count", "1"])
        .output()
        .expect("the fuzz runs");
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "a check failed\n{text}");
    assert!(
        text.contains("1 scenes (0 with strings): 0 errors"),
        "{text}"
    );
}
