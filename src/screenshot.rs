//! Saving screenshots: the folder, the stamp, the file, and the outcome shown to the user.
//!
//! Capturing the window's frame needs the renderer (the `render` feature's
//! [`LabRenderPlugin`](crate::render::LabRenderPlugin) turns a [`ScreenshotRequested`] into a
//! [`FrameCaptured`]); everything after the capture is here and runs headless.

use std::path::{Path, PathBuf};

use bevy::prelude::*;
use bevy::tasks::{IoTaskPool, Task, TaskPool, futures::check_ready};
use image::RgbaImage;

use crate::stamp::stamp_time;

/// Where screenshots go. The folder is created if missing. Default `screenshots/`.
#[derive(Resource, Clone, Debug, PartialEq, Eq)]
pub struct ScreenshotSettings {
    /// The folder.
    pub folder: PathBuf,
}

impl Default for ScreenshotSettings {
    fn default() -> Self {
        Self {
            folder: PathBuf::from("screenshots"),
        }
    }
}

/// Asks for a screenshot of the next frame, stamped with the simulated time `time`.
#[derive(Message, Clone, Copy, Debug, PartialEq)]
pub struct ScreenshotRequested {
    /// Simulated seconds shown in the frame.
    pub time: f64,
}

/// A captured frame, to be stamped and saved.
#[derive(Message, Clone, Debug)]
pub struct FrameCaptured {
    /// The frame's pixels.
    pub image: RgbaImage,
    /// Simulated seconds shown in the frame.
    pub time: f64,
}

/// How many frames in a row the renderer has drawn with every pipeline compiled (the
/// `render` feature keeps it; headless apps have none). Unattended screenshots wait for a
/// few, so they never capture a frame drawn before the shaders were ready.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderReady {
    /// Consecutive frames with no pipeline waiting to compile.
    pub frames: u32,
}

impl RenderReady {
    /// Frames in a row with every pipeline compiled after which the picture is taken as
    /// settled (the window and the panels drawn): the simulation's clock is held until then,
    /// and unattended screenshots wait for it, so one is taken at its mark.
    pub const SETTLED: u32 = 10;

    /// Whether [`RenderReady::SETTLED`] frames have been drawn in a row.
    pub fn settled(&self) -> bool {
        self.frames >= Self::SETTLED
    }
}

/// The last screenshot's outcome, shown on screen.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct ScreenshotStatus {
    /// `Ok(path)` once saved, `Err(message)` if saving failed; `None` before the first.
    pub last: Option<Result<PathBuf, String>>,
    /// Screenshots saved.
    pub saved: u32,
    /// Screenshots that failed.
    pub failed: u32,
    /// Screenshots being saved (stamped, encoded and written off the main thread).
    pub saving: u32,
}

/// Stamps `time` onto `image` and saves it as a PNG in `folder` (created if missing), as
/// `sphere-lab-NNN.png` numbered after the highest already there (so the names follow the
/// order the pictures were taken, even after some were deleted). Returns the file's path, or
/// an error that says what could not be done where.
pub fn save_screenshot(folder: &Path, mut image: RgbaImage, time: f64) -> Result<PathBuf, String> {
    std::fs::create_dir_all(folder)
        .map_err(|e| format!("cannot create folder {}: {e}", folder.display()))?;
    stamp_time(&mut image, time);
    // Claim the name by creating the file (never overwriting one, even if another lab saves
    // into the same folder at the same moment), then write into it.
    let next = std::fs::read_dir(folder)
        .map_err(|e| format!("cannot list folder {}: {e}", folder.display()))?
        .filter_map(|entry| {
            let name = entry.ok()?.file_name();
            let number = name
                .to_str()?
                .strip_prefix("sphere-lab-")?
                .strip_suffix(".png")?;
            number.parse::<u64>().ok()
        })
        .max()
        .map_or(Some(0), |highest| highest.checked_add(1));
    // (`next..` would overflow past the largest number, a panic in the dev profile.)
    for n in next.into_iter().flat_map(|next| next..=u64::MAX) {
        let path = folder.join(format!("sphere-lab-{n:03}.png"));
        let file = match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&path)
        {
            Ok(file) => file,
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(format!("cannot create {}: {e}", path.display())),
        };
        let mut out = std::io::BufWriter::new(file);
        image
            .write_to(&mut out, image::ImageFormat::Png)
            .and_then(|()| {
                use std::io::Write;
                out.flush().map_err(image::ImageError::IoError)
            })
            .map_err(|e| {
                // Leave no broken file among the screenshots.
                let _ = std::fs::remove_file(&path);
                format!("cannot write {}: {e}", path.display())
            })?;
        return Ok(path);
    }
    Err(format!(
        "no number left for a screenshot in {} (sphere-lab-{}.png is there)",
        folder.display(),
        u64::MAX
    ))
}

/// Screenshots being saved on the I/O task pool: stamping a frame and encoding it as PNG
/// take tens of milliseconds, which on the main thread would hold the window still for a
/// frame or more. (With the `render` feature Bevy's task pools have threads of their own;
/// a headless build without Bevy's `multi_threaded` runs the save on the main thread, at
/// the end of the frame.)
#[derive(Resource, Default)]
pub(crate) struct SavingScreenshots(Vec<Task<(f64, Result<PathBuf, String>)>>);

/// Starts saving each captured frame on the I/O task pool.
pub(crate) fn save_captured_frames(
    mut frames: MessageReader<FrameCaptured>,
    settings: Res<ScreenshotSettings>,
    mut saving: ResMut<SavingScreenshots>,
    mut status: ResMut<ScreenshotStatus>,
) {
    for frame in frames.read() {
        let (folder, image, time) = (settings.folder.clone(), frame.image.clone(), frame.time);
        saving.0.push(
            IoTaskPool::get_or_init(TaskPool::default)
                .spawn(async move { (time, save_screenshot(&folder, image, time)) }),
        );
        status.saving += 1;
    }
}

/// Records the outcome of each screenshot saved since the last frame, in the order they
/// finish (two in flight may finish out of order: [`ScreenshotStatus::last`] is the latest
/// to finish). Runs before [`save_captured_frames`], so a frame captured in this update is
/// recorded in a later one.
pub(crate) fn record_saved_screenshots(
    mut saving: ResMut<SavingScreenshots>,
    mut status: ResMut<ScreenshotStatus>,
) {
    saving.0.retain_mut(|task| {
        let Some((time, outcome)) = check_ready(task) else {
            return true;
        };
        match &outcome {
            Ok(path) => {
                info!("screenshot at t = {time:.3} s saved to {}", path.display());
                status.saved += 1;
            }
            Err(e) => {
                error!("screenshot failed: {e}");
                status.failed += 1;
            }
        }
        status.saving -= 1;
        status.last = Some(outcome);
        false
    });
}
