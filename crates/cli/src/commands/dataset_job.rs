//! The one way datasets are written: copy the chunks of existing datasets (refine, add-light,
//! merge), trace new paths into it (trace, refine, add-light), and finish it atomically.
//!
//! Tracing and writing overlap (a writer thread drains finished chunks while the next batch
//! traces). On Ctrl-C the paths completed so far are saved beside the target as
//! `NAME.partial.opds` — a valid dataset with those N_k — and the target is left as it was.
//! Its last pass records the plan, so `opticks resume` traces exactly the missing blocks.

use super::trace_with_progress;
use crate::strategy_args::StrategyArgs;
use anyhow::{Context, Result, anyhow, bail};
use opticks_core::dataset::{Chunk, LightTable};
use opticks_core::scene::Scene;
use opticks_core::trace::{LightPlan, TraceSettings};
use opticks_io::dataset_file::{DatasetHeader, DatasetReader, DatasetSummary, DatasetWriter, TracePass};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The arguments `refine` and `add-light` share: where the extended dataset goes, and the
/// seed, strategy and threads of the pass they add.
#[derive(clap::Args, Debug)]
pub struct ExtendArgs {
    /// Where to write the result (default: replace the dataset).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Seed (default: the dataset's first; a stream not used yet is picked either way).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Strategy options (default: those of the dataset's last pass).
    #[command(flatten)]
    pub strategy: StrategyArgs,
    #[command(flatten)]
    pub threads: super::ThreadArgs,
}

/// New paths to trace into the dataset.
pub struct NewPaths<'a> {
    /// The scene (its geometry fingerprint is the header's).
    pub scene: &'a Scene,
    /// Seed, stream and roulette depth.
    pub settings: TraceSettings,
    /// Which lights, filed under which table index, how many paths.
    pub plan: Vec<LightPlan>,
    /// Blocks of the plan already in the sources (non-zero when resuming an interrupted pass).
    pub first_block: usize,
}

/// A dataset whose chunks are copied into the new one.
pub struct Source<'a> {
    /// The dataset.
    pub reader: &'a DatasetReader,
    /// Where each of its lights is in the new table (`None`: at the same index).
    pub lights: Option<Vec<u32>>,
}

impl<'a> Source<'a> {
    /// All chunks of `reader`, under their own light indices.
    pub fn as_is(reader: &'a DatasetReader) -> Self {
        Source { reader, lights: None }
    }
}

/// What the job produced.
pub struct JobReport {
    /// The file written.
    pub summary: DatasetSummary,
    /// Its final light table.
    pub table: LightTable,
    /// Seconds spent tracing (0 without new paths).
    pub trace_seconds: f64,
}

/// Writes `header` (whose table lists every light, with N_k = the paths of the copied chunks,
/// and whose last pass is the new one when `new` is given) to `output`: first every chunk of
/// `sources`, then the new paths.
pub fn write_dataset(
    output: &Path,
    mut header: DatasetHeader,
    sources: &[Source<'_>],
    new: Option<NewPaths<'_>>,
) -> Result<JobReport> {
    let mut writer = DatasetWriter::create(output, &header)
        .with_context(|| format!("cannot create dataset {}", output.display()))?;
    for source in sources {
        let r = source.reader;
        for i in 0..r.chunk_count() {
            let mut c = r.chunk(i)?.to_chunk();
            if let Some(map) = &source.lights {
                c.light = map[c.light as usize];
            }
            super::unless_interrupted()
                .with_context(|| format!("{} was left as it was", output.display()))?;
            writer.write_chunk(&c)?;
        }
    }
    let mut trace_seconds = 0.0;
    let mut interrupted = false;
    if let Some(new) = new {
        let t0 = Instant::now();
        let (traced, w) = trace_overlapped(writer, &new)?;
        writer = w;
        trace_seconds = t0.elapsed().as_secs_f64();
        for (p, n) in new.plan.iter().zip(&traced) {
            header.table.lights[p.table_index as usize].paths += n;
        }
        let pass = header.trace.passes.last_mut().ok_or_else(|| anyhow!("a new pass needs a pass record"))?;
        pass.paths += traced.iter().sum::<u64>();
        pass.seconds += trace_seconds as f32;
        interrupted = !pass.is_complete();
    }
    let target = if interrupted { partial_path(output) } else { output.to_owned() };
    writer.retarget(&target);
    let summary = writer
        .finish(&header.table, &header.trace)
        .with_context(|| format!("cannot write dataset {}", target.display()))?;
    if interrupted {
        bail!(
            "interrupted: {} was left as it was; the {} paths completed are saved in {} \
             (a valid dataset: render it, or `opticks resume {}` to finish the run)",
            output.display(),
            header.trace.passes.last().map_or(0, |p| p.paths),
            target.display(),
            target.display()
        );
    }
    Ok(JobReport { summary, table: header.table, trace_seconds })
}

/// Writes `reader`'s chunks and then the new paths of `plan` (a new pass of `settings`) to
/// `output`: `refine` and `add-light`.
pub fn extend_dataset(
    reader: &DatasetReader,
    mut header: DatasetHeader,
    output: &Path,
    scene: &Scene,
    settings: TraceSettings,
    plan: Vec<LightPlan>,
) -> Result<JobReport> {
    header.trace.passes.push(TracePass::new(&settings, &plan));
    let new = NewPaths { scene, settings, plan, first_block: 0 };
    write_dataset(output, header, &[Source::as_is(reader)], Some(new))
}

/// `dir/NAME.partial.opds` for `dir/NAME.opds`.
pub fn partial_path(output: &Path) -> PathBuf {
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    output.with_file_name(format!("{stem}.partial.opds"))
}

/// The settings of a pass that continues a dataset (`refine`, `add-light`): `seed` or the
/// dataset's first, a stream no pass of that seed has used, and the strategy of the dataset's
/// last pass unless `strategy` overrides it — so that the new paths are drawn by the same
/// estimator as the old ones.
pub fn continued_settings(
    header: &DatasetHeader,
    paths: u64,
    seed: Option<u64>,
    strategy: &StrategyArgs,
) -> TraceSettings {
    let seed = seed.unwrap_or(header.trace.passes.first().map_or(0, |p| p.seed));
    let last = header.trace.passes.last().map(|p| p.settings()).unwrap_or_default();
    let base = TraceSettings { paths, seed, stream: header.trace.next_stream(seed), ..last };
    let s = strategy.over(base);
    TraceSettings { rr_depth: s.rr_depth.max(1), ..s }
}

/// The scene light of each light of the dataset's table, found by name; refuses lights that
/// are gone or emit from another place or in another way (their shape hash differs).
pub fn scene_lights(table: &LightTable, scene: &Scene, verb: &str) -> Result<Vec<usize>> {
    table
        .lights
        .iter()
        .map(|record| match scene.light_index(&record.name) {
            Some(i) if scene.light_shapes[i] == record.shape => Ok(i),
            Some(_) => bail!(
                "light '{}' has moved or changed shape since the trace: {verb} needs the same scene",
                record.name
            ),
            None => bail!(
                "light '{}' of the dataset is not in the scene any more: {verb} needs the same scene",
                record.name
            ),
        })
        .collect()
}

/// Traces `new.plan` on the rayon pool while a writer thread appends the chunks.
fn trace_overlapped(mut writer: DatasetWriter, new: &NewPaths<'_>) -> Result<(Vec<u64>, DatasetWriter)> {
    std::thread::scope(|s| {
        let (send, receive) = std::sync::mpsc::sync_channel::<Chunk>(128);
        let writing = s.spawn(move || -> Result<DatasetWriter> {
            for c in receive {
                writer.write_chunk(&c)?;
            }
            Ok(writer)
        });
        let traced = trace_with_progress(new.scene, &new.settings, &new.plan, new.first_block, |c| {
            send.send(c).map_err(|_| anyhow!("the dataset writer stopped"))
        });
        drop(send);
        let written = writing.join().map_err(|_| anyhow!("the dataset writer panicked"))?;
        // A write error explains a trace that stopped because the writer did: report it first.
        let writer = written?;
        Ok((traced?, writer))
    })
}
