//! Scene loading for the commands: a path to a scene file, or the name of a built-in scene.

use anyhow::{Context, Result, bail};
use opticks_core::scene::{Scene, SceneDescription, cornell_box};
use std::path::Path;

/// Dataset label of the built-in Cornell box.
pub const BUILTIN_CORNELL: &str = "builtin:cornell";

/// Every built-in scene, by the name a command takes.
pub const BUILTINS: &[&str] = &[BUILTIN_CORNELL];

/// Whether `spec` names a built-in scene (`builtin:…`), known or not.
pub fn is_builtin(spec: &str) -> bool {
    spec.starts_with("builtin:")
}

/// Loads a scene description from a file, or a built-in scene by its label.
pub fn load_description(spec: &str) -> Result<SceneDescription> {
    if spec == BUILTIN_CORNELL {
        return Ok(cornell_box());
    }
    if is_builtin(spec) {
        bail!("there is no built-in scene '{spec}' (built-in scenes: {})", BUILTINS.join(", "));
    }
    opticks_io::output_paths::check_input_file(Path::new(spec), "a scene file")?;
    let loaded = opticks_io::scene_formats::load_scene(Path::new(spec))?;
    for w in &loaded.warnings {
        crate::output::warning(&w.to_string());
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
        crate::output::warning(&format!(
            "{spec}: dropped {} degenerate (zero-area) triangles",
            scene.dropped_triangles
        ));
    }
    Ok(scene)
}
