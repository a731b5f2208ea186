//! `opticks merge`: datasets of the same scene traced independently (other seeds, other
//! machines) become one — the thesis's master/worker merge (§6.2.4), by
//! `opticks_core::dataset::merge_header`. Lights are matched by name and N_k summed; a light
//! only some inputs have (one of them gained it by `add-light`) keeps those inputs' paths, and a
//! light whose shape differs is refused. Datasets that share a random stream are refused, since
//! their paths would be copies, not new samples. On Ctrl-C nothing is written.

use super::job_error;
use crate::progress::TraceProgress;
use anyhow::{Result, anyhow};
use opticks_core::dataset::{MergeError, merge_header};
use opticks_io::dataset_file::DatasetReader;
use opticks_io::dataset_job::{Source, write_dataset};
use std::path::PathBuf;

/// Arguments of `opticks merge`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Datasets to merge (at least two).
    #[arg(required = true, num_args = 2..)]
    inputs: Vec<PathBuf>,
    /// Output dataset.
    #[arg(short, long)]
    output: PathBuf,
}

/// Merges the datasets.
pub fn run(a: Args) -> Result<()> {
    let readers: Vec<DatasetReader> =
        a.inputs.iter().map(|p| DatasetReader::open(p)).collect::<Result<_, _>>()?;
    let mut header = readers[0].header().clone();
    let mut sources = vec![Source::as_is(&readers[0])];
    for (r, path) in readers.iter().zip(&a.inputs).skip(1) {
        let (first, path) = (a.inputs[0].display(), path.display());
        let lights = merge_header(&mut header, r.header()).map_err(|e| match e {
            MergeError::DifferentScenes { first: f, other } => anyhow!(
                "{first} and {path} were traced from different scenes (geometry fingerprints {} and {})",
                f.geometry_hex(),
                other.geometry_hex()
            ),
            MergeError::ShapeChanged(_) | MergeError::TooManyPaths(_) => {
                anyhow!("cannot merge {path} into {first}: {e}")
            }
            MergeError::RepeatedStream { seed, stream } => anyhow!(
                "{path} repeats the random stream (seed {seed}, stream {stream}) of an earlier input: its paths \
                 are copies, not independent samples (trace workers with different --seed)"
            ),
        })?;
        sources.push(Source { reader: r, lights: Some(lights) });
    }
    let report =
        write_dataset(&a.output, header, &sources, None, &TraceProgress::default()).map_err(job_error)?;
    println!(
        "merged {} datasets: {} paths, {} lights, {} samples → {}",
        readers.len(),
        report.table.total_paths(),
        report.table.lights.len(),
        report.summary.samples,
        a.output.display()
    );
    Ok(())
}
