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
        if wo.z > 0.0 { self.eval_lit() } else { Rgb::ZERO }
    }

    /// f_r above the surface, ρ/π (the one expression [`Lambert::eval`] and the splats' flat
    /// fast path, `Scene::flat_lambert`, share: their results are the same to the bit).
    #[inline]
    pub fn eval_lit(&self) -> Rgb {
        self.reflectance * FRAC_1_PI
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
        (pdf > 0.0).then_some(BsdfSample { wo, weight: self.reflectance, pdf, delta: false })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{Chi2Test, SphereGrid, directional_albedo};
    use crate::sampling::RandomStream;
    use glam::DVec3;

    /// (a) χ² of cosine-weighted sampling against the pdf (the incident direction is irrelevant
    /// to Lambert but is varied anyway, the grid is tilted to cut the horizon).
    #[test]
    fn chi2_sampling_matches_pdf() {
        let b = Lambert::new(Rgb::new(0.8, 0.5, 0.2)).unwrap();
        // Grid about the normal (horizon on a θ edge), and tilted towards a grazing reflection
        // direction (horizon across cells).
        let grazing = Vec3::new(0.99, 0.0, 0.1).normalize();
        for (i, (wi, axis)) in [(Vec3::Z, Vec3::Z), (grazing, Vec3::new(-grazing.x, -grazing.y, grazing.z))]
            .into_iter()
            .enumerate()
        {
            Chi2Test::new(axis, 500 + i as u64)
                .run(|_, u| b.sample(wi, u).map(|s| (s.wo, s.pdf)), |wo| b.pdf(wi, wo))
                .assert_ok(&format!("Lambert wi={wi} axis={axis}"));
        }
    }

    /// (b) Reciprocity.
    #[test]
    fn eval_is_reciprocal() {
        let b = Lambert::new(Rgb::new(0.8, 0.5, 0.2)).unwrap();
        let mut rng = RandomStream::new(501, &[]);
        for _ in 0..10_000 {
            let wi = warp::square_to_cosine_hemisphere(rng.next_2d());
            let wo = warp::square_to_cosine_hemisphere(rng.next_2d());
            assert_eq!(b.eval(wi, wo), b.eval(wo, wi));
        }
    }

    /// (c) + (d) The albedo is ρ by quadrature (exactly 1 for white), and every sample weight
    /// is ρ, so their mean is too.
    #[test]
    fn albedo_equals_reflectance() {
        let grid = SphereGrid::adapted(Vec3::Z, &[], 1, 16);
        let white = Lambert::new(Rgb::ONE).unwrap();
        let a = directional_albedo(&grid, |wo| white.eval(Vec3::Z, wo));
        assert!((a - DVec3::ONE).abs().max_element() < 1e-6, "{a}");
        let b = Lambert::new(Rgb::new(0.8, 0.5, 0.2)).unwrap();
        let a = directional_albedo(&grid, |wo| b.eval(Vec3::Z, wo));
        assert!((a - b.reflectance.as_dvec3()).abs().max_element() < 1e-6, "{a}");
        let mut rng = RandomStream::new(502, &[]);
        for _ in 0..10_000 {
            let s = white.sample(Vec3::Z, rng.next_2d()).unwrap();
            assert_eq!(s.weight, Rgb::ONE);
            assert!((s.weight - white.eval(Vec3::Z, s.wo) * s.wo.z / s.pdf).abs().max_element() < 1e-5);
        }
    }

    /// (e) Parameter validation.
    #[test]
    fn new_rejects_invalid_reflectance() {
        assert_eq!(Lambert::new(Rgb::new(0.1, f32::NAN, 0.1)), Err(MaterialError::NotFinite("reflectance")));
        assert_eq!(Lambert::new(Rgb::new(0.1, -0.1, 0.1)), Err(MaterialError::Negative("reflectance")));
        let r = Rgb::new(0.1, 1.1, 0.1);
        assert_eq!(Lambert::new(r), Err(MaterialError::CreatesEnergy(r)));
        assert!(Lambert::new(Rgb::ONE).is_ok() && Lambert::new(Rgb::ZERO).is_ok());
    }
}
