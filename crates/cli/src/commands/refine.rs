//! `opticks refine`: more paths for an existing dataset, from a fresh random stream. The result
//! is statistically the same as having traced all the paths at once (N_k simply grows); the
//! dataset is rewritten atomically, so an interrupted refine leaves it as it was.

use super::dataset_job::{NewPaths, new_pass, write_dataset};
use super::{ThreadArgs, open_with_scene};
use anyhow::{Result, bail};
use opticks_core::trace::{LightPlan, TraceSettings, path_quotas};
use std::path::PathBuf;

/// Arguments of `opticks refine`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Dataset to refine.
    dataset: PathBuf,
    /// Light paths to add, over all lights (split in proportion to their power).
    #[arg(long)]
    paths: u64,
    /// Where to write the result (default: replace the dataset).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Scene file (default: the one recorded in the dataset).
    #[arg(long)]
    scene: Option<String>,
    /// Seed (default: the dataset's first; a stream not used yet is picked either way).
    #[arg(long)]
    seed: Option<u64>,
    #[command(flatten)]
    threads: ThreadArgs,
}

/// Runs the refinement.
pub fn run(a: Args) -> Result<()> {
    if a.paths == 0 {
        bail!("--paths must be at least 1");
    }
    a.threads.apply()?;
    let (reader, _, scene) = open_with_scene(&a.dataset, a.scene.as_deref())?;
    let mut header = reader.header().clone();
    let mut scene_lights = Vec::new();
    for record in &header.table.lights {
        match scene.light_index(&record.name) {
            Some(i) if scene.light_shapes[i] == record.shape => scene_lights.push(i),
            Some(_) => bail!(
                "light '{}' has moved or changed shape since the trace: refine needs the same scene",
                record.name
            ),
            None => bail!(
                "light '{}' of the dataset is not in the scene any more: refine needs the same scene",
                record.name
            ),
        }
    }
    let powers: Vec<_> = scene_lights.iter().map(|&i| scene.lights[i].power()).collect();
    let plan: Vec<LightPlan> = path_quotas(&powers, a.paths)
        .into_iter()
        .zip(&scene_lights)
        .enumerate()
        .map(|(k, (paths, &scene_light))| LightPlan { scene_light, table_index: k as u32, paths })
        .collect();
    let last = header.trace.passes.last().copied().unwrap_or_default();
    let seed = a.seed.unwrap_or(header.trace.passes.first().map_or(0, |p| p.seed));
    let settings = TraceSettings {
        paths: a.paths,
        seed,
        stream: header.trace.next_stream(seed),
        rr_depth: last.rr_depth.max(1),
        ..Default::default()
    };
    header.trace.passes.push(new_pass(&settings));
    let output = a.output.clone().unwrap_or_else(|| a.dataset.clone());
    let before = header.table.total_paths();
    let report =
        write_dataset(&output, header, &[&reader], Some(NewPaths { scene: &scene, settings, plan }))?;
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
