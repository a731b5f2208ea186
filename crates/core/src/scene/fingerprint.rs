//! Content fingerprints: a dataset is only valid for the scene it was traced in.
//!
//! Two hashes (BLAKE3, 128 bits each): `geometry` covers triangles and their materials (the
//! reflectance each triangle has, not the index of its material in the scene's list) — it must
//! match for a dataset to be rendered; `lights` covers the lights' names and shapes (where and
//! how they emit, not how much) — it may change (adding a light) without invalidating the stored
//! samples of the other lights, which are checked one by one with their own shape hashes.
//!
//! Which triangles emit is deliberately not part of `geometry`: a surface that becomes a light
//! changes nothing the stored paths saw (they were reflected by the same triangles with the same
//! BSDFs), so `add-light` accepts it. New or moved triangles, or a changed reflectance, are
//! refused: they would occlude or reflect the old lights' light, and the stored paths never saw
//! them. (Datasets of format version 1 recorded an older hash that also covered emission; the
//! scene keeps it as `Scene::geometry_v1` so they still match their scene.)

/// The scene's content hashes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Fingerprint {
    /// Hash of world-space triangles and their materials (not of which emit).
    pub geometry: [u8; 16],
    /// Hash of the lights' names and shapes (not their powers).
    pub lights: [u8; 16],
}

impl Fingerprint {
    /// Short hexadecimal form of the geometry hash, for messages.
    pub fn geometry_hex(&self) -> String {
        hex(&self.geometry)
    }

    /// Short hexadecimal form of the light hash, for messages.
    pub fn lights_hex(&self) -> String {
        hex(&self.lights)
    }
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

/// Incremental hasher over little-endian numbers.
pub(crate) struct Hasher(pub(crate) blake3::Hasher);

impl Hasher {
    pub(crate) fn new(domain: &str) -> Self {
        let mut h = blake3::Hasher::new();
        h.update(domain.as_bytes());
        Hasher(h)
    }
    pub(crate) fn f32s(&mut self, v: &[f32]) {
        for x in v {
            self.0.update(&x.to_le_bytes());
        }
    }
    pub(crate) fn u32s(&mut self, v: &[u32]) {
        for x in v {
            self.0.update(&x.to_le_bytes());
        }
    }
    pub(crate) fn finish(&self) -> [u8; 16] {
        let mut out = [0u8; 16];
        out.copy_from_slice(&self.0.finalize().as_bytes()[..16]);
        out
    }
}

#[cfg(test)]
mod tests {
    use crate::bsdf::{Bsdf, Lambert};
    use crate::math::Rgb;
    use crate::scene::{Scene, demo::cornell_box};

    #[test]
    fn emission_is_not_geometry_but_reflectance_and_triangles_are() {
        let base = cornell_box();
        let fp = |d: &crate::scene::SceneDescription| Scene::build(d).unwrap().fingerprint;
        let original = fp(&base);
        let non_emitting = base.meshes.iter().position(|m| m.emission.is_none()).unwrap();

        let mut glowing = base.clone();
        glowing.meshes[non_emitting].emission = Some(crate::scene::AreaEmission::lambertian(Rgb::splat(0.5)));
        assert_eq!(fp(&glowing).geometry, original.geometry, "a surface turned light is the same geometry");
        assert_ne!(fp(&glowing).lights, original.lights, "but the lights changed");

        let mut extra_material = base.clone();
        extra_material.materials.push(extra_material.materials[0].clone());
        assert_eq!(fp(&extra_material).geometry, original.geometry, "an unused material changes nothing");

        let mut repainted = base.clone();
        let m = repainted.meshes[non_emitting].material;
        repainted.materials[m].bsdf = Bsdf::Lambert(Lambert { reflectance: Rgb::splat(0.123) });
        assert_ne!(fp(&repainted).geometry, original.geometry, "another reflectance is another scene");

        let mut moved = base.clone();
        moved.meshes[non_emitting].positions[0].x += 1e-3;
        assert_ne!(fp(&moved).geometry, original.geometry, "moved triangles are another scene");
    }
}
