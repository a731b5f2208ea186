//! Rays, hits, surface normals, the scene's [`Triangle`] record and robust ray origins.
//!
//! Self-intersection is avoided the way Wächter & Binder describe in *Ray Tracing Gems* ch. 6
//! ("A Fast and Robust Method for Avoiding Self-Intersection"): the origin is pushed off the
//! surface along the geometric normal by a few ULPs of its own coordinates, so the offset is
//! right at any distance from the world origin and needs no scene-dependent epsilon.

mod triangle;

pub use triangle::Triangle;

use crate::math::{Frame, Vec3};

/// A ray with a bounded extent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin.
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
    /// Far end of the segment (`f32::INFINITY` for an unbounded ray).
    pub t_max: f32,
}

/// Closest intersection of a ray with the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray.
    pub t: f32,
    /// Triangle index in the scene.
    pub prim: u32,
    /// Hit point.
    pub position: Vec3,
    /// Unit geometric normal of the triangle (front side, not flipped toward the ray).
    pub normal: Vec3,
}

/// The two normals at a surface point: the triangle's geometric normal (which decides the
/// surface's sides, emission and ray offsets) and the shading normal the BSDF is oriented by
/// (interpolated vertex normals; equal to the geometric one on faceted meshes) — and, for a
/// BSDF that depends on the azimuth (anisotropic roughness), the tangent its frame follows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceNormals {
    /// Unit geometric normal (front side, not flipped toward any ray).
    pub geometric: Vec3,
    /// Unit shading normal, on the geometric normal's side of the surface.
    pub shading: Vec3,
    /// The shading frame's x axis: ∂p/∂u made orthogonal to `shading` and unit (Mitsuba's
    /// `sh_frame.s`), set only where the material is anisotropic and the triangle has texture
    /// coordinates (`crate::scene::Scene::normals_at`); `None` elsewhere, where the frame is
    /// [`Frame::from_normal`] of `shading` (what Mitsuba's `coordinate_system` gives a mesh
    /// without texture coordinates, and what an isotropic BSDF cannot tell from any other).
    pub tangent: Option<Vec3>,
}

impl SurfaceNormals {
    /// A faceted point: the shading normal is the geometric one.
    #[inline]
    pub fn flat(n: Vec3) -> Self {
        SurfaceNormals { geometric: n, shading: n, tangent: None }
    }

    /// The shading frame: around `shading`, its x axis `tangent` where one is set.
    #[inline]
    pub fn frame(&self) -> Frame {
        self.frame_of(self.shading)
    }

    /// [`SurfaceNormals::frame`] around `n` (the shading normal or its negation).
    #[inline]
    pub fn frame_of(&self, n: Vec3) -> Frame {
        match self.tangent {
            None => Frame::from_normal(n),
            Some(s) => Frame::with_tangent(n, s),
        }
    }

    /// Whether the shading normal is the geometric one (then nothing about shading normals
    /// applies and every result is bit-identical to a mesh without normals).
    #[inline]
    pub fn is_flat(&self) -> bool {
        self.geometric == self.shading
    }
}

/// Moves `p` (on a surface of geometric normal `n`) off the surface toward the side that
/// `dir` leaves into, so a ray from the result does not hit the surface it starts on.
#[inline]
pub fn offset_ray_origin(p: Vec3, n: Vec3, dir: Vec3) -> Vec3 {
    let n = if n.dot(dir) < 0.0 { -n } else { n };
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let of_i = (n * INT_SCALE).as_ivec3();
    // Wrapping: `-0.0`'s bits are `i32::MIN`, and a step away from zero then wraps to a NaN's
    // bits; such a coordinate is below `ORIGIN`, so `pick` discards the stepped value anyway
    // (what release builds always did; an overflow-checked build panicked).
    let step = |x: f32, o: i32| {
        let bits = x.to_bits() as i32;
        f32::from_bits(bits.wrapping_add(if x < 0.0 { o.wrapping_neg() } else { o }) as u32)
    };
    let p_i = Vec3::new(step(p.x, of_i.x), step(p.y, of_i.y), step(p.z, of_i.z));
    let pick = |x: f32, xi: f32, nx: f32| if x.abs() < ORIGIN { x + FLOAT_SCALE * nx } else { xi };
    Vec3::new(pick(p.x, p_i.x, n.x), pick(p.y, p_i.y, n.y), pick(p.z, p_i.z, n.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_moves_to_the_requested_side_at_any_scale() {
        let n = Vec3::new(0.0, 1.0, 0.0);
        for base in [0.0f32, 1e-3, 1.0, 1e3, 1e5] {
            for p in [Vec3::new(base, base, base), Vec3::new(-base, -base, base)] {
                let up = offset_ray_origin(p, n, Vec3::Y);
                let down = offset_ray_origin(p, n, -Vec3::Y);
                assert!(up.y > p.y && down.y < p.y, "p={p:?} up={up:?} down={down:?}");
                // The push is tiny compared to the coordinate.
                assert!((up.y - p.y).abs() <= 1e-4 * p.y.abs().max(1.0));
            }
        }
    }

    /// Issue 26: `-0.0`'s bits are `i32::MIN`; stepping them by a negative normal component
    /// overflowed in an overflow-checked build (this test's dev profile).
    #[test]
    fn offset_of_negative_zero_does_not_overflow() {
        let z = Vec3::new(-0.0, -0.0, -0.0);
        for n in [Vec3::new(0.0, -1.0, 0.0), Vec3::new(-0.6, -0.8, 0.0), Vec3::new(0.0, 0.6, -0.8)] {
            for dir in [n, -n] {
                let o = offset_ray_origin(z, n, dir);
                assert!(o.is_finite() && (o - z).dot(dir) > 0.0, "n={n:?} dir={dir:?} o={o:?}");
            }
        }
        // Other inputs are unchanged: the step of a coordinate far from 0 is a few ulps.
        let o = offset_ray_origin(Vec3::new(-2.0, 3.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::Y);
        assert_eq!((o.x, o.y), (-2.0, f32::from_bits(3.0f32.to_bits() + 256)));
    }
}
