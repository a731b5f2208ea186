//! `opticks trace`: light sampling of a scene file into a dataset file (written atomically).
//! `--time` stops it at a block boundary when the time is up, leaving a valid
//! `NAME.partial.opds` that `opticks resume` completes (the blocks are traced in a fixed order,
//! so what a run of any length traced is a prefix of the plan).

use super::{ThreadArgs, parse_seconds, unless_time_up, write_job};
use crate::progress::TraceProgress;
use crate::scene_arg::load_scene;
use crate::strategy_args::StrategyArgs;
use anyhow::Result;
use opticks_core::dataset::new_trace;
use opticks_io::dataset_job::NewPaths;
use std::path::PathBuf;
use std::time::Duration;

/// Arguments of `opticks trace`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (Mitsuba 3 XML or OBJ), or `builtin:cornell`.
    scene: String,
    /// Light paths to trace, over all lights (split in proportion to their power).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..), default_value_t = 4_000_000)]
    paths: u64,
    /// Output dataset file.
    #[arg(short, long)]
    output: PathBuf,
    /// Random seed; the same seed gives the same dataset whatever the thread count.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Stop after this many seconds (at the next block boundary), saving the paths traced as
    /// NAME.partial.opds for `opticks resume`; give a large --paths to trace for a fixed time.
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    time: Option<Duration>,
    #[command(flatten)]
    strategy: StrategyArgs,
    #[command(flatten)]
    pub(crate) threads: ThreadArgs,
}

/// Runs the trace.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    let scene = load_scene(&a.scene)?;
    let (header, pass) = new_trace(&scene, &a.scene, a.strategy.settings(a.paths, a.seed));
    let new = NewPaths { scene: &scene, pass };
    let progress = TraceProgress::with_time_limit(a.time);
    let Some(report) =
        unless_time_up(write_job(&a.scene, &a.output, header, &[], Some(new), &progress), &progress)?
    else {
        return Ok(());
    };
    let paths = report.table.total_paths();
    println!(
        "traced {paths} paths → {} samples in {:.2} s ({:.2} M paths/s) → {} ({:.1} MB)",
        report.summary.samples,
        report.trace_seconds,
        paths as f64 / report.trace_seconds / 1e6,
        a.output.display(),
        report.summary.bytes as f64 / 1e6
    );
    Ok(())
}
