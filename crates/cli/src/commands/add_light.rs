//! `opticks add-light`: the scene file gained a light; trace only that light into the dataset.
//! The other lights' samples are reused untouched (geometry and materials must be unchanged —
//! the fingerprint says so — while the light table may grow).

use super::dataset_job::{ExtendArgs, continued_settings, extend_dataset};
use super::open_with_scene;
use anyhow::{Result, bail};
use opticks_core::dataset::LightRecord;
use opticks_core::trace::LightPlan;
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
    extend: ExtendArgs,
}

/// Adds the light.
pub fn run(a: Args) -> Result<()> {
    a.extend.threads.apply()?;
    let (reader, _, scene) = open_with_scene(&a.dataset, a.scene.as_deref())?;
    let mut header = reader.header().clone();
    let Some(scene_light) = scene.light_index(&a.light) else {
        let names: Vec<_> = scene.lights.iter().map(|l| l.name()).collect();
        bail!("the scene has no light '{}' (its lights: {names:?})", a.light);
    };
    if header.table.lights.iter().any(|l| l.name == a.light) {
        bail!(
            "light '{}' is already in {}: use `opticks refine` for more paths",
            a.light,
            a.dataset.display()
        );
    }
    let power = scene.lights[scene_light].power();
    let traced_power: f32 = header.table.lights.iter().map(|l| l.power.element_sum()).sum();
    let paths = match a.paths {
        Some(n) => n,
        None if traced_power > 0.0 => {
            ((header.table.total_paths() as f64 * (power.element_sum() / traced_power) as f64).ceil() as u64)
                .max(1)
        }
        None => bail!("give --paths: the dataset's lights have no power to compare with"),
    };
    if paths == 0 {
        bail!("--paths must be at least 1");
    }
    let table_index = header.table.lights.len() as u32;
    header.table.lights.push(LightRecord {
        name: a.light.clone(),
        shape: scene.light_shapes[scene_light],
        power,
        paths: 0,
    });
    header.fingerprint = scene.fingerprint; // matched (perhaps as a version-1 hash): now current
    let settings = continued_settings(&header, paths, a.extend.seed, &a.extend.strategy);
    let plan = vec![LightPlan { scene_light, table_index, paths }];
    let output = a.extend.output.clone().unwrap_or_else(|| a.dataset.clone());
    let report = extend_dataset(&reader, header, &output, &scene, settings, plan)?;
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
