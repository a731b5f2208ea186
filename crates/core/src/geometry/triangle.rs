//! The scene's triangle record: one vertex and two edges, what light sampling (a point uniform
//! on the triangle), shading (the geometric normal, barycentrics of a stored point) and the
//! fingerprints read. Scenes store them in scene order ([`crate::scene::Scene::triangles`]);
//! lights refer to them by index.

use crate::math::Vec3;

/// A triangle as stored for sampling and shading: v0 and two edges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// First vertex.
    pub v0: Vec3,
    /// v1 − v0.
    pub e1: Vec3,
    /// v2 − v0.
    pub e2: Vec3,
}

impl Triangle {
    /// The triangle of `positions` with vertex indices `t` (which must be in range).
    #[inline]
    pub fn from_indices(positions: &[Vec3], t: [u32; 3]) -> Triangle {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        Triangle { v0: a, e1: b - a, e2: c - a }
    }
    /// `p` (a point on or next to the triangle, e.g. `origin + t·dir` of a hit) moved onto the
    /// triangle's plane: the point at its barycentrics, computed from the vertex and the edges.
    /// A hit point is then as exact as the vertices are: on a wall at x = 0 its x is 0, where
    /// `origin + t·dir` carries the rounding error of the ray's origin and length (≈ 1e-4 in a
    /// scene measured in millimetres), larger than [`super::offset_ray_origin`]'s offset near
    /// the coordinate origin, so rays leaving such a wall hit it again. A degenerate triangle
    /// leaves `p` as it is.
    #[inline]
    pub fn snap(&self, p: Vec3) -> Vec3 {
        let d = p - self.v0;
        let (d00, d01, d11) = (self.e1.dot(self.e1), self.e1.dot(self.e2), self.e2.dot(self.e2));
        let (d20, d21) = (d.dot(self.e1), d.dot(self.e2));
        let denom = d00 * d11 - d01 * d01;
        if !(denom > 0.0) {
            return p;
        }
        let b1 = (d11 * d20 - d01 * d21) / denom;
        let b2 = (d00 * d21 - d01 * d20) / denom;
        let q = self.point(b1, b2);
        if q.is_finite() { q } else { p }
    }

    /// Point at barycentrics (b1, b2).
    #[inline]
    pub fn point(&self, b1: f32, b2: f32) -> Vec3 {
        self.v0 + b1 * self.e1 + b2 * self.e2
    }
    /// Unit geometric normal (e1 × e2, counter-clockwise front).
    #[inline]
    pub fn normal(&self) -> Vec3 {
        self.e1.cross(self.e2).normalize()
    }
    /// Area.
    #[inline]
    pub fn area(&self) -> f32 {
        0.5 * self.e1.cross(self.e2).length()
    }
    /// Barycentrics (b1, b2) of the point of the triangle's plane nearest to `p` (so a stored
    /// position, which does not record where on its triangle it lies, gives them back).
    #[inline]
    pub fn barycentrics(&self, p: Vec3) -> (f32, f32) {
        let d = p - self.v0;
        let (d00, d01, d11) = (self.e1.dot(self.e1), self.e1.dot(self.e2), self.e2.dot(self.e2));
        let (d20, d21) = (d.dot(self.e1), d.dot(self.e2));
        let inv = 1.0 / (d00 * d11 - d01 * d01);
        ((d11 * d20 - d01 * d21) * inv, (d00 * d21 - d01 * d20) * inv)
    }
}
