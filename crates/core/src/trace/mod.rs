//! Light sampling, the thesis's Algorithm 1: paths start at the lights, bounce through the
//! scene by importance-sampling each BSDF, and every vertex that can reflect light is stored as
//! a [`Sample`]. **Trace never sees a camera.**
//!
//! Weights follow docs/estimator.md §2–3: β₁ = 1 (the first ray carries the light's share Φ_k/N_k),
//! β_{i+1} = β_i · f_r·|cos θ_o|/p(ω_o), divided by q when Russian roulette (from depth
//! `rr_depth` on, survival q = min(2·max β, 0.95)) lets a path survive. The estimator is unbiased
//! and nothing is normalised by the sum of weights (the thesis's eq. 6.8 would be biased).
//!
//! Delta surfaces (ideal mirrors, smooth dielectrics, [`crate::bsdf::Bsdf::is_delta`]) are not stored: their
//! BSDF is zero for every direction a sensor could ask about, so such a vertex could never
//! contribute. The path continues through them with β ← β·weight, the weight of
//! [`TransportMode::Importance`]: a light path carries flux, which an interface transmits
//! unchanged (times 1 − F), so refraction's 1/η² radiance scaling does **not** apply here
//! (docs/estimator.md §4; the adjoint BSDF, Veach's thesis §5.2; see the `bsdf` module docs).
//! With shading normals the weight is the adjoint one, f_eff·|cos θ_o,geometric|/p
//! ([`crate::bsdf::shading`] derives it); sides and ray offsets always follow the geometric
//! normal. Dielectrics scatter on both faces, so a path may enter a glass object, bounce inside it
//! (total internal reflection) and leave it.
//!
//! Absorbing glass (Beer–Lambert): a dielectric may bound an absorbing inside of coefficient
//! σ_a ([`crate::bsdf::Bsdf::absorption`]); flux crossing a distance t inside is multiplied by
//! exp(−σ_a·t) per channel, at the segment's end, before the vertex there is stored. Which
//! medium a segment travels in is decided where it starts, locally: a segment leaving a
//! dielectric surface on its **back** side (the inside, behind the geometric normal) is inside
//! that object and carries its σ_a; one leaving on the front side is outside (σ_a = 0); a
//! segment leaving any other surface (a diffuse receiver inside a glass block, a mirror) stays
//! in the medium the path arrived in. Paths start outside (σ_a = 0). This is exact for closed,
//! non-nested dielectric objects with lights outside them; a dielectric inside another one is
//! not modelled (leaving the inner one puts the path back in vacuum, not in the outer medium).
//!
//! What to trace is the dataset's plan (`crate::dataset`'s `plan.rs`, re-exported here where
//! call sites want it): the [`TraceSettings`] and strategy, and a [`LightPlan`] per light saying
//! how far to trace it — all lights for a new dataset, all of them again with a fresh stream for
//! a refinement, or only a new light when one is added to an existing dataset.
//!
//! Parallelism and determinism: each light's quota N_k is cut into blocks of
//! [`BLOCK_PATHS`] paths; block b of light k draws from its own random stream named by
//! (seed, stream, k, b) and becomes one [`Chunk`]. Blocks are traced in parallel (rayon) in the
//! plan's [`block_order`] and handed to the sink in that order, so the dataset is the same
//! whatever the thread count. Blocks of different lights are interleaved, so a trace stopped
//! early is still balanced.

use crate::bsdf::TransportMode;
#[cfg(doc)]
use crate::dataset::LightVertexMis;
use crate::dataset::{Block, Chunk, LightTable, MisRecord, Sample, block_order, plan_all, planned_table};
use crate::geometry::{Ray, offset_ray_origin};
use crate::math::{Rgb, Vec3};
use crate::sampling::RandomStream;
use crate::scene::Scene;
use mis::{PathMis, SegmentMis};
use rayon::prelude::*;

mod mis;

pub use crate::dataset::{BLOCK_PATHS, Directions, LightPlan, Roulette, Selection, TraceSettings};
pub use mis::{
    SAMPLING_SIGNATURE, emitter_densities, light_direction_pdf, light_direction_pdf_at, samples_uniformly,
};

/// Russian roulette survival probability is q = min(0.95, ROULETTE_SCALE · max β): a path still
/// carrying half of its light's share is never culled more often than one time in twenty.
/// Measured on the Cornell box at 4M paths (four seeds): scale 2 gives relMSE 4.05e-3 with
/// 4.35 stored vertices per path, scale 1 gives 4.24e-3 with 4.18, no roulette at all 4.01e-3
/// with 7.4; Mitsuba's `ptracer` 3.99e-3.
const ROULETTE_SCALE: f32 = 2.0;

/// Russian roulette does not act on delta vertices (see [`trace_path`]), so light trapped by
/// total internal reflection could bounce forever. After this many delta surfaces (mirrors,
/// smooth glass) in a row, each further delta bounce survives with probability
/// [`DELTA_RUN_SURVIVAL`] and divides β by it: the estimator stays unbiased (no truncation
/// anywhere in the tracer), and a trapped path still ends (after ~20 more bounces on average).
/// Paths this long are so rare in real scenes (a 0.5-radius glass icosphere in a furnace room:
/// none measurable) that the larger weights they then carry add no visible noise; only a lossless
/// cavity that light almost never leaves (escape probability per bounce below 1 − q) would make
/// those weights' variance large, and there truncation would instead be a visible bias.
const MAX_DELTA_RUN: u32 = 1024;

/// Survival probability of a delta bounce beyond [`MAX_DELTA_RUN`].
const DELTA_RUN_SURVIVAL: f32 = 0.95;

/// Blocks traced per parallel batch before they are handed to the sink in order.
const BATCH_BLOCKS: usize = 64;

/// The energy a path is kept at under [`Selection::Priority`].
pub const PRIORITY_TARGET: f32 = 0.5;
/// Most children a vertex gets under [`Selection::Priority`].
pub const MAX_SPLIT: f32 = 8.0;

/// A path continuation waiting to be traced (splitting makes a path a tree), carrying the MIS
/// state `M` of its segment (`()` when no records are made, so that a trace without records
/// moves exactly the bytes it always moved).
#[derive(Clone, Copy, Debug)]
struct Branch<M> {
    origin: Vec3,
    dir: Vec3,
    beta: Rgb,
    depth: u32,
    /// Consecutive delta (mirror, glass) bounces just before this branch.
    delta_run: u32,
    /// Absorption coefficient σ_a (1/m) of the medium this segment travels in (module docs).
    absorption: Rgb,
    mis: M,
}

/// Scratch space of [`trace_path`], reused across paths: the branches waiting to be traced.
#[derive(Clone, Debug, Default)]
pub struct PathScratch {
    plain: Vec<Branch<()>>,
    with_records: Vec<Branch<SegmentMis>>,
}

/// Traces one path (a tree, under [`Selection::Priority`]) from light `k`, appending its stored
/// vertices to `out` and, when `settings.mis` asks for them, each one's MIS record to
/// `records` (the same order: `records[i]` belongs to `out[i]`). `scratch` is reused across
/// paths.
///
/// The records follow `docs/bidirectional.md` §4: the state starts at the emission
/// ([`LightVertexMis::at_emission`] with the light's own densities, [`emitter_densities`]; y₀
/// of an area light stores [`LightVertexMis::emission_vertex`]), becomes the hit vertex's
/// ([`LightVertexMis::after_hit`]: squared distance between the vertices, |cos θ| of the
/// arriving direction against the geometric normal) and continues with every child
/// ([`LightVertexMis::after_scatter`]: |cos θ| of the new direction, the density it was drawn
/// with — uniform or importance, or the delta lobe's probability — and the camera tracer's
/// density [`crate::bsdf::Material::pdf_world`] of the reverse step). Roulette, selection and
/// the delta-run survival do not enter. Records draw no random numbers: the samples are the
/// same with and without them.
#[inline]
pub fn trace_path(
    scene: &Scene,
    k: usize,
    settings: &TraceSettings,
    rng: &mut RandomStream,
    out: &mut Vec<Sample>,
    records: &mut Vec<MisRecord>,
    scratch: &mut PathScratch,
) {
    match settings.mis {
        None => walk(scene, k, settings, rng, out, &mut (), &mut scratch.plain),
        Some(h) => walk(scene, k, settings, rng, out, &mut (h, records), &mut scratch.with_records),
    }
}

/// [`trace_path`] with the MIS state `M` (the records it makes go to `sink`).
#[inline(always)]
fn walk<M: PathMis>(
    scene: &Scene,
    k: usize,
    settings: &TraceSettings,
    rng: &mut RandomStream,
    out: &mut Vec<Sample>,
    sink: &mut M::Sink<'_>,
    stack: &mut Vec<Branch<M>>,
) {
    let (u_pos, u_dir) = (rng.next_2d(), rng.next_2d());
    let light = &scene.lights[k];
    let e = light.sample_emission(&scene.triangles, u_pos, u_dir);
    if !(e.emitted.max_element() > 0.0) {
        return; // a textured light's black point: the path carries nothing (it still counts in N_k)
    }
    let mut origin = e.origin;
    let mis = M::at_emission(light, &e, sink);
    if let Some((normal, prim)) = e.surface {
        let mut start = Sample::emitted(e.origin, prim);
        start.beta = e.emitted.to_array(); // T(uv)/T̄ of a textured light, else 1 as before
        out.push(start);
        origin = offset_ray_origin(e.origin, normal, e.dir);
    }
    stack.clear();
    stack.push(Branch {
        origin,
        dir: e.dir,
        beta: e.weight,
        depth: 0,
        delta_run: 0,
        absorption: Rgb::ZERO,
        mis,
    });
    while let Some(mut b) = stack.pop() {
        let Some(hit) = scene.intersect(&Ray { origin: b.origin, dir: b.dir, t_max: f32::INFINITY }) else {
            continue;
        };
        let depth = b.depth + 1;
        let wi = -b.dir;
        let mut resolved = None;
        let (material, normals) = scene.surface_at(hit.prim, hit.position, &mut resolved);
        // One shading frame for the vertex's queries: the side, each child's sample, its MIS
        // record's reverse density.
        let point = material.at(normals);
        let from = point.direction(wi);
        if !point.scatters_from(&from) {
            continue; // the back of a one-sided surface: black, absorbs everything
        }
        if b.absorption != Rgb::ZERO {
            b.beta *= (-b.absorption * hit.t).exp(); // Beer–Lambert along the segment
        }
        let mis = b.mis.after_hit(hit.position, wi.dot(hit.normal).abs());
        let delta = material.bsdf.is_delta();
        if !delta {
            out.push(Sample::scattered(hit.position, wi, hit.prim, b.beta));
            mis.store(sink);
        }
        // Priority selection: c expected children, each carrying 1/c of the weight.
        let c = match settings.selection {
            Selection::Priority if !delta => (b.beta.max_element() / PRIORITY_TARGET).clamp(1.0, MAX_SPLIT),
            _ => 1.0,
        };
        // c is in [1, MAX_SPLIT] (or NaN: no child either way), where its truncation is its
        // floor: the same counts as c.floor() and c.fract(), without their libm calls.
        let whole = c as u32;
        let children = whole + u32::from(rng.next_f32() < c - whole as f32);
        for _ in 0..children {
            let (u_lobe, u) = (rng.next_f32(), rng.next_2d());
            // Importance mode: `wi` is where the light came from (no 1/η² on refraction, DESIGN §2).
            // Uniform directions only make sense for reflecting surfaces without a delta lobe.
            let sampled = if samples_uniformly(settings.directions, &material.bsdf) {
                point.sample_uniform(&from, u)
            } else {
                point.sample(&from, u_lobe, u, TransportMode::Importance)
            };
            let Some(s) = sampled else { continue };
            let mut beta = b.beta * s.weight / c;
            let mut delta_run = 0;
            if s.delta {
                // Roulette acts at stored vertices only: through clear glass β stays 1, so
                // rouletting there would turn light bouncing many times inside an object (total
                // internal reflection in a tessellated sphere) into rare huge weights 1/0.95^k —
                // unbiased, but so heavy-tailed that a million paths measurably underestimate
                // the flux.
                delta_run = b.delta_run + 1;
                if delta_run > MAX_DELTA_RUN {
                    if !(rng.next_f32() < DELTA_RUN_SURVIVAL) {
                        continue;
                    }
                    beta /= DELTA_RUN_SURVIVAL;
                }
            } else if depth >= settings.rr_depth && c <= 1.0 {
                let q = match settings.roulette {
                    Roulette::Energy => (ROULETTE_SCALE * beta.max_element()).min(0.95),
                    Roulette::Fixed => 0.95,
                };
                if !(rng.next_f32() < q) {
                    continue;
                }
                beta /= q;
            }
            // The medium of the next segment: a dielectric's inside is behind its normal.
            let absorption = match material.bsdf.transmits() {
                true if s.wo.dot(hit.normal) < 0.0 => material.bsdf.absorption(),
                true => Rgb::ZERO,
                false => b.absorption,
            };
            if beta.max_element() > 0.0 {
                // The camera tracer, arriving from s.wo, would continue toward wi.
                let rev = || point.pdf_of(&point.direction(s.wo), &from, s.delta);
                let mis = mis.after_scatter(s.wo.dot(hit.normal).abs(), s.pdf, rev, s.delta);
                stack.push(Branch {
                    origin: offset_ray_origin(hit.position, hit.normal, s.wo),
                    dir: s.wo,
                    beta,
                    depth,
                    delta_run,
                    absorption,
                    mis,
                });
            }
        }
    }
}

/// Traces block `block` of scene light `k` into a chunk filed under `table_index` (which, with
/// the seed, the stream and the block, names the block's random stream).
pub fn trace_block(
    scene: &Scene,
    settings: &TraceSettings,
    k: usize,
    table_index: u32,
    block: u64,
    paths: u64,
) -> Chunk {
    let mut rng = RandomStream::new(settings.seed, &[settings.stream, table_index as u64, block]);
    let mut samples = Vec::with_capacity(paths as usize * 6);
    let mut records = Vec::with_capacity(if settings.mis.is_some() { samples.capacity() } else { 0 });
    let mut scratch = PathScratch::default();
    for _ in 0..paths {
        trace_path(scene, k, settings, &mut rng, &mut samples, &mut records, &mut scratch);
    }
    debug_assert!(records.is_empty() || records.len() == samples.len());
    Chunk { light: table_index, paths, samples, records }
}

/// Traces the plan, handing chunks to `sink` in a deterministic order and calling
/// `progress(paths_done)` after each batch. Between batches `stop()` is asked whether to end
/// early (Ctrl-C). Returns the paths actually traced per plan entry: every chunk handed to the
/// sink is complete, so stopping early still leaves a valid, unbiased dataset with those N_k.
pub fn trace_plan<E>(
    scene: &Scene,
    settings: &TraceSettings,
    plan: &[LightPlan],
    sink: impl FnMut(Chunk) -> Result<(), E>,
    progress: impl Fn(u64),
    stop: impl Fn() -> bool,
) -> Result<Vec<u64>, E> {
    trace_plan_from(scene, settings, plan, 0, sink, progress, stop)
}

/// [`trace_plan`] without its first `first_block` blocks: resumes a run of the plan that was
/// stopped after that many ([`crate::dataset::blocks_done`]). Every block has its own random stream, so the
/// chunks are exactly those the uninterrupted run would have produced after them.
pub fn trace_plan_from<E>(
    scene: &Scene,
    settings: &TraceSettings,
    plan: &[LightPlan],
    first_block: usize,
    mut sink: impl FnMut(Chunk) -> Result<(), E>,
    progress: impl Fn(u64),
    stop: impl Fn() -> bool,
) -> Result<Vec<u64>, E> {
    // The plan's blocks are made lazily, a batch at a time: memory and the time to the first
    // batch (and so to the first check of `stop`) do not depend on the path count.
    let mut blocks = block_order(plan).skip(first_block);
    let mut traced = vec![0u64; plan.len()];
    let mut done = 0u64;
    let mut batch = Vec::with_capacity(BATCH_BLOCKS);
    loop {
        if stop() {
            break;
        }
        batch.clear();
        batch.extend(blocks.by_ref().take(BATCH_BLOCKS));
        if batch.is_empty() {
            break;
        }
        let block = |b: &Block| {
            trace_block(scene, settings, b.light.scene_light, b.light.table_index, b.index, b.paths)
        };
        // A batch of one block (a plan of ≤ 4096 paths a light, one light) is traced on this
        // thread: the same chunk (its stream is named by the block), without starting the pool's
        // threads (~0.3 ms of a 3 ms trace of a small case).
        let chunks: Vec<Chunk> = match batch.as_slice() {
            [one] => vec![block(one)],
            _ => batch.par_iter().map(block).collect(),
        };
        for c in chunks {
            done += c.paths;
            if let Some(i) = plan.iter().position(|p| p.table_index == c.light) {
                traced[i] += c.paths;
            }
            sink(c)?;
        }
        progress(done);
    }
    Ok(traced)
}

/// Traces `settings.paths` light paths over all lights ([`plan_all`]), handing chunks to `sink`
/// in a deterministic order. Returns the light table (Φ_k, N_k).
pub fn trace<E>(
    scene: &Scene,
    settings: &TraceSettings,
    sink: impl FnMut(Chunk) -> Result<(), E>,
    progress: impl Fn(u64),
) -> Result<LightTable, E> {
    let plan = plan_all(scene, settings.paths);
    trace_plan(scene, settings, &plan, sink, progress, || false)?;
    Ok(planned_table(scene, settings.paths))
}
