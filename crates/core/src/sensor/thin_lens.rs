//! The thin-lens camera: a pinhole's image plane and field of view, with a lens of radius r at
//! the eye focused at distance F (depth of field).
//!
//! Importance (Veach's thesis §10.3, pbrt-v4 `PerspectiveCamera::We`/`SampleWi`): a ray leaving
//! lens point c in direction ω reaches the plane of focus at p_F = c + ω·F/cos θ (θ between ω and
//! the axis), and that point is imaged through the lens centre to the film point of a pinhole at
//! the eye. Every lens point maps the film area dA to dω = cos³θ·dA (the same Jacobian as the
//! pinhole, because |p_F − c| = F/cos θ), so reading the radiance averaged over pixel j
//! (film area a) and over the lens (area π r²) means W_e(c, ω) = 1/(a·π r²·cos⁴θ) per unit lens
//! area and solid angle. Sampling c uniformly on the lens (pdf 1/(π r²) per unit area) and
//! connecting to x, whose solid angle at c is dω = |cos θ_x|·dA_x/d², with the lens's own
//! cos θ for the projected lens area, gives
//!
//! ```text
//! W = W_e · cos θ / (p(c) · d²) = 1/(a · d² · cos³θ)
//! ```
//!
//! — the pinhole's factor, with d and θ measured from the lens point c. The pixel is the one
//! p_F projects into. With r = 0 the camera is exactly the pinhole.

use super::{Connection, FilmHit, Pinhole};
use crate::math::{Vec2, Vec3};
use crate::sampling::warp::square_to_concentric_disk;

/// A thin-lens perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinLens {
    /// Lens centre, axis, image plane and field of view (the lens centre is `pinhole.eye`).
    pub pinhole: Pinhole,
    /// Lens (aperture) radius, metres; 0 is a pinhole.
    pub radius: f32,
    /// Distance from the lens to the plane in focus (perpendicular to the axis), metres.
    pub focus_distance: f32,
}

/// Why a thin lens cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LensError {
    /// Negative or non-finite radius.
    #[error("lens radius {0} must be a finite number ≥ 0")]
    Radius(f32),
    /// Non-positive or non-finite focus distance.
    #[error("focus distance {0} must be a finite number > 0")]
    FocusDistance(f32),
}

/// The one rule for a thin lens's parameters: a radius finite and ≥ 0, a focus distance finite
/// and > 0. Public so that scene readers apply it where the file gives the values.
pub fn check_lens(radius: f32, focus_distance: f32) -> Result<(), LensError> {
    if !(radius.is_finite() && radius >= 0.0) {
        return Err(LensError::Radius(radius));
    }
    if !(focus_distance.is_finite() && focus_distance > 0.0) {
        return Err(LensError::FocusDistance(focus_distance));
    }
    Ok(())
}

impl ThinLens {
    /// A thin lens on the pinhole's eye and axis.
    pub fn new(pinhole: Pinhole, radius: f32, focus_distance: f32) -> Result<Self, LensError> {
        check_lens(radius, focus_distance)?;
        Ok(ThinLens { pinhole, radius, focus_distance })
    }

    /// The point on the lens for `u` ∈ [0,1)² (uniform over the disk).
    #[inline]
    pub fn lens_point(&self, u: Vec2) -> Vec3 {
        let l = self.radius * square_to_concentric_disk(u);
        self.pinhole.eye + l.x * self.pinhole.right + l.y * self.pinhole.up
    }

    /// Connects `x` to the lens point chosen by `u`.
    #[inline]
    pub(super) fn connect(&self, x: Vec3, u: Vec2) -> Option<Connection> {
        let p = &self.pinhole;
        if self.radius == 0.0 {
            return p.connect(x);
        }
        let c = self.lens_point(u);
        let v = x - c;
        let z = v.dot(p.forward);
        if z <= 0.0 {
            return None;
        }
        let focus = c + v * (self.focus_distance / z);
        let (pixel, _) = p.project(focus)?;
        let d2 = v.length_squared();
        let cos = z / d2.sqrt();
        let weight = 1.0 / (p.pixel_area() * d2 * cos * cos * cos);
        Some(Connection { pixel, point: c, weight })
    }

    /// [`ThinLens::connect`] for a filtered splat: the film coordinates of x's image through
    /// the lens point, unclipped.
    #[inline]
    pub(super) fn film_hit(&self, x: Vec3, u: Vec2) -> Option<FilmHit> {
        let p = &self.pinhole;
        if self.radius == 0.0 {
            return p.film_hit(x);
        }
        let c = self.lens_point(u);
        let v = x - c;
        let z = v.dot(p.forward);
        if z <= 0.0 {
            return None;
        }
        let (sx, sy, _) = p.film_of(c + v * (self.focus_distance / z))?;
        let d2 = v.length_squared();
        let cos = z / d2.sqrt();
        let weight = 1.0 / (p.pixel_area() * d2 * cos * cos * cos);
        Some(FilmHit { film: (sx, sy), point: c, weight })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{CameraDesc, CameraKind};

    fn lens(radius: f32) -> ThinLens {
        let p = Pinhole::new(&CameraDesc {
            eye: Vec3::new(0.0, 0.0, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_x_degrees: 40.0,
            width: 64,
            height: 48,
            kind: CameraKind::Perspective,
            film: Default::default(),
        })
        .unwrap();
        ThinLens::new(p, radius, 3.0).unwrap()
    }

    #[test]
    fn points_in_focus_land_on_the_pinhole_pixel_from_every_lens_point() {
        let t = lens(0.2);
        let x = Vec3::new(0.31, -0.17, 0.0); // on the plane of focus
        let (pix, _) = t.pinhole.project(x).unwrap();
        for u in [Vec2::new(0.1, 0.9), Vec2::new(0.5, 0.5), Vec2::new(0.97, 0.03)] {
            let c = t.connect(x, u).unwrap();
            assert_eq!(c.pixel, pix);
        }
        // Out of focus, the lens point moves the pixel.
        let y = Vec3::new(0.05, -0.03, 1.5);
        let a = t.connect(y, Vec2::new(0.02, 0.5)).unwrap().pixel;
        let b = t.connect(y, Vec2::new(0.98, 0.5)).unwrap().pixel;
        assert_ne!(a, b);
    }

    #[test]
    fn zero_radius_is_the_pinhole_and_bad_lenses_are_refused() {
        let t = lens(0.0);
        let x = Vec3::new(0.2, 0.1, -1.0);
        assert_eq!(t.connect(x, Vec2::new(0.3, 0.7)), t.pinhole.connect(x));
        assert!(ThinLens::new(t.pinhole, -1.0, 1.0).is_err());
        assert!(ThinLens::new(t.pinhole, f32::NAN, 1.0).is_err());
        assert!(ThinLens::new(t.pinhole, 0.1, 0.0).is_err());
    }
}
