//! `opticks info`: what a dataset holds, readably, after verifying every checksum in it.

use anyhow::Result;
use opticks_io::dataset_file::DatasetReader;
use std::path::PathBuf;

/// Arguments of `opticks info`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Dataset file.
    dataset: PathBuf,
}

/// Prints the summary.
pub fn run(a: Args) -> Result<()> {
    let reader = DatasetReader::open(&a.dataset)?;
    reader.verify()?; // every chunk's checksum: `info` is also the integrity check
    let h = reader.header();
    let samples = reader.total_samples();
    let paths = h.table.total_paths();
    println!("dataset   {}", a.dataset.display());
    println!("scene     {}", h.label);
    println!("geometry  {}", h.fingerprint.geometry_hex());
    println!("lights    {}", h.fingerprint.lights_hex());
    for p in &h.trace.passes {
        let state = if p.is_complete() {
            String::new()
        } else {
            format!(
                " — interrupted: {} of {} planned paths (`opticks resume` finishes it)",
                p.paths,
                p.planned_paths()
            )
        };
        println!(
            "pass      seed {}, stream {}: {} paths in {:.2} s; --roulette {} --rr-depth {} --directions {} \
             --selection {} --mis-records {}{state}",
            p.seed,
            p.stream,
            p.paths,
            p.seconds,
            flag(p.roulette),
            p.rr_depth,
            flag(p.directions),
            flag(p.selection),
            p.mis.map_or("none".to_string(), |m| format!(
                "{} (sampling signature {})",
                flag(m.heuristic),
                m.signature
            ))
        );
    }
    match opticks_core::dataset::mis_compatibility(h) {
        Ok(m) => {
            println!("mis       the bidirectional estimator can weight it ({} heuristic)", flag(m.heuristic))
        }
        Err(e) => println!("mis       not usable by the bidirectional estimator: {e}"),
    }
    println!("paths     {paths}");
    println!("samples   {samples} ({:.2} per path)", samples as f64 / paths.max(1) as f64);
    println!("chunks    {}", reader.chunk_count());
    println!(
        "size      {} bytes ({:.1} bytes/sample)",
        reader.file_len(),
        reader.file_len() as f64 / samples.max(1) as f64
    );
    println!("{:>5}  {:<24} {:>14}  power Φ (W, RGB)", "light", "name", "paths N_k");
    for (k, l) in h.table.lights.iter().enumerate() {
        println!(
            "{k:>5}  {:<24} {:>14}  {:.6} {:.6} {:.6}",
            l.name, l.paths, l.power.x, l.power.y, l.power.z
        );
    }
    Ok(())
}

/// A strategy value as its command-line spelling (`Energy` → `energy`), so `info` shows the
/// options that would repeat the pass.
fn flag(value: impl std::fmt::Debug) -> String {
    format!("{value:?}").to_lowercase()
}
