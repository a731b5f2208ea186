//! `opticks resume`: finishes an interrupted `trace`, `refine` or `add-light` from the
//! `NAME.partial.opds` it saved. The partial file's last pass records what the run planned;
//! `opticks_core::dataset::resume_plan` finds the blocks still missing, and only those are
//! traced. The result holds exactly the samples of an uninterrupted run. With `--time` it stops
//! at a block boundary when the time is up and saves what it has as the partial again.
//!
//! An existing `NAME.opds` is replaced only if it is still the dataset the interrupted run
//! started from (`opticks_core::dataset::check_resume_target`): after a later refinement of it,
//! finishing the old run there would discard that refinement, so the command refuses (write the
//! result elsewhere with `-o`, or give `--overwrite`).

use super::{
    Opened, ThreadArgs, begin_dataset_write, check_before_trace, open_with_scene, parse_seconds,
    unless_time_up, write_job,
};
use crate::output;
use crate::progress::TraceProgress;
use anyhow::{Result, anyhow};
use opticks_core::dataset::{ResumeError, check_resume_target, resume_plan};
use opticks_io::dataset_file::DatasetReader;
use opticks_io::dataset_job::{NewPaths, Source, estimate_bytes, finished_path, remove_partial};
use opticks_io::dataset_lock::{WriteIntent, same_file};
use opticks_io::scene_ref::label_for;
use std::path::PathBuf;

/// Arguments of `opticks resume`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The partial dataset an interrupted run saved (`NAME.partial.opds`).
    partial: PathBuf,
    /// Where to write the finished dataset (default: `NAME.opds`, the interrupted run's target).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Replace the output even if it is not the dataset the interrupted run started from.
    #[arg(long)]
    overwrite: bool,
    /// Scene file (default: the one recorded in the dataset).
    #[arg(long, value_parser = crate::scene_arg::parse_scene)]
    scene: Option<opticks_io::scene_source::SceneRef>,
    #[command(flatten)]
    defines: crate::scene_arg::DefineArgs,
    #[command(flatten)]
    pub(crate) threads: ThreadArgs,
    /// Stop after this many seconds of tracing (at the next block boundary), saving the paths traced so
    /// far as NAME.partial.opds again, for the next `opticks resume`.
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    time: Option<std::time::Duration>,
}

/// Resumes the run.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    let output = a.output.clone().unwrap_or_else(|| finished_path(&a.partial));
    let intent = WriteIntent { inputs: &[], resuming: Some(&a.partial), overwrite: a.overwrite };
    let _lock = begin_dataset_write(&output, intent)?;
    let Opened { reader, scene, scene_ref, .. } = open_with_scene(&a.partial, a.scene.as_ref(), &a.defines)?;
    let mut header = reader.header().clone();
    let partial = a.partial.display();
    let pass = resume_plan(&header, &scene).map_err(|e| match e {
        ResumeError::Complete => anyhow!("{partial}: nothing to resume, its last trace pass is complete"),
        ResumeError::Light(e) => anyhow!("{e}: resume needs the same scene"),
        ResumeError::NotBlockAligned { paths } => anyhow!(
            "{partial}: its last pass traced {paths} paths, which is no whole number of its blocks: not a file \
             saved by an interrupted run"
        ),
    })?;
    if output.exists() && !same_file(&output, &a.partial) && !a.overwrite {
        let target = DatasetReader::open(&output).map_err(|e| {
            anyhow!("{e}: it would be replaced by the resumed run; give --overwrite to replace it")
        })?;
        check_resume_target(&header, target.header()).map_err(|e| {
            anyhow!(
                "{}: {e}; write the result elsewhere with -o, or give --overwrite to replace it",
                output.display()
            )
        })?;
    }
    let (done, planned) = (header.trace.passes.last().map_or(0, |p| p.paths), pass.settings.paths);
    header.label = label_for(&scene_ref.label(), &output);
    let sources = [Source::as_is(&reader)];
    check_before_trace(&output, &header.table, &pass, estimate_bytes(&sources, planned - done))?;
    let new = NewPaths { scene: &scene, pass };
    let _graceful = crate::interrupt::graceful();
    let progress = TraceProgress::with_time_limit(a.time);
    let job = write_job((&scene_ref, &a.defines), &output, header, &sources, Some(new), &progress);
    let Some(report) = unless_time_up(job, &progress)? else {
        return Ok(());
    };
    remove_partial(&a.partial, &output)?;
    output::result(&format!(
        "resumed {partial}: {done} + {} paths = {planned} planned ({:.2} s) → {} ({} paths, {} samples)",
        planned - done,
        report.trace_seconds,
        output.display(),
        report.table.total_paths(),
        report.summary.samples
    ));
    Ok(())
}
