//! Vector maths: a re-export of glam plus the few types a renderer adds on top of it
//! (an orthonormal [`Frame`], the [`Rgb`] alias, and octahedral unit-vector encoding).

mod frame;
mod octahedral;

pub use frame::Frame;
pub use glam::{Mat3, Mat4, Vec2, Vec3, Vec3A, Vec4, vec2, vec3};
pub use octahedral::{decode_unit_vector, encode_unit_vector};

/// Linear-sRGB (Rec. 709 primaries) triple: radiance, power, albedo or a path weight.
pub type Rgb = Vec3;

/// Luminance of a linear-sRGB colour (Rec. 709 weights).
#[inline]
pub fn luminance(c: Rgb) -> f32 {
    0.212_671 * c.x + 0.715_160 * c.y + 0.072_169 * c.z
}
