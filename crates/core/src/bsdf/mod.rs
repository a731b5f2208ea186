//! BSDFs: how a surface scatters light. A closed set, dispatched by `match` ([`Bsdf`]).
//!
//! Conventions (shared by every BSDF here):
//! * Directions are in the local shading frame (z = normal) and point **away** from the surface.
//! * `wi` is the direction light arrived from (in light tracing, toward the previous vertex);
//!   `wo` the direction it leaves in. Callers guarantee `wi.z > 0` (the [`Material`] flips
//!   two-sided surfaces and blackens the back of one-sided ones); BSDFs return zero when
//!   `wo.z <= 0` (they only reflect).
//! * `eval` returns f_r (no cosine). `sample` returns `weight = f_r · cos θ_o / pdf`, the factor a
//!   light path's β is multiplied by. All BSDFs here are reciprocal, so the same code serves
//!   light (importance) paths and camera paths.

#[cfg(test)]
mod chi2;
mod lambert;
mod phong;

pub use lambert::Lambert;
pub use phong::ModifiedPhong;

use crate::math::{Frame, Rgb, Vec2, Vec3};

/// A direction sampled from a BSDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// Sampled outgoing direction (local frame, unit length).
    pub wo: Vec3,
    /// f_r · cos θ_o / pdf.
    pub weight: Rgb,
    /// Solid-angle density of `wo`.
    pub pdf: f32,
}

/// The closed set of BSDFs.
#[derive(Clone, Debug, PartialEq)]
pub enum Bsdf {
    /// Ideal diffuse reflector.
    Lambert(Lambert),
    /// Modified Phong of Lafortune & Willems 1994 (the thesis's material model).
    ModifiedPhong(ModifiedPhong),
}

impl Bsdf {
    /// f_r(wi → wo), local frame.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        match self {
            Bsdf::Lambert(b) => b.eval(wi, wo),
            Bsdf::ModifiedPhong(b) => b.eval(wi, wo),
        }
    }

    /// Density with which [`Bsdf::sample`] picks `wo` given `wi`.
    #[inline]
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        match self {
            Bsdf::Lambert(b) => b.pdf(wi, wo),
            Bsdf::ModifiedPhong(b) => b.pdf(wi, wo),
        }
    }

    /// Importance-samples `wo` given `wi` from three uniform numbers (`u_lobe` picks a lobe).
    /// `None` when the sampled direction carries no energy (e.g. below the surface).
    #[inline]
    pub fn sample(&self, wi: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        match self {
            Bsdf::Lambert(b) => b.sample(wi, u),
            Bsdf::ModifiedPhong(b) => b.sample(wi, u_lobe, u),
        }
    }

    /// Upper bound of the directional albedo per channel (kd for Lambert, kd + ks for Phong).
    pub fn max_albedo(&self) -> Rgb {
        match self {
            Bsdf::Lambert(b) => b.reflectance,
            Bsdf::ModifiedPhong(b) => b.kd + b.ks,
        }
    }
}

/// A BSDF bound to a surface, with its sidedness (as Mitsuba defines it: a one-sided surface is
/// black seen from behind; a two-sided one scatters identically on both faces).
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
    /// The local frame for light arriving from world direction `wi` at a surface with unit
    /// geometric normal `n`; `None` if that side does not scatter.
    #[inline]
    pub fn frame_for(&self, n: Vec3, wi: Vec3) -> Option<Frame> {
        let c = n.dot(wi);
        if c > 0.0 {
            Some(Frame::from_normal(n))
        } else if c < 0.0 && self.two_sided {
            Some(Frame::from_normal(-n))
        } else {
            None
        }
    }

    /// f_r for world directions at a surface of unit geometric normal `n`.
    #[inline]
    pub fn eval_world(&self, n: Vec3, wi: Vec3, wo: Vec3) -> Rgb {
        match self.frame_for(n, wi) {
            Some(f) => {
                let (li, lo) = (f.to_local(wi), f.to_local(wo));
                if lo.z <= 0.0 { Rgb::ZERO } else { self.bsdf.eval(li, lo) }
            }
            None => Rgb::ZERO,
        }
    }

    /// Samples a world-space outgoing direction uniformly over the scattering hemisphere (the
    /// baseline of the thesis's §6.2.2, for measuring what importance sampling buys).
    #[inline]
    pub fn sample_uniform_world(&self, n: Vec3, wi: Vec3, u: Vec2) -> Option<BsdfSample> {
        let f = self.frame_for(n, wi)?;
        let wo = crate::sampling::warp::square_to_uniform_hemisphere(u);
        let pdf = crate::sampling::warp::UNIFORM_HEMISPHERE_PDF;
        let weight = self.bsdf.eval(f.to_local(wi), wo) * wo.z / pdf;
        Some(BsdfSample { wo: f.to_world(wo), weight, pdf })
    }

    /// Samples a world-space outgoing direction; `weight` is f_r·|cos θ_o|/pdf.
    #[inline]
    pub fn sample_world(&self, n: Vec3, wi: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let f = self.frame_for(n, wi)?;
        let s = self.bsdf.sample(f.to_local(wi), u_lobe, u)?;
        Some(BsdfSample { wo: f.to_world(s.wo), ..s })
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
    /// The BSDF would reflect more energy than it receives.
    #[error("kd + ks = {0} exceeds 1 in some channel: the surface would create energy")]
    CreatesEnergy(Rgb),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sided_is_black_behind_and_two_sided_is_symmetric() {
        let bsdf = Bsdf::Lambert(Lambert::new(Rgb::splat(0.5)).unwrap());
        let one = Material { name: "a".into(), bsdf: bsdf.clone(), two_sided: false };
        let two = Material { name: "b".into(), bsdf, two_sided: true };
        let n = Vec3::Y;
        let (up, up2) = (Vec3::new(0.3, 0.9, 0.1).normalize(), Vec3::new(-0.5, 0.7, 0.2).normalize());
        let down = |v: Vec3| Vec3::new(v.x, -v.y, v.z);
        assert!(one.eval_world(n, up, up2).x > 0.0);
        assert_eq!(one.eval_world(n, down(up), down(up2)), Rgb::ZERO);
        assert_eq!(two.eval_world(n, down(up), down(up2)), two.eval_world(n, up, up2));
        // Reflection only: light never crosses the surface.
        assert_eq!(two.eval_world(n, up, down(up2)), Rgb::ZERO);
    }
}
