//! The fingerprint stage of [`super::Scene::build`]: the content hashes of a built scene — the
//! geometry (every triangle's corners, material and shading normals, not which emit), the one
//! format-version-1 datasets recorded, each light's shape and the light table's, and one hash
//! per mesh and per used material ([`super::objects`]) — computed from the flattened triangles
//! and the built lights. What the hashes mean and why is
//! documented with [`super::Fingerprint`].

use super::Fingerprint;
use super::fingerprint::{Hasher, light_shape, material_hash, material_v2};
use super::meshes::{Flat, NO_SHADING};
use super::objects::{ObjectHash, ObjectKind};
use super::textures::{Bound, MaterialTextures};
use crate::bsdf::Material;
use crate::light::Light;
use std::ops::Range;

/// A built scene's hashes.
pub(super) struct Hashes {
    /// Geometry and lights.
    pub fingerprint: Fingerprint,
    /// The geometry hash as format-version-1 datasets recorded it.
    pub geometry_v1: [u8; 16],
    /// Per light, the hash of where and how it emits.
    pub light_shapes: Vec<[u8; 16]>,
    /// Per mesh, then per used material: its hash.
    pub objects: Vec<ObjectHash>,
}

/// The hash of `material` with its `textures`: [`material_hash`] for an untextured one (so
/// untextured scenes keep their fingerprints), else that hash followed by every texture's slot
/// and numbers.
fn textured_material_hash(material: &Material, textures: &[Bound]) -> [u8; 16] {
    let plain = material_hash(material);
    if textures.is_empty() {
        return plain;
    }
    let mut h = Hasher::new("opticks textured material");
    h.0.update(&plain);
    for b in textures {
        h.0.update(b.slot.name().as_bytes());
        b.texture.fingerprint_with(&mut |words| h.f32s(words));
    }
    h.finish()
}

/// Appends `xs` (little-endian `f32`s) to both byte streams: the version-2 and the version-1
/// geometry hash take the same shading normals, texture coordinates and attribute values.
fn push_f32s(outs: [&mut Vec<u8>; 2], xs: &[f32]) {
    for out in outs {
        for x in xs {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
}

/// The hashes of a scene of `materials` with their `textures`, triangles `flat` and `lights`;
/// `meshes` names each mesh and the range of `flat`'s triangles it became.
pub(super) fn fingerprints(
    materials: &[Material],
    textures: &MaterialTextures,
    anisotropic: &[bool],
    flat: &Flat,
    lights: &[Light],
    meshes: &[(&str, Range<usize>)],
) -> Hashes {
    // The geometry fingerprint covers each triangle's corners and material, not whether it
    // emits: emission is the lights' business (each light has its own shape hash), so a
    // surface may become a light without invalidating the samples of the others.
    let mut geo = Hasher::new("opticks geometry v2");
    let material_hashes: Vec<[u8; 16]> =
        materials.iter().zip(textures).map(|(m, t)| textured_material_hash(m, t)).collect();
    // The hash datasets of format version 1 recorded (it also covered emitter assignment).
    let mut geo_v1 = Hasher::new("opticks geometry v1");
    let mut objects = Vec::with_capacity(meshes.len() + materials.len());
    // The meshes' ranges cover the triangles in order (every triangle comes from a mesh).
    debug_assert_eq!(meshes.iter().map(|m| m.1.len()).sum::<usize>(), flat.vertices.len());
    // The bytes are gathered in blocks and handed to the hashers whole: BLAKE3 digests a
    // stream the same however it is cut, and a 36-byte update per corner triple cost more in
    // per-call overhead than the hashing itself (callgrind, bunny-box: ~2/3 of the hashing).
    let (mut bytes, mut bytes_v1) = (Vec::with_capacity(BLOCK + 128), Vec::with_capacity(BLOCK + 128));
    for (name, range) in meshes {
        let mut mesh = Hasher::new("opticks mesh v1");
        for i in range.clone() {
            for p in flat.vertices[i] {
                for x in p.to_array() {
                    bytes.extend_from_slice(&x.to_le_bytes());
                }
            }
            bytes_v1.extend_from_slice(&bytes[bytes.len() - 36..]);
            bytes.extend_from_slice(&material_hashes[flat.material_of[i] as usize]);
            bytes_v1.extend_from_slice(&flat.material_of[i].to_le_bytes());
            bytes_v1.extend_from_slice(&flat.light_of[i].to_le_bytes());
            let shading = flat.shading_of[i];
            if shading != NO_SHADING {
                // Shading normals change what every stored vertex reflects; a version-1
                // dataset (traced before they were honoured) must not match such a scene.
                let normals = flat.shading_normals[shading as usize].map(|n| n.to_array());
                push_f32s([&mut bytes, &mut bytes_v1], normals.as_flattened());
            }
            let bound = &textures[flat.material_of[i] as usize];
            if !bound.is_empty() {
                // A textured material's colours depend on where on the triangle a point is.
                if let Some(uv) = flat.uvs.get(flat.uv_of[i] as usize) {
                    push_f32s([&mut bytes, &mut bytes_v1], uv.map(|v| v.to_array()).as_flattened());
                }
                // ... and on the values of the mesh attributes its textures read.
                for k in bound.iter().filter_map(|b| b.attribute) {
                    if let Some(c) = flat.attributes[k].corners(i as u32) {
                        push_f32s([&mut bytes, &mut bytes_v1], c.map(|v| v.to_array()).as_flattened());
                    }
                }
            }
            if anisotropic[flat.material_of[i] as usize] {
                // An anisotropic BSDF's frame follows the triangle's ∂p/∂u, so its texture
                // coordinates orient what every stored vertex on it reflects. The tag refuses
                // datasets traced before the frame followed them (`fingerprint` module docs).
                if let Some(uv) = flat.uvs.get(flat.uv_of[i] as usize) {
                    bytes.extend_from_slice(b"dp/du");
                    bytes_v1.extend_from_slice(b"dp/du");
                    push_f32s([&mut bytes, &mut bytes_v1], uv.map(|v| v.to_array()).as_flattened());
                }
            }
            if bytes.len() >= BLOCK {
                flush(&mut bytes, &mut [&mut geo, &mut mesh]);
                flush(&mut bytes_v1, &mut [&mut geo_v1]);
            }
        }
        flush(&mut bytes, &mut [&mut geo, &mut mesh]);
        objects.push(ObjectHash { kind: ObjectKind::Mesh, name: name.to_string(), hash: mesh.finish() });
    }
    flush(&mut bytes_v1, &mut [&mut geo_v1]);
    let mut used = vec![false; materials.len()];
    for &m in &flat.material_of {
        used[m as usize] = true;
    }
    for (m, hash) in materials.iter().zip(&material_hashes).zip(&used).filter(|p| *p.1).map(|p| p.0) {
        objects.push(ObjectHash { kind: ObjectKind::Material, name: m.name.clone(), hash: *hash });
    }
    for m in materials {
        geo_v1.0.update(material_v2(m).as_bytes());
    }
    let light_shapes: Vec<[u8; 16]> = lights.iter().map(|l| light_shape(l, &flat.triangles)).collect();
    let mut lit = Hasher::new("opticks lights v1");
    for (l, shape) in lights.iter().zip(&light_shapes) {
        lit.0.update(l.name().as_bytes());
        lit.0.update(shape);
    }
    Hashes {
        fingerprint: Fingerprint { geometry: geo.finish(), lights: lit.finish() },
        geometry_v1: geo_v1.finish(),
        light_shapes,
        objects,
    }
}

/// Bytes gathered before they are hashed.
const BLOCK: usize = 64 * 1024;

/// Hands `bytes` to every hasher of `to` and empties it.
fn flush(bytes: &mut Vec<u8>, to: &mut [&mut Hasher]) {
    for h in to {
        h.0.update(bytes);
    }
    bytes.clear();
}
