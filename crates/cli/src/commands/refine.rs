//! `opticks refine`: more paths for an existing dataset, from a fresh random stream. The result
//! is statistically the same as having traced all the paths at once (N_k simply grows); the
//! dataset is rewritten atomically, so an interrupted refine leaves it as it was (and saves
//! `NAME.partial.opds`, which `opticks resume` completes). The new paths use the strategy of the
//! dataset's last pass unless overridden, so the estimator stays the one the dataset was made by.

use super::dataset_job::{ExtendArgs, continued_settings, extend_dataset, scene_lights};
use super::open_with_scene;
use anyhow::Result;
use opticks_core::trace::{LightPlan, path_quotas};
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
    extend: ExtendArgs,
}

/// Runs the refinement.
pub fn run(a: Args) -> Result<()> {
    a.extend.threads.apply()?;
    let (reader, _, scene) = open_with_scene(&a.dataset, a.scene.as_deref())?;
    let mut header = reader.header().clone();
    let scene_lights = scene_lights(&header.table, &scene, "refine")?;
    header.fingerprint.geometry = scene.fingerprint.geometry; // matched: record the current hash
    let powers: Vec<_> = scene_lights.iter().map(|&i| scene.lights[i].power()).collect();
    let plan: Vec<LightPlan> = path_quotas(&powers, a.paths)
        .into_iter()
        .zip(&scene_lights)
        .enumerate()
        .map(|(k, (paths, &scene_light))| LightPlan { scene_light, table_index: k as u32, paths })
        .collect();
    let settings = continued_settings(&header, a.paths, a.extend.seed, &a.extend.strategy);
    let output = a.extend.output.clone().unwrap_or_else(|| a.dataset.clone());
    let before = header.table.total_paths();
    let report = extend_dataset(&reader, header, &output, &scene, settings, plan)?;
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
