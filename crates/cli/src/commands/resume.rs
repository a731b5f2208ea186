//! `opticks resume`: finishes an interrupted `trace`, `refine` or `add-light` from the
//! `NAME.partial.opds` it saved. The partial file's last pass records what the run planned;
//! `opticks_core::dataset::resume_plan` finds the blocks still missing, and only those are
//! traced. The result holds exactly the samples of an uninterrupted run. With `--time` it ends
//! at a block boundary when the time is up, complete with what it traced; with `--finish-now`
//! it traces nothing and ends the pass where the interrupted run stopped
//! (`opticks_core::dataset::end_pass_here`).
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
use opticks_core::dataset::{ResumeError, check_resume_target, end_pass_here, resume_plan};
use opticks_io::dataset_file::DatasetReader;
use opticks_io::dataset_job::{NewPaths, Source, estimate_bytes, finished_path, remove_partial};
use opticks_io::dataset_lock::{WriteIntent, same_file};
use opticks_io::scene_ref::{label_for, with_options};
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
    /// Scene file (default: the one recorded in the dataset) (repeated for several .rad files).
    #[arg(long, value_parser = crate::scene_arg::parse_scene)]
    scene: Vec<opticks_io::scene_source::SceneRef>,
    #[command(flatten)]
    defines: crate::scene_arg::DefineArgs,
    #[command(flatten)]
    pub(crate) threads: ThreadArgs,
    /// Trace for this many seconds more (ending at the next block boundary): the dataset is then
    /// complete with the paths traced by then.
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    time: Option<std::time::Duration>,
    /// Trace nothing more: accept the paths the interrupted run traced as the finished run (its
    /// last pass ends where it stopped), so that it can be refined, merged or given a light.
    #[arg(long, conflicts_with = "time")]
    finish_now: bool,
}

/// Resumes the run.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    a.defines.refuse_camera("resume")?;
    let output = a.output.clone().unwrap_or_else(|| finished_path(&a.partial));
    let intent = WriteIntent { inputs: &[], resuming: Some(&a.partial), overwrite: a.overwrite };
    let _lock = begin_dataset_write(&output, intent)?;
    let Opened { reader, scene, scene_ref, options, .. } =
        open_with_scene(&a.partial, crate::scene_arg::joined(&a.scene)?.as_ref(), &a.defines)?;
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
        // Read only to be checked: replacing it is what finishing the run is for.
        drop(target);
        opticks_io::input_file::forget(&output);
    }
    let (done, planned) = (header.trace.passes.last().map_or(0, |p| p.paths), pass.settings.paths);
    header.label = with_options(&label_for(&scene_ref.label(), &output), &options);
    let sources = [Source::as_is(&reader)];
    if a.finish_now {
        end_pass_here(&mut header).map_err(|e| anyhow!("{partial}: {e}"))?;
        let _graceful = crate::interrupt::graceful();
        let progress = TraceProgress::default();
        let report = write_job((&scene_ref, &options), &output, header, &sources, None, &progress)
            .map_err(super::job_error)?;
        remove_partial(&a.partial, &output)?;
        output::result(&format!(
            "finished {partial} as it is: {done} of the {planned} paths planned → {} ({} paths, {} samples)",
            output.display(),
            report.table.total_paths(),
            report.summary.samples
        ));
        return Ok(());
    }
    check_before_trace(&output, &header.table, &pass, estimate_bytes(&sources, planned - done))?;
    let new = NewPaths { scene: &scene, pass };
    let _graceful = crate::interrupt::graceful();
    let progress = TraceProgress::with_time_limit(a.time);
    let job = write_job((&scene_ref, &options), &output, header, &sources, Some(new), &progress);
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
