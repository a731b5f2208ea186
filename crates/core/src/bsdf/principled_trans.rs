//! The transmission lobe of Mitsuba 3's `principled` BSDF (`spec_trans` > 0,
//! [`Principled::has_spec_trans`]) and the back side it opens: Mitsuba's principled.cpp with
//! `m_has_spec_trans`. The BSDF is then oriented like a dielectric: +z is the outside, −z the
//! inside, η the relative index inside/outside; η_p = η for light arriving from outside
//! (wi.z > 0), 1/η from inside.
//!
//! With b = (1 − m)·t (`spec_trans` t, `metallic` m) the weight of the rough dielectric, h the
//! generalised half vector ∝ wi + η_p·wo for a refraction (wi + wo for a reflection) turned to
//! +z, F = F_dielectric(wi·h, η) (from wi's side) and D, G the main lobe's GGX terms:
//!
//! ```text
//! front (wi.z > 0), wo above:   the reflective lobes of `principled.rs` (diffuse weight (1 − m)(1 − t))
//! back  (wi.z < 0), wo below:   b·F·D·G / (4 |cos θ_i| |cos θ_o|)      (no tint, no metal, no diffuse)
//! either side, wo across:        √c · b · (1 − F)·D·G·η_p²·|wi·h||wo·h| / (|cos θ_i||cos θ_o| (wi·h + η_p wo·h)²)
//! ```
//!
//! This is the physical f(wi → wo) for light arriving from wi, Mitsuba's `eval` in
//! `TransportMode::Importance`. Refraction is not reciprocal: f(a→b)/η_b² = f(b→a)/η_a²
//! (tested), so Mitsuba's radiance-mode value (its default), f(wo → wi), carries the extra
//! factor 1/η_p², and the sample weights of [`TransportMode::Radiance`] are divided by η_p² as
//! the rough dielectric's. Opticks's light tracer uses the importance weights (the adjoint of
//! the radiance BSDF), as it does for `roughdielectric`.
//!
//! Sampling as Mitsuba: a normal m visible from wi (from −wi inside) is drawn first; then the
//! lobe by the probabilities, from outside, diffuse (1 − m)(1 − t)·`diffuse_rate`, clearcoat
//! ¼·clearcoat·`clearcoat_rate`, refraction `specular_rate`·b·(1 − F(wi·m)), main reflection
//! `specular_rate`·(1 − b·(1 − F(wi·m))), normalised; from inside refraction 1 − F, reflection
//! F (no diffuse, no clearcoat). `pdf` is that mixture, with dω_h/dω_o = η_p²|wo·h|/(wi·h +
//! η_p wo·h)² for refraction.
//!
//! One deliberate difference: where b = 0 at a point (`metallic` 1, or a `spec_trans` texture
//! at 0) the back side scatters nothing here, `pdf` included; Mitsuba's `pdf` there still
//! answers the back reflection's density although its `eval` and `sample` give nothing.

use super::{BsdfSample, Principled, TransportMode, fresnel};
use crate::math::{Rgb, Vec2, Vec3};

/// Mitsuba's `fresnel(cos_i, η)`: the dielectric reflectance and cos θ_t (≥ 0) for a cosine
/// of either sign, η inverted when light arrives from below the facet.
#[inline]
fn fresnel_signed(cos_i: f32, eta: f32) -> (f32, f32) {
    if cos_i >= 0.0 { fresnel::dielectric(cos_i, eta) } else { fresnel::dielectric(-cos_i, 1.0 / eta) }
}

impl Principled {
    /// The share 1 − b·(1 − F(`cos_i`)) of the main specular sampling rate that reflects from
    /// outside (1 without transmission, where F is not computed).
    #[inline]
    pub(super) fn reflection_share(&self, cos_i: f32) -> f32 {
        let b = self.bsdf_weight();
        if b > 0.0 { 1.0 - b * (1.0 - fresnel_signed(cos_i, self.eta).0) } else { 1.0 }
    }

    /// The colour √c the transmission is tinted with.
    #[inline]
    pub(super) fn transmission_colour(&self) -> Rgb {
        let c = self.base_color;
        Rgb::new(c.x.sqrt(), c.y.sqrt(), c.z.sqrt())
    }

    /// η_p, the index of wo's side over wi's for a refraction from the side of `cos_i`.
    #[inline]
    fn eta_path(&self, cos_i: f32) -> f32 {
        if cos_i > 0.0 { self.eta } else { 1.0 / self.eta }
    }

    /// The half vector of (wi, wo) turned to +z, whether the pair is a reflection, and whether
    /// the facet is compatible with both directions (Mitsuba's `mac_mic_compatibility`);
    /// `None` for a direction in the plane or a degenerate pair.
    #[inline]
    fn half_vector(&self, wi: Vec3, wo: Vec3) -> Option<(Vec3, bool)> {
        if wi.z == 0.0 || wo.z == 0.0 {
            return None;
        }
        let reflect = wi.z * wo.z > 0.0;
        let h = (wi + wo * if reflect { 1.0 } else { self.eta_path(wi.z) }).try_normalize()?;
        let h = if h.z < 0.0 { -h } else { h };
        let hs = if wi.z > 0.0 { h } else { -h };
        let ok = wi.dot(hs) > 0.0 && if reflect { wo.dot(hs) > 0.0 } else { wo.dot(hs) < 0.0 };
        ok.then_some((h, reflect))
    }

    /// f(wi → wo) of every pair but front-to-front (module docs), with transmission.
    pub(super) fn eval_two_sided(&self, wi: Vec3, wo: Vec3) -> Rgb {
        let b = self.bsdf_weight();
        if !(b > 0.0) {
            return Rgb::ZERO;
        }
        let Some((h, reflect)) = self.half_vector(wi, wo) else { return Rgb::ZERO };
        let (ih, oh) = (wi.dot(h), wo.dot(h));
        let f = fresnel_signed(ih, self.eta).0;
        let mf = self.microfacet();
        let dg = mf.d(h) * mf.g1_mitsuba(wi, h) * mf.g1_mitsuba(wo, h);
        let (ci, co) = (wi.z.abs(), wo.z.abs());
        if reflect {
            // Only from inside (front-to-front is `eval`'s): the bare dielectric reflection.
            return Rgb::splat(if f > 0.0 { b * f * dg / (4.0 * ci * co) } else { 0.0 });
        }
        if !(f < 1.0) {
            return Rgb::ZERO;
        }
        let eta = self.eta_path(wi.z);
        let denom = ih + eta * oh;
        let v = b * (1.0 - f) * dg * eta * eta * (ih * oh).abs() / (ci * co * denom * denom);
        self.transmission_colour() * v
    }

    /// The density of every pair but front-to-front (module docs), with transmission.
    pub(super) fn pdf_two_sided(&self, wi: Vec3, wo: Vec3) -> f32 {
        let b = self.bsdf_weight();
        let front = wi.z > 0.0;
        if !(b > 0.0) && !front {
            return 0.0;
        }
        let Some((h, reflect)) = self.half_vector(wi, wo) else { return 0.0 };
        let (ih, oh) = (wi.dot(h), wo.dot(h));
        let f = fresnel_signed(ih, self.eta).0;
        let eta = self.eta_path(wi.z);
        let visible = self.microfacet().visible_pdf(if front { wi } else { -wi }, h);
        let (p_reflect, p_refract) = if front {
            let lobes = self.lobes();
            (0.0, lobes.specular * b * (1.0 - f))
        } else {
            (f, 1.0 - f)
        };
        if reflect {
            // From inside only (front-to-front is `pdf`'s).
            p_reflect * visible / (4.0 * oh.abs())
        } else {
            let denom = ih + eta * oh;
            p_refract * visible * (eta * eta * oh.abs() / (denom * denom))
        }
    }

    /// The sample of a refraction through the normal `m` (z > 0) visible from `wi` (from `−wi`
    /// inside): `None` under total internal reflection or if the refracted direction is on the
    /// wrong side of the surface or of the facet.
    pub(super) fn refracted_sample(&self, wi: Vec3, m: Vec3, mode: TransportMode) -> Option<BsdfSample> {
        let ms = if wi.z > 0.0 { m } else { -m };
        let eta = self.eta_path(wi.z);
        let (f, cos_t) = fresnel::dielectric(wi.dot(ms), eta);
        if !(f < 1.0) {
            return None;
        }
        let wo = fresnel::refract(wi, ms, eta, cos_t);
        if !(wi.z * wo.z < 0.0 && wo.dot(ms) < 0.0) {
            return None;
        }
        let s = BsdfSample::of_density(wo, self.pdf(wi, wo), || self.eval(wi, wo))?;
        Some(match mode {
            TransportMode::Importance => s,
            TransportMode::Radiance => BsdfSample { weight: s.weight / (eta * eta), ..s },
        })
    }

    /// Light arriving from inside (wi.z < 0): refraction out with probability 1 − F(wi·m),
    /// else reflection back inside, about a GGX normal m visible from −wi.
    pub(super) fn sample_back(
        &self,
        wi: Vec3,
        u_lobe: f32,
        u: Vec2,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        if !(wi.z < 0.0 && self.bsdf_weight() > 0.0) {
            return None;
        }
        let m = self.microfacet().sample_visible(-wi, u);
        let f = fresnel_signed(wi.dot(m), self.eta).0;
        if u_lobe < 1.0 - f {
            return self.refracted_sample(wi, m, mode);
        }
        let wo = 2.0 * wi.dot(m) * m - wi;
        if !(wo.z < 0.0 && wi.dot(m) < 0.0 && wo.dot(m) < 0.0) {
            return None;
        }
        BsdfSample::of_density(wo, self.pdf(wi, wo), || self.eval(wi, wo))
    }
}
