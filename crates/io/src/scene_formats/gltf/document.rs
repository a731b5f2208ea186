//! The first step of the glTF pipeline: the file read, its JSON or GLB parsed and validated
//! (with the checks the `gltf` crate misses done first), its buffers loaded, and the
//! `extensionsRequired` it lists that Opticks does not support reported.

use super::Report;
use super::buffers;
use crate::scene_formats::SceneFileError;
use std::path::Path;

/// A parsed and validated glTF file with the data of its buffers.
pub struct GltfFile {
    /// The document and, for a GLB, its binary chunk.
    pub gltf: ::gltf::Gltf,
    /// The data of every buffer, in index order.
    pub buffers: Vec<Vec<u8>>,
}

/// The extensions the loader reads; any other in `extensionsRequired` is warned about.
const SUPPORTED_EXTENSIONS: [&str; 7] = [
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_specular",
    "KHR_materials_ior",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_texture_transform",
];

/// Reads, parses and validates the glTF file at `path` and loads its buffers (external ones
/// from the file's folder). Errors name the file, and the line and column for malformed JSON.
pub(super) fn open(path: &Path, report: &Report) -> Result<GltfFile, SceneFileError> {
    let data = crate::input_file::read(path)
        .map_err(|source| SceneFileError::Read { path: path.to_path_buf(), source })?;
    let gltf = parse(&data, report)?;
    let folder = path.parent().unwrap_or(Path::new(""));
    let buffers = buffers::load_buffers(&gltf.document, gltf.blob.as_deref(), folder)
        .map_err(|(i, e)| report.invalid(format!("buffer {i}"), e))?;
    Ok(GltfFile { gltf, buffers })
}

/// The document in `data` (JSON or GLB), parsed and validated.
fn parse(data: &[u8], report: &Report) -> Result<::gltf::Gltf, SceneFileError> {
    // gltf 1.4.1 subtracts the 12-byte header from a GLB's declared length unchecked (an
    // overflow panic on a length below 12, found by fuzzing): the header is checked here first.
    if let Some(message) = bad_glb_length(data) {
        return Err(report.invalid("GLB container", message));
    }
    // Parsed without validation first: gltf-json 1.4.1's validation indexes the POSITION
    // accessor without a bounds check (a panic, found by fuzzing), so that index is checked
    // here before the crate's validation runs.
    let gltf = ::gltf::Gltf::from_slice_without_validation(data).and_then(|g| {
        let json = g.document.into_json();
        if let Some((m, p, index)) = bad_position_accessor(&json) {
            let message = format!(
                "meshes[{m}].primitives[{p}].attributes.POSITION: accessor {index} does not exist (the file has {})",
                json.accessors.len()
            );
            return Ok(Err(report.invalid("glTF document", format!("invalid glTF: {message}"))));
        }
        Ok(Ok(::gltf::Gltf { document: ::gltf::Document::from_json(json)?, blob: g.blob }))
    });
    gltf.map_err(|e| parse_error(e, report))?
}

/// The loader's error for what the `gltf` crate reports.
fn parse_error(e: ::gltf::Error, report: &Report) -> SceneFileError {
    match e {
        ::gltf::Error::Deserialize(j) => {
            // serde_json's message ends with the position, which the location already gives.
            let text = j.to_string();
            let suffix = format!(" at line {} column {}", j.line(), j.column());
            SceneFileError::Invalid {
                at: report.at(u32::try_from(j.line()).unwrap_or(0), u32::try_from(j.column()).unwrap_or(0)),
                element: "glTF JSON".into(),
                message: format!("malformed JSON: {}", text.strip_suffix(&suffix).unwrap_or(&text)),
            }
        }
        ::gltf::Error::Validation(errors) => {
            let list: Vec<String> = errors.iter().take(5).map(|(p, e)| format!("{p}: {e}")).collect();
            let more =
                if errors.len() > 5 { format!(" (and {} more)", errors.len() - 5) } else { String::new() };
            report.invalid("glTF document", format!("invalid glTF: {}{more}", list.join("; ")))
        }
        ::gltf::Error::Binary(b) => report.invalid("GLB container", format!("malformed binary glTF: {b}")),
        other => report.invalid("glTF", other.to_string()),
    }
}

/// Warns about each extension of `extensionsRequired` the loader does not support.
pub(super) fn warn_unsupported_extensions(doc: &::gltf::Document, report: &mut Report) {
    for ext in doc.extensions_required() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            report.warn("extensionsRequired", format!("{ext} is not supported; the scene may look wrong"));
        }
    }
}

/// The first mesh primitive whose POSITION attribute names a missing accessor: (mesh,
/// primitive, accessor index).
fn bad_position_accessor(json: &::gltf::json::Root) -> Option<(usize, usize, usize)> {
    use ::gltf::json::validation::Checked;
    let position = Checked::Valid(::gltf::json::mesh::Semantic::Positions);
    json.meshes.iter().enumerate().find_map(|(m, mesh)| {
        mesh.primitives.iter().enumerate().find_map(|(p, prim)| {
            let index = prim.attributes.get(&position)?.value();
            (index >= json.accessors.len()).then_some((m, p, index))
        })
    })
}

/// What is wrong with the declared length of a GLB file (`data` starting with the `glTF`
/// magic): it must cover the 12-byte header and not exceed the file.
fn bad_glb_length(data: &[u8]) -> Option<String> {
    if !data.starts_with(b"glTF") || data.len() < 12 {
        return None;
    }
    let length = u32::from_le_bytes([data[8], data[9], data[10], data[11]]) as usize;
    (length < 12 || length > data.len()).then(|| {
        format!(
            "malformed binary glTF: the header declares {length} bytes, the file has {} (at least 12)",
            data.len()
        )
    })
}
