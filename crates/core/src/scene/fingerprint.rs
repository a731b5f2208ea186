//! Content fingerprints: a dataset is only valid for the scene it was traced in.
//!
//! Two hashes (BLAKE3, 128 bits each): `geometry` covers triangles and materials — it must match
//! for a dataset to be rendered; `lights` covers the lights' names and shapes (where and how they
//! emit, not how much) — it may change (adding a light) without invalidating the stored samples
//! of the other lights, which are checked one by one with their own shape hashes.

/// The scene's content hashes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Fingerprint {
    /// Hash of world-space triangles, their materials and emitter assignment.
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
