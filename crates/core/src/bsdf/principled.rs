//! Mitsuba 3's `principled` BSDF (Burley's Disney BSDF as Mitsuba implements it,
//! src/bsdfs/principled.cpp and principledhelpers.h): the artist's parameters of Mitsuba's
//! plugin, with its defaults and its exact formulas, so that a scene written for Mitsuba renders
//! the same here. Without its transmission lobe (`has_spec_trans` false: `spec_trans` absent or
//! 0) Mitsuba's BSDF is one-sided and reflective, as every reflection-only BSDF here (black from
//! behind, zero below the surface); the reflective lobes below are the front side's. With it,
//! the BSDF is oriented like a dielectric (+z outside, −z inside, η = inside/outside) and
//! scatters from both sides: see `principled_trans.rs` for the transmission lobe, the back
//! side and the lobe probabilities.
//!
//! With h the half vector of wi and wo, c the base colour, m `metallic`, and Mitsuba's Schlick
//! weight w(μ) = (1 − μ)⁵:
//!
//! ```text
//! f = F_p(wi·h)·D(h)·G₁(wi)·G₁(wo) / (4 cos θ_i cos θ_o)       main specular, GGX (α_x, α_y)
//!   + ¼·clearcoat·F_s(0.04, wi·h)·D_cc(h)·G_cc(wi)·G_cc(wo)      clearcoat (no 1/(4 cos cos): Mitsuba's)
//!   + (1 − m)(1 − t)·c/π·lerp(f_d + f_r, f_ss, flatness)         diffuse, retro-reflection
//!   + sheen·(1 − m)·w(h·wo)·lerp(1, c/lum(c), sheen_tint)        sheen
//! t = `spec_trans`,  f_d = (1 − w_i/2)(1 − w_o/2),  R_r = 2·roughness·(h·wo)²,  f_r = R_r(w_o + w_i + w_o w_i (R_r − 1))
//! F_p = (1 − m)(1 − spec_tint)·F_dielectric(η) + m·F_s(c) + (1 − m)·spec_tint·F_s(c/lum(c)·R₀(η))
//! ```
//!
//! where F_s(R₀, μ) = R₀ + (1 − R₀)·w(μ) is Schlick's Fresnel (with the refracted cosine when
//! η < 1, as Mitsuba's `calc_schlick`), R₀(η) = ((η − 1)/(η + 1))², α_x = max(10⁻³, r²/a),
//! α_y = max(10⁻³, r²·a) with a = √(1 − 0.9·anisotropic), D_cc Burley's GTR1 of roughness
//! lerp(0.1, 0.001, clearcoat_gloss) and G_cc the separable Smith GGX masking of roughness ¼.
//! η is `eta`, or from `specular` s: η = 2/(1 − √(0.08 s)) − 1 (the loader converts). The main
//! lobe vanishes, metallic part included, where F_dielectric is 0 (η = 1: `specular` = 0), as in
//! Mitsuba.
//!
//! Every reflective term is symmetric in wi and wo, so reflection is reciprocal and the same in
//! both transport modes (the adjoint is f itself); transmission is not (`principled_trans.rs`).
//!
//! Sampling as Mitsuba: a lobe by the probabilities diffuse (1 − m)(1 − t)·`diffuse_rate`,
//! clearcoat ¼·clearcoat·`clearcoat_rate`, main specular `specular_rate` (normalised; with
//! transmission the main specular share is split between reflection and refraction about the
//! same sampled normal, `principled_trans.rs`); the diffuse lobe
//! draws a cosine-weighted direction, the clearcoat reflects wi about a GTR1 normal of density
//! D_cc·cos θ_h, the main lobe about a GGX normal visible from wi
//! ([`Microfacet::sample_visible`]). `pdf` is the mixture and the weight f·cos θ_o/pdf.

use super::{BsdfSample, MaterialError, TransportMode, check_unit_colour, fresnel};
use crate::math::{Rgb, Vec2, Vec3, luminance};
use crate::sampling::microfacet::{Distribution, Microfacet};
use crate::sampling::warp;
use std::f32::consts::{FRAC_1_PI, PI, TAU};

/// Mitsuba 3's `principled` BSDF (see the module docs). The fields are
/// Mitsuba's parameters; textures set them point by point
/// (`crate::texture::set_principled`), so nothing is derived from them at construction.
#[derive(Clone, Debug, PartialEq)]
pub struct Principled {
    /// `base_color` c, in [0, 1] per channel.
    pub base_color: Rgb,
    /// `roughness` of the main specular lobe (and of the retro-reflection), in [0, 1].
    pub roughness: f32,
    /// `anisotropic`: 0 isotropic, 1 the most anisotropic (α_x / α_y = 1/(1 − 0.9)).
    pub anisotropic: f32,
    /// `metallic`: the share of the metallic (Schlick, base-coloured) Fresnel.
    pub metallic: f32,
    /// `spec_tint`: the share of the dielectric reflection tinted towards the base colour.
    pub spec_tint: f32,
    /// Relative index of refraction η of the dielectric reflection (from `eta` or `specular`).
    pub eta: f32,
    /// `sheen`: the weight of the grazing sheen lobe.
    pub sheen: f32,
    /// `sheen_tint`: how far the sheen is tinted towards the base colour.
    pub sheen_tint: f32,
    /// `clearcoat`: the weight of the secondary (GTR1) specular lobe.
    pub clearcoat: f32,
    /// `clearcoat_gloss`: 0 a rough coat (α 0.1), 1 a glossy one (α 0.001).
    pub clearcoat_gloss: f32,
    /// `flatness`: blend of the diffuse lobe towards Hanrahan–Krueger's fake subsurface.
    pub flatness: f32,
    /// `diffuse_reflectance_sampling_rate` (≥ 0).
    pub diffuse_rate: f32,
    /// `main_specular_sampling_rate` (> 0).
    pub specular_rate: f32,
    /// `clearcoat_sampling_rate` (≥ 0).
    pub clearcoat_rate: f32,
    /// `spec_trans` t: the share of the non-metallic part that is the rough dielectric
    /// (reflection and transmission) instead of the diffuse base, in [0, 1].
    pub spec_trans: f32,
    /// Whether the transmission lobe exists (Mitsuba's `m_has_spec_trans`: `spec_trans` given as
    /// a texture or a non-zero float). If so the BSDF is oriented and scatters from both sides
    /// ([`super::Bsdf::transmits`]), also where a texture makes t = 0.
    pub has_spec_trans: bool,
}

impl Default for Principled {
    /// Mitsuba's defaults: base colour 0.5, roughness 0.5, `specular` 0.5 (η = 1.5), every other
    /// weight 0, sampling rates 1.
    fn default() -> Self {
        Principled {
            base_color: Rgb::splat(0.5),
            roughness: 0.5,
            anisotropic: 0.0,
            metallic: 0.0,
            spec_tint: 0.0,
            eta: eta_of_specular(0.5),
            sheen: 0.0,
            sheen_tint: 0.0,
            clearcoat: 0.0,
            clearcoat_gloss: 0.0,
            flatness: 0.0,
            diffuse_rate: 1.0,
            specular_rate: 1.0,
            clearcoat_rate: 1.0,
            spec_trans: 0.0,
            has_spec_trans: false,
        }
    }
}

/// η from Mitsuba's `specular` s: 2/(1 − √(0.08 s)) − 1 (s = 0.5 gives 1.5).
pub fn eta_of_specular(specular: f32) -> f32 {
    2.0 / (1.0 - (0.08 * specular).sqrt()) - 1.0
}

/// Mitsuba's Schlick weight (1 − μ)⁵, μ clamped to [0, 1].
#[inline]
pub(super) fn schlick_weight(mu: f32) -> f32 {
    let m = (1.0 - mu).clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// Schlick's Fresnel weight for light arriving with `cos_i` at relative index `eta`
/// (Mitsuba's `calc_schlick`): w(|cos θ_i|) when the light enters a denser medium, else w of
/// the refracted cosine (1 under total internal reflection). F = R₀ + (1 − R₀)·(this).
#[inline]
fn schlick_factor(cos_i: f32, eta: f32) -> f32 {
    let eta_it = if cos_i >= 0.0 { eta } else { 1.0 / eta };
    if eta_it > 1.0 {
        schlick_weight(cos_i.abs())
    } else {
        let cos_t2 = 1.0 - (1.0 - cos_i * cos_i) / (eta_it * eta_it);
        schlick_weight(cos_t2.max(0.0).sqrt())
    }
}

/// The GGX distribution of Mitsuba's principled BSDFs for `roughness` r and `anisotropic` a
/// (Mitsuba's `calc_dist_params`): α_x = max(10⁻³, r²/s), α_y = max(10⁻³, r²·s), s = √(1 − 0.9a).
#[inline]
pub(super) fn ggx(roughness: f32, anisotropic: f32) -> Microfacet {
    let r2 = roughness * roughness;
    let aspect = (1.0 - 0.9 * anisotropic).sqrt();
    Microfacet::anisotropic(Distribution::Ggx, (r2 / aspect).max(1e-3), (r2 * aspect).max(1e-3))
}

/// The base colour `c` normalised by its luminance (white if black): the tint of `spec_tint`
/// and `sheen_tint`.
#[inline]
pub(super) fn colour_tint(c: Rgb) -> Rgb {
    let lum = luminance(c);
    if lum > 0.0 { c / lum } else { Rgb::ONE }
}

/// The main lobe's Fresnel term F_p (module docs) for light arriving at `cos_i` = wi·h ≥ 0 on
/// a facet, given the dielectric reflectance `f_dielectric` there, relative index `eta`,
/// `metallic` m, `spec_tint` and the base colour (Mitsuba's `principled_fresnel` from the front;
/// with m = 0 its `thin_fresnel`, the lerp of F_dielectric towards the tinted Schlick term).
#[inline]
pub(super) fn tinted_fresnel(f_dielectric: f32, cos_i: f32, eta: f32, m: f32, tint: f32, base: Rgb) -> Rgb {
    let w = schlick_factor(cos_i, eta);
    let schlick = |r0: Rgb| r0 + (Rgb::ONE - r0) * w;
    let mut f = Rgb::splat((1.0 - m) * (1.0 - tint) * f_dielectric);
    if m > 0.0 {
        f += m * schlick(base);
    }
    if tint > 0.0 {
        let r0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
        f += (1.0 - m) * tint * schlick(colour_tint(base) * r0);
    }
    f
}

/// Burley's diffuse lobe with retro-reflection, blended by `flatness` towards Hanrahan–Krueger's
/// fake subsurface (module docs: lerp(f_d + f_r, f_ss, flatness), times c/π by the caller), for
/// the cosines of wi and wo with the normal and `cos_oh` = wo·h.
#[inline]
pub(super) fn burley_diffuse(roughness: f32, flatness: f32, cos_i: f32, cos_o: f32, cos_oh: f32) -> f32 {
    let (w_o, w_i) = (schlick_weight(cos_o), schlick_weight(cos_i));
    let diffuse = (1.0 - 0.5 * w_i) * (1.0 - 0.5 * w_o);
    let rr = 2.0 * roughness * cos_oh * cos_oh;
    let retro = rr * (w_o + w_i + w_o * w_i * (rr - 1.0));
    let mut lobe = diffuse + retro;
    if flatness > 0.0 {
        let ss90 = 0.5 * rr;
        let ss = (1.0 + (ss90 - 1.0) * w_o) * (1.0 + (ss90 - 1.0) * w_i);
        let f_ss = 1.25 * (ss * (1.0 / (cos_o + cos_i) - 0.5) + 0.5);
        lobe += (f_ss - lobe) * flatness;
    }
    lobe
}

/// The sheen lobe sheen·w(h·wo)·lerp(1, c/lum(c), sheen_tint), before the weight of the base it
/// rides on.
#[inline]
pub(super) fn sheen(base: Rgb, sheen: f32, sheen_tint: f32, cos_oh: f32) -> Rgb {
    let tint = Rgb::ONE + (colour_tint(base) - Rgb::ONE) * sheen_tint;
    tint * (sheen * schlick_weight(cos_oh))
}

/// Burley's GTR1 normal distribution of roughness α (the clearcoat's), Mitsuba's
/// `GTR1Isotropic`: D(m) = (α² − 1)/(π ln α² (1 + (α² − 1) cos²θ_m)), sampled exactly from
/// D·cos θ_m.
#[derive(Clone, Copy, Debug)]
struct Gtr1 {
    alpha2: f32,
}

impl Gtr1 {
    fn new(clearcoat_gloss: f32) -> Self {
        let alpha = 0.1 * (1.0 - clearcoat_gloss) + 0.001 * clearcoat_gloss;
        Gtr1 { alpha2: alpha * alpha }
    }

    #[inline]
    fn d(&self, m: Vec3) -> f32 {
        let a2 = self.alpha2;
        let d = (a2 - 1.0) / (PI * a2.ln() * (1.0 + (a2 - 1.0) * m.z * m.z));
        if d * m.z > 1e-20 { d } else { 0.0 }
    }

    #[inline]
    fn pdf(&self, m: Vec3) -> f32 {
        if m.z < 0.0 { 0.0 } else { m.z * self.d(m) }
    }

    #[inline]
    fn sample(&self, u: Vec2) -> Vec3 {
        let (sin_phi, cos_phi) = (TAU * u.x).sin_cos();
        let a2 = self.alpha2;
        let cos2 = (1.0 - a2.powf(1.0 - u.y)) / (1.0 - a2);
        let (sin, cos) = ((1.0 - cos2).max(0.0).sqrt(), cos2.max(0.0).sqrt());
        Vec3::new(cos_phi * sin, sin_phi * sin, cos)
    }
}

/// Smith's separable GGX masking of roughness α for direction `v` and normal `h` (Mitsuba's
/// `smith_ggx1`, the clearcoat's, always with α = ¼); 0 on the back of the facet.
#[inline]
fn smith_ggx1(v: Vec3, h: Vec3, alpha: f32) -> f32 {
    if v.dot(h) * v.z <= 0.0 {
        return 0.0;
    }
    if v.z == 1.0 {
        return 1.0;
    }
    let cos2 = v.z * v.z;
    let tan2 = (1.0 - cos2) / cos2;
    2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

/// The lobe probabilities (diffuse, clearcoat, main specular), normalised.
#[derive(Clone, Copy, Debug)]
struct Lobes {
    diffuse: f32,
    clearcoat: f32,
    specular: f32,
}

impl Principled {
    /// The BSDF if its parameters are possible: colours and weights in [0, 1], η finite and
    /// positive, sampling rates finite and non-negative with the main specular one positive
    /// (the only lobe every point has).
    pub fn checked(self) -> Result<Self, MaterialError> {
        check_unit_colour("base_color", self.base_color)?;
        for (name, v) in self.unit_parameters() {
            if !v.is_finite() {
                return Err(MaterialError::NotFinite(name));
            }
            if !(0.0..=1.0).contains(&v) {
                return Err(MaterialError::OutOfUnitRange(name, v));
            }
        }
        super::check_positive("eta", self.eta)?;
        super::check_positive("main_specular_sampling_rate", self.specular_rate)?;
        for (name, v) in [
            ("diffuse_reflectance_sampling_rate", self.diffuse_rate),
            ("clearcoat_sampling_rate", self.clearcoat_rate),
        ] {
            if !v.is_finite() {
                return Err(MaterialError::NotFinite(name));
            }
            if v < 0.0 {
                return Err(MaterialError::Negative(name));
            }
        }
        Ok(self)
    }

    /// The parameters that must lie in [0, 1], by Mitsuba's names.
    fn unit_parameters(&self) -> [(&'static str, f32); 10] {
        [
            ("roughness", self.roughness),
            ("anisotropic", self.anisotropic),
            ("metallic", self.metallic),
            ("spec_tint", self.spec_tint),
            ("sheen", self.sheen),
            ("sheen_tint", self.sheen_tint),
            ("clearcoat", self.clearcoat),
            ("clearcoat_gloss", self.clearcoat_gloss),
            ("flatness", self.flatness),
            ("spec_trans", self.spec_trans),
        ]
    }

    /// The main lobe's GGX distribution (Mitsuba's `calc_dist_params`).
    #[inline]
    pub fn microfacet(&self) -> Microfacet {
        ggx(self.roughness, self.anisotropic)
    }

    /// The main lobe's Fresnel term F_p (module docs) for light arriving at `cos_i` = wi·h ≥ 0
    /// on a facet, given the dielectric reflectance `f_dielectric` there.
    #[inline]
    fn fresnel(&self, f_dielectric: f32, cos_i: f32) -> Rgb {
        tinted_fresnel(f_dielectric, cos_i, self.eta, self.metallic, self.spec_tint, self.base_color)
    }

    /// The base colour normalised by its luminance (white if black): the tint of `spec_tint`
    /// and `sheen_tint`.
    #[inline]
    fn colour_tint(&self) -> Rgb {
        colour_tint(self.base_color)
    }

    /// The lobes' sampling probabilities.
    #[inline]
    fn lobes(&self) -> Lobes {
        let diffuse = self.brdf_weight() * self.diffuse_rate;
        let clearcoat = 0.25 * self.clearcoat * self.clearcoat_rate;
        let specular = self.specular_rate;
        let inv = 1.0 / (diffuse + clearcoat + specular);
        Lobes { diffuse: diffuse * inv, clearcoat: clearcoat * inv, specular: specular * inv }
    }

    /// The weight (1 − m)(1 − t) of the diffuse base (Mitsuba's `brdf`).
    #[inline]
    pub(super) fn brdf_weight(&self) -> f32 {
        (1.0 - self.metallic) * (1.0 - self.spec_trans)
    }

    /// The weight (1 − m)·t of the rough dielectric lobe (Mitsuba's `bsdf`), 0 without it.
    #[inline]
    pub(super) fn bsdf_weight(&self) -> f32 {
        if self.has_spec_trans { (1.0 - self.metallic) * self.spec_trans } else { 0.0 }
    }

    /// f(wi → wo), the physical BSDF for light arriving from `wi` (module docs); without
    /// transmission zero unless both directions are above the surface.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !(wi.z > 0.0 && wo.z > 0.0) {
            return if self.has_spec_trans { self.eval_two_sided(wi, wo) } else { Rgb::ZERO };
        }
        let Some(h) = (wi + wo).try_normalize() else { return Rgb::ZERO };
        let (cos_i, cos_o, cos_ih, cos_oh) = (wi.z, wo.z, wi.dot(h), wo.dot(h));
        if !(cos_ih > 0.0 && cos_oh > 0.0) {
            return Rgb::ZERO;
        }
        let mut f = Rgb::ZERO;
        // Mitsuba's `fresnel` answers exactly 0 for matched indices (here rounding would not).
        let f_dielectric = if self.eta == 1.0 { 0.0 } else { fresnel::dielectric(cos_ih, self.eta).0 };
        if f_dielectric > 0.0 {
            let mf = self.microfacet();
            let dg = mf.d(h) * mf.g1_mitsuba(wi, h) * mf.g1_mitsuba(wo, h);
            f += self.fresnel(f_dielectric, cos_ih) * (dg / (4.0 * cos_i * cos_o));
        }
        if self.clearcoat > 0.0 {
            let f_cc = 0.04 + 0.96 * schlick_factor(cos_ih, self.eta);
            let d_cc = Gtr1::new(self.clearcoat_gloss).d(h);
            let g_cc = smith_ggx1(wi, h, 0.25) * smith_ggx1(wo, h, 0.25);
            f += Rgb::splat(0.25 * self.clearcoat * f_cc * d_cc * g_cc);
        }
        let brdf = self.brdf_weight();
        if brdf > 0.0 {
            let lobe = burley_diffuse(self.roughness, self.flatness, cos_i, cos_o, cos_oh);
            f += self.base_color * (brdf * FRAC_1_PI * lobe);
            // Sheen: weighted (1 − m), not reduced by spec_trans (Mitsuba's), but only with a
            // diffuse base.
            if self.sheen > 0.0 {
                let sheen = sheen(self.base_color, self.sheen, self.sheen_tint, cos_oh);
                f += sheen * (1.0 - self.metallic);
            }
        }
        f
    }

    /// The density of `wo` under [`Self::sample`] given `wi` (module docs).
    #[inline]
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if !(wi.z > 0.0 && wo.z > 0.0) {
            return if self.has_spec_trans { self.pdf_two_sided(wi, wo) } else { 0.0 };
        }
        let lobes = self.lobes();
        let mut pdf = lobes.diffuse * warp::cosine_hemisphere_pdf(wo);
        if let Some(h) = (wi + wo).try_normalize()
            && wi.dot(h) > 0.0
            && wo.dot(h) > 0.0
        {
            let dh_dwo = 1.0 / (4.0 * wo.dot(h));
            let reflect = self.reflection_share(wi.dot(h));
            pdf += lobes.specular * reflect * self.microfacet().visible_pdf(wi, h) * dh_dwo;
            if lobes.clearcoat > 0.0 {
                pdf += lobes.clearcoat * Gtr1::new(self.clearcoat_gloss).pdf(h) * dh_dwo;
            }
        }
        pdf
    }

    /// A direction of one lobe picked by `u_lobe` (diffuse, clearcoat, main specular
    /// transmission, main specular reflection, in Mitsuba's order), drawn from `u`; weight
    /// f·|cos θ_o|/pdf with the mixture's pdf, in `mode` (refraction differs, see
    /// `principled_trans.rs`). `None` from behind without transmission or when the scattered
    /// direction falls on the wrong side of the surface or of its facet.
    #[inline]
    pub fn sample(&self, wi: Vec3, u_lobe: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if !(wi.z > 0.0) {
            return if self.has_spec_trans { self.sample_back(wi, u_lobe, u, mode) } else { None };
        }
        let lobes = self.lobes();
        let wo = if u_lobe < lobes.diffuse {
            warp::square_to_cosine_hemisphere(u)
        } else {
            let cc = lobes.diffuse + lobes.clearcoat;
            let m = if u_lobe < cc {
                Gtr1::new(self.clearcoat_gloss).sample(u)
            } else {
                let m = self.microfacet().sample_visible(wi, u);
                if self.has_spec_trans
                    && u_lobe < cc + lobes.specular * (1.0 - self.reflection_share(wi.dot(m)))
                {
                    return self.refracted_sample(wi, m, mode);
                }
                m
            };
            let wo = 2.0 * wi.dot(m) * m - wi;
            // A reflection must stay above the surface (with transmission, eval and pdf
            // below it are the refraction's).
            if !(wi.dot(m) > 0.0 && wo.dot(m) > 0.0 && wo.z > 0.0) {
                return None;
            }
            wo
        };
        BsdfSample::of_density(wo, self.pdf(wi, wo), || self.eval(wi, wo))
    }

    /// A bound of the directional albedo per channel in importance mode (not tight: the sum of
    /// each lobe's largest reflectance or transmittance; Burley's diffuse with retro-reflection may exceed the base colour,
    /// by at most a factor 2 at grazing angles).
    pub fn max_albedo(&self) -> Rgb {
        let brdf = self.brdf_weight();
        let specular = Rgb::ONE.max(self.colour_tint() * self.spec_tint);
        let diffuse = self.base_color * (2.0 * brdf);
        let sheen = (Rgb::ONE.max(self.colour_tint())) * (self.sheen * (1.0 - self.metallic));
        let transmission = self.transmission_colour() * self.bsdf_weight();
        specular + diffuse + sheen + transmission + Rgb::splat(0.25 * self.clearcoat)
    }
}

#[path = "principled_trans.rs"]
mod trans;

#[cfg(test)]
#[path = "principled_tests.rs"]
mod tests;
