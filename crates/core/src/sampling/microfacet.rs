//! Microfacet normal distributions for the rough BSDFs ([`Microfacet`]): GGX (Trowbridge–Reitz)
//! and Beckmann, each isotropic or anisotropic (roughness α_u along the local x axis, α_v along
//! y), with Smith's masking function Λ and a sampling routine with its exact density.
//!
//! With unit m in the local frame (z = normal) and the slopes x̃ = −m.x/m.z, ỹ = −m.y/m.z:
//!
//! ```text
//! GGX       D(m) = 1 / (π α_u α_v cos⁴θ_m (1 + x̃²/α_u² + ỹ²/α_v²)²)
//!           Λ(w) = (−1 + √(1 + α²tan²θ)) / 2
//! Beckmann  D(m) = exp(−(x̃²/α_u² + ỹ²/α_v²)) / (π α_u α_v cos⁴θ_m)
//!           Λ(w) = (e^(−a²)/(a√π) − erfc(a)) / 2,   a = 1/(α tan θ)
//! ```
//!
//! where α tan θ = √(w.x² α_u² + w.y² α_v²)/|w.z| is the roughness projected on w's azimuth
//! (Heitz 2014, "Understanding the Masking-Shadowing Function", §5.3). ∫ D(m) cos θ_m dω_m = 1,
//! and Λ makes ∫ G₁(w)·max(0, w·m)·D(m)/cos θ dω_m = 1 with G₁ = 1/(1 + Λ) (both tested). The
//! BSDFs use the height-correlated G₂(wi, wo) = 1/(1 + Λ(wi) + Λ(wo)), symmetric in its
//! arguments. (Mitsuba 3 uses the separable G₁(wi)·G₁(wo) and, for Beckmann, Walter's rational
//! fit of G₁; the difference is a fraction of a percent of the reflected energy except at
//! grazing angles on very rough surfaces.)
//!
//! Sampling ([`Microfacet::sample_normal`], density [`Microfacet::normal_pdf`]):
//! * GGX: Heitz 2018's exact sampling of the normals **visible** from wi ("Sampling the GGX
//!   Distribution of Visible Normals", JCGT 7(4)): stretch wi to the α = 1 configuration, sample
//!   the projected hemisphere, unstretch. Density D_wi(m) = G₁(wi)·max(0, wi·m)·D(m)/cos θ_i;
//!   the BSDF weights are then G₂/G₁(wi) ≤ 1.
//! * Beckmann: the slope distribution is a Gaussian, so m is sampled from D(m)·cos θ_m exactly
//!   (Walter et al. 2007, eq. 28, in slope form: x̃ = α_u r cos φ, ỹ = α_v r sin φ with
//!   r² = −ln(1 − u₁), φ = 2πu₂). Normals facing away from wi (wi·m ≤ 0) carry no light: the
//!   density is D(m)·cos θ_m·[wi·m > 0] and the caller rejects the others, so it integrates to
//!   less than 1. The weights G₂·(wi·m)/(cos θ_i cos θ_m) may exceed 1 near grazing incidence
//!   (the estimator stays unbiased; only its variance is larger than with visible normals).

use glam::{Vec2, Vec3};
use std::f32::consts::{PI, TAU};

/// The shape of a microfacet normal distribution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Distribution {
    /// Trowbridge–Reitz (GGX): long tails.
    Ggx,
    /// Beckmann (Gaussian slopes): Mitsuba's default for `roughconductor`/`roughdielectric`.
    Beckmann,
}

/// A microfacet distribution: shape and roughness along the local x (`alpha_u`) and y
/// (`alpha_v`) axes. Isotropic when they are equal. The BSDF constructors validate α.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microfacet {
    /// GGX or Beckmann.
    pub distribution: Distribution,
    /// Roughness along the local x axis (the frame's tangent).
    pub alpha_u: f32,
    /// Roughness along the local y axis (the frame's bitangent).
    pub alpha_v: f32,
}

/// 1/√π.
const INV_SQRT_PI: f64 = 0.564_189_583_547_756_3;

/// The complementary error function, |relative error| < 1.2·10⁻⁷ (Numerical Recipes' `erfcc`,
/// a Chebyshev fit), in f64 so that Λ keeps f32 precision.
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let p = -1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * (-z * z + p).exp();
    if x >= 0.0 { r } else { 2.0 - r }
}

impl Microfacet {
    /// Isotropic GGX of roughness α.
    pub fn ggx(alpha: f32) -> Self {
        Microfacet { distribution: Distribution::Ggx, alpha_u: alpha, alpha_v: alpha }
    }

    /// Isotropic Beckmann of roughness α.
    pub fn beckmann(alpha: f32) -> Self {
        Microfacet { distribution: Distribution::Beckmann, alpha_u: alpha, alpha_v: alpha }
    }

    /// `distribution` with roughness α_u along x and α_v along y.
    pub fn anisotropic(distribution: Distribution, alpha_u: f32, alpha_v: f32) -> Self {
        Microfacet { distribution, alpha_u, alpha_v }
    }

    /// D(m) for unit `m` with `m.z > 0`, 0 below.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let (au, av) = (self.alpha_u, self.alpha_v);
        let z2 = m.z * m.z;
        match self.distribution {
            Distribution::Ggx => {
                // α_u α_v ((m.x/α_u)² + (m.y/α_v)² + m.z²): exact for unit m, no cancellation.
                let t = m.x * m.x * (av / au) + m.y * m.y * (au / av) + au * av * z2;
                au * av / (PI * t * t)
            }
            Distribution::Beckmann => {
                let e = ((m.x / au).powi(2) + (m.y / av).powi(2)) / z2;
                (-e).exp() / (PI * au * av * z2 * z2)
            }
        }
    }

    /// Smith's Λ(w) (either hemisphere: |cos θ| is used); +∞ in the surface plane.
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let z2 = w.z * w.z;
        if z2 <= 0.0 {
            return f32::INFINITY;
        }
        // α²tan²θ along w's azimuth.
        let a2tan2 = ((w.x * self.alpha_u).powi(2) + (w.y * self.alpha_v).powi(2)) / z2;
        match self.distribution {
            // (√(1 + x) − 1)/2 = x / (2(√(1 + x) + 1)): no cancellation for small x.
            Distribution::Ggx => a2tan2 / (2.0 * ((1.0 + a2tan2).sqrt() + 1.0)),
            Distribution::Beckmann => {
                if a2tan2 <= 0.0 {
                    return 0.0;
                }
                let a = 1.0 / (a2tan2 as f64).sqrt();
                if a > 6.0 {
                    return 0.0; // below 10⁻¹⁷
                }
                (0.5 * ((-a * a).exp() * INV_SQRT_PI / a - erfc(a))).max(0.0) as f32
            }
        }
    }

    /// Height-correlated Smith masking-shadowing G₂(wi, wo) = 1/(1 + Λ(wi) + Λ(wo)).
    #[inline]
    pub fn g2(&self, wi: Vec3, wo: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wi) + self.lambda(wo))
    }

    /// A microfacet normal for light arriving from `wi` (`wi.z > 0`), density
    /// [`Self::normal_pdf`] (module docs). May face away from `wi` (Beckmann): callers reject
    /// such normals.
    #[inline]
    pub fn sample_normal(&self, wi: Vec3, u: Vec2) -> Vec3 {
        let (au, av) = (self.alpha_u, self.alpha_v);
        match self.distribution {
            Distribution::Ggx => {
                let vh = Vec3::new(au * wi.x, av * wi.y, wi.z).normalize();
                let lensq = vh.x * vh.x + vh.y * vh.y;
                let t1 = if lensq > 0.0 { Vec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt() } else { Vec3::X };
                let t2 = vh.cross(t1);
                let r = u.x.sqrt();
                let phi = TAU * u.y;
                let p1 = r * phi.cos();
                let s = 0.5 * (1.0 + vh.z);
                let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
                let nh = t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
                Vec3::new(au * nh.x, av * nh.y, nh.z.max(1e-7)).normalize()
            }
            Distribution::Beckmann => self.sample_d_cos(u),
        }
    }

    /// A normal of density D(m)·cos θ_m (Mitsuba's sampling when `sample_visible` is off), in
    /// slope form: x̃ = α_u r cos φ, ỹ = α_v r sin φ with r² = u₁/(1 − u₁) (GGX) or
    /// −ln(1 − u₁) (Beckmann), φ = 2πu₂. Density [`Self::d_cos_pdf`].
    #[inline]
    pub fn sample_d_cos(&self, u: Vec2) -> Vec3 {
        let r = match self.distribution {
            Distribution::Ggx => (u.x / (1.0 - u.x).max(f32::MIN_POSITIVE)).sqrt(),
            Distribution::Beckmann => (-(-u.x).ln_1p()).sqrt(),
        };
        let (sin, cos) = (TAU * u.y).sin_cos();
        Vec3::new(-self.alpha_u * r * cos, -self.alpha_v * r * sin, 1.0).normalize()
    }

    /// Density of [`Self::sample_d_cos`]: D(m)·cos θ_m.
    #[inline]
    pub fn d_cos_pdf(&self, m: Vec3) -> f32 {
        self.d(m) * m.z.max(0.0)
    }

    /// Smith's G₁(v) = 1/(1 + Λ(v)) for a normal `m` that `v` sees (0 if v·m and v.z differ
    /// in sign: the back of a facet is never seen).
    #[inline]
    pub fn g1(&self, v: Vec3, m: Vec3) -> f32 {
        if v.dot(m) * v.z <= 0.0 {
            return 0.0;
        }
        1.0 / (1.0 + self.lambda(v))
    }

    /// Mitsuba 3's G₁ (`smith_g1`), which the BSDFs that reproduce Mitsuba's separable
    /// G₁(wi)·G₁(wo) evaluate: exact for GGX, Walter et al.'s rational fit for Beckmann
    /// ((3.535a + 2.181a²)/(1 + 2.276a + 2.577a²) for a = 1/(α tan θ) < 1.6, else 1; relative
    /// error below 0.35 % of [`Self::g1`]); 0 on the back of a facet.
    #[inline]
    pub fn g1_mitsuba(&self, v: Vec3, m: Vec3) -> f32 {
        if v.dot(m) * v.z <= 0.0 {
            return 0.0;
        }
        let xy = (self.alpha_u * v.x).powi(2) + (self.alpha_v * v.y).powi(2);
        if xy == 0.0 {
            return 1.0;
        }
        let t2 = xy / (v.z * v.z);
        match self.distribution {
            Distribution::Ggx => 2.0 / (1.0 + (1.0 + t2).sqrt()),
            Distribution::Beckmann => {
                let a = 1.0 / t2.sqrt();
                if a >= 1.6 { 1.0 } else { (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a) }
            }
        }
    }

    /// A normal **visible** from `wi` (`wi.z > 0`), exactly of density [`Self::visible_pdf`],
    /// for both distributions, with the mapping of `u` Mitsuba 3 uses (Heitz & d'Eon 2014,
    /// "Importance Sampling Microfacet-Based BSDFs using the Distribution of Visible Normals"):
    /// stretch wi to the α = 1 configuration, sample the visible slopes there (GGX: the
    /// concentric disk squeezed onto the visible half, Heitz 2017; Beckmann: the marginal CDF
    /// of the slope along wi's azimuth inverted numerically, the other slope Gaussian),
    /// rotate to wi's azimuth and unstretch. With the same mapping, quadratures over `u` (the
    /// tables of `roughplastic`) reproduce Mitsuba's.
    pub fn sample_visible(&self, wi: Vec3, u: Vec2) -> Vec3 {
        let (au, av) = (self.alpha_u, self.alpha_v);
        let w = Vec3::new(au * wi.x, av * wi.y, wi.z).normalize();
        let s2 = w.x * w.x + w.y * w.y;
        let (cos_phi, sin_phi) =
            if s2 <= 4.0 * f32::EPSILON { (1.0, 0.0) } else { (w.x / s2.sqrt(), w.y / s2.sqrt()) };
        let slope = match self.distribution {
            Distribution::Ggx => ggx_visible_slope(w.z, u),
            Distribution::Beckmann => beckmann_visible_slope(w.z, u),
        };
        let sx = (cos_phi * slope.x - sin_phi * slope.y) * au;
        let sy = (sin_phi * slope.x + cos_phi * slope.y) * av;
        Vec3::new(-sx, -sy, 1.0).normalize()
    }

    /// Density of [`Self::sample_visible`]: D_wi(m) = G₁(wi)·max(0, wi·m)·D(m)/cos θ_i (exact
    /// Λ); 0 for `wi.z ≤ 0`.
    #[inline]
    pub fn visible_pdf(&self, wi: Vec3, m: Vec3) -> f32 {
        let wm = wi.dot(m);
        if wi.z <= 0.0 || wm <= 0.0 {
            return 0.0;
        }
        self.d(m) * wm / (wi.z * (1.0 + self.lambda(wi)))
    }

    /// Solid-angle density of [`Self::sample_normal`] at `m`, restricted to normals facing `wi`
    /// (`wi.z > 0`): GGX G₁(wi)·(wi·m)·D(m)/cos θ_i, Beckmann D(m)·cos θ_m; 0 when wi·m ≤ 0.
    #[inline]
    pub fn normal_pdf(&self, wi: Vec3, m: Vec3) -> f32 {
        let wm = wi.dot(m);
        if wi.z <= 0.0 || wm <= 0.0 {
            return 0.0;
        }
        match self.distribution {
            Distribution::Ggx => self.d(m) * wm / (wi.z * (1.0 + self.lambda(wi))),
            Distribution::Beckmann => self.d(m) * m.z,
        }
    }

    /// D(m)·G₂(wi, wo)·(wi·m) / (cos θ_i · [`Self::normal_pdf`]): the factor that turns a
    /// sampled normal's colour (R·F, T·(1 − F), …) into the BSDF weight f·|cos θ_o|/pdf, for
    /// reflection and refraction alike (`wi.z > 0`, `wi·m > 0`). GGX: G₂/G₁(wi) ≤ 1.
    #[inline]
    pub fn sample_weight(&self, wi: Vec3, wo: Vec3, m: Vec3) -> f32 {
        let (li, lo) = (self.lambda(wi), self.lambda(wo));
        let g2 = 1.0 / (1.0 + li + lo);
        match self.distribution {
            Distribution::Ggx => (1.0 + li) * g2,
            Distribution::Beckmann => g2 * wi.dot(m) / (wi.z * m.z),
        }
    }
}

/// The visible slope (x̃, ỹ) of the α = 1 GGX seen from cos θ = `cos_i` along +x (Mitsuba's
/// mapping: a concentric disk point, its y squeezed onto the visible half, lifted to the
/// hemisphere and turned into a slope).
fn ggx_visible_slope(cos_i: f32, u: Vec2) -> Vec2 {
    let p = super::warp::square_to_concentric_disk(u);
    let s = 0.5 * (1.0 + cos_i);
    let y = (1.0 - s) * (1.0 - p.x * p.x).max(0.0).sqrt() + s * p.y;
    let x = p.x;
    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
    let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
    let norm = 1.0 / (sin_i * y + cos_i * z);
    Vec2::new((cos_i * y - sin_i * z) * norm, x * norm)
}

/// The visible slope of the α = 1 Beckmann distribution seen from cos θ = `cos_i` along +x.
/// The slope x̃ has the CDF ∝ 1 + erf(x̃) + tan θ·e^(−x̃²)/√π on (−∞, cot θ]; it is inverted
/// in the erf domain (x = erf(x̃), on which the CDF is monotone with derivative 1 − x̃ tan θ)
/// by Newton steps kept inside a bracket, in f64. ỹ = erfinv(2u₂ − 1). `u` is clamped to
/// [10⁻⁶, 1 − 10⁻⁶] as Mitsuba does.
fn beckmann_visible_slope(cos_i: f32, u: Vec2) -> Vec2 {
    let u = u.clamp(Vec2::splat(1e-6), Vec2::splat(1.0 - 1e-6));
    let c = (cos_i as f64).clamp(1e-7, 1.0);
    let tan = (1.0 - c * c).max(0.0).sqrt() / c;
    let cot = 1.0 / tan;
    let hi0 = 1.0 - erfc(cot);
    let inv_sqrt_pi = INV_SQRT_PI;
    let target = u.x as f64 * (1.0 + hi0 + inv_sqrt_pi * tan * (-cot * cot).exp());
    let cdf = |x: f64| {
        let s = erfinv(x);
        (1.0 + x + inv_sqrt_pi * tan * (-s * s).exp() - target, s)
    };
    let (mut lo, mut hi) = (-1.0f64, hi0);
    // Mitsuba's initial guess (exact at grazing incidence).
    let mut x = hi0 - (hi0 + 1.0) * (1.0 - erfc((-(u.x as f64).ln()).sqrt()));
    // erfinv is accurate to f32 precision, so the CDF is known to ~10⁻⁸: stop there.
    for _ in 0..30 {
        if !(x > lo && x < hi) {
            x = 0.5 * (lo + hi);
        }
        let (v, s) = cdf(x);
        if v < 0.0 {
            lo = x
        } else {
            hi = x
        }
        let d = 1.0 - s * tan;
        let step = if d > 1e-12 { v / d } else { f64::INFINITY };
        if step.abs() < 1e-8 || hi - lo < 1e-8 {
            x = (x - step).clamp(lo, hi);
            break;
        }
        x -= step;
    }
    Vec2::new(erfinv(x.clamp(-1.0, hi0)) as f32, erfinv(2.0 * u.y as f64 - 1.0) as f32)
}

/// The inverse error function on (−1, 1) (Giles 2010, "Approximating the erfinv function",
/// the single-precision fit; ±∞ at ±1).
fn erfinv(x: f64) -> f64 {
    let w = -((1.0 - x) * (1.0 + x)).ln();
    let p = if w < 5.0 {
        let w = w - 2.5;
        [
            2.810_226_36e-08,
            3.432_739_39e-07,
            -3.523_387_7e-06,
            -4.391_506_54e-06,
            0.000_218_580_87,
            -0.001_253_725_03,
            -0.004_177_681_64,
            0.246_640_727,
            1.501_409_41,
        ]
        .iter()
        .fold(0.0, |p, c| c + p * w)
    } else {
        let w = w.sqrt() - 3.0;
        [
            -0.000_200_214_257,
            0.000_100_950_558,
            0.001_349_343_22,
            -0.003_673_428_44,
            0.005_739_507_73,
            -0.007_622_461_3,
            0.009_438_870_47,
            1.001_674_06,
            2.832_976_82,
        ]
        .iter()
        .fold(0.0, |p, c| c + p * w)
    };
    p * x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::RandomStream;

    fn all() -> [Microfacet; 6] {
        use Distribution::*;
        [
            Microfacet::ggx(0.05),
            Microfacet::ggx(1.0),
            Microfacet::anisotropic(Ggx, 0.1, 0.6),
            Microfacet::beckmann(0.05),
            Microfacet::beckmann(1.0),
            Microfacet::anisotropic(Beckmann, 0.5, 0.08),
        ]
    }

    /// χ² of the visible-normal sampler (Mitsuba's mapping, both distributions) against its
    /// density, and of the D·cos sampler against D·cos, at normal, oblique and grazing wi.
    #[test]
    fn visible_and_d_cos_sampling_match_their_densities() {
        use crate::bsdf::chi2::{Chi2Test, incident};
        use rayon::prelude::*;
        let cases: Vec<(Microfacet, f32)> =
            [Microfacet::ggx(0.3), Microfacet::beckmann(0.3), Microfacet::beckmann(0.8)]
                .into_iter()
                .flat_map(|mf| [0.0, 60.0, 88.0].map(move |d| (mf, d)))
                .collect();
        cases.into_par_iter().enumerate().for_each(|(i, (mf, deg))| {
            let wi = incident(deg);
            Chi2Test::new(Vec3::Z, 70 + i as u64)
                .run(
                    |_, u| Some((mf.sample_visible(wi, u), mf.visible_pdf(wi, mf.sample_visible(wi, u)))),
                    |m| mf.visible_pdf(wi, m),
                )
                .assert_ok(&format!("visible {mf:?} θi={deg}°"));
            if deg == 0.0 {
                Chi2Test::new(Vec3::Z, 90 + i as u64)
                    .run(
                        |_, u| Some((mf.sample_d_cos(u), mf.d_cos_pdf(mf.sample_d_cos(u)))),
                        |m| mf.d_cos_pdf(m),
                    )
                    .assert_ok(&format!("D·cos {mf:?}"));
            }
        });
    }

    #[test]
    fn erfinv_inverts_erf() {
        for x in [-0.999_99, -0.9, -0.3, 1e-4, 0.5, 0.99, 0.999_999] {
            let y = erfinv(x);
            assert!(((1.0 - erfc(y)) - x).abs() < 1e-6, "erf(erfinv({x})) = {}", 1.0 - erfc(y));
        }
    }

    #[test]
    fn erfc_matches_known_values() {
        for (x, want) in [(0.0, 1.0), (0.5, 0.479_500_122_186_953_5), (1.0, 0.157_299_207_050_285_1)] {
            assert!((erfc(x) - want).abs() < 2e-7 * want, "erfc({x}) = {}", erfc(x));
        }
        assert!((erfc(3.0) / 2.209_049_699_858_544e-5 - 1.0).abs() < 2e-7);
        assert!((erfc(-1.0) - 1.842_700_792_949_715).abs() < 1e-7);
    }

    /// ∫ D(m) cos θ_m dω = 1 (the distribution is normalised) and ∫ G₁(wi)·max(0, wi·m)·D(m)/
    /// cos θ_i dω = 1 (Λ is Smith's for this D), by the midpoint rule in (cos θ, φ); the
    /// sampling density integrates to 1 (GGX) or to the fraction of normals facing wi (≤ 1).
    #[test]
    fn distributions_are_normalised_and_lambda_is_smiths() {
        for mf in all() {
            for wi in [Vec3::Z, Vec3::new(0.6, 0.2, 0.5).normalize(), Vec3::new(0.3, 0.95, 0.08).normalize()]
            {
                let (nt, np) = (4000, 128);
                let (mut d, mut vis, mut p) = (0.0f64, 0.0f64, 0.0f64);
                let g1 = 1.0 / (1.0 + mf.lambda(wi) as f64);
                for i in 0..nt {
                    // cos θ = 1 − x², x uniform: dense near the pole where narrow lobes live.
                    let x = (i as f64 + 0.5) / nt as f64;
                    let ct = 1.0 - x * x;
                    let st = (1.0 - ct * ct).max(0.0).sqrt();
                    for j in 0..np {
                        let phi = std::f64::consts::TAU * (j as f64 + 0.5) / np as f64;
                        let m = Vec3::new((st * phi.cos()) as f32, (st * phi.sin()) as f32, ct as f32);
                        let dw = 2.0 * x / nt as f64 * std::f64::consts::TAU / np as f64;
                        let dm = mf.d(m) as f64;
                        d += dm * ct * dw;
                        vis += g1 * (wi.dot(m).max(0.0) as f64) * dm / wi.z as f64 * dw;
                        p += mf.normal_pdf(wi, m) as f64 * dw;
                    }
                }
                let ctx = format!("{mf:?} wi={wi}");
                assert!((d - 1.0).abs() < 2e-3, "{ctx}: ∫D cos = {d}");
                assert!((vis - 1.0).abs() < 2e-3, "{ctx}: ∫D_wi = {vis}");
                match mf.distribution {
                    Distribution::Ggx => assert!((p - 1.0).abs() < 2e-3, "{ctx}: ∫pdf = {p}"),
                    Distribution::Beckmann => assert!(p <= 1.0 + 2e-3 && p > 0.5, "{ctx}: ∫pdf = {p}"),
                }
            }
        }
    }

    #[test]
    fn isotropic_ggx_matches_the_closed_form_and_anisotropy_stretches() {
        let mf = Microfacet::ggx(0.3);
        let m = Vec3::new(0.2, -0.1, 0.9).normalize();
        let a2 = 0.09f32;
        let want = a2 / (PI * ((a2 - 1.0) * m.z * m.z + 1.0).powi(2));
        assert!((mf.d(m) - want).abs() < 1e-5 * want);
        // Rougher along x: a normal tilted along x is likelier than one tilted as far along y.
        for dist in [Distribution::Ggx, Distribution::Beckmann] {
            let a = Microfacet::anisotropic(dist, 0.5, 0.1);
            let (tx, ty) = (Vec3::new(0.3, 0.0, 0.95).normalize(), Vec3::new(0.0, 0.3, 0.95).normalize());
            let (gx, gy) = (Vec3::new(0.8, 0.0, 0.6), Vec3::new(0.0, 0.8, 0.6));
            assert!(a.d(tx) > 10.0 * a.d(ty), "{dist:?}");
            assert!(a.lambda(gx) > a.lambda(gy), "{dist:?}");
        }
    }

    #[test]
    fn sampled_normals_are_finite_and_upward() {
        let mut s = RandomStream::new(7, &[]);
        for mf in all().into_iter().chain([Microfacet::ggx(1e-3), Microfacet::beckmann(1e-3)]) {
            for wi in [Vec3::Z, Vec3::new(1.0, 0.0, 1e-4).normalize(), Vec3::new(0.3, -0.4, 0.8).normalize()]
            {
                for _ in 0..10_000 {
                    let m = mf.sample_normal(wi, s.next_2d());
                    assert!(m.is_finite() && m.z > 0.0 && (m.length() - 1.0).abs() < 1e-5, "{m}");
                    if mf.distribution == Distribution::Ggx {
                        assert!(wi.dot(m) > -1e-5, "visible normals face the viewer: {mf:?} wi={wi} m={m}");
                    }
                }
            }
            for u in [Vec2::ZERO, Vec2::new(0.999_999_9, 0.999_999_9)] {
                assert!(mf.sample_normal(Vec3::Z, u).is_finite());
            }
            assert_eq!(mf.lambda(Vec3::X), f32::INFINITY);
            assert_eq!(mf.lambda(Vec3::Z), 0.0);
        }
    }
}
