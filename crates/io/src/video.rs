//! A walkthrough's PNG frames (`frame_00000.png`, …) as an MP4 video, through `ffmpeg` when it
//! is on the PATH: no video crate encodes H.264 as well, and every machine that plays videos
//! can have ffmpeg. The video is written atomically (a temporary file, renamed into place).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Why no video was written.
#[derive(Debug, thiserror::Error)]
pub enum VideoError {
    /// ffmpeg could not be started.
    #[error("cannot run ffmpeg")]
    Run(#[source] std::io::Error),
    /// ffmpeg ran but failed.
    #[error("ffmpeg failed to encode {} ({status})", video.display())]
    Encode {
        /// The video.
        video: PathBuf,
        /// ffmpeg's exit status.
        status: std::process::ExitStatus,
    },
    /// The video would replace a file the run reads.
    #[error(transparent)]
    ReplacesInput(#[from] crate::output_paths::OutputError),
    /// The finished video could not be moved into place.
    #[error("cannot move the video into place as {}", video.display())]
    Rename {
        /// The video.
        video: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

/// Whether `ffmpeg` runs here.
pub fn ffmpeg_available() -> bool {
    Command::new("ffmpeg")
        .arg("-version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Encodes `frames` PNG frames of `folder` at `fps` into `video` (H.264, even dimensions).
pub fn encode_frames(folder: &Path, frames: usize, fps: f32, video: &Path) -> Result<(), VideoError> {
    crate::output_paths::spares_what_was_read(video)?;
    let tmp = folder.join(format!(".walk.tmp-{}.mp4", std::process::id()));
    let status = Command::new("ffmpeg")
        .args(["-y", "-loglevel", "error", "-framerate", &fps.to_string(), "-start_number", "0", "-i"])
        .arg(folder.join("frame_%05d.png"))
        .args([
            "-frames:v",
            &frames.to_string(),
            "-pix_fmt",
            "yuv420p",
            "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
        ])
        .arg(&tmp)
        .status();
    let done = match status {
        Ok(s) if s.success() && tmp.exists() => std::fs::rename(&tmp, video)
            .map_err(|source| VideoError::Rename { video: video.to_owned(), source }),
        Ok(status) => Err(VideoError::Encode { video: video.to_owned(), status }),
        Err(e) => Err(VideoError::Run(e)),
    };
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done
}
