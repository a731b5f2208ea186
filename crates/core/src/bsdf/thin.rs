//! A thin dielectric sheet, Mitsuba 3's `thindielectric` (a window pane, a soap film): two
//! parallel smooth interfaces of relative index η so close together that light leaves where it
//! entered. Light is reflected (mirror direction) with R = r·2/(1 + r), r = F(|cos θ_i|, η) —
//! the sum r + t²r + t²r³ + … over the internal reflections — and otherwise passes straight
//! through (wo = −wi, no refraction: the two refractions cancel) with T = 1 − R. Both lobes are
//! Dirac deltas, on either face (the sheet has no inside: no absorption, no medium). R and T are
//! scaled by `specular_reflectance` and `specular_transmittance`; flux is conserved when both
//! are 1. Transmission does not bend, so no η² appears in either transport mode.

use super::{BsdfSample, MaterialError, check_unit_colour, fresnel};
use crate::math::{Rgb, Vec3};

/// A thin dielectric sheet (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ThinDielectric {
    /// Relative index int_ior / ext_ior of the sheet's material.
    pub eta: f32,
    /// Scale of the reflected part.
    pub specular_reflectance: Rgb,
    /// Scale of the transmitted part.
    pub specular_transmittance: Rgb,
}

impl ThinDielectric {
    /// A thin sheet; refuses indices ≤ 0 or non-finite, colours outside [0, 1].
    pub fn new(
        int_ior: f32,
        ext_ior: f32,
        specular_reflectance: Rgb,
        specular_transmittance: Rgb,
    ) -> Result<Self, MaterialError> {
        for (name, v) in [("int_ior", int_ior), ("ext_ior", ext_ior)] {
            if !v.is_finite() {
                return Err(MaterialError::NotFinite(name));
            }
            if v <= 0.0 {
                return Err(MaterialError::NotPositive(name));
            }
        }
        check_unit_colour("specular_reflectance", specular_reflectance)?;
        check_unit_colour("specular_transmittance", specular_transmittance)?;
        Ok(ThinDielectric { eta: int_ior / ext_ior, specular_reflectance, specular_transmittance })
    }

    /// R for light arriving at cos θ = `cos_i` (either face).
    pub fn reflectance(&self, cos_i: f32) -> f32 {
        let r = fresnel::dielectric(cos_i.abs(), self.eta).0;
        r * 2.0 / (1.0 + r)
    }

    /// T = (1 − R)·`specular_transmittance` for light arriving at cos θ = `cos_i` (either face):
    /// the straight-through lobe's weight, its probability 1 − R in [`ThinDielectric::sample`]
    /// times that sample's weight — with R's sum over the internal reflections, what a shadow
    /// ray crossing the sheet carries ([`crate::scene::Scene::shadow_transmittance`]).
    #[inline]
    pub fn transmittance(&self, cos_i: f32) -> Rgb {
        self.specular_transmittance * (1.0 - self.reflectance(cos_i))
    }

    /// The probability with which [`ThinDielectric::sample`] given `wi` picks the lobe leading
    /// to `wo`: R for the reflection (same side), 1 − R for the transmission.
    #[inline]
    pub fn lobe_probability(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z == 0.0 || !wi.is_finite() {
            return 0.0;
        }
        let r = self.reflectance(wi.z);
        if wi.z * wo.z > 0.0 { r } else { 1.0 - r }
    }

    /// Reflection with probability R (weight `specular_reflectance`), else straight
    /// transmission (weight `specular_transmittance`).
    #[inline]
    pub fn sample(&self, wi: Vec3, u_lobe: f32) -> Option<BsdfSample> {
        if wi.z == 0.0 {
            return None;
        }
        let r = self.reflectance(wi.z);
        Some(if u_lobe < r {
            BsdfSample {
                wo: Vec3::new(-wi.x, -wi.y, wi.z),
                weight: self.specular_reflectance,
                pdf: r,
                delta: true,
            }
        } else {
            BsdfSample { wo: -wi, weight: self.specular_transmittance, pdf: 1.0 - r, delta: true }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::incident;
    use crate::sampling::RandomStream;

    /// The reflected fraction is the series r + t²r + t²r³ + … of a slab's two interfaces
    /// (summed here term by term), on both faces, and a white sheet loses no flux.
    #[test]
    fn reflectance_sums_the_internal_reflections_and_flux_is_kept() {
        let sheet = ThinDielectric::new(1.5, 1.0, Rgb::ONE, Rgb::ONE).unwrap();
        let mut rng = RandomStream::new(950, &[]);
        for deg in [0.0, 30.0, 60.0, 85.0] {
            let wi = incident(deg);
            let r = fresnel::dielectric(wi.z, 1.5).0 as f64;
            let t = 1.0 - r;
            let series = r + (0..200).map(|k| t * t * r.powi(2 * k + 1)).sum::<f64>();
            assert!((sheet.reflectance(wi.z) as f64 - series).abs() < 1e-6, "{deg}");
            assert_eq!(sheet.reflectance(-wi.z), sheet.reflectance(wi.z));
            let n = 100_000;
            let (mut reflected, mut flux) = (0usize, 0.0f64);
            for _ in 0..n {
                let s = sheet.sample(wi, rng.next_f32()).unwrap();
                assert!(s.delta);
                if s.wo.z > 0.0 {
                    reflected += 1;
                    assert!((s.wo - Vec3::new(-wi.x, -wi.y, wi.z)).length() < 1e-6);
                } else {
                    assert_eq!(s.wo, -wi);
                }
                flux += s.weight.x as f64;
            }
            assert_eq!(flux, n as f64, "white sheet: every weight 1");
            let f = reflected as f64 / n as f64;
            let se = (series * (1.0 - series) / n as f64).sqrt();
            assert!((f - series).abs() < 5.0 * se + 1e-9, "{deg}: {f} vs {series}");
        }
        let tinted = ThinDielectric::new(1.5, 1.0, Rgb::splat(0.5), Rgb::new(1.0, 0.5, 0.0)).unwrap();
        let s = tinted.sample(Vec3::Z, 0.99).unwrap();
        assert_eq!((s.wo, s.weight), (-Vec3::Z, Rgb::new(1.0, 0.5, 0.0)));
        assert!(tinted.sample(Vec3::X, 0.5).is_none());
    }

    /// The straight-through weight is the transmission lobe's probability times its sample
    /// weight (so 1 − R of the series above for a white sheet), the same on both faces, per
    /// channel, and 0 at grazing incidence.
    #[test]
    fn transmittance_is_the_straight_lobe_weight() {
        let tinted = ThinDielectric::new(1.52, 1.0, Rgb::ONE, Rgb::new(1.0, 0.5, 0.0)).unwrap();
        for deg in [0.0, 30.0, 60.0, 85.0] {
            let wi = incident(deg);
            let s = tinted.sample(wi, 1.0 - 1e-7).unwrap();
            assert_eq!(s.wo, -wi);
            let t = tinted.transmittance(wi.z);
            assert_eq!(t, s.weight * tinted.lobe_probability(wi, -wi), "{deg}");
            assert_eq!(tinted.transmittance(-wi.z), t);
            let r = fresnel::dielectric(wi.z, 1.52).0 as f64;
            assert!((t.x as f64 - (1.0 - r) / (1.0 + r)).abs() < 1e-6, "{deg}: {t:?}");
            assert_eq!(t.z, 0.0);
        }
        assert_eq!(tinted.transmittance(0.0), Rgb::ZERO);
    }

    #[test]
    fn parameters_are_validated() {
        use MaterialError::*;
        assert_eq!(ThinDielectric::new(0.0, 1.0, Rgb::ONE, Rgb::ONE), Err(NotPositive("int_ior")));
        assert_eq!(ThinDielectric::new(1.5, f32::NAN, Rgb::ONE, Rgb::ONE), Err(NotFinite("ext_ior")));
        assert_eq!(
            ThinDielectric::new(1.5, 1.0, Rgb::splat(2.0), Rgb::ONE),
            Err(AboveOne("specular_reflectance"))
        );
    }
}
