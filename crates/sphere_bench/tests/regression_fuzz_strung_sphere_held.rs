//! Regression: with no gravity, a light sphere on a short taut string, pressed out along it
//! by a much heavier one, was left deep in it: the separation that moves overlapping spheres
//! apart at a step's end shared each move by the masses, so the light sphere took nearly all
//! of it, and its string, holding it at its length, took it back. `sphere-fuzz --strings
//! fast` found two such scenes among seeds 0 to 14 999 (of 102 and 114 spheres): at seed
//! 1213 a sphere of 65 mg on a string of 24 cm pressed by one of 1 kg ended a step 1.1 of its
//! radii into it, at seed 9000 one of 11 g on a string of 18 cm pressed by one of 19 kg 20%
//! deep for three steps. A sphere its string holds against the move (within 30° of straight
//! out along it) is no longer moved: the other sphere takes all of the move. Neither scene
//! now ends a step more than 2% of a radius deep; this test holds them under the fuzz's 5%.
//!
//! The scenes are the fuzz's own (a pair reduced from either does not do it), so the test
//! runs the fuzz binary on those two seeds and reads its summary.

use std::process::Command;

#[test]
fn regression_strung_spheres_pressed_out_along_their_strings_are_moved_apart() {
    for seed in ["1213", "9000"] {
        let output = Command::new(env!("CARGO_BIN_EXE_sphere-fuzz"))
            .args(["--strings", "fast", "--from", seed, "--count", "1"])
            .output()
            .expect("the fuzz runs");
        let text = String::from_utf8_lossy(&output.stdout);
        assert!(
            output.status.success(),
            "seed {seed}: a check failed\n{text}"
        );
        // One summary line and no scene listed as past 5% of a radius.
        assert!(
            text.contains("0 errors; past 5% of a radius: 0 within the collision budget"),
            "seed {seed}:\n{text}"
        );
        assert_eq!(text.lines().count(), 1, "seed {seed}:\n{text}");
    }
}
