//! The light tracer's densities, as the bidirectional estimator's MIS needs them
//! (`docs/bidirectional.md` §4, §7): written once, here, and used both by the tracer (to
//! compute the [`MisRecord`] of each stored sample)
//! and by the camera-side renderer (to evaluate the light tracer's densities at camera
//! vertices and connections), so that the two can never disagree.
//!
//! * [`light_direction_pdf`]: the solid-angle density with which the tracer continues a path
//!   in a direction at a surface, with the dataset's [`Directions`] rule ([`samples_uniformly`]
//!   decides, for the tracer too).
//! * [`emitter_densities`]: a light's densities of a path start (position and direction), as
//!   the [`Emitter`] the MIS functions take.
//! * [`SAMPLING_SIGNATURE`]: the number a dataset records with its MIS records, bumped whenever
//!   a density these records depend on changes.
//!
//! Roulette, priority selection and the delta-run survival never enter (`docs/bidirectional.md`
//! §2): the records hold the densities of the sampling procedures, not of the culling.

use super::Directions;
use crate::bsdf::{Bsdf, Direction, Material, ShadingPoint};
use crate::dataset::{Emitter, Heuristic, LightVertexMis, MisRecord};
use crate::geometry::SurfaceNormals;
use crate::light::{Emission, Light};
use crate::math::Vec3;

/// The sampling signature of this build's MIS records (`docs/bidirectional.md` §7): bump it
/// whenever a density they depend on changes — the lights' emission sampling, `Bsdf::sample` /
/// `Bsdf::pdf` / `Bsdf::lobe_probability`, the uniform-direction rule ([`samples_uniformly`]),
/// the light-leak guard, or the camera tracer's sampling. A dataset whose passes record
/// another signature cannot be rendered with MIS by this build. 0 is never a signature.
pub const SAMPLING_SIGNATURE: u32 = 1;

/// Whether the tracer, under `directions`, draws continuation directions at a surface of
/// `bsdf` uniformly over the hemisphere (the thesis's §6.2.2 baseline) instead of importance
/// sampling the BSDF: only for [`Directions::Uniform`] on non-transmitting surfaces without a
/// delta lobe (a plastic's coating must be sampled by [`Bsdf::sample`]).
#[inline]
pub fn samples_uniformly(directions: Directions, bsdf: &Bsdf) -> bool {
    directions == Directions::Uniform && !bsdf.has_delta_lobe() && !bsdf.transmits()
}

/// The solid-angle density with which the light tracer, under `directions`, continues a path
/// at a surface of `material` with normals `n` in world direction `wo`, light having arrived
/// from `wi` (both unit, pointing away from the surface): [`Material::pdf_uniform_world`]
/// where [`samples_uniformly`], else [`Material::pdf_world`] (importance sampling; for a delta
/// BSDF the probability of the lobe leading to `wo`, which must then be that lobe's
/// direction). Zero where the tracer never continues in `wo`. `delta` says which kind of event
/// the density is for (`BsdfSample::delta`): a plastic has both, and a delta event's density is
/// its coating's lobe probability ([`Material::pdf_world_of`]).
///
/// The camera side uses it for the light tracer's density of continuing from a camera vertex
/// (`CameraVertexMis::after_scatter`'s `pdf_rev_w`: `wi` the next camera direction, `wo`
/// toward the previous camera vertex) and of a connection (`ConnectionEnd::pdf_fwd_w` at a
/// stored vertex: `wi` its `from_dir`, `wo` toward the camera vertex).
#[inline]
pub fn light_direction_pdf(
    material: &Material,
    n: SurfaceNormals,
    wi: Vec3,
    wo: Vec3,
    directions: Directions,
    delta: bool,
) -> f32 {
    let p = material.at(n);
    light_direction_pdf_at(&p, &p.direction(wi), &p.direction(wo), directions, delta)
}

/// [`light_direction_pdf`] at a [`ShadingPoint`] whose frame other queries share, for
/// directions prepared there.
#[inline]
pub fn light_direction_pdf_at(
    p: &ShadingPoint,
    wi: &Direction,
    wo: &Direction,
    directions: Directions,
    delta: bool,
) -> f32 {
    if delta {
        p.pdf_of(wi, wo, true)
    } else if samples_uniformly(directions, &p.material.bsdf) {
        p.pdf_uniform(wi, wo)
    } else {
        p.pdf(wi, wo)
    }
}

/// Light `light`'s densities of a path start at a point of geometric normal `normal` (area
/// lights; ignored otherwise) emitting along the unit world direction `dir`
/// ([`Light::emission_pdfs`]), as MIS takes them. For NEE and emitter hits, `dir` points from
/// the light point toward the camera vertex.
#[inline]
pub fn emitter_densities(light: &Light, normal: Vec3, dir: Vec3) -> Emitter {
    let (first, second) = light.emission_pdfs(normal, dir);
    match light {
        Light::Area(_) => Emitter::area(first, second),
        Light::Point(_) => Emitter::point(second),
        Light::Directional(_) => Emitter::directional(second),
        Light::Environment(_) => Emitter::environment(first, second),
    }
}

/// What a light path carries along for its MIS records (`trace_path`'s recursion): nothing
/// (`()`: no records), or [`SegmentMis`]. Monomorphised, so a trace without records runs the
/// code it ran before records existed.
pub(super) trait PathMis: Copy {
    /// Where the records go.
    type Sink<'a>;
    /// The state of the first segment of a path starting with emission `e` of `light` (an area
    /// light's y₀ stores its record).
    fn at_emission(light: &Light, e: &Emission, sink: &mut Self::Sink<'_>) -> Self;
    /// The state at the vertex `at` the segment hits, arriving at |cos θ| = `cos_in`.
    fn after_hit(self, at: Vec3, cos_in: f32) -> Self;
    /// Stores the record of the vertex state (a stored, non-delta vertex).
    fn store(&self, sink: &mut Self::Sink<'_>);
    /// The state of the segment leaving the vertex: see [`LightVertexMis::after_scatter`];
    /// `pdf_rev` is evaluated only when records are made.
    fn after_scatter(self, cos_out: f32, pdf_fwd: f32, pdf_rev: impl FnOnce() -> f32, delta: bool) -> Self;
}

impl PathMis for () {
    type Sink<'a> = ();
    #[inline(always)]
    fn at_emission(_: &Light, _: &Emission, _: &mut ()) {}
    #[inline(always)]
    fn after_hit(self, _: Vec3, _: f32) {}
    #[inline(always)]
    fn store(&self, _: &mut ()) {}
    #[inline(always)]
    fn after_scatter(self, _: f32, _: f32, _: impl FnOnce() -> f32, _: bool) {}
}

/// The light subpath's MIS state on a segment (or at a vertex), with the position of the vertex
/// the segment leaves (the vertex, not the offset ray origin: distances between vertices are
/// what the camera side computes too).
#[derive(Clone, Copy, Debug)]
pub(super) struct SegmentMis {
    state: LightVertexMis,
    from: Vec3,
}

impl PathMis for SegmentMis {
    type Sink<'a> = (Heuristic, &'a mut Vec<MisRecord>);

    #[inline]
    fn at_emission(light: &Light, e: &Emission, (h, records): &mut Self::Sink<'_>) -> Self {
        let normal = e.surface.map_or(Vec3::ZERO, |s| s.0);
        let emitter = emitter_densities(light, normal, e.dir);
        if e.surface.is_some() {
            records.push(LightVertexMis::emission_vertex(emitter, *h).record());
        }
        SegmentMis {
            state: LightVertexMis::at_emission(emitter, e.dir.dot(normal).abs(), *h),
            from: e.origin,
        }
    }

    #[inline]
    fn after_hit(self, at: Vec3, cos_in: f32) -> Self {
        SegmentMis { state: self.state.after_hit((at - self.from).length_squared(), cos_in), from: at }
    }

    #[inline]
    fn store(&self, (_, records): &mut Self::Sink<'_>) {
        records.push(self.state.record());
    }

    #[inline]
    fn after_scatter(self, cos_out: f32, pdf_fwd: f32, pdf_rev: impl FnOnce() -> f32, delta: bool) -> Self {
        SegmentMis { state: self.state.after_scatter(cos_out, pdf_fwd, pdf_rev(), delta), ..self }
    }
}

#[cfg(test)]
mod tests;
