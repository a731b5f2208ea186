//! `opticks merge`: datasets of the same scene traced independently (other seeds, other
//! machines) become one — the thesis's master/worker merge (§6.2.4), by
//! `opticks_core::dataset::merge_header`. Lights are matched by name and N_k summed; a light
//! only some inputs have (one of them gained it by `add-light`) keeps those inputs' paths, and a
//! light whose shape differs is refused. Datasets that share a random stream are refused, since
//! their paths would be copies, not new samples. Partial datasets are refused (resume them
//! first). The result records the scene of the input that has every light (the one that gained
//! a light by `add-light`), from the output's location. An existing file at the output is
//! replaced only if it is one of the inputs (the result contains it) or with `--overwrite`. On
//! a signal nothing is written.

use super::{begin_dataset_write, check_finished, job_error};
use crate::output;
use crate::progress::TraceProgress;
use anyhow::{Result, anyhow, bail};
use opticks_core::dataset::{ChangesText, MergeError, merge_header, mis_compatibility};
use opticks_io::dataset_file::DatasetReader;
use opticks_io::dataset_job::{Source, write_dataset};
use opticks_io::dataset_lock::{WriteIntent, same_file};
use opticks_io::output_paths::check_input_file;
use std::path::{Path, PathBuf};

/// Arguments of `opticks merge`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Datasets to merge (at least two).
    #[arg(required = true, num_args = 2..)]
    inputs: Vec<PathBuf>,
    /// Output dataset (.opds).
    #[arg(short, long)]
    output: PathBuf,
    /// Replace an existing dataset at the output, also one of the inputs (the merge then holds
    /// all of it).
    #[arg(long)]
    overwrite: bool,
}

/// Merges the datasets.
pub fn run(a: Args) -> Result<()> {
    let inputs: Vec<&Path> = a.inputs.iter().map(PathBuf::as_path).collect();
    // Unlike refine's in-place update, replacing an input is a choice the user states.
    if !a.overwrite && inputs.iter().any(|i| same_file(i, &a.output)) {
        bail!("{}: is one of the inputs; give --overwrite to replace it by the merge", a.output.display());
    }
    let _lock = begin_dataset_write(
        &a.output,
        WriteIntent { inputs: &inputs, overwrite: a.overwrite, ..Default::default() },
    )?;
    let mut readers = Vec::new();
    for p in &a.inputs {
        check_input_file(p, "a dataset")?;
        let r = DatasetReader::open(p)?;
        check_finished(p, r.header())?;
        readers.push(r);
    }
    let mut header = readers[0].header().clone();
    let mut sources = vec![Source::as_is(&readers[0])];
    for (r, path) in readers.iter().zip(&a.inputs).skip(1) {
        let (first, path) = (a.inputs[0].display(), path.display());
        let lights = merge_header(&mut header, r.header()).map_err(|e| match e {
            MergeError::DifferentScenes { first: f, other, changes } => anyhow!(
                "{first} and {path} were traced from different scenes: {} (geometry fingerprints {} and {})",
                ChangesText(changes.as_ref()),
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
    // The label is one input's (the one with every light): record its scene from the output.
    if let Some(from) = readers.iter().zip(&a.inputs).find(|(r, _)| r.header().label == header.label) {
        if opticks_io::scene_ref::resolve(&header.label, from.1).is_err() {
            output::warning(&format!(
                "the scene {} records is not found from there, so neither will the merged dataset find it: \
                 give --scene when you use {}",
                from.1.display(),
                a.output.display()
            ));
        }
        header.label = opticks_io::scene_ref::rebase(&header.label, from.1, &a.output);
    }
    // Passes without MIS records (older datasets) leave the whole merge without them.
    if let Err(why) = mis_compatibility(&header)
        && readers.iter().any(|r| mis_compatibility(r.header()).is_ok())
    {
        output::warning(&format!(
            "the merged dataset cannot be rendered with --estimator bidirectional ({why}), though some of \
             its inputs could: `opticks upgrade {}` gives it MIS records",
            a.output.display()
        ));
    }
    let _graceful = crate::interrupt::graceful();
    let report =
        write_dataset(&a.output, header, &sources, None, &TraceProgress::default()).map_err(job_error)?;
    output::result(&format!(
        "merged {} datasets: {} paths, {}, {} samples → {}",
        readers.len(),
        report.table.total_paths(),
        output::count(report.table.lights.len() as u64, "light"),
        report.summary.samples,
        a.output.display()
    ));
    Ok(())
}
