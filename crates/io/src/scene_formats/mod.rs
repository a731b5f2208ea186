//! Scene files: [`load_scene`] reads a file into a plain
//! [`SceneDescription`], dispatching on the extension.
//!
//! | extension | format | module |
//! |---|---|---|
//! | `.xml` | Mitsuba 3 scene (the subset documented in [`mitsuba`], plus Opticks extensions) | [`mitsuba`] |
//! | `.wrl`, `.wrz`, `.wrl.gz` | VRML97 with the Opticks physical extension (the thesis's format) | [`vrml`] |
//! | `.obj` | Wavefront OBJ with MTL materials (area lights from `Ke`), no camera | [`wavefront`] |
//! | `.gltf`, `.glb` | glTF 2.0 (meshes, metallic-roughness materials, emission, point, spot and directional lights, cameras) | [`gltf`] |
//! | `.rad` | Radiance scene description (primitives, materials, `!xform` includes; never executed) | [`radiance`] |
//!
//! The extension is matched case-insensitively; anything else is a
//! [`SceneFileError::UnsupportedExtension`].
//!
//! How OBJ/MTL and glTF map to Opticks materials and lights is in [`wavefront`], [`gltf`] and
//! `docs/scene-formats.md`.
//!
//! # Errors and warnings
//!
//! Every [`SceneFileError`] names the file, and where it applies the line, the column and the XML
//! element it is about, in the `file:line:column: <element>: message` form compilers use:
//!
//! ```text
//! scene.xml:42:5: <bsdf type="hair">: unsupported BSDF type "hair" (supported: diffuse, phong (Opticks extension), twosided, …)
//! meshes/box.obj:17: face refers to vertex 9, but the file defines only 8 vertices (mesh of <shape type="obj" id="box"> at scene.xml:30:5)
//! ```
//!
//! Things the loader can read but Opticks does not reproduce (an integrator's finite
//! `max_depth`, a non-box reconstruction filter, an unknown parameter) are not errors: they are
//! reported as human-readable lines in [`LoadedScene::warnings`], in the same format.
//!
//! # Memory limits
//!
//! A small file can describe a huge amount of data (a PNG of one colour, a zlib stream of
//! zeros), so the readers bound what they allocate from a file's own counts, before decoding,
//! by the [`LoadLimits`] in [`LoadOptions::limits`]: the texels of each texture or environment
//! map ([`LoadLimits::max_texels`]) and how far a serialized mesh may expand its compressed
//! bytes ([`LoadLimits::max_mesh_expansion`]). A file beyond a limit is an error naming the
//! file, the size found, the limit, and the CLI option that raises it (`--max-texels`,
//! `--max-mesh-expansion`).

pub mod gltf;
pub mod lights;
pub mod mesh_bytes;
pub mod mitsuba;
pub mod obj;
pub mod ply;
pub mod radiance;
pub mod serialized;
pub mod tessellate;
pub mod vrml;
pub mod wavefront;

use opticks_core::bsdf::MaterialError;
use opticks_core::scene::SceneDescription;
use std::fmt;
use std::path::{Path, PathBuf};

/// A loaded scene and what the loader had to say about it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadedScene {
    /// The scene.
    pub description: SceneDescription,
    /// Things read but not reproduced exactly, one message per line
    /// (`file:line:column: <element>: message`).
    pub warnings: Vec<String>,
}

/// Bounds on what a scene's files may make the readers allocate (see the module docs). The
/// defaults admit any real file of a reasonable size; raise them for larger ones (the CLI's
/// `--max-texels` and `--max-mesh-expansion`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadLimits {
    /// The most texels (width × height) of one texture image or environment map, checked
    /// against the file's header before any pixel is decoded. Default
    /// [`crate::texture_file::MAX_TEXELS`], 2²⁶ (8192 × 8192): 805 MB as linear `f32` RGB, and
    /// about 15–28 bytes a texel at the peak of the read (see [`crate::texture_file`]).
    pub max_texels: u64,
    /// The most bytes a `.serialized` mesh's counts may call for per byte of its compressed
    /// stream, checked before decompressing. Default [`serialized::MAX_EXPANSION`],
    /// 128 (real meshes compress 2–10 times; zlib can reach about 1032 only on runs of one byte).
    pub max_mesh_expansion: u64,
}

impl Default for LoadLimits {
    fn default() -> Self {
        LoadLimits {
            max_texels: crate::texture_file::MAX_TEXELS,
            max_mesh_expansion: serialized::MAX_EXPANSION,
        }
    }
}

/// Options for [`load_scene_with`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// Values for `$name` parameters of a Mitsuba scene, overriding its `<default>`s (like
    /// `mitsuba -Dname=value`).
    pub defines: Vec<(String, String)>,
    /// The camera to use, by name, when the file has several (the CLI's `--camera`): a glTF
    /// camera's node or camera name, a Mitsuba `<sensor>`'s `id`, a VRML `Viewpoint`'s
    /// `description` or DEF name. `None`: the format's default camera. A name the file does not have is an
    /// error listing the ones it has.
    pub camera: Option<String>,
    /// The scene to load from a file holding several (glTF's `scenes`, the CLI's
    /// `--gltf-scene`): its name, or its index. `None`: the file's default scene.
    pub gltf_scene: Option<String>,
    /// Bounds on the memory a file's own counts may ask for ([`LoadLimits`]). They do not
    /// change a scene that loads, so a dataset does not record them.
    pub limits: LoadLimits,
}

/// A position in a scene file. Displays as `file:line:column` (line and column are 1-based; a
/// zero is left out).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileLocation {
    /// The file, as the user named it (mesh files: joined to the scene file's folder).
    pub file: PathBuf,
    /// 1-based line, 0 if unknown.
    pub line: u32,
    /// 1-based column, 0 if unknown.
    pub column: u32,
}

impl fmt::Display for FileLocation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if self.line > 0 {
            write!(f, ":{}", self.line)?;
            if self.column > 0 {
                write!(f, ":{}", self.column)?;
            }
        }
        Ok(())
    }
}

/// Why a scene file cannot be loaded. The message always starts with the file (and line, column
/// and element where they apply).
#[derive(Debug, thiserror::Error)]
pub enum SceneFileError {
    /// The scene file itself cannot be read.
    #[error("{}: cannot read the scene file: {source}", .path.display())]
    Read {
        /// The scene file.
        path: PathBuf,
        /// The operating system's reason.
        #[source]
        source: std::io::Error,
    },
    /// The extension is not one [`load_scene`] knows.
    #[error(
        "{}: unsupported scene file type (supported extensions: .xml for Mitsuba 3 scenes, .wrl, .wrz and .wrl.gz for VRML97, .obj for OBJ/MTL, .gltf and .glb for glTF 2.0, .rad for Radiance)",
        .path.display()
    )]
    UnsupportedExtension {
        /// The file.
        path: PathBuf,
    },
    /// The file is not well-formed XML.
    #[error("{at}: malformed XML: {message}")]
    Xml {
        /// Where the parser gave up.
        at: FileLocation,
        /// The XML parser's message.
        message: String,
    },
    /// Well-formed XML that is not a scene this loader supports (unknown plugin, bad value,
    /// undefined `$name`, dangling reference…).
    #[error("{at}: {element}: {message}")]
    Invalid {
        /// Where.
        at: FileLocation,
        /// The element, as written: `<bsdf type="hair" id="floor">`.
        element: String,
        /// What is wrong and, where useful, what is supported.
        message: String,
    },
    /// A BSDF's parameters are physically impossible (e.g. reflectance > 1).
    #[error("{at}: {element}: invalid material: {source}")]
    Material {
        /// Where.
        at: FileLocation,
        /// The offending parameter's element, e.g. `<rgb name="reflectance">`.
        element: String,
        /// The core's reason.
        #[source]
        source: MaterialError,
    },
    /// A mesh file named by a shape cannot be read.
    #[error("{at}: {element}: cannot read mesh file {}: {source}", .mesh.display())]
    MeshFile {
        /// The shape that names the file.
        at: FileLocation,
        /// The shape element.
        element: String,
        /// The mesh file as resolved (relative to the scene file's folder).
        mesh: PathBuf,
        /// The operating system's reason.
        #[source]
        source: std::io::Error,
    },
    /// A PLY or serialized mesh file's content is wrong: the file (with the line, for text
    /// parts) and the byte offset.
    #[error("{at}: byte {offset}: {message}{}", referenced_by(.referenced_from))]
    MeshData {
        /// The mesh file, and the line for a PLY header or ASCII PLY data (else 0).
        at: FileLocation,
        /// Byte offset in the file.
        offset: u64,
        /// What is wrong.
        message: String,
        /// The scene element that loaded this mesh, and where: (`<shape ...>`, location).
        referenced_from: Option<(String, FileLocation)>,
    },
    /// An OBJ file's content is wrong.
    #[error("{at}: {message}{}", referenced_by(.referenced_from))]
    Obj {
        /// The OBJ file and line.
        at: FileLocation,
        /// What is wrong.
        message: String,
        /// The scene element that loaded this mesh, and where: (`<shape ...>`, location).
        referenced_from: Option<(String, FileLocation)>,
    },
}

fn referenced_by(r: &Option<(String, FileLocation)>) -> String {
    match r {
        Some((element, at)) => format!(" (mesh of {element} at {at})"),
        None => String::new(),
    }
}

impl SceneFileError {
    /// Where the error is, if it is at a place in a file (the OBJ file for [`Self::Obj`]).
    pub fn location(&self) -> Option<&FileLocation> {
        match self {
            SceneFileError::Read { .. } | SceneFileError::UnsupportedExtension { .. } => None,
            SceneFileError::Xml { at, .. }
            | SceneFileError::Invalid { at, .. }
            | SceneFileError::Material { at, .. }
            | SceneFileError::MeshFile { at, .. }
            | SceneFileError::MeshData { at, .. }
            | SceneFileError::Obj { at, .. } => Some(at),
        }
    }
}

/// Loads a scene file (see the table at the top of this module) with default options.
pub fn load_scene(path: &Path) -> Result<LoadedScene, SceneFileError> {
    load_scene_with(path, &LoadOptions::default())
}

/// Loads a scene file, with `$name` parameter values from `options`.
pub fn load_scene_with(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneFileError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase());
    match ext.as_deref() {
        Some("xml") => mitsuba::load(path, options),
        Some("obj") => {
            refuse_selection(path, options, "an OBJ file has no cameras and one scene")?;
            wavefront::load_obj_mtl_scene(path)
        }
        Some("gltf" | "glb") => gltf::load_gltf_scene_with(path, options),
        Some("rad") => radiance::load(path, options),
        _ if vrml::is_vrml_path(path) => {
            refuse_selection(
                path,
                options,
                "a VRML file has one scene (cameras are not chosen by name yet)",
            )?;
            vrml::load(path)
        }
        _ => Err(SceneFileError::UnsupportedExtension { path: path.to_path_buf() }),
    }
}

/// An error when `options` choose a camera or a scene that a format without them cannot give
/// (silently ignoring `--camera` would render the wrong view).
fn refuse_selection(path: &Path, options: &LoadOptions, why: &str) -> Result<(), SceneFileError> {
    let chosen = match (&options.camera, &options.gltf_scene) {
        (Some(c), _) => format!("--camera {c:?}"),
        (None, Some(s)) => format!("--gltf-scene {s:?}"),
        (None, None) => return Ok(()),
    };
    Err(SceneFileError::Invalid {
        at: FileLocation { file: path.to_path_buf(), line: 0, column: 0 },
        element: chosen,
        message: format!("cannot be used here: {why}"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_extension_names_the_file_and_the_supported_ones() {
        let e = load_scene(Path::new("dir/scene.ply")).unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with("dir/scene.ply: unsupported scene file type"), "{msg}");
        for ext in [".xml", ".wrl", ".wrz", ".wrl.gz", ".obj", ".gltf", ".glb", ".rad"] {
            assert!(msg.contains(ext), "{ext}: {msg}");
        }
        assert!(matches!(load_scene(Path::new("noext")), Err(SceneFileError::UnsupportedExtension { .. })));
    }

    #[test]
    fn locations_display_like_a_compiler() {
        let l = FileLocation { file: "a/b.xml".into(), line: 4, column: 7 };
        assert_eq!(l.to_string(), "a/b.xml:4:7");
        assert_eq!(FileLocation { column: 0, ..l.clone() }.to_string(), "a/b.xml:4");
        assert_eq!(FileLocation { line: 0, ..l }.to_string(), "a/b.xml");
    }
}
