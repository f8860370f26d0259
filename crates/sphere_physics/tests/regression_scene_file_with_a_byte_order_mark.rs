//! Regression (found by review): a scene file saved with a byte-order mark (as some editors on
//! Windows save text) failed at line 1, column 1, "Expected opening '(' for struct
//! 'SceneDesc'", though nothing was wrong with it. The mark is skipped, and an error after it
//! is placed where an editor shows it.

use sphere_physics::{SceneDesc, SceneError};

#[test]
fn regression_a_byte_order_mark_is_skipped() {
    let scene = SceneDesc::from_ron("\u{feff}(name: \"marked\", spheres: [])").unwrap();
    assert_eq!(scene.name, "marked");
    match SceneDesc::from_ron("\u{feff}(name: \"marked\",\n    spheres: [oops])") {
        Err(SceneError::Parse { line, column, .. }) => assert_eq!((line, column), (2, 15)),
        other => panic!("{other:?}"),
    }
}
