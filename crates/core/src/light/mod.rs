//! Light sources: a closed set ([`Light`]) of one-sided area lights (emissive triangle meshes),
//! point lights and directional (sun) lights. A light's defining quantity is its power Φ;
//! what the tracer needs from it is an *emission sample*: a start point and direction drawn
//! from the light's own emission density, with the weight that keeps the estimator exact.
//!
//! How the emission is distributed over directions is an [`EmissionProfile`] (a probability
//! density f_e, see [`profile`]): cosine (Lambertian, the default of area lights), uniform (the
//! default of point lights), cosⁿ, Mitsuba's spot cone, or IES photometric data.
//!
//! ## An area light's photometric frame
//! An area light evaluates and samples its profile in a frame per triangle: the vertical 0°
//! axis (local z) is the triangle's geometric normal, and the horizontal 0° reference (local x,
//! φ = 0; local y = z × x is φ = 90°) is the light's [`AreaLight::tangent`] projected onto the
//! triangle's plane. The tangent is world +x unless the scene sets one
//! ([`crate::scene::MeshDesc::emission_tangent`]); where it is (within 0.6° of) parallel to a
//! triangle's normal, world +x and then world +z are projected instead
//! ([`AreaLight::frame`]). Only profiles that depend on φ (IES tables) need this frame; the
//! rotationally symmetric ones use the equivalent, cheaper `Frame::from_normal`. The tracer
//! (emission sampling) and the sensor (emitters seen directly, through
//! [`Light::emitted_fraction`]) both go through [`AreaLight::frame`], so they agree.
//!
//! A [`DirectionalLight`] sends parallel rays of irradiance E (W/m² on a plane perpendicular to
//! them) over the whole scene: paths start uniformly on a disk perpendicular to the direction,
//! just outside the scene's bounding sphere, whose radius is the bounding radius r, so
//! Φ = E·π·r². Like point lights it is invisible to cameras (a delta distribution).

pub mod profile;

pub use profile::{
    BuiltProfile, EmissionProfile, IesProfile, LUMENS_PER_WATT, ProfileError, lumens_to_watts,
};

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
    /// of [`profile`]).
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
    /// Total emitting area A, m².
    pub fn area(&self) -> f32 {
        self.cumulative_area.last().copied().unwrap_or(0.0)
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
    /// Power Φ, W per channel (= intensity·∫s dω).
    pub power: Rgb,
    /// The emission density.
    pub profile: BuiltProfile,
    /// The profile's frame (z = axis, x = φ = 0).
    pub frame: Frame,
}

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

/// The closed set of lights.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Emissive triangle mesh.
    Area(AreaLight),
    /// Point light.
    Point(PointLight),
    /// Directional light.
    Directional(DirectionalLight),
}

/// Where and in which direction a light path starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emission {
    /// Start point y0.
    pub origin: Vec3,
    /// Surface normal at y0 and its triangle (area lights only).
    pub surface: Option<(Vec3, u32)>,
    /// Unit direction of the first ray.
    pub dir: Vec3,
    /// β₁: emitted flux along this ray divided by Φ/N, i.e.
    /// L_e(y0, ω)·cos θ / (p_A(y0)·p_ω(ω)·Φ) = f_e(ω)/p_ω(ω). Exactly 1 when the direction
    /// density matches the emission function (cosine, uniform, cosⁿ, directional); mean 1 for
    /// the spot and IES profiles, which are sampled approximately.
    pub weight: Rgb,
}

impl Light {
    /// Name from the scene file.
    pub fn name(&self) -> &str {
        match self {
            Light::Area(l) => &l.name,
            Light::Point(l) => &l.name,
            Light::Directional(l) => &l.name,
        }
    }

    /// Power Φ in watts per channel: π·L·A for a Lambertian area light (L·A·∫s dω in general),
    /// 4π·I for an isotropic point light, E·π·r² for a directional light.
    pub fn power(&self) -> Rgb {
        match self {
            Light::Area(l) => l.profile.integral() * l.radiance * l.area(),
            Light::Point(l) => l.power,
            Light::Directional(l) => l.irradiance * (std::f32::consts::PI * l.radius * l.radius),
        }
    }

    /// L_e(y0, ω)·A/Φ of an area light in the world direction `dir` from a point of normal
    /// `normal`: f_e(ω)/cos θ (1/π for a Lambertian emitter), what the sensor uses in place of
    /// f_r at an emission vertex. 0 for delta lights (point, directional) and behind the surface.
    #[inline]
    pub fn emitted_fraction(&self, normal: Vec3, dir: Vec3) -> f32 {
        match self {
            Light::Area(l) => match l.profile {
                BuiltProfile::Cosine => std::f32::consts::FRAC_1_PI,
                ref p => p.emitted_fraction(l.frame(normal).to_local(dir)),
            },
            _ => 0.0,
        }
    }

    /// Draws a path start from two uniform points of [0,1)²: `u_pos` picks a point uniform over
    /// the light's area (p_A = 1/A; its x coordinate first picks a triangle ∝ area and is then
    /// reused, rescaled, so stratified inputs stay stratified), `u_dir` a direction from the
    /// emission density (the light's profile; a directional light uses `u_pos` for a point
    /// uniform on its disk).
    #[inline]
    pub fn sample_emission(&self, triangles: &[Triangle], u_pos: Vec2, u_dir: Vec2) -> Emission {
        match self {
            Light::Area(l) => {
                let target = u_pos.x * l.area();
                let i = l.cumulative_area.partition_point(|&c| c <= target).min(l.triangles.len() - 1);
                let lo = if i == 0 { 0.0 } else { l.cumulative_area[i - 1] };
                let ux = ((target - lo) / (l.cumulative_area[i] - lo)).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
                let prim = l.triangles[i];
                let tri = &triangles[prim as usize];
                let b = warp::square_to_uniform_triangle(Vec2::new(ux, u_pos.y));
                let origin = tri.point(b.x, b.y);
                let normal = tri.normal();
                let (local, w) = l.profile.sample(u_dir);
                let dir = l.frame(normal).to_world(local);
                Emission { origin, surface: Some((normal, prim)), dir, weight: Rgb::splat(w) }
            }
            Light::Point(l) => {
                let (dir, w) = match l.profile {
                    BuiltProfile::Uniform { hemisphere: false } => {
                        (warp::square_to_uniform_sphere(u_dir), 1.0)
                    }
                    ref p => {
                        let (local, w) = p.sample(u_dir);
                        (l.frame.to_world(local).normalize(), w)
                    }
                };
                Emission { origin: l.position, surface: None, dir, weight: Rgb::splat(w) }
            }
            Light::Directional(l) => {
                let d = l.radius * warp::square_to_concentric_disk(u_pos);
                let origin = l.centre + d.x * l.frame.s + d.y * l.frame.t;
                Emission { origin, surface: None, dir: l.direction, weight: Rgb::ONE }
            }
        }
    }
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
