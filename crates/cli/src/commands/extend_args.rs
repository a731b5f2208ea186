//! The arguments `refine` and `add-light` share: where the extended dataset goes, and the
//! seed, strategy and threads of the pass they add.

use super::{Opened, begin_dataset_write, check_finished, open_with_scene};
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
    mut_arg("selection", |a| a.help("Vertex selection [default: the dataset's last pass's]"))
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
}

impl ExtendArgs {
    /// The start of every extension of `dataset`: the output (default: the dataset itself)
    /// locked for writing, the dataset opened against its scene (`scene`, else the recorded
    /// one), and refused if its last pass was interrupted. Returns the lock, the output and
    /// the opened dataset.
    pub fn begin(&self, dataset: &Path, scene: Option<&str>) -> Result<(WriteLock, PathBuf, Opened)> {
        self.threads.apply()?;
        let output = self.output.clone().unwrap_or_else(|| dataset.to_owned());
        let inputs = [dataset];
        let lock = begin_dataset_write(
            &output,
            WriteIntent { inputs: &inputs, overwrite: self.overwrite, ..Default::default() },
        )?;
        let opened = open_with_scene(dataset, scene)?;
        check_finished(dataset, opened.reader.header())?;
        Ok((lock, output, opened))
    }
}
