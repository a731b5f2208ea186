//! Point lights: intensity I(ω) = Φ·f_e(ω) from one point, with the frame that orients a
//! profiled one (a spot's axis, an IES file's 0° angles). Invisible to cameras (a delta
//! distribution). A spot may project a texture ([`super::spot_texture`]).

use super::check::{check_emission, check_orientation, check_position, check_power};
use super::spot_texture::SpotTexture;
use super::{BuiltProfile, Emission, EmissionProfile, LightError};
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::warp;
use crate::texture::Texture;
use glam::DVec3;
use std::sync::Arc;

/// A point light: intensity I(ω) = Φ·f_e(ω).
#[derive(Clone, Debug, PartialEq)]
pub struct PointLight {
    /// Name from the scene.
    pub name: String,
    /// Position.
    pub position: Vec3,
    /// Strength: radiant intensity on the profile's axis, W/sr (everywhere for the uniform
    /// profile); I(ω) = intensity·s(ω).
    pub intensity: Rgb,
    /// Power Φ, W per channel (= intensity·∫s dω; intensity·Q̂ with a texture).
    pub power: Rgb,
    /// The emission density.
    pub profile: BuiltProfile,
    /// The profile's frame (z = axis, x = φ = 0).
    pub frame: Frame,
    /// The texture a spot projects, if any: I(ω) = intensity·T(uv(ω))·s(ω).
    pub texture: Option<SpotTexture>,
}

impl PointLight {
    /// The point light `name` at `position` with `profile` (`None`: isotropic) in the frame
    /// `orientation` (`None`: the identity), of strength `intensity` (W/sr on the axis) or, if
    /// given, power Φ = `power` (the intensity then follows: Φ/∫s dω). A spot may project
    /// `texture` ([`super::spot_texture`]: Φ = intensity·Q̂). Checks every parameter.
    pub fn new(
        name: String,
        position: Vec3,
        intensity: Rgb,
        profile: Option<&EmissionProfile>,
        orientation: Option<Frame>,
        power: Option<Rgb>,
        texture: Option<Arc<Texture>>,
    ) -> Result<PointLight, LightError> {
        check_emission(intensity)?;
        check_position(position)?;
        let profile = BuiltProfile::build(profile.unwrap_or(&EmissionProfile::Uniform), false)?;
        let frame = match orientation {
            None => Frame { s: Vec3::X, t: Vec3::Y, n: Vec3::Z },
            Some(f) => check_orientation(f)?,
        };
        let texture = texture.map(|t| SpotTexture::new(t, &profile)).transpose()?;
        let (intensity, power) = match (&texture, power) {
            (None, Some(phi)) => (check_power(phi)? / profile.integral(), phi),
            (None, None) => (intensity, profile.integral() * intensity),
            (Some(t), Some(phi)) => {
                check_power(phi)?;
                if (0..3).any(|c| phi[c] > 0.0 && !(t.integral[c] > 0.0)) {
                    return Err(LightError::PowerUnreachable(phi.to_array()));
                }
                (Rgb::select(t.integral.cmpgt(Rgb::ZERO), phi / t.integral, Rgb::ZERO), phi)
            }
            (Some(t), None) => (intensity, t.integral * intensity),
        };
        Ok(PointLight { name, position, intensity, power, profile, frame, texture })
    }

    /// f_e(ω) per channel of the unit world direction `dir`: the profile's s/S, times
    /// T(uv)·S/Q̂ for a textured spot ([`super::spot_texture`]).
    #[inline]
    pub fn emission_density(&self, dir: Vec3) -> Rgb {
        let local = self.frame.to_local(dir);
        let f = self.profile.eval(local);
        match &self.texture {
            Some(t) => t.relative(local) * f,
            None => Rgb::splat(f),
        }
    }

    /// The solid-angle density with which [`PointLight::sample_emission`] draws the unit world
    /// direction `dir`: the profile's sampling pdf.
    #[inline]
    pub fn direction_pdf(&self, dir: Vec3) -> f32 {
        match self.profile {
            BuiltProfile::Uniform { hemisphere: false } => warp::UNIFORM_SPHERE_PDF,
            ref p => p.sampling_pdf(self.frame.to_local(dir)),
        }
    }

    /// A path start at the light: `u_dir` draws a direction from the profile (uniform on the
    /// sphere, exactly, for an isotropic light).
    #[inline]
    pub fn sample_emission(&self, u_dir: Vec2) -> Emission {
        let (dir, weight, emitted) = match self.profile {
            BuiltProfile::Uniform { hemisphere: false } => {
                (warp::square_to_uniform_sphere(u_dir), Rgb::ONE, Rgb::ONE)
            }
            ref p => {
                let (local, w) = p.sample(u_dir);
                let dir = self.frame.to_world(local).normalize();
                match &self.texture {
                    None => (dir, Rgb::splat(w), Rgb::ONE),
                    // The texture's share of f_e/p ([`super::spot_texture`]); a black texel's
                    // path carries nothing (`emitted` 0 drops it).
                    Some(t) => {
                        let relative = t.relative(local);
                        (dir, relative * w, if relative.max_element() > 0.0 { Rgb::ONE } else { Rgb::ZERO })
                    }
                }
            }
        };
        Emission { origin: self.position, surface: None, dir, weight, emitted }
    }
}

/// The frame of a light whose axis is `axis` (z), with x as close to `x` as possible
/// (perpendicular to the axis; any perpendicular if `x` is parallel to it). Computed in double
/// precision, as loaders give their transformed axes. [`LightError::Direction`] if the axis is
/// zero or not finite.
pub fn axis_frame(axis: DVec3, x: DVec3) -> Result<Frame, LightError> {
    let n = super::check::unit_axis(axis)?;
    let s = x - n * x.dot(n);
    let s = if s.is_finite() && s.length() > 1e-9 * x.length().max(1e-300) {
        s.normalize()
    } else {
        Frame::from_normal(n.as_vec3()).s.as_dvec3()
    };
    Ok(Frame { s: s.as_vec3(), t: n.cross(s).as_vec3(), n: n.as_vec3() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_frame_keeps_x_perpendicular_and_refuses_a_zero_axis() {
        let f = axis_frame(DVec3::new(0.0, 0.0, -2.0), DVec3::X).unwrap();
        assert_eq!(f.n, Vec3::NEG_Z);
        assert_eq!(f.s, Vec3::X);
        let f = axis_frame(DVec3::X, DVec3::X).unwrap();
        assert!(f.s.dot(f.n).abs() < 1e-6 && (f.s.length() - 1.0).abs() < 1e-6);
        assert_eq!(axis_frame(DVec3::ZERO, DVec3::X), Err(LightError::Direction([0.0; 3])));
    }
}
