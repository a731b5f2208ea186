//! Directional (sun) lights: parallel rays of irradiance E (W/m² on a plane perpendicular to
//! them) over the whole scene. Paths start uniformly on a disk perpendicular to the direction,
//! just outside the scene's bounding sphere, whose radius is the bounding radius r, so
//! Φ = E·π·r². Like point lights they are invisible to cameras (a delta distribution).

use super::check::{check_emission, unit_direction};
use super::{Emission, LightError};
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::warp;

/// Parallel light covering the scene (a sun).
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Name from the scene.
    pub name: String,
    /// Unit direction the light travels in.
    pub direction: Vec3,
    /// Irradiance E on a plane perpendicular to `direction`, W/m².
    pub irradiance: Rgb,
    /// Centre of the emitting disk (outside the scene's bounding sphere).
    pub centre: Vec3,
    /// Disk radius (the scene's bounding radius).
    pub radius: f32,
    /// Frame with z = `direction`.
    pub frame: Frame,
}

impl DirectionalLight {
    /// The light travelling along `direction` (normalised here) with `irradiance` over a scene
    /// whose bounding sphere has centre `centre` and radius `radius`: its disk has that radius,
    /// just outside the sphere. Checks the irradiance and the direction.
    pub fn new(
        name: String,
        direction: Vec3,
        irradiance: Rgb,
        (centre, radius): (Vec3, f32),
    ) -> Result<Self, LightError> {
        check_emission(irradiance)?;
        let direction = unit_direction(direction)?;
        Ok(DirectionalLight {
            name,
            direction,
            irradiance,
            centre: centre - direction * (radius * 1.001 + 1e-4),
            radius,
            frame: Frame::from_normal(direction),
        })
    }

    /// Power Φ = E·π·r² per channel.
    #[inline]
    pub fn power(&self) -> Rgb {
        self.irradiance * (std::f32::consts::PI * self.radius * self.radius)
    }

    /// The area density of a path's start point on the disk: 1/(π r²).
    #[inline]
    pub fn disk_pdf(&self) -> f32 {
        1.0 / (std::f32::consts::PI * self.radius * self.radius)
    }

    /// A path start: `u_pos` a point uniform on the disk; the direction is the light's.
    #[inline]
    pub fn sample_emission(&self, u_pos: Vec2) -> Emission {
        let d = self.radius * warp::square_to_concentric_disk(u_pos);
        let origin = self.centre + d.x * self.frame.s + d.y * self.frame.t;
        Emission { origin, surface: None, dir: self.direction, weight: Rgb::ONE, emitted: Rgb::ONE }
    }
}
