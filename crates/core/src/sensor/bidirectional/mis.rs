//! Multiple importance sampling for the bidirectional estimator, its camera side: the weights of
//! its strategies, computed where a camera subpath meets the light side. The recursive MIS
//! quantities are those of Georgiev's *Implementing Vertex Connection and Merging* (2012),
//! restricted to vertex connection (no merging) and adapted to a light vertex cache whose
//! strategies are sampled at different rates. The derivation, with every quantity defined, is
//! `docs/bidirectional.md`; this module is the camera side of its code, with the notation used
//! there.
//!
//! A full path x₀ … x_k runs from a light (x₀) to the camera (x_k). Strategy s takes s vertices
//! from the light side and t = k + 1 − s from the camera side. Per camera path and per light k
//! the strategies have the expected sample counts n_s (P = N_k/N, the light's share of the
//! dataset's paths, which is also NEE's light-pick probability):
//!
//! | strategy | s, t | n_s |
//! |---|---|---|
//! | emitter hit | s = 0 | 1 |
//! | next-event estimation (NEE) | s = 1, t ≥ 2 | P |
//! | cache connection | s ≥ 2, t ≥ 2 | `Counts::conn`·P = n_c·N_k/\|Y\| |
//! | light tracing (a stored sample's splat) | t = 1 | `Counts::light_trace`·P = N_k/M |
//!
//! and the weight of strategy s is w_s = (n_s p̃_s)^β / Σ_j (n_j p̃_j)^β over the strategies j
//! that can produce the path (p̃: the area-measure density of the strategy, *without* the
//! light-pick probability; β = 1 balance, 2 power heuristic).
//!
//! Each side carries a few numbers along its subpath ([`LightVertexMis`], [`CameraVertexMis`]),
//! updated by [`LightVertexMis::after_hit`]/[`LightVertexMis::after_scatter`] (and the camera
//! side's equivalents), so that a weight costs a few multiplications when the two sides meet
//! ([`weight_emitter_hit`], [`weight_nee`], [`weight_connection`], [`weight_light_trace`]).
//! The light side and the recursion both sides share are the dataset's
//! (`crates/core/src/dataset/mis/`), because the tracer computes the light side's numbers and
//! the dataset stores them with each sample ([`MisRecord`], 16 bytes, for one [`Heuristic`]);
//! they depend neither on the camera nor on the counts, which enter only here, at render time.
//! The conventions for pdfs, cosines and precision are the recursion's, stated there: pdfs are
//! the tracers' own, cosines absolute against the geometric normal, inputs and weights f32,
//! the recursion f64, and a product with a zero factor is zero, so a weight is never NaN.

#[cfg(doc)]
use crate::dataset::MisRecord;
use crate::dataset::mis::{Subpath, div, mul};
use crate::dataset::{Emitter, Heuristic, LightKind, LightVertexMis};

/// The render-time sample counts per camera path of the strategies whose rate is a render
/// option, relative to a light's share P = N_k/N (module docs). NEE and emitter hits count 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Counts {
    /// c_conn = n_c·N/|Y|: every non-delta camera vertex draws n_c of the |Y| stored
    /// non-emission vertices uniformly (N light paths in total).
    pub conn: f64,
    /// c_LT = N/M: N light paths are each splatted once into an image of M camera paths
    /// (W·H·spp of the whole render).
    pub light_trace: f64,
}

impl Counts {
    /// The counts of a render that connects each camera vertex to `connections` (n_c) cache
    /// vertices drawn from `cache_vertices` (|Y|, stored non-emission vertices of the lights
    /// rendered), with `light_paths` (N = Σ N_k of those lights) and `camera_paths` (M) camera
    /// paths in the whole image. A zero count (no connections, an empty cache) switches the
    /// strategy off; `camera_paths` = 0 gives c_LT = ∞ (light tracing only).
    pub fn new(connections: u32, light_paths: u64, cache_vertices: u64, camera_paths: u64) -> Self {
        let n = light_paths as f64;
        let conn = if cache_vertices == 0 { 0.0 } else { connections as f64 * n / cache_vertices as f64 };
        let light_trace = if camera_paths == 0 { f64::INFINITY } else { n / camera_paths as f64 };
        Counts { conn, light_trace }
    }
}

/// 1/(1 + sum), the weight of a strategy whose other strategies' ratios sum to `sum`.
#[inline]
fn weight(sum: f64) -> f32 {
    let w = 1.0 / (1.0 + sum);
    if w.is_nan() { 0.0 } else { w as f32 }
}

/// How a camera draws its rays, image-wide: the camera-side density every strategy that takes
/// the first camera hit from the camera needs (`docs/bidirectional.md` §3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraPdf {
    /// Rays leave a point (the pinhole, a lens point, the 360° camera's centre) in a direction of
    /// this solid-angle density (pinhole 1/(A·cos³θ), A the image area at unit distance;
    /// equirectangular 1/(2π² sin θ)): the first hit x₁ has area density p·|cos θ₁|/d².
    Solid(f32),
    /// Rays leave the film plane in one direction from a point of this area density
    /// (orthographic: 1 over the film's area): x₁ has area density p·|cos θ₁|, no 1/d² — the
    /// camera vertex is a direction, as a directional light's x₀ is.
    Area(f32),
}

impl CameraPdf {
    /// The density times `k`: a filtered pixel's density is the image-wide one times the
    /// normalised filter f̂ at the ray's offset from the pixel's centre (`crate::sensor::raster`;
    /// 1 for the box).
    #[inline]
    #[must_use]
    pub fn scaled(self, k: f32) -> Self {
        match self {
            CameraPdf::Solid(p) => CameraPdf::Solid(p * k),
            CameraPdf::Area(p) => CameraPdf::Area(p * k),
        }
    }

    /// The area density of a point at |cos θ| = `cos`, `dist2` from the camera point.
    #[inline]
    fn of_point(self, cos: f32, dist2: f32) -> f64 {
        match self {
            CameraPdf::Solid(p) => p as f64 * cos as f64 / dist2 as f64,
            CameraPdf::Area(p) => p as f64 * cos as f64,
        }
    }
}

/// The camera subpath's MIS state at a vertex z_m (after [`CameraVertexMis::after_hit`]) or on
/// the segment leaving it. Values are raised to the power β; they hold no counts, so one
/// camera path serves any [`Counts`]. Its `vcm` is 1/p←(z_m)^β, the strategy that takes z_m
/// from the light side (light tracing of z₁ at the first hit, a connection deeper); its sums
/// are those of light tracing (z₁ taken from the light side) and of the connections that end
/// the light side at z₂ … z_{m−1}.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraVertexMis(Subpath<2>);

/// The camera side's count classes, in `Subpath::vc` order.
const LIGHT_TRACE: usize = 0;

impl CameraVertexMis {
    /// The state of the segment leaving the camera, whose rays are drawn with the image-wide
    /// density `pdf` ([`CameraPdf`]). The lens position's own density (thin lens) is the same
    /// for every strategy and cancels.
    #[inline]
    pub fn at_camera(pdf: CameraPdf, heuristic: Heuristic) -> Self {
        let (p, infinite_segment) = match pdf {
            CameraPdf::Solid(p) => (p, false),
            CameraPdf::Area(p) => (p, true),
        };
        let vcm = heuristic.mis(1.0 / p as f64);
        CameraVertexMis(Subpath { vcm, vc: [0.0; 2], class: LIGHT_TRACE, heuristic, infinite_segment })
    }

    /// The state at the vertex the current segment hits (as [`LightVertexMis::after_hit`]).
    #[inline]
    #[must_use]
    pub fn after_hit(self, dist2: f32, cos_in: f32) -> Self {
        CameraVertexMis(self.0.after_hit(dist2, cos_in))
    }

    /// The state of the segment leaving the current vertex (as
    /// [`LightVertexMis::after_scatter`], sides swapped): `pdf_fwd_w` is the camera tracer's
    /// density of the new direction, `pdf_rev_w` the **light tracer's** density of continuing
    /// from the new direction to the previous camera vertex, with the dataset's strategy.
    #[inline]
    #[must_use]
    pub fn after_scatter(self, cos_out: f32, pdf_fwd_w: f32, pdf_rev_w: f32, delta: bool) -> Self {
        CameraVertexMis(self.0.after_scatter(cos_out, pdf_fwd_w, pdf_rev_w, delta))
    }

    /// The heuristic the state is powered for.
    #[inline]
    pub fn heuristic(&self) -> Heuristic {
        self.0.heuristic
    }

    /// Whether this is the first hit z₁ (or the segment leaving the camera).
    #[inline]
    fn first(&self) -> bool {
        self.0.class == LIGHT_TRACE
    }

    /// The camera-side sum of a strategy that takes this vertex from the camera side and whose
    /// light side would sample it with area density `p_light` (then continue to the previous
    /// camera vertex with `pdf_rev_w`), relative to that strategy's count (`f`).
    #[inline]
    fn sum(&self, p_light: f64, pdf_rev_w: f32, f: &Factors) -> f64 {
        self.0.sum(p_light, pdf_rev_w, [f.lt, f.conn])
    }
}

/// One end of a connection (or NEE's camera end, or a splat's light end): |cos θ| of the
/// connecting segment at this vertex, the density with which this side's tracer would sample
/// the connection direction (`pdf_fwd_w`), and the density with which the other side's tracer,
/// arriving along the connection, would continue to this vertex's predecessor (`pdf_rev_w`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConnectionEnd {
    /// |cos θ| at this vertex of the connecting segment (geometric normal).
    pub cos: f32,
    /// This side's tracer's solid-angle density of the direction to the other end.
    pub pdf_fwd_w: f32,
    /// The other side's tracer's solid-angle density of the direction from here to this
    /// side's previous vertex, given that it arrived from the other end.
    pub pdf_rev_w: f32,
}

/// The strategy whose weight is computed.
#[derive(Clone, Copy)]
enum Target {
    Hit,
    Nee,
    Conn,
    LightTrace,
}

/// (n_j/n_s)^β for each count class j, for the target strategy s (module docs: n = 1, P,
/// c_conn·P, c_LT·P). Written out per target so that P cancels exactly where it cancels.
struct Factors {
    hit: f64,
    nee: f64,
    conn: f64,
    lt: f64,
}

impl Factors {
    #[inline]
    fn new(target: Target, counts: Counts, pick: f32, h: Heuristic) -> Self {
        let (c, l, p) = (counts.conn, counts.light_trace, pick as f64);
        let m = |x: f64| h.mis(x);
        match target {
            Target::Hit => Factors { hit: 1.0, nee: m(p), conn: m(c * p), lt: m(l * p) },
            Target::Nee => Factors { hit: m(1.0 / p), nee: 1.0, conn: m(c), lt: m(l) },
            Target::Conn => Factors { hit: m(1.0 / (c * p)), nee: m(1.0 / c), conn: 1.0, lt: m(l / c) },
            Target::LightTrace => Factors { hit: m(1.0 / (l * p)), nee: m(1.0 / l), conn: m(c / l), lt: 1.0 },
        }
    }
}

/// The weight of an emitter hit (s = 0): the camera path, in state `camera` after its hit on
/// an area light (or, for an environment, on the segment that left the scene: no hit
/// conversion, the environment's x₀ has a solid-angle measure), found the emitter there;
/// `emitter` holds that light's densities of the hit point (an environment: of the direction
/// the segment left in) and of the direction back to the previous camera vertex. `pick` =
/// N_k/N of the light. Zero for lights camera paths cannot hit.
#[inline]
pub fn weight_emitter_hit(camera: &CameraVertexMis, emitter: Emitter, pick: f32, counts: Counts) -> f32 {
    if !matches!(emitter.kind(), LightKind::Area | LightKind::Environment) {
        return 0.0;
    }
    let (c, h) = (&camera.0, camera.0.heuristic);
    let f = Factors::new(Target::Hit, counts, pick, h);
    // x₀ taken from the light side: NEE (deeper) or the splat of y₀ (seen directly), both
    // drawing x₀ with the light's own position density. Not `Subpath::sum`: here the class of
    // `vcm` is not that of the sum it joins deeper. An environment's y₀ is not stored (no
    // surface to splat from): seen directly, the hit is its only strategy.
    let own = match (camera.first(), emitter.kind()) {
        (true, LightKind::Area) => f.lt,
        (true, _) => 0.0,
        (false, _) => f.nee,
    };
    let older = mul(f.lt, c.vc[LIGHT_TRACE]) + mul(f.conn, c.vc[Subpath::<2>::CONN]);
    weight(mul(h.mis(emitter.first), mul(own, c.vcm) + mul(h.mis(emitter.second), older)))
}

/// The weight of next-event estimation (s = 1) from camera vertex z (state `camera`, after its
/// hit) to a light point x₀ drawn with the light's own position sampling: `at_camera` is z's
/// end of the shadow segment (its `pdf_fwd_w` the camera tracer's density toward x₀, used for
/// area lights only), `emitter` the light's densities of x₀ and of the direction x₀ → z,
/// `cos_light` |cos θ| at x₀ (area lights), `dist2` = |x₀ − z|² (ignored for directional lights).
#[inline]
pub fn weight_nee(
    camera: &CameraVertexMis,
    at_camera: ConnectionEnd,
    emitter: Emitter,
    cos_light: f32,
    dist2: f32,
    pick: f32,
    counts: Counts,
) -> f32 {
    let h = camera.heuristic();
    let f = Factors::new(Target::Nee, counts, pick, h);
    let light = match emitter.kind() {
        // The emitter hit: the camera tracer would have found x₀ with area density
        // pdf_fwd·cos θ₀/d², NEE drew it with the light's own density.
        LightKind::Area => {
            let p_hit = at_camera.pdf_fwd_w as f64 * cos_light as f64 / dist2 as f64;
            mul(f.hit, h.mis(p_hit / emitter.first))
        }
        // A camera ray leaving along the shadow ray's direction hits the environment: the
        // camera tracer's solid-angle density against NEE's.
        LightKind::Environment => mul(f.hit, h.mis(div(at_camera.pdf_fwd_w as f64, emitter.first))),
        LightKind::Point | LightKind::Directional => 0.0,
    };
    let p_light = emitter.segment(dist2 as f64) * at_camera.cos as f64;
    weight(light + camera.sum(p_light, at_camera.pdf_rev_w, &f))
}

/// The weight of a cache connection (s ≥ 2, t ≥ 2) of camera vertex z (state `camera`) to a
/// stored light vertex y (state `light`, from its [`MisRecord`]), `dist2` = |y − z|² apart.
#[inline]
pub fn weight_connection(
    camera: &CameraVertexMis,
    at_camera: ConnectionEnd,
    light: &LightVertexMis,
    at_light: ConnectionEnd,
    dist2: f32,
    pick: f32,
    counts: Counts,
) -> f32 {
    debug_assert_eq!(camera.heuristic(), light.heuristic(), "a dataset renders with its own heuristic");
    let f = Factors::new(Target::Conn, counts, pick, camera.heuristic());
    let dist2 = dist2 as f64;
    let p_camera = at_camera.pdf_fwd_w as f64 * at_light.cos as f64 / dist2; // the camera side samples y
    let p_light = at_light.pdf_fwd_w as f64 * at_camera.cos as f64 / dist2; // the light side samples z
    weight(
        light.sum(p_camera, at_light.pdf_rev_w, [f.hit, f.nee, f.conn])
            + camera.sum(p_light, at_camera.pdf_rev_w, &f),
    )
}

/// The weight of light tracing (t = 1): the stored vertex y (state `light`; y₀ of an area light
/// included) splatted to the camera, whose image-wide density of the ray camera → y is
/// `camera_pdf` ([`CameraVertexMis::at_camera`]), `dist2` away; `at_light.cos` is |cos θ| at y
/// of that direction, `at_light.pdf_rev_w` the camera tracer's density of continuing from y
/// (arriving from the camera) to y's predecessor; `at_light.pdf_fwd_w` is not used (the light
/// path hitting the lens is not a strategy).
#[inline]
pub fn weight_light_trace(
    light: &LightVertexMis,
    at_light: ConnectionEnd,
    camera_pdf: CameraPdf,
    dist2: f32,
    pick: f32,
    counts: Counts,
) -> f32 {
    let f = Factors::new(Target::LightTrace, counts, pick, light.heuristic());
    let p_camera = camera_pdf.of_point(at_light.cos, dist2);
    weight(light.sum(p_camera, at_light.pdf_rev_w, [f.hit, f.nee, f.conn]))
}

#[cfg(test)]
mod tests;
