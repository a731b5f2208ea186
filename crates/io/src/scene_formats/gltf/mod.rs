//! glTF 2.0 scenes (`.gltf` with embedded base64 or external `.bin` buffers, and binary `.glb`):
//! [`load_gltf_scene`]. The JSON is parsed and validated by the `gltf` crate; buffers and
//! accessors are read here, with bounds checks ([`buffers`]).
//!
//! | glTF | Opticks |
//! |---|---|
//! | scene | the one [`LoadOptions::gltf_scene`] names (by name or index; the CLI's `--gltf-scene`), else the default `scene`, else the first; with no scene at all, every root node (warning) |
//! | node transforms | `matrix` or TRS (`T·R·S`), multiplied down the tree; vertices are baked to world space; a negative determinant flips the winding so front faces stay front faces |
//! | mesh primitives, mode `TRIANGLES` | one [`MeshDesc`] per primitive instance, named after the node (else the mesh), `.k` appended for primitive k of several; indexed (`u8`/`u16`/`u32`) and non-indexed; positions must be `VEC3`/`FLOAT` |
//! | `NORMAL` | per-vertex shading normals (`VEC3`/`FLOAT`, one per position), taken to world space by the inverse transpose of the node transform; without it the primitive is faceted (glTF's flat normals) |
//! | other primitive modes (points, lines, strips, fans) | warning, skipped |
//! | materials (metallic-roughness) | Lambert or Modified Phong, see [`materials`]; no material → glTF's default (white metal, roughness 1) |
//! | `baseColorTexture`, `metallicRoughnessTexture`, samplers, `KHR_texture_transform` | bitmap textures on kd and ks, baked per texel ([`materials`], [`textures`]); the primitive's `TEXCOORD_n` (`FLOAT`, or normalized `UNSIGNED_BYTE`/`UNSIGNED_SHORT`) become the mesh's UVs |
//! | `KHR_materials_transmission`, `KHR_materials_volume` | thin-walled or refracting glass ([`materials`]) |
//! | `emissiveFactor` × `KHR_materials_emissive_strength` | area light of that radiance in W/(m²·sr) (see [`materials`]) |
//! | `KHR_lights_punctual` point | [`PointLightDesc`] of intensity `color × intensity / 683` W/sr (glTF gives candela = lm/sr; 683 lm/W is the luminous efficacy at 555 nm, the convention glTF exporters such as Blender's use); `range` is ignored (physical inverse-square falloff) |
//! | `KHR_lights_punctual` spot | a spot [`PointLightDesc`] on the node's −Z, `color × intensity / 683` W/sr on the axis, full within `innerConeAngle` (at least [`SPOT_MIN_BEAM`] × outer) and falling **linearly in angle** to zero at `outerConeAngle` (glTF leaves the fall-off curve to the renderer); `range` ignored |
//! | `KHR_lights_punctual` directional | a [`DirectionalLightDesc`] along the node's −Z of irradiance `color × intensity / 683` W/m² (glTF gives lux), a sun covering the scene |
//! | cameras | the camera [`LoadOptions::camera`] names (its node's name or its own; the CLI's `--camera`), else the camera of the lowest-index node in the scene (orthographic ones with the film's half extents `xmag` × `ymag`, 512 pixels high); it looks down its local −Z with +Y up; `yfov` is vertical: `fov_x = 2·atan(tan(yfov/2)·W/H)`; the image is 512 pixels high and `round(512·aspectRatio)` wide (512×512 without `aspectRatio`) |
//! | skins, morph targets, animations, normal, occlusion and emissive textures | ignored (warnings for the ones that change what is seen) |
//!
//! glTF's units and axes (metres, right-handed, +Y up) are Opticks's, so nothing is converted.
//!
//! Errors name the file, and the JSON line and column for malformed JSON: unreadable file,
//! malformed JSON or GLB, a document the `gltf` crate's validation rejects (the JSON path is
//! given), a buffer whose file is missing (its path is given) or too short, an accessor outside
//! its buffer, an index past the vertex count, a non-finite transform, an invalid material value,
//! a light or camera the core's constructors refuse (in the core's words, at the element).
//! No input makes the loader panic.
//!
//! The loader is a pipeline, one module per step: [`document`] reads the file, validates it and
//! loads its buffers; [`nodes`] chooses the scene, places its nodes in the world and bakes their
//! mesh primitives; [`lights`] converts the nodes' punctual lights; [`cameras`] chooses and
//! converts the camera; [`materials`] converts the materials the primitives use (with
//! [`textures`] and [`buffers`] below them).
//!
//! [`MeshDesc`]: opticks_core::scene::MeshDesc
//! [`PointLightDesc`]: opticks_core::scene::PointLightDesc
//! [`DirectionalLightDesc`]: opticks_core::scene::DirectionalLightDesc

pub mod buffers;
pub mod cameras;
pub mod document;
pub mod lights;
pub mod materials;
pub mod nodes;
pub mod textures;

pub use cameras::DEFAULT_IMAGE_HEIGHT;
pub use lights::SPOT_MIN_BEAM;

use super::{FileLocation, LoadOptions, LoadedScene, SceneFileError};
use opticks_core::scene::{SceneDescription, Source};
use std::path::{Path, PathBuf};

/// Loads a `.gltf` or `.glb` file as a scene (see the module docs): its default scene and camera.
pub fn load_gltf_scene(path: &Path) -> Result<LoadedScene, SceneFileError> {
    load_gltf_scene_with(path, &LoadOptions::default())
}

/// Loads a `.gltf` or `.glb` file as a scene, the scene and camera chosen by `options`
/// ([`LoadOptions::gltf_scene`], [`LoadOptions::camera`]; see the module docs).
pub fn load_gltf_scene_with(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneFileError> {
    let mut report = Report::new(path);
    let file = document::open(path, &report)?;
    let doc = &file.gltf.document;
    document::warn_unsupported_extensions(doc, &mut report);

    let roots = nodes::scene_roots(doc, options.gltf_scene.as_deref(), &mut report)?;
    let placed = nodes::place(doc, roots, &report)?;

    let mut desc = SceneDescription::default();
    let folder = path.parent().unwrap_or(Path::new(""));
    let mut materials = materials::MaterialTable::new(doc, &file.buffers, folder, options.limits.max_texels);
    // The scene's cameras, in node order (one is chosen once every node is converted).
    let mut cameras = Vec::new();
    for (node, world) in &placed {
        nodes::add_node_meshes(node, *world, &file.buffers, &mut materials, &mut desc, &mut report)?;
        lights::add_node_light(node, *world, &mut desc, &report)?;
        if let Some(camera) = node.camera() {
            cameras.push(cameras::Placed { node: node.clone(), camera, world: *world });
        }
    }
    desc.camera = cameras::choose_camera(&cameras, options.camera.as_deref(), &mut report)?;

    if doc.animations().len() > 0 {
        report.warn("animations", "animations are ignored; the static pose is loaded");
    }
    if desc.meshes.is_empty() {
        report.warn("scene", "no triangle mesh was loaded");
    }
    Ok(LoadedScene { description: desc, warnings: report.warnings })
}

/// Where the loader's errors and warnings point (the file), and the warnings so far.
struct Report {
    /// The file, for error locations.
    path: PathBuf,
    /// The file as warnings and mesh sources name it.
    file_name: String,
    /// The warnings, in the order they were found.
    warnings: Vec<String>,
}

impl Report {
    /// A report on `path`, without warnings yet.
    fn new(path: &Path) -> Self {
        Report { path: path.to_path_buf(), file_name: path.display().to_string(), warnings: Vec::new() }
    }

    /// A location in the file (line and column 0: unknown).
    fn at(&self, line: u32, column: u32) -> FileLocation {
        FileLocation { file: self.path.clone(), line, column }
    }

    /// The error `message` (a text, or one of the loader's typed errors) at `element` of the
    /// file.
    fn invalid(&self, element: impl Into<String>, message: impl std::fmt::Display) -> SceneFileError {
        SceneFileError::Invalid { at: self.at(0, 0), element: element.into(), message: message.to_string() }
    }

    /// Records the warning `message` at `element` of the file.
    fn warn(&mut self, element: &str, message: impl Into<String>) {
        self.warnings.push(format!("{}: {element}: {}", self.file_name, message.into()));
    }

    /// The source every element of the file is given (glTF has no lines).
    fn source(&self) -> Source {
        Source { file: self.file_name.clone(), line: 0 }
    }
}
