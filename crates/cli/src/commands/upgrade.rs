//! `opticks upgrade`: gives a dataset written without MIS records (dataset format 1 or 2, or
//! traced with `--mis-records none`) the records the bidirectional estimator needs, by
//! re-tracing every pass from its own seeds and streams and checking that they trace the same
//! paths, up to rounding (`opticks_core::dataset::reproduces`; the dataset's samples are kept
//! bit for bit) (`opticks_io::dataset_job::upgrade_dataset`; the plan is
//! `opticks_core::dataset::upgrade_plan`). The result is written atomically; a chunk that does
//! not re-trace writes nothing. Like every dataset writer it first checks its output and takes
//! the output's write lock ([`begin_dataset_write`]): it replaces its own input in place (the
//! result holds the same samples), but `-o` onto a scene or another existing dataset is refused
//! without `--overwrite`, and a second writer of the same dataset is refused while it runs.

use super::{begin_dataset_write, job_error, open_with_scene};
use crate::progress::TraceProgress;
use anyhow::Result;
use clap::ValueEnum;
use opticks_core::dataset::Heuristic;
use opticks_io::dataset_job::upgrade_dataset;
use opticks_io::dataset_lock::WriteIntent;
use opticks_io::scene_ref::{label_for, with_options};
use std::path::PathBuf;

/// The heuristic of the records.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum HeuristicArg {
    /// Power heuristic (β = 2).
    Power,
    /// Balance heuristic (β = 1).
    Balance,
}

/// Arguments of `opticks upgrade`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Dataset to upgrade.
    dataset: PathBuf,
    /// Scene file (default: the one recorded in the dataset) (repeated for several .rad files).
    #[arg(long, value_parser = crate::scene_arg::parse_scene)]
    scene: Vec<opticks_io::scene_source::SceneRef>,
    #[command(flatten)]
    defines: crate::scene_arg::DefineArgs,
    /// Where to write the result (default: replace the dataset).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Replace an existing dataset at --output that is not the one upgraded.
    #[arg(long, requires = "output")]
    overwrite: bool,
    /// Heuristic of the MIS records.
    #[arg(long, value_enum, default_value = "power")]
    mis_records: HeuristicArg,
    #[command(flatten)]
    threads: super::ThreadArgs,
}

/// Runs the upgrade.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    a.defines.refuse_camera("upgrade")?;
    let output = a.output.clone().unwrap_or_else(|| a.dataset.clone());
    let inputs = [a.dataset.as_path()];
    let _lock = begin_dataset_write(
        &output,
        WriteIntent { inputs: &inputs, overwrite: a.overwrite, ..Default::default() },
    )?;
    let super::Opened { reader, scene, scene_ref, options, .. } =
        open_with_scene(&a.dataset, crate::scene_arg::joined(&a.scene)?.as_ref(), &a.defines)?;
    // The scene as used (--scene, -D), recorded from where the output is.
    let label = with_options(&label_for(&scene_ref.label(), &output), &options);
    let heuristic = match a.mis_records {
        HeuristicArg::Power => Heuristic::Power,
        HeuristicArg::Balance => Heuristic::Balance,
    };
    let report = upgrade_dataset(&reader, &scene, heuristic, (&output, label), &TraceProgress::default())
        .map_err(job_error)?;
    println!(
        "upgraded {}: {} chunks re-traced to the same {} samples, with MIS records ({:.2} s) → {} ({:.1} MB)",
        a.dataset.display(),
        report.summary.chunks,
        report.summary.samples,
        report.trace_seconds,
        output.display(),
        report.summary.bytes as f64 / 1e6
    );
    Ok(())
}
