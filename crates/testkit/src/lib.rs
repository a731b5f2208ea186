//! The helpers every integration-test binary of the workspace shares, compiled once as this
//! dev-dependency crate instead of once per test file: the reference scenes of `testdata/scenes`
//! (loaded through `opticks-io`), their reference images and statistics; [`physics`]
//! (trace-and-render in memory, small scenes, statistics; re-exported here), [`regions`] (image
//! and region means with measured standard errors) and [`files`] (scene files written into a
//! temporary folder and loaded, scene comparison, a generator for mangling inputs).

// Test helpers, not an API: a batch that cannot fail in a test returns `Result<_, ()>` (what the
// renderer's batch callback takes), and the input mangler's generator is called `next`.
#![allow(clippy::result_unit_err, clippy::should_implement_trait)]

pub mod files;
pub mod physics;
pub use physics::*;
pub mod regions;
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
