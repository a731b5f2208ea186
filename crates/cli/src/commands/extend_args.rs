//! The arguments `refine` and `add-light` share: where the extended dataset goes, and the
//! seed, strategy and threads of the pass they add.

use crate::strategy_args::StrategyArgs;
use std::path::PathBuf;

/// Output, seed, strategy and threads of a pass that extends a dataset.
#[derive(clap::Args, Debug)]
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
