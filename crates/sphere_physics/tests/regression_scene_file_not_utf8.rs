//! Regression (found by review): a scene file that is not UTF-8 text failed with "stream did
//! not contain valid UTF-8" and no place; it now says the line and column of its first bad
//! byte, as a parse error does.

use sphere_physics::{SceneDesc, SceneError};

#[test]
fn regression_a_file_that_is_not_utf8_says_where() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("scene_not_utf8");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.ron");
    // A Latin-1 "é" (one byte, 0xe9) in the second line's name.
    let mut bytes = b"(name: \"ok\",\n spheres: [(name: \"caf".to_vec();
    bytes.push(0xe9);
    bytes.extend_from_slice(b"\", position: (0.0, 0.0, 0.0), radius: 1.0)])");
    std::fs::write(&path, &bytes).unwrap();
    match SceneDesc::load(&path) {
        Err(SceneError::Parse {
            path: Some(at),
            line,
            column,
            message,
        }) => {
            assert_eq!(at, path);
            assert_eq!((line, column), (2, 23), "{message}");
        }
        other => panic!("{other:?}"),
    }
    // The same file as UTF-8 loads.
    let fixed = String::from_utf8_lossy(&bytes).replace('\u{fffd}', "é");
    std::fs::write(&path, fixed).unwrap();
    assert_eq!(
        SceneDesc::load(&path).unwrap().spheres[0].name.as_deref(),
        Some("café")
    );
}

/// Regression (found by review of the core's documentation): after a byte-order mark, which
/// `from_ron` skips before counting lines and columns, the place of a byte that is not UTF-8
/// on the first line counted the mark as a character (a column too many).
#[test]
fn regression_a_byte_order_mark_is_not_counted_before_a_bad_byte() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("scene_not_utf8_bom");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.ron");
    let mut bytes = "\u{feff}(name: \"caf".as_bytes().to_vec();
    bytes.push(0xe9);
    bytes.extend_from_slice(b"\")");
    std::fs::write(&path, &bytes).unwrap();
    match SceneDesc::load(&path) {
        Err(SceneError::Parse { line, column, .. }) => assert_eq!((line, column), (1, 12)),
        other => panic!("{other:?}"),
    }
}
