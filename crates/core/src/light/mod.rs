//! Light sources: a closed set ([`Light`]) of one-sided Lambertian area lights (emissive
//! triangle meshes) and isotropic point lights. A light's defining quantity is its power Φ;
//! what the tracer needs from it is an *emission sample*: a start point and direction drawn
//! from the light's own emission density, with the weight that keeps the estimator exact.

use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::warp;
use crate::scene::Triangle;
use std::f32::consts::PI;

/// A one-sided Lambertian emitter made of scene triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct AreaLight {
    /// Name from the scene.
    pub name: String,
    /// Emitted radiance L_e, W/(m²·sr), constant over the surface and the front hemisphere.
    pub radiance: Rgb,
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
}

/// An isotropic point light.
#[derive(Clone, Debug, PartialEq)]
pub struct PointLight {
    /// Name from the scene.
    pub name: String,
    /// Position.
    pub position: Vec3,
    /// Radiant intensity I, W/sr.
    pub intensity: Rgb,
}

/// The closed set of lights.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Emissive triangle mesh.
    Area(AreaLight),
    /// Point light.
    Point(PointLight),
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
    /// L_e(y0, ω)·cos θ / (p_A(y0)·p_ω(ω)·Φ). Exactly 1 when the direction density matches
    /// the emission function, as it does for both lights here.
    pub weight: Rgb,
}

impl Light {
    /// Name from the scene file.
    pub fn name(&self) -> &str {
        match self {
            Light::Area(l) => &l.name,
            Light::Point(l) => &l.name,
        }
    }

    /// Power Φ in watts per channel: π·L·A for a Lambertian area light, 4π·I for a point light.
    pub fn power(&self) -> Rgb {
        match self {
            Light::Area(l) => PI * l.radiance * l.area(),
            Light::Point(l) => 4.0 * PI * l.intensity,
        }
    }

    /// Draws a path start from two uniform points of [0,1)²: `u_pos` picks a point uniform over
    /// the light's area (p_A = 1/A; its x coordinate first picks a triangle ∝ area and is then
    /// reused, rescaled, so stratified inputs stay stratified), `u_dir` a direction from the
    /// emission density (cosine for area lights, uniform sphere for point lights).
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
                let dir = Frame::from_normal(normal).to_world(warp::square_to_cosine_hemisphere(u_dir));
                Emission { origin, surface: Some((normal, prim)), dir, weight: Rgb::ONE }
            }
            Light::Point(l) => Emission {
                origin: l.position,
                surface: None,
                dir: warp::square_to_uniform_sphere(u_dir),
                weight: Rgb::ONE,
            },
        }
    }
}
