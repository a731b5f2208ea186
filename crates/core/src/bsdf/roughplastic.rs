//! Rough plastic, Mitsuba 3's `roughplastic`: the rough counterpart of [`super::Plastic`] — a
//! diffuse base under a dielectric coating of relative index η = int_ior/ext_ior whose surface
//! is a microfacet distribution (Beckmann or GGX, isotropic α), exactly as Mitsuba models it:
//!
//! ```text
//! f(wi → wo) = s·F(wi·h)·D(h)·G₁(wi)·G₁(wo) / (4 cos θ_i cos θ_o)                (specular)
//!            + ρ'·t(cos θ_i)·t(cos θ_o)/(π η²)                                   (diffuse)
//! ρ' = ρ/(1 − R_int) (default), or ρ/(1 − ρ·R_int) with `nonlinear`
//! ```
//!
//! with h the half vector, G₁ Mitsuba's separable Smith masking
//! ([`Microfacet::g1_mitsuba`]: Walter's rational fit for Beckmann), t(μ) the coating's rough
//! transmittance for light arriving at cos θ = μ — tabulated at 64 equally spaced μ in [0, 1]
//! and interpolated linearly, as Mitsuba — and R_int the coating's diffuse reflectance seen
//! from inside (a cosine-weighted mean of the rough reflectance at index 1/η). Both come from
//! the same quadratures Mitsuba runs (Gauss–Legendre, 32² nodes for η > 1 and 128² for η < 1,
//! over the visible normals with Mitsuba's mapping, [`Microfacet::sample_visible`]):
//! t(μ) = E_m[(1 − F(wi·m))·G₁(wt)] over refracted wt, and R_int = 2·mean_μ(μ·E_m[F·G₁(wr)])
//! over reflected wr.
//!
//! f is symmetric in wi and wo (reciprocal, the same in both transport modes). It is one-sided
//! (black from behind), like Mitsuba's.
//!
//! Sampling as Mitsuba: the specular lobe with probability p_s = (1 − t_i)·w / ((1 − t_i)·w +
//! t_i·(1 − w)), w = s̄/(ρ̄ + s̄) the specular sampling weight (channel means of the colours the
//! BSDF was built with: a texel changes ρ, not w), else a cosine-weighted direction. The
//! specular lobe reflects wi about a visible normal ([`Microfacet::sample_visible`], density
//! D·G₁(wi)/(4 cos θ_i) in wo) or, with `sample_visible` off, a normal of density D·cos θ_m.
//! `pdf` is the mixture p_s·p_spec + (1 − p_s)·cos θ_o/π and the weight f·cos θ_o/pdf.
//!
//! One deviation, for unbiasedness: Mitsuba's pdf of visible-normal sampling uses the same
//! G₁ fit as its eval, whereas its Beckmann sampler draws from the exact visible
//! distribution; here the density is the sampler's (exact Λ, [`Microfacet::visible_pdf`]), so
//! for Beckmann `pdf` differs from Mitsuba's by the fit's error (< 0.35 % of the specular
//! part). eval is Mitsuba's.

use super::{BsdfSample, MaterialError, check_microfacet, check_unit_colour, fresnel};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::microfacet::{Distribution, Microfacet};
use crate::sampling::warp;
use std::f32::consts::FRAC_1_PI;
use std::sync::Arc;

/// Points of the transmittance table (Mitsuba's `MI_ROUGH_TRANSMITTANCE_RES`).
const TABLE: usize = 64;

/// Rough plastic (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct RoughPlastic {
    /// The base's diffuse reflectance ρ.
    pub diffuse_reflectance: Rgb,
    /// Scale of the coating's specular reflection (1: a physical coating).
    pub specular_reflectance: Rgb,
    /// Relative index of the coating, int_ior / ext_ior.
    pub eta: f32,
    /// The coating's (isotropic) microfacet distribution.
    pub microfacet: Microfacet,
    /// Whether the specular lobe is sampled from the visible normals (Mitsuba's default).
    pub sample_visible: bool,
    /// Whether internal scattering tints (ρ/(1 − ρ·R_int)) rather than scales (ρ/(1 − R_int)).
    pub nonlinear: bool,
    /// Mitsuba's specular sampling weight s̄/(ρ̄ + s̄), fixed at construction.
    specular_weight: f32,
    /// t(μ) at μ = i/63, and R_int, the coating's diffuse reflectance from inside: shared (a
    /// texel's copy of the BSDF clones a pointer; the enum stays small).
    tables: Arc<Tables>,
    inv_eta2: f32,
}

impl RoughPlastic {
    /// A rough plastic. Refuses colours outside [0, 1], non-finite or non-positive indices,
    /// equal indices (Mitsuba's rule) and α outside (0, 1].
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        diffuse_reflectance: Rgb,
        specular_reflectance: Rgb,
        int_ior: f32,
        ext_ior: f32,
        distribution: Distribution,
        alpha: f32,
        sample_visible: bool,
        nonlinear: bool,
    ) -> Result<Self, MaterialError> {
        check_unit_colour("diffuse_reflectance", diffuse_reflectance)?;
        check_unit_colour("specular_reflectance", specular_reflectance)?;
        for (name, v) in [("int_ior", int_ior), ("ext_ior", ext_ior)] {
            super::check_positive(name, v)?;
        }
        if int_ior == ext_ior {
            return Err(MaterialError::EqualIors(int_ior));
        }
        let microfacet = Microfacet { distribution, alpha_u: alpha, alpha_v: alpha };
        check_microfacet(&microfacet)?;
        let eta = int_ior / ext_ior;
        let (d_mean, s_mean) =
            (diffuse_reflectance.element_sum() / 3.0, specular_reflectance.element_sum() / 3.0);
        let specular_weight = if d_mean + s_mean > 0.0 { s_mean / (d_mean + s_mean) } else { 0.5 };
        let tables = tables(&microfacet, eta);
        Ok(RoughPlastic {
            diffuse_reflectance,
            specular_reflectance,
            eta,
            microfacet,
            sample_visible,
            nonlinear,
            specular_weight,
            tables,
            inv_eta2: 1.0 / (eta * eta),
        })
    }

    /// R_int (module docs).
    pub fn internal_reflectance(&self) -> f32 {
        self.tables.1
    }

    /// The coating's rough transmittance t(μ) for light arriving at cos θ = `mu` ∈ [0, 1],
    /// interpolated in the table as Mitsuba does.
    #[inline]
    pub fn transmittance(&self, mu: f32) -> f32 {
        let x = mu.clamp(0.0, 1.0) * (TABLE - 1) as f32;
        let i = (x as usize).min(TABLE - 2);
        let t = &self.tables.0;
        let (a, b) = (t[i], t[i + 1]);
        a + (b - a) * (x - i as f32)
    }

    /// ρ' (module docs).
    fn base(&self) -> Rgb {
        let d = self.diffuse_reflectance;
        let r = self.tables.1;
        if self.nonlinear { d / (Rgb::ONE - d * r) } else { d / (1.0 - r) }
    }

    /// The probability of the specular lobe for light arriving with transmittance `t_i`.
    #[inline]
    fn specular_probability(&self, t_i: f32) -> f32 {
        let s = (1.0 - t_i) * self.specular_weight;
        let d = t_i * (1.0 - self.specular_weight);
        if s + d > 0.0 { s / (s + d) } else { 0.0 }
    }

    /// f(wi → wo); zero unless both directions are above the surface.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !(wi.z > 0.0 && wo.z > 0.0) {
            return Rgb::ZERO;
        }
        let mf = &self.microfacet;
        let specular = match (wi + wo).try_normalize() {
            Some(h) => {
                let f = fresnel::dielectric(wi.dot(h).max(0.0), self.eta).0;
                f * mf.d(h) * mf.g1_mitsuba(wi, h) * mf.g1_mitsuba(wo, h) / (4.0 * wi.z * wo.z)
            }
            None => 0.0,
        };
        let (t_i, t_o) = (self.transmittance(wi.z), self.transmittance(wo.z));
        self.specular_reflectance * specular + self.base() * (FRAC_1_PI * self.inv_eta2 * t_i * t_o)
    }

    /// The density of `wo` under [`Self::sample`] given `wi` (module docs).
    #[inline]
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if !(wi.z > 0.0 && wo.z > 0.0) {
            return 0.0;
        }
        let p_s = self.specular_probability(self.transmittance(wi.z));
        let specular = match (wi + wo).try_normalize() {
            Some(h) if self.sample_visible => self.microfacet.visible_pdf(wi, h) / (4.0 * wo.dot(h)),
            Some(h) => self.microfacet.d_cos_pdf(h) / (4.0 * wo.dot(h)),
            None => 0.0,
        };
        p_s * specular + (1.0 - p_s) * warp::cosine_hemisphere_pdf(wo)
    }

    /// The specular lobe if `u_lobe` < p_s (wi reflected about a sampled normal), else a
    /// cosine-weighted direction; weight f·cos θ_o/pdf with the mixture's pdf. `None` from
    /// behind or when the reflected direction falls below the surface.
    #[inline]
    pub fn sample(&self, wi: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if !(wi.z > 0.0) {
            return None;
        }
        let p_s = self.specular_probability(self.transmittance(wi.z));
        let wo = if u_lobe < p_s {
            let m = if self.sample_visible {
                self.microfacet.sample_visible(wi, u)
            } else {
                self.microfacet.sample_d_cos(u)
            };
            (2.0 * wi.dot(m) * m - wi).normalize()
        } else {
            warp::square_to_cosine_hemisphere(u)
        };
        BsdfSample::of_density(wo, self.pdf(wi, wo), || self.eval(wi, wo))
    }

    /// Upper bound of the directional albedo per channel: the specular lobe reflects at most
    /// s·(1 − t_i), the diffuse one at most ρ'·t_i/η² (as for the smooth plastic).
    pub fn max_albedo(&self) -> Rgb {
        self.specular_reflectance.max(self.base() * self.inv_eta2)
    }
}

/// The coating's tables: t(i/63) and R_int.
type Tables = ([f32; TABLE], f32);

/// [`compute_tables`], remembered for the last few (distribution, α, η): a scene's materials
/// (and the loader's copies of them) share a few coatings, and the quadratures take a fraction
/// of a second.
fn tables(mf: &Microfacet, eta: f32) -> Arc<Tables> {
    use std::sync::Mutex;
    type Key = (Distribution, u32, u32);
    static MEMO: Mutex<Vec<(Key, Arc<Tables>)>> = Mutex::new(Vec::new());
    const KEEP: usize = 16;
    let key = (mf.distribution, mf.alpha_u.to_bits(), eta.to_bits());
    let hit = |memo: &Vec<(Key, Arc<Tables>)>| memo.iter().find(|(k, _)| *k == key).map(|(_, t)| t.clone());
    if let Some(t) = MEMO.lock().ok().and_then(|m| hit(&m)) {
        return t;
    }
    let t = Arc::new(compute_tables(mf, eta));
    if let Ok(mut memo) = MEMO.lock()
        && hit(&memo).is_none()
    {
        if memo.len() == KEEP {
            memo.remove(0);
        }
        memo.push((key, t.clone()));
    }
    t
}

/// The transmittance table t(i/63) and R_int for `mf` and relative index `eta`, by Mitsuba's
/// quadratures (module docs), accumulated in f64, the 64 directions on all cores.
fn compute_tables(mf: &Microfacet, eta: f32) -> Tables {
    use rayon::prelude::*;
    let nodes = |eta: f32| gauss_legendre(if eta > 1.0 { 32 } else { 128 });
    let (outside, inside) = (nodes(eta), nodes(1.0 / eta));
    let rows: Vec<(f32, f64)> = (0..TABLE)
        .into_par_iter()
        .map(|i| {
            let mu = (i as f32 / (TABLE - 1) as f32).max(1e-6);
            let wi = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
            let t = quadrature(&outside, |u| {
                let m = mf.sample_visible(wi, u);
                let (f, cos_t) = fresnel::dielectric(wi.dot(m).max(0.0), eta);
                if f >= 1.0 {
                    return 0.0;
                }
                let wt = fresnel::refract(wi, m, eta, cos_t);
                if wt.z * wi.z >= 0.0 { 0.0 } else { mf.g1_mitsuba(wt, m) * (1.0 - f) }
            });
            let r = quadrature(&inside, |u| {
                let m = mf.sample_visible(wi, u);
                let wm = wi.dot(m);
                let wr = 2.0 * wm * m - wi;
                if wr.z <= 0.0 {
                    0.0
                } else {
                    mf.g1_mitsuba(wr, m) * fresnel::dielectric(wm.max(0.0), 1.0 / eta).0
                }
            });
            (t as f32, r * mu as f64)
        })
        .collect();
    let mut t = [0.0f32; TABLE];
    for (ti, row) in t.iter_mut().zip(&rows) {
        *ti = row.0;
    }
    // Summed in order: the same R_int on any number of threads.
    let r_sum: f64 = rows.iter().map(|r| r.1).sum();
    (t, (2.0 * r_sum / TABLE as f64) as f32)
}

/// ∫∫ g(u) du over [0, 1]² by the tensor product of the Gauss–Legendre `nodes` (on [−1, 1]).
fn quadrature(nodes: &[(f64, f64)], g: impl Fn(Vec2) -> f32) -> f64 {
    let mut sum = 0.0;
    for &(x, wx) in nodes {
        for &(y, wy) in nodes {
            let u = Vec2::new((0.5 * x + 0.5) as f32, (0.5 * y + 0.5) as f32);
            sum += g(u) as f64 * wx * wy * 0.25;
        }
    }
    sum
}

/// The `n` Gauss–Legendre nodes and weights on [−1, 1] (Newton on the Legendre recurrence).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    (p0, p1) = (p1, p2);
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-15 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::Bsdf;
    use crate::bsdf::chi2::{
        SphereGrid, assert_reciprocal_and_consistent, chi2_at_three_incidences, direction,
        directional_albedo, incident, mean_sample_weight, pilot,
    };
    use crate::sampling::RandomStream;
    use rayon::prelude::*;

    use crate::bsdf::roughplastic_mitsuba::MITSUBA;

    /// The cases of tools/mitsuba/roughplastic_values.py, in its order.
    fn mitsuba_cases() -> Vec<RoughPlastic> {
        use Distribution::*;
        let air = 1.000277;
        vec![
            RoughPlastic::new(Rgb::splat(0.5), Rgb::ONE, 1.49, air, Beckmann, 0.1, true, false).unwrap(),
            RoughPlastic::new(Rgb::new(0.8, 0.4, 0.1), Rgb::ONE, 1.49, air, Ggx, 0.3, true, true).unwrap(),
            RoughPlastic::new(Rgb::new(0.2, 0.5, 0.9), Rgb::ONE, 1.7, 1.1, Beckmann, 0.5, false, false)
                .unwrap(),
            RoughPlastic::new(Rgb::splat(0.3), Rgb::new(0.7, 0.6, 0.5), 1.9, air, Ggx, 0.08, true, false)
                .unwrap(),
        ]
    }

    /// Mitsuba's own eval (÷ cos θ_o) and pdf at fixed directions (the table of
    /// tools/mitsuba/roughplastic_values.py): eval within 10⁻⁵ (the tables are Mitsuba's
    /// quadratures; f32 rounding), pdf within 10⁻⁵ but for Beckmann's visible normals, whose
    /// density here uses the exact Λ rather than Mitsuba's fit (module docs): within 0.35 %.
    #[test]
    fn matches_mitsuba_values() {
        let cases = mitsuba_cases();
        assert_eq!(cases.len(), MITSUBA.len());
        for (b, (name, pairs)) in cases.iter().zip(MITSUBA) {
            let pdf_tol = if b.sample_visible && b.microfacet.distribution == Distribution::Beckmann {
                3.5e-3
            } else {
                1e-5
            };
            for &(i, o, f, pdf) in pairs.iter() {
                let (wi, wo) = (direction(i), direction(o));
                let (ours, our_pdf) = (b.eval(wi, wo), b.pdf(wi, wo));
                for c in 0..3 {
                    assert!(
                        (ours[c] - f[c]).abs() <= 1e-5 * f[c],
                        "{name} wi={i:?} wo={o:?} channel {c}: f = {} vs Mitsuba's {}",
                        ours[c],
                        f[c]
                    );
                }
                assert!(
                    (our_pdf - pdf).abs() <= pdf_tol * pdf,
                    "{name} wi={i:?} wo={o:?}: pdf {our_pdf} vs Mitsuba's {pdf}"
                );
                // One-sided: nothing from behind, nothing below.
                let below = Vec3::new(wo.x, wo.y, -wo.z);
                assert_eq!(
                    (b.eval(below, wi), b.eval(wi, below), b.pdf(wi, below)),
                    (Rgb::ZERO, Rgb::ZERO, 0.0)
                );
            }
        }
    }

    /// The cases the sampling, reciprocity and energy tests sweep: Mitsuba's, a rough GGX with
    /// visible sampling off and an outside denser than the inside (η < 1).
    fn cases() -> Vec<RoughPlastic> {
        let mut v = mitsuba_cases();
        v.push(
            RoughPlastic::new(Rgb::splat(0.6), Rgb::ONE, 1.5, 1.0, Distribution::Ggx, 0.7, false, false)
                .unwrap(),
        );
        v.push(
            RoughPlastic::new(Rgb::splat(0.4), Rgb::ONE, 1.0, 1.33, Distribution::Beckmann, 0.2, true, true)
                .unwrap(),
        );
        v
    }

    /// (a) χ² of the samples against `pdf` at normal, oblique and grazing incidence.
    #[test]
    fn chi2_sampling_matches_pdf() {
        let cases: Vec<Bsdf> = cases().into_iter().map(Bsdf::RoughPlastic).collect();
        chi2_at_three_incidences(&cases, 1900, "roughplastic");
    }

    /// (b) Reciprocity f(wi → wo) = f(wo → wi) (Mitsuba's model is symmetric: t and the
    /// separable G₁G₁ are), and the weights agree with eval·cos/pdf.
    #[test]
    fn reciprocal_and_consistent() {
        let cases: Vec<Bsdf> = cases().into_iter().map(Bsdf::RoughPlastic).collect();
        assert_reciprocal_and_consistent(&cases, 1901);
    }

    /// (c, d) Energy: the mean sample weight equals the quadrature of f·cos within 5σ, and the
    /// directional albedo stays ≤ 1 for a white base and coating at every incidence (the
    /// single-scattering coating loses energy, the fitted R_int may add a little: within 1 %).
    #[test]
    fn furnace() {
        let white: Vec<RoughPlastic> =
            [(Distribution::Beckmann, 0.1), (Distribution::Ggx, 0.3), (Distribution::Ggx, 1.0)]
                .into_iter()
                .flat_map(|(d, a)| {
                    [false, true]
                        .map(|nl| RoughPlastic::new(Rgb::ONE, Rgb::ONE, 1.5, 1.0, d, a, true, nl).unwrap())
                })
                .collect();
        let all: Vec<(usize, RoughPlastic)> = cases().into_iter().chain(white).enumerate().collect();
        all.into_par_iter().for_each(|(k, b)| {
            let mut rng = RandomStream::new(1902, &[k as u64]);
            for deg in [0.0, 45.0, 80.0] {
                let wi = incident(deg);
                let dirs = pilot(|ul, u| b.sample(wi, ul, u).map(|s| (s.wo, s.pdf)), 20_000, 3);
                let grid = SphereGrid::adapted(Vec3::Z, &dirs, 16, 16);
                let want = directional_albedo(&grid, |wo| b.eval(wi, wo));
                let (mean, se) = mean_sample_weight(200_000, || {
                    b.sample(wi, rng.next_f32(), rng.next_2d()).map(|s| s.weight)
                });
                for c in 0..3 {
                    assert!(
                        (mean[c] - want[c]).abs() <= 5.0 * se[c] + 1e-4,
                        "case {k} θ={deg} channel {c}: {} vs {} ± {}",
                        mean[c],
                        want[c],
                        se[c]
                    );
                    assert!(want[c] <= 1.01, "case {k} θ={deg}: albedo {}", want[c]);
                }
                println!("case {k} θ={deg}: albedo {want}");
            }
        });
    }

    #[test]
    fn parameters_are_validated() {
        use Distribution::Beckmann;
        use MaterialError::*;
        let p = |d, s, i, e, a| RoughPlastic::new(d, s, i, e, Beckmann, a, true, false);
        assert_eq!(p(Rgb::splat(1.2), Rgb::ONE, 1.5, 1.0, 0.1), Err(AboveOne("diffuse_reflectance")));
        assert_eq!(p(Rgb::ONE, Rgb::splat(-1.0), 1.5, 1.0, 0.1), Err(Negative("specular_reflectance")));
        assert_eq!(p(Rgb::ONE, Rgb::ONE, 0.0, 1.0, 0.1), Err(NotPositive("int_ior")));
        assert_eq!(p(Rgb::ONE, Rgb::ONE, 1.5, f32::NAN, 0.1), Err(NotFinite("ext_ior")));
        assert_eq!(p(Rgb::ONE, Rgb::ONE, 1.5, 1.5, 0.1), Err(EqualIors(1.5)));
        assert_eq!(p(Rgb::ONE, Rgb::ONE, 1.5, 1.0, 0.0), Err(NotPositive("alpha")));
        assert!(matches!(p(Rgb::ONE, Rgb::ONE, 1.5, 1.0, 2.0), Err(TooLarge { name: "alpha", .. })));
        let t = std::time::Instant::now();
        assert!(compute_tables(&Microfacet::beckmann(0.1), 1.37).1 > 0.0);
        println!("Beckmann tables: {:?}", t.elapsed());
        let t = std::time::Instant::now();
        assert!(compute_tables(&Microfacet::ggx(0.1), 1.37).1 > 0.0);
        println!("GGX tables: {:?}", t.elapsed());
    }
}
