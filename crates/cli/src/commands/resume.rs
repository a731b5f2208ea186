//! `opticks resume`: finishes an interrupted `trace`, `refine` or `add-light` from the
//! `NAME.partial.opds` it saved. The partial file's last pass records what the run planned
//! (paths per light, seed, stream, strategy); blocks are traced in a fixed order, each from its
//! own random stream, so the blocks already saved are a known prefix and only the rest is
//! traced. The result holds exactly the samples of an uninterrupted run.

use super::dataset_job::{NewPaths, Source, scene_lights, write_dataset};
use super::{ThreadArgs, open_with_scene};
use anyhow::{Result, bail};
use opticks_core::trace::{LightPlan, blocks_done};
use std::path::{Path, PathBuf};

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
    threads: ThreadArgs,
}

/// Resumes the run.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    let (reader, _, scene) = open_with_scene(&a.partial, a.scene.as_deref())?;
    let header = reader.header().clone();
    let Some(pass) = header.trace.passes.last().filter(|p| !p.is_complete()) else {
        bail!("{}: nothing to resume, its last trace pass is complete", a.partial.display());
    };
    let scene_lights = scene_lights(&header.table, &scene, "resume")?;
    let plan: Vec<LightPlan> = pass
        .planned
        .iter()
        .map(|&(table_index, paths)| LightPlan {
            scene_light: scene_lights[table_index as usize],
            table_index,
            paths,
        })
        .collect();
    let Some(first_block) = blocks_done(&plan, pass.paths) else {
        bail!(
            "{}: its last pass traced {} paths, which is no whole number of its blocks: not a file \
             saved by an interrupted run",
            a.partial.display(),
            pass.paths
        );
    };
    let settings = pass.settings();
    let done = pass.paths;
    let output = a.output.clone().unwrap_or_else(|| finished_path(&a.partial));
    let report = write_dataset(
        &output,
        header,
        &[Source::as_is(&reader)],
        Some(NewPaths { scene: &scene, settings, plan, first_block }),
    )?;
    if output != a.partial {
        std::fs::remove_file(&a.partial).map_err(|e| {
            anyhow::anyhow!("finished {}, but cannot remove {}: {e}", output.display(), a.partial.display())
        })?;
    }
    println!(
        "resumed {}: {} + {} paths = {} planned ({:.2} s) → {} ({} paths, {} samples)",
        a.partial.display(),
        done,
        settings.paths - done,
        settings.paths,
        report.trace_seconds,
        output.display(),
        report.table.total_paths(),
        report.summary.samples
    );
    Ok(())
}

/// `dir/NAME.opds` for `dir/NAME.partial.opds` (other names are kept: resume then writes in place).
fn finished_path(partial: &Path) -> PathBuf {
    let name = partial.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    match name.strip_suffix(".partial.opds") {
        Some(stem) if !stem.is_empty() => partial.with_file_name(format!("{stem}.opds")),
        _ => partial.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_finished_name_drops_partial() {
        assert_eq!(finished_path(Path::new("d/box.partial.opds")), Path::new("d/box.opds"));
        assert_eq!(finished_path(Path::new("box.opds")), Path::new("box.opds"));
    }
}
