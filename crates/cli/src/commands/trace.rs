//! `opticks trace`: light sampling of a scene file into a dataset file (written atomically).

use super::{ThreadArgs, trace_with_progress};
use crate::scene_arg::load_scene;
use anyhow::{Context, Result, bail};
use opticks_core::dataset::Chunk;
use opticks_core::trace::{TraceSettings, planned_table};
use opticks_io::dataset_file::{DatasetHeader, DatasetWriter, TraceInfo};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `opticks trace`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (Mitsuba 3 XML), or `builtin:cornell`.
    scene: String,
    /// Light paths to trace, over all lights (split in proportion to their power).
    #[arg(long, default_value_t = 4_000_000)]
    paths: u64,
    /// Output dataset file.
    #[arg(short, long)]
    output: PathBuf,
    /// Random seed; the same seed gives the same dataset whatever the thread count.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Path depth from which Russian roulette may end paths.
    #[arg(long, default_value_t = 5)]
    rr_depth: u32,
    #[command(flatten)]
    threads: ThreadArgs,
}

/// Runs the trace.
pub fn run(a: Args) -> Result<()> {
    if a.paths == 0 {
        bail!("--paths must be at least 1");
    }
    a.threads.apply()?;
    let scene = load_scene(&a.scene)?;
    let settings = TraceSettings { paths: a.paths, seed: a.seed, stream: 0, rr_depth: a.rr_depth };
    let header = DatasetHeader {
        fingerprint: scene.fingerprint,
        label: a.scene.clone(),
        trace: TraceInfo { seed: a.seed, rr_depth: a.rr_depth },
        table: planned_table(&scene, a.paths),
    };
    let t0 = Instant::now();
    let mut writer = DatasetWriter::create(&a.output, &header)
        .with_context(|| format!("cannot create dataset {}", a.output.display()))?;
    // Writing overlaps tracing: a writer thread drains finished chunks while the next batch is
    // traced. The bounded channel keeps at most a few batches in memory.
    let (table, writer) = std::thread::scope(|s| -> Result<_> {
        let (send, receive) = std::sync::mpsc::sync_channel::<Chunk>(128);
        let writing = s.spawn(move || -> Result<DatasetWriter> {
            for c in receive {
                writer.write_chunk(&c)?;
            }
            Ok(writer)
        });
        let traced = trace_with_progress(&scene, &settings, |c| {
            send.send(c).map_err(|_| anyhow::anyhow!("the dataset writer stopped"))
        });
        drop(send);
        let written = writing.join().map_err(|_| anyhow::anyhow!("the dataset writer panicked"))?;
        // A write error explains a trace that stopped because the writer did: report it first.
        let writer = written?;
        Ok((traced?, writer))
    })?;
    let summary =
        writer.finish(&table).with_context(|| format!("cannot write dataset {}", a.output.display()))?;
    let secs = t0.elapsed().as_secs_f64();
    println!(
        "traced {} paths → {} samples in {:.2} s ({:.2} M paths/s) → {} ({:.1} MB)",
        table.total_paths(),
        summary.samples,
        secs,
        table.total_paths() as f64 / secs / 1e6,
        a.output.display(),
        summary.bytes as f64 / 1e6
    );
    Ok(())
}
