//! Camera paths for walkthroughs: keyframes (time, eye, target, up, field of view) interpolated
//! smoothly — Catmull–Rom splines through the eye and target positions (C¹, passing through
//! every keyframe), linear up vector and field of view.

use super::{CameraDesc, CameraKind};
use crate::math::Vec3;

/// One keyframe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraKey {
    /// Time, seconds.
    pub time: f32,
    /// Camera position.
    pub eye: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up hint.
    pub up: Vec3,
    /// Horizontal field of view, degrees.
    pub fov_x_degrees: f32,
}

/// A validated camera path: keyframes with strictly increasing times.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraPath {
    keys: Vec<CameraKey>,
}

/// Why keyframes do not make a path.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CameraPathError {
    /// No keyframes.
    #[error("a camera path needs at least one keyframe")]
    Empty,
    /// Times do not increase.
    #[error("keyframe {0}: times must increase strictly ({1} s follows {2} s)")]
    TimeOrder(usize, f32, f32),
    /// A number is NaN or infinite.
    #[error("keyframe {0}: every number must be finite")]
    NotFinite(usize),
}

impl CameraPath {
    /// Validates keyframes.
    pub fn new(keys: Vec<CameraKey>) -> Result<Self, CameraPathError> {
        if keys.is_empty() {
            return Err(CameraPathError::Empty);
        }
        for (i, k) in keys.iter().enumerate() {
            let finite = k.time.is_finite()
                && k.eye.is_finite()
                && k.target.is_finite()
                && k.up.is_finite()
                && k.fov_x_degrees.is_finite();
            if !finite {
                return Err(CameraPathError::NotFinite(i));
            }
            if i > 0 && k.time <= keys[i - 1].time {
                return Err(CameraPathError::TimeOrder(i, k.time, keys[i - 1].time));
            }
        }
        Ok(CameraPath { keys })
    }

    /// First and last keyframe times.
    pub fn span(&self) -> (f32, f32) {
        (self.keys[0].time, self.keys[self.keys.len() - 1].time)
    }

    /// The camera at time `t` (clamped to the path's span), with the given image size.
    pub fn at(&self, t: f32, width: u32, height: u32) -> CameraDesc {
        let k = &self.keys;
        let (t0, t1) = self.span();
        let t = t.clamp(t0, t1);
        let i = k.partition_point(|key| key.time <= t).saturating_sub(1).min(k.len().saturating_sub(2));
        if k.len() == 1 {
            let a = k[0];
            return CameraDesc {
                eye: a.eye,
                target: a.target,
                up: a.up,
                fov_x_degrees: a.fov_x_degrees,
                width,
                height,
                kind: CameraKind::Perspective,
                film: Default::default(),
            };
        }
        let (a, b) = (k[i], k[i + 1]);
        let s = (t - a.time) / (b.time - a.time);
        let prev = if i > 0 { k[i - 1] } else { a };
        let next = if i + 2 < k.len() { k[i + 2] } else { b };
        CameraDesc {
            eye: catmull_rom(prev.eye, a.eye, b.eye, next.eye, s),
            target: catmull_rom(prev.target, a.target, b.target, next.target, s),
            up: a.up.lerp(b.up, s),
            fov_x_degrees: a.fov_x_degrees + (b.fov_x_degrees - a.fov_x_degrees) * s,
            width,
            height,
            kind: CameraKind::Perspective,
            film: Default::default(),
        }
    }
}

/// Uniform Catmull–Rom segment from p1 (s = 0) to p2 (s = 1).
fn catmull_rom(p0: Vec3, p1: Vec3, p2: Vec3, p3: Vec3, s: f32) -> Vec3 {
    let (s2, s3) = (s * s, s * s * s);
    0.5 * ((2.0 * p1)
        + (p2 - p0) * s
        + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * s2
        + (3.0 * p1 - p0 - 3.0 * p2 + p3) * s3)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(time: f32, x: f32) -> CameraKey {
        CameraKey {
            time,
            eye: Vec3::new(x, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_x_degrees: 40.0 + x,
        }
    }

    #[test]
    fn passes_through_keyframes_and_is_smooth() {
        let p = CameraPath::new(vec![key(0.0, 0.0), key(1.0, 1.0), key(3.0, -2.0), key(4.0, 0.5)]).unwrap();
        for k in [key(0.0, 0.0), key(1.0, 1.0), key(3.0, -2.0), key(4.0, 0.5)] {
            let c = p.at(k.time, 8, 8);
            assert!((c.eye - k.eye).length() < 1e-5 && (c.fov_x_degrees - k.fov_x_degrees).abs() < 1e-4);
        }
        // Continuous across a keyframe, and clamped outside the span.
        let (l, r) = (p.at(1.0 - 1e-3, 8, 8).eye, p.at(1.0 + 1e-3, 8, 8).eye);
        assert!((l - r).length() < 1e-2);
        assert_eq!(p.at(-5.0, 8, 8).eye, key(0.0, 0.0).eye);
        assert_eq!(p.at(50.0, 8, 8).eye, key(4.0, 0.5).eye);
        let single = CameraPath::new(vec![key(2.0, 3.0)]).unwrap();
        assert_eq!(single.at(0.0, 4, 4).eye, key(2.0, 3.0).eye);
    }

    #[test]
    fn bad_keyframes_are_refused() {
        assert_eq!(CameraPath::new(vec![]), Err(CameraPathError::Empty));
        assert!(matches!(
            CameraPath::new(vec![key(1.0, 0.0), key(1.0, 1.0)]),
            Err(CameraPathError::TimeOrder(1, ..))
        ));
        assert!(matches!(CameraPath::new(vec![key(f32::NAN, 0.0)]), Err(CameraPathError::NotFinite(0))));
    }
}
