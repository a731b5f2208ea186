//! `opticks add-light`: the scene file gained a light; trace only that light into the dataset.
//! The other lights' samples are reused untouched (geometry and materials must be unchanged —
//! the fingerprint says so — while the light table may grow): `opticks_core::dataset::add_light`.
//! The result records the scene file used (`--scene`): it is the scene the dataset now belongs
//! to.

use super::extend_args::{ExtendArgs, Extending};
use super::{Opened, check_before_trace, unless_time_up, write_job};
use crate::output;
use crate::progress::TraceProgress;
use anyhow::{Result, anyhow};
use opticks_core::dataset::AddLightError;
use opticks_io::dataset_job::{NewPaths, Source, estimate_bytes};
use opticks_io::scene_ref::{label_for, with_options};
use std::path::PathBuf;

/// Arguments of `opticks add-light`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Dataset to extend.
    dataset: PathBuf,
    /// Name of the new light in the scene file.
    light: String,
    /// Scene file with the new light (default: the one recorded in the dataset; repeated for
    /// several .rad files); the result records it.
    #[arg(long, value_parser = crate::scene_arg::parse_scene)]
    scene: Vec<opticks_io::scene_source::SceneRef>,
    #[command(flatten)]
    defines: crate::scene_arg::DefineArgs,
    /// Paths for the new light (default: its fair share, N·Φ_new/ΣΦ of the lights already traced).
    #[arg(long, allow_hyphen_values = true, value_parser = opticks_io::count_text::parse_count)]
    paths: Option<u64>,
    #[command(flatten)]
    pub(crate) extend: ExtendArgs,
}

/// Adds the light.
pub fn run(a: Args) -> Result<()> {
    let Extending { output, lock: _lock, opened } =
        a.extend.begin(&a.dataset, crate::scene_arg::joined(&a.scene)?.as_ref(), &a.defines)?;
    let Opened { reader, scene, scene_ref, options, .. } = opened;
    let (seed, strategy) = (a.extend.seed, a.extend.strategy.choice());
    let (mut header, pass) =
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
    header.label = with_options(&label_for(&scene_ref.label(), &output), &options);
    let sources = [Source::as_is(&reader)];
    check_before_trace(&output, &header.table, &pass, estimate_bytes(&sources, paths))?;
    let new = NewPaths { scene: &scene, pass };
    let _graceful = crate::interrupt::graceful();
    let progress = TraceProgress::with_time_limit(a.extend.time);
    let job = write_job((&scene_ref, &options), &output, header, &sources, Some(new), &progress);
    let Some(report) = unless_time_up(job, &progress)? else {
        return Ok(());
    };
    output::result(&format!(
        "added light '{}' with {paths} paths ({:.2} s) → {} ({}, {} samples)",
        a.light,
        report.trace_seconds,
        output.display(),
        output::count(report.table.lights.len() as u64, "light"),
        report.summary.samples
    ));
    Ok(())
}
