//! Conductors (metals and mirrors): Mitsuba's `conductor` and `roughconductor`.
//!
//! * [`SmoothConductor`]: an ideal mirror. The reflected direction is reflect(wi) =
//!   (−wi.x, −wi.y, wi.z) with weight R·F(cos θ_i): `specular_reflectance` R times the Fresnel
//!   reflectance of a conductor of complex index η + iκ ([`fresnel::conductor`]), or 1 for
//!   Mitsuba's default `material="none"` (a perfect mirror). A Dirac delta: `eval`/`pdf` are 0,
//!   the tracer never stores its vertices.
//! * [`RoughConductor`]: the GGX (Trowbridge–Reitz) microfacet BRDF of Walter et al. 2007 with
//!   the height-correlated Smith masking-shadowing G₂ (Heitz 2014),
//!
//!   ```text
//!   f(wi, wo) = R · F(wi·h) · D(h) · G₂(wi, wo) / (4 cos θ_i cos θ_o),   h = (wi + wo)/|wi + wo|
//!   ```
//!
//!   sampled by reflecting wi about a visible normal (Heitz 2018, [`warp`]): pdf(wo) =
//!   D_wi(h)/(4 wo·h), weight = R·F·G₂/G₁(wi) ≤ R. Symmetric in wi and wo, hence reciprocal; it
//!   loses the energy of multiple scattering between microfacets (as Mitsuba's does), more at
//!   grazing angles and high roughness.
//!
//! Both are one-sided, as in Mitsuba (black from behind unless wrapped in `twosided`).

use super::{BsdfSample, MaterialError, check_alpha, check_unit_colour, fresnel};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::warp;

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

/// GGX microfacet conductor (isotropic roughness α).
#[derive(Clone, Debug, PartialEq)]
pub struct RoughConductor {
    /// GGX roughness α in (0, [`super::MAX_ALPHA`]].
    pub alpha: f32,
    /// Multiplier of the reflectance, each channel in [0, 1].
    pub specular_reflectance: Rgb,
    /// Complex index; `None` = F = 1.
    pub ior: ConductorIor,
}

impl RoughConductor {
    /// Validated constructor (see [`SmoothConductor::new`]; α in (0, 1]).
    pub fn new(alpha: f32, specular_reflectance: Rgb, ior: ConductorIor) -> Result<Self, MaterialError> {
        check_alpha(alpha)?;
        check_unit_colour("specular_reflectance", specular_reflectance)?;
        check_ior(&ior)?;
        Ok(RoughConductor { alpha, specular_reflectance, ior })
    }

    /// f(wi → wo); zero unless both directions are above the surface.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Rgb::ZERO;
        }
        let Some(h) = (wi + wo).try_normalize() else { return Rgb::ZERO };
        let a = self.alpha;
        let g2 = 1.0 / (1.0 + warp::ggx_lambda(wi, a) + warp::ggx_lambda(wo, a));
        let v = warp::ggx_d(h, a) * g2 / (4.0 * wi.z * wo.z);
        self.specular_reflectance * fresnel_of(&self.ior, wi.dot(h)) * v
    }

    /// D_wi(h)/(4 wo·h) above the surface, zero elsewhere.
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
        warp::ggx_visible_normal_pdf(wi, h, self.alpha) / (4.0 * oh)
    }

    /// Reflects `wi` about a GGX visible normal; weight R·F·G₂/G₁(wi). `None` below the surface.
    #[inline]
    pub fn sample(&self, wi: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wi.z <= 0.0 {
            return None;
        }
        let m = warp::square_to_ggx_visible_normal(wi, self.alpha, u);
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
        let (li, lo) = (warp::ggx_lambda(wi, self.alpha), warp::ggx_lambda(wo, self.alpha));
        let weight = self.specular_reflectance * fresnel_of(&self.ior, im) * ((1.0 + li) / (1.0 + li + lo));
        weight.is_finite().then_some(BsdfSample { wo, weight, pdf, delta: false })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{Chi2Test, SphereGrid, directional_albedo, incident, pilot, reflect};
    use crate::sampling::RandomStream;

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

    /// (a) χ² of visible-normal sampling against the pdf.
    #[test]
    fn chi2_rough_conductor() {
        for (i, (alpha, deg)) in
            [(0.05, 0.0), (0.05, 70.0), (0.3, 45.0), (0.3, 85.0), (1.0, 30.0), (1.0, 88.0)]
                .into_iter()
                .enumerate()
        {
            let b = RoughConductor::new(alpha, Rgb::ONE, gold()).unwrap();
            let wi = incident(deg);
            Chi2Test::new(reflect(wi), 700 + i as u64)
                .run(|_, u| b.sample(wi, u).map(|s| (s.wo, s.pdf)), |wo| b.pdf(wi, wo))
                .assert_ok(&format!("rough conductor α={alpha} θi={deg}°"));
        }
    }

    /// (b) Reciprocity, exactly up to rounding.
    #[test]
    fn rough_conductor_is_reciprocal() {
        let mut rng = RandomStream::new(71, &[]);
        for alpha in [0.01, 0.2, 1.0] {
            let b = RoughConductor::new(alpha, Rgb::new(0.9, 0.8, 0.7), None).unwrap();
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
                    "α={alpha} {wi} {wo}: {f} {g}"
                );
            }
        }
    }

    /// (c, d) White furnace: the mean weight equals the quadrature albedo within 5σ, and both
    /// are ≤ 1 (F = 1, R = 1: what is missing is the multiple scattering the model ignores).
    #[test]
    fn rough_conductor_energy() {
        let mut rng = RandomStream::new(81, &[]);
        for alpha in [0.05, 0.3, 1.0] {
            let b = RoughConductor::new(alpha, Rgb::ONE, None).unwrap();
            for deg in [0.0, 60.0, 85.0] {
                let wi = incident(deg);
                let dirs = pilot(|_, u| b.sample(wi, u).map(|s| (s.wo, s.pdf)), 20_000, 3);
                let grid = SphereGrid::adapted(reflect(wi), &dirs, 16, 16);
                let want = directional_albedo(&grid, |wo| b.eval(wi, wo)).x;
                let m = 200_000;
                let (mut sum, mut sum2) = (0.0f64, 0.0f64);
                for _ in 0..m {
                    if let Some(s) = b.sample(wi, rng.next_2d()) {
                        let w = s.weight.x as f64;
                        assert!(w <= 1.0 + 1e-5);
                        sum += w;
                        sum2 += w * w;
                    }
                }
                let mean = sum / m as f64;
                let se = ((sum2 / m as f64 - mean * mean).max(0.0) / m as f64).sqrt();
                assert!(want <= 1.0 + 1e-4 && mean <= 1.0, "α={alpha} θ={deg}: {want} {mean}");
                assert!((mean - want).abs() <= 5.0 * se + 1e-4, "α={alpha} θ={deg}: {mean} vs {want} ± {se}");
                if alpha <= 0.05 && deg == 0.0 {
                    assert!(mean > 0.99, "a smooth-ish metal at normal incidence keeps ~all energy: {mean}");
                }
            }
        }
    }

    #[test]
    fn rough_conductor_sample_agrees_with_eval_and_pdf() {
        let mut rng = RandomStream::new(91, &[]);
        let b = RoughConductor::new(0.2, Rgb::ONE, gold()).unwrap();
        for deg in [0.0, 45.0, 88.0] {
            let wi = incident(deg);
            for _ in 0..2_000 {
                let Some(s) = b.sample(wi, rng.next_2d()) else { continue };
                let w = b.eval(wi, s.wo) * s.wo.z / s.pdf;
                assert!((s.weight - w).abs().max_element() <= 1e-3 * w.max_element(), "{s:?} {w}");
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
    }
}
