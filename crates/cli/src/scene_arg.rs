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

/// The `-D` option of every verb that loads a scene.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct DefineArgs {
    /// Value of the Mitsuba scene parameter `$NAME` (overrides its `<default>`), as
    /// `mitsuba -D NAME=VALUE`; repeatable. A dataset traced with parameters renders only
    /// against the same ones (its scene fingerprint says so).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    define: Vec<(String, String)>,
}

impl DefineArgs {
    /// The parameters as given, `(NAME, VALUE)` (what a cluster worker is sent).
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    pub fn pairs(&self) -> &[(String, String)] {
        &self.define
    }

    /// The parameters `pairs` (as [`DefineArgs::pairs`] gave them).
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    pub fn from_pairs(pairs: Vec<(String, String)>) -> Self {
        DefineArgs { define: pairs }
    }

    fn options(&self) -> LoadOptions {
        LoadOptions { defines: self.define.clone() }
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
