//! The pinhole camera's connection (the camera itself, [`Pinhole`], lives in `scene::camera`).
//!
//! Importance: the pinhole reads, for pixel j, the radiance at the eye averaged over the pixel's
//! square (area a) on the image plane at unit distance. A film area dA maps to the solid angle
//! dω = cos³θ_c·dA, so W_e = 1/(a·cos³θ_c) per unit solid angle, and a point x at distance d
//! subtends dω = |cos θ_x|·dA_x/d²: W = 1/(d²·a·cos³θ_c).

use super::Connection;
use crate::math::Vec3;
use crate::scene::Pinhole;

/// Connects `x` to the pinhole at `camera.eye`.
#[inline]
pub(super) fn connect(camera: &Pinhole, x: Vec3) -> Option<Connection> {
    let (pixel, cos_c) = camera.project(x)?;
    let d2 = (camera.eye - x).length_squared();
    let weight = 1.0 / (camera.pixel_area() * d2 * cos_c * cos_c * cos_c);
    Some(Connection { pixel, point: camera.eye, weight })
}
