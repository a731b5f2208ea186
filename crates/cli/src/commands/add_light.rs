//! `opticks add-light`: the scene file gained a light; trace only that light into the dataset.
//! The other lights' samples are reused untouched (geometry and materials must be unchanged —
//! the fingerprint says so — while the light table may grow): `opticks_core::dataset::add_light`.

use super::extend_args::ExtendArgs;
use super::{job_error, open_with_scene, scene_spec, write_job};
use crate::progress::TraceProgress;
use anyhow::{Result, anyhow};
use opticks_core::dataset::AddLightError;
use opticks_io::dataset_job::{NewPaths, Source};
use std::path::PathBuf;

/// Arguments of `opticks add-light`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Dataset to extend.
    dataset: PathBuf,
    /// Name of the new light in the scene file.
    light: String,
    /// Scene file with the new light (default: the one recorded in the dataset).
    #[arg(long)]
    scene: Option<String>,
    /// Paths for the new light (default: its fair share, N·Φ_new/ΣΦ of the lights already traced).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    paths: Option<u64>,
    #[command(flatten)]
    pub(crate) extend: ExtendArgs,
}

/// Adds the light.
pub fn run(a: Args) -> Result<()> {
    a.extend.threads.apply()?;
    let (reader, _, scene) = open_with_scene(&a.dataset, a.scene.as_deref())?;
    let (seed, strategy) = (a.extend.seed, a.extend.strategy.choice());
    let (header, pass) =
        opticks_core::dataset::add_light(reader.header(), &scene, &a.light, a.paths, seed, &strategy)
            .map_err(|e| match e {
                AddLightError::AlreadyTraced(name) => anyhow!(
                    "light '{name}' is already in {}: use `opticks refine` for more paths",
                    a.dataset.display()
                ),
                AddLightError::NoPowerToCompare => {
                    anyhow!("give --paths: the dataset's lights have no power to compare with")
                }
                AddLightError::NoPaths => anyhow!("--paths must be at least 1"),
                e @ AddLightError::NoSuchLight { .. } => e.into(),
            })?;
    let paths = pass.settings.paths;
    let output = a.extend.output.clone().unwrap_or_else(|| a.dataset.clone());
    let new = NewPaths { scene: &scene, pass };
    let spec = scene_spec(&reader, a.scene.as_deref());
    let report =
        write_job(spec, &output, header, &[Source::as_is(&reader)], Some(new), &TraceProgress::default())
            .map_err(job_error)?;
    println!(
        "added light '{}' with {paths} paths ({:.2} s) → {} ({} lights, {} samples)",
        a.light,
        report.trace_seconds,
        output.display(),
        report.table.lights.len(),
        report.summary.samples
    );
    Ok(())
}
