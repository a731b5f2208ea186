//! The scene's triangle record: one vertex and two edges, what light sampling (a point uniform
//! on the triangle), shading (the geometric normal, barycentrics of a stored point) and the
//! fingerprints read. Scenes store them in scene order ([`crate::scene::Scene::triangles`]);
//! lights refer to them by index.

use crate::math::Vec3;

/// Below this sin² of the angle between the edges at `v0` (1.8°), barycentrics are solved in
/// f64: the f32 solve's relative error grows as ε/sin², so on the slivers of a finely tessellated
/// thin cylinder (128 facets of 1.5 mm × 0.75 m: sin² ≈ 4·10⁻⁶) it put stored points centimetres
/// from their hits, bunched at a few heights (the light estimator drew such a table leg as
/// dotted lines). Above it the f32 solve is kept, so ordinary triangles keep their bits.
const ILL_CONDITIONED: f32 = 1e-3;

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
        let (b1, b2) = if denom < ILL_CONDITIONED * d00 * d11 {
            self.barycentrics_f64(p)
        } else {
            ((d11 * d20 - d01 * d21) / denom, (d00 * d21 - d01 * d20) / denom)
        };
        let q = self.point(b1, b2);
        if q.is_finite() { q } else { p }
    }

    /// Barycentrics in f64, for a triangle whose edges at `v0` are nearly parallel (a sliver:
    /// [`ILL_CONDITIONED`]), where the f32 solve loses most of its digits to cancellation.
    #[cold]
    fn barycentrics_f64(&self, p: Vec3) -> (f32, f32) {
        let (e1, e2, d) = (self.e1.as_dvec3(), self.e2.as_dvec3(), p.as_dvec3() - self.v0.as_dvec3());
        let (d00, d01, d11) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (d20, d21) = (d.dot(e1), d.dot(e2));
        let denom = d00 * d11 - d01 * d01;
        (((d11 * d20 - d01 * d21) / denom) as f32, ((d00 * d21 - d01 * d20) / denom) as f32)
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
        let denom = d00 * d11 - d01 * d01;
        if denom > 0.0 && denom < ILL_CONDITIONED * d00 * d11 {
            return self.barycentrics_f64(p);
        }
        let inv = 1.0 / denom;
        ((d11 * d20 - d01 * d21) * inv, (d00 * d21 - d01 * d20) * inv)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A facet of a thin cylinder as the tessellation makes it (radius 3 cm, 128 segments, 0.75 m
    /// tall, away from the origin): its two triangles, the second with nearly parallel edges at
    /// `v0` (the diagonal and the long side). Points on them snap to within 1 µm of themselves
    /// and their barycentrics give them back; the f32 solve alone moved them by up to ~2 cm.
    #[test]
    fn slivers_snap_points_where_they_are() {
        let (r, h, step) = (0.03f64, 0.75f64, std::f64::consts::TAU / 128.0);
        let c = glam::DVec3::new(2.622, 2.404, 0.0);
        let at =
            |s: f64, z: f64| (c + glam::DVec3::new(r * (s * step).cos(), r * (s * step).sin(), z)).as_vec3();
        let (a, b, cc, d) = (at(5.0, 0.0), at(6.0, 0.0), at(6.0, h), at(5.0, h));
        let mut worst = 0.0f32;
        for t in [Triangle { v0: a, e1: b - a, e2: cc - a }, Triangle { v0: a, e1: cc - a, e2: d - a }] {
            for i in 1..200 {
                for j in [0.05f32, 0.3, 0.6] {
                    // A point inside: along e2 by i/200, across by j of what is left.
                    let (u, v) = (j * (1.0 - i as f32 / 200.0), i as f32 / 200.0);
                    let p = t.point(u, v);
                    let q = t.snap(p);
                    worst = worst.max((q - p).length());
                    let (b1, b2) = t.barycentrics(p);
                    worst = worst.max((t.point(b1, b2) - p).length());
                }
            }
        }
        assert!(worst < 1e-6, "a point moved by {worst} m");
    }
}
