//! `opticks resume`: finishes an interrupted `trace`, `refine` or `add-light` from the
//! `NAME.partial.opds` it saved. The partial file's last pass records what the run planned;
//! `opticks_core::dataset::resume_plan` finds the blocks still missing, and only those are
//! traced. The result holds exactly the samples of an uninterrupted run.

use super::{ThreadArgs, job_error, open_with_scene, scene_spec, write_job};
use crate::progress::TraceProgress;
use anyhow::{Result, anyhow};
use opticks_core::dataset::{ResumeError, resume_plan};
use opticks_io::dataset_job::{NewPaths, Source, finished_path, remove_partial};
use std::path::PathBuf;

/// Arguments of `opticks resume`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The partial dataset an interrupted run saved (`NAME.partial.opds`).
    partial: PathBuf,
    /// Where to write the finished dataset (default: `NAME.opds`, the interrupted run's target).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Scene file (default: the one recorded in the dataset).
    #[arg(long)]
    scene: Option<String>,
    #[command(flatten)]
    pub(crate) threads: ThreadArgs,
}

/// Resumes the run.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    let (reader, _, scene) = open_with_scene(&a.partial, a.scene.as_deref())?;
    let header = reader.header().clone();
    let partial = a.partial.display();
    let pass = resume_plan(&header, &scene).map_err(|e| match e {
        ResumeError::Complete => anyhow!("{partial}: nothing to resume, its last trace pass is complete"),
        ResumeError::Light(e) => anyhow!("{e}: resume needs the same scene"),
        ResumeError::NotBlockAligned { paths } => anyhow!(
            "{partial}: its last pass traced {paths} paths, which is no whole number of its blocks: not a file \
             saved by an interrupted run"
        ),
    })?;
    let (done, planned) = (header.trace.passes.last().map_or(0, |p| p.paths), pass.settings.paths);
    let output = a.output.clone().unwrap_or_else(|| finished_path(&a.partial));
    let new = NewPaths { scene: &scene, pass };
    let spec = scene_spec(&reader, a.scene.as_deref());
    let report =
        write_job(spec, &output, header, &[Source::as_is(&reader)], Some(new), &TraceProgress::default())
            .map_err(job_error)?;
    remove_partial(&a.partial, &output)?;
    println!(
        "resumed {partial}: {done} + {} paths = {planned} planned ({:.2} s) → {} ({} paths, {} samples)",
        planned - done,
        report.trace_seconds,
        output.display(),
        report.table.total_paths(),
        report.summary.samples
    );
    Ok(())
}
