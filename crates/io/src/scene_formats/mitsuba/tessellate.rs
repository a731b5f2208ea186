//! Mitsuba's analytic `sphere`, `disk` and `cylinder` as triangle meshes (Opticks renders
//! triangles only), fine enough to match the analytic shapes within the noise of a converged
//! image: 128 segments around (and 64 rings for the sphere), smooth normals on the curved
//! surfaces (the exact normal of the analytic shape at each vertex), and the radius scaled so
//! that each mesh has exactly the analytic shape's area — so an area light on it emits
//! Mitsuba's power, and the surface it offers to light is the same.
//!
//! Each function returns object-space positions, counter-clockwise triangles whose front faces
//! the way Mitsuba's normal points (outward; +z for the disk) and the vertex normals (empty for
//! the flat disk). The `to_world` and `flip_normals` of the shape are applied by
//! [`super::shape`] as for every shape.

use opticks_core::math::{Vec2, Vec3};
use std::f64::consts::PI;

/// Segments around the curved shapes.
pub const SEGMENTS: usize = 128;
/// Rings from pole to pole of the sphere.
pub const RINGS: usize = 64;

/// A mesh of object-space positions, triangles, vertex normals and Mitsuba's texture
/// coordinates of the analytic shape at each vertex.
pub type Tessellation = (Vec<Vec3>, Vec<[u32; 3]>, Vec<Vec3>, Vec<Vec2>);

/// The sphere of `radius` about `center`, with Mitsuba's (u, v) = (φ/2π, θ/π) (θ from +z, φ
/// from +x toward +y): each ring has a seam vertex at φ = 2π (u = 1, the position of φ = 0),
/// and each pole one vertex per segment (u at the segment's middle).
pub fn sphere(center: Vec3, radius: f32) -> Tessellation {
    let (n, r) = (SEGMENTS as u32, RINGS as u32);
    let mut dirs = Vec::with_capacity(2 * SEGMENTS + (RINGS - 1) * (SEGMENTS + 1));
    let mut uvs = Vec::with_capacity(dirs.capacity());
    for s in 0..SEGMENTS {
        dirs.push(glam::DVec3::Z);
        uvs.push(Vec2::new((s as f32 + 0.5) / SEGMENTS as f32, 0.0));
    }
    for ring in 1..RINGS {
        let theta = PI * ring as f64 / RINGS as f64;
        for s in 0..=SEGMENTS {
            let phi = 2.0 * PI * (s % SEGMENTS) as f64 / SEGMENTS as f64;
            dirs.push(glam::DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()));
            uvs.push(Vec2::new(s as f32 / SEGMENTS as f32, ring as f32 / RINGS as f32));
        }
    }
    let south = dirs.len() as u32;
    for s in 0..SEGMENTS {
        dirs.push(-glam::DVec3::Z);
        uvs.push(Vec2::new((s as f32 + 0.5) / SEGMENTS as f32, 1.0));
    }
    let ring = |k: u32, s: u32| n + (k - 1) * (n + 1) + s;
    let mut triangles = Vec::with_capacity(2 * SEGMENTS * (RINGS - 1));
    for s in 0..n {
        triangles.push([s, ring(1, s), ring(1, s + 1)]);
        triangles.push([south + s, ring(r - 1, s + 1), ring(r - 1, s)]);
        for k in 1..r - 1 {
            let (a, b, c, d) = (ring(k, s), ring(k + 1, s), ring(k + 1, s + 1), ring(k, s + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    let area: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| dirs[i as usize]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum();
    let k = radius as f64 * (4.0 * PI / area).sqrt();
    let positions = dirs.iter().map(|d| center + (*d * k).as_vec3()).collect();
    (positions, triangles, dirs.iter().map(|d| d.as_vec3()).collect(), uvs)
}

/// The unit disk at z = 0, facing +z (faceted), with Mitsuba's (u, v) = (r, φ/2π): a seam
/// vertex at φ = 2π and a centre vertex per segment (v at the segment's middle). The rim,
/// pushed out to keep the disk's area, has u = 1.
pub fn disk() -> Tessellation {
    let step = 2.0 * PI / SEGMENTS as f64;
    // The fan's area is SEGMENTS/2 · k² · sin(step) = π.
    let k = (step / step.sin()).sqrt();
    let n = SEGMENTS as u32;
    let mut positions = vec![Vec3::ZERO; SEGMENTS];
    let mut uvs: Vec<Vec2> =
        (0..SEGMENTS).map(|s| Vec2::new(0.0, (s as f32 + 0.5) / SEGMENTS as f32)).collect();
    for s in 0..=SEGMENTS {
        let phi = step * (s % SEGMENTS) as f64;
        positions.push(Vec3::new((k * phi.cos()) as f32, (k * phi.sin()) as f32, 0.0));
        uvs.push(Vec2::new(1.0, s as f32 / SEGMENTS as f32));
    }
    let triangles = (0..n).map(|s| [s, n + s, n + s + 1]).collect();
    (positions, triangles, Vec::new(), uvs)
}

/// The open cylinder of `radius` around the segment `p0`–`p1` (no caps), normals outward.
/// `None` if `p0` = `p1`.
pub fn cylinder(p0: glam::DVec3, p1: glam::DVec3, radius: f64) -> Option<Tessellation> {
    let axis = (p1 - p0).try_normalize()?;
    let (u, v) = axis.any_orthonormal_pair();
    let step = 2.0 * PI / SEGMENTS as f64;
    // A prism of SEGMENTS sides of width 2k·sin(step/2) has the area of the cylinder.
    let k = radius * (step / 2.0) / (step / 2.0).sin();
    let mut positions = Vec::with_capacity(2 * SEGMENTS + 2);
    let mut normals = Vec::with_capacity(2 * SEGMENTS + 2);
    let mut uvs = Vec::with_capacity(2 * SEGMENTS + 2);
    // Mitsuba's (u, v) = (φ/2π, z) in the frame of the axis (the same orthonormal basis as
    // Mitsuba's `Frame3f`), with a seam column at φ = 2π.
    for s in 0..=SEGMENTS {
        let phi = step * (s % SEGMENTS) as f64;
        let n = u * phi.cos() + v * phi.sin();
        for (end, z) in [(p0, 0.0), (p1, 1.0)] {
            positions.push((end + n * k).as_vec3());
            normals.push(n.as_vec3());
            uvs.push(Vec2::new(s as f32 / SEGMENTS as f32, z));
        }
    }
    let mut triangles = Vec::with_capacity(2 * SEGMENTS);
    for s in 0..SEGMENTS as u32 {
        let t = s + 1;
        let (a, b, c, d) = (2 * s, 2 * t, 2 * t + 1, 2 * s + 1);
        // u × v = axis: going around (u → v) with the axis up, (a, b, c) winds outward.
        triangles.push([a, b, c]);
        triangles.push([a, c, d]);
    }
    Some((positions, triangles, normals, uvs))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area_and_outwardness((p, t, n, _): &Tessellation, centre: impl Fn(Vec3) -> Vec3) -> (f64, bool) {
        let mut area = 0.0;
        let mut outward = true;
        for tri in t {
            let [a, b, c] = tri.map(|i| p[i as usize]);
            let g = (b - a).cross(c - a);
            area += 0.5 * g.length() as f64;
            let m = (a + b + c) / 3.0;
            outward &= g.dot(m - centre(m)) > 0.0;
            if !n.is_empty() {
                outward &= tri.iter().all(|&i| n[i as usize].dot(g) > 0.0);
            }
        }
        (area, outward)
    }

    #[test]
    fn areas_are_the_analytic_ones_and_fronts_face_out() {
        let s = sphere(Vec3::new(1.0, 2.0, 3.0), 2.0);
        let (a, out) = area_and_outwardness(&s, |_| Vec3::new(1.0, 2.0, 3.0));
        assert!((a / (16.0 * PI) - 1.0).abs() < 1e-5 && out, "{a}");
        assert!(s.2.iter().all(|n| (n.length() - 1.0).abs() < 1e-5));
        let d = disk();
        let (a, _) = area_and_outwardness(&d, |m| m - Vec3::Z);
        assert!((a / PI - 1.0).abs() < 1e-5, "{a}");
        let c = cylinder(glam::DVec3::ZERO, glam::DVec3::new(0.0, 0.0, 3.0), 0.5).unwrap();
        let (a, out) = area_and_outwardness(&c, |m| Vec3::new(0.0, 0.0, m.z));
        assert!((a / (2.0 * PI * 0.5 * 3.0) - 1.0).abs() < 1e-5 && out, "{a}");
        // Vertices deviate from the analytic surface by less than 0.1% of the radius.
        assert!(s.0.iter().all(|p| ((*p - Vec3::new(1.0, 2.0, 3.0)).length() / 2.0 - 1.0).abs() < 1e-3));
        assert!(cylinder(glam::DVec3::ONE, glam::DVec3::ONE, 1.0).is_none());
    }

    #[test]
    fn vertex_uvs_are_mitsubas_parameterisation_of_the_analytic_shape() {
        let phi = |x: f32, y: f32| {
            let p = y.atan2(x) / (2.0 * std::f32::consts::PI);
            if p < 0.0 { p + 1.0 } else { p }
        };
        // Away from seams and poles each vertex's (u, v) is the analytic one at its position.
        let (p, _, _, uv) = sphere(Vec3::ZERO, 1.0);
        assert_eq!(p.len(), uv.len());
        for (q, t) in p.iter().zip(&uv) {
            let q = q.normalize();
            let v = q.z.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
            assert!((t.y - v).abs() < 1e-5, "{q} {t}");
            if t.y > 0.0 && t.y < 1.0 && t.x < 1.0 {
                assert!((t.x - phi(q.x, q.y)).abs() < 1e-5, "{q} {t}");
            }
        }
        let (p, _, _, uv) = disk();
        for (q, t) in p.iter().zip(&uv).filter(|(q, _)| q.length() > 0.0) {
            assert_eq!(t.x, 1.0);
            assert!(t.y == 1.0 || (t.y - phi(q.x, q.y)).abs() < 1e-5, "{q} {t}");
        }
        let (p, _, _, uv) = cylinder(glam::DVec3::ZERO, glam::DVec3::new(0.0, 0.0, 2.0), 1.0).unwrap();
        for (q, t) in p.iter().zip(&uv) {
            assert_eq!(t.y, q.z / 2.0);
        }
        // The seam: u = 1 at the positions of u = 0.
        let (seam, start) = (uv.iter().position(|t| t.x == 1.0).unwrap(), 0);
        assert_eq!(p[seam], p[start]);
    }
}
