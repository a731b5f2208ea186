//! Helpers shared by the end-to-end tests: the reference scenes of `testdata/scenes` (loaded
//! through `opticks-io`), their reference images and statistics, and everything of
//! [`physics`] (trace-and-render in memory, small scenes, statistics), which needs only the core,
//! and [`regions`] (image and region means with measured standard errors).

#![allow(dead_code)] // each test binary uses a different subset

mod physics;
#[allow(unused_imports)] // some test binaries use none of them
pub use physics::*;
pub mod regions;
#[allow(unused_imports)]
pub use regions::Estimate;

use opticks_core::scene::Scene;
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
