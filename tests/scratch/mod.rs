//! Scratch paths for the whole-stack tests, removed when the test ends (passed or failed), so
//! test runs leave nothing behind in the system's temporary folder.

use std::ops::Deref;
use std::path::{Path, PathBuf};

/// A path under the system's temporary folder, unique to this process and `name`, emptied when
/// made and removed (folder or file) when dropped.
pub struct Scratch(PathBuf);

impl Scratch {
    /// The scratch path for `name` (`prefix` names the test file), nothing there yet.
    pub fn new(prefix: &str, name: &str) -> Self {
        let path = std::env::temp_dir().join(format!("{prefix}_{}_{name}", std::process::id()));
        remove(&path);
        Self(path)
    }
}

/// Removes `path`, whether a folder, a file or nothing.
fn remove(path: &Path) {
    if std::fs::remove_dir_all(path).is_err() {
        let _ = std::fs::remove_file(path);
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        remove(&self.0);
    }
}

impl Deref for Scratch {
    type Target = Path;

    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}
