//! Modified Phong BRDF of Lafortune & Willems 1994 ("Using the modified Phong reflectance model
//! for physically based rendering"), the material model of the thesis:
//!
//! ```text
//! f_r(wi, wo) = kd/π + ks·(n+2)/(2π)·max(0, cos α)ⁿ,   cos α = wo · reflect(wi)
//! ```
//!
//! where reflect(wi) = (−wi.x, −wi.y, wi.z) is the mirror direction about the normal. The
//! (n+2)/(2π) normalisation makes the specular lobe's albedo exactly `ks` at normal incidence and
//! less elsewhere, so kd + ks ≤ 1 per channel guarantees energy conservation. The BRDF is
//! symmetric in wi and wo (cos α is), hence reciprocal.
//!
//! Sampling picks a lobe with probability proportional to its mean albedo, then samples the
//! diffuse lobe by a cosine-weighted hemisphere or the specular lobe by the Phong lobe
//! (n+1)/(2π)·cosⁿα around reflect(wi) ([`warp::square_to_phong_lobe`]). The returned pdf is the
//! *combined* density of both strategies (one-sample MIS, balance heuristic), so `eval`, `pdf` and
//! `sample` agree exactly. Directions of the specular lobe that fall below the surface carry no
//! energy and make `sample` return `None`; `pdf` is then a density over the returned directions
//! integrating to 1 − P(None).
//!
//! Exponents from 0 to [`ModifiedPhong::MAX_EXPONENT`] are handled without overflow or NaN: cosⁿα
//! is computed from the versine 1 − cos α = |wo − reflect(wi)|²/2 (see [`warp`]), which keeps full
//! precision inside narrow lobes.

use super::{BsdfSample, MaterialError};
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::warp;
use std::f32::consts::FRAC_1_PI;

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

/// 1 − cos α between `wo` and reflect(`wi`), as |wo − reflect(wi)|²/2: accurate for small α,
/// insensitive to rounding in the vectors' lengths, and bitwise symmetric in `wi` and `wo`.
#[inline]
fn versine(wi: Vec3, wo: Vec3) -> f32 {
    let d = Vec3::new(wo.x + wi.x, wo.y + wi.y, wo.z - wi.z);
    0.5 * d.length_squared()
}

impl ModifiedPhong {
    /// Largest accepted exponent (a lobe about 0.06° wide); beyond it the f32 directions of the
    /// renderer cannot resolve the lobe.
    pub const MAX_EXPONENT: f32 = 1e6;

    /// The exponent whose lobe has the width of a microfacet surface of RMS slope `alpha` near
    /// its peak, n = 2/α² − 2, within [0, [`Self::MAX_EXPONENT`]] (α = 0: the largest). The
    /// rule the glTF (α = roughness²) and Radiance (Ward's α) readers map roughness with.
    pub fn exponent_for_slope(alpha: f32) -> f32 {
        (2.0 / (alpha * alpha) - 2.0).clamp(0.0, Self::MAX_EXPONENT)
    }

    /// Validated constructor: every parameter finite and non-negative, `exponent` at most
    /// [`Self::MAX_EXPONENT`], and `kd + ks ≤ 1` in every channel (energy conservation).
    pub fn new(kd: Rgb, ks: Rgb, exponent: f32) -> Result<Self, MaterialError> {
        if !kd.is_finite() {
            return Err(MaterialError::NotFinite("kd"));
        }
        if !ks.is_finite() {
            return Err(MaterialError::NotFinite("ks"));
        }
        if !exponent.is_finite() {
            return Err(MaterialError::NotFinite("exponent"));
        }
        if kd.min_element() < 0.0 {
            return Err(MaterialError::Negative("kd"));
        }
        if ks.min_element() < 0.0 {
            return Err(MaterialError::Negative("ks"));
        }
        if exponent < 0.0 {
            return Err(MaterialError::Negative("exponent"));
        }
        if exponent > Self::MAX_EXPONENT {
            return Err(MaterialError::TooLarge {
                name: "exponent",
                value: exponent,
                max: Self::MAX_EXPONENT,
            });
        }
        let sum = kd + ks;
        if sum.max_element() > 1.0 {
            return Err(MaterialError::CreatesEnergy(sum));
        }
        Ok(ModifiedPhong { kd, ks, exponent })
    }

    /// Probability of sampling the specular lobe: mean(ks) / (mean(kd) + mean(ks)); `None` when
    /// the surface is black (nothing to sample). 0 when ks = 0 and 1 when kd = 0, exactly.
    #[inline]
    fn specular_probability(&self) -> Option<f32> {
        let (d, s) = (self.kd.element_sum(), self.ks.element_sum());
        (d + s > 0.0).then(|| s / (d + s))
    }

    /// f_r(wi → wo) = kd/π + ks·(n+2)/(2π)·cosⁿα above the surface; zero if either direction is
    /// at or below it (so that `eval(wi, wo) == eval(wo, wi)` everywhere, bit for bit).
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Rgb::ZERO;
        }
        let diffuse = self.kd * FRAC_1_PI;
        if self.ks == Rgb::ZERO {
            return diffuse;
        }
        let n = self.exponent;
        let lobe = (n + 2.0) * (0.5 * FRAC_1_PI) * warp::pow_cos_from_versine(versine(wi, wo), n);
        diffuse + self.ks * lobe
    }

    /// Combined density of [`Self::sample`]: p_d·cos θ_o/π + p_s·(n+1)/(2π)·cosⁿα for wo above
    /// the surface, zero below it (where `sample` returns `None` instead).
    #[inline]
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let Some(ps) = self.specular_probability() else { return 0.0 };
        let mut pdf = 0.0;
        if ps < 1.0 {
            pdf += (1.0 - ps) * warp::cosine_hemisphere_pdf(wo);
        }
        if ps > 0.0 {
            pdf += ps * warp::phong_lobe_pdf_from_versine(versine(wi, wo), self.exponent);
        }
        pdf
    }

    /// Samples `wo`: the specular lobe if `u_lobe < p_s`, else the diffuse lobe, using `u` for
    /// the direction. `pdf` is the combined [`Self::pdf`] and `weight = f_r·cos θ_o / pdf`.
    /// `None` for a black surface or a direction that carries no energy (below the surface).
    #[inline]
    pub fn sample(&self, wi: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wi.z <= 0.0 {
            return None;
        }
        let ps = self.specular_probability()?;
        let wo = if u_lobe < ps {
            let reflected = Vec3::new(-wi.x, -wi.y, wi.z);
            Frame::from_normal(reflected).to_world(warp::square_to_phong_lobe(u, self.exponent))
        } else {
            warp::square_to_cosine_hemisphere(u)
        };
        if wo.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wi, wo);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight = self.eval(wi, wo) * wo.z / pdf;
        weight.is_finite().then_some(BsdfSample { wo, weight, pdf, delta: false })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{
        Chi2Test, SphereGrid, directional_albedo, incident, mean_sample_weight, pilot, reflect,
    };
    use crate::sampling::RandomStream;
    use glam::DVec3;
    use rayon::prelude::*;

    fn phong(kd: f32, ks: f32, n: f32) -> ModifiedPhong {
        ModifiedPhong::new(Rgb::splat(kd), Rgb::splat(ks), n).unwrap()
    }

    /// A quadrature grid about the reflection direction, adapted to the BSDF's own samples.
    fn albedo_grid(b: &ModifiedPhong, wi: Vec3) -> SphereGrid {
        let dirs = pilot(|ul, u| b.sample(wi, ul, u).map(|s| (s.wo, s.pdf)), 20_000, 77);
        SphereGrid::adapted(reflect(wi), &dirs, 16, 16)
    }

    fn albedo(b: &ModifiedPhong, wi: Vec3) -> DVec3 {
        directional_albedo(&albedo_grid(b, wi), |wo| b.eval(wi, wo))
    }

    fn chi2(b: &ModifiedPhong, deg: f32, seed: u64) {
        let wi = incident(deg);
        Chi2Test::new(reflect(wi), seed)
            .run(|ul, u| b.sample(wi, ul, u).map(|s| (s.wo, s.pdf)), |wo| b.pdf(wi, wo))
            .assert_ok(&format!("{b:?} at θi = {deg}°"));
    }

    /// (a) χ² of `sample` against `pdf`: exponent `n`, three incidences (normal, oblique,
    /// grazing) and two kd/ks mixes (pure specular, and a coloured half-half one).
    fn chi2_for_exponent(n: f32) {
        let coloured = ModifiedPhong::new(Rgb::new(0.5, 0.3, 0.1), Rgb::new(0.2, 0.4, 0.6), n).unwrap();
        // Independent runs (each seeded by its case), in parallel.
        [0.0, 40.0, 85.0].into_par_iter().enumerate().for_each(|(i, deg)| {
            chi2(&phong(0.0, 0.9, n), deg, 100 * n as u64 + i as u64);
            chi2(&coloured, deg, 100 * n as u64 + 10 + i as u64);
        });
    }

    #[test]
    fn chi2_exponent_1() {
        chi2_for_exponent(1.0);
    }

    #[test]
    fn chi2_exponent_10() {
        chi2_for_exponent(10.0);
    }

    #[test]
    fn chi2_exponent_100() {
        chi2_for_exponent(100.0);
    }

    #[test]
    fn chi2_exponent_1000() {
        chi2_for_exponent(1000.0);
    }

    #[test]
    fn chi2_exponent_10000() {
        chi2_for_exponent(10000.0);
    }

    #[test]
    fn chi2_extreme_exponents_and_diffuse_only() {
        chi2(&phong(0.3, 0.6, 0.0), 60.0, 1);
        chi2(&phong(0.1, 0.9, 1e5), 85.0, 2);
        chi2(&phong(0.8, 0.0, 50.0), 30.0, 3);
    }

    /// (b) eval(wi, wo) == eval(wo, wi) exactly, on random pairs and on pairs inside the lobe.
    #[test]
    fn eval_is_reciprocal() {
        let mut rng = RandomStream::new(21, &[]);
        for n in [0.0, 1.0, 37.0, 1e3, 1e5] {
            let b = ModifiedPhong::new(Rgb::new(0.2, 0.5, 0.1), Rgb::new(0.7, 0.3, 0.4), n).unwrap();
            for _ in 0..5_000 {
                let up = |v: Vec3| Vec3::new(v.x, v.y, v.z.abs());
                let wi = up(warp::square_to_uniform_sphere(rng.next_2d()));
                let wo = match b.sample(wi, rng.next_f32(), rng.next_2d()) {
                    Some(s) if rng.next_f32() < 0.5 => s.wo,
                    _ => up(warp::square_to_uniform_sphere(rng.next_2d())),
                };
                assert_eq!(b.eval(wi, wo), b.eval(wo, wi), "n={n} wi={wi} wo={wo}");
            }
        }
    }

    /// (c) Directional albedo ≤ kd + ks for every exponent and incidence, and the specular
    /// lobe's albedo is exactly ks at normal incidence (the point of the (n+2)/(2π) factor).
    #[test]
    fn albedo_is_bounded_by_kd_plus_ks() {
        for n in [0.0, 1.0, 10.0, 100.0, 1e3, 1e4, 1e5] {
            let spec = phong(0.0, 1.0, n);
            let a = albedo(&spec, Vec3::Z);
            assert!((a - DVec3::ONE).abs().max_element() < 1e-4, "n={n}: normal-incidence albedo {a}");
            let b = ModifiedPhong::new(Rgb::new(0.6, 0.2, 0.0), Rgb::new(0.4, 0.3, 0.95), n).unwrap();
            let bound = (b.kd + b.ks).as_dvec3();
            for deg in [0.0, 30.0, 60.0, 85.0, 89.5] {
                let a = albedo(&b, incident(deg));
                assert!(
                    a.cmple(bound + 1e-4).all() && a.cmpge(DVec3::ZERO).all(),
                    "n={n} θi={deg}: {a} > {bound}"
                );
            }
        }
    }

    /// (d) The mean sample weight (None counting as 0) equals the numerical albedo within 5
    /// standard errors: the weights are unbiased.
    #[test]
    fn sample_weights_are_unbiased() {
        let mut rng = RandomStream::new(31, &[]);
        for (kd, ks, n) in
            [(0.0, 1.0, 10.0), (0.3, 0.6, 1.0), (0.5, 0.5, 1e3), (0.2, 0.7, 1e4), (0.1, 0.8, 0.0)]
        {
            let b = ModifiedPhong::new(Rgb::new(kd, kd * 0.5, kd), Rgb::new(ks, ks, ks * 0.3), n).unwrap();
            for deg in [0.0, 50.0, 85.0] {
                let wi = incident(deg);
                let want = albedo(&b, wi);
                let (mean, se) = mean_sample_weight(200_000, || {
                    b.sample(wi, rng.next_f32(), rng.next_2d()).map(|s| s.weight)
                });
                let err = (mean - want).abs();
                assert!(
                    err.cmple(5.0 * se + 1e-4).all(),
                    "kd={kd} ks={ks} n={n} θi={deg}: {mean} vs {want} (σ {se})"
                );
            }
        }
    }

    /// `sample` reports `pdf(wi, wo)` and weight = eval·cos/pdf, above the surface.
    #[test]
    fn sample_agrees_with_eval_and_pdf() {
        let mut rng = RandomStream::new(41, &[]);
        for n in [0.0, 3.0, 300.0, 3e4] {
            let b = ModifiedPhong::new(Rgb::new(0.3, 0.1, 0.2), Rgb::new(0.5, 0.6, 0.7), n).unwrap();
            for deg in [0.0, 45.0, 88.0] {
                let wi = incident(deg);
                for _ in 0..2_000 {
                    let Some(s) = b.sample(wi, rng.next_f32(), rng.next_2d()) else { continue };
                    assert!(s.wo.z > 0.0 && (s.wo.length() - 1.0).abs() < 1e-5);
                    assert_eq!(s.pdf, b.pdf(wi, s.wo));
                    let w = b.eval(wi, s.wo) * s.wo.z / s.pdf;
                    assert!((s.weight - w).abs().max_element() <= 1e-6 * w.max_element(), "{s:?}");
                }
            }
        }
    }

    /// With ks = 0 it is exactly Lambert; with kd = ks = 0 nothing is sampled.
    #[test]
    fn degenerate_mixes() {
        let b = ModifiedPhong::new(Rgb::new(0.2, 0.4, 0.6), Rgb::ZERO, 20.0).unwrap();
        let l = super::super::Lambert::new(b.kd).unwrap();
        let wi = incident(30.0);
        let mut rng = RandomStream::new(51, &[]);
        for _ in 0..1_000 {
            let (ul, u) = (rng.next_f32(), rng.next_2d());
            let (s, t) = (b.sample(wi, ul, u).unwrap(), l.sample(wi, u).unwrap());
            assert_eq!(s.wo, t.wo);
            assert_eq!(s.pdf, t.pdf);
            assert!((s.weight - t.weight).abs().max_element() < 1e-6);
            assert_eq!(b.eval(wi, s.wo), l.eval(wi, s.wo));
        }
        let black = phong(0.0, 0.0, 10.0);
        assert!(black.sample(wi, 0.5, Vec2::splat(0.5)).is_none());
        assert_eq!(black.pdf(wi, reflect(wi)), 0.0);
        assert_eq!(black.eval(wi, reflect(wi)), Rgb::ZERO);
    }

    /// No NaN, infinity or negative value for extreme exponents, grazing and exactly
    /// specular configurations, and directions on or below the horizon.
    #[test]
    fn extreme_configurations_stay_finite() {
        let mut rng = RandomStream::new(61, &[]);
        for n in [0.0, 1e-3, 1.0, 1e5, ModifiedPhong::MAX_EXPONENT] {
            for (kd, ks) in [(0.0, 1.0), (0.5, 0.5), (1.0, 0.0)] {
                let b = phong(kd, ks, n);
                for wi in [Vec3::Z, incident(89.99), Vec3::new(1.0, 0.0, 1e-6).normalize(), incident(45.0)] {
                    let wos = [reflect(wi), Vec3::Z, Vec3::X, -Vec3::Z, Vec3::new(0.6, 0.8, 0.0), -wi];
                    for wo in wos {
                        let (f, p) = (b.eval(wi, wo), b.pdf(wi, wo));
                        assert!(
                            f.is_finite() && f.min_element() >= 0.0 && p.is_finite() && p >= 0.0,
                            "{b:?} {wi} {wo}"
                        );
                        if wo.z <= 0.0 {
                            assert!(f == Rgb::ZERO && p == 0.0);
                        }
                    }
                    let corners =
                        [Vec2::ZERO, Vec2::ONE, Vec2::new(1.0 - f32::EPSILON, 0.0), Vec2::new(1e-30, 0.5)];
                    for u in corners.into_iter().chain((0..200).map(|_| rng.next_2d())) {
                        for ul in [0.0, 0.5, 0.999_999] {
                            if let Some(s) = b.sample(wi, ul, u) {
                                assert!(s.wo.is_finite() && s.weight.is_finite() && s.pdf.is_finite());
                                assert!(
                                    s.pdf > 0.0 && s.weight.min_element() >= 0.0 && s.wo.z > 0.0,
                                    "{s:?}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    /// (e) Parameter validation.
    #[test]
    fn new_rejects_invalid_parameters() {
        use MaterialError::*;
        let (h, z) = (Rgb::splat(0.5), Rgb::ZERO);
        assert_eq!(ModifiedPhong::new(Rgb::new(f32::NAN, 0.0, 0.0), z, 1.0), Err(NotFinite("kd")));
        assert_eq!(ModifiedPhong::new(z, Rgb::splat(f32::INFINITY), 1.0), Err(NotFinite("ks")));
        assert_eq!(ModifiedPhong::new(h, z, f32::NAN), Err(NotFinite("exponent")));
        assert_eq!(ModifiedPhong::new(h, z, f32::INFINITY), Err(NotFinite("exponent")));
        assert_eq!(ModifiedPhong::new(Rgb::new(0.1, -0.1, 0.1), z, 1.0), Err(Negative("kd")));
        assert_eq!(ModifiedPhong::new(z, Rgb::new(0.1, 0.1, -1e-9), 1.0), Err(Negative("ks")));
        assert_eq!(ModifiedPhong::new(h, h, -1.0), Err(Negative("exponent")));
        assert_eq!(
            ModifiedPhong::new(h, h, 2e6),
            Err(TooLarge { name: "exponent", value: 2e6, max: ModifiedPhong::MAX_EXPONENT })
        );
        let (kd, ks) = (Rgb::new(0.5, 0.2, 0.9), Rgb::new(0.5, 0.2, 0.2));
        assert_eq!(ModifiedPhong::new(kd, ks, 1.0), Err(CreatesEnergy(kd + ks)));
        // Boundaries are accepted.
        assert!(ModifiedPhong::new(h, h, 0.0).is_ok());
        assert!(ModifiedPhong::new(z, Rgb::ONE, ModifiedPhong::MAX_EXPONENT).is_ok());
        assert!(ModifiedPhong::new(z, z, 5.0).is_ok());
    }
}
