//! The lab's scene files, damaged at random (characters cut, inserted or replaced, numbers made
//! huge, negative, zero or not numbers, the text cut short): loading never panics, a file that
//! does not parse says where (a line and a column within the text), and one that parses
//! either builds a world that steps or says which field is wrong.

mod common;

use proptest::prelude::*;
use sphere_physics::{SceneDesc, SceneError};

const SCENES: [&str; 12] = [
    include_str!("../../../assets/scenes/applied_forces.ron"),
    include_str!("../../../assets/scenes/ball_pit.ron"),
    include_str!("../../../assets/scenes/density_collisions.ron"),
    include_str!("../../../assets/scenes/gas_box.ron"),
    include_str!("../../../assets/scenes/light_on_heavy.ron"),
    include_str!("../../../assets/scenes/newtons_cradle.ron"),
    include_str!("../../../assets/scenes/newtons_cradle_two.ron"),
    include_str!("../../../assets/scenes/settling_ball.ron"),
    include_str!("../../../assets/scenes/sphere_shower.ron"),
    include_str!("../../../assets/scenes/stress_shower.ron"),
    include_str!("../../../assets/scenes/touching_cradle.ron"),
    include_str!("../../../assets/scenes/two_spheres.ron"),
];

/// Numbers a damaged file may hold.
const NUMBERS: [&str; 12] = [
    "0",
    "-1",
    "1e400",
    "-1e400",
    "NaN",
    "inf",
    "1e308",
    "4294967296",
    "1e-320",
    "-0.0",
    "1e9",
    "9999999999999999999999",
];

#[derive(Clone, Debug)]
enum Damage {
    /// Cut `len` characters at `at` (both as shares of the text).
    Cut(f64, f64),
    /// Insert a piece of RON syntax at `at`.
    Insert(f64, &'static str),
    /// Replace the number nearest after `at` with another.
    Number(f64, &'static str),
    /// Keep only the text before `at`.
    Truncate(f64),
}

fn damage() -> impl Strategy<Value = Damage> {
    let at = 0.0..1.0f64;
    prop_oneof![
        (at.clone(), 0.0..0.05f64).prop_map(|(a, l)| Damage::Cut(a, l)),
        (
            at.clone(),
            prop::sample::select(vec![
                "(",
                ")",
                "[",
                "]",
                ",",
                ":",
                "\"",
                "x",
                "fixed: true,",
                "radius: 0.0,",
                "tether: (anchor: (0.0, 0.0, 0.0), length: 1.0),",
                "Some(",
                "//",
                "/*",
                "generate: [],",
                "count: 4000000000,",
                "((((((((((((((((",
                "[[[[[[[[[[[[[[[[",
            ])
        )
            .prop_map(|(a, s)| Damage::Insert(a, s)),
        (at.clone(), prop::sample::select(NUMBERS.to_vec()))
            .prop_map(|(a, n)| Damage::Number(a, n)),
        at.prop_map(Damage::Truncate),
    ]
}

/// The character boundary nearest at or after the share `at` of `text`.
fn boundary(text: &str, at: f64) -> usize {
    let mut i = ((text.len() as f64) * at) as usize;
    while i < text.len() && !text.is_char_boundary(i) {
        i += 1;
    }
    i.min(text.len())
}

fn apply(text: &str, damage: &Damage) -> String {
    match *damage {
        Damage::Cut(at, len) => {
            let start = boundary(text, at);
            let end = boundary(text, (at + len).min(1.0)).max(start);
            format!("{}{}", &text[..start], &text[end..])
        }
        Damage::Insert(at, piece) => {
            let i = boundary(text, at);
            format!("{}{piece}{}", &text[..i], &text[i..])
        }
        Damage::Number(at, number) => {
            let i = boundary(text, at);
            let Some(start) = text[i..].find(|c: char| c.is_ascii_digit()).map(|s| s + i) else {
                return text.to_string();
            };
            let end = text[start..]
                .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == 'e' || c == '-'))
                .map_or(text.len(), |e| e + start);
            format!("{}{number}{}", &text[..start], &text[end..])
        }
        Damage::Truncate(at) => text[..boundary(text, at)].to_string(),
    }
}

proptest! {
    #![proptest_config(common::proptest_config(128, common::SEED))]

    #[test]
    fn damaged_scene_files_are_refused_or_run(
        scene in 0..SCENES.len(),
        damages in prop::collection::vec(damage(), 1..4),
    ) {
        let mut text = SCENES[scene].to_string();
        for d in &damages {
            text = apply(&text, d);
        }
        match SceneDesc::from_ron(&text) {
            Err(SceneError::Parse { line, column, message, .. }) => {
                let lines = text.lines().count().max(1);
                prop_assert!(line >= 1 && line <= lines + 1, "line {} of {}: {}", line, lines, message);
                // Within its line (or just past its end, where the text ran out).
                let width = text.lines().nth(line - 1).map_or(0, |l| l.chars().count());
                prop_assert!(
                    column >= 1 && column <= width + 2,
                    "column {} of {}: {}", column, width, message
                );
                prop_assert!(!message.is_empty());
            }
            Err(other) => prop_assert!(false, "not a parse error: {other}"),
            Ok(desc) => {
                // A scene of millions of spheres is refused or made: not stepped here. The
                // stress shower's 10 001 are, for fewer steps (until the fifty-seventh session
                // every scene past 5000 spheres was skipped, the stress shower among them).
                if desc.len() > 20_000 {
                    return Ok(());
                }
                let steps = if desc.len() > 5000 { 3 } else { 30 };
                match desc.build() {
                    Ok(mut world) => {
                        let dt = 1.0 / 60.0;
                        for _ in 0..steps {
                            if let Err(error) = world.step(dt) {
                                prop_assert!(!error.to_string().is_empty());
                                break;
                            }
                        }
                        for body in world.bodies() {
                            prop_assert!(body.position().is_finite() && body.velocity().is_finite());
                        }
                    }
                    Err(error) => prop_assert!(!error.to_string().is_empty()),
                }
            }
        }
    }
}
