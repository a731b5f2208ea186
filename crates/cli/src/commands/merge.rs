//! `opticks merge`: datasets of the same scene traced independently (other seeds, other
//! machines) become one — the thesis's master/worker merge (§6.2.4). Lights are matched by name
//! and N_k summed; a light only some inputs have (one of them gained it by `add-light`) keeps
//! those inputs' paths, and a light whose shape differs is refused. Datasets that share a random
//! stream are refused, since their paths would be copies, not new samples. On Ctrl-C nothing
//! is written.

use super::dataset_job::{Source, write_dataset};
use anyhow::{Result, bail};
use opticks_core::dataset::merge_tables;
use opticks_io::dataset_file::DatasetReader;
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
        let h = r.header();
        if h.fingerprint.geometry != header.fingerprint.geometry {
            bail!(
                "{} and {} were traced from different scenes (geometry fingerprints {} and {})",
                a.inputs[0].display(),
                path.display(),
                header.fingerprint.geometry_hex(),
                h.fingerprint.geometry_hex()
            );
        }
        let (table, lights) = merge_tables(&header.table, &h.table).map_err(|e| {
            anyhow::anyhow!("cannot merge {} into {}: {e}", path.display(), a.inputs[0].display())
        })?;
        if table.lights.len() == h.table.lights.len() {
            header.fingerprint.lights = h.fingerprint.lights; // this input has every light
        }
        header.table = table;
        for p in &h.trace.passes {
            if header.trace.passes.iter().any(|q| q.seed == p.seed && q.stream == p.stream) {
                bail!(
                    "{} repeats the random stream (seed {}, stream {}) of an earlier input: its paths are \
                     copies, not independent samples (trace workers with different --seed)",
                    path.display(),
                    p.seed,
                    p.stream
                );
            }
            let mut p = p.clone();
            p.planned.iter_mut().for_each(|(light, _)| *light = lights[*light as usize]);
            header.trace.passes.push(p);
        }
        sources.push(Source { reader: r, lights: Some(lights) });
    }
    let report = write_dataset(&a.output, header, &sources, None)?;
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
