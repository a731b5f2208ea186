//! Radiance scene descriptions (`.rad`): primitives, `!xform` includes and a view, read with
//! Radiance's semantics; nothing in a file is ever executed. The manual — each primitive and
//! material, what it becomes and what is approximated — is `docs/scene-formats.md`, section
//! "Radiance"; keep it in step with the code.
//!
//! Staged like the other loaders:
//!
//! | file | job |
//! |---|---|
//! | `lexer.rs` | text → located records: primitives (`modifier type identifier` and the three argument lists) and `!command` lines |
//! | `xform.rs` | an `xform` command's arguments → a similarity transform, the renaming options and the files (read, never run) |
//! | `build.rs` | records → [`SceneDescription`](opticks_core::scene::SceneDescription): modifiers resolved as Radiance resolves them (latest definition, `void`, `alias`), materials mapped to the core's, surfaces tessellated ([`super::tessellate`]), `mesh` primitives read from their `.obj` files (`build/mesh.rs`, through [`super::obj`]), includes followed |
//! | `sky/` | `!gensky` and `!gendaylit` interpreted: the sun's position, the CIE and Perez skies' brightness (`skybright.cal`, `perezlum.cal`), the levels; rasterised into environment lights by `build/sources.rs`; the CIE general skies as an API |
//! | `view.rs` | `--camera`'s Radiance view (a view file or `-vp …` options) → the camera; without one, a view of the bounding box |
//!
//! Every error is `file:line:column: type identifier: message` (or `!command` for a command),
//! located at the primitive's first word.

mod build;
mod lexer;
pub mod sky;
mod view;
mod xform;

pub use sky::cie::{CieGeneralSky, SkyModel};

use super::{FileLocation, LoadOptions, LoadedScene, SceneFileError};
use std::path::{Path, PathBuf};

/// An error at `at` about `element` (`polygon floor`, `!gensky`).
fn err(at: &FileLocation, element: &str, message: String) -> SceneFileError {
    SceneFileError::Invalid { at: at.clone(), element: element.to_string(), message }
}

/// Loads a Radiance scene file and what it includes. `options.camera` is a Radiance view: a
/// view file, or view options when it starts with `-`; without it, a view of the bounding box
/// (`docs/scene-formats.md`, "Views and the camera"). `--gltf-scene` is refused.
pub fn load(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneFileError> {
    load_files(&[path.to_path_buf()], options)
}

/// Loads several Radiance files as one scene, read in order as `oconv a.rad b.rad` reads them:
/// a modifier defined in one file is defined in the files after it, and a later definition of
/// a name replaces the earlier one from there on, as within one file. Otherwise as [`load`];
/// `paths` is not empty.
pub fn load_files(paths: &[PathBuf], options: &LoadOptions) -> Result<LoadedScene, SceneFileError> {
    let path = paths.first().map_or(Path::new(""), PathBuf::as_path);
    if let Some(s) = &options.gltf_scene {
        return Err(err(
            &FileLocation { file: path.to_path_buf(), line: 0, column: 0 },
            &format!("--gltf-scene {s:?}"),
            "cannot be used here: a Radiance file has one scene".into(),
        ));
    }
    let mut loaded = build::build(paths)?;
    let camera = match &options.camera {
        None => view::default_view(&loaded.description),
        Some(spec) => Some(camera_of(spec, path)?),
    };
    loaded.description.camera = camera;
    Ok(loaded)
}

/// The camera `--camera` gives: view options (starting with `-`) or a view file.
fn camera_of(spec: &str, scene: &Path) -> Result<opticks_core::scene::CameraDesc, SceneFileError> {
    let here = FileLocation { file: scene.to_path_buf(), line: 0, column: 0 };
    let element = format!("--camera {spec:?}");
    let text = if spec.trim_start().starts_with('-') {
        spec.to_string()
    } else {
        let data = crate::input_file::read(Path::new(spec))
            .map_err(|e| err(&here, &element, format!("cannot read the Radiance view file: {e}")))?;
        String::from_utf8_lossy(&data).into_owned()
    };
    view::parse_view(&text).map_err(|m| err(&here, &element, format!("Radiance view: {m}")))
}
