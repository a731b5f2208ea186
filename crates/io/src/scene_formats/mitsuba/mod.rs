//! Mitsuba 3 XML scenes: the subset Opticks renders, read with Mitsuba's semantics and
//! defaults. The user-facing manual — every element and parameter, what it becomes, the Opticks
//! extensions — is `docs/scene-formats.md`, section "Mitsuba 3 XML"; keep it in step with the
//! code.
//!
//! The loader is staged like the VRML one:
//!
//! | file | job |
//! |---|---|
//! | `xml.rs` | text → records (`Element`: tag, attributes, children, each with `file:line:column`), `$name` parameters substituted, `<ref>`s resolved, ids checked |
//! | `include.rs` | `<include>` replaced by the included file's records (each keeping its own file's locations), `<path>` search folders collected |
//! | `build.rs` | records → [`SceneDescription`](opticks_core::scene::SceneDescription): the walk over the top-level elements and the state the builders share |
//! | `properties.rs`, `transform.rs` | the typed property getters every builder reads its parameters through, and `<transform>` (`spectrum.rs`, `cie.rs`: `<spectrum>` to RGB as Mitsuba's RGB variants convert it) |
//! | `sensor.rs` | `<sensor>` and `<film>` → the camera |
//! | `bsdf.rs` | `<bsdf>` → materials (`conductors.rs`: Mitsuba's named conductors in RGB, generated; `texture.rs`: `<texture>` colour parameters) |
//! | `shape.rs` | `<shape>` → meshes, with their normals (`medium.rs`: a shape's absorbing interior; the analytic sphere, disk and cylinder tessellated by [`super::tessellate`]) |
//! | `instance.rs` | `shapegroup` and `instance` shapes → world-space copies of the group's meshes |
//! | `emitter.rs` | `<emitter>` → area, point, spot, IES and directional lights |
//!
//! # Adding a plugin type
//!
//! Each stage file owns the table mapping Mitsuba type names to builder functions
//! (`bsdf::BSDF_TYPES`, `shape::SHAPE_TYPES`, `emitter::TOP_EMITTERS`, `sensor::SENSOR_TYPES`,
//! and `build::TOP_LEVEL` for the elements of `<scene>`), and its "unsupported type" error lists
//! that table. A new type is one entry and one function in that file, reading its parameters
//! with `properties::Props` (which warns about the ones nobody reads), plus its test in
//! `crates/io/tests/it/mitsuba.rs` and its row in the manual.
//!
//! # Errors
//!
//! Every error and warning is `file:line:column: <element>: message`, located at the offending
//! element or attribute value (see [`super::SceneFileError`]). Errors are raised in file order,
//! at the point where the builder reads the value, so a file with several mistakes reports the
//! first one it reaches. Physically impossible material parameters are the core's
//! [`MaterialError`](opticks_core::bsdf::MaterialError), located at the parameter it names.

mod bsdf;
mod build;
mod cie;
mod conductors;
mod emitter;
mod include;
mod instance;
mod medium;
mod principled;
mod properties;
mod sensor;
mod shape;
mod sky;
mod spectrum;
mod texture;
mod transform;
mod xml;

use super::{LoadOptions, LoadedScene, SceneFileError};
use std::path::Path;

pub use sensor::fov_to_x;

type Result<T> = std::result::Result<T, SceneFileError>;

/// Reads and loads a Mitsuba 3 XML file.
pub fn load(path: &Path, options: &LoadOptions) -> Result<LoadedScene> {
    let text = crate::input_file::read_to_string(path)
        .map_err(|source| SceneFileError::Read { path: path.to_path_buf(), source })?;
    parse(&text, path, options)
}

/// Loads a Mitsuba 3 scene from its text. `path` is used in messages and to resolve relative mesh
/// file names (against its folder); it is not read.
pub fn parse(text: &str, path: &Path, options: &LoadOptions) -> Result<LoadedScene> {
    build::build(&xml::read(text, path, options)?)
}
