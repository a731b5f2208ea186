//! The one way datasets are written: copy the chunks of existing datasets (a refinement, an
//! added light, a merge), trace new paths into it (a trace, a refinement, an added light, a
//! resumption), and finish it atomically. What to write — the header, the pass and its plan —
//! comes from the core (`opticks_core::dataset`); this module does the files.
//!
//! Tracing and writing overlap (a writer thread drains finished chunks while the next batch
//! traces). Progress and the request to stop are the caller's ([`JobProgress`]), asked between
//! chunks copied and between batches traced. Stopped while copying, nothing is written; stopped
//! while tracing, the paths completed so far are saved beside the target as
//! `NAME.partial.opds` ([`partial_path`]) — a valid dataset with those N_k — and the target is
//! left as it was. Its last pass records the plan, so resuming it
//! (`opticks_core::dataset::resume_plan`) traces exactly the missing blocks, into the target
//! again ([`finished_path`]).
//!
//! Who traces the new paths is a [`PassTracer`]: this process on its rayon pool
//! ([`LocalTracer`], what [`write_dataset`] uses), or, in the CLI's cluster build, worker
//! processes that an MPI master hands the blocks to ([`write_dataset_with`]). Either way the
//! chunks arrive in the plan's block order, so the file is the same.

use crate::dataset_file::{DatasetError, DatasetReader, DatasetSummary, DatasetWriter};
use opticks_core::dataset::{
    Chunk, DatasetHeader, LightTable, NoPassRecord, PassPlan, TooManyPaths, TraceSettings, UpgradeError,
    upgrade_plan,
};
use opticks_core::dataset::{Heuristic, check_path_budget, end_pass_here, reproduces};
use opticks_core::scene::Scene;
use opticks_core::trace::{trace_block, trace_plan_from};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

mod space;
pub use space::{ASSUMED_BYTES_PER_PATH, SpaceShortfall, estimate_bytes, free_space, preflight};

/// What a long job reports, and how it is asked to stop (by default: silently, never).
pub trait JobProgress {
    /// Tracing begins; `paths` are planned in all (those of blocks already done included).
    fn tracing(&self, _paths: u64) {}
    /// `done` paths have been traced so far by this run (called after each batch of blocks).
    fn traced(&self, _done: u64) {}
    /// Tracing ended without an error (completely, or stopped).
    fn traced_all(&self) {}
    /// Whether to stop (e.g. Ctrl-C was pressed): asked before each chunk copied and between
    /// batches of blocks traced.
    fn stop(&self) -> bool {
        false
    }
    /// Whether the stop asked for was the run's own time limit (`--time`), not a signal: a run
    /// with a time limit is complete by definition, so its pass ends where it stopped
    /// ([`opticks_core::dataset::end_pass_here`]) and the dataset is written whole, not saved as
    /// a partial run to resume.
    fn time_is_up(&self) -> bool {
        false
    }
}

/// No progress shown, never stopped.
impl JobProgress for () {}

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

/// New paths to trace into the dataset: a pass of `scene` (its geometry fingerprint is the
/// header's).
pub struct NewPaths<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// Settings, plan, and the blocks of it already in the sources (when resuming).
    pub pass: PassPlan,
}

/// What the job produced.
#[derive(Debug)]
pub struct JobReport {
    /// The file written.
    pub summary: DatasetSummary,
    /// Its final light table.
    pub table: LightTable,
    /// Seconds spent tracing (0 without new paths).
    pub trace_seconds: f64,
}

/// Why a dataset was not written.
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    /// The dataset file could not be started.
    #[error("cannot create dataset {}", path.display())]
    Create {
        /// The target.
        path: PathBuf,
        /// Why.
        #[source]
        source: DatasetError,
    },
    /// A source chunk could not be read, or a chunk not written.
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    /// The dataset would replace a file the run reads other than a source dataset (a file the
    /// scene names); refused before any work.
    #[error(transparent)]
    ReplacesInput(#[from] crate::output_paths::OutputError),
    /// Asked to stop while copying: nothing was written.
    #[error("{} was left as it was: interrupted: stopped, nothing written", output.display())]
    Stopped {
        /// The target, untouched.
        output: PathBuf,
    },
    /// Asked to stop while tracing: the target is untouched, the paths completed are saved in
    /// `partial`.
    #[error(
        "interrupted: {} was left as it was; the {paths} paths completed are saved in {}",
        output.display(),
        partial.display()
    )]
    Interrupted {
        /// The target, untouched.
        output: PathBuf,
        /// The valid partial dataset written instead ([`partial_path`]).
        partial: PathBuf,
        /// The paths the interrupted pass has traced.
        paths: u64,
    },
    /// The finished dataset could not be written.
    #[error("cannot write dataset {}", path.display())]
    Finish {
        /// The file being finished.
        path: PathBuf,
        /// Why.
        #[source]
        source: DatasetError,
    },
    /// New paths came without a pass record in the header.
    #[error(transparent)]
    NoPass(#[from] NoPassRecord),
    /// The pass would take the dataset beyond the most paths a dataset may hold (checked before
    /// anything is written or traced).
    #[error("cannot trace into {}: {source}", path.display())]
    TooManyPaths {
        /// The target.
        path: PathBuf,
        /// The counts.
        #[source]
        source: TooManyPaths,
    },
    /// Writing failed while tracing (a full disk): the target is untouched, and the chunks
    /// written before the failure are saved in `partial`, if that could be done.
    #[error(
        "{source}{}",
        match partial {
            Some(p) => format!("; {} was left as it was, and the {paths} paths written are saved in {}", output.display(), p.display()),
            None => format!("; {} was left as it was", output.display()),
        }
    )]
    WriteFailed {
        /// The target, untouched.
        output: PathBuf,
        /// The valid partial dataset of the chunks written, if it could be finished.
        partial: Option<PathBuf>,
        /// The paths of the interrupted pass it holds.
        paths: u64,
        /// Why writing failed.
        #[source]
        source: Box<DatasetError>,
    },
    /// The dataset's passes cannot be re-traced.
    #[error(transparent)]
    Upgrade(#[from] UpgradeError),
    /// A re-traced chunk differs from the dataset's: nothing was written.
    #[error(
        "chunk {chunk} (pass {pass}: seed {seed}, stream {stream}) does not re-trace to the same samples: this \
         Opticks traces differently from the one that wrote the dataset, or a merge renumbered its light; \
         nothing was written (trace the dataset anew instead)"
    )]
    NotReproduced {
        /// The chunk.
        chunk: usize,
        /// Its pass.
        pass: usize,
        /// The pass's seed.
        seed: u64,
        /// The pass's stream.
        stream: u64,
    },
    /// The tracer failed (a [`PassTracer`] other than [`LocalTracer`]: e.g. a cluster job whose
    /// workers could not take part).
    #[error("{0}")]
    Trace(String),
    /// The writer thread ended before the tracer.
    #[error("the dataset writer stopped")]
    WriterStopped,
    /// The writer thread panicked.
    #[error("the dataset writer panicked")]
    WriterPanicked,
    /// A resumed dataset was finished, but its partial file could not be removed.
    #[error("finished {}, but cannot remove {}: {source}", output.display(), partial.display())]
    RemovePartial {
        /// The finished dataset.
        output: PathBuf,
        /// The partial dataset it was resumed from.
        partial: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
}

/// Writes `header` (whose table lists every light, with N_k = the paths of the copied chunks,
/// and whose last pass is the new one when `new` is given) to `output`: first every chunk of
/// `sources`, then the new paths, booked in the header as they are traced
/// ([`DatasetHeader::record_traced`]). Stopped while tracing, the completed paths go to
/// [`partial_path`]`(output)` instead and the error says so.
pub fn write_dataset(
    output: &Path,
    header: DatasetHeader,
    sources: &[Source<'_>],
    new: Option<NewPaths<'_>>,
    progress: &dyn JobProgress,
) -> Result<JobReport, JobError> {
    write_dataset_with(output, header, sources, new, progress, &LocalTracer)
}

/// Who traces a pass's blocks for [`write_dataset_with`]. `trace_pass` hands every chunk to
/// `sink` in the plan's block order (after the first `pass.first_block`), reports to
/// `progress` and stops between blocks when it asks to; it returns the paths traced per plan
/// entry. Every chunk handed over is complete, so a stop leaves a valid prefix of the plan.
pub trait PassTracer {
    /// Traces `pass` of `scene` into `sink`.
    fn trace_pass(
        &self,
        scene: &Scene,
        pass: &PassPlan,
        sink: &mut dyn FnMut(Chunk) -> Result<(), JobError>,
        progress: &dyn JobProgress,
    ) -> Result<Vec<u64>, JobError>;
}

/// Traces in this process, on the rayon pool ([`trace_observed`]).
pub struct LocalTracer;

impl PassTracer for LocalTracer {
    fn trace_pass(
        &self,
        scene: &Scene,
        pass: &PassPlan,
        sink: &mut dyn FnMut(Chunk) -> Result<(), JobError>,
        progress: &dyn JobProgress,
    ) -> Result<Vec<u64>, JobError> {
        trace_observed(scene, pass, sink, progress)
    }
}

/// [`write_dataset`] with the new paths traced by `tracer`.
pub fn write_dataset_with(
    output: &Path,
    mut header: DatasetHeader,
    sources: &[Source<'_>],
    new: Option<NewPaths<'_>>,
    progress: &dyn JobProgress,
    tracer: &dyn PassTracer,
) -> Result<JobReport, JobError> {
    if let Some(new) = &new {
        check_path_budget(&header.table, &new.pass)
            .map_err(|source| JobError::TooManyPaths { path: output.to_owned(), source })?;
    }
    // Replacing a source dataset is the documented in-place update; nothing else read may go.
    if !sources.iter().any(|s| crate::dataset_lock::same_file(s.reader.path(), output)) {
        crate::output_paths::spares_what_was_read(output)?;
    }
    let mut writer = DatasetWriter::create(output, &header)
        .map_err(|source| JobError::Create { path: output.to_owned(), source })?;
    for source in sources {
        let r = source.reader;
        for i in 0..r.chunk_count() {
            let mut c = r.owned_chunk(i)?;
            if let Some(map) = &source.lights {
                c.light = map[c.light as usize];
            }
            if progress.stop() {
                return Err(JobError::Stopped { output: output.to_owned() });
            }
            writer.write_chunk(&c)?;
        }
    }
    let mut trace_seconds = 0.0;
    let mut interrupted = false;
    if let Some(new) = new {
        let t0 = Instant::now();
        let (traced, w, failed) = trace_overlapped(writer, &new, progress, tracer)?;
        writer = w;
        trace_seconds = t0.elapsed().as_secs_f64();
        if let Some(source) = failed {
            return Err(save_written(writer, header, &new, output, trace_seconds, source));
        }
        interrupted = !header.record_traced(&new.pass.lights, &traced?, trace_seconds)?;
        // Out of time: the pass ends here, complete. (Only if every light it was to trace has a
        // path by now; otherwise it is saved to be resumed, as an interrupted run is.)
        if interrupted && progress.time_is_up() && end_pass_here(&mut header).is_ok() {
            interrupted = false;
        }
    }
    let target = if interrupted { partial_path(output) } else { output.to_owned() };
    writer.retarget(&target);
    let summary = writer
        .finish(&header.table, &header.trace)
        .map_err(|source| JobError::Finish { path: target.clone(), source })?;
    if interrupted {
        return Err(JobError::Interrupted {
            output: output.to_owned(),
            partial: target,
            paths: header.trace.passes.last().map_or(0, |p| p.paths),
        });
    }
    Ok(JobReport { summary, table: header.table, trace_seconds })
}

/// Writes the dataset of `reader`, traced from `scene`, to `output` with MIS records of
/// `heuristic` (`docs/bidirectional.md` §7): every chunk is re-traced from its block's own
/// random stream ([`upgrade_plan`]), in parallel batches, and compared with the dataset's
/// (`opticks_core::dataset::reproduces`: the same paths, up to rounding); the dataset's samples
/// are written unchanged, with the records of the re-trace. A chunk that does not re-trace, or a stop request,
/// writes nothing. The header keeps every pass's figures and gains the records' heuristic and
/// sampling signature; its label becomes `label` (the scene as used, recorded from `output`'s
/// place: [`crate::scene_ref`]).
pub fn upgrade_dataset(
    reader: &DatasetReader,
    scene: &Scene,
    heuristic: Heuristic,
    (output, label): (&Path, String),
    progress: &dyn JobProgress,
) -> Result<JobReport, JobError> {
    let (mut header, blocks) = upgrade_plan(reader.header(), scene, heuristic, reader.chunk_count())?;
    header.label = label;
    let mut writer = DatasetWriter::create(output, &header)
        .map_err(|source| JobError::Create { path: output.to_owned(), source })?;
    let t0 = Instant::now();
    progress.tracing(blocks.iter().map(|b| b.block.paths).sum());
    let mut done = 0;
    const BATCH: usize = 64;
    for (n, batch) in blocks.chunks(BATCH).enumerate() {
        if progress.stop() {
            return Err(JobError::Stopped { output: output.to_owned() });
        }
        let traced: Vec<Chunk> = batch
            .par_iter()
            .map(|b| {
                let l = b.block.light;
                trace_block(scene, &b.settings, l.scene_light, l.table_index, b.block.index, b.block.paths)
            })
            .collect();
        for (j, (c, b)) in traced.into_iter().zip(batch).enumerate() {
            let i = n * BATCH + j;
            let old = reader.chunk(i)?;
            if (c.light, c.paths) != (old.light, old.paths) || !reproduces(&old.samples, &c.samples) {
                let p = &header.trace.passes[b.pass];
                return Err(JobError::NotReproduced {
                    chunk: i,
                    pass: b.pass,
                    seed: p.seed,
                    stream: p.stream,
                });
            }
            done += c.paths;
            // The dataset's own samples, bit for bit, with the re-trace's records.
            writer.write_chunk(&Chunk { samples: old.samples, ..c })?;
        }
        progress.traced(done);
    }
    progress.traced_all();
    let trace_seconds = t0.elapsed().as_secs_f64();
    let summary = writer
        .finish(&header.table, &header.trace)
        .map_err(|source| JobError::Finish { path: output.to_owned(), source })?;
    Ok(JobReport { summary, table: header.table, trace_seconds })
}

/// Traces `pass` of `scene`, handing chunks to `sink` in order and reporting to `progress`
/// (which may stop it between batches). Returns the paths traced per plan entry.
pub fn trace_observed<E>(
    scene: &Scene,
    pass: &PassPlan,
    sink: impl FnMut(Chunk) -> Result<(), E>,
    progress: &dyn JobProgress,
) -> Result<Vec<u64>, E> {
    progress.tracing(pass.lights.iter().map(|p| p.paths).sum());
    let traced = trace_plan_from(
        scene,
        &pass.settings,
        &pass.lights,
        pass.first_block,
        sink,
        |done| progress.traced(done),
        || progress.stop(),
    )?;
    progress.traced_all();
    Ok(traced)
}

/// A dataset traced into memory and never written (`opticks demo`, a quick look from a
/// notebook): the header of a new trace of `scene` (recorded as `scene_label`) with `settings`,
/// and its chunks in block order. `None` when `progress` asked the trace to stop.
pub fn trace_in_memory(
    scene: &Scene,
    scene_label: &str,
    settings: TraceSettings,
    progress: &dyn JobProgress,
) -> Result<Option<(DatasetHeader, Vec<Chunk>)>, NoPassRecord> {
    let started = Instant::now();
    let (mut header, pass) = opticks_core::dataset::new_trace(scene, scene_label, settings);
    let mut chunks = Vec::new();
    let sink = |c| {
        chunks.push(c);
        Ok::<(), std::convert::Infallible>(())
    };
    let Ok(traced) = trace_observed(scene, &pass, sink, progress);
    if progress.stop() {
        return Ok(None);
    }
    header.record_traced(&pass.lights, &traced, started.elapsed().as_secs_f64())?;
    Ok(Some((header, chunks)))
}

/// A write failed while tracing `new`: the chunks known to be in the file become a valid
/// partial dataset (a prefix of the pass's blocks, so `resume` finishes it), saved as
/// [`partial_path`]`(output)`; the error says whether that worked.
fn save_written(
    mut writer: DatasetWriter,
    mut header: DatasetHeader,
    new: &NewPaths<'_>,
    output: &Path,
    seconds: f64,
    source: DatasetError,
) -> JobError {
    let source = Box::new(source);
    let failed = |partial, paths| JobError::WriteFailed { output: output.to_owned(), partial, paths, source };
    if writer.keep_written_prefix().is_err() {
        return failed(None, 0);
    }
    let kept = writer.light_paths();
    let traced: Vec<u64> = new
        .pass
        .lights
        .iter()
        .map(|p| {
            kept[p.table_index as usize].saturating_sub(header.table.lights[p.table_index as usize].paths)
        })
        .collect();
    if header.record_traced(&new.pass.lights, &traced, seconds).is_err() {
        return failed(None, 0);
    }
    let partial = partial_path(output);
    writer.retarget(&partial);
    match writer.finish(&header.table, &header.trace) {
        Ok(_) => failed(Some(partial), header.trace.passes.last().map_or(0, |p| p.paths)),
        Err(_) => failed(None, 0),
    }
}

/// What the tracer and the writer thread ended with: the paths traced per plan entry, the
/// writer, and the write error that stopped it, if one did.
type Overlapped = (Result<Vec<u64>, JobError>, DatasetWriter, Option<DatasetError>);

/// Traces `new` with `tracer` while a writer thread appends the chunks; a pass of one block
/// (nothing to overlap) writes its chunk on this thread instead, without starting one.
fn trace_overlapped(
    mut writer: DatasetWriter,
    new: &NewPaths<'_>,
    progress: &dyn JobProgress,
    tracer: &dyn PassTracer,
) -> Result<Overlapped, JobError> {
    let blocks: u64 =
        new.pass.lights.iter().map(|l| l.paths.div_ceil(opticks_core::dataset::BLOCK_PATHS)).sum();
    if blocks.saturating_sub(new.pass.first_block as u64) <= 1 {
        let mut failed = None;
        let traced = tracer.trace_pass(
            new.scene,
            &new.pass,
            &mut |c| {
                writer.write_chunk(&c).map_err(|e| {
                    failed = Some(e);
                    JobError::WriterStopped
                })
            },
            progress,
        );
        return Ok((traced, writer, failed));
    }
    std::thread::scope(|s| {
        let (send, receive) = std::sync::mpsc::sync_channel::<Chunk>(128);
        let writing = s.spawn(move || -> (DatasetWriter, Option<DatasetError>) {
            for c in receive {
                if let Err(e) = writer.write_chunk(&c) {
                    return (writer, Some(e));
                }
            }
            (writer, None)
        });
        let traced = tracer.trace_pass(
            new.scene,
            &new.pass,
            &mut |c| send.send(c).map_err(|_| JobError::WriterStopped),
            progress,
        );
        drop(send);
        let (writer, failed) = writing.join().map_err(|_| JobError::WriterPanicked)?;
        Ok((traced, writer, failed))
    })
}

/// `dir/NAME.partial.opds` for `dir/NAME.opds`: where an interrupted job saves its work.
pub fn partial_path(output: &Path) -> PathBuf {
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    output.with_file_name(format!("{stem}.partial.opds"))
}

/// `dir/NAME.opds` for `dir/NAME.partial.opds` (other names are kept: a resumption then
/// writes in place).
pub fn finished_path(partial: &Path) -> PathBuf {
    let name = partial.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    match name.strip_suffix(".partial.opds") {
        Some(stem) if !stem.is_empty() => partial.with_file_name(format!("{stem}.opds")),
        _ => partial.to_owned(),
    }
}

/// Removes the partial dataset a resumption finished into `output` (unless it was finished in
/// place).
pub fn remove_partial(partial: &Path, output: &Path) -> Result<(), JobError> {
    if output == partial {
        return Ok(());
    }
    std::fs::remove_file(partial).map_err(|source| JobError::RemovePartial {
        output: output.to_owned(),
        partial: partial.to_owned(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset_file::read_all;
    use opticks_core::dataset::{TraceSettings, merge_header, new_trace, resume_plan};
    use opticks_core::scene::{PointLightDesc, cornell_box};
    use std::cell::Cell;

    fn scene(bulb: bool) -> Scene {
        let mut d = cornell_box();
        if bulb {
            d.point_lights.push(PointLightDesc {
                name: "bulb".into(),
                intensity: 0.3 * opticks_core::math::Rgb::ONE,
                ..Default::default()
            });
        }
        Scene::build(&d).unwrap()
    }

    /// Stops when asked for the `n`-th time.
    struct StopAt(Cell<u32>);
    impl JobProgress for StopAt {
        fn stop(&self) -> bool {
            let n = self.0.get();
            self.0.set(n.saturating_sub(1));
            n == 0
        }
    }

    fn trace(
        scene: &Scene,
        path: &Path,
        paths: u64,
        seed: u64,
        progress: &dyn JobProgress,
    ) -> Result<JobReport, JobError> {
        let (header, pass) = new_trace(scene, "box", TraceSettings { paths, seed, ..Default::default() });
        write_dataset(path, header, &[], Some(NewPaths { scene, pass }), progress)
    }

    fn files(dir: &Path) -> Vec<String> {
        let mut names: Vec<_> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        names.sort();
        names
    }

    #[test]
    fn a_trace_is_written_as_traced_and_booked() {
        let dir = tempfile::tempdir().unwrap();
        let (scene, path) = (scene(true), dir.path().join("two.opds"));
        let report = trace(&scene, &path, 9000, 2, &()).unwrap();
        let (header, chunks) = read_all(&path).unwrap();
        let (planned, pass) =
            new_trace(&scene, "box", TraceSettings { paths: 9000, seed: 2, ..Default::default() });
        let mut expected = Vec::new();
        trace_observed(
            &scene,
            &pass,
            |c| {
                expected.push(c);
                Ok::<(), ()>(())
            },
            &(),
        )
        .unwrap();
        assert_eq!(chunks, expected);
        assert_eq!((header.table.total_paths(), report.table), (9000, header.table.clone()));
        assert_eq!(header.trace.passes.len(), 1);
        let written = &header.trace.passes[0];
        assert!(written.is_complete() && written.seconds > 0.0 && report.trace_seconds > 0.0);
        assert_eq!(written.planned, planned.trace.passes[0].planned);
        assert_eq!((report.summary.path, report.summary.chunks), (path, chunks.len() as u64));
    }

    #[test]
    fn stopped_while_tracing_the_work_is_saved_as_partial_and_resumes_to_the_whole() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let scene = scene(true);
        trace(&scene, &d.join("whole.opds"), 9000, 3, &()).unwrap();
        std::fs::write(d.join("cut.opds"), b"the previous file").unwrap();
        let e = trace(&scene, &d.join("cut.opds"), 9000, 3, &StopAt(Cell::new(0))).unwrap_err();
        let JobError::Interrupted { output, partial, paths } = &e else { panic!("{e}") };
        assert_eq!(
            (output.as_path(), partial.as_path(), *paths),
            (d.join("cut.opds").as_path(), d.join("cut.partial.opds").as_path(), 0)
        );
        assert_eq!(
            std::fs::read(d.join("cut.opds")).unwrap(),
            b"the previous file",
            "the target is left as it was"
        );
        assert_eq!(files(d), ["cut.opds", "cut.partial.opds", "whole.opds"], "no temporary file is left");

        let reader = DatasetReader::open(partial).unwrap();
        let pass = resume_plan(reader.header(), &scene).unwrap();
        let output = finished_path(partial);
        write_dataset(
            &output,
            reader.header().clone(),
            &[Source::as_is(&reader)],
            Some(NewPaths { scene: &scene, pass }),
            &(),
        )
        .unwrap();
        remove_partial(partial, &output).unwrap();
        let contents = |f: &str| {
            let (mut h, chunks) = read_all(&d.join(f)).unwrap();
            h.trace.passes.iter_mut().for_each(|p| p.seconds = 0.0);
            (h, chunks)
        };
        assert!(contents("cut.opds") == contents("whole.opds"), "resumed ≠ uninterrupted");
        assert_eq!(files(d), ["cut.opds", "whole.opds"], "the partial file is used up");
    }

    #[test]
    fn stopped_while_copying_nothing_is_written() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let scene = scene(false);
        trace(&scene, &d.join("a.opds"), 9000, 1, &()).unwrap();
        let reader = DatasetReader::open(&d.join("a.opds")).unwrap();
        let e = write_dataset(
            &d.join("b.opds"),
            reader.header().clone(),
            &[Source::as_is(&reader)],
            None,
            &StopAt(Cell::new(1)),
        )
        .unwrap_err();
        assert!(matches!(&e, JobError::Stopped { output } if output == &d.join("b.opds")), "{e}");
        assert_eq!(
            e.to_string(),
            format!(
                "{} was left as it was: interrupted: stopped, nothing written",
                d.join("b.opds").display()
            )
        );
        assert_eq!(files(d), ["a.opds"]);
    }

    #[test]
    fn merged_sources_are_copied_under_their_lights_in_the_merged_table() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        trace(&scene(false), &d.join("box.opds"), 5000, 1, &()).unwrap();
        trace(&scene(true), &d.join("two.opds"), 6000, 2, &()).unwrap();
        let (a, b) = (
            DatasetReader::open(&d.join("two.opds")).unwrap(),
            DatasetReader::open(&d.join("box.opds")).unwrap(),
        );
        let mut header = a.header().clone();
        let lights = merge_header(&mut header, b.header()).unwrap();
        let sources = [Source::as_is(&a), Source { reader: &b, lights: Some(lights) }];
        let report = write_dataset(&d.join("m.opds"), header.clone(), &sources, None, &()).unwrap();
        assert_eq!(report.trace_seconds, 0.0);
        let (written, chunks) = read_all(&d.join("m.opds")).unwrap();
        assert_eq!(written, header);
        let (_, box_chunks) = read_all(&d.join("box.opds")).unwrap();
        assert_eq!(
            chunks[chunks.len() - box_chunks.len()..],
            box_chunks[..],
            "the box's light is light 0 in both"
        );
        assert_eq!(written.table.lights[0].paths, a.header().table.lights[0].paths + 5000);
    }

    #[test]
    fn an_interrupted_run_is_saved_beside_its_target_and_resumed_into_it() {
        assert_eq!(partial_path(Path::new("d/box.opds")), Path::new("d/box.partial.opds"));
        assert_eq!(finished_path(Path::new("d/box.partial.opds")), Path::new("d/box.opds"));
        assert_eq!(finished_path(Path::new("box.opds")), Path::new("box.opds"));
        assert_eq!(finished_path(Path::new(".partial.opds")), Path::new(".partial.opds"));
        remove_partial(Path::new("no such file"), Path::new("no such file")).unwrap();
        let e = remove_partial(Path::new("no such file"), Path::new("x.opds")).unwrap_err();
        assert!(e.to_string().starts_with("finished x.opds, but cannot remove no such file: "), "{e}");
    }

    /// A dataset traced without records upgrades to exactly the dataset traced with them; one
    /// whose samples were altered (as if another tracer had written it) is refused, and nothing
    /// is written.
    #[test]
    fn an_upgrade_re_traces_to_the_dataset_traced_with_records() {
        let dir = tempfile::tempdir().unwrap();
        let scene = scene(true);
        let write = |name: &str, mis| {
            let path = dir.path().join(name);
            let settings = TraceSettings { paths: 9000, seed: 4, mis, ..Default::default() };
            let (header, pass) = new_trace(&scene, "box", settings);
            write_dataset(&path, header, &[], Some(NewPaths { scene: &scene, pass }), &()).unwrap();
            path
        };
        let (plain, with) = (write("plain.opds", None), write("with.opds", Some(Heuristic::Power)));
        let up = dir.path().join("up.opds");
        let reader = DatasetReader::open(&plain).unwrap();
        upgrade_dataset(&reader, &scene, Heuristic::Power, (&up, reader.header().label.clone()), &())
            .unwrap();
        let (mut a, b) = (read_all(&up).unwrap(), read_all(&with).unwrap());
        a.0.trace.passes.iter_mut().zip(&b.0.trace.passes).for_each(|(p, q)| p.seconds = q.seconds);
        assert_eq!(a, b);
        assert!(a.1.iter().all(|c| c.records.len() == c.samples.len()));

        // Another seed's samples under this header: chunk 0 does not re-trace.
        let other = DatasetReader::open(&write("other.opds", None)).unwrap();
        let mut h = other.header().clone();
        h.trace.passes[0].seed = 5;
        let forged = dir.path().join("forged.opds");
        write_dataset(&forged, h, &[Source::as_is(&other)], None, &()).unwrap();
        let bad = dir.path().join("bad.opds");
        let e = upgrade_dataset(
            &DatasetReader::open(&forged).unwrap(),
            &scene,
            Heuristic::Power,
            (&bad, String::new()),
            &(),
        )
        .unwrap_err();
        assert!(matches!(e, JobError::NotReproduced { chunk: 0, pass: 0, seed: 5, stream: 0 }), "{e}");
        assert!(e.to_string().contains("does not re-trace to the same samples"), "{e}");
        assert!(!bad.exists(), "nothing written");
    }
}
