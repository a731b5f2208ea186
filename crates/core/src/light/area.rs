//! Area lights: one-sided emitters made of scene triangles, with the photometric frame their
//! profile is evaluated in.
//!
//! ## An area light's photometric frame
//! An area light evaluates and samples its profile in a frame per triangle: the vertical 0°
//! axis (local z) is the triangle's geometric normal, and the horizontal 0° reference (local x,
//! φ = 0; local y = z × x is φ = 90°) is the light's [`AreaLight::tangent`] projected onto the
//! triangle's plane. The tangent is world +x unless the scene sets one
//! ([`crate::scene::AreaEmission::tangent`]); where it is (within 0.6° of) parallel to a
//! triangle's normal, world +x and then world +z are projected instead
//! ([`AreaLight::frame`]). Only profiles that depend on φ (IES tables) need this frame; the
//! rotationally symmetric ones use the equivalent, cheaper `Frame::from_normal`. The tracer
//! (emission sampling) and the sensor (emitters seen directly, through
//! [`super::Light::emitted_fraction`]) both go through [`AreaLight::frame`], so they agree.

use super::check::{check_power, unit_tangent};
use super::{BuiltProfile, Emission, EmissionProfile, LightError};
use crate::geometry::Triangle;
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::warp;

/// A one-sided emitter made of scene triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct AreaLight {
    /// Name from the scene.
    pub name: String,
    /// Emitted radiance along the normal, W/(m²·sr) (for the default cosine profile, the
    /// radiance in every direction of the front hemisphere). Φ = radiance·A·∫s dω (module docs
    /// of [`super::profile`]).
    pub radiance: Rgb,
    /// The emission density over the front hemisphere, in each triangle's frame
    /// [`AreaLight::frame`].
    pub profile: BuiltProfile,
    /// Unit world direction whose projection onto each triangle's plane is the profile's
    /// horizontal 0° (module docs); world +x by default.
    pub tangent: Vec3,
    /// Scene triangle indices of the emitter.
    pub triangles: Vec<u32>,
    /// Cumulative areas (for picking a triangle ∝ area); last entry = total area.
    pub cumulative_area: Vec<f32>,
}

impl AreaLight {
    /// The area light `name` over the scene triangles `triangles` (with their cumulative areas),
    /// emitting `radiance` along the normal with `profile` (`None`: Lambertian) oriented by
    /// `tangent` (`None`: world +x); a `power` Φ, if given, overrides the radiance (which
    /// becomes Φ/(A·∫s dω)). Checks the profile (one-sided: cut at 90°), the tangent and the
    /// power; the radiance is the caller's to check ([`super::check::check_emission`]).
    pub fn new(
        name: String,
        radiance: Rgb,
        profile: Option<&EmissionProfile>,
        tangent: Option<Vec3>,
        power: Option<Rgb>,
        triangles: Vec<u32>,
        cumulative_area: Vec<f32>,
    ) -> Result<AreaLight, LightError> {
        let profile = BuiltProfile::build(profile.unwrap_or(&EmissionProfile::Cosine), true)?;
        let tangent = tangent.map_or(Ok(Vec3::X), unit_tangent)?;
        let area = cumulative_area.last().copied().unwrap_or(0.0);
        let radiance = match power {
            None => radiance,
            Some(phi) => {
                check_power(phi)?;
                if !(area > 0.0) && phi.max_element() > 0.0 {
                    return Err(LightError::PowerWithoutArea(phi.to_array()));
                }
                let per_radiance = profile.integral() * area;
                if !(per_radiance > 0.0) && phi.max_element() > 0.0 {
                    return Err(LightError::PowerUnreachable(phi.to_array()));
                }
                if per_radiance > 0.0 { phi / per_radiance } else { Rgb::ZERO }
            }
        };
        Ok(AreaLight { name, radiance, profile, tangent, triangles, cumulative_area })
    }

    /// Total emitting area A, m².
    pub fn area(&self) -> f32 {
        self.cumulative_area.last().copied().unwrap_or(0.0)
    }

    /// Power Φ per channel: L·A·∫s dω (π·L·A for a Lambertian emitter).
    #[inline]
    pub fn power(&self) -> Rgb {
        self.profile.integral() * self.radiance * self.area()
    }

    /// The profile's frame on a triangle of unit geometric normal `normal`: z = `normal`,
    /// x = the first of [`AreaLight::tangent`], world +x, world +z whose projection onto the
    /// triangle's plane is not (nearly) zero, normalised (module docs). For profiles that do not
    /// depend on the azimuth, `Frame::from_normal(normal)`.
    #[inline]
    pub fn frame(&self, normal: Vec3) -> Frame {
        if !self.profile.depends_on_azimuth() {
            return Frame::from_normal(normal);
        }
        tangent_frame(normal, self.tangent)
    }

    /// L_e(y0, ω)·A/Φ in the world direction `dir` from a point of normal `normal`:
    /// f_e(ω)/cos θ (1/π for a Lambertian emitter); 0 behind the surface.
    #[inline]
    pub fn emitted_fraction(&self, normal: Vec3, dir: Vec3) -> f32 {
        match self.profile {
            BuiltProfile::Cosine => std::f32::consts::FRAC_1_PI,
            ref p => p.emitted_fraction(self.frame(normal).to_local(dir)),
        }
    }

    /// The solid-angle density with which [`AreaLight::sample_emission`] draws the world
    /// direction `dir` from a point of normal `normal`: the profile's sampling pdf.
    #[inline]
    pub fn direction_pdf(&self, normal: Vec3, dir: Vec3) -> f32 {
        match self.profile {
            BuiltProfile::Cosine => dir.dot(normal).max(0.0) * std::f32::consts::FRAC_1_PI,
            ref p => p.sampling_pdf(self.frame(normal).to_local(dir)),
        }
    }

    /// A point uniform over the light's area (density 1/A), its triangle's geometric normal
    /// and the triangle: `u_pos.x` picks a triangle ∝ area and is reused, rescaled, with
    /// `u_pos.y` for a point uniform on it (so stratified inputs stay stratified). The position
    /// half of [`AreaLight::sample_emission`], which the meter's direct term also draws with.
    #[inline]
    pub fn sample_position(&self, triangles: &[Triangle], u_pos: Vec2) -> (Vec3, Vec3, u32) {
        let target = u_pos.x * self.area();
        let i = self.cumulative_area.partition_point(|&c| c <= target).min(self.triangles.len() - 1);
        let lo = if i == 0 { 0.0 } else { self.cumulative_area[i - 1] };
        let ux = ((target - lo) / (self.cumulative_area[i] - lo)).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
        let prim = self.triangles[i];
        let tri = &triangles[prim as usize];
        let b = warp::square_to_uniform_triangle(Vec2::new(ux, u_pos.y));
        (tri.point(b.x, b.y), tri.normal(), prim)
    }

    /// A path start: a point from [`AreaLight::sample_position`] (`u_pos`); `u_dir` a direction
    /// from the profile, in the triangle's frame.
    #[inline]
    pub fn sample_emission(&self, triangles: &[Triangle], u_pos: Vec2, u_dir: Vec2) -> Emission {
        let (origin, normal, prim) = self.sample_position(triangles, u_pos);
        let (local, w) = self.profile.sample(u_dir);
        let dir = self.frame(normal).to_world(local);
        Emission { origin, surface: Some((normal, prim)), dir, weight: Rgb::splat(w) }
    }
}

/// The frame of z = `normal` (unit) whose x axis is `tangent` (unit) projected onto the plane ⊥ `normal`,
/// falling back to world +x, then +z, when that projection is shorter than 10⁻² (the tangent
/// within 0.6° of the normal).
fn tangent_frame(normal: Vec3, tangent: Vec3) -> Frame {
    let project = |t: Vec3| t - normal * t.dot(normal);
    let mut s = project(tangent);
    for fallback in [Vec3::X, Vec3::Z] {
        if s.length_squared() >= 1e-4 {
            break;
        }
        s = project(fallback);
    }
    let s = s.normalize();
    Frame { s, t: normal.cross(s), n: normal }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangent_frame_follows_the_projected_tangent_and_falls_back() {
        let n = Vec3::new(0.0, -1.0, 1.0).normalize();
        for (tangent, want_s) in [
            (Vec3::X, Vec3::X),
            (Vec3::Y, Vec3::new(0.0, 1.0, 1.0).normalize()),
            (-Vec3::Y, Vec3::new(0.0, -1.0, -1.0).normalize()),
            (n, Vec3::X),                                       // parallel to the normal: world +x
            (Vec3::new(0.0, -1.0, 1.001).normalize(), Vec3::X), // within 0.6°: still the fallback
        ] {
            let f = tangent_frame(n, tangent);
            assert!((f.s - want_s).length() < 1e-5, "{tangent}: s = {}", f.s);
            assert!(f.s.dot(f.n).abs() < 1e-6 && (f.t - n.cross(f.s)).length() < 1e-6 && f.n == n);
        }
        // Normal along +x with tangent +x: +x projects to zero, +z is used.
        assert!((tangent_frame(Vec3::X, Vec3::X).s - Vec3::Z).length() < 1e-6);
        assert!((tangent_frame(-Vec3::Y, Vec3::X).s - Vec3::X).length() < 1e-6);
    }
}
