//! The orthographic camera: parallel rays along the view direction from a film rectangle
//! (Mitsuba's `orthographic`).
//!
//! The film is a 2h_x × 2h_y rectangle perpendicular to the unit view direction d, centred on
//! the camera's origin o; film point (s_x, s_y) ∈ \[0,1\]² (s_y downward) is the world point
//! o + (2s_x − 1)·h_x·right + (1 − 2s_y)·h_y·up, and its ray leaves it along d. Points behind the
//! film plane are not seen.
//!
//! Importance: pixel j reads the radiance along d averaged over its rectangle of the film
//! (world area a = 4h_x·h_y/(W·H)): W_e(c, ω) = δ(ω − d)/a per unit film area. The light
//! tracer's t = 1 connection of a surface point x is deterministic: c is x's projection onto the
//! film plane along d (the shadow ray runs along −d), and a film area dA_c is the projection of
//! the surface area dA_x = dA_c/|cos θ_x| — so the δ of W_e is absorbed by the projection and
//!
//! ```text
//! W = 1/a
//! ```
//!
//! with no 1/d² (the camera is the mirror image of a directional light: its vertex is a
//! direction, and its rays reach x₁ with area density p_A·|cos θ₁|, p_A = 1/(4h_x·h_y) over the
//! whole film — `bidirectional/camera.rs`).

use super::{CameraError, Connection, FilmHit, Pinhole, Raster};
use crate::math::Vec3;
use crate::scene::{CameraDesc, CameraKind};

/// An orthographic camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orthographic {
    /// Centre of the film rectangle.
    pub origin: Vec3,
    /// Unit view direction (every ray's).
    pub forward: Vec3,
    /// Unit image-right direction.
    pub right: Vec3,
    /// Unit image-up direction.
    pub up: Vec3,
    /// Half the film's width, metres.
    pub half_width: f32,
    /// Half the film's height, metres.
    pub half_height: f32,
    /// Width in pixels of the full film (the image is the raster's window).
    pub width: u32,
    /// Height in pixels of the full film.
    pub height: u32,
    /// The pixels written and the reconstruction filter.
    pub raster: Raster,
}

impl Orthographic {
    /// From a camera description's position, orientation and size (its field of view is not
    /// used) and the film's half sides in metres, each finite and > 0.
    pub fn new(d: &CameraDesc, half_width: f32, half_height: f32) -> Result<Self, CameraError> {
        let p = Pinhole::new(&CameraDesc { fov_x_degrees: 90.0, kind: CameraKind::Perspective, ..*d })?;
        let ok = |h: f32| h.is_finite() && h > 0.0;
        if !(ok(half_width) && ok(half_height)) {
            return Err(CameraError::FilmExtent(2.0 * half_width, 2.0 * half_height));
        }
        Ok(Orthographic {
            origin: p.eye,
            forward: p.forward,
            right: p.right,
            up: p.up,
            half_width,
            half_height,
            width: d.width,
            height: d.height,
            raster: p.raster,
        })
    }

    /// World area of one pixel of the film.
    #[inline]
    pub fn pixel_area(&self) -> f32 {
        (2.0 * self.half_width / self.width as f32) * (2.0 * self.half_height / self.height as f32)
    }

    /// The world point of film point (s_x, s_y) ∈ \[0,1\]², where its ray starts.
    #[inline]
    pub fn film_point(&self, sx: f32, sy: f32) -> Vec3 {
        self.origin
            + (2.0 * sx - 1.0) * self.half_width * self.right
            + (1.0 - 2.0 * sy) * self.half_height * self.up
    }

    /// Connects `x` to its projection on the film.
    #[inline]
    pub(super) fn connect(&self, x: Vec3) -> Option<Connection> {
        let hit = self.film_hit(x)?;
        let pixel = self.raster.box_pixel(hit.film.0, hit.film.1)?;
        Some(Connection { pixel, point: hit.point, weight: hit.weight })
    }

    /// Connects `x` to its projection on the film plane, within the film or beyond it.
    #[inline]
    pub(super) fn film_hit(&self, x: Vec3) -> Option<FilmHit> {
        let v = x - self.origin;
        let z = v.dot(self.forward);
        if !(z > 0.0) {
            return None;
        }
        let sx = 0.5 * (1.0 + v.dot(self.right) / self.half_width);
        let sy = 0.5 * (1.0 - v.dot(self.up) / self.half_height);
        Some(FilmHit { film: (sx, sy), point: x - z * self.forward, weight: 1.0 / self.pixel_area() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam() -> Orthographic {
        let d = CameraDesc {
            eye: Vec3::new(0.0, 0.0, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_x_degrees: 1.0,
            width: 40,
            height: 20,
            kind: CameraKind::Perspective,
            film: Default::default(),
        };
        Orthographic::new(&d, 2.0, 1.0).unwrap()
    }

    #[test]
    fn film_points_project_back_to_their_pixel() {
        let c = cam();
        for (sx, sy) in [(0.5f32, 0.5f32), (0.01, 0.02), (0.99, 0.7), (0.3, 0.999)] {
            let p = c.film_point(sx, sy);
            let x = p + 2.5 * c.forward;
            let conn = c.connect(x).unwrap();
            assert_eq!(conn.pixel % 40, (sx * 40.0) as usize);
            assert_eq!(conn.pixel / 40, (sy * 20.0) as usize);
            assert!((conn.point - p).length() < 1e-5, "{:?} vs {p:?}", conn.point);
            assert!((conn.weight - 1.0 / (4.0 * 2.0 * 1.0 / 800.0)).abs() < 1e-3);
        }
        // Behind the film, or beside it.
        assert!(c.connect(c.origin - c.forward).is_none());
        assert!(c.connect(c.origin + 2.1 * c.right + c.forward).is_none());
        // Image right is +x for a camera looking down −z.
        assert!((c.right - Vec3::X).length() < 1e-6 && (c.forward - Vec3::NEG_Z).length() < 1e-6);
    }

    #[test]
    fn bad_extents_are_refused() {
        let d = CameraDesc {
            eye: Vec3::ZERO,
            target: Vec3::Z,
            up: Vec3::Y,
            fov_x_degrees: 45.0,
            width: 4,
            height: 4,
            kind: CameraKind::Perspective,
            film: Default::default(),
        };
        assert!(Orthographic::new(&d, 1.0, 1.0).is_ok());
        for (w, h) in [(0.0, 1.0), (1.0, -1.0), (f32::NAN, 1.0), (1.0, f32::INFINITY)] {
            assert!(Orthographic::new(&d, w, h).is_err(), "{w} {h}");
        }
    }
}
