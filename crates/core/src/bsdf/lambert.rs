//! Lambertian (ideal diffuse) reflection: f_r = ρ/π, sampled with a cosine-weighted hemisphere,
//! so a sampled direction's weight is exactly ρ. Mitsuba's `diffuse`.

use super::{BsdfSample, MaterialError};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::warp;
use std::f32::consts::FRAC_1_PI;

/// Ideal diffuse reflector of albedo `reflectance` (each channel in [0, 1]).
#[derive(Clone, Debug, PartialEq)]
pub struct Lambert {
    /// Diffuse albedo ρ.
    pub reflectance: Rgb,
}

impl Lambert {
    /// A Lambertian BSDF; refuses albedos outside [0, 1] or non-finite ones.
    pub fn new(reflectance: Rgb) -> Result<Self, MaterialError> {
        if !reflectance.is_finite() {
            return Err(MaterialError::NotFinite("reflectance"));
        }
        if reflectance.min_element() < 0.0 {
            return Err(MaterialError::Negative("reflectance"));
        }
        if reflectance.max_element() > 1.0 {
            return Err(MaterialError::CreatesEnergy(reflectance));
        }
        Ok(Lambert { reflectance })
    }

    /// f_r = ρ/π above the surface.
    #[inline]
    pub fn eval(&self, _wi: Vec3, wo: Vec3) -> Rgb {
        if wo.z > 0.0 { self.reflectance * FRAC_1_PI } else { Rgb::ZERO }
    }

    /// cos θ_o / π.
    #[inline]
    pub fn pdf(&self, _wi: Vec3, wo: Vec3) -> f32 {
        warp::cosine_hemisphere_pdf(wo)
    }

    /// Cosine-weighted sampling; weight = ρ.
    #[inline]
    pub fn sample(&self, _wi: Vec3, u: Vec2) -> Option<BsdfSample> {
        let wo = warp::square_to_cosine_hemisphere(u);
        let pdf = warp::cosine_hemisphere_pdf(wo);
        (pdf > 0.0).then_some(BsdfSample { wo, weight: self.reflectance, pdf })
    }
}
