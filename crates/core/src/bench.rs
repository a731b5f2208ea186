//! The speed measurement behind `opticks bench`, for any front end: a scene's light paths traced
//! into memory and rendered through a camera, each phase run `repeat` times and the best time
//! kept, so a one-off hiccup of the machine does not count. Nothing touches a disk, so the times
//! are the engine's own. Everything traced is held in memory, so [`memory_estimate`] measures a
//! pilot trace's bytes per path first, for a front end to refuse a count the machine cannot hold
//! before it starts.

use crate::dataset::{Chunk, LightTable, TraceSettings};
use crate::film::Film;
use crate::scene::Scene;
use crate::sensor::{SampleBatch, Sensor, render};
use crate::trace::trace;
use std::convert::Infallible;
use std::time::Instant;

/// What a benchmark measured.
#[derive(Clone, Debug)]
pub struct BenchReport {
    /// The best trace time, in seconds.
    pub trace_seconds: f64,
    /// The best render time, in seconds.
    pub render_seconds: f64,
    /// The samples stored by one trace.
    pub samples: u64,
    /// The rendered image (to compare against a reference).
    pub film: Film,
}

/// Light paths of the pilot trace behind [`memory_estimate`] (one block of the tracer).
pub const PILOT_PATHS: u64 = 4096;

/// Bytes the samples and MIS records of `settings.paths` traced paths of `scene` take in memory,
/// estimated from a pilot trace of [`PILOT_PATHS`] of them (their stored bytes per path, scaled;
/// saturating at `u64::MAX`).
pub fn memory_estimate(scene: &Scene, settings: &TraceSettings) -> u64 {
    let pilot_paths = settings.paths.clamp(1, PILOT_PATHS);
    let pilot = TraceSettings { paths: pilot_paths, ..*settings };
    let mut bytes = 0u128;
    let sink = |c: Chunk| {
        bytes += (c.samples.len() * std::mem::size_of::<crate::dataset::Sample>()
            + c.records.len() * std::mem::size_of::<crate::dataset::MisRecord>()) as u128;
        Ok::<(), Infallible>(())
    };
    match trace(scene, &pilot, sink, |_| {}) {
        Ok(_) => {}
    }
    let total = bytes * settings.paths as u128 / pilot_paths as u128;
    u64::try_from(total).unwrap_or(u64::MAX)
}

/// Traces `settings.paths` paths of `scene` and renders them through `camera`, each `repeat`
/// times (at least once), keeping the best time of each phase.
pub fn bench(scene: &Scene, camera: &Sensor, settings: &TraceSettings, repeat: u32) -> BenchReport {
    let mut best_trace = f64::INFINITY;
    let mut chunks: Vec<Chunk> = Vec::new();
    let mut table = LightTable::default();
    for _ in 0..repeat.max(1) {
        chunks.clear();
        let t = Instant::now();
        let sink = |c| {
            chunks.push(c);
            Ok::<(), Infallible>(())
        };
        table = match trace(scene, settings, sink, |_| {}) {
            Ok(table) => table,
        };
        best_trace = best_trace.min(t.elapsed().as_secs_f64());
    }
    let samples = chunks.iter().map(|c| c.samples.len() as u64).sum();
    let mut best_render = f64::INFINITY;
    let mut film = Film::new(1, 1);
    for _ in 0..repeat.max(1) {
        let t = Instant::now();
        let batch = |i: usize| {
            let c = &chunks[i];
            Ok::<_, Infallible>(SampleBatch {
                flux_per_path: table.flux_per_path(c.light as usize),
                samples: &c.samples,
            })
        };
        film = match render(scene, camera, chunks.len(), batch, |_| {}) {
            Ok(film) => film,
        };
        best_render = best_render.min(t.elapsed().as_secs_f64());
    }
    BenchReport { trace_seconds: best_trace, render_seconds: best_render, samples, film }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::cornell_box;

    /// The estimate scales with the paths asked for, from bytes a pilot really stored.
    #[test]
    fn the_memory_estimate_scales_the_pilots_bytes_per_path() {
        let scene = Scene::build(&cornell_box()).unwrap();
        let settings = TraceSettings { paths: PILOT_PATHS, ..Default::default() };
        let pilot = memory_estimate(&scene, &settings);
        assert!(pilot >= PILOT_PATHS * 32, "at least a sample a path in the Cornell box: {pilot}");
        let huge = memory_estimate(&scene, &TraceSettings { paths: 4_000_000_000_000, ..settings });
        assert_eq!(huge, (pilot as u128 * 4_000_000_000_000 / PILOT_PATHS as u128) as u64);
        let most = memory_estimate(&scene, &TraceSettings { paths: u64::MAX, ..settings });
        assert_eq!(most, u64::MAX, "saturates");
    }
}
