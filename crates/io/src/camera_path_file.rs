//! Camera path files for `opticks walk`: a small JSON document of keyframes.
//!
//! ```json
//! {
//!   "fps": 24,
//!   "size": [320, 240],
//!   "keyframes": [
//!     { "time": 0.0, "eye": [0, 0, 3.9], "target": [0, 0, 0], "fov": 39.3 },
//!     { "time": 2.5, "eye": [0.8, 0.3, 3.0], "target": [0, -0.2, 0], "up": [0, 1, 0] }
//!   ]
//! }
//! ```
//!
//! | field | meaning | default |
//! |---|---|---|
//! | `fps` | frames per second; frames are rendered at t = t₀, t₀ + 1/fps, … ≤ t₁ | 24 |
//! | `size` | image width and height in pixels | the scene camera's |
//! | `keyframes[].time` | seconds, strictly increasing | required |
//! | `keyframes[].eye`, `.target` | camera position and the point it looks at | required |
//! | `keyframes[].up` | up hint | `[0, 1, 0]` |
//! | `keyframes[].fov` | horizontal field of view, degrees | the previous keyframe's, else the scene camera's, else 45 |
//!
//! Positions are interpolated by Catmull–Rom splines (see `opticks_core::scene::CameraPath`).
//! JSON (serde_json) because it is the one format every tool can write; errors give line and column.

use opticks_core::math::Vec3;
use opticks_core::scene::{CameraKey, CameraPath};
use opticks_core::sensor::{Pinhole, check_fov};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A loaded walkthrough description.
#[derive(Clone, Debug, PartialEq)]
pub struct Walkthrough {
    /// The validated path.
    pub path: CameraPath,
    /// Frames per second.
    pub fps: f32,
    /// Image size, if the file gives one.
    pub size: Option<(u32, u32)>,
}

/// The most frames a walkthrough renders.
pub const MAX_FRAMES: usize = 100_000;

/// Why a walkthrough's frames cannot be rendered.
#[derive(Debug, thiserror::Error)]
pub enum FramesError {
    /// The time span and fps give no frame (a span or rate out of range).
    #[error("the camera path's time span and fps make no frame")]
    NoFrame,
    /// More frames than [`MAX_FRAMES`].
    #[error(
        "{frames:.0} frames ({t0} s to {t1} s at {fps} fps) is more than a walkthrough renders ({MAX_FRAMES})"
    )]
    TooMany {
        /// How many the path makes.
        frames: f64,
        /// Its start, in seconds.
        t0: f32,
        /// Its end, in seconds.
        t1: f32,
        /// Frames per second.
        fps: f32,
    },
    /// An interpolated camera is invalid (e.g. its field of view), though every keyframe's is.
    #[error("frame {frame} (t = {t} s): invalid camera")]
    Camera {
        /// The frame.
        frame: usize,
        /// Its time.
        t: f32,
        /// Why.
        source: opticks_core::sensor::CameraError,
    },
}

impl Walkthrough {
    /// The camera of every frame, at t = t₀, t₀ + 1/fps, … ≤ t₁, of `size` pixels, all
    /// checked before any is rendered; the count computed without overflow and bounded by
    /// [`MAX_FRAMES`].
    pub fn cameras(&self, size: (u32, u32)) -> Result<Vec<Pinhole>, FramesError> {
        let (t0, t1) = self.path.span();
        let frames = frame_count(t0, t1, self.fps).ok_or(FramesError::NoFrame)?;
        if frames > MAX_FRAMES as f64 {
            return Err(FramesError::TooMany { frames, t0, t1, fps: self.fps });
        }
        (0..frames as usize)
            .map(|frame| {
                let t = t0 + frame as f32 / self.fps;
                Pinhole::new(&self.path.at(t, size.0, size.1)).map_err(|source| FramesError::Camera {
                    frame,
                    t,
                    source,
                })
            })
            .collect()
    }
}

/// Frames in [t0, t1] at `fps` (in f64: a huge span is too many frames, never 0).
fn frame_count(t0: f32, t1: f32, fps: f32) -> Option<f64> {
    let n = ((f64::from(t1) - f64::from(t0)) * f64::from(fps) + 1e-4).floor() + 1.0;
    (n.is_finite() && n >= 1.0).then_some(n)
}

/// Why a camera path file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum CameraPathFileError {
    /// Cannot read the file. (The cause is part of the message, not a `source`, so that error
    /// chains print it once.)
    #[error("{}: {cause}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        cause: std::io::Error,
    },
    /// Not valid JSON, or not of the documented shape (serde's message has line and column).
    #[error("{}: {cause}", path.display())]
    Json {
        /// The file.
        path: PathBuf,
        /// Why, with line and column.
        cause: serde_json::Error,
    },
    /// Valid JSON with impossible values.
    #[error("{}: {detail}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        detail: String,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileKey {
    time: f32,
    eye: [f32; 3],
    target: [f32; 3],
    up: Option<[f32; 3]>,
    fov: Option<f32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    fps: Option<f32>,
    size: Option<[u32; 2]>,
    keyframes: Vec<FileKey>,
}

/// Reads a camera path file; `default_fov` is used until a keyframe gives one.
pub fn read_camera_path(path: &Path, default_fov: f32) -> Result<Walkthrough, CameraPathFileError> {
    let text = crate::input_file::read_to_string(path)
        .map_err(|cause| CameraPathFileError::Read { path: path.to_owned(), cause })?;
    let file: File = serde_json::from_str(&text)
        .map_err(|cause| CameraPathFileError::Json { path: path.to_owned(), cause })?;
    let invalid = |detail: String| CameraPathFileError::Invalid { path: path.to_owned(), detail };
    let fps = file.fps.unwrap_or(24.0);
    if !(fps > 0.0 && fps <= 1000.0) {
        return Err(invalid(format!("fps {fps} must be in (0, 1000]")));
    }
    if let Some([w, h]) = file.size {
        opticks_core::sensor::check_image_size(w, h).map_err(|e| invalid(format!("size: {e}")))?;
    }
    let mut fov = default_fov;
    let mut keys = Vec::with_capacity(file.keyframes.len());
    for (i, k) in file.keyframes.iter().enumerate() {
        fov = k.fov.unwrap_or(fov);
        check_fov(fov).map_err(|err| invalid(format!("keyframe {i}: {err}")))?;
        let key = CameraKey {
            time: k.time,
            eye: Vec3::from_array(k.eye),
            target: Vec3::from_array(k.target),
            up: Vec3::from_array(k.up.unwrap_or([0.0, 1.0, 0.0])),
            fov_x_degrees: fov,
        };
        if let Some(problem) = key_problem(&key) {
            return Err(invalid(format!("keyframe {i}: {problem}")));
        }
        keys.push(key);
    }
    let path_ = CameraPath::new(keys).map_err(|e| invalid(e.to_string()))?;
    Ok(Walkthrough { path: path_, fps, size: file.size.map(|[w, h]| (w, h)) })
}

/// What makes a keyframe's camera impossible (the spline between valid keyframes may still
/// pass through such a camera; `walk` then names the frame).
fn key_problem(k: &CameraKey) -> Option<String> {
    let finite = [k.eye, k.target, k.up].iter().all(|v| v.is_finite()) && k.time.is_finite();
    let view = k.target - k.eye;
    if !finite {
        Some("every number must be finite".into())
    } else if view.length_squared() == 0.0 {
        Some(format!("eye and target are the same point {:?}: no view direction", k.eye.to_array()))
    } else if k.up.length_squared() == 0.0 {
        Some("the up vector is zero".into())
    } else if view.normalize().cross(k.up.normalize()).length() < 1e-6 {
        Some(format!("the up vector {:?} is parallel to the view direction", k.up.to_array()))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_counts_never_overflow_to_zero() {
        assert_eq!(frame_count(0.0, 1.0, 24.0), Some(25.0));
        assert_eq!(frame_count(0.0, 0.0, 24.0), Some(1.0));
        assert!(frame_count(0.0, 1e30, 1000.0).unwrap() > MAX_FRAMES as f64, "too many, not 0 frames");
        assert_eq!(frame_count(0.0, f32::INFINITY, 24.0), None);
    }

    fn read(text: &str) -> Result<Walkthrough, CameraPathFileError> {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("cam.json");
        std::fs::write(&p, text).unwrap();
        read_camera_path(&p, 50.0)
    }

    #[test]
    fn reads_the_documented_format() {
        let w = read(
            r#"{"fps": 10, "size": [64, 48], "keyframes": [
                {"time": 0, "eye": [0,0,4], "target": [0,0,0], "fov": 40},
                {"time": 1, "eye": [1,0,4], "target": [0,0,0]}]}"#,
        )
        .unwrap();
        assert_eq!((w.fps, w.size), (10.0, Some((64, 48))));
        assert_eq!(w.path.at(1.0, 64, 48).fov_x_degrees, 40.0);
        assert_eq!(
            read(r#"{"keyframes": [{"time": 0, "eye": [0,0,4], "target": [0,0,0]}]}"#).unwrap().fps,
            24.0
        );
    }

    #[test]
    fn bad_files_name_the_problem() {
        let e = read("{\"keyframes\": [\n {\"time\": 0, \"eye\": [0,0], \"target\": [0,0,0]}]}")
            .unwrap_err()
            .to_string();
        assert!(e.contains("cam.json") && e.contains("line 2"), "{e}");
        let e = read(r#"{"keyframes": []}"#).unwrap_err().to_string();
        assert!(e.contains("at least one keyframe"), "{e}");
        let e = read(r#"{"keyframes": [{"time": 1, "eye": [0,0,4], "target": [0,0,0]}, {"time": 0, "eye": [0,0,4], "target": [0,0,0]}]}"#).unwrap_err().to_string();
        assert!(e.contains("increase"), "{e}");
        let e = read(r#"{"fps": 0, "keyframes": [{"time": 0, "eye": [0,0,4], "target": [0,0,0]}]}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("fps"), "{e}");
        let e = read(r#"{"keyframes": [{"time": 0, "eye": [0,0,4], "target": [0,0,0], "zoom": 2}]}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("zoom"), "{e}");
        assert!(read("not json").is_err());
        let key =
            |k: &str| format!(r#"{{"keyframes": [{{"time": 0, "eye": [0,0,4], "target": [0,0,0]}}, {k}]}}"#);
        for (k, needle) in [
            (r#"{"time": 1, "eye": [1,1,1], "target": [1,1,1]}"#, "keyframe 1: eye and target are the same"),
            (
                r#"{"time": 1, "eye": [0,0,4], "target": [0,0,0], "up": [0,0,0]}"#,
                "keyframe 1: the up vector is zero",
            ),
            (
                r#"{"time": 1, "eye": [0,0,4], "target": [0,0,0], "up": [0,0,2]}"#,
                "keyframe 1: the up vector [0.0, 0.0, 2.0] is parallel",
            ),
            (r#"{"time": 0, "eye": [0,0,4], "target": [0,0,1]}"#, "keyframe 1: times must increase"),
            (r#"{"time": 1e39, "eye": [0,0,4], "target": [0,0,1]}"#, "keyframe 1"),
        ] {
            let e = read(&key(k)).unwrap_err().to_string();
            assert!(e.contains("cam.json") && e.contains(needle), "{needle}: {e}");
        }
        // The JSON error is the whole message: no `source` chain that would print it again.
        let e = read("not json").unwrap_err();
        assert!(std::error::Error::source(&e).is_none());
    }
}
