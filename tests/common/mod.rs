//! Helpers shared by the end-to-end tests: trace-and-render in memory, reference images.

#![allow(dead_code)] // each test binary uses a different subset

use opticks_core::dataset::{Chunk, LightTable};
use opticks_core::film::Film;
use opticks_core::scene::{Pinhole, Scene};
use opticks_core::sensor::{SampleBatch, Sensor, render};
use opticks_core::trace::{TraceSettings, trace};
use std::path::{Path, PathBuf};

/// The repository root.
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().unwrap()
}

/// `testdata/scenes/NAME/FILE`.
pub fn scene_file(name: &str, file: &str) -> PathBuf {
    repo().join("testdata/scenes").join(name).join(file)
}

/// Loads and builds a reference scene.
pub fn load(name: &str) -> Scene {
    let loaded = opticks_io::scene_formats::load_scene(&scene_file(name, "scene.xml")).unwrap();
    Scene::build(&loaded.description).unwrap()
}

/// The scene's own camera.
pub fn camera(scene: &Scene) -> Pinhole {
    Pinhole::new(scene.camera.as_ref().expect("scene has a camera")).unwrap()
}

/// Traces `paths` light paths with `seed` into memory.
pub fn trace_chunks(scene: &Scene, paths: u64, seed: u64) -> (LightTable, Vec<Chunk>) {
    trace_chunks_with(scene, &TraceSettings { paths, seed, ..Default::default() })
}

/// Traces with any settings into memory.
pub fn trace_chunks_with(scene: &Scene, settings: &TraceSettings) -> (LightTable, Vec<Chunk>) {
    let mut chunks: Vec<Chunk> = Vec::new();
    let table = trace(
        scene,
        settings,
        |c| {
            chunks.push(c);
            Ok::<(), ()>(())
        },
        |_| {},
    )
    .unwrap();
    (table, chunks)
}

/// Renders in-memory chunks through a sensor.
pub fn render_chunks(scene: &Scene, sensor: &Sensor, table: &LightTable, chunks: &[Chunk]) -> Film {
    render(
        scene,
        sensor,
        chunks.len(),
        |i| {
            Ok::<_, ()>(SampleBatch {
                flux_per_path: table.flux_per_path(chunks[i].light as usize),
                samples: &chunks[i].samples,
            })
        },
        |_| {},
    )
    .unwrap()
}

/// Traces `paths` light paths with `seed` and renders them through `cam`, in memory.
pub fn trace_and_render(scene: &Scene, cam: &Pinhole, paths: u64, seed: u64) -> Film {
    trace_and_render_with(scene, cam, &TraceSettings { paths, seed, ..Default::default() })
}

/// Traces with any settings and renders through `cam`, in memory.
pub fn trace_and_render_with(scene: &Scene, cam: &Pinhole, settings: &TraceSettings) -> Film {
    let (table, chunks) = trace_chunks_with(scene, settings);
    render_chunks(scene, &Sensor::from(*cam), &table, &chunks)
}

/// The reference image of a scene as interleaved RGB.
pub fn reference(name: &str) -> Vec<f32> {
    opticks_io::image_file::read_exr_rgb(&scene_file(name, "reference.exr")).unwrap().2
}

/// A number from the scene's `reference_stats.json` (`reference.KEY`).
pub fn reference_stat(name: &str, key: &str) -> f64 {
    let text = std::fs::read_to_string(scene_file(name, "reference_stats.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["reference"][key].as_f64().unwrap()
}
