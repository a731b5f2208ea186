//! The second step of the glTF pipeline: the scene chosen, its nodes placed in the world (their
//! transforms multiplied down the tree), and each node's mesh primitives baked to world-space
//! [`MeshDesc`]s, their materials converted on first use ([`MaterialTable`]).

use super::Report;
use super::buffers;
use super::materials::MaterialTable;
use crate::scene_formats::SceneFileError;
use ::gltf::mesh::Mode;
use opticks_core::math::{Mat4, Vec2, Vec3};
use opticks_core::scene::{AreaEmission, MeshDesc, SceneDescription};

/// The root nodes to load: those of the scene `wanted` names (by name or index), else of the
/// default scene, else of the first; with no scene at all, every root node (a warning).
pub(super) fn scene_roots<'a>(
    doc: &'a ::gltf::Document,
    wanted: Option<&str>,
    report: &mut Report,
) -> Result<Vec<::gltf::Node<'a>>, SceneFileError> {
    let chosen = match wanted {
        None => doc.default_scene().or_else(|| doc.scenes().next()),
        Some(wanted) => Some(
            choose_scene(doc, wanted).map_err(|m| report.invalid(format!("--gltf-scene {wanted:?}"), m))?,
        ),
    };
    Ok(match chosen {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    if let Some(x) = is_child.get_mut(c.index()) {
                        *x = true;
                    }
                }
            }
            if doc.nodes().len() > 0 {
                report.warn("scenes", "the file has no scene; every root node is loaded");
            }
            doc.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    })
}

/// No scene of the document has the name or index asked for; `scenes` lists those it has
/// (index, and quoted name if any).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
struct NoSuchScene {
    scenes: Vec<String>,
}

impl std::fmt::Display for NoSuchScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.scenes.is_empty() {
            write!(f, "no scene of that name or index: the file has no scenes")
        } else {
            write!(f, "no scene of that name or index (the file's scenes: {})", self.scenes.join(", "))
        }
    }
}

/// The scene `wanted` names: a scene's `name`, else its index. The error lists the scenes.
fn choose_scene<'a>(doc: &'a ::gltf::Document, wanted: &str) -> Result<::gltf::Scene<'a>, NoSuchScene> {
    if let Some(s) = doc.scenes().find(|s| s.name() == Some(wanted)) {
        return Ok(s);
    }
    if let Some(s) = wanted.parse::<usize>().ok().and_then(|i| doc.scenes().nth(i)) {
        return Ok(s);
    }
    let scenes = doc
        .scenes()
        .map(|s| match s.name() {
            Some(n) => format!("{} ({n:?})", s.index()),
            None => s.index().to_string(),
        })
        .collect();
    Err(NoSuchScene { scenes })
}

/// Every node under `roots` with its world matrix, in node-index order. A node reached twice
/// means the hierarchy is not a tree (the glTF spec forbids that; it would loop forever or
/// duplicate geometry): an error, as is a non-finite transform.
pub(super) fn place<'a>(
    doc: &'a ::gltf::Document,
    roots: Vec<::gltf::Node<'a>>,
    report: &Report,
) -> Result<Vec<(::gltf::Node<'a>, Mat4)>, SceneFileError> {
    // Depth-first, with the parent's world matrix.
    let mut reached = vec![false; doc.nodes().len()];
    let mut placed: Vec<(::gltf::Node<'_>, Mat4)> = Vec::new();
    let mut stack: Vec<(::gltf::Node<'_>, Mat4)> =
        roots.into_iter().rev().map(|n| (n, Mat4::IDENTITY)).collect();
    while let Some((node, parent)) = stack.pop() {
        let element = node_element(&node);
        let seen = reached
            .get_mut(node.index())
            .ok_or_else(|| report.invalid(element.clone(), "index out of range"))?;
        if *seen {
            return Err(report.invalid(element, "node is reached twice: the node hierarchy is not a tree"));
        }
        let m = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if !m.is_finite() {
            return Err(report.invalid(element, "transform is not finite"));
        }
        *seen = true;
        placed.push((node.clone(), m));
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c, m));
        }
    }
    placed.sort_by_key(|(n, _)| n.index());
    Ok(placed)
}

/// Adds the mesh primitives of `node` (placed by `m`) to `desc`, baked to world space: one
/// [`MeshDesc`] per `TRIANGLES` primitive, named after the node (else the mesh), `.k` appended
/// for primitive k of several. Other modes and primitives without positions are warnings;
/// skins and morph targets too (the rest pose is used).
pub(super) fn add_node_meshes(
    node: &::gltf::Node<'_>,
    m: Mat4,
    buffers: &[Vec<u8>],
    materials: &mut MaterialTable<'_>,
    desc: &mut SceneDescription,
    report: &mut Report,
) -> Result<(), SceneFileError> {
    let element = node_element(node);
    if node.skin().is_some() || node.weights().is_some() {
        report.warn(&element, "skins and morph targets are not supported; the rest pose is used");
    }
    let Some(mesh) = node.mesh() else { return Ok(()) };
    let prims: Vec<_> = mesh.primitives().collect();
    let base = node.name().or(mesh.name()).map_or_else(|| format!("node {}", node.index()), str::to_string);
    for (k, prim) in prims.iter().enumerate() {
        let pel = format!("{element}: mesh {} primitive {k}", mesh.index());
        let name = if prims.len() > 1 { format!("{base}.{k}") } else { base.clone() };
        if let Some(mesh) = primitive_mesh(prim, &pel, m, buffers, materials, desc, report)? {
            desc.meshes.push(MeshDesc { name, ..mesh });
        }
    }
    Ok(())
}

/// The mesh of one primitive (`pel` names it in messages; the caller names the mesh), `None` if
/// it is skipped (a warning).
fn primitive_mesh(
    prim: &::gltf::Primitive<'_>,
    pel: &str,
    m: Mat4,
    buffers: &[Vec<u8>],
    materials: &mut MaterialTable<'_>,
    desc: &mut SceneDescription,
    report: &mut Report,
) -> Result<Option<MeshDesc>, SceneFileError> {
    if prim.mode() != Mode::Triangles {
        report.warn(pel, format!("mode {:?} is not supported (only TRIANGLES); skipped", prim.mode()));
        return Ok(None);
    }
    let Some(pos_acc) = prim.get(&::gltf::Semantic::Positions) else {
        report.warn(pel, "has no POSITION attribute; skipped");
        return Ok(None);
    };
    let local = buffers::read_vec3(&pos_acc, buffers).map_err(|e| report.invalid(pel, e))?;
    let n = local.len();
    let mut idx = match prim.indices() {
        Some(a) => buffers::read_indices(&a, buffers).map_err(|e| report.invalid(pel, e))?,
        None => (0..u32::try_from(n).unwrap_or(u32::MAX)).collect(),
    };
    if let Some(&bad) = idx.iter().find(|&&i| i as usize >= n) {
        return Err(report.invalid(pel, format!("index {bad} is past the {n} vertices of the primitive")));
    }
    if idx.len() % 3 != 0 {
        report.warn(
            pel,
            format!("{} indices are not a multiple of 3; the last {} are ignored", idx.len(), idx.len() % 3),
        );
        idx.truncate(idx.len() - idx.len() % 3);
    }
    // A negative determinant flips the winding so front faces stay front faces.
    let flip = m.determinant() < 0.0;
    let triangles: Vec<[u32; 3]> =
        idx.chunks_exact(3).map(|t| if flip { [t[0], t[2], t[1]] } else { [t[0], t[1], t[2]] }).collect();
    let positions: Vec<Vec3> = local.iter().map(|p| m.transform_point3(Vec3::from_array(*p))).collect();
    // NORMAL: shading normals, carried to world space by the inverse transpose.
    let normals = match prim.get(&::gltf::Semantic::Normals) {
        None => Vec::new(),
        Some(acc) => {
            let local = buffers::read_vec3(&acc, buffers).map_err(|e| report.invalid(pel, e))?;
            if local.len() != n {
                return Err(
                    report.invalid(pel, format!("NORMAL has {} entries for {n} positions", local.len()))
                );
            }
            let nm = glam::Mat3::from_mat4(m).inverse().transpose();
            local.iter().map(|v| nm * Vec3::from_array(*v)).collect()
        }
    };
    let used = materials.resolve(&prim.material(), desc, report)?;
    let uvs = match used.tex_coord {
        None => Vec::new(),
        Some(set) => texture_coordinates(prim, set, n, pel, buffers, report)?,
    };
    Ok(Some(MeshDesc {
        name: String::new(),
        source: report.source(),
        positions,
        triangles,
        normals,
        material: used.index,
        emission: used.emission.map(AreaEmission::lambertian),
        uvs,
        attributes: Vec::new(),
    }))
}

/// The `TEXCOORD_set` of a primitive of `n` positions, which its material's textures read.
fn texture_coordinates(
    prim: &::gltf::Primitive<'_>,
    set: u32,
    n: usize,
    pel: &str,
    buffers: &[Vec<u8>],
    report: &Report,
) -> Result<Vec<Vec2>, SceneFileError> {
    let Some(acc) = prim.get(&::gltf::Semantic::TexCoords(set)) else {
        return Err(report.invalid(
            pel,
            format!("its material is textured through TEXCOORD_{set}, which the primitive does not have"),
        ));
    };
    let uv = buffers::read_vec2(&acc, buffers).map_err(|e| report.invalid(pel, e))?;
    if uv.len() != n {
        return Err(report.invalid(pel, format!("TEXCOORD_{set} has {} entries for {n} positions", uv.len())));
    }
    if uv.iter().flatten().any(|c| !c.is_finite()) {
        return Err(report.invalid(pel, format!("TEXCOORD_{set} has a non-finite value")));
    }
    Ok(uv.into_iter().map(Vec2::from_array).collect())
}

/// How messages name a node: its index, and its name if it has one.
pub(super) fn node_element(node: &::gltf::Node<'_>) -> String {
    match node.name() {
        Some(n) => format!("node {} ({n:?})", node.index()),
        None => format!("node {}", node.index()),
    }
}
