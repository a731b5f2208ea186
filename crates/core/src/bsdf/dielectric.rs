//! Dielectric interfaces (glass, water): Mitsuba's `dielectric` and `roughdielectric`.
//!
//! Both are **oriented**: the local +z side (the side the geometric normal points to) is the
//! outside, of index `ext_ior`; the −z side the inside, of index `int_ior`. They accept light from
//! either side; when `wi.z < 0` everything is computed in the mirrored configuration (z negated,
//! relative index η = int/ext inverted), which is exact because the geometry is symmetric.
//!
//! * [`SmoothDielectric`]: Fresnel reflection (weight R = `specular_reflectance`) with
//!   probability F, refraction by Snell's law (weight T = `specular_transmittance`) with
//!   probability 1 − F, total internal reflection when F = 1. Dirac deltas: `eval` = `pdf` = 0;
//!   [`BsdfSample::pdf`] is the lobe's probability. In [`TransportMode::Importance`] the
//!   refraction weight is T — flux crosses the interface unchanged; in
//!   [`TransportMode::Radiance`] it is T/η² (η = index of the sampled side over the given side),
//!   the radiance compression of pbrt's `TransportMode::Radiance`. The light tracer uses the
//!   former (docs/estimator.md §4: the 1/η² scaling applies to radiance/camera paths only).
//! * [`RoughDielectric`]: Walter et al. 2007 ("Microfacet Models for Refraction through Rough
//!   Surfaces") with a GGX or Beckmann distribution, isotropic or anisotropic ([`Microfacet`]:
//!   GGX samples visible normals (Heitz 2018), Beckmann samples D·cos θ_m) and the
//!   height-correlated Smith G₂. With η = η_o/η_i relative to the side of wi:
//!
//!   ```text
//!   reflection   (wo on wi's side):  R · F(wi·h) · D(h) · G₂ / (4 |cos θ_i| |cos θ_o|),  h ∝ wi + wo
//!   transmission (other side):       T · (1 − F(wi·h)) · D(h) · G₂ · η² · |wi·h| |wo·h|
//!                                      / (|cos θ_i| |cos θ_o| (wi·h + η wo·h)²),        h ∝ −(wi + η wo)
//!   ```
//!
//!   This is the physical f(wi → wo) for light arriving from wi: the η² = (η_o/η_i)² factor makes
//!   it obey f(a→b)/η_b² = f(b→a)/η_a² (tested). `sample` picks a microfacet normal m (density
//!   p_m), reflects with probability F(wi·m), else refracts; the weight is (R or T)·D·G₂·(wi·m)/
//!   (cos θ_i·p_m) (= (R or T)·G₂/G₁(wi) for GGX) in importance mode and the transmission weight
//!   is divided by η² in radiance mode, since f(b→a) = f(a→b)·η_a²/η_b².
//!
//! # Absorption (Beer–Lambert)
//!
//! Both carry an `absorption` coefficient σ_a (RGB, 1/m, each channel finite and ≥ 0; zero by
//! default, set with `with_absorption`): the object the interface bounds is filled with a
//! purely absorbing medium, so flux travelling a distance t inside it is multiplied by
//! exp(−σ_a·t) per channel. The BSDF itself is unchanged; the light tracer applies the factor to
//! path segments inside the object (see the `trace` module docs for how it knows it is
//! inside). A BSDF's `absorption` is part of the material, so it is covered by the scene
//! fingerprint.
//!
//! See the transport-mode discussion in the [module docs of `bsdf`](super) for why the sensor's
//! connection and the tracer's weight update both call the same `eval`.

use super::{
    BsdfSample, MaterialError, TransportMode, check_microfacet, check_positive, check_unit_colour, fresnel,
};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::microfacet::Microfacet;

/// (x, y, −z): the mirror image through the surface plane.
#[inline]
fn flip(v: Vec3) -> Vec3 {
    Vec3::new(v.x, v.y, -v.z)
}

fn check_iors(int_ior: f32, ext_ior: f32) -> Result<f32, MaterialError> {
    check_positive("int_ior", int_ior)?;
    check_positive("ext_ior", ext_ior)?;
    let eta = int_ior / ext_ior;
    if !eta.is_finite() || eta <= 0.0 {
        return Err(MaterialError::NotFinite("int_ior / ext_ior"));
    }
    Ok(eta)
}

/// An absorption coefficient σ_a: finite and ≥ 0 per channel (1/m). Public so that scene
/// readers apply this one rule where they read σ_a (to point at the right element).
pub fn check_absorption(sigma_a: Rgb) -> Result<Rgb, MaterialError> {
    if !sigma_a.is_finite() {
        Err(MaterialError::NotFinite("absorption"))
    } else if sigma_a.min_element() < 0.0 {
        Err(MaterialError::Negative("absorption"))
    } else {
        Ok(sigma_a)
    }
}

/// Smooth dielectric interface.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothDielectric {
    /// Relative index int_ior / ext_ior.
    pub eta: f32,
    /// Multiplier of the reflected part, each channel in [0, 1].
    pub specular_reflectance: Rgb,
    /// Multiplier of the transmitted part, each channel in [0, 1].
    pub specular_transmittance: Rgb,
    /// Absorption coefficient σ_a of the inside (1/m, ≥ 0; module docs).
    pub absorption: Rgb,
}

impl SmoothDielectric {
    /// Validated constructor: indices finite and > 0, colours in [0, 1].
    pub fn new(
        int_ior: f32,
        ext_ior: f32,
        reflectance: Rgb,
        transmittance: Rgb,
    ) -> Result<Self, MaterialError> {
        let eta = check_iors(int_ior, ext_ior)?;
        check_unit_colour("specular_reflectance", reflectance)?;
        check_unit_colour("specular_transmittance", transmittance)?;
        Ok(SmoothDielectric {
            eta,
            specular_reflectance: reflectance,
            specular_transmittance: transmittance,
            absorption: Rgb::ZERO,
        })
    }

    /// The same interface bounding an absorbing inside of coefficient σ_a (1/m, per channel
    /// finite and ≥ 0).
    pub fn with_absorption(self, sigma_a: Rgb) -> Result<Self, MaterialError> {
        Ok(SmoothDielectric { absorption: check_absorption(sigma_a)?, ..self })
    }

    /// Reflects with probability F (`u_lobe < F`), else refracts; see the module docs for the
    /// weights. `None` only for a direction in the surface plane.
    #[inline]
    pub fn sample(&self, wi: Vec3, u_lobe: f32, mode: TransportMode) -> Option<BsdfSample> {
        if wi.z == 0.0 || !wi.is_finite() {
            return None;
        }
        let inside = wi.z < 0.0;
        let (w, eta) = if inside { (flip(wi), 1.0 / self.eta) } else { (wi, self.eta) };
        let (f, cos_t) = fresnel::dielectric(w.z, eta);
        let (wo, weight, pdf) = if u_lobe < f {
            (Vec3::new(-w.x, -w.y, w.z), self.specular_reflectance, f)
        } else {
            let wo = Vec3::new(-w.x / eta, -w.y / eta, -cos_t).normalize();
            let scale = match mode {
                TransportMode::Importance => 1.0,
                TransportMode::Radiance => 1.0 / (eta * eta),
            };
            (wo, self.specular_transmittance * scale, 1.0 - f)
        };
        let wo = if inside { flip(wo) } else { wo };
        Some(BsdfSample { wo, weight, pdf, delta: true })
    }

    /// The probability with which [`SmoothDielectric::sample`] given `wi` picks the lobe that
    /// leads to `wo` (reflection if both lie on one side, else refraction): F or 1 − F, computed
    /// exactly as `sample` computes it (`wo` is assumed to be that lobe's direction).
    #[inline]
    pub fn lobe_probability(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z == 0.0 || !wi.is_finite() {
            return 0.0;
        }
        let eta = if wi.z < 0.0 { 1.0 / self.eta } else { self.eta };
        let f = fresnel::dielectric(wi.z.abs(), eta).0;
        if wi.z * wo.z > 0.0 { f } else { 1.0 - f }
    }
}

/// Microfacet dielectric interface.
#[derive(Clone, Debug, PartialEq)]
pub struct RoughDielectric {
    /// Relative index int_ior / ext_ior (≠ 1).
    pub eta: f32,
    /// Normal distribution; each α in (0, [`super::MAX_ALPHA`]].
    pub microfacet: Microfacet,
    /// Multiplier of the reflected part, each channel in [0, 1].
    pub specular_reflectance: Rgb,
    /// Multiplier of the transmitted part, each channel in [0, 1].
    pub specular_transmittance: Rgb,
    /// Absorption coefficient σ_a of the inside (1/m, ≥ 0; module docs).
    pub absorption: Rgb,
}

/// The generalized half vector of (wi, wo) for wi.z > 0 (oriented to +z) and whether the pair is
/// a reflection; `None` if degenerate or if the configuration is impossible (a microfacet
/// facing away from either direction).
#[inline]
fn half_vector(wi: Vec3, wo: Vec3, eta: f32) -> Option<(Vec3, bool)> {
    let reflect = wo.z > 0.0;
    let h = if reflect { wi + wo } else { -(wi + eta * wo) };
    let h = h.try_normalize()?;
    let h = if h.z < 0.0 { -h } else { h };
    let (ih, oh) = (wi.dot(h), wo.dot(h));
    let ok = if reflect { ih > 0.0 && oh > 0.0 } else { ih > 0.0 && oh < 0.0 };
    ok.then_some((h, reflect))
}

impl RoughDielectric {
    /// Validated constructor of an isotropic GGX interface (other distributions:
    /// [`Self::with_microfacet`]): indices finite, > 0 and different (by more than 10⁻³
    /// relative), α in (0, 1], colours in [0, 1].
    pub fn new(
        int_ior: f32,
        ext_ior: f32,
        alpha: f32,
        reflectance: Rgb,
        transmittance: Rgb,
    ) -> Result<Self, MaterialError> {
        let eta = check_iors(int_ior, ext_ior)?;
        if (eta - 1.0).abs() < 1e-3 {
            return Err(MaterialError::EqualIors(int_ior));
        }
        let microfacet = Microfacet::ggx(alpha);
        check_microfacet(&microfacet)?;
        check_unit_colour("specular_reflectance", reflectance)?;
        check_unit_colour("specular_transmittance", transmittance)?;
        Ok(RoughDielectric {
            eta,
            microfacet,
            specular_reflectance: reflectance,
            specular_transmittance: transmittance,
            absorption: Rgb::ZERO,
        })
    }

    /// The same interface bounding an absorbing inside of coefficient σ_a (1/m, per channel
    /// finite and ≥ 0).
    pub fn with_absorption(self, sigma_a: Rgb) -> Result<Self, MaterialError> {
        Ok(RoughDielectric { absorption: check_absorption(sigma_a)?, ..self })
    }

    /// The same interface with another microfacet distribution (each α in (0, 1]).
    pub fn with_microfacet(self, microfacet: Microfacet) -> Result<Self, MaterialError> {
        check_microfacet(&microfacet)?;
        Ok(RoughDielectric { microfacet, ..self })
    }

    /// (wi, wo, η) mirrored so that wi.z > 0; `None` for wi in the plane.
    #[inline]
    fn oriented(&self, wi: Vec3, wo: Vec3) -> Option<(Vec3, Vec3, f32)> {
        if wi.z > 0.0 {
            Some((wi, wo, self.eta))
        } else if wi.z < 0.0 {
            Some((flip(wi), flip(wo), 1.0 / self.eta))
        } else {
            None
        }
    }

    /// The physical f(wi → wo), reflection or transmission (module docs).
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        let Some((wi, wo, eta)) = self.oriented(wi, wo) else { return Rgb::ZERO };
        if wo.z == 0.0 {
            return Rgb::ZERO;
        }
        let Some((h, reflect)) = half_vector(wi, wo, eta) else { return Rgb::ZERO };
        let mf = &self.microfacet;
        let (ih, oh) = (wi.dot(h), wo.dot(h));
        // F is the same seen from either side of a refraction (Stokes); evaluating it from the
        // optically thinner side keeps 1 − F accurate near the critical angle and makes
        // generalized reciprocity hold to rounding.
        let f = if reflect || eta >= 1.0 {
            fresnel::dielectric(ih, eta).0
        } else {
            fresnel::dielectric(-oh, 1.0 / eta).0
        };
        let dg = mf.d(h) * mf.g2(wi, wo);
        if reflect {
            self.specular_reflectance * (f * dg / (4.0 * wi.z * wo.z))
        } else {
            let denom = ih + eta * oh;
            let v = (1.0 - f) * dg * eta * eta * (ih * oh).abs() / (wi.z * wo.z.abs() * denom * denom);
            self.specular_transmittance * v
        }
    }

    /// Density of [`Self::sample`] (either mode): F·p_m(h)/(4|wo·h|) for reflection,
    /// (1 − F)·p_m(h)·η²|wo·h|/(wi·h + η wo·h)² for transmission (p_m: the normal's density).
    #[inline]
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        let Some((wi, wo, eta)) = self.oriented(wi, wo) else { return 0.0 };
        if wo.z == 0.0 {
            return 0.0;
        }
        let Some((h, reflect)) = half_vector(wi, wo, eta) else { return 0.0 };
        let (ih, oh) = (wi.dot(h), wo.dot(h));
        let f = fresnel::dielectric(ih, eta).0;
        let vis = self.microfacet.normal_pdf(wi, h);
        if reflect {
            f * vis / (4.0 * oh)
        } else {
            let denom = ih + eta * oh;
            (1.0 - f) * vis * eta * eta * oh.abs() / (denom * denom)
        }
    }

    /// Samples a microfacet normal m, then reflects (`u_lobe < F(wi·m)`) or refracts about it.
    /// Weight as in the module docs, the transmission one divided by η² in radiance mode. `None`
    /// for a normal facing away from `wi` or when the scattered direction ends on the wrong side.
    #[inline]
    pub fn sample(&self, wi: Vec3, u_lobe: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let inside = wi.z < 0.0;
        let (w, _, eta) = self.oriented(wi, Vec3::Z)?;
        let m = self.microfacet.sample_normal(w, u);
        let im = w.dot(m);
        if !(im > 0.0) {
            return None;
        }
        let (f, cos_t) = fresnel::dielectric(im, eta);
        let (wo, colour) = if u_lobe < f {
            let wo = (2.0 * im * m - w).normalize();
            if wo.z <= 0.0 {
                return None;
            }
            (wo, self.specular_reflectance)
        } else {
            let wo = fresnel::refract(w, m, eta, cos_t);
            if wo.z >= 0.0 {
                return None;
            }
            let scale = match mode {
                TransportMode::Importance => 1.0,
                TransportMode::Radiance => 1.0 / (eta * eta),
            };
            (wo, self.specular_transmittance * scale)
        };
        let wo_world = if inside { flip(wo) } else { wo };
        let pdf = self.pdf(wi, wo_world);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight = colour * self.microfacet.sample_weight(w, wo, m);
        weight.is_finite().then_some(BsdfSample { wo: wo_world, weight, pdf, delta: false })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{Chi2Test, SphereGrid, incident, pilot};
    use crate::sampling::microfacet::Distribution;
    use crate::sampling::{RandomStream, warp};
    use glam::DVec3;
    use rayon::prelude::*;

    const IMP: TransportMode = TransportMode::Importance;
    const RAD: TransportMode = TransportMode::Radiance;

    fn glass() -> SmoothDielectric {
        SmoothDielectric::new(1.5, 1.0, Rgb::ONE, Rgb::ONE).unwrap()
    }

    #[test]
    fn absorption_must_be_finite_and_non_negative() {
        let rough = RoughDielectric::new(1.5, 1.0, 0.3, Rgb::ONE, Rgb::ONE).unwrap();
        assert_eq!(glass().absorption, Rgb::ZERO);
        assert_eq!(rough.absorption, Rgb::ZERO);
        let sigma = Rgb::new(0.0, 0.5, 2.0);
        assert_eq!(glass().with_absorption(sigma).unwrap().absorption, sigma);
        assert_eq!(rough.clone().with_absorption(sigma).unwrap().absorption, sigma);
        for bad in [Rgb::new(-0.1, 0.0, 0.0), Rgb::new(0.0, f32::NAN, 0.0), Rgb::splat(f32::INFINITY)] {
            let e = glass().with_absorption(bad).unwrap_err();
            assert!(matches!(
                e,
                MaterialError::Negative("absorption") | MaterialError::NotFinite("absorption")
            ));
            assert!(rough.clone().with_absorption(bad).is_err());
        }
    }

    /// Mean and standard error of the first channel of the weights of `m` samples (None = 0).
    fn mean_weight(
        mut f: impl FnMut(&mut RandomStream) -> Option<BsdfSample>,
        m: usize,
        seed: u64,
    ) -> (f64, f64) {
        let mut rng = RandomStream::new(seed, &[]);
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..m {
            if let Some(x) = f(&mut rng) {
                let w = x.weight.x as f64;
                s += w;
                s2 += w * w;
            }
        }
        let mean = s / m as f64;
        (mean, ((s2 / m as f64 - mean * mean).max(0.0) / m as f64).sqrt())
    }

    #[test]
    fn smooth_dielectric_reflects_refracts_and_conserves_flux() {
        let g = glass();
        for deg in [0.0f32, 30.0, 60.0, 89.0] {
            for wi in [incident(deg), flip(incident(deg))] {
                let inside = wi.z < 0.0;
                let eta = if inside { 1.0 / 1.5 } else { 1.5 };
                let (f, _) = fresnel::dielectric(wi.z.abs(), eta);
                let r = g.sample(wi, 0.0, IMP).unwrap();
                let t = g.sample(wi, 0.999_999, IMP).unwrap();
                assert!(r.delta && t.delta);
                assert!((r.wo - Vec3::new(-wi.x, -wi.y, wi.z)).length() < 1e-6);
                assert!((r.pdf - f).abs() < 1e-6);
                if f < 1.0 {
                    // Snell: η_i sin θ_i = η_t sin θ_t, and the refracted ray crosses the surface.
                    let (si, st) = (wi.truncate().length(), t.wo.truncate().length());
                    assert!((si - eta * st).abs() < 1e-5, "{deg}: {si} vs {eta}·{st}");
                    assert!(t.wo.z * wi.z < 0.0 && (t.pdf - (1.0 - f)).abs() < 1e-6);
                    // Importance (flux) weight 1; radiance weight 1/η².
                    assert_eq!(t.weight, Rgb::ONE);
                    let tr = g.sample(wi, 0.999_999, RAD).unwrap();
                    assert!((tr.weight.x - 1.0 / (eta * eta)).abs() < 1e-6);
                    assert_eq!(tr.wo, t.wo);
                } else {
                    assert!(inside && t.wo == r.wo, "total internal reflection");
                }
                // White furnace: every sample has weight 1, so the mean is exactly 1.
                let (mean, _) = mean_weight(|rng| g.sample(wi, rng.next_f32(), IMP), 10_000, 5);
                assert_eq!(mean, 1.0);
            }
        }
        // Lobe selection frequencies follow F.
        let wi = incident(70.0);
        let f = fresnel::dielectric(wi.z, 1.5).0 as f64;
        let m = 200_000;
        let mut rng = RandomStream::new(9, &[]);
        let refl = (0..m).filter(|_| g.sample(wi, rng.next_f32(), IMP).unwrap().wo.z > 0.0).count();
        let se = (f * (1.0 - f) / m as f64).sqrt();
        assert!((refl as f64 / m as f64 - f).abs() < 5.0 * se, "{refl} vs F = {f}");
        assert_eq!(g.sample(Vec3::X, 0.5, IMP), None);
    }

    fn rough(alpha: f32) -> RoughDielectric {
        RoughDielectric::new(1.5, 1.0, alpha, Rgb::ONE, Rgb::ONE).unwrap()
    }

    fn rough_with(mf: Microfacet) -> RoughDielectric {
        rough(0.5).with_microfacet(mf).unwrap()
    }

    /// The distributions the reciprocity, weight and energy tests sweep.
    fn distributions(alpha: f32) -> [Microfacet; 3] {
        [
            Microfacet::ggx(alpha),
            Microfacet::beckmann(alpha),
            Microfacet::anisotropic(Distribution::Beckmann, alpha, 0.25 * alpha),
        ]
    }

    /// (a) χ² over the whole sphere (reflection and transmission lobes), from outside and inside.
    #[test]
    fn chi2_rough_dielectric() {
        use Distribution::*;
        let cases = [
            (Microfacet::ggx(0.05), 30.0),
            (Microfacet::ggx(0.2), 0.0),
            (Microfacet::ggx(0.2), 75.0),
            (Microfacet::ggx(0.5), 60.0),
            (Microfacet::ggx(1.0), 85.0),
            (Microfacet::beckmann(0.05), 30.0),
            (Microfacet::beckmann(0.2), 75.0),
            (Microfacet::beckmann(0.5), 60.0),
            (Microfacet::beckmann(1.0), 85.0),
            (Microfacet::anisotropic(Ggx, 0.4, 0.05), 50.0),
            (Microfacet::anisotropic(Beckmann, 0.05, 0.4), 50.0),
        ];
        // `incident` has azimuth 0.3 rad: the plane of incidence is off both anisotropy axes.
        let runs: Vec<_> = cases
            .into_iter()
            .enumerate()
            .flat_map(|(i, (alpha, deg))| {
                [incident(deg), flip(incident(deg))]
                    .into_iter()
                    .enumerate()
                    .map(move |(j, wi)| (i, j, alpha, wi))
            })
            .collect();
        // Independent runs (each seeded by its case), in parallel.
        runs.into_par_iter().for_each(|(i, j, alpha, wi)| {
            let b = rough_with(alpha);
            // Pole on the refracted direction (the transmission lobe is usually the larger
            // one); the pilot-adapted θ edges resolve the reflection lobe too.
            let axis = Vec3::new(-wi.x, -wi.y, -wi.z);
            Chi2Test::new(axis, 900 + 10 * i as u64 + j as u64)
                .run(|ul, u| b.sample(wi, ul, u, IMP).map(|s| (s.wo, s.pdf)), |wo| b.pdf(wi, wo))
                .assert_ok(&format!("rough dielectric {alpha:?} wi={wi}"));
        });
    }

    /// (b) Generalized reciprocity f(a→b)/η_b² = f(b→a)/η_a² (absolute indices), on random pairs
    /// on both sides, and plain reciprocity for reflection.
    #[test]
    fn rough_dielectric_generalized_reciprocity() {
        let mut rng = RandomStream::new(17, &[]);
        let eta_of = |v: Vec3| if v.z > 0.0 { 1.0f32 } else { 1.5 };
        for mf in [0.05, 0.3, 1.0].into_iter().flat_map(distributions) {
            let b = rough_with(mf);
            let mut tested = 0;
            for _ in 0..20_000 {
                let wa = warp::square_to_uniform_sphere(rng.next_2d());
                let wb = match b.sample(wa, rng.next_f32(), rng.next_2d(), IMP) {
                    Some(s) if rng.next_f32() < 0.7 => s.wo,
                    _ => warp::square_to_uniform_sphere(rng.next_2d()),
                };
                let lhs = b.eval(wa, wb).x / eta_of(wb).powi(2);
                let rhs = b.eval(wb, wa).x / eta_of(wa).powi(2);
                assert!(lhs.is_finite() && rhs.is_finite() && lhs >= 0.0);
                assert!((lhs - rhs).abs() <= 1e-3 * lhs.max(rhs) + 1e-7, "{mf:?} {wa} {wb}: {lhs} vs {rhs}");
                tested += (lhs > 0.0) as usize;
            }
            assert!(tested > 5_000, "{tested}");
        }
    }

    /// Per sample: the importance weight is f(wi→wo)|cos θ_o|/pdf and the radiance weight is
    /// f(wo→wi)|cos θ_o|/pdf — the adjoint identity each mode claims.
    #[test]
    fn rough_dielectric_weights_match_eval_in_both_modes() {
        let mut rng = RandomStream::new(27, &[]);
        let water =
            RoughDielectric::new(1.33, 1.0, 0.3, Rgb::new(0.9, 0.8, 0.7), Rgb::new(0.5, 0.6, 1.0)).unwrap();
        let mut n = 0;
        for (b, deg) in distributions(0.3)
            .into_iter()
            .flat_map(|mf| [0.0, 40.0, 80.0].map(|deg| (water.clone().with_microfacet(mf).unwrap(), deg)))
        {
            for wi in [incident(deg), flip(incident(deg))] {
                for _ in 0..3_000 {
                    let (ul, u) = (rng.next_f32(), rng.next_2d());
                    let (Some(si), Some(sr)) = (b.sample(wi, ul, u, IMP), b.sample(wi, ul, u, RAD)) else {
                        continue;
                    };
                    assert_eq!((si.wo, si.pdf), (sr.wo, sr.pdf));
                    assert_eq!(si.pdf, b.pdf(wi, si.wo));
                    let wi_ = b.eval(wi, si.wo) * si.wo.z.abs() / si.pdf;
                    let wr_ = b.eval(si.wo, wi) * si.wo.z.abs() / si.pdf;
                    let close = |a: Rgb, e: Rgb| (a - e).abs().max_element() <= 2e-3 * e.max_element() + 1e-6;
                    assert!(close(si.weight, wi_), "importance {si:?} vs {wi_}");
                    assert!(close(sr.weight, wr_), "radiance {sr:?} vs {wr_}");
                    n += 1;
                }
            }
        }
        assert!(n > 30_000);
    }

    /// (c, d) Energy: mean weight equals the quadrature albedo ∫ f |cos θ_o| over the sphere
    /// within 5σ and is ≤ 1 (R = T = 1), in importance mode; in radiance mode it matches
    /// ∫ f(wo→wi) |cos θ_o| dwo, the adjoint's albedo (which may exceed 1 inside glass).
    #[test]
    fn rough_dielectric_energy() {
        // Anisotropic only at α = 0.5 (its quadrature is the slow part of this test).
        let isotropic = |a| [Microfacet::ggx(a), Microfacet::beckmann(a)];
        let mfs = [isotropic(0.1).as_slice(), &distributions(0.5), &isotropic(1.0)].concat();
        let incidences = [incident(0.0), incident(60.0), flip(incident(30.0)), flip(incident(70.0))];
        // Independent cases (each seeded by its incidence), in parallel.
        mfs.into_par_iter().for_each(|mf| {
            let (b, alpha) = (rough_with(mf), mf.alpha_u);
            for (k, wi) in incidences.into_iter().enumerate() {
                let dirs = pilot(|ul, u| b.sample(wi, ul, u, IMP).map(|s| (s.wo, s.pdf)), 20_000, 4);
                let grid = SphereGrid::adapted(-wi, &dirs, 16, 16);
                let forward = grid.integrate(|wo| DVec3::splat((b.eval(wi, wo).x * wo.z.abs()) as f64)).x;
                let adjoint = grid.integrate(|wo| DVec3::splat((b.eval(wo, wi).x * wo.z.abs()) as f64)).x;
                let seed = 40 + k as u64;
                let (mi, ei) = mean_weight(|r| b.sample(wi, r.next_f32(), r.next_2d(), IMP), 100_000, seed);
                let (mr, er) = mean_weight(|r| b.sample(wi, r.next_f32(), r.next_2d(), RAD), 100_000, seed);
                assert!(mi <= 1.0 + 5.0 * ei && forward <= 1.0 + 1e-3, "{mf:?} wi={wi}: {mi} {forward}");
                assert!((mi - forward).abs() <= 5.0 * ei + 1e-3, "{mf:?} wi={wi}: {mi} ± {ei} vs {forward}");
                assert!((mr - adjoint).abs() <= 5.0 * er + 1e-3, "{mf:?} wi={wi}: {mr} ± {er} vs {adjoint}");
                if alpha <= 0.1 && wi.z > 0.9 {
                    assert!(mi > 0.98, "nearly smooth glass at normal incidence loses little: {mi}");
                }
            }
        });
    }

    #[test]
    fn dielectric_parameters_are_validated() {
        use MaterialError::*;
        let o = Rgb::ONE;
        assert_eq!(SmoothDielectric::new(0.0, 1.0, o, o), Err(NotPositive("int_ior")));
        assert_eq!(SmoothDielectric::new(1.5, -1.0, o, o), Err(NotPositive("ext_ior")));
        assert_eq!(SmoothDielectric::new(f32::NAN, 1.0, o, o), Err(NotFinite("int_ior")));
        assert_eq!(
            SmoothDielectric::new(1.5, 1.0, Rgb::splat(1.2), o),
            Err(AboveOne("specular_reflectance"))
        );
        assert_eq!(SmoothDielectric::new(1.5, 1.0, o, -o), Err(Negative("specular_transmittance")));
        assert!(SmoothDielectric::new(1.0, 1.0, o, o).is_ok(), "an invisible interface is fine when smooth");
        assert_eq!(RoughDielectric::new(1.5, 1.5, 0.1, o, o), Err(EqualIors(1.5)));
        assert_eq!(RoughDielectric::new(1.5, 1.0, -0.1, o, o), Err(NotPositive("alpha")));
        assert_eq!(
            RoughDielectric::new(1.5, 1.0, 2.0, o, o),
            Err(TooLarge { name: "alpha", value: 2.0, max: 1.0 })
        );
    }
}
