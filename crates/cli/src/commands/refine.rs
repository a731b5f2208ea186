//! `opticks refine`: more paths for an existing dataset, from a fresh random stream. The result
//! is statistically the same as having traced all the paths at once (N_k simply grows); the
//! dataset is rewritten atomically, so an interrupted refine leaves it as it was (and saves
//! `NAME.partial.opds`, which `opticks resume` completes). The new paths use the strategy of the
//! dataset's last pass unless overridden, so the estimator stays the one the dataset was made by
//! (`opticks_core::dataset::refine`). A partial dataset is refused: resume it first (a pass
//! added after an interrupted one would make it impossible to resume).

use super::extend_args::{ExtendArgs, Extending};
use super::{Opened, check_before_trace, unless_time_up, write_job};
use crate::output;
use crate::progress::TraceProgress;
use anyhow::{Result, anyhow};
use opticks_core::dataset::check_emission;
use opticks_io::dataset_job::{NewPaths, Source, estimate_bytes};
use opticks_io::scene_ref::{label_for, with_options};
use std::path::PathBuf;

/// Arguments of `opticks refine`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Dataset to refine.
    dataset: PathBuf,
    /// Light paths to add, over all lights (split in proportion to their power); e.g. 4M, 4e6.
    #[arg(long, allow_hyphen_values = true, value_parser = opticks_io::count_text::parse_count)]
    paths: u64,
    /// Scene file (default: the one recorded in the dataset); the result records it (repeated for several .rad files).
    #[arg(long, value_parser = crate::scene_arg::parse_scene)]
    scene: Vec<opticks_io::scene_source::SceneRef>,
    #[command(flatten)]
    defines: crate::scene_arg::DefineArgs,
    #[command(flatten)]
    pub(crate) extend: ExtendArgs,
}

/// Runs the refinement.
pub fn run(a: Args) -> Result<()> {
    let Extending { output, lock: _lock, opened } =
        a.extend.begin(&a.dataset, crate::scene_arg::joined(&a.scene)?.as_ref(), &a.defines)?;
    let Opened { reader, scene, scene_ref, options, .. } = opened;
    let (seed, strategy) = (a.extend.seed, a.extend.strategy.choice());
    let (mut header, pass) = opticks_core::dataset::refine(reader.header(), &scene, a.paths, seed, &strategy)
        .map_err(|e| anyhow!("{e}: refine needs the same scene"))?;
    check_emission(&pass.lights).map_err(|e| anyhow!("{scene_ref}: {e}"))?;
    header.label = with_options(&label_for(&scene_ref.label(), &output), &options);
    output::detail(&format!("plan: {}", pass.describe(&header.table)));
    let before = reader.header().table.total_paths();
    let sources = [Source::as_is(&reader)];
    check_before_trace(&output, &header.table, &pass, estimate_bytes(&sources, a.paths))?;
    let new = NewPaths { scene: &scene, pass };
    let _graceful = crate::interrupt::graceful();
    let progress = TraceProgress::with_time_limit(a.extend.time);
    let job = write_job((&scene_ref, &options), &output, header, &sources, Some(new), &progress);
    let Some(report) = unless_time_up(job, &progress)? else {
        return Ok(());
    };
    output::result(&format!(
        "refined {}: {} + {} paths = {} paths, {} samples ({:.2} s) → {}",
        a.dataset.display(),
        before,
        report.table.total_paths() - before,
        report.table.total_paths(),
        report.summary.samples,
        report.trace_seconds,
        output.display()
    ));
    Ok(())
}
