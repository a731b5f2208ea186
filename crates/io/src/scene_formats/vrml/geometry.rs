//! Geometry nodes → triangles in the node's local coordinates: `IndexedFaceSet` (polygons
//! triangulated by [`super::triangulate`]), `ElevationGrid`, and the tessellated primitives
//! `Box`, `Sphere`, `Cylinder`, `Cone` with VRML's default sizes.
//!
//! Every triangle is counter-clockwise seen from the side VRML calls the front (`ccw FALSE`
//! reverses the winding; primitives face outward). Normals, colours and texture coordinates are
//! read by the parser and ignored here: Opticks shades with flat geometric normals.

use super::tree::{FieldValue, Node};
use super::triangulate::triangulate;
use opticks_core::math::Vec3;
use std::f32::consts::PI;

/// Segments around the axis of a sphere, cylinder or cone (a sphere has half as many rings):
/// 64 segments keep the area within 0.2 % of the true surface.
pub const SEGMENTS: usize = 64;

/// Triangles in a node's local coordinates.
#[derive(Debug, Default)]
pub struct LocalMesh {
    /// Positions.
    pub positions: Vec<Vec3>,
    /// Counter-clockwise triangles (front = VRML's front).
    pub triangles: Vec<[u32; 3]>,
    /// VRML's `solid`: only the front is meant to be seen.
    pub solid: bool,
}

/// What became of a geometry node.
pub enum Geometry {
    /// Triangles.
    Mesh(LocalMesh),
    /// A node with no surface or one not supported; the message says which.
    Skipped(String),
}

/// Triangulates geometry node `g`; `warn` collects messages about it. Errors are invalid
/// content (an index out of range, a height count that does not match the grid).
pub fn geometry(g: &Node, warn: &mut Vec<String>) -> Result<Geometry, String> {
    let mesh = match g.type_name.as_str() {
        "IndexedFaceSet" => indexed_face_set(g, warn)?,
        "ElevationGrid" => elevation_grid(g)?,
        "Box" => boxx(g.vec3("size", [2.0, 2.0, 2.0])),
        "Sphere" => sphere(g.float("radius", 1.0)),
        "Cylinder" => {
            let (r, h) = (g.float("radius", 1.0), g.float("height", 2.0));
            let caps = [g.bool("bottom", true), g.bool("top", true)];
            revolved(&[(r, -h / 2.0), (r, h / 2.0)], g.bool("side", true), caps)
        }
        "Cone" => {
            let (r, h) = (g.float("bottomRadius", 1.0), g.float("height", 2.0));
            revolved(&[(r, -h / 2.0), (0.0, h / 2.0)], g.bool("side", true), [g.bool("bottom", true), false])
        }
        "IndexedLineSet" | "PointSet" => {
            return Ok(Geometry::Skipped(format!("`{}` has no surface: ignored", g.type_name)));
        }
        "Extrusion" | "Text" => {
            return Ok(Geometry::Skipped(format!(
                "`{}` geometry is not supported yet: ignored",
                g.type_name
            )));
        }
        other => return Ok(Geometry::Skipped(format!("`{other}` is not a geometry node: ignored"))),
    };
    Ok(Geometry::Mesh(mesh))
}

fn indexed_face_set(g: &Node, warn: &mut Vec<String>) -> Result<LocalMesh, String> {
    let points: Vec<Vec3> = match g.node("coord") {
        Some(c) if c.type_name == "Coordinate" => match c.get("point") {
            Some(FieldValue::Vec3s(p)) => p.iter().map(|&p| Vec3::from(p)).collect(),
            _ => Vec::new(),
        },
        Some(c) => return Err(format!("coord must be a Coordinate node, not `{}`", c.type_name)),
        None => Vec::new(),
    };
    let index: &[i32] = match g.get("coordIndex") {
        Some(FieldValue::Ints(v)) => v,
        _ => &[],
    };
    let mut triangles = Vec::with_capacity(index.len() / 4 + 1);
    let mut poly: Vec<u32> = Vec::with_capacity(8);
    let (mut short, mut fanned) = (0usize, 0usize);
    let n = points.len();
    let mut flush = |poly: &mut Vec<u32>, triangles: &mut Vec<[u32; 3]>| {
        if poly.len() < 3 {
            short += usize::from(!poly.is_empty());
        } else if !triangulate(&points, poly, triangles) {
            fanned += 1;
        }
        poly.clear();
    };
    for (k, &i) in index.iter().enumerate() {
        if i == -1 {
            flush(&mut poly, &mut triangles);
        } else if i < 0 || i as usize >= n {
            return Err(format!(
                "coordIndex[{k}] = {i} is out of range: the Coordinate node has {n} points (0..{})",
                n.saturating_sub(1)
            ));
        } else {
            poly.push(i as u32);
        }
    }
    flush(&mut poly, &mut triangles);
    if short > 0 {
        warn.push(format!("{short} faces with fewer than 3 corners ignored"));
    }
    if fanned > 0 {
        warn.push(format!(
            "{fanned} faces with more than {} corners were fanned, not ear-clipped (correct only if convex)",
            super::triangulate::EAR_CLIP_MAX
        ));
    }
    if !g.bool("ccw", true) {
        triangles.iter_mut().for_each(|t| t.swap(1, 2));
    }
    Ok(LocalMesh { positions: points, triangles, solid: g.bool("solid", true) })
}

fn elevation_grid(g: &Node) -> Result<LocalMesh, String> {
    let (nx, nz) = (g.int("xDimension", 0), g.int("zDimension", 0));
    let (dx, dz) = (g.float("xSpacing", 1.0), g.float("zSpacing", 1.0));
    let heights: &[f32] = match g.get("height") {
        Some(FieldValue::Floats(h)) => h,
        _ => &[],
    };
    if nx < 0 || nz < 0 {
        return Err(format!("xDimension {nx} and zDimension {nz} must not be negative"));
    }
    let (nx, nz) = (nx as usize, nz as usize);
    if nx.checked_mul(nz) != Some(heights.len()) {
        return Err(format!("height has {} values, xDimension × zDimension = {nx} × {nz}", heights.len()));
    }
    let mut positions = Vec::with_capacity(heights.len());
    for j in 0..nz {
        for i in 0..nx {
            positions.push(Vec3::new(i as f32 * dx, heights[i + j * nx], j as f32 * dz));
        }
    }
    let mut triangles = Vec::new();
    let id = |i: usize, j: usize| (i + j * nx) as u32;
    for j in 0..nz.saturating_sub(1) {
        for i in 0..nx.saturating_sub(1) {
            // Counter-clockwise seen from +y (x right, z toward the viewer).
            let q = [id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)];
            triangles.push([q[0], q[1], q[2]]);
            triangles.push([q[0], q[2], q[3]]);
        }
    }
    if !g.bool("ccw", true) {
        triangles.iter_mut().for_each(|t| t.swap(1, 2));
    }
    Ok(LocalMesh { positions, triangles, solid: g.bool("solid", true) })
}

/// Adds a triangle of a shape convex about the origin, turned to face away from it.
fn push_outward(m: &mut LocalMesh, t: [u32; 3]) {
    let [a, b, c] = t.map(|i| m.positions[i as usize]);
    let n = (b - a).cross(c - a);
    m.triangles.push(if n.dot(a + b + c) < 0.0 { [t[0], t[2], t[1]] } else { t });
}

fn boxx(size: [f32; 3]) -> LocalMesh {
    let h = Vec3::from(size) * 0.5;
    let mut m = LocalMesh { solid: true, ..Default::default() };
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = m.positions.len() as u32;
            for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = [0.0f32; 3];
                p[axis] = sign * h[axis];
                p[u] = su * h[u];
                p[v] = sv * h[v];
                m.positions.push(Vec3::from(p));
            }
            push_outward(&mut m, [base, base + 1, base + 2]);
            push_outward(&mut m, [base, base + 2, base + 3]);
        }
    }
    m
}

fn sphere(r: f32) -> LocalMesh {
    let rings = SEGMENTS / 2;
    let mut m = LocalMesh { solid: true, ..Default::default() };
    for j in 0..=rings {
        let theta = PI * j as f32 / rings as f32;
        for i in 0..SEGMENTS {
            let phi = 2.0 * PI * i as f32 / SEGMENTS as f32;
            m.positions.push(r * Vec3::new(theta.sin() * phi.sin(), theta.cos(), theta.sin() * phi.cos()));
        }
    }
    let id = |i: usize, j: usize| (j * SEGMENTS + i % SEGMENTS) as u32;
    for j in 0..rings {
        for i in 0..SEGMENTS {
            if j > 0 {
                push_outward(&mut m, [id(i, j), id(i, j + 1), id(i + 1, j)]);
            }
            if j + 1 < rings {
                push_outward(&mut m, [id(i + 1, j), id(i, j + 1), id(i + 1, j + 1)]);
            }
        }
    }
    m
}

/// A surface of revolution about y through the profile `(radius, y)` from bottom to top, with
/// optional side and caps (bottom, top). Used for cylinders and cones.
fn revolved(profile: &[(f32, f32); 2], side: bool, caps: [bool; 2]) -> LocalMesh {
    let mut m = LocalMesh { solid: true, ..Default::default() };
    let ring = |m: &mut LocalMesh, (r, y): (f32, f32)| -> u32 {
        let base = m.positions.len() as u32;
        for i in 0..SEGMENTS {
            let phi = 2.0 * PI * i as f32 / SEGMENTS as f32;
            m.positions.push(Vec3::new(r * phi.sin(), y, r * phi.cos()));
        }
        base
    };
    let next = |b: u32, i: usize| b + ((i + 1) % SEGMENTS) as u32;
    if side {
        let (lo, hi) = (ring(&mut m, profile[0]), ring(&mut m, profile[1]));
        for i in 0..SEGMENTS {
            let (a, b, c, d) = (lo + i as u32, next(lo, i), next(hi, i), hi + i as u32);
            push_outward(&mut m, [a, b, c]);
            if profile[1].0 > 0.0 {
                push_outward(&mut m, [a, c, d]);
            }
        }
    }
    for (k, &cap) in caps.iter().enumerate() {
        if cap && profile[k].0 > 0.0 {
            let b = ring(&mut m, profile[k]);
            let centre = m.positions.len() as u32;
            m.positions.push(Vec3::new(0.0, profile[k].1, 0.0));
            for i in 0..SEGMENTS {
                push_outward(&mut m, [centre, b + i as u32, next(b, i)]);
            }
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area_and_outward(m: &LocalMesh) -> (f32, bool) {
        let mut area = 0.0;
        let mut outward = true;
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let n = 0.5 * (b - a).cross(c - a);
            area += n.length();
            outward &= n.dot(a + b + c) > 0.0;
        }
        (area, outward)
    }

    #[test]
    fn primitives_face_outward_with_the_right_area() {
        let (a, out) = area_and_outward(&boxx([1.0, 2.0, 3.0]));
        assert!(out && (a - 22.0).abs() < 1e-5, "{a}");
        let (a, out) = area_and_outward(&sphere(2.0));
        assert!(out && (a / (16.0 * PI) - 1.0).abs() < 3e-3, "{a}");
        let cyl = revolved(&[(1.0, -1.0), (1.0, 1.0)], true, [true, true]);
        let (a, out) = area_and_outward(&cyl);
        assert!(out && (a / (6.0 * PI) - 1.0).abs() < 3e-3, "{a}");
        let cone = revolved(&[(1.0, -1.0), (0.0, 1.0)], true, [true, false]);
        let (a, out) = area_and_outward(&cone);
        let exact = PI * (1.0 + 5f32.sqrt());
        assert!(out && (a / exact - 1.0).abs() < 3e-3, "{a} vs {exact}");
    }

    #[test]
    fn elevation_grid_faces_up() {
        let g = Node {
            type_name: "ElevationGrid".into(),
            pos: Default::default(),
            def_name: None,
            fields: vec![
                super::super::tree::Field {
                    name: "xDimension".into(),
                    pos: Default::default(),
                    value: FieldValue::Int(3),
                },
                super::super::tree::Field {
                    name: "zDimension".into(),
                    pos: Default::default(),
                    value: FieldValue::Int(2),
                },
                super::super::tree::Field {
                    name: "height".into(),
                    pos: Default::default(),
                    value: FieldValue::Floats(vec![0.0; 6]),
                },
            ],
            proto: None,
            unexpanded: false,
            unknown: false,
        };
        let m = elevation_grid(&g).unwrap();
        assert_eq!(m.triangles.len(), 4);
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            assert!((b - a).cross(c - a).y > 0.0);
        }
    }
}
