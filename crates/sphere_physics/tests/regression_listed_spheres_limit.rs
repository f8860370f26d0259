//! Regression (found by review, sixty-fourth session): a scene file's listed spheres had no
//! limit but the file's size, 4 GiB, which holds 150 million spheres of 28 bytes each: some
//! 27 GB once read, where a generator's spheres are held to ten million. A file listing more
//! than [`MAX_LISTED`] is refused where it passes the limit.

use sphere_physics::{MAX_LISTED, SceneDesc, SceneError};

#[test]
fn regression_a_file_listing_more_than_the_limit_is_refused_where_it_passes_it() {
    let entry = "(position: (0, 0, 0), radius: 1),\n";
    let count = MAX_LISTED as usize + 1;
    let mut text = String::with_capacity(count * entry.len() + 64);
    text.push_str("(name: \"big\", spheres: [\n");
    for _ in 0..count {
        text.push_str(entry);
    }
    text.push_str("])");
    match SceneDesc::from_ron(&text) {
        Err(SceneError::Parse { line, message, .. }) => {
            assert!(message.contains("spheres listed"), "{message}");
            // The sphere past the limit is on line `count + 1`.
            assert!(
                (count..=count + 2).contains(&line),
                "refused at line {line}: {message}"
            );
        }
        Err(other) => panic!("refused, but not where: {other}"),
        Ok(scene) => panic!("{} spheres taken", scene.spheres.len()),
    }
}
