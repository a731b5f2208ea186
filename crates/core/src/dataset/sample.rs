//! The stored path vertex: 32 bytes, plain old data, written to disk as is (little endian).

use crate::math::{Rgb, Vec3, decode_unit_vector, encode_unit_vector};
use bytemuck::{Pod, Zeroable};

/// Bit set in [`Sample::prim`] for a light's emission vertex y0 (the path's start on an area
/// light), which sensors see as emitted radiance rather than reflected light.
pub const EMISSION_FLAG: u32 = 1 << 31;

/// One stored path vertex (the thesis's *sample*): where the light arrived, from where, on which
/// triangle (which gives the normal and the material), and its weight β. The light it came from
/// is stored once per [`super::Chunk`]. 32 bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct Sample {
    /// World-space position of the vertex.
    pub position: [f32; 3],
    /// Octahedral-encoded unit direction toward the previous path vertex (where light came from).
    pub from_dir: u32,
    /// Triangle index in the scene; [`EMISSION_FLAG`] marks an emission vertex.
    pub prim: u32,
    /// Path weight β (RGB), the thesis's energy modifier.
    pub beta: [f32; 3],
}

const _: () = assert!(std::mem::size_of::<Sample>() == 32);

impl Sample {
    /// A reflection vertex: light arrived at `position` on triangle `prim` from direction `from`.
    #[inline]
    pub fn scattered(position: Vec3, from: Vec3, prim: u32, beta: Rgb) -> Self {
        Sample {
            position: position.to_array(),
            from_dir: encode_unit_vector(from),
            prim,
            beta: beta.to_array(),
        }
    }

    /// An emission vertex y0 on triangle `prim` of an area light (β = 1 by construction).
    #[inline]
    pub fn emitted(position: Vec3, prim: u32) -> Self {
        Sample { position: position.to_array(), from_dir: 0, prim: prim | EMISSION_FLAG, beta: [1.0; 3] }
    }

    /// Whether this is an emission vertex.
    #[inline]
    pub fn is_emission(&self) -> bool {
        self.prim & EMISSION_FLAG != 0
    }

    /// Triangle index without the flag bit.
    #[inline]
    pub fn triangle(&self) -> u32 {
        self.prim & !EMISSION_FLAG
    }

    /// Position as a vector.
    #[inline]
    pub fn position(&self) -> Vec3 {
        Vec3::from_array(self.position)
    }

    /// Unit direction toward where the light came from.
    #[inline]
    pub fn from_dir(&self) -> Vec3 {
        decode_unit_vector(self.from_dir)
    }

    /// β as a colour.
    #[inline]
    pub fn beta(&self) -> Rgb {
        Rgb::from_array(self.beta)
    }
}
