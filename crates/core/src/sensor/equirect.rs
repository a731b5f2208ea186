//! The equirectangular (longitude/latitude) 360° camera.
//!
//! Pixel (i, j) of a W×H image covers longitudes φ ∈ [−π + 2πi/W, −π + 2π(i+1)/W] (φ = 0 is the
//! view direction, φ grows toward the right) and latitudes from π/2 − πj/H down to
//! π/2 − π(j+1)/H (row 0 at the zenith, `up`). It reads the radiance at the eye averaged over the
//! pixel's solid angle Ω_j = (2π/W)·(cos(πj/H) − cos(π(j+1)/H)), so its importance is
//! W_e = 1/Ω_j per unit solid angle; a point x at distance d subtends dω = |cos θ_x|·dA_x/d²:
//!
//! ```text
//! W = 1/(Ω_j · d²)
//! ```

use super::{CameraError, Connection, Pinhole, Raster};
use crate::math::Vec3;
use crate::scene::CameraDesc;
use std::f32::consts::{PI, TAU};

/// A 360° longitude/latitude camera at `eye`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Equirectangular {
    /// Centre of projection.
    pub eye: Vec3,
    /// Unit direction of the image centre (longitude 0, latitude 0).
    pub forward: Vec3,
    /// Unit direction of longitude +90°.
    pub right: Vec3,
    /// Unit direction of the zenith (top row).
    pub up: Vec3,
    /// Width in pixels (360° of longitude).
    pub width: u32,
    /// Height in pixels (180° of latitude).
    pub height: u32,
    /// The pixels written (a crop window); its filter is the box.
    pub raster: Raster,
}

impl Equirectangular {
    /// From a camera description (its field of view is ignored: the camera sees everything).
    pub fn new(d: &CameraDesc) -> Result<Self, CameraError> {
        let p = Pinhole::new(&CameraDesc { fov_x_degrees: 90.0, ..*d })?;
        if !p.raster.is_box() {
            // Its pixels are not squares of the film's measure: a filter over (longitude,
            // latitude) would need importance of its own.
            return Err(CameraError::Filter(
                "the equirectangular camera takes only the box reconstruction filter".into(),
            ));
        }
        Ok(Equirectangular {
            eye: p.eye,
            forward: p.forward,
            right: p.right,
            up: p.up,
            width: d.width,
            height: d.height,
            raster: p.raster,
        })
    }

    /// Solid angle of a pixel in row `j`.
    #[inline]
    pub fn pixel_solid_angle(&self, j: u32) -> f32 {
        let h = self.height as f32;
        let (a, b) = (PI * j as f32 / h, PI * (j + 1) as f32 / h);
        TAU / self.width as f32 * (a.cos() - b.cos())
    }

    /// The unit direction through film point (sx, sy) ∈ \[0,1\]² (for tests).
    pub fn direction(&self, sx: f32, sy: f32) -> Vec3 {
        let (lon, lat) = ((sx - 0.5) * TAU, (0.5 - sy) * PI);
        lat.cos() * (lon.cos() * self.forward + lon.sin() * self.right) + lat.sin() * self.up
    }

    /// Connects `x` to the eye.
    #[inline]
    pub(super) fn connect(&self, x: Vec3) -> Option<Connection> {
        let v = x - self.eye;
        let d2 = v.length_squared();
        if !(d2 > 0.0) {
            return None;
        }
        let lon = v.dot(self.right).atan2(v.dot(self.forward));
        let lat = (v.dot(self.up) / d2.sqrt()).clamp(-1.0, 1.0).asin();
        let sx = 0.5 + lon / TAU;
        let sy = 0.5 - lat / PI;
        let i = ((sx * self.width as f32).max(0.0) as u32).min(self.width - 1);
        let j = ((sy * self.height as f32).max(0.0) as u32).min(self.height - 1);
        let pixel = self.raster.window_pixel(i, j)?;
        let weight = 1.0 / (self.pixel_solid_angle(j) * d2);
        Some(Connection { pixel, point: self.eye, weight })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::CameraKind;

    #[test]
    fn pixels_tile_the_sphere_and_directions_invert() {
        let e = Equirectangular::new(&CameraDesc {
            eye: Vec3::new(1.0, 2.0, 3.0),
            target: Vec3::new(1.0, 2.0, 0.0),
            up: Vec3::Y,
            fov_x_degrees: 1.0,
            width: 40,
            height: 20,
            kind: CameraKind::Perspective,
            film: Default::default(),
        })
        .unwrap();
        let total: f32 = (0..20).map(|j| e.pixel_solid_angle(j) * 40.0).sum();
        assert!((total - 4.0 * PI).abs() < 1e-4, "{total}");
        for (sx, sy) in [(0.5f32, 0.5f32), (0.01, 0.3), (0.77, 0.95), (0.26, 0.02)] {
            let c = e.connect(e.eye + 2.0 * e.direction(sx, sy)).unwrap();
            assert_eq!(c.pixel % 40, (sx * 40.0) as usize, "({sx},{sy})");
            assert_eq!(c.pixel / 40, (sy * 20.0) as usize, "({sx},{sy})");
        }
        // Image centre looks at the target; right is +x... for a camera looking down −z.
        assert!((e.direction(0.5, 0.5) - Vec3::NEG_Z).length() < 1e-6);
        assert!((e.direction(0.75, 0.5) - Vec3::X).length() < 1e-5);
        assert!(e.connect(e.eye).is_none());
    }
}
