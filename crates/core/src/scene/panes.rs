//! Shadow rays through window panes: [`Scene::shadow_transmittance`].
//!
//! A thin dielectric sheet (core `ThinDielectric`: Radiance's `glass`, Mitsuba's
//! `thindielectric`) does not deflect what it transmits: its transmission lobe is a Dirac delta
//! at ω_o = −ω_i with weight T(θ) = (1 − R(θ))·`specular_transmittance`, R summing the sheet's
//! internal reflections ([`crate::bsdf::ThinDielectric::transmittance`]). A segment between two
//! points that crosses such sheets and nothing else therefore carries light from one end to the
//! other along the segment itself, multiplied by the product of the sheets' T at the angles it
//! crosses them — per colour channel, texture and shading normal resolved at each crossing
//! ([`crate::bsdf::ShadingPoint::straight_through`], the weight the BSDF gives that lobe).
//!
//! [`Scene::shadow_transmittance`] answers that product for a segment: `None` when any other
//! surface blocks it (mirrors, refracting dielectrics, opaque surfaces: exactly where
//! [`Scene::occluded`] says so, a masked surface by the same stochastic rule as every query,
//! `Scene::meets`), `Some(Rgb::ONE)` when nothing is in the way. The panes are found one after
//! the other by closest-hit queries, each starting just past the previous pane; past
//! [`MAX_PANES`] panes the segment counts as blocked (`None`): a bound on the work of a shadow
//! ray, not a physical limit (eight panes of clear glass at normal incidence pass 0.92⁸ ≈ 51 %,
//! so a scene with more panes stacked on one line of sight than that reads too little there).
//!
//! Only the illuminance meter's connections ask this (`crate::sensor::meter`; its module docs
//! say why this counts nothing twice); every camera estimator keeps [`Scene::occluded`], whose
//! bidirectional weights assume that a pane blocks. A scene without panes answers with one
//! [`Scene::occluded`] query behind a flag, so the common case costs what it did.

use super::Scene;
use crate::geometry::{Ray, offset_ray_origin};
use crate::math::Rgb;

/// The most panes a shadow ray crosses ([`Scene::shadow_transmittance`]); one more blocks it.
pub const MAX_PANES: usize = 8;

impl Scene {
    /// The fraction of light the open segment from `ray.origin` of length `ray.t_max` passes
    /// (`t_max` may be infinite), per channel: `None` if a surface other than a thin pane
    /// blocks it, or more than [`MAX_PANES`] panes lie on it; otherwise the product of the
    /// panes' straight-through transmittance at the angles the segment crosses them (`Rgb::ONE`
    /// with none). See the module docs.
    #[inline]
    pub fn shadow_transmittance(&self, ray: &Ray) -> Option<Rgb> {
        if !self.panes {
            return (!self.occluded(ray)).then_some(Rgb::ONE);
        }
        self.through_panes(ray)
    }

    /// [`Scene::shadow_transmittance`] in a scene with panes: the closest hit, crossed if it is
    /// a pane, then the rest of the segment (out of line, as the masked queries).
    #[inline(never)]
    fn through_panes(&self, ray: &Ray) -> Option<Rgb> {
        let (mut ray, mut through, mut crossed) = (*ray, Rgb::ONE, 0);
        loop {
            // The segment is open at its origin, as for `occluded`: a surface through the
            // origin does not block it.
            let q = ray;
            let Some((t, prim)) = self.accel.intersect_where(&q, |p, t| t > 0.0 && self.meets(&q, p, t))
            else {
                return Some(through);
            };
            if crossed == MAX_PANES || !self.material(prim).bsdf.is_pane() {
                return None;
            }
            crossed += 1;
            let position = self.triangles[prim as usize].snap(ray.origin + t * ray.dir);
            let mut resolved = None;
            let (material, normals) = self.surface_at(prim, position, &mut resolved);
            let point = material.at(normals);
            through *= point.straight_through(&point.direction(ray.dir))?;
            if through == Rgb::ZERO {
                return None;
            }
            let origin = offset_ray_origin(position, self.normal(prim), ray.dir);
            let t_max = ray.t_max - (origin - ray.origin).dot(ray.dir);
            if !(t_max > 0.0) {
                return Some(through);
            }
            ray = Ray { origin, dir: ray.dir, t_max };
        }
    }
}

#[cfg(test)]
#[path = "panes_tests.rs"]
mod tests;
