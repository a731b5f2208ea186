//! The fingerprint stage of [`super::Scene::build`]: the content hashes of a built scene — the
//! geometry (every triangle's corners, material and shading normals, not which emit), the one
//! format-version-1 datasets recorded, each light's shape and the light table's — computed
//! from the flattened triangles and the built lights. What the hashes mean and why is
//! documented with [`super::Fingerprint`].

use super::Fingerprint;
use super::fingerprint::{Hasher, light_shape, material_hash, material_v2};
use super::meshes::{Flat, NO_SHADING};
use super::textures::MaterialTextures;
use crate::bsdf::Material;
use crate::light::Light;
use crate::texture::{ColourSlot, Texture};
use std::sync::Arc;

/// A built scene's hashes.
pub(super) struct Hashes {
    /// Geometry and lights.
    pub fingerprint: Fingerprint,
    /// The geometry hash as format-version-1 datasets recorded it.
    pub geometry_v1: [u8; 16],
    /// Per light, the hash of where and how it emits.
    pub light_shapes: Vec<[u8; 16]>,
}

/// The hash of `material` with its `textures`: [`material_hash`] for an untextured one (so
/// untextured scenes keep their fingerprints), else that hash followed by every texture's slot
/// and numbers.
fn textured_material_hash(material: &Material, textures: &[(ColourSlot, Arc<Texture>)]) -> [u8; 16] {
    let plain = material_hash(material);
    if textures.is_empty() {
        return plain;
    }
    let mut h = Hasher::new("opticks textured material");
    h.0.update(&plain);
    for (slot, t) in textures {
        h.0.update(slot.name().as_bytes());
        h.f32s(&t.fingerprint_words());
    }
    h.finish()
}

/// The hashes of a scene of `materials`, triangles `flat` and `lights`.
pub(super) fn fingerprints(
    materials: &[Material],
    textures: &MaterialTextures,
    flat: &Flat,
    lights: &[Light],
) -> Hashes {
    // The geometry fingerprint covers each triangle's corners and material, not whether it
    // emits: emission is the lights' business (each light has its own shape hash), so a
    // surface may become a light without invalidating the samples of the others.
    let mut geo = Hasher::new("opticks geometry v2");
    let material_hashes: Vec<[u8; 16]> =
        materials.iter().zip(textures).map(|(m, t)| textured_material_hash(m, t)).collect();
    // The hash datasets of format version 1 recorded (it also covered emitter assignment).
    let mut geo_v1 = Hasher::new("opticks geometry v1");
    for (i, [a, b, c]) in flat.vertices.iter().enumerate() {
        let corners = [a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z];
        geo.f32s(&corners);
        geo.0.update(&material_hashes[flat.material_of[i] as usize]);
        geo_v1.f32s(&corners);
        geo_v1.u32s(&[flat.material_of[i], flat.light_of[i]]);
        let shading = flat.shading_of[i];
        if shading != NO_SHADING {
            // Shading normals change what every stored vertex reflects; a version-1
            // dataset (traced before they were honoured) must not match such a scene.
            let normals = flat.shading_normals[shading as usize].map(|n| n.to_array()).concat();
            geo.f32s(&normals);
            geo_v1.f32s(&normals);
        }
        if !textures[flat.material_of[i] as usize].is_empty() {
            // A textured material's colours depend on where on the triangle a point is.
            let uv =
                flat.uvs.get(flat.uv_of[i] as usize).map_or(Vec::new(), |t| t.map(|v| v.to_array()).concat());
            geo.f32s(&uv);
            geo_v1.f32s(&uv);
        }
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
    }
}
