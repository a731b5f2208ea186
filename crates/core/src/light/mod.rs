//! Light sources: a closed set ([`Light`]) of one-sided area lights (emissive triangle meshes,
//! [`area`]), point lights ([`point`]), directional (sun) lights ([`directional`]) and
//! environments at infinity (a constant colour or a lat-long map, [`environment`]), one file
//! per kind as [`crate::bsdf`] has one per BSDF. A light's defining quantity is its power Φ;
//! what the tracer needs from it is an *emission sample*: a start point and direction drawn
//! from the light's own emission density, with the weight that keeps the estimator exact.
//!
//! How the emission is distributed over directions is an [`EmissionProfile`] (a probability
//! density f_e): the analytic ones in [`profile`] — cosine (Lambertian, the default of area
//! lights), uniform (the default of point lights), cosⁿ, Mitsuba's spot cone — and IES
//! photometric tables in [`ies`].
//!
//! A spot light may project a texture ([`spot_texture`]).
//!
//! Every physical constraint on a light's parameters is written once, in [`check`] (amounts,
//! axes, tangents, frames, lumens) and in the profile constructors ([`EmissionProfile::spot`],
//! [`EmissionProfile::cosine_power`], [`IesProfile::validate`]); [`crate::scene::Scene::build`]
//! and the loaders call them.
//!
//! Adding a light kind: a file here with its struct, `power` and `sample_emission`, a variant of
//! [`Light`] with its arms below, its description in [`crate::scene::SceneDescription`] and its
//! construction in the scene's lights stage.

pub mod area;
pub mod check;
pub mod directional;
pub mod environment;
pub mod ies;
pub mod point;
pub mod profile;
pub mod spot_texture;

pub use area::{AreaLight, EmitterTexture, EmitterTextureDesc};
pub use check::{LUMENS_PER_WATT, LightError, lumens_to_watts};
pub use directional::DirectionalLight;
pub use environment::{EnvRadiance, EnvironmentLight, LatLong};
pub use ies::{IesProfile, IesTableError};
pub use point::{PointLight, axis_frame};
pub use profile::{BuiltProfile, EmissionProfile, ProfileError};
pub use spot_texture::SpotTexture;

use crate::geometry::Triangle;
use crate::math::{Rgb, Vec2, Vec3};

/// The closed set of lights.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Emissive triangle mesh.
    Area(AreaLight),
    /// Point light.
    Point(PointLight),
    /// Directional light.
    Directional(DirectionalLight),
    /// Environment at infinity (seen by camera rays that leave the scene).
    Environment(EnvironmentLight),
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
    /// the spot and IES profiles, which are sampled approximately; a textured area light's
    /// also carries `emitted`.
    pub weight: Rgb,
    /// The radiance at y0 relative to the light's mean: T(uv)/T̄ of a textured area light
    /// ([`area`] module docs), 1 otherwise. The weight of the emission vertex's stored sample.
    pub emitted: Rgb,
}

impl Light {
    /// Name from the scene file.
    pub fn name(&self) -> &str {
        match self {
            Light::Area(l) => &l.name,
            Light::Point(l) => &l.name,
            Light::Directional(l) => &l.name,
            Light::Environment(l) => &l.name,
        }
    }

    /// Power Φ in watts per channel: π·L·A for a Lambertian area light (L·A·∫s dω in general),
    /// 4π·I for an isotropic point light, E·π·r² for a directional light, π·r²·∫L dω for an
    /// environment.
    pub fn power(&self) -> Rgb {
        match self {
            Light::Area(l) => l.power(),
            Light::Point(l) => l.power,
            Light::Directional(l) => l.power(),
            Light::Environment(l) => l.power(),
        }
    }

    /// L_e(y0, ω)·A/Φ of an area light in the world direction `dir` from a point of normal
    /// `normal`: f_e(ω)/cos θ (1/π for a Lambertian emitter), what the sensor uses in place of
    /// f_r at an emission vertex. 0 for delta lights (point, directional) and behind the surface.
    #[inline]
    pub fn emitted_fraction(&self, normal: Vec3, dir: Vec3) -> f32 {
        match self {
            Light::Area(l) => l.emitted_fraction(normal, dir),
            _ => 0.0,
        }
    }

    /// The densities [`Light::sample_emission`] draws a path start with, for a start point of
    /// geometric normal `normal` (area lights; ignored otherwise) emitting along the unit world
    /// direction `dir`: (position, second) = (1/A, the profile's *sampling* pdf of `dir`) for
    /// area lights, (1, the profile's sampling pdf) for point lights (a delta position), and
    /// (1, 1/(π r²)) for directional lights (a delta direction, the start point uniform on the
    /// disk), (p(−dir), 1/(π r²)) for environments (the solid-angle density of the direction the
    /// light comes from, then the disk). What the bidirectional estimator's MIS needs of a light
    /// (`crate::trace::emitter_densities`); the tracer's weights do not use it.
    #[inline]
    pub fn emission_pdfs(&self, normal: Vec3, dir: Vec3) -> (f32, f32) {
        match self {
            Light::Area(l) => (1.0 / l.area(), l.direction_pdf(normal, dir)),
            Light::Point(l) => (1.0, l.direction_pdf(dir)),
            Light::Directional(l) => (1.0, l.disk_pdf()),
            Light::Environment(l) => (l.direction_pdf(-dir), l.disk_pdf()),
        }
    }

    /// Draws a path start from two uniform points of [0,1)²: `u_pos` picks a point uniform over
    /// the light's area (p_A = 1/A; its x coordinate first picks a triangle ∝ area and is then
    /// reused, rescaled, so stratified inputs stay stratified), `u_dir` a direction from the
    /// emission density (the light's profile; a directional light uses `u_pos` for a point
    /// uniform on its disk; an environment `u_dir` for the direction, `u_pos` for the disk).
    #[inline]
    pub fn sample_emission(&self, triangles: &[Triangle], u_pos: Vec2, u_dir: Vec2) -> Emission {
        match self {
            Light::Area(l) => l.sample_emission(triangles, u_pos, u_dir),
            Light::Point(l) => l.sample_emission(u_dir),
            Light::Directional(l) => l.sample_emission(u_pos),
            Light::Environment(l) => l.sample_emission(u_pos, u_dir),
        }
    }
}
