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

/// Asks the CPU to start loading the cache line of `value` (a hint: no effect on any result).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
#[allow(unsafe_code)]
pub fn prefetch<T>(value: &T) {
    use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
    // SAFETY: a prefetch is only a hint: it reads nothing into the program and cannot fault,
    // and the pointer comes from a live reference. SSE is part of the x86_64 baseline.
    unsafe { _mm_prefetch::<_MM_HINT_T0>((value as *const T).cast::<i8>()) }
}

/// Elsewhere a prefetch is nothing.
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
pub fn prefetch<T>(_: &T) {}
