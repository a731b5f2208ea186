//! The speed measurement behind `opticks bench`, for any front end: a scene's light paths traced
//! into memory and rendered through a camera, each phase run `repeat` times and the best time
//! kept, so a one-off hiccup of the machine does not count. Nothing touches a disk, so the times
//! are the engine's own.

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
