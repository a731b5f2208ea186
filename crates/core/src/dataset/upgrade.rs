//! Upgrading a dataset to MIS records by re-tracing its passes (`docs/bidirectional.md` §7):
//! every block of every pass was traced from its own random stream, named by (seed, stream,
//! light table index, block), so tracing the same blocks again reproduces the samples bit for
//! bit — and, this time, computes their records. The chunks of a dataset are its passes' blocks
//! in the header's pass order, each pass's in [`super::block_order`] (a trace, refine, add-light
//! or resume appends them so; a merge concatenates its inputs'), so chunk i is re-traced by
//! block i of [`upgrade_plan`]. Whoever re-traces must compare each block's samples with the
//! chunk's ([`reproduces`]) and refuse a block that traced other paths: a tracer that changed
//! since, or a merge that renumbered a light (its stream was named by its old index), does not
//! reproduce the dataset. The comparison allows what a correction of the tracer's rounding
//! leaves of the same paths — vertex positions in their last bits (hit points are now snapped
//! onto their triangles), and the directions and energies computed from them — and the upgraded
//! dataset keeps its own samples, bit for bit, with the records of the re-trace.

use super::resume::traced_plan;
use super::{Block, DatasetHeader, Heuristic, LightMismatch, PassMis, Sample, TraceSettings};
use super::{block_order, scene_lights};
use crate::scene::Scene;
use crate::trace::SAMPLING_SIGNATURE;

/// Why a dataset's passes cannot be re-traced.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum UpgradeError {
    /// A light of the dataset is not in the scene as it was traced.
    #[error(transparent)]
    Light(#[from] LightMismatch),
    /// A pass recorded no plan (format version 1): which blocks it traced is unknown.
    #[error(
        "pass {pass} (seed {seed}, stream {stream}) recorded no plan (dataset format 1): its blocks cannot be re-traced"
    )]
    NoPlan {
        /// The pass.
        pass: usize,
        /// Its seed.
        seed: u64,
        /// Its stream.
        stream: u64,
    },
    /// A pass traced a number of paths that is no whole number of its first blocks.
    #[error("pass {pass} traced {paths} paths, which is no whole number of its blocks")]
    NotBlockAligned {
        /// The pass.
        pass: usize,
        /// Its paths.
        paths: u64,
    },
    /// The passes' blocks are not as many as the dataset's chunks.
    #[error(
        "the passes traced {blocks} blocks but the dataset has {chunks} chunks: not the chunks its passes made"
    )]
    ChunkCount {
        /// Blocks of the passes.
        blocks: usize,
        /// Chunks of the dataset.
        chunks: usize,
    },
}

/// One chunk's re-trace: the settings of its pass (with records) and its block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RetraceBlock {
    /// Index of the pass in the header.
    pub pass: usize,
    /// The pass's settings, records of the chosen heuristic switched on.
    pub settings: TraceSettings,
    /// The block (its light plan names the scene light and the table index of its stream).
    pub block: Block,
}

/// The header of the upgraded dataset (every pass now with records of `heuristic` and this
/// build's [`SAMPLING_SIGNATURE`]) and the block that re-traces each of its `chunks` chunks, in
/// file order. `scene` must have passed [`super::check_scene`] against the header.
pub fn upgrade_plan(
    header: &DatasetHeader,
    scene: &Scene,
    heuristic: Heuristic,
    chunks: usize,
) -> Result<(DatasetHeader, Vec<RetraceBlock>), UpgradeError> {
    let scene_lights = scene_lights(&header.table, scene)?;
    let mut blocks = Vec::with_capacity(chunks);
    for (i, p) in header.trace.passes.iter().enumerate() {
        if p.planned.is_empty() && p.paths > 0 {
            return Err(UpgradeError::NoPlan { pass: i, seed: p.seed, stream: p.stream });
        }
        let (lights, done) = traced_plan(p, |t| scene_lights[t as usize]);
        let done = done.ok_or(UpgradeError::NotBlockAligned { pass: i, paths: p.paths })?;
        let settings = TraceSettings { mis: Some(heuristic), ..p.settings() };
        blocks.extend(block_order(&lights).take(done).map(|block| RetraceBlock { pass: i, settings, block }));
    }
    if blocks.len() != chunks {
        return Err(UpgradeError::ChunkCount { blocks: blocks.len(), chunks });
    }
    let mut upgraded = header.clone();
    // The scene matched: its object hashes are the dataset's (older formats had none).
    upgraded.objects = scene.objects.clone();
    for p in &mut upgraded.trace.passes {
        p.mis = Some(PassMis { heuristic, signature: SAMPLING_SIGNATURE });
    }
    Ok((upgraded, blocks))
}

/// Whether `retraced` (a block traced again) holds the same path vertices as `stored` (the
/// dataset's chunk of that block): as many samples, each on the same triangle (or the same
/// emission), at the same place and with the same direction and energy up to rounding and its
/// growth along a path — positions within 1e-3 of the scene's scale, directions within
/// 6e-3 rad, β per channel within 1% relative (a different path lands elsewhere by the scale of
/// the scene). Measured on the committed format-2 datasets after hit points were snapped:
/// positions moved by up to 1.4e-5 m in a 2 m box. The records then carry densities of
/// vertices that far from the stored ones: MIS weights off by about that relative amount,
/// which no test can see (the weights' own rounding is 5e-5).
pub fn reproduces(stored: &[Sample], retraced: &[Sample]) -> bool {
    stored.len() == retraced.len()
        && stored.iter().zip(retraced).all(|(a, b)| {
            let (pa, pb) = (a.position(), b.position());
            let scale = pa.abs().max_element().max(1.0);
            let beta = |x: f32, y: f32| (x - y).abs() <= 1e-2 * x.abs().max(y.abs()) || x == y;
            let (ba, bb) = (a.beta(), b.beta());
            a.prim == b.prim
                && (pa - pb).abs().max_element() <= 1e-3 * scale
                && (a.from_dir == b.from_dir || a.from_dir().dot(b.from_dir()) >= 1.0 - 2e-5)
                && beta(ba.x, bb.x)
                && beta(ba.y, bb.y)
                && beta(ba.z, bb.z)
        })
}

#[cfg(test)]
mod tests {

    /// The same paths up to rounding reproduce a chunk; another triangle, a vertex elsewhere,
    /// another energy or one sample more do not.
    #[test]
    fn a_retrace_reproduces_only_the_same_paths() {
        use crate::math::{Rgb, Vec3};
        let s = |p: Vec3, prim: u32, b: f32| {
            Sample::scattered(p, Vec3::new(0.0, 0.6, 0.8), prim, Rgb::new(b, 0.5, 0.1))
        };
        let stored = [s(Vec3::new(1.0, -0.28, 0.44), 3, 0.7), s(Vec3::new(200.0, 1.0, 0.0), 5, 0.2)];
        let rounded =
            [s(Vec3::new(1.0, -0.28 + 1.4e-5, 0.44), 3, 0.7), s(Vec3::new(200.0, 1.0, 1e-4), 5, 0.2)];
        assert!(super::reproduces(&stored, &stored));
        assert!(super::reproduces(&stored, &rounded));
        assert!(!super::reproduces(&stored, &stored[..1]));
        assert!(!super::reproduces(&stored, &[stored[0], s(Vec3::new(200.0, 1.0, 0.0), 6, 0.2)]));
        assert!(!super::reproduces(&stored, &[stored[0], s(Vec3::new(200.0, 1.5, 0.0), 5, 0.2)]));
        assert!(!super::reproduces(&stored, &[stored[0], s(Vec3::new(200.0, 1.0, 0.0), 5, 0.3)]));
    }
    use super::*;
    use crate::dataset::testing::{Traced, cornell_with_bulb, trace_into};
    use crate::dataset::{StrategyChoice, TraceInfo, add_light, mis_compatibility, refine};
    use crate::scene::cornell_box;
    use crate::trace::trace_block;

    /// Why [`upgrade`] failed: no plan, or a chunk the plan does not reproduce.
    #[derive(Debug, thiserror::Error)]
    enum Failed {
        /// The dataset has no upgrade plan.
        #[error(transparent)]
        Plan(#[from] UpgradeError),
        /// Chunk `0`'s re-trace differs from the stored chunk.
        #[error("chunk {0} does not re-trace")]
        Chunk(usize),
    }

    /// Re-traces `data` by its upgrade plan, checking every chunk.
    fn upgrade(data: &Traced, scene: &Scene) -> Result<Traced, Failed> {
        let (header, blocks) = upgrade_plan(&data.header, scene, Heuristic::Power, data.chunks.len())?;
        let mut chunks = Vec::new();
        for (i, (b, old)) in blocks.iter().zip(&data.chunks).enumerate() {
            let l = b.block.light;
            let c =
                trace_block(scene, &b.settings, l.scene_light, l.table_index, b.block.index, b.block.paths);
            if (c.light, c.paths, &c.samples) != (old.light, old.paths, &old.samples) {
                return Err(Failed::Chunk(i));
            }
            chunks.push(c);
        }
        Ok(Traced { header, chunks })
    }

    fn without_records(t: &Traced) -> Traced {
        let mut t = t.clone();
        t.chunks.iter_mut().for_each(|c| c.records.clear());
        t.header.trace.passes.iter_mut().for_each(|p| p.mis = None);
        t
    }

    /// A dataset of a trace, a refinement and an added light, stripped of its records (as a
    /// format-2 file reads), re-traces to exactly itself with records; a merged one whose light
    /// indices moved does not, and says which chunk.
    #[test]
    fn re_tracing_the_passes_restores_the_records_exactly() {
        let (one, two) = (Scene::build(&cornell_box()).unwrap(), Scene::build(&cornell_with_bulb()).unwrap());
        let mut data = trace_into(&one, 9_000, 1);
        let none = StrategyChoice::default();
        let (h, pass) = refine(&data.header, &one, 5_000, None, &none).unwrap();
        data.header = h;
        data.run(&one, &pass);
        let (h, pass) = add_light(&data.header, &two, "bulb", Some(5_000), None, &none).unwrap();
        data.header = h;
        data.run(&two, &pass);
        let old = without_records(&data);
        assert!(mis_compatibility(&old.header).is_err());
        let upgraded = upgrade(&old, &two).unwrap();
        assert_eq!(upgraded, data, "the re-trace is the dataset traced with records");
        assert!(mis_compatibility(&upgraded.header).is_ok());

        // A merge whose second input's light 0 became light 1: its streams were named by 0.
        let b = trace_into(&two, 6_000, 2);
        let mut header = b.header.clone();
        header.table.lights.swap(0, 1);
        header.trace = TraceInfo { passes: b.header.trace.passes.clone() };
        for p in &mut header.trace.passes {
            p.planned.iter_mut().for_each(|(l, _)| *l = 1 - *l);
        }
        let mut swapped = b.clone();
        swapped.header = header;
        swapped.chunks.iter_mut().for_each(|c| c.light = 1 - c.light);
        let e = upgrade(&without_records(&swapped), &two).unwrap_err();
        assert!(matches!(e, Failed::Chunk(_)), "{e}");
        // Too few chunks for the passes.
        let mut cut = old.clone();
        cut.chunks.pop();
        let e = upgrade(&cut, &two).unwrap_err();
        assert!(matches!(e, Failed::Plan(UpgradeError::ChunkCount { .. })), "{e}");
        assert!(e.to_string().contains("but the dataset has"), "{e}");
    }
}
