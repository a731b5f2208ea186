//! Wavefront OBJ scenes with MTL materials: [`load_obj_mtl_scene`] is what
//! [`load_scene`](super::load_scene) runs for a `.obj` file. The OBJ text is read by
//! [`super::obj`], the one OBJ reader (Mitsuba's `<shape type="obj">` uses it too); this module
//! makes meshes of its groups and materials and converts the MTL libraries ([`mtl`]).
//!
//! # OBJ statements
//!
//! | statement | handling |
//! |---|---|
//! | `v x y z [w] [r g b]` | a position (`w` and vertex colours ignored) |
//! | `vn x y z` | a vertex normal, used by corners `v//vn` and `v/vt/vn` as the shading normal (see [`super::obj`] for corners without one) |
//! | `f i j k …` | a polygon, fanned into triangles `(i, j, k), (i, k, l), …`; corners `v`, `v/vt`, `v//vn`, `v/vt/vn` (`vt` ignored); 1-based, negative = relative to the latest vertex; forward references accepted |
//! | `o name`, `g name …` | starts a new group: later faces go to a mesh named after it |
//! | `usemtl name` | later faces use that material |
//! | `mtllib a.mtl …` | material libraries, relative to the OBJ file's folder (a name with spaces is tried whole first) |
//! | `#…` | comment (to the end of the line) |
//! | `vt`, `vp`, `s`, `l`, `p`, curves, anything else | ignored |
//!
//! Every distinct (group, material) pair becomes one
//! [`MeshDesc`], in order of first appearance, holding only the
//! vertices its faces use. A mesh is named after its group (`o`/`g`, else the file stem); a group
//! split by several `usemtl` gets `group[material]` names. Winding is kept as written (front face
//! counter-clockwise); no camera and no point lights come from an OBJ file (the CLI's
//! `--eye`/`--target` give a camera).
//!
//! # MTL → Opticks materials
//!
//! | MTL | Opticks |
//! |---|---|
//! | `Kd` (1 or 3 numbers, linear RGB) | diffuse reflectance kd; absent → 0.5 |
//! | `Ks` | specular reflectance ks; absent or 0 in every channel → [`Lambert`]`(kd)` |
//! | `Ns` | exponent n of [`ModifiedPhong`](opticks_core::bsdf::ModifiedPhong)`(kd, ks, n)` (absent → 0) |
//! | kd + ks > 1 in a channel | both scaled by 1 / max(kd + ks) (hue kept), with a warning |
//! | `Ke` > 0 and no `map_Ke` | the mesh is an area light of **radiance Ke in W/(m²·sr)**, emitting from its front (counter-clockwise) side only, as every Opticks area light |
//! | `map_Ke` | warning; the material does not emit (Ke is then only the texture's multiplier) |
//! | `map_Kd`, `map_Ks`, `bump`, other maps | warning; textures are not supported, constants are used |
//! | `d` < 1, `Tr` > 0 | warning; surfaces are opaque |
//! | `Ka`, `illum`, `Ni`, `Tf`, `sharpness` | ignored (`illum` does not choose the model: `Ks` does) |
//! | unknown statements (e.g. the PBR extension `Pr`, `Pm`) | warning once per file |
//!
//! **Every material is two-sided**: OBJ has no notion of sidedness, and closed and open models
//! alike are usually meant to look the same from both sides. (Emission stays one-sided.)
//!
//! Missing things are warnings, not errors, so a model still loads: an `mtllib` file that cannot
//! be read, a `usemtl` name no library defines, and faces before any `usemtl` all get the
//! `default` material, a two-sided Lambertian of albedo 0.5. Errors name the file and line: a
//! malformed number or colour, a non-finite coordinate, a face with fewer than 3 corners, a bad
//! index, a negative reflectance, a Phong exponent beyond the core's maximum.
//!
//! # Why a hand-written reader and not `tobj`
//!
//! `tobj` 4 was checked (the tests use it as an independent reader to cross-check this one): it reads `Kd`, `Ks`, `Ns` and leaves `Ke` in an
//! untyped map, which would do; but its errors are bare enum values (`FaceVertexOutOfBounds`,
//! `PositionParseError`, `MaterialParseError`) that name neither the file nor the line, it accepts
//! `nan`/`inf` coordinates silently, a missing `.mtl` makes it fail the whole load or drop the
//! materials without saying which file, and it allocates per line. The reader ([`super::obj`]) is
//! one pass over the bytes that allocates nothing per vertex or face line, so every message has
//! `file:line` and a million triangles load in a fraction of a second.

pub mod mtl;

use super::obj::{ObjFile, parse_obj_file};
use super::{FileLocation, LoadedScene, SceneFileError};
use opticks_core::bsdf::{Bsdf, Lambert, Material};
use opticks_core::math::Rgb;
use opticks_core::scene::{AreaEmission, MeshDesc, SceneDescription, Source};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The faces sharing a group and a material name: one mesh.
struct Slot {
    group: String,
    material: Option<String>,
    /// Line of the `usemtl` that named the material (for the "no such material" warning).
    usemtl_line: u32,
    /// Its runs of faces ([`ObjFile::runs`] indices), in file order.
    runs: Vec<usize>,
}

/// What the OBJ text says, before materials are resolved.
struct ParsedObj {
    obj: ObjFile,
    slots: Vec<Slot>,
}

/// An error in an OBJ or MTL file, at `file:line`.
pub(super) fn err(file: &Path, line: u32, message: String) -> SceneFileError {
    SceneFileError::Obj {
        at: FileLocation { file: file.to_path_buf(), line, column: 0 },
        message,
        referenced_from: None,
    }
}

/// Reads the OBJ text and groups its runs of faces by (group, material), in order of first
/// appearance; faces outside any group belong to `default_group`.
fn parse(data: &[u8], file: &Path, default_group: &str) -> Result<ParsedObj, SceneFileError> {
    let obj = parse_obj_file(data, false).map_err(|e| err(file, e.line, e.message))?;
    let mut slots: Vec<Slot> = Vec::new();
    let mut slot_of: HashMap<(String, Option<String>), usize> = HashMap::new();
    for (i, run) in obj.runs.iter().enumerate() {
        let group = run.group.clone().unwrap_or_else(|| default_group.to_string());
        let material = run.material.as_ref().map(|m| m.0.clone());
        let s = *slot_of.entry((group.clone(), material.clone())).or_insert_with(|| {
            let usemtl_line = run.material.as_ref().map_or(0, |m| m.1);
            slots.push(Slot { group, material, usemtl_line, runs: Vec::new() });
            slots.len() - 1
        });
        slots[s].runs.push(i);
    }
    Ok(ParsedObj { obj, slots })
}

/// The `default` material: two-sided Lambertian of albedo 0.5.
fn default_material() -> Material {
    Material {
        name: "default".into(),
        bsdf: Bsdf::Lambert(Lambert { reflectance: Rgb::splat(mtl::DEFAULT_KD) }),
        two_sided: true,
    }
}

/// Reads the material libraries an OBJ names. A library that cannot be read is a warning.
fn read_libraries(
    obj_file: &Path,
    mtllibs: &[(String, u32)],
    warnings: &mut Vec<String>,
) -> Result<Vec<(PathBuf, mtl::MtlLibrary)>, SceneFileError> {
    let folder = obj_file.parent().unwrap_or(Path::new(""));
    let mut libs = Vec::new();
    for (arg, line) in mtllibs {
        // A file name may contain spaces: try the whole argument, then its words.
        let whole = folder.join(arg);
        let names: Vec<String> = if whole.is_file() || !arg.contains(char::is_whitespace) {
            vec![arg.clone()]
        } else {
            arg.split_whitespace().map(str::to_string).collect()
        };
        for name in names {
            let path = folder.join(&name);
            match crate::input_file::read(&path) {
                Ok(data) => {
                    let lib = mtl::parse_mtl(&data, &path)?;
                    libs.push((path, lib));
                }
                Err(e) => warnings.push(format!(
                    "{}:{line}: mtllib {name}: cannot read {}: {e}; its materials are replaced by the default material (two-sided Lambertian, albedo 0.5)",
                    obj_file.display(),
                    path.display()
                )),
            }
        }
    }
    Ok(libs)
}

/// Loads an OBJ file and its MTL libraries as a scene (see the module docs).
pub fn load_obj_mtl_scene(path: &Path) -> Result<LoadedScene, SceneFileError> {
    let data = crate::input_file::read(path)
        .map_err(|source| SceneFileError::Read { path: path.to_path_buf(), source })?;
    let stem = path.file_stem().map_or_else(|| "mesh".to_string(), |s| s.to_string_lossy().into_owned());
    let parsed = parse(&data, path, &stem)?;
    let mut warnings = Vec::new();
    let libs = read_libraries(path, &parsed.obj.mtllibs, &mut warnings)?;
    for (_, lib) in &libs {
        warnings.extend(lib.warnings.iter().cloned());
    }

    let mut desc = SceneDescription::default();
    // Material name → (index in desc.materials, emission); None = the default material.
    let mut resolved: HashMap<Option<String>, (usize, Option<Rgb>)> = HashMap::new();
    let mut default_index: Option<usize> = None;
    let source_file = path.display().to_string();
    let mut remap = parsed.obj.vertices.remap_table();
    // Groups split by several materials get `group[material]` names.
    let mut materials_per_group: HashMap<&str, usize> = HashMap::new();
    for s in &parsed.slots {
        *materials_per_group.entry(s.group.as_str()).or_default() += 1;
    }

    for slot in &parsed.slots {
        let (material, emission) = match resolved.get(&slot.material) {
            Some(&r) => r,
            None => {
                let found = slot.material.as_ref().and_then(|name| {
                    libs.iter()
                        .find_map(|(p, lib)| lib.materials.iter().find(|m| &m.name == name).map(|m| (p, m)))
                });
                let r = match found {
                    Some((lib_path, m)) => {
                        let c = mtl::convert(m, lib_path)?;
                        warnings.extend(c.warnings);
                        desc.materials.push(c.material);
                        (desc.materials.len() - 1, c.emission)
                    }
                    None => {
                        if let Some(name) = &slot.material {
                            warnings.push(format!(
                                "{}:{}: usemtl {name}: no material of that name in the material libraries; the default material (two-sided Lambertian, albedo 0.5) is used",
                                path.display(),
                                slot.usemtl_line
                            ));
                        }
                        let index = *default_index.get_or_insert_with(|| {
                            desc.materials.push(default_material());
                            desc.materials.len() - 1
                        });
                        (index, None)
                    }
                };
                resolved.insert(slot.material.clone(), r);
                r
            }
        };
        // Compact the vertices this mesh uses, in order of first use.
        let runs: Vec<&[[u32; 3]]> = slot.runs.iter().map(|&r| parsed.obj.run_triangles(r)).collect();
        let mesh = parsed.obj.vertices.gather(&runs, &mut remap);
        let name = match (&slot.material, materials_per_group.get(slot.group.as_str())) {
            (Some(m), Some(&n)) if n > 1 => format!("{}[{m}]", slot.group),
            _ => slot.group.clone(),
        };
        desc.meshes.push(MeshDesc {
            name,
            source: Source { file: source_file.clone(), line: 0 },
            positions: mesh.positions,
            triangles: mesh.triangles,
            normals: mesh.normals,
            material,
            emission: emission.map(AreaEmission::lambertian),
            uvs: Vec::new(),
            attributes: Vec::new(),
        });
    }
    if desc.meshes.is_empty() {
        warnings.push(format!("{}: the file has no faces", path.display()));
    } else if desc.meshes.iter().all(|m| m.emission.is_none()) {
        warnings.push(format!(
            "{}: no material has an emission (Ke): the scene has no light of its own",
            path.display()
        ));
    }
    Ok(LoadedScene { description: desc, warnings })
}
