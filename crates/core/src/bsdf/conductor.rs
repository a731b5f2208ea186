//! Conductors (metals and mirrors): Mitsuba's `conductor` and `roughconductor`.
//!
//! * [`SmoothConductor`]: an ideal mirror. The reflected direction is reflect(wi) =
//!   (−wi.x, −wi.y, wi.z) with weight R·F(cos θ_i): `specular_reflectance` R times the Fresnel
//!   reflectance of a conductor of complex index η + iκ ([`fresnel::conductor`]), or 1 for
//!   Mitsuba's default `material="none"` (a perfect mirror). A Dirac delta: `eval`/`pdf` are 0,
//!   the tracer never stores its vertices.
//! * [`RoughConductor`]: the microfacet BRDF of Walter et al. 2007 with a GGX or Beckmann
//!   distribution D, isotropic or anisotropic ([`Microfacet`]), and the height-correlated Smith
//!   masking-shadowing G₂ (Heitz 2014),
//!
//!   ```text
//!   f(wi, wo) = R · F(wi·h) · D(h) · G₂(wi, wo) / (4 cos θ_i cos θ_o),   h = (wi + wo)/|wi + wo|
//!   ```
//!
//!   sampled by reflecting wi about a sampled normal m (GGX: visible normals, Beckmann: D·cos;
//!   see [`microfacet`](crate::sampling::microfacet)): pdf(wo) = p_m(h)/(4 wo·h), weight =
//!   R·F·D·G₂·(wi·m)/(cos θ_i·p_m(m)) (= R·F·G₂/G₁(wi) ≤ R for GGX). Symmetric in wi and wo,
//!   hence reciprocal; it loses the energy of multiple scattering between microfacets (as
//!   Mitsuba's does), more at grazing angles and high roughness.
//!
//! Both are one-sided, as in Mitsuba (black from behind unless wrapped in `twosided`).

use super::{BsdfSample, MaterialError, check_microfacet, check_unit_colour, fresnel};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::microfacet::Microfacet;

/// Complex index of refraction η + iκ of a conductor relative to the outside medium, per
/// channel; `None` for a perfect mirror (F = 1).
pub type ConductorIor = Option<(Rgb, Rgb)>;

fn check_ior(ior: &ConductorIor) -> Result<(), MaterialError> {
    if let Some((eta, k)) = ior {
        for (name, c) in [("eta", eta), ("k", k)] {
            if !c.is_finite() {
                return Err(MaterialError::NotFinite(name));
            }
            if c.min_element() < 0.0 {
                return Err(MaterialError::Negative(name));
            }
        }
    }
    Ok(())
}

#[inline]
fn fresnel_of(ior: &ConductorIor, cos_i: f32) -> Rgb {
    match ior {
        Some((eta, k)) => fresnel::conductor(cos_i, *eta, *k),
        None => Rgb::ONE,
    }
}

/// Ideal mirror with optional conductor Fresnel term.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothConductor {
    /// Multiplier of the reflectance (Mitsuba's `specular_reflectance`), each channel in [0, 1].
    pub specular_reflectance: Rgb,
    /// Complex index; `None` = perfect mirror.
    pub ior: ConductorIor,
}

impl SmoothConductor {
    /// Validated constructor: `specular_reflectance` in [0, 1], `eta`, `k` finite and ≥ 0.
    pub fn new(specular_reflectance: Rgb, ior: ConductorIor) -> Result<Self, MaterialError> {
        check_unit_colour("specular_reflectance", specular_reflectance)?;
        check_ior(&ior)?;
        Ok(SmoothConductor { specular_reflectance, ior })
    }

    /// The mirror direction, weight R·F, `pdf` 1 (the only lobe), `delta`. `None` from behind.
    #[inline]
    pub fn sample(&self, wi: Vec3) -> Option<BsdfSample> {
        if wi.z <= 0.0 {
            return None;
        }
        let weight = self.specular_reflectance * fresnel_of(&self.ior, wi.z);
        Some(BsdfSample { wo: Vec3::new(-wi.x, -wi.y, wi.z), weight, pdf: 1.0, delta: true })
    }
}

/// Microfacet conductor.
#[derive(Clone, Debug, PartialEq)]
pub struct RoughConductor {
    /// Normal distribution; each α in (0, [`super::MAX_ALPHA`]].
    pub microfacet: Microfacet,
    /// Multiplier of the reflectance, each channel in [0, 1].
    pub specular_reflectance: Rgb,
    /// Complex index; `None` = F = 1.
    pub ior: ConductorIor,
}

impl RoughConductor {
    /// Validated constructor of an isotropic GGX conductor (see [`Self::with_microfacet`]).
    pub fn new(alpha: f32, specular_reflectance: Rgb, ior: ConductorIor) -> Result<Self, MaterialError> {
        Self::with_microfacet(Microfacet::ggx(alpha), specular_reflectance, ior)
    }

    /// Validated constructor (see [`SmoothConductor::new`]; each α in (0, 1]).
    pub fn with_microfacet(
        microfacet: Microfacet,
        specular_reflectance: Rgb,
        ior: ConductorIor,
    ) -> Result<Self, MaterialError> {
        check_microfacet(&microfacet)?;
        check_unit_colour("specular_reflectance", specular_reflectance)?;
        check_ior(&ior)?;
        Ok(RoughConductor { microfacet, specular_reflectance, ior })
    }

    /// f(wi → wo); zero unless both directions are above the surface.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Rgb::ZERO;
        }
        let Some(h) = (wi + wo).try_normalize() else { return Rgb::ZERO };
        let mf = &self.microfacet;
        let v = mf.d(h) * mf.g2(wi, wo) / (4.0 * wi.z * wo.z);
        self.specular_reflectance * fresnel_of(&self.ior, wi.dot(h)) * v
    }

    /// p_m(h)/(4 wo·h) above the surface (p_m the density of the sampled normal), zero elsewhere.
    #[inline]
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let Some(h) = (wi + wo).try_normalize() else { return 0.0 };
        let oh = wo.dot(h);
        if oh <= 0.0 {
            return 0.0;
        }
        self.microfacet.normal_pdf(wi, h) / (4.0 * oh)
    }

    /// Reflects `wi` about a sampled microfacet normal (module docs). `None` below the surface or
    /// for a normal facing away from `wi`.
    #[inline]
    pub fn sample(&self, wi: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wi.z <= 0.0 {
            return None;
        }
        let m = self.microfacet.sample_normal(wi, u);
        let im = wi.dot(m);
        if im <= 0.0 {
            return None;
        }
        let wo = (2.0 * im * m - wi).normalize();
        if wo.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wi, wo);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight =
            self.specular_reflectance * fresnel_of(&self.ior, im) * self.microfacet.sample_weight(wi, wo, m);
        weight.is_finite().then_some(BsdfSample { wo, weight, pdf, delta: false })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{
        Chi2Test, SphereGrid, directional_albedo, incident, mean_sample_weight, pilot, reflect,
    };
    use crate::sampling::microfacet::Distribution;
    use crate::sampling::{RandomStream, warp};
    use rayon::prelude::*;

    fn gold() -> ConductorIor {
        Some((Rgb::new(0.143, 0.374, 1.442), Rgb::new(3.983, 2.385, 1.603)))
    }

    #[test]
    fn mirror_reflects_with_fresnel() {
        let m = SmoothConductor::new(Rgb::new(1.0, 0.5, 0.25), None).unwrap();
        let wi = incident(40.0);
        let s = m.sample(wi).unwrap();
        assert!(s.delta && s.pdf == 1.0 && (s.wo - reflect(wi)).length() < 1e-6);
        assert_eq!(s.weight, Rgb::new(1.0, 0.5, 0.25));
        assert!(m.sample(-wi).is_none(), "one-sided");
        let g = SmoothConductor::new(Rgb::ONE, gold()).unwrap();
        let s = g.sample(Vec3::Z).unwrap();
        let want = fresnel::conductor(1.0, gold().unwrap().0, gold().unwrap().1);
        assert_eq!(s.weight, want);
        assert!(want.x > 0.9 && want.z < 0.5, "gold is yellow: {want}");
    }

    fn conductor(mf: Microfacet, ior: ConductorIor) -> RoughConductor {
        RoughConductor::with_microfacet(mf, Rgb::ONE, ior).unwrap()
    }

    /// The distributions the energy, reciprocity and weight tests sweep.
    fn distributions(alpha: f32) -> [Microfacet; 4] {
        [
            Microfacet::ggx(alpha),
            Microfacet::beckmann(alpha),
            Microfacet::anisotropic(Distribution::Ggx, alpha, 0.3 * alpha),
            Microfacet::anisotropic(Distribution::Beckmann, 0.3 * alpha, alpha),
        ]
    }

    /// (a) χ² of the sampling (GGX visible normals, Beckmann D·cos) against the pdf.
    #[test]
    fn chi2_rough_conductor() {
        use Distribution::*;
        let cases = [
            (Microfacet::ggx(0.05), 0.0),
            (Microfacet::ggx(0.05), 70.0),
            (Microfacet::ggx(0.3), 45.0),
            (Microfacet::ggx(0.3), 85.0),
            (Microfacet::ggx(1.0), 30.0),
            (Microfacet::ggx(1.0), 88.0),
            (Microfacet::beckmann(0.05), 0.0),
            (Microfacet::beckmann(0.05), 70.0),
            (Microfacet::beckmann(0.3), 45.0),
            (Microfacet::beckmann(0.3), 85.0),
            (Microfacet::beckmann(1.0), 30.0),
            (Microfacet::beckmann(1.0), 88.0),
            (Microfacet::anisotropic(Ggx, 0.05, 0.5), 60.0),
            (Microfacet::anisotropic(Ggx, 0.6, 0.1), 80.0),
            (Microfacet::anisotropic(Beckmann, 0.05, 0.5), 60.0),
            (Microfacet::anisotropic(Beckmann, 0.6, 0.1), 80.0),
        ];
        // Independent runs (each seeded by its case), in parallel.
        cases.into_par_iter().enumerate().for_each(|(i, (mf, deg))| {
            let b = conductor(mf, gold());
            // `incident` has azimuth 0.3 rad: the plane of incidence is off both anisotropy axes.
            let wi = incident(deg);
            Chi2Test::new(reflect(wi), 700 + i as u64)
                .run(|_, u| b.sample(wi, u).map(|s| (s.wo, s.pdf)), |wo| b.pdf(wi, wo))
                .assert_ok(&format!("rough conductor {mf:?} θi={deg}°"));
        });
    }

    /// (b) Reciprocity, exactly up to rounding.
    #[test]
    fn rough_conductor_is_reciprocal() {
        let mut rng = RandomStream::new(71, &[]);
        for alpha in [0.01, 0.2, 1.0] {
            for mf in distributions(alpha) {
                let b = RoughConductor::with_microfacet(mf, Rgb::new(0.9, 0.8, 0.7), None).unwrap();
                for _ in 0..5_000 {
                    let up = |v: Vec3| Vec3::new(v.x, v.y, v.z.abs());
                    let wi = up(warp::square_to_uniform_sphere(rng.next_2d()));
                    let wo = match b.sample(wi, rng.next_2d()) {
                        Some(s) if rng.next_f32() < 0.5 => s.wo,
                        _ => up(warp::square_to_uniform_sphere(rng.next_2d())),
                    };
                    let (f, g) = (b.eval(wi, wo), b.eval(wo, wi));
                    assert!(
                        (f - g).abs().max_element() <= 1e-5 * f.max_element(),
                        "{mf:?} {wi} {wo}: {f} {g}"
                    );
                }
            }
        }
    }

    /// (c, d) White furnace: the mean weight equals the quadrature albedo within 5σ, and both
    /// are ≤ 1 (F = 1, R = 1: what is missing is the multiple scattering the model ignores).
    /// GGX's visible-normal weights are ≤ 1 one by one; Beckmann's D·cos sampling only bounds
    /// the mean.
    #[test]
    fn rough_conductor_energy() {
        let mut rng = RandomStream::new(81, &[]);
        // Anisotropic only at α = 0.3 (its quadrature is the slow part of this test).
        let isotropic = |a| [Microfacet::ggx(a), Microfacet::beckmann(a)];
        let mfs = [isotropic(0.05).as_slice(), &distributions(0.3), &isotropic(1.0)].concat();
        for (mf, alpha) in mfs.into_iter().map(|m| (m, m.alpha_u)) {
            let b = conductor(mf, None);
            for deg in [0.0, 60.0, 85.0] {
                let wi = incident(deg);
                let dirs = pilot(|_, u| b.sample(wi, u).map(|s| (s.wo, s.pdf)), 20_000, 3);
                let grid = SphereGrid::adapted(reflect(wi), &dirs, 16, 16);
                let want = directional_albedo(&grid, |wo| b.eval(wi, wo)).x;
                let (mean, se) = mean_sample_weight(100_000, || {
                    b.sample(wi, rng.next_2d()).map(|s| {
                        assert!(mf.distribution == Distribution::Beckmann || s.weight.x <= 1.0 + 1e-5);
                        s.weight
                    })
                });
                let (mean, se) = (mean.x, se.x);
                let ctx = format!("{mf:?} θ={deg}");
                assert!(want <= 1.0 + 1e-4 && mean <= 1.0 + 5.0 * se, "{ctx}: {want} {mean}");
                assert!((mean - want).abs() <= 5.0 * se + 1e-4, "{ctx}: {mean} vs {want} ± {se}");
                if alpha <= 0.05 && deg == 0.0 {
                    assert!(mean > 0.99, "a smooth-ish metal at normal incidence keeps ~all energy: {mean}");
                }
            }
        }
    }

    #[test]
    fn rough_conductor_sample_agrees_with_eval_and_pdf() {
        let mut rng = RandomStream::new(91, &[]);
        for mf in distributions(0.2) {
            let b = conductor(mf, gold());
            for deg in [0.0, 45.0, 88.0] {
                let wi = incident(deg);
                for _ in 0..2_000 {
                    let Some(s) = b.sample(wi, rng.next_2d()) else { continue };
                    let w = b.eval(wi, s.wo) * s.wo.z / s.pdf;
                    assert!((s.weight - w).abs().max_element() <= 1e-3 * w.max_element(), "{mf:?} {s:?} {w}");
                }
            }
        }
    }

    #[test]
    fn conductor_parameters_are_validated() {
        use MaterialError::*;
        assert_eq!(SmoothConductor::new(Rgb::splat(1.1), None), Err(AboveOne("specular_reflectance")));
        assert_eq!(SmoothConductor::new(Rgb::splat(-0.1), None), Err(Negative("specular_reflectance")));
        assert_eq!(
            SmoothConductor::new(Rgb::ONE, Some((Rgb::splat(f32::NAN), Rgb::ONE))),
            Err(NotFinite("eta"))
        );
        assert_eq!(SmoothConductor::new(Rgb::ONE, Some((Rgb::ONE, -Rgb::ONE))), Err(Negative("k")));
        assert_eq!(RoughConductor::new(0.0, Rgb::ONE, None), Err(NotPositive("alpha")));
        assert_eq!(RoughConductor::new(f32::NAN, Rgb::ONE, None), Err(NotFinite("alpha")));
        assert_eq!(
            RoughConductor::new(1.5, Rgb::ONE, None),
            Err(TooLarge { name: "alpha", value: 1.5, max: 1.0 })
        );
        assert!(RoughConductor::new(1.0, Rgb::ONE, gold()).is_ok());
        let aniso = |u, v| {
            RoughConductor::with_microfacet(
                Microfacet::anisotropic(Distribution::Beckmann, u, v),
                Rgb::ONE,
                None,
            )
        };
        assert_eq!(aniso(0.1, 0.0), Err(NotPositive("alpha_v")));
        assert_eq!(aniso(1.2, 0.1), Err(TooLarge { name: "alpha_u", value: 1.2, max: 1.0 }));
        assert!(aniso(0.1, 0.9).is_ok());
    }
}
