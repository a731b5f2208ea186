//! Smooth plastic, Mitsuba 3's `plastic`: a diffuse base under a smooth dielectric coating of
//! relative index η = int_ior/ext_ior, with the internal scattering between them summed in
//! closed form. Light either reflects specularly off the coating (Fresnel F(θ_i), a delta lobe)
//! or enters, is scattered by the base any number of times between it and the coating's inside,
//! and leaves through the coating:
//!
//! f(wi → wo) = (1 − F(θ_i))·(1 − F(θ_o))/η² · ρ'/π,
//! ρ' = ρ / (1 − F_dr,int) (Mitsuba's default, linear in ρ), or ρ / (1 − ρ·F_dr,int) with
//! `nonlinear` (each internal bounce also tints: saturated colours),
//!
//! where F_dr,int is the coating's diffuse reflectance from inside
//! ([`fresnel::diffuse_reflectance`] of 1/η, the fits Mitsuba uses). f is symmetric in wi, wo:
//! the same in both transport modes.
//!
//! Sampling follows Mitsuba: the specular lobe with probability F(θ_i)·w / (F(θ_i)·w +
//! (1 − F(θ_i))·(1 − w)), w = s̄/(ρ̄ + s̄) (s̄, ρ̄ the channel means of the specular and diffuse
//! reflectances), else a cosine-weighted direction; `pdf` is the diffuse part's density (the
//! delta lobe has none). One-sided (black from behind) like Mitsuba's.

use super::{BsdfSample, MaterialError, check_unit_colour, fresnel};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::warp;
use std::f32::consts::FRAC_1_PI;

/// Smooth plastic (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Plastic {
    /// The base's diffuse reflectance ρ.
    pub diffuse_reflectance: Rgb,
    /// Scale of the coating's specular reflection (Mitsuba's `specular_reflectance`, 1: a
    /// physical coating).
    pub specular_reflectance: Rgb,
    /// Relative index of the coating, int_ior / ext_ior.
    pub eta: f32,
    /// Whether internal scattering tints (ρ/(1 − ρ·F_dr)) rather than scales (ρ/(1 − F_dr)).
    pub nonlinear: bool,
    /// F_dr of the coating seen from inside, 1/η².
    fdr_int: f32,
    inv_eta2: f32,
    /// Mitsuba's specular sampling weight s̄/(ρ̄ + s̄).
    specular_weight: f32,
}

impl Plastic {
    /// A smooth plastic. Refuses colours outside [0, 1], non-finite values and indices ≤ 0.
    pub fn new(
        diffuse_reflectance: Rgb,
        specular_reflectance: Rgb,
        int_ior: f32,
        ext_ior: f32,
        nonlinear: bool,
    ) -> Result<Self, MaterialError> {
        check_unit_colour("diffuse_reflectance", diffuse_reflectance)?;
        check_unit_colour("specular_reflectance", specular_reflectance)?;
        for (name, v) in [("int_ior", int_ior), ("ext_ior", ext_ior)] {
            if !v.is_finite() {
                return Err(MaterialError::NotFinite(name));
            }
            if v <= 0.0 {
                return Err(MaterialError::NotPositive(name));
            }
        }
        let eta = int_ior / ext_ior;
        let (d_mean, s_mean) =
            (diffuse_reflectance.element_sum() / 3.0, specular_reflectance.element_sum() / 3.0);
        let specular_weight = if d_mean + s_mean > 0.0 { s_mean / (d_mean + s_mean) } else { 0.5 };
        Ok(Plastic {
            diffuse_reflectance,
            specular_reflectance,
            eta,
            nonlinear,
            fdr_int: fresnel::diffuse_reflectance(1.0 / eta),
            inv_eta2: 1.0 / (eta * eta),
            specular_weight,
        })
    }

    /// ρ' (module docs).
    fn base(&self) -> Rgb {
        let d = self.diffuse_reflectance;
        if self.nonlinear { d / (Rgb::ONE - d * self.fdr_int) } else { d / (1.0 - self.fdr_int) }
    }

    /// The probability of sampling the specular lobe for light arriving at cos θ_i with
    /// Fresnel reflectance `f_i`.
    fn specular_probability(&self, f_i: f32) -> f32 {
        let s = f_i * self.specular_weight;
        let d = (1.0 - f_i) * (1.0 - self.specular_weight);
        if s + d > 0.0 { s / (s + d) } else { 0.0 }
    }

    /// The probability with which [`Plastic::sample`] given `wi` picks the coating's delta lobe
    /// (whose direction `wo` is the mirror of `wi`): P_spec, or 0 from below.
    #[inline]
    pub fn coating_probability(&self, wi: Vec3, wo: Vec3) -> f32 {
        if !(wi.z > 0.0 && wo.z > 0.0) {
            return 0.0;
        }
        self.specular_probability(fresnel::dielectric(wi.z, self.eta).0)
    }

    /// The diffuse part f(wi → wo) (the delta lobe is not a function).
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !(wi.z > 0.0 && wo.z > 0.0) {
            return Rgb::ZERO;
        }
        let f_i = fresnel::dielectric(wi.z, self.eta).0;
        let f_o = fresnel::dielectric(wo.z, self.eta).0;
        self.base() * (self.inv_eta2 * (1.0 - f_i) * (1.0 - f_o) * FRAC_1_PI)
    }

    /// Density of a diffuse sample: cos θ_o/π times the probability of the diffuse lobe.
    #[inline]
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if !(wi.z > 0.0 && wo.z > 0.0) {
            return 0.0;
        }
        let f_i = fresnel::dielectric(wi.z, self.eta).0;
        (1.0 - self.specular_probability(f_i)) * warp::cosine_hemisphere_pdf(wo)
    }

    /// The specular lobe (delta, weight F·s/P_spec) if `u_lobe` < P_spec, else a cosine-weighted
    /// direction with weight f·cos/pdf.
    #[inline]
    pub fn sample(&self, wi: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if !(wi.z > 0.0) {
            return None;
        }
        let f_i = fresnel::dielectric(wi.z, self.eta).0;
        let p_spec = self.specular_probability(f_i);
        if u_lobe < p_spec {
            let wo = Vec3::new(-wi.x, -wi.y, wi.z);
            let weight = self.specular_reflectance * (f_i / p_spec);
            return Some(BsdfSample { wo, weight, pdf: p_spec, delta: true });
        }
        let wo = warp::square_to_cosine_hemisphere(u);
        let pdf = (1.0 - p_spec) * warp::cosine_hemisphere_pdf(wo);
        if !(pdf > 0.0) {
            return None;
        }
        let weight = self.eval(wi, wo) * (wo.z / pdf);
        Some(BsdfSample { wo, weight, pdf, delta: false })
    }

    /// Upper bound of the directional albedo per channel.
    pub fn max_albedo(&self) -> Rgb {
        self.specular_reflectance.max(self.base() * self.inv_eta2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{Chi2Test, SphereGrid, directional_albedo, incident, mean_sample_weight, pilot};
    use crate::sampling::RandomStream;
    use rayon::prelude::*;

    fn plastics() -> Vec<Plastic> {
        vec![
            Plastic::new(Rgb::new(0.8, 0.4, 0.1), Rgb::ONE, 1.49, 1.000277, false).unwrap(),
            Plastic::new(Rgb::new(0.8, 0.4, 0.1), Rgb::ONE, 1.49, 1.000277, true).unwrap(),
            Plastic::new(Rgb::splat(0.2), Rgb::splat(0.5), 2.0, 1.0, false).unwrap(),
        ]
    }

    /// (a) χ² of the diffuse samples against `pdf` (delta samples are "not accepted": ∫pdf
    /// must equal the diffuse fraction), at normal, oblique and grazing incidence.
    #[test]
    fn chi2_sampling_matches_pdf() {
        let cases: Vec<(usize, f32)> = (0..3).flat_map(|b| [0.0, 60.0, 87.0].map(move |d| (b, d))).collect();
        cases.into_par_iter().enumerate().for_each(|(i, (k, deg))| {
            let b = &plastics()[k];
            let wi = incident(deg);
            Chi2Test::new(Vec3::Z, 900 + i as u64)
                .run(
                    |ul, u| b.sample(wi, ul, u).filter(|s| !s.delta).map(|s| (s.wo, s.pdf)),
                    |wo| b.pdf(wi, wo),
                )
                .assert_ok(&format!("plastic {k} θi={deg}°"));
        });
    }

    /// (b) Reciprocity, and the weights agree with eval/pdf.
    #[test]
    fn reciprocal_and_consistent() {
        let mut rng = RandomStream::new(901, &[]);
        for b in plastics() {
            for _ in 0..5_000 {
                let wi = warp::square_to_cosine_hemisphere(rng.next_2d());
                let wo = warp::square_to_cosine_hemisphere(rng.next_2d());
                let (f, g) = (b.eval(wi, wo), b.eval(wo, wi));
                assert!((f - g).abs().max_element() <= 1e-6 * f.max_element().max(1e-6), "{f} {g}");
                let Some(s) = b.sample(wi, rng.next_f32(), rng.next_2d()) else { continue };
                if s.delta {
                    assert_eq!(s.wo, Vec3::new(-wi.x, -wi.y, wi.z));
                } else {
                    let w = b.eval(wi, s.wo) * s.wo.z / s.pdf;
                    assert!((s.weight - w).abs().max_element() <= 1e-4 * w.max_element(), "{s:?} {w}");
                    assert_eq!(b.pdf(wi, s.wo), s.pdf);
                }
            }
            assert!(b.sample(-Vec3::Z, 0.5, Vec2::splat(0.5)).is_none(), "one-sided");
            assert_eq!(b.eval(-Vec3::Z, Vec3::Z), Rgb::ZERO);
        }
    }

    /// (c, d) White furnace: the mean sample weight equals F(θ_i)·s + the quadrature of
    /// f·cos within 5σ. For a white base (ρ = 1, s = 1) that albedo is 1 up to the accuracy of
    /// the F_dr fit (physically (1 − F_dr,ext) = η²·(1 − F_dr,int), so no energy is lost or made):
    /// within 1%. The linear model never exceeds 1 + 1% anywhere.
    #[test]
    fn furnace() {
        let mut rng = RandomStream::new(902, &[]);
        let white = Plastic::new(Rgb::ONE, Rgb::ONE, 1.5, 1.0, false).unwrap();
        for (k, b) in plastics().into_iter().chain([white.clone()]).enumerate() {
            for deg in [0.0, 45.0, 80.0] {
                let wi = incident(deg);
                let dirs =
                    pilot(|ul, u| b.sample(wi, ul, u).filter(|s| !s.delta).map(|s| (s.wo, s.pdf)), 20_000, 3);
                let grid = SphereGrid::adapted(Vec3::Z, &dirs, 16, 16);
                let f_i = fresnel::dielectric(wi.z, b.eta).0 as f64;
                let want =
                    directional_albedo(&grid, |wo| b.eval(wi, wo)) + b.specular_reflectance.as_dvec3() * f_i;
                let (mean, se) = mean_sample_weight(200_000, || {
                    b.sample(wi, rng.next_f32(), rng.next_2d()).map(|s| s.weight)
                });
                for c in 0..3 {
                    assert!(
                        (mean[c] - want[c]).abs() <= 5.0 * se[c] + 1e-4,
                        "plastic {k} θ={deg} channel {c}: {} vs {} ± {}",
                        mean[c],
                        want[c],
                        se[c]
                    );
                    assert!(want[c] <= 1.01, "plastic {k} θ={deg}: albedo {}", want[c]);
                }
                if k == 3 {
                    assert!((want - 1.0).abs().max_element() < 0.01, "white plastic θ={deg}: albedo {want}");
                }
            }
        }
    }

    #[test]
    fn parameters_are_validated() {
        use MaterialError::*;
        let p = |d, s, i, e| Plastic::new(d, s, i, e, false);
        assert_eq!(p(Rgb::splat(1.2), Rgb::ONE, 1.5, 1.0), Err(AboveOne("diffuse_reflectance")));
        assert_eq!(p(Rgb::ONE, Rgb::splat(-1.0), 1.5, 1.0), Err(Negative("specular_reflectance")));
        assert_eq!(p(Rgb::ONE, Rgb::ONE, 0.0, 1.0), Err(NotPositive("int_ior")));
        assert_eq!(p(Rgb::ONE, Rgb::ONE, 1.5, f32::NAN), Err(NotFinite("ext_ior")));
        assert!(p(Rgb::ZERO, Rgb::ZERO, 1.5, 1.0).is_ok());
    }
}
