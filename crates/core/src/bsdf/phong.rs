//! Modified Phong BRDF (Lafortune & Willems 1994). PLACEHOLDER: being written.

use super::{BsdfSample, MaterialError};
use crate::math::{Rgb, Vec2, Vec3};

/// Modified Phong: kd/π + ks·(n+2)/(2π)·cosⁿα.
#[derive(Clone, Debug, PartialEq)]
pub struct ModifiedPhong {
    /// Diffuse reflectance.
    pub kd: Rgb,
    /// Specular reflectance.
    pub ks: Rgb,
    /// Phong exponent n.
    pub exponent: f32,
}

impl ModifiedPhong {
    /// Validated constructor.
    pub fn new(kd: Rgb, ks: Rgb, exponent: f32) -> Result<Self, MaterialError> {
        let _ = (kd, ks, exponent);
        todo!()
    }
    /// f_r.
    pub fn eval(&self, _wi: Vec3, _wo: Vec3) -> Rgb {
        todo!()
    }
    /// pdf.
    pub fn pdf(&self, _wi: Vec3, _wo: Vec3) -> f32 {
        todo!()
    }
    /// sample.
    pub fn sample(&self, _wi: Vec3, _u_lobe: f32, _u: Vec2) -> Option<BsdfSample> {
        todo!()
    }
}
