//! `opticks info`: what a dataset holds, readably (or as JSON with `--json`), after verifying
//! every checksum in it (`opticks_io::dataset_info`). The scene is shown as the dataset records
//! it — relative to the dataset's own folder and absolute — with which of them is found.

use crate::output;
use anyhow::Result;
use opticks_io::dataset_info::DatasetInfo;
use std::path::PathBuf;

/// Arguments of `opticks info`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Dataset file.
    dataset: PathBuf,
    /// Print one JSON object instead of the readable summary.
    #[arg(long)]
    json: bool,
}

/// Prints the summary.
pub fn run(a: Args) -> Result<()> {
    let info = DatasetInfo::read(&a.dataset)?;
    for w in &info.warnings {
        output::warning(w);
    }
    if a.json {
        output::data(&serde_json::to_string(&info)?);
    } else {
        for line in info.lines() {
            output::data(&line);
        }
    }
    Ok(())
}
