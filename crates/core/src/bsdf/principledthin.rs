//! Mitsuba 3's `principledthin` BSDF (src/bsdfs/principledthin.cpp): the principled model of a
//! sheet with no inside (a leaf, paper, a curtain). Light meets it from either face and the two
//! faces are alike, so every query is turned to the face wi arrives on (both directions
//! flipped with the sign of wi.z); its "transmission" continues to the other face without
//! bending (no η change across the sheet: η only sets the Fresnel split and roughens the
//! transmitted lobe). Not a refraction, so nothing is scaled by η² in either transport mode.
//!
//! With wi on the +z side, wo′ = (wo.x, wo.y, |wo.z|) (wo mirrored to wi's face), h the half
//! vector of wi and wo′, c `base_color`, t `spec_trans`, d = `diff_trans`/2 (Mitsuba's range
//! [0, 2] made [0, 1]), F = F_dielectric(wi·h, η) and D, G the GGX terms (Mitsuba's separable
//! G₁(wi)·G₁(wo), `super::Principled`'s distribution):
//!
//! ```text
//! wo on wi's face:     t·F_thin·D·G / (4 cos θ_i cos θ_o)                       specular reflection
//!                    + (1 − t)(1 − d)·c/π·lerp(f_d + f_r, f_ss, flatness)       diffuse (principled's)
//!                    + (1 − t)(1 − d)·sheen lobe                                sheen (principled's)
//! wo on the far face:  t·c·(1 − F)·D_s·G_s(wi, wo) / (4 cos θ_i |cos θ_o|)      rough thin transmission
//!                    + (1 − t)·d·c/π                                            diffuse transmission
//! F_thin = lerp(F, F_s(c/lum(c)·R₀(η)), spec_tint)
//! ```
//!
//! where D_s, G_s are GGX of the roughness scaled by (0.65η − 0.35) (Burley 2015, fig. 15) and
//! G_s(wi, wo) is evaluated with wo itself (on the far face), as Mitsuba does: G₁(wo) is zero
//! unless wo·h < 0, the same condition as the facet's (`mac_mic_compatibility`).
//!
//! # Transport modes
//!
//! Mitsuba's `eval(wi, wo)` ignores the transport mode: its path tracer reads it as the
//! radiance-mode value f(wo → wi) (`wi` toward the camera). That is the model, and Opticks's
//! physical f(wi → wo) is therefore Mitsuba's value with its arguments swapped. Every term is
//! symmetric in wi and wo except the transmission's masking (G₁(wo) only vanishes for wo·h ≥ 0,
//! G₁(wi) never), so f is reciprocal wherever both f(a → b) and f(b → a) are non-zero; where
//! only one is, the light tracer's importance weights must take f(wi → wo) (the adjoint of
//! Mitsuba's radiance BSDF), which is what [`TransportMode::Importance`] gives (Mitsuba's own
//! light tracer would take its radiance value there).
//!
//! # Sampling
//!
//! As Mitsuba: a lobe by the probabilities specular reflection t·`specular_reflectance_rate`/2,
//! specular transmission t·`specular_transmittance_rate`/2, diffuse reflection
//! (1 − t)(1 − d)·`diffuse_reflectance_rate`, diffuse transmission (1 − t)·d·
//! `diffuse_transmittance_rate`, normalised; the specular lobes reflect wi about a GGX normal
//! visible from wi (the transmission about one of the scaled distribution, then mirror the
//! result to the far face), the diffuse ones draw a cosine-weighted direction on wi's face or on
//! the far one. `pdf` is that mixture; the weight f·|cos θ_o|/pdf in the requested mode.

use super::principled::{burley_diffuse, ggx, sheen, tinted_fresnel};
use super::{BsdfSample, MaterialError, TransportMode, check_unit_colour, fresnel};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::microfacet::Microfacet;
use crate::sampling::warp;
use std::f32::consts::FRAC_1_PI;

/// Mitsuba 3's `principledthin` BSDF (see the module docs). The fields are Mitsuba's parameters;
/// textures set them point by point (`crate::texture::set_principled`).
#[derive(Clone, Debug, PartialEq)]
pub struct PrincipledThin {
    /// `base_color` c, in [0, 1] per channel.
    pub base_color: Rgb,
    /// `roughness` of the specular lobes (the transmission's scaled by 0.65η − 0.35), in [0, 1].
    pub roughness: f32,
    /// `anisotropic`: 0 isotropic, 1 the most anisotropic (α_x / α_y = 1/(1 − 0.9)).
    pub anisotropic: f32,
    /// `spec_trans` t: the share of the rough specular sheet (reflection and transmission)
    /// instead of the diffuse base, in [0, 1].
    pub spec_trans: f32,
    /// `eta`: the sheet's relative index of refraction (Fresnel split and transmission roughness).
    pub eta: f32,
    /// `spec_tint`: the share of the specular reflection tinted towards the base colour.
    pub spec_tint: f32,
    /// `sheen`: the weight of the grazing sheen lobe.
    pub sheen: f32,
    /// `sheen_tint`: how far the sheen is tinted towards the base colour.
    pub sheen_tint: f32,
    /// `flatness`: blend of the diffuse lobe towards Hanrahan–Krueger's fake subsurface.
    pub flatness: f32,
    /// `diff_trans`, in [0, 2] as Mitsuba's: twice the share of the diffuse base that is
    /// transmitted (Lambertian) instead of reflected.
    pub diff_trans: f32,
    /// `specular_reflectance_sampling_rate` (≥ 0).
    pub spec_reflect_rate: f32,
    /// `specular_transmittance_sampling_rate` (≥ 0).
    pub spec_trans_rate: f32,
    /// `diffuse_reflectance_sampling_rate` (≥ 0).
    pub diffuse_reflect_rate: f32,
    /// `diffuse_transmittance_sampling_rate` (≥ 0).
    pub diffuse_trans_rate: f32,
}

impl Default for PrincipledThin {
    /// Mitsuba's defaults: base colour 0.5, roughness 0.5, η 1.5, every other weight 0,
    /// sampling rates 1.
    fn default() -> Self {
        PrincipledThin {
            base_color: Rgb::splat(0.5),
            roughness: 0.5,
            anisotropic: 0.0,
            spec_trans: 0.0,
            eta: 1.5,
            spec_tint: 0.0,
            sheen: 0.0,
            sheen_tint: 0.0,
            flatness: 0.0,
            diff_trans: 0.0,
            spec_reflect_rate: 1.0,
            spec_trans_rate: 1.0,
            diffuse_reflect_rate: 1.0,
            diffuse_trans_rate: 1.0,
        }
    }
}

/// The lobe probabilities (specular reflection, specular transmission, diffuse reflection,
/// diffuse transmission), normalised; all zero if every rate of a present lobe is zero.
#[derive(Clone, Copy, Debug)]
struct Lobes {
    spec_reflect: f32,
    spec_trans: f32,
    diffuse_reflect: f32,
    diffuse_trans: f32,
}

/// `v` (and `w` with it) turned to the face `v` is on: both flipped when v.z < 0.
#[inline]
fn to_front(v: Vec3, w: Vec3) -> (Vec3, Vec3) {
    if v.z < 0.0 { (-v, -w) } else { (v, w) }
}

/// The half vector of `wi` (z > 0) and `wo` mirrored to wi's face; `None` if degenerate.
#[inline]
fn half_vector(wi: Vec3, wo: Vec3) -> Option<Vec3> {
    (wi + Vec3::new(wo.x, wo.y, wo.z.abs())).try_normalize()
}

impl PrincipledThin {
    /// The BSDF if its parameters are possible: colour and weights in [0, 1] (`diff_trans` in
    /// [0, 2]), η finite and positive, sampling rates finite and non-negative.
    pub fn checked(self) -> Result<Self, MaterialError> {
        check_unit_colour("base_color", self.base_color)?;
        for (name, v, max) in self.bounded_parameters() {
            if !v.is_finite() {
                return Err(MaterialError::NotFinite(name));
            }
            if !(0.0..=max).contains(&v) {
                return Err(if max == 1.0 {
                    MaterialError::OutOfUnitRange(name, v)
                } else if v < 0.0 {
                    MaterialError::Negative(name)
                } else {
                    MaterialError::TooLarge { name, value: v, max }
                });
            }
        }
        super::check_positive("eta", self.eta)?;
        for (name, v) in [
            ("specular_reflectance_sampling_rate", self.spec_reflect_rate),
            ("specular_transmittance_sampling_rate", self.spec_trans_rate),
            ("diffuse_reflectance_sampling_rate", self.diffuse_reflect_rate),
            ("diffuse_transmittance_sampling_rate", self.diffuse_trans_rate),
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

    /// The bounded parameters by Mitsuba's names, with their largest value (the least is 0).
    fn bounded_parameters(&self) -> [(&'static str, f32, f32); 8] {
        [
            ("roughness", self.roughness, 1.0),
            ("anisotropic", self.anisotropic, 1.0),
            ("spec_trans", self.spec_trans, 1.0),
            ("spec_tint", self.spec_tint, 1.0),
            ("sheen", self.sheen, 1.0),
            ("sheen_tint", self.sheen_tint, 1.0),
            ("flatness", self.flatness, 1.0),
            ("diff_trans", self.diff_trans, 2.0),
        ]
    }

    /// The specular reflection's GGX distribution (principled's).
    #[inline]
    fn reflection_microfacet(&self) -> Microfacet {
        ggx(self.roughness, self.anisotropic)
    }

    /// The specular transmission's GGX distribution: the roughness scaled by 0.65η − 0.35.
    #[inline]
    fn transmission_microfacet(&self) -> Microfacet {
        ggx((0.65 * self.eta - 0.35) * self.roughness, self.anisotropic)
    }

    /// d = `diff_trans`/2, the transmitted share of the diffuse base.
    #[inline]
    fn diffuse_trans_share(&self) -> f32 {
        0.5 * self.diff_trans
    }

    /// The lobes' sampling probabilities.
    #[inline]
    fn lobes(&self) -> Lobes {
        let (t, d) = (self.spec_trans, self.diffuse_trans_share());
        let spec_reflect = 0.5 * t * self.spec_reflect_rate;
        let spec_trans = 0.5 * t * self.spec_trans_rate;
        let diffuse_reflect = (1.0 - t) * (1.0 - d) * self.diffuse_reflect_rate;
        let diffuse_trans = (1.0 - t) * d * self.diffuse_trans_rate;
        let total = spec_reflect + spec_trans + diffuse_reflect + diffuse_trans;
        let inv = if total > 0.0 { 1.0 / total } else { 0.0 };
        Lobes {
            spec_reflect: spec_reflect * inv,
            spec_trans: spec_trans * inv,
            diffuse_reflect: diffuse_reflect * inv,
            diffuse_trans: diffuse_trans * inv,
        }
    }

    /// Mitsuba's `eval(wi = a, wo = b)` divided by |cos θ_b|: the radiance-mode f(b → a), light
    /// leaving along `a` (module docs).
    fn mitsuba_value(&self, a: Vec3, b: Vec3) -> Rgb {
        if a.z == 0.0 || b.z == 0.0 {
            return Rgb::ZERO;
        }
        let (wi, wo) = to_front(a, b);
        let Some(h) = half_vector(wi, wo) else { return Rgb::ZERO };
        let (cos_i, cos_o, ih, oh) = (wi.z, wo.z, wi.dot(h), wo.dot(h));
        let reflect = cos_o > 0.0;
        let (t, d, c) = (self.spec_trans, self.diffuse_trans_share(), self.base_color);
        let mut f = Rgb::ZERO;
        if t > 0.0 && ih > 0.0 && (oh > 0.0) == reflect && oh != 0.0 {
            // Mitsuba's `fresnel` answers exactly 0 for matched indices (here rounding would not).
            let f_dielectric = if self.eta == 1.0 { 0.0 } else { fresnel::dielectric(ih, self.eta).0 };
            let denom = 4.0 * cos_i * cos_o.abs();
            if reflect {
                let mf = self.reflection_microfacet();
                let dg = mf.d(h) * mf.g1_mitsuba(wi, h) * mf.g1_mitsuba(wo, h);
                let tinted = tinted_fresnel(f_dielectric, ih, self.eta, 0.0, self.spec_tint, c);
                f += tinted * (t * dg / denom);
            } else {
                let mf = self.transmission_microfacet();
                let dg = mf.d(h) * mf.g1_mitsuba(wi, h) * mf.g1_mitsuba(wo, h);
                f += c * (t * (1.0 - f_dielectric) * dg / denom);
            }
        }
        if t < 1.0 {
            if reflect && d < 1.0 {
                let base = (1.0 - t) * (1.0 - d);
                let lobe = burley_diffuse(self.roughness, self.flatness, cos_i, cos_o, oh);
                f += c * (base * FRAC_1_PI * lobe);
                if self.sheen > 0.0 {
                    f += sheen(c, self.sheen, self.sheen_tint, oh.abs()) * base;
                }
            } else if !reflect && d > 0.0 {
                f += c * ((1.0 - t) * d * FRAC_1_PI);
            }
        }
        f
    }

    /// f(wi → wo), the physical BSDF for light arriving from `wi` (module docs), either face.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        self.mitsuba_value(wo, wi)
    }

    /// The density of `wo` under [`Self::sample`] given `wi`, either face (module docs).
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z == 0.0 || wo.z == 0.0 {
            return 0.0;
        }
        let (wi, wo) = to_front(wi, wo);
        let lobes = self.lobes();
        let reflect = wo.z > 0.0;
        let mut pdf = 0.0;
        if lobes.spec_reflect + lobes.spec_trans > 0.0
            && let Some(h) = half_vector(wi, wo)
        {
            let oh = wo.dot(h);
            if wi.dot(h) > 0.0 && oh != 0.0 && (oh > 0.0) == reflect {
                let (p, mf) = if reflect {
                    (lobes.spec_reflect, self.reflection_microfacet())
                } else {
                    (lobes.spec_trans, self.transmission_microfacet())
                };
                // dω_h/dω_o of the reflection that made wo′ (the mirrored wo).
                let mirrored_oh = Vec3::new(wo.x, wo.y, wo.z.abs()).dot(h);
                pdf += p * mf.visible_pdf(wi, h) / (4.0 * mirrored_oh);
            }
        }
        let p_diffuse = if reflect { lobes.diffuse_reflect } else { lobes.diffuse_trans };
        pdf + p_diffuse * warp::cosine_hemisphere_pdf(Vec3::new(wo.x, wo.y, wo.z.abs()))
    }

    /// A direction of one lobe picked by `u_lobe` (specular reflection, specular transmission,
    /// diffuse reflection, diffuse transmission, Mitsuba's order), drawn from `u`; weight
    /// f·|cos θ_o|/pdf with the mixture's pdf: f(wi → wo) in importance mode, f(wo → wi) in
    /// radiance mode. `None` for wi in the plane, or when the direction falls on the wrong side
    /// of its facet or face.
    pub fn sample(&self, wi: Vec3, u_lobe: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if wi.z == 0.0 {
            return None;
        }
        let sign = wi.z.signum();
        let front = wi * sign;
        let lobes = self.lobes();
        let specular = lobes.spec_reflect + lobes.spec_trans;
        let wo = if u_lobe < specular {
            let reflect = u_lobe < lobes.spec_reflect;
            let mf = if reflect { self.reflection_microfacet() } else { self.transmission_microfacet() };
            let m = mf.sample_visible(front, u);
            let r = 2.0 * front.dot(m) * m - front;
            let wo = if reflect { r } else { Vec3::new(r.x, r.y, -r.z) };
            let facet_ok = front.dot(m) > 0.0 && if reflect { wo.dot(m) > 0.0 } else { wo.dot(m) < 0.0 };
            if !(facet_ok && (wo.z > 0.0) == reflect && wo.z != 0.0) {
                return None;
            }
            wo
        } else if u_lobe < specular + lobes.diffuse_reflect {
            warp::square_to_cosine_hemisphere(u)
        } else if lobes.diffuse_trans > 0.0 {
            -warp::square_to_cosine_hemisphere(u)
        } else {
            return None;
        };
        let wo = wo * sign;
        BsdfSample::of_density(wo, self.pdf(wi, wo), || match mode {
            TransportMode::Importance => self.eval(wi, wo),
            TransportMode::Radiance => self.eval(wo, wi),
        })
    }

    /// A bound of the directional albedo per channel (not tight: the sum of each lobe's largest
    /// share; Burley's diffuse with retro-reflection may exceed the base colour by at most a
    /// factor 2 at grazing angles).
    pub fn max_albedo(&self) -> Rgb {
        let (t, d) = (self.spec_trans, self.diffuse_trans_share());
        let specular = t * (Rgb::ONE.max(super::principled::colour_tint(self.base_color) * self.spec_tint));
        let diffuse = self.base_color * ((1.0 - t) * ((1.0 - d) * 2.0 + d));
        let sheen = Rgb::ONE.max(super::principled::colour_tint(self.base_color)) * (self.sheen * (1.0 - t));
        specular + self.base_color * t + diffuse + sheen
    }
}

#[cfg(test)]
#[path = "principledthin_tests.rs"]
mod tests;
