//! `opticks trace`: light sampling of a scene file into a dataset file (written atomically).
//! An existing dataset at the output is replaced only with `--overwrite` (it may hold hours of
//! refined work); see `opticks_io::dataset_lock` for every rule checked before the trace starts.
//! `--time` ends it at a block boundary when the time is up, complete with what it traced
//! (`opticks_core::dataset::end_pass_here`: the blocks are traced in a fixed order, each from
//! its own stream, so what a run of any length traced is what a run planning it traces).

use super::{ThreadArgs, begin_dataset_write, check_before_trace, parse_seconds, unless_time_up, write_job};
use crate::output;
use crate::progress::TraceProgress;
use crate::scene_arg::load_scene;
use crate::strategy_args::StrategyArgs;
use anyhow::{Result, anyhow};
use opticks_core::dataset::{check_emission, new_trace};
use opticks_io::dataset_job::{ASSUMED_BYTES_PER_PATH, NewPaths};
use opticks_io::dataset_lock::WriteIntent;
use opticks_io::scene_ref::{label_for, with_options};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Arguments of `opticks trace`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (Mitsuba 3 XML, VRML97 .wrl/.wrz, OBJ/MTL, glTF .gltf/.glb, Radiance .rad), or
    /// `builtin:cornell`; several Radiance .rad files are read in order as one scene (as oconv reads them).
    #[arg(value_parser = crate::scene_arg::parse_scene, required = true, num_args = 1..)]
    scene: Vec<opticks_io::scene_source::SceneRef>,
    /// Light paths to trace, over all lights (split in proportion to their power); e.g.
    /// 4000000, 4_000_000, 4M, 4e6.
    #[arg(long, allow_hyphen_values = true, value_parser = opticks_io::count_text::parse_count, default_value = "4M")]
    paths: u64,
    /// Output dataset file (.opds).
    #[arg(short, long)]
    output: PathBuf,
    /// Replace an existing dataset at the output.
    #[arg(long)]
    overwrite: bool,
    /// Random seed; the same seed gives the same dataset whatever the thread count.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Trace for this many seconds (ending at the next block boundary): the dataset is complete with
    /// the paths traced by then, as if they had been planned; give a large --paths.
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    time: Option<Duration>,
    #[command(flatten)]
    strategy: StrategyArgs,
    #[command(flatten)]
    pub(crate) threads: ThreadArgs,
    #[command(flatten)]
    defines: crate::scene_arg::DefineArgs,
}

/// Runs the trace.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    a.defines.refuse_camera("trace")?;
    let scene_ref = crate::scene_arg::joined(&a.scene)?.expect("clap requires a scene");
    let inputs: Vec<&Path> = scene_ref.files();
    let _lock = begin_dataset_write(
        &a.output,
        WriteIntent { inputs: &inputs, overwrite: a.overwrite, ..Default::default() },
    )?;
    let scene = load_scene(&scene_ref, &a.defines)?;
    let options = a.defines.options();
    let (header, pass) = new_trace(
        &scene,
        &with_options(&label_for(&scene_ref.label(), &a.output), &options),
        a.strategy.settings(a.paths, a.seed),
    );
    check_emission(&pass.lights).map_err(|e| anyhow!("{scene_ref}: {e}"))?;
    output::detail(&format!(
        "scene {}: {} triangles, {}; plan: {}",
        scene_ref,
        scene.triangles.len(),
        output::count(scene.lights.len() as u64, "light"),
        pass.describe(&header.table)
    ));
    check_before_trace(&a.output, &header.table, &pass, a.paths.saturating_mul(ASSUMED_BYTES_PER_PATH))?;
    let new = NewPaths { scene: &scene, pass };
    let _graceful = crate::interrupt::graceful();
    let progress = TraceProgress::with_time_limit(a.time);
    let job = write_job((&scene_ref, &options), &a.output, header, &[], Some(new), &progress);
    let Some(report) = unless_time_up(job, &progress)? else {
        return Ok(());
    };
    let paths = report.table.total_paths();
    output::result(&format!(
        "traced {paths} paths → {} samples in {:.2} s ({:.2} M paths/s) → {} ({})",
        report.summary.samples,
        report.trace_seconds,
        paths as f64 / report.trace_seconds / 1e6,
        a.output.display(),
        output::bytes(report.summary.bytes)
    ));
    Ok(())
}
