//! BSDFs: how a surface scatters light. A closed set, dispatched by `match` ([`Bsdf`]).
//!
//! Conventions (shared by every BSDF here):
//! * Directions are in the local shading frame (z = normal) and point **away** from the surface.
//! * `wi` is the direction light arrived from (in light tracing, toward the previous vertex);
//!   `wo` the direction it leaves in. For reflection-only BSDFs callers guarantee `wi.z > 0`
//!   (the [`Material`] flips two-sided surfaces and blackens the back of one-sided ones) and the
//!   BSDF returns zero when `wo.z <= 0`. Dielectrics ([`SmoothDielectric`], [`RoughDielectric`])
//!   are oriented instead: +z is the outside (index `ext_ior`), −z the inside (`int_ior`); they
//!   accept `wi` on either side and `wo` on either side (refraction). [`Material::frame_for`]
//!   never flips their frame.
//! * `eval(wi, wo)` returns the **physical** BSDF f(wi → wo) (no cosine) for light that arrives
//!   from `wi` and leaves along `wo`, i.e. the factor of the path integral at this vertex in the
//!   order light flows. `sample` returns `weight = f · |cos θ_o| / pdf` in the requested
//!   [`TransportMode`].
//!
//! # Transport mode and the adjoint (docs/estimator.md §4)
//!
//! Every vertex factor of the measurement contribution is f(x_{i−1} → x_i → x_{i+1}) in the
//! order light flows. Opticks's `eval(wi, wo)` takes its arguments in that order, so **one
//! function serves both of its uses**: the light tracer's weight update β ← β·f(wi→wo)|cos θ_o|/p
//! and the sensor's connection f(from_dir → to_camera) (the camera sees the radiance leaving a
//! stored vertex toward it, which is exactly f in light-flow order). What is *not* symmetric is
//! the refraction term: f(a→b) for transmission carries a factor η_b² (the index on the side
//! light leaves into), so f(a→b)/η_b² = f(b→a)/η_a² (generalized reciprocity, Veach's thesis
//! §5.2) rather than f(a→b) = f(b→a). Sampling therefore depends on which end of the path the
//! given direction belongs to:
//! * [`TransportMode::Importance`] (light paths, the only mode Opticks's tracer uses): the given
//!   direction is where light came from and the sampled one is where it goes; the weight is
//!   f(given → sampled)·|cos|/p. For a smooth dielectric that is (1 − F)·T: flux is conserved
//!   through an interface, and **no 1/η² factor appears**.
//! * [`TransportMode::Radiance`] (camera paths, for a future path tracer or tests): the given
//!   direction is toward the camera and the sampled one toward the light; the weight is
//!   f(sampled → given)·|cos|/p, which for refraction is the importance weight times
//!   (η_given/η_sampled)², the familiar radiance scaling of pbrt's `TransportMode::Radiance`.
//!   Reflection weights are the same in both modes.
mod blend;
#[cfg(test)]
pub(crate) mod chi2;
mod conductor;
mod dielectric;
pub mod fresnel;
mod lambert;
mod phong;
mod plastic;
mod principled;
#[cfg(test)]
mod principled_mitsuba;
mod principledthin;
#[cfg(test)]
mod principledthin_mitsuba;
mod roughplastic;
#[cfg(test)]
mod roughplastic_mitsuba;
pub mod shading;
mod thin;

pub use blend::Blend;
pub use conductor::{RoughConductor, SmoothConductor};
pub use dielectric::{RoughDielectric, SmoothDielectric, check_absorption};
pub use lambert::Lambert;
pub use phong::ModifiedPhong;
pub use plastic::Plastic;
pub use principled::{Principled, eta_of_specular};
pub use principledthin::PrincipledThin;
pub use roughplastic::RoughPlastic;
pub use thin::ThinDielectric;

use crate::geometry::SurfaceNormals;
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::microfacet::Microfacet;
pub use shading::{Direction, LocalFrame, ShadingPoint};

/// A direction sampled from a BSDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// Sampled outgoing direction (local frame, unit length).
    pub wo: Vec3,
    /// f_r · cos θ_o / pdf.
    pub weight: Rgb,
    /// Solid-angle density of `wo`; for a `delta` sample, the discrete probability of the chosen
    /// lobe (reflection or refraction) instead.
    pub pdf: f32,
    /// Whether `wo` was picked by a Dirac delta (ideal mirror or smooth dielectric): `eval` and
    /// `pdf` are zero for such a pair.
    pub delta: bool,
}

impl BsdfSample {
    /// The non-delta sample `wo` of a BSDF whose density there is `pdf` and whose f_r is
    /// `f()`, weighted f_r·(|cos θ_o| / pdf); `None` where the density is not positive and finite
    /// or the weight not finite (what the mixture BSDFs, rough plastic and principled, share).
    #[inline]
    pub(crate) fn of_density(wo: Vec3, pdf: f32, f: impl FnOnce() -> Rgb) -> Option<BsdfSample> {
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight = f() * (wo.z.abs() / pdf);
        weight.is_finite().then_some(BsdfSample { wo, weight, pdf, delta: false })
    }
}

/// Which end of a path the given direction of [`Bsdf::sample`] belongs to (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    /// Light paths: the given direction is where light came from; weights are f(given→sampled)·
    /// |cos θ_sampled|/p. Opticks's tracer uses this mode.
    Importance,
    /// Camera paths: the given direction is toward the camera; weights are f(sampled→given)·
    /// |cos θ_sampled|/p (refraction gains the (η_given/η_sampled)² radiance scaling).
    Radiance,
}

/// The closed set of BSDFs.
#[derive(Clone, Debug, PartialEq)]
pub enum Bsdf {
    /// Ideal diffuse reflector.
    Lambert(Lambert),
    /// Modified Phong of Lafortune & Willems 1994 (the thesis's material model).
    ModifiedPhong(ModifiedPhong),
    /// Ideal mirror, optionally with a conductor's Fresnel reflectance (delta).
    SmoothConductor(SmoothConductor),
    /// Smooth glass-like interface: Fresnel reflection and refraction (delta, oriented).
    SmoothDielectric(SmoothDielectric),
    /// Microfacet conductor (GGX or Beckmann, isotropic or anisotropic).
    RoughConductor(RoughConductor),
    /// Microfacet dielectric interface (GGX or Beckmann; oriented).
    RoughDielectric(RoughDielectric),
    /// Smooth plastic: a diffuse base under a dielectric coating (a delta lobe and a diffuse one).
    Plastic(Plastic),
    /// Rough plastic (Mitsuba's `roughplastic`): a diffuse base under a microfacet coating.
    RoughPlastic(RoughPlastic),
    /// A blend of two BSDFs (Mitsuba's `blendbsdf`), boxed: the enum stays small.
    Blend(Blend),
    /// Thin dielectric sheet: delta reflection and straight delta transmission (oriented by
    /// nothing: the same on both faces).
    ThinDielectric(ThinDielectric),
    /// Mitsuba's `principled` (Disney) BSDF: one-sided and reflective, or oriented and
    /// transmitting with its `spec_trans` lobe.
    Principled(Principled),
    /// Mitsuba's `principledthin`: a thin sheet, the same from both faces, reflecting and
    /// transmitting without refraction.
    PrincipledThin(PrincipledThin),
}

impl Bsdf {
    /// The physical f(wi → wo) (light arrives from `wi`, leaves along `wo`), local frame; zero
    /// for delta BSDFs.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        match self {
            Bsdf::Lambert(b) => b.eval(wi, wo),
            Bsdf::ModifiedPhong(b) => b.eval(wi, wo),
            Bsdf::SmoothConductor(_) | Bsdf::SmoothDielectric(_) | Bsdf::ThinDielectric(_) => Rgb::ZERO,
            Bsdf::RoughConductor(b) => b.eval(wi, wo),
            Bsdf::RoughDielectric(b) => b.eval(wi, wo),
            Bsdf::Plastic(b) => b.eval(wi, wo),
            Bsdf::RoughPlastic(b) => b.eval(wi, wo),
            Bsdf::Blend(b) => b.eval(wi, wo),
            Bsdf::Principled(b) => b.eval(wi, wo),
            Bsdf::PrincipledThin(b) => b.eval(wi, wo),
        }
    }

    /// Density with which [`Bsdf::sample`] picks `wo` given `wi` (the same in both transport
    /// modes); zero for delta BSDFs.
    #[inline]
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        match self {
            Bsdf::Lambert(b) => b.pdf(wi, wo),
            Bsdf::ModifiedPhong(b) => b.pdf(wi, wo),
            Bsdf::SmoothConductor(_) | Bsdf::SmoothDielectric(_) | Bsdf::ThinDielectric(_) => 0.0,
            Bsdf::RoughConductor(b) => b.pdf(wi, wo),
            Bsdf::RoughDielectric(b) => b.pdf(wi, wo),
            Bsdf::Plastic(b) => b.pdf(wi, wo),
            Bsdf::RoughPlastic(b) => b.pdf(wi, wo),
            Bsdf::Blend(b) => b.pdf(wi, wo),
            Bsdf::Principled(b) => b.pdf(wi, wo),
            Bsdf::PrincipledThin(b) => b.pdf(wi, wo),
        }
    }

    /// For a delta event (a direction [`Bsdf::sample`] returned with `delta` set), the discrete
    /// probability with which [`Bsdf::sample`] given `wi` picks the delta lobe that leads to
    /// `wo` (`wo` assumed to be that lobe's direction; the same in both transport modes): 1 for
    /// a mirror lit from the front, F or 1 − F for smooth glass, R or 1 − R for a thin sheet,
    /// the coating's share for a plastic. Zero for BSDFs without a delta lobe, whose densities
    /// are [`Bsdf::pdf`]. Every BSDF with a delta lobe must answer here: MIS divides by it.
    #[inline]
    pub fn lobe_probability(&self, wi: Vec3, wo: Vec3) -> f32 {
        match self {
            Bsdf::SmoothConductor(_) if wi.z > 0.0 => 1.0,
            Bsdf::SmoothDielectric(b) => b.lobe_probability(wi, wo),
            Bsdf::ThinDielectric(b) => b.lobe_probability(wi, wo),
            Bsdf::Plastic(b) => b.coating_probability(wi, wo),
            Bsdf::Blend(b) => b.lobe_probability(wi, wo),
            Bsdf::SmoothConductor(_)
            | Bsdf::Lambert(_)
            | Bsdf::ModifiedPhong(_)
            | Bsdf::RoughConductor(_)
            | Bsdf::RoughDielectric(_)
            | Bsdf::RoughPlastic(_)
            | Bsdf::Principled(_)
            | Bsdf::PrincipledThin(_) => 0.0,
        }
    }

    /// Importance-samples a direction given `wi` from three uniform numbers (`u_lobe` picks a
    /// lobe), with the weight of `mode`. `None` when the sampled direction carries no energy
    /// (e.g. below the surface).
    #[inline]
    pub fn sample(&self, wi: Vec3, u_lobe: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        match self {
            Bsdf::Lambert(b) => b.sample(wi, u),
            Bsdf::ModifiedPhong(b) => b.sample(wi, u_lobe, u),
            Bsdf::SmoothConductor(b) => b.sample(wi),
            Bsdf::SmoothDielectric(b) => b.sample(wi, u_lobe, mode),
            Bsdf::RoughConductor(b) => b.sample(wi, u),
            Bsdf::RoughDielectric(b) => b.sample(wi, u_lobe, u, mode),
            Bsdf::Plastic(b) => b.sample(wi, u_lobe, u),
            Bsdf::RoughPlastic(b) => b.sample(wi, u_lobe, u),
            Bsdf::Blend(b) => b.sample(wi, u_lobe, u, mode),
            Bsdf::ThinDielectric(b) => b.sample(wi, u_lobe),
            Bsdf::Principled(b) => b.sample(wi, u_lobe, u, mode),
            Bsdf::PrincipledThin(b) => b.sample(wi, u_lobe, u, mode),
        }
    }

    /// Whether the BSDF depends on the azimuth about the normal (anisotropic roughness: a
    /// microfacet distribution with α_u ≠ α_v, a principled BSDF with `anisotropic` > 0, or a
    /// blend of one): its frame must then follow the surface's ∂p/∂u, as Mitsuba's does
    /// ([`crate::geometry::SurfaceNormals::tangent`]). A texture on `alpha_u`, `alpha_v` or
    /// `anisotropic` makes a material anisotropic too; the scene adds that.
    pub fn is_anisotropic(&self) -> bool {
        let microfacet = |m: &crate::sampling::microfacet::Microfacet| m.alpha_u != m.alpha_v;
        match self {
            Bsdf::RoughConductor(b) => microfacet(&b.microfacet),
            Bsdf::RoughDielectric(b) => microfacet(&b.microfacet),
            Bsdf::RoughPlastic(b) => microfacet(&b.microfacet),
            Bsdf::Principled(b) => b.anisotropic != 0.0,
            Bsdf::PrincipledThin(b) => b.anisotropic != 0.0,
            Bsdf::Blend(b) => b.bsdfs.iter().any(Bsdf::is_anisotropic),
            Bsdf::Lambert(_)
            | Bsdf::ModifiedPhong(_)
            | Bsdf::SmoothConductor(_)
            | Bsdf::SmoothDielectric(_)
            | Bsdf::Plastic(_)
            | Bsdf::ThinDielectric(_) => false,
        }
    }

    /// Whether every sampled direction is a Dirac delta (ideal mirror, smooth dielectric):
    /// `eval` is zero everywhere, so a vertex there can never be connected to a sensor and the
    /// tracer does not store it (the path continues through it).
    #[inline]
    pub fn is_delta(&self) -> bool {
        matches!(self, Bsdf::SmoothConductor(_) | Bsdf::SmoothDielectric(_) | Bsdf::ThinDielectric(_))
    }

    /// Whether some sampled directions are Dirac deltas (every delta BSDF, and the coating of
    /// [`Plastic`]): `eval` then misses part of the scattering, so directions must come from
    /// [`Bsdf::sample`], never from another density weighted by `eval`.
    #[inline]
    pub fn has_delta_lobe(&self) -> bool {
        match self {
            Bsdf::Plastic(_) => true,
            Bsdf::Blend(b) => b.bsdfs.iter().any(Bsdf::has_delta_lobe),
            _ => self.is_delta(),
        }
    }

    /// The weight of a straight-through delta lobe (ω_o = −ω_i, no deflection) for light
    /// arriving from local `wi`: `Some` for a thin sheet (its (1 − R)·`specular_transmittance`,
    /// [`ThinDielectric::transmittance`]; 0 in the tangent plane), `None` for every BSDF without
    /// such a lobe. Only a surface with `Some` here may be crossed by a shadow ray
    /// ([`crate::scene::Scene::shadow_transmittance`]).
    #[inline]
    pub fn straight_through(&self, wi: Vec3) -> Option<Rgb> {
        match self {
            Bsdf::ThinDielectric(b) if wi.z != 0.0 => Some(b.transmittance(wi.z)),
            Bsdf::ThinDielectric(_) => Some(Rgb::ZERO),
            _ => None,
        }
    }

    /// Whether [`Bsdf::straight_through`] answers `Some` (a thin sheet: a window pane).
    #[inline]
    pub fn is_pane(&self) -> bool {
        matches!(self, Bsdf::ThinDielectric(_))
    }

    /// Whether light crosses the surface (dielectrics, a principled BSDF with its transmission
    /// lobe, and the thin principled sheet): such BSDFs are oriented and accept light from both
    /// sides (the thin sheet turns every query to wi's face itself).
    #[inline]
    pub fn transmits(&self) -> bool {
        match self {
            Bsdf::SmoothDielectric(_)
            | Bsdf::RoughDielectric(_)
            | Bsdf::ThinDielectric(_)
            | Bsdf::PrincipledThin(_) => true,
            Bsdf::Principled(b) => b.has_spec_trans,
            _ => false,
        }
    }

    /// The absorption coefficient σ_a (1/m) of the inside of a dielectric (zero for every other
    /// BSDF): flux travelling a distance t inside is multiplied by exp(−σ_a·t).
    #[inline]
    pub fn absorption(&self) -> Rgb {
        match self {
            Bsdf::SmoothDielectric(b) => b.absorption,
            Bsdf::RoughDielectric(b) => b.absorption,
            _ => Rgb::ZERO,
        }
    }

    /// Upper bound of the directional albedo per channel (kd for Lambert, kd + ks for Phong, the
    /// specular reflectance for conductors, the larger of the specular reflectance and
    /// transmittance for dielectrics).
    pub fn max_albedo(&self) -> Rgb {
        match self {
            Bsdf::Lambert(b) => b.reflectance,
            Bsdf::ModifiedPhong(b) => b.kd + b.ks,
            Bsdf::SmoothConductor(b) => b.specular_reflectance,
            Bsdf::RoughConductor(b) => b.specular_reflectance,
            Bsdf::SmoothDielectric(b) => b.specular_reflectance.max(b.specular_transmittance),
            Bsdf::RoughDielectric(b) => b.specular_reflectance.max(b.specular_transmittance),
            Bsdf::Plastic(b) => b.max_albedo(),
            Bsdf::RoughPlastic(b) => b.max_albedo(),
            Bsdf::Blend(b) => b.max_albedo(),
            Bsdf::ThinDielectric(b) => b.specular_reflectance.max(b.specular_transmittance),
            Bsdf::Principled(b) => b.max_albedo(),
            Bsdf::PrincipledThin(b) => b.max_albedo(),
        }
    }
}

/// A BSDF bound to a surface, with its sidedness (as Mitsuba defines it: a one-sided surface is
/// black seen from behind; a two-sided one scatters identically on both faces). Dielectrics are
/// neither: they scatter on both faces, differently (`two_sided` is ignored for them).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name from the scene file (for messages and `info`).
    pub name: String,
    /// How the surface scatters.
    pub bsdf: Bsdf,
    /// Whether the back face scatters like the front.
    pub two_sided: bool,
}

impl Material {
    /// The local frame for light arriving from world direction `wi` at a surface with normals
    /// `n`; `None` if that side does not scatter ([`ShadingPoint::side`]: the side is decided by
    /// the geometric normal, dielectrics always get the unflipped frame, and a reflecting
    /// surface whose shading normal faces away from `wi` does not scatter either, see
    /// [`shading`]).
    #[inline]
    pub fn frame_for(&self, n: SurfaceNormals, wi: Vec3) -> Option<LocalFrame> {
        let p = self.at(n);
        p.side(&p.direction(wi)).map(|flip| LocalFrame::new(n, flip))
    }

    /// This material at a surface point of normals `n`: one shading frame for every query made
    /// there ([`ShadingPoint`]; the methods below are its single queries).
    #[inline]
    pub fn at(&self, n: SurfaceNormals) -> ShadingPoint<'_> {
        ShadingPoint::new(self, n)
    }

    /// f_r for world directions in light-flow order at a surface of normals `n`: the physical
    /// BSDF, or with shading normals the adjoint-consistent f_eff of [`shading`].
    #[inline]
    pub fn eval_world(&self, n: SurfaceNormals, wi: Vec3, wo: Vec3) -> Rgb {
        let p = self.at(n);
        p.eval(&p.direction(wi), &p.direction(wo))
    }

    /// The density with which [`Material::sample_world`] (either [`TransportMode`]) given `wi`
    /// returns `wo`: [`Bsdf::pdf`] in the shading frame, or for a delta BSDF the probability of
    /// the lobe leading to `wo` ([`Bsdf::lobe_probability`]); 0 where `sample_world` never
    /// returns `wo` (the side refused by [`Material::frame_for`], the light-leak guard). The
    /// camera tracer's density at a surface, and the light tracer's under
    /// `Directions::Importance` (`crate::trace::light_direction_pdf` says which). For a BSDF
    /// with both kinds of lobe (plastic) this is the non-delta density: a delta event's is
    /// [`Material::pdf_world_of`] with `delta` set.
    #[inline]
    pub fn pdf_world(&self, n: SurfaceNormals, wi: Vec3, wo: Vec3) -> f32 {
        self.pdf_world_of(n, wi, wo, self.bsdf.is_delta())
    }

    /// [`Material::pdf_world`] for one kind of event: with `delta`, the probability of the delta
    /// lobe leading to `wo` ([`Bsdf::lobe_probability`]), else the density of the other lobes
    /// ([`Bsdf::pdf`]). MIS takes the kind from the sampled event (`BsdfSample::delta`).
    #[inline]
    pub fn pdf_world_of(&self, n: SurfaceNormals, wi: Vec3, wo: Vec3, delta: bool) -> f32 {
        let p = self.at(n);
        p.pdf_of(&p.direction(wi), &p.direction(wo), delta)
    }

    /// The density with which [`Material::sample_uniform_world`] given `wi` returns `wo`:
    /// 1/2π on the shading hemisphere, 0 where it never returns `wo`.
    #[inline]
    pub fn pdf_uniform_world(&self, n: SurfaceNormals, wi: Vec3, wo: Vec3) -> f32 {
        let p = self.at(n);
        p.pdf_uniform(&p.direction(wi), &p.direction(wo))
    }

    /// Samples a world-space outgoing direction uniformly over the scattering hemisphere (the
    /// baseline of the thesis's §6.2.2, for measuring what importance sampling buys); weights
    /// as [`Material::sample_world`] in importance mode.
    #[inline]
    pub fn sample_uniform_world(&self, n: SurfaceNormals, wi: Vec3, u: Vec2) -> Option<BsdfSample> {
        let p = self.at(n);
        p.sample_uniform(&p.direction(wi), u)
    }

    /// Samples a world-space direction given `wi`; `weight` as [`Bsdf::sample`] in `mode`, with
    /// the shading-normal correction of `mode` (see [`shading`]).
    #[inline]
    pub fn sample_world(
        &self,
        n: SurfaceNormals,
        wi: Vec3,
        u_lobe: f32,
        u: Vec2,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        let p = self.at(n);
        p.sample(&p.direction(wi), u_lobe, u, mode)
    }
}

/// Why a material's parameters are impossible.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MaterialError {
    /// A parameter is NaN or infinite.
    #[error("{0} is not a finite number")]
    NotFinite(&'static str),
    /// A reflectance is negative.
    #[error("{0} must not be negative")]
    Negative(&'static str),
    /// An index of refraction or a roughness is zero or negative.
    #[error("{0} must be positive")]
    NotPositive(&'static str),
    /// A reflectance or transmittance exceeds 1.
    #[error("{0} exceeds 1 in some channel: the surface would create energy")]
    AboveOne(&'static str),
    /// A rough interface between media of the same index (no refraction to speak of).
    #[error("int_ior = ext_ior = {0}: a rough interface needs different indices (use a smooth one)")]
    EqualIors(f32),
    /// The BSDF would reflect more energy than it receives.
    #[error("kd + ks = {0} exceeds 1 in some channel: the surface would create energy")]
    CreatesEnergy(Rgb),
    /// A weight that must lie in [0, 1] lies outside.
    #[error("{0} = {1} is not in [0, 1]")]
    OutOfUnitRange(&'static str, f32),
    /// A combination of BSDFs Opticks does not handle.
    #[error("{0} is not supported")]
    Unsupported(&'static str),
    /// A parameter exceeds the largest value the BSDF handles accurately.
    #[error("{name} = {value} exceeds the supported maximum {max}")]
    TooLarge {
        /// Which parameter.
        name: &'static str,
        /// The value given.
        value: f32,
        /// The largest value accepted.
        max: f32,
    },
}

/// A colour parameter in [0, 1] per channel, or the error naming it.
pub(crate) fn check_unit_colour(name: &'static str, c: Rgb) -> Result<(), MaterialError> {
    if !c.is_finite() {
        Err(MaterialError::NotFinite(name))
    } else if c.min_element() < 0.0 {
        Err(MaterialError::Negative(name))
    } else if c.max_element() > 1.0 {
        Err(MaterialError::AboveOne(name))
    } else {
        Ok(())
    }
}

/// A finite, strictly positive number, or the error naming it.
pub(crate) fn check_positive(name: &'static str, x: f32) -> Result<(), MaterialError> {
    if !x.is_finite() {
        Err(MaterialError::NotFinite(name))
    } else if x <= 0.0 {
        Err(MaterialError::NotPositive(name))
    } else {
        Ok(())
    }
}

/// A microfacet roughness α in (0, [`MAX_ALPHA`]], named `name` in the error.
fn check_alpha(name: &'static str, alpha: f32) -> Result<(), MaterialError> {
    check_positive(name, alpha)?;
    if alpha > MAX_ALPHA {
        return Err(MaterialError::TooLarge { name, value: alpha, max: MAX_ALPHA });
    }
    Ok(())
}

/// Both roughnesses of a microfacet distribution in (0, [`MAX_ALPHA`]] (errors name `alpha`
/// when isotropic, else `alpha_u` / `alpha_v`, as the scene file does).
pub(crate) fn check_microfacet(m: &Microfacet) -> Result<(), MaterialError> {
    if m.alpha_u.to_bits() == m.alpha_v.to_bits() {
        check_alpha("alpha", m.alpha_u)
    } else {
        check_alpha("alpha_u", m.alpha_u)?;
        check_alpha("alpha_v", m.alpha_v)
    }
}

/// Largest accepted microfacet roughness α (α = 1 is already a very rough surface;
/// beyond it single-scattering microfacet models lose most of their energy).
pub const MAX_ALPHA: f32 = 1.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sided_is_black_behind_and_two_sided_is_symmetric() {
        let bsdf = Bsdf::Lambert(Lambert::new(Rgb::splat(0.5)).unwrap());
        let one = Material { name: "a".into(), bsdf: bsdf.clone(), two_sided: false };
        let two = Material { name: "b".into(), bsdf, two_sided: true };
        let n = SurfaceNormals::flat(Vec3::Y);
        let (up, up2) = (Vec3::new(0.3, 0.9, 0.1).normalize(), Vec3::new(-0.5, 0.7, 0.2).normalize());
        let down = |v: Vec3| Vec3::new(v.x, -v.y, v.z);
        assert!(one.eval_world(n, up, up2).x > 0.0);
        assert_eq!(one.eval_world(n, down(up), down(up2)), Rgb::ZERO);
        assert_eq!(two.eval_world(n, down(up), down(up2)), two.eval_world(n, up, up2));
        // Reflection only: light never crosses the surface.
        assert_eq!(two.eval_world(n, up, down(up2)), Rgb::ZERO);
    }

    #[test]
    fn dielectrics_scatter_on_both_faces_and_delta_bsdfs_evaluate_to_zero() {
        let n = SurfaceNormals::flat(Vec3::Y);
        let rough = Bsdf::RoughDielectric(RoughDielectric::new(1.5, 1.0, 0.3, Rgb::ONE, Rgb::ONE).unwrap());
        let m = Material { name: "g".into(), bsdf: rough, two_sided: false };
        let above = Vec3::new(0.3, 0.9, 0.1).normalize();
        let below = Vec3::new(-0.2, -0.8, 0.3).normalize();
        // The frame is never flipped: its z is the geometric normal from either side.
        assert_eq!(m.frame_for(n, above).unwrap().frame.n, Vec3::Y);
        assert_eq!(m.frame_for(n, below).unwrap().frame.n, Vec3::Y);
        assert!(m.frame_for(n, Vec3::X).is_none());
        // Transmission both ways, related by generalized reciprocity (η_out = 1, η_in = 1.5).
        let (down, up) = (m.eval_world(n, above, below), m.eval_world(n, below, above));
        assert!(down.x > 0.0 && up.x > 0.0);
        assert!((down.x / 2.25 - up.x).abs() < 1e-3 * up.x, "{down} {up}");
        let s = m.sample_world(n, below, 0.9, Vec2::new(0.3, 0.6), TransportMode::Importance).unwrap();
        assert!(s.wo.is_finite() && !s.delta);

        let glass = Bsdf::SmoothDielectric(SmoothDielectric::new(1.5, 1.0, Rgb::ONE, Rgb::ONE).unwrap());
        let mirror = Bsdf::SmoothConductor(SmoothConductor::new(Rgb::ONE, None).unwrap());
        for b in [glass, mirror] {
            assert!(b.is_delta());
            let wi = Vec3::new(0.3, -0.2, 0.9).normalize();
            let s = b.sample(wi, 0.0, Vec2::splat(0.5), TransportMode::Importance).unwrap();
            assert!(s.delta);
            assert_eq!((b.eval(wi, s.wo), b.pdf(wi, s.wo)), (Rgb::ZERO, 0.0));
        }
        assert!(!Bsdf::Lambert(Lambert::new(Rgb::ONE).unwrap()).is_delta());
    }
}
