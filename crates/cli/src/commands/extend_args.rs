//! The arguments `refine` and `add-light` share: where the extended dataset goes, and the
//! seed, strategy, threads and time limit (`--time`: stop at a block boundary, saving
//! `NAME.partial.opds` for `opticks resume`) of the pass they add.

use super::{Opened, begin_dataset_write, check_finished, open_with_scene};
use crate::scene_arg::DefineArgs;
use crate::strategy_args::StrategyArgs;
use anyhow::Result;
use opticks_io::dataset_lock::{WriteIntent, WriteLock};
use std::path::{Path, PathBuf};

/// Output, seed, strategy and threads of a pass that extends a dataset. The strategy options'
/// help says what their default is here: the dataset's last pass's, not `trace`'s.
#[derive(clap::Args, Debug)]
#[command(
    mut_arg("rr_depth", |a| a.help("Path depth from which Russian roulette may end paths [default: the dataset's last pass's]")),
    mut_arg("roulette", |a| a.help("Russian roulette rule [default: the dataset's last pass's]")),
    mut_arg("directions", |a| a.help("Direction sampling [default: the dataset's last pass's]")),
    mut_arg("selection", |a| a.help("Vertex selection [default: the dataset's last pass's]")),
    mut_arg("mis_records", |a| a.help("MIS records for the bidirectional estimator, 16 bytes per sample (docs/bidirectional.md) [default: the dataset's last pass's]"))
)]
pub struct ExtendArgs {
    /// Where to write the result (default: replace the dataset, which the result contains).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Replace an existing dataset at --output that is not the one extended.
    #[arg(long, requires = "output")]
    pub overwrite: bool,
    /// Seed (default: the dataset's first; a stream not used yet is picked either way).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Strategy options (default: those of the dataset's last pass).
    #[command(flatten)]
    pub strategy: StrategyArgs,
    #[command(flatten)]
    pub threads: super::ThreadArgs,
    /// Trace for this many seconds (ending at the next block boundary): the dataset is complete with
    /// the paths traced by then (give a large --paths).
    #[arg(long, value_name = "SECONDS", value_parser = super::parse_seconds)]
    pub time: Option<std::time::Duration>,
}

/// A dataset about to be extended: where the result goes, the write lock held on it, and the
/// dataset opened against its scene (checked to be finished: a pass added after an interrupted
/// one would make that one impossible to resume).
pub struct Extending {
    /// The result's path (`--output`, else the dataset itself).
    pub output: PathBuf,
    /// Held until the result is written.
    pub lock: WriteLock,
    /// The dataset and its scene.
    pub opened: Opened,
}

impl ExtendArgs {
    /// What `refine` and `add-light` do first: apply `--threads`, lock the output (refusing to
    /// write onto an input or an existing dataset without `--overwrite`), open `dataset` with
    /// `scene` (or the one it records) and refuse an unfinished dataset.
    pub fn begin(
        &self,
        dataset: &Path,
        scene: Option<&opticks_io::scene_source::SceneRef>,
        defines: &DefineArgs,
    ) -> Result<Extending> {
        self.threads.apply()?;
        defines.refuse_camera("a dataset verb")?;
        let output = self.output.clone().unwrap_or_else(|| dataset.to_path_buf());
        let inputs = [dataset];
        let lock = begin_dataset_write(
            &output,
            WriteIntent { inputs: &inputs, overwrite: self.overwrite, ..Default::default() },
        )?;
        let opened = open_with_scene(dataset, scene, defines)?;
        check_finished(dataset, opened.reader.header())?;
        Ok(Extending { output, lock, opened })
    }
}
