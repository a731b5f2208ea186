//! `opticks refine`: more paths for an existing dataset, from a fresh random stream. The result
//! is statistically the same as having traced all the paths at once (N_k simply grows); the
//! dataset is rewritten atomically, so an interrupted refine leaves it as it was (and saves
//! `NAME.partial.opds`, which `opticks resume` completes). The new paths use the strategy of the
//! dataset's last pass unless overridden, so the estimator stays the one the dataset was made by
//! (`opticks_core::dataset::refine`).

use super::extend_args::ExtendArgs;
use super::{job_error, open_with_scene, scene_spec, write_job};
use crate::progress::TraceProgress;
use anyhow::{Result, anyhow};
use opticks_io::dataset_job::{NewPaths, Source};
use std::path::PathBuf;

/// Arguments of `opticks refine`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Dataset to refine.
    dataset: PathBuf,
    /// Light paths to add, over all lights (split in proportion to their power).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    paths: u64,
    /// Scene file (default: the one recorded in the dataset).
    #[arg(long)]
    scene: Option<String>,
    #[command(flatten)]
    pub(crate) extend: ExtendArgs,
}

/// Runs the refinement.
pub fn run(a: Args) -> Result<()> {
    a.extend.threads.apply()?;
    let (reader, _, scene) = open_with_scene(&a.dataset, a.scene.as_deref())?;
    let (seed, strategy) = (a.extend.seed, a.extend.strategy.choice());
    let (header, pass) = opticks_core::dataset::refine(reader.header(), &scene, a.paths, seed, &strategy)
        .map_err(|e| anyhow!("{e}: refine needs the same scene"))?;
    let output = a.extend.output.clone().unwrap_or_else(|| a.dataset.clone());
    let before = reader.header().table.total_paths();
    let new = NewPaths { scene: &scene, pass };
    let spec = scene_spec(&reader, a.scene.as_deref());
    let report =
        write_job(spec, &output, header, &[Source::as_is(&reader)], Some(new), &TraceProgress::default())
            .map_err(job_error)?;
    println!(
        "refined {}: {} + {} paths = {} paths, {} samples ({:.2} s) → {}",
        a.dataset.display(),
        before,
        report.table.total_paths() - before,
        report.table.total_paths(),
        report.summary.samples,
        report.trace_seconds,
        output.display()
    );
    Ok(())
}
