//! Scene loading for the commands: a path to a scene file, or the name of a built-in scene.

use anyhow::{Context, Result};
use opticks_core::scene::{Scene, SceneDescription, cornell_box};
use std::path::Path;

/// Dataset label of the built-in Cornell box.
pub const BUILTIN_CORNELL: &str = "builtin:cornell";

/// Loads a scene description from a file, or a built-in scene by its label.
pub fn load_description(spec: &str) -> Result<SceneDescription> {
    if spec == BUILTIN_CORNELL {
        return Ok(cornell_box());
    }
    let loaded = opticks_io::scene_formats::load_scene(Path::new(spec))?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
    Ok(loaded.description)
}

/// Loads and validates a scene (builds its BVH).
pub fn load_scene(spec: &str) -> Result<Scene> {
    build_scene(spec, &load_description(spec)?)
}

/// Validates a loaded description into a scene, reporting dropped triangles.
pub fn build_scene(spec: &str, desc: &SceneDescription) -> Result<Scene> {
    let scene = Scene::build(desc).with_context(|| format!("invalid scene {spec}"))?;
    if scene.dropped_triangles > 0 {
        eprintln!("warning: {spec}: dropped {} degenerate (zero-area) triangles", scene.dropped_triangles);
    }
    Ok(scene)
}
