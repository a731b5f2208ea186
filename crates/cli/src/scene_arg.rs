//! Scene loading for the commands: a path to a scene file, or the name of a built-in scene,
//! with the `-D NAME=VALUE` parameters of a Mitsuba scene ([`DefineArgs`]).

use anyhow::{Context, Result, bail};
use opticks_core::scene::{Scene, SceneDescription, cornell_box};
use opticks_io::scene_formats::LoadOptions;
use std::path::Path;

/// Dataset label of the built-in Cornell box.
pub const BUILTIN_CORNELL: &str = "builtin:cornell";

/// Every built-in scene, by the name a command takes.
pub const BUILTINS: &[&str] = &[BUILTIN_CORNELL];

/// Whether `spec` names a built-in scene (`builtin:…`), known or not.
pub fn is_builtin(spec: &str) -> bool {
    spec.starts_with("builtin:")
}

/// The options of every verb that loads a scene: `-D` parameters, and which camera and which
/// scene of a file that holds several.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct DefineArgs {
    /// Value of the Mitsuba scene parameter `$NAME` (overrides its `<default>`), as
    /// `mitsuba -D NAME=VALUE`; repeatable. A dataset traced with parameters renders only
    /// against the same ones (its scene fingerprint says so).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    define: Vec<(String, String)>,
    /// The scene file's camera to use, by name, where it has several: a glTF camera (its
    /// node's or its own name), a Mitsuba `<sensor>` (its `id`), a VRML `Viewpoint` (its
    /// `description` or DEF name). Default: the format's first.
    /// Cameras do not change a dataset: any of them renders it.
    #[arg(long, value_name = "NAME")]
    camera: Option<String>,
    /// The scene of a glTF file holding several, by name or index (default: the file's
    /// default scene). A dataset renders only against the scene it was traced from.
    #[arg(long, value_name = "NAME|INDEX")]
    gltf_scene: Option<String>,
}

impl DefineArgs {
    /// The parameters as given, `(NAME, VALUE)` (what a cluster worker is sent).
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    pub fn pairs(&self) -> &[(String, String)] {
        &self.define
    }

    /// The glTF scene chosen, if any (what a cluster worker is sent with the parameters).
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    pub fn gltf_scene(&self) -> Option<&str> {
        self.gltf_scene.as_deref()
    }

    /// What a cluster worker loads its scene with: the parameters `pairs` (as
    /// [`DefineArgs::pairs`] gave them) and the glTF scene (a worker needs no camera).
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    pub fn for_worker(pairs: Vec<(String, String)>, gltf_scene: Option<String>) -> Self {
        DefineArgs { define: pairs, camera: None, gltf_scene }
    }

    fn options(&self) -> LoadOptions {
        LoadOptions {
            defines: self.define.clone(),
            camera: self.camera.clone(),
            gltf_scene: self.gltf_scene.clone(),
        }
    }
}

/// `NAME=VALUE`, NAME of letters, digits and `_` (what a `$NAME` in a scene can refer to).
fn parse_define(s: &str) -> Result<(String, String)> {
    let Some((name, value)) = s.split_once('=') else { bail!("expected NAME=VALUE, got \"{s}\"") };
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        bail!("parameter name \"{name}\" must be letters, digits and _ (as in $NAME)");
    }
    Ok((name.to_string(), value.to_string()))
}

/// Loads a scene description from a file, or a built-in scene by its label.
pub fn load_description(spec: &str, defines: &DefineArgs) -> Result<SceneDescription> {
    if spec == BUILTIN_CORNELL {
        if !defines.define.is_empty() {
            bail!("-D gives parameters of a scene file; {BUILTIN_CORNELL} has none");
        }
        if defines.camera.is_some() || defines.gltf_scene.is_some() {
            bail!(
                "--camera and --gltf-scene choose within a scene file; {BUILTIN_CORNELL} has one camera and one scene"
            );
        }
        return Ok(cornell_box());
    }
    if is_builtin(spec) {
        bail!("there is no built-in scene '{spec}' (built-in scenes: {})", BUILTINS.join(", "));
    }
    opticks_io::output_paths::check_input_file(Path::new(spec), "a scene file")?;
    let loaded = opticks_io::scene_formats::load_scene_with(Path::new(spec), &defines.options())?;
    for w in &loaded.warnings {
        crate::output::warning(&w.to_string());
    }
    Ok(loaded.description)
}

/// Loads and validates a scene (builds its BVH).
pub fn load_scene(spec: &str, defines: &DefineArgs) -> Result<Scene> {
    build_scene(spec, &load_description(spec, defines)?)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defines_are_name_value_pairs() {
        assert_eq!(parse_define("spp=16").unwrap(), ("spp".into(), "16".into()));
        assert_eq!(parse_define("a_1=x=y").unwrap(), ("a_1".into(), "x=y".into()));
        assert_eq!(parse_define("e=").unwrap(), ("e".into(), String::new()));
        for bad in ["novalue", "=3", "a-b=1", "$a=1"] {
            assert!(parse_define(bad).is_err(), "{bad}");
        }
    }
}
