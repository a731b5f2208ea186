//! The scene arguments of the commands: `SCENE` parsed into the library's typed reference
//! (`opticks_io::scene_source::SceneRef`), the `-D NAME=VALUE` parameters, `--camera` and
//! `--gltf-scene`, and the memory limits on loading, `--max-texels` and `--max-mesh-expansion`
//! ([`DefineArgs`]); loading prints the library's warnings.

use anyhow::{Result, bail};
use opticks_core::scene::{Scene, SceneDescription};
use opticks_io::scene_formats::{LoadLimits, LoadOptions};
use opticks_io::scene_source::{self, SceneRef};

/// `SCENE` on the command line: a scene file, or `builtin:NAME` ([`SceneRef::parse`]).
pub fn parse_scene(spec: &str) -> Result<SceneRef> {
    Ok(SceneRef::parse(spec)?)
}

/// The scene `SCENE…` (or `--scene` repeated) gives: none, one, or several Radiance `.rad`
/// files read in order as one scene, as `oconv` reads them ([`SceneRef::joined`]).
pub fn joined(given: &[SceneRef]) -> Result<Option<SceneRef>> {
    Ok(if given.is_empty() { None } else { Some(SceneRef::joined(given.to_vec())?) })
}

/// The options of every verb that loads a scene: `-D` parameters, which camera and which scene
/// of a file that holds several, and the bounds on what its files may allocate.
#[derive(clap::Args, Debug, Clone)]
pub struct DefineArgs {
    /// Value of the Mitsuba scene parameter `$NAME` (overrides its `<default>`), as
    /// `mitsuba -D NAME=VALUE`; repeatable. A dataset traced with parameters renders only
    /// against the same ones (its scene fingerprint says so).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    define: Vec<(String, String)>,
    /// The scene file's camera to use, by name, where it has several: a glTF camera (its
    /// node's or its own name), a Mitsuba `<sensor>` (its `id`), a VRML `Viewpoint` (its
    /// `description` or DEF name). Default: the format's first. For a Radiance `.rad` scene
    /// (which has no view): a Radiance view file, or view options (`--camera="-vp 1 2 1.5 -vd 0 1 0"`).
    /// Cameras do not change a dataset: any of them renders it.
    #[arg(long, value_name = "NAME")]
    camera: Option<String>,
    /// The scene of a glTF file holding several, by name or index (default: the file's
    /// default scene). A dataset renders only against the scene it was traced from.
    #[arg(long, value_name = "NAME|INDEX")]
    gltf_scene: Option<String>,
    /// The most texels (width × height) a texture or environment map the scene names may
    /// have, checked from the file's header before it is decoded; a count (1e8, 100M). Reading
    /// one peaks at 15–28 bytes a texel and keeps 12 (default: 8192², 805 MB kept).
    #[arg(
        long,
        value_name = "N",
        allow_hyphen_values = true,
        value_parser = opticks_io::count_text::parse_count,
        default_value_t = opticks_io::texture_file::MAX_TEXELS
    )]
    max_texels: u64,
    /// The most a `.serialized` mesh the scene names may expand: bytes its counts call for per
    /// byte of its compressed stream, checked before decompressing (real meshes: 2–10; zlib's
    /// most, on runs of one value: about 1032).
    #[arg(
        long,
        value_name = "N",
        allow_hyphen_values = true,
        value_parser = opticks_io::count_text::parse_count,
        default_value_t = opticks_io::scene_formats::serialized::MAX_EXPANSION
    )]
    max_mesh_expansion: u64,
}

/// No parameters, the default camera and scene, and the default limits ([`LoadLimits`]).
impl Default for DefineArgs {
    fn default() -> Self {
        let limits = LoadLimits::default();
        DefineArgs {
            define: Vec::new(),
            camera: None,
            gltf_scene: None,
            max_texels: limits.max_texels,
            max_mesh_expansion: limits.max_mesh_expansion,
        }
    }
}

impl DefineArgs {
    /// Refuses `--camera` for `verb`, which writes a dataset: no camera changes one.
    pub fn refuse_camera(&self, verb: &str) -> Result<()> {
        if self.camera.is_some() {
            bail!("--camera chooses a view to render; {verb} writes a dataset, which no camera changes");
        }
        Ok(())
    }

    /// The loader's options.
    pub fn options(&self) -> LoadOptions {
        LoadOptions {
            defines: self.define.clone(),
            camera: self.camera.clone(),
            gltf_scene: self.gltf_scene.clone(),
            limits: LoadLimits { max_texels: self.max_texels, max_mesh_expansion: self.max_mesh_expansion },
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

/// Loads a scene description (`opticks_io::scene_source::load`), printing its warnings.
pub fn load_description(scene: &SceneRef, defines: &DefineArgs) -> Result<SceneDescription> {
    let loaded = scene_source::load(scene, &defines.options())?;
    for w in &loaded.warnings {
        crate::output::warning(w);
    }
    Ok(loaded.description)
}

/// Loads and validates a scene (builds its BVH).
pub fn load_scene(scene: &SceneRef, defines: &DefineArgs) -> Result<Scene> {
    build_scene(scene, &load_description(scene, defines)?)
}

/// Validates a loaded description into a scene, printing what it dropped.
pub fn build_scene(scene: &SceneRef, desc: &SceneDescription) -> Result<Scene> {
    let built = scene_source::build(scene, desc)?;
    if let Some(w) = &built.warning {
        crate::output::warning(w);
    }
    Ok(built.scene)
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
