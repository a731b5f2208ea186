//! Analytic shapes as triangle meshes (Opticks renders triangles only): Mitsuba's `sphere`,
//! `disk` and `cylinder`, and Radiance's cones and rings (a cylinder is a cone of equal radii,
//! a disk a ring without a hole). Fine enough to match the analytic shapes within the noise of a converged
//! image: 128 segments around (and 64 rings for the sphere), smooth normals on the curved
//! surfaces (the exact normal of the analytic shape at each vertex), and the radius scaled so
//! that each mesh has exactly the analytic shape's area — so an area light on it emits
//! Mitsuba's power, and the surface it offers to light is the same.
//!
//! A sphere that only emits needs less: its power is exact at any grid (the area is), and what
//! is left of the grid is the intensity in each direction — the radiance × the projected area,
//! ½ Σ A_f |n_f · d| for a convex mesh, which a coarse grid makes anisotropic. [`LIGHT_SPHERE`]
//! is the coarsest grid of the ladder 8 × 4 … 128 × 64 that keeps it within 0.1 % of πr² in
//! every direction (0.09 %; 48 × 24: 0.16 %, the fine grid: 0.02 %): a tenth of a 1 % meter's
//! target, for a quarter of the fine grid's triangles (3,968, not 16,128) — Radiance's point
//! source, a small `light` sphere, was a BVH of 16,128 triangles in a scene of a few.
//!
//! Each function returns positions, counter-clockwise triangles whose front faces the way the
//! analytic normal points (outward; +z for the disk, the given normal for a ring) and the
//! vertex normals (empty for the flat disk and ring). A Mitsuba shape's `to_world` and
//! `flip_normals` are applied by its loader as for every shape; Radiance's shapes are built
//! from their world-space parameters, and its inward variants (`bubble`, `cup`, `tube`) flip
//! the result ([`flip`]).

use opticks_core::math::{Vec2, Vec3};
use std::f64::consts::PI;

/// Segments around the curved shapes.
pub const SEGMENTS: usize = 128;
/// Rings from pole to pole of the sphere.
pub const RINGS: usize = 64;
/// The grid (segments around, rings from pole to pole) of a sphere that emits: its intensity
/// within 0.1 % in every direction (the module's docs).
pub const LIGHT_SPHERE: (usize, usize) = (64, 32);

/// A mesh of object-space positions, triangles, vertex normals and Mitsuba's texture
/// coordinates of the analytic shape at each vertex.
pub type Tessellation = (Vec<Vec3>, Vec<[u32; 3]>, Vec<Vec3>, Vec<Vec2>);

/// The sphere of `radius` about `center` on the fine grid ([`SEGMENTS`] × [`RINGS`]): see
/// [`sphere_grid`].
pub fn sphere(center: Vec3, radius: f32) -> Tessellation {
    sphere_grid(center, radius, (SEGMENTS, RINGS))
}

/// The sphere of `radius` about `center` on a grid of `segments` around and `rings` from pole
/// to pole (each at least 3 and 2), with Mitsuba's (u, v) = (φ/2π, θ/π) (θ from +z, φ from +x
/// toward +y): each ring has a seam vertex at φ = 2π (u = 1, the position of φ = 0), and each
/// pole one vertex per segment (u at the segment's middle).
pub fn sphere_grid(center: Vec3, radius: f32, (segments, rings): (usize, usize)) -> Tessellation {
    assert!(segments >= 3 && rings >= 2, "a sphere's grid needs 3 segments and 2 rings");
    let (n, r) = (segments as u32, rings as u32);
    let mut dirs = Vec::with_capacity(2 * segments + (rings - 1) * (segments + 1));
    let mut uvs = Vec::with_capacity(dirs.capacity());
    for s in 0..segments {
        dirs.push(glam::DVec3::Z);
        uvs.push(Vec2::new((s as f32 + 0.5) / segments as f32, 0.0));
    }
    for ring in 1..rings {
        let theta = PI * ring as f64 / rings as f64;
        for s in 0..=segments {
            let phi = 2.0 * PI * (s % segments) as f64 / segments as f64;
            dirs.push(glam::DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()));
            uvs.push(Vec2::new(s as f32 / segments as f32, ring as f32 / rings as f32));
        }
    }
    let south = dirs.len() as u32;
    for s in 0..segments {
        dirs.push(-glam::DVec3::Z);
        uvs.push(Vec2::new((s as f32 + 0.5) / segments as f32, 1.0));
    }
    let ring = |k: u32, s: u32| n + (k - 1) * (n + 1) + s;
    let mut triangles = Vec::with_capacity(2 * segments * (rings - 1));
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
    cone(p0, p1, radius, radius)
}

/// The open cone (a frustum) around the segment `p0`–`p1`, of radius `r0` at `p0` and `r1` at
/// `p1` (no caps; one of them may be 0, an apex), smooth normals outward (perpendicular to the
/// slanted side). The radii are scaled as the cylinder's, so a cylinder's area is exact and a
/// cone's within 2·10⁻⁴. `None` if `p0` = `p1` or both radii are 0.
pub fn cone(p0: glam::DVec3, p1: glam::DVec3, r0: f64, r1: f64) -> Option<Tessellation> {
    let h = (p1 - p0).length();
    let axis = (p1 - p0).try_normalize()?;
    if r0 <= 0.0 && r1 <= 0.0 {
        return None;
    }
    let (u, v) = axis.any_orthonormal_pair();
    let step = 2.0 * PI / SEGMENTS as f64;
    // A prism of SEGMENTS sides of width 2k·sin(step/2) has the area of the cylinder (written
    // as it always was, so that Mitsuba's cylinders keep their bits).
    let k = |radius: f64| radius * (step / 2.0) / (step / 2.0).sin();
    let mut positions = Vec::with_capacity(2 * SEGMENTS + 2);
    let mut normals = Vec::with_capacity(2 * SEGMENTS + 2);
    let mut uvs = Vec::with_capacity(2 * SEGMENTS + 2);
    // Mitsuba's (u, v) = (φ/2π, z) in the frame of the axis (the same orthonormal basis as
    // Mitsuba's `Frame3f`), with a seam column at φ = 2π.
    for s in 0..=SEGMENTS {
        let phi = step * (s % SEGMENTS) as f64;
        let n = u * phi.cos() + v * phi.sin();
        // The side's normal leans toward the narrow end; a cylinder's is the radial one as is.
        let normal = if r0 == r1 { n } else { (n * h - axis * (r1 - r0)).normalize() };
        for (end, r, z) in [(p0, r0, 0.0), (p1, r1, 1.0)] {
            positions.push((end + n * k(r)).as_vec3());
            normals.push(normal.as_vec3());
            uvs.push(Vec2::new(s as f32 / SEGMENTS as f32, z));
        }
    }
    let mut triangles = Vec::with_capacity(2 * SEGMENTS);
    for s in 0..SEGMENTS as u32 {
        let t = s + 1;
        let (a, b, c, d) = (2 * s, 2 * t, 2 * t + 1, 2 * s + 1);
        // u × v = axis: going around (u → v) with the axis up, (a, b, c) winds outward. At an
        // apex one of the two triangles has no area and is left out.
        if r0 > 0.0 {
            triangles.push([a, b, c]);
        }
        if r1 > 0.0 {
            triangles.push([a, c, d]);
        }
    }
    Some((positions, triangles, normals, uvs))
}

/// The flat ring (annulus) about `center` facing `normal`, between radii `r0` ≥ 0 (the hole)
/// and `r1` > `r0`, faceted: two triangles per segment (one where `r0` = 0), the radii
/// pushed out as the disk's so that the area π(r1² − r0²) is exact. No UVs. `None` if the
/// normal is zero or the radii are not 0 ≤ `r0` < `r1`.
pub fn ring(center: glam::DVec3, normal: glam::DVec3, r0: f64, r1: f64) -> Option<Tessellation> {
    let normal = normal.try_normalize()?;
    if !(0.0 <= r0 && r0 < r1) {
        return None;
    }
    let (u, v) = normal.any_orthonormal_pair();
    let step = 2.0 * PI / SEGMENTS as f64;
    // The fan's area is SEGMENTS/2 · k² · sin(step) · (r1² − r0²) = π(r1² − r0²).
    let k = (step / step.sin()).sqrt();
    let mut positions = Vec::with_capacity(2 * SEGMENTS);
    for s in 0..SEGMENTS {
        let phi = step * s as f64;
        let d = u * phi.cos() + v * phi.sin();
        for r in [r0, r1] {
            positions.push((center + d * (k * r)).as_vec3());
        }
    }
    let n = SEGMENTS as u32;
    let mut triangles = Vec::with_capacity(2 * SEGMENTS);
    for s in 0..n {
        let t = (s + 1) % n;
        // u × v = normal: (inner s, outer s, outer t) winds counter-clockwise seen from it.
        let (a, b, c, d) = (2 * s, 2 * s + 1, 2 * t + 1, 2 * t);
        triangles.push([a, b, c]);
        if r0 > 0.0 {
            triangles.push([a, c, d]);
        }
    }
    Some((positions, triangles, Vec::new(), Vec::new()))
}

/// Turns a tessellation inside out: the winding reversed and the normals negated (Radiance's
/// `bubble`, `cup` and `tube`).
pub fn flip(t: &mut Tessellation) {
    for tri in &mut t.1 {
        tri.swap(1, 2);
    }
    for n in &mut t.2 {
        *n = -*n;
    }
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
        // A frustum of radii 1 and 0.5 over height 2, and a cone with its apex at p1.
        let (p0, p1) = (glam::DVec3::new(1.0, 0.0, 0.0), glam::DVec3::new(1.0, 0.0, 2.0));
        for (r0, r1) in [(1.0, 0.5), (0.7, 0.0), (0.0, 0.3)] {
            let c = cone(p0, p1, r0, r1).unwrap();
            let (a, out) = area_and_outwardness(&c, |m| Vec3::new(1.0, 0.0, m.z));
            let slant = (4.0f64 + (r1 - r0) * (r1 - r0)).sqrt();
            let exact = PI * (r0 + r1) * slant;
            assert!((a / exact - 1.0).abs() < 2e-4 && out, "{r0} {r1}: {a} {exact}");
            assert!(c.1.iter().all(|t| t.iter().all(|&i| (i as usize) < c.0.len())));
        }
        assert!(cone(p0, p1, 0.0, 0.0).is_none());
        let r = ring(glam::DVec3::new(0.0, 1.0, 0.0), glam::DVec3::new(0.0, 2.0, 0.0), 0.5, 1.5).unwrap();
        let (a, _) = area_and_outwardness(&r, |m| m - Vec3::Y);
        assert!((a / (PI * 2.0) - 1.0).abs() < 1e-5, "{a}");
        let g = |t: [u32; 3]| {
            let [a, b, c] = t.map(|i| r.0[i as usize]);
            (b - a).cross(c - a)
        };
        assert!(r.1.iter().all(|&t| g(t).y > 0.0), "the ring faces its normal");
        assert_eq!(ring(glam::DVec3::ZERO, glam::DVec3::Z, 0.0, 1.0).unwrap().1.len(), SEGMENTS);
        assert!(ring(glam::DVec3::ZERO, glam::DVec3::Z, 1.0, 1.0).is_none());
        let mut s = sphere(Vec3::ZERO, 1.0);
        flip(&mut s);
        let (_, out) = area_and_outwardness(&s, |m| m * 2.0);
        assert!(out, "flipped: every front and normal faces the centre");
    }

    /// The projected area ½ Σ A_f |n_f · d| of a convex mesh about its centre in direction `d`
    /// over that of the analytic sphere, πr², minus 1: its intensity's error as a light.
    fn projected_area_error((p, t, _, _): &Tessellation, radius: f64, d: glam::DVec3) -> f64 {
        let twice: f64 = t
            .iter()
            .map(|tri| {
                let [a, b, c] = tri.map(|i| p[i as usize].as_dvec3());
                (b - a).cross(c - a).dot(d).abs()
            })
            .sum();
        0.25 * twice / (PI * radius * radius) - 1.0
    }

    /// Directions on a Fibonacci spiral, the poles and the equator at a vertex's and a
    /// segment's middle azimuth (where a grid's projection is extreme).
    fn directions() -> Vec<glam::DVec3> {
        let n = 2000;
        let golden = PI * (3.0 - 5f64.sqrt());
        let mut d: Vec<glam::DVec3> = (0..n)
            .map(|i| {
                let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
                let (s, phi) = ((1.0 - z * z).sqrt(), golden * i as f64);
                glam::DVec3::new(s * phi.cos(), s * phi.sin(), z)
            })
            .collect();
        let mid = PI / LIGHT_SPHERE.0 as f64;
        d.extend([glam::DVec3::Z, glam::DVec3::X, glam::DVec3::new(mid.cos(), mid.sin(), 0.0)]);
        d
    }

    /// A light sphere's grid against the analytic sphere (Radiance's `sphere` is analytic): its
    /// power exact (the area, to f32 rounding), its intensity within 0.1 % in every direction,
    /// the vertices on the sphere within 0.5 % of r; and the next coarser grid of the ladder
    /// misses 0.1 % (so LIGHT_SPHERE is the coarsest that keeps it).
    #[test]
    fn a_light_sphere_keeps_its_power_and_intensity_within_a_tenth_of_a_percent() {
        let (centre, radius) = (Vec3::new(0.0, 0.0, 3.0), 0.01);
        let s = sphere_grid(centre, radius, LIGHT_SPHERE);
        assert_eq!(s.1.len(), 2 * LIGHT_SPHERE.0 * (LIGHT_SPHERE.1 - 1));
        let (a, out) = area_and_outwardness(&s, |_| centre);
        let exact = 4.0 * PI * (radius as f64).powi(2);
        assert!((a / exact - 1.0).abs() < 1e-5 && out, "{a} {exact}");
        let worst = |s: &Tessellation| {
            directions()
                .into_iter()
                .map(|d| projected_area_error(s, radius as f64, d).abs())
                .fold(0.0, f64::max)
        };
        let w = worst(&s);
        assert!(w < 1e-3, "the light sphere's intensity is off by {:.3} % in some direction", 100.0 * w);
        assert!(s.0.iter().all(|p| ((*p - centre).length() / radius - 1.0).abs() < 5e-3));
        let coarser = worst(&sphere_grid(centre, radius, (48, 24)));
        assert!(coarser > 1e-3, "48 × 24 would do: {:.3} %", 100.0 * coarser);
        // The fine grid, for comparison: four times better.
        assert!(worst(&sphere(centre, radius)) < 0.3e-3);
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
