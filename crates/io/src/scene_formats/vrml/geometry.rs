//! Geometry nodes → triangles in the node's local coordinates: `IndexedFaceSet` (polygons
//! triangulated by [`super::triangulate`]), `ElevationGrid`, and the tessellated primitives
//! `Box`, `Sphere`, `Cylinder`, `Cone` with VRML's default sizes.
//!
//! Every triangle is counter-clockwise seen from the side VRML calls the front (`ccw FALSE`
//! reverses the winding; primitives face outward). Colours and texture coordinates are read by
//! the parser and ignored here.
//!
//! Shading normals ([`LocalMesh::normals`]): an `IndexedFaceSet` with a `Normal` node uses it as
//! VRML97 §6.23 says — `normalPerVertex TRUE` (default): corner k gets `vector[normalIndex[k]]`,
//! or `vector[coordIndex[k]]` without `normalIndex`; `FALSE`: face f gets
//! `vector[normalIndex[f]]`, or `vector[f]`. Without a `Normal` node, normals are generated from
//! `creaseAngle` (§4.6.3.5): a corner's normal is the area-weighted mean of the normals of the
//! faces around its point that are within `creaseAngle` of its own face; the default 0 gives a
//! faceted mesh (no normals at all, exactly as before). `Sphere`, and the sides of `Cylinder` and
//! `Cone`, get their smooth analytic normals; `Box`, caps and `ElevationGrid` stay faceted.

use super::tree::{FieldValue, Node};
use super::triangulate::triangulate;
use opticks_core::math::Vec3;
use std::f32::consts::PI;

/// Segments around the axis of a sphere, cylinder or cone (a sphere has half as many rings):
/// 64 segments keep the area within 0.2 % of the true surface.
pub const SEGMENTS: usize = 64;

/// Most face-pair comparisons `creaseAngle` normal generation may make (Σ over points of the
/// square of the number of faces at the point); beyond it the face set stays faceted.
pub const MAX_CREASE_WORK: u64 = 50_000_000;

#[cfg(test)]
thread_local! {
    /// Work counter of the tests: the face comparisons and corner look-up steps normal
    /// generation makes on this thread, so its bounds are checked as counted work, not as time.
    static STEPS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Adds `n` to the tests' work counter (nothing outside the tests).
#[inline]
fn count_steps(n: usize) {
    #[cfg(test)]
    STEPS.with(|s| s.set(s.get() + n as u64));
    #[cfg(not(test))]
    let _ = n;
}

/// Triangles in a node's local coordinates.
#[derive(Debug, Default)]
pub struct LocalMesh {
    /// Positions.
    pub positions: Vec<Vec3>,
    /// Counter-clockwise triangles (front = VRML's front).
    pub triangles: Vec<[u32; 3]>,
    /// One shading normal per position (not necessarily unit length), or empty: faceted.
    pub normals: Vec<Vec3>,
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

/// Why a geometry node's content is invalid.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GeometryError {
    /// An `IndexedFaceSet`'s `coord` is another node type.
    #[error("coord must be a Coordinate node, not `{0}`")]
    NotCoordinate(String),
    /// A `coordIndex` entry past the points (or negative other than the `-1` separator).
    #[error(
        "coordIndex[{position}] = {index} is out of range: the Coordinate node has {points} points (0..{})",
        points.saturating_sub(1)
    )]
    CoordIndex {
        /// Position in `coordIndex`.
        position: usize,
        /// The index found.
        index: i32,
        /// The Coordinate node's point count.
        points: usize,
    },
    /// An `IndexedFaceSet`'s `normal` is another node type.
    #[error("normal must be a Normal node, not `{0}`")]
    NotNormal(String),
    /// A normal index (from `normalIndex`, `coordIndex` or the face number) past the vectors.
    #[error("{field}[{position}] = {index} is out of range: the Normal node has {vectors} vectors")]
    NormalIndex {
        /// Where the index comes from: "normalIndex", "coordIndex" or "face".
        field: &'static str,
        /// Position in that field (the face number for "face").
        position: usize,
        /// The index found.
        index: i32,
        /// The Normal node's vector count.
        vectors: usize,
    },
    /// An `ElevationGrid` with a negative dimension.
    #[error("xDimension {x} and zDimension {z} must not be negative")]
    NegativeDimension {
        /// `xDimension`.
        x: i32,
        /// `zDimension`.
        z: i32,
    },
    /// An `ElevationGrid` whose heights are not one per grid point.
    #[error("height has {heights} values, xDimension × zDimension = {x} × {z}")]
    HeightCount {
        /// Values in `height`.
        heights: usize,
        /// `xDimension`.
        x: usize,
        /// `zDimension`.
        z: usize,
    },
}

/// Triangulates geometry node `g`; `warn` collects messages about it. Errors are invalid
/// content (an index out of range, a height count that does not match the grid).
pub fn geometry(g: &Node, warn: &mut Vec<String>) -> Result<Geometry, GeometryError> {
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

fn indexed_face_set(g: &Node, warn: &mut Vec<String>) -> Result<LocalMesh, GeometryError> {
    let points: Vec<Vec3> = match g.node("coord") {
        Some(c) if c.type_name == "Coordinate" => match c.get("point") {
            Some(FieldValue::Vec3s(p)) => p.iter().map(|&p| Vec3::from(p)).collect(),
            _ => Vec::new(),
        },
        Some(c) => return Err(GeometryError::NotCoordinate(c.type_name.clone())),
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
            return Err(GeometryError::CoordIndex { position: k, index: i, points: n });
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
    let ccw = g.bool("ccw", true);
    if !ccw {
        triangles.iter_mut().for_each(|t| t.swap(1, 2));
    }
    let mut mesh =
        LocalMesh { positions: points, triangles, solid: g.bool("solid", true), ..Default::default() };
    if let Some(corner_normal) = corner_normals(g, index, &mesh.positions, ccw, warn)? {
        split_by_normal(&mut mesh, index, &corner_normal);
    }
    Ok(mesh)
}

/// The shading normal of every corner of `coordIndex` (`None` for the `-1` separators), from the
/// `Normal` node or generated from `creaseAngle`; `None` if the face set is faceted.
fn corner_normals(
    g: &Node,
    index: &[i32],
    points: &[Vec3],
    ccw: bool,
    warn: &mut Vec<String>,
) -> Result<Option<Vec<Option<Vec3>>>, GeometryError> {
    let faces: Vec<std::ops::Range<usize>> = {
        let mut out = Vec::new();
        let mut start = 0;
        for (k, &i) in index.iter().enumerate() {
            if i == -1 {
                out.push(start..k);
                start = k + 1;
            }
        }
        if start < index.len() {
            out.push(start..index.len());
        }
        out
    };
    let mut normals = vec![None; index.len()];
    if let Some(node) = g.node("normal") {
        if node.type_name != "Normal" {
            return Err(GeometryError::NotNormal(node.type_name.clone()));
        }
        let vector: Vec<Vec3> = match node.get("vector") {
            Some(FieldValue::Vec3s(v)) => v.iter().map(|&v| Vec3::from(v)).collect(),
            _ => Vec::new(),
        };
        let normal_index: &[i32] = match g.get("normalIndex") {
            Some(FieldValue::Ints(v)) => v,
            _ => &[],
        };
        let pick =
            |field: &'static str, k: usize, i: i32| -> Result<Vec3, GeometryError> {
                usize::try_from(i)
                    .ok()
                    .and_then(|i| vector.get(i).copied())
                    .ok_or(GeometryError::NormalIndex { field, position: k, index: i, vectors: vector.len() })
            };
        let per_vertex = g.bool("normalPerVertex", true);
        for (f, face) in faces.iter().enumerate() {
            for k in face.clone() {
                normals[k] = Some(match (per_vertex, normal_index.is_empty()) {
                    (true, true) => pick("coordIndex", k, index[k])?,
                    (true, false) => pick("normalIndex", k, *normal_index.get(k).unwrap_or(&-1))?,
                    (false, true) => pick("face", f, f as i32)?,
                    (false, false) => pick("normalIndex", f, *normal_index.get(f).unwrap_or(&-1))?,
                });
            }
        }
        return Ok(Some(normals));
    }
    let crease = g.float("creaseAngle", 0.0);
    if crease.is_nan() || crease <= 0.0 {
        return Ok(None);
    }
    // Area-weighted face normals (Newell's), facing VRML's front.
    let sign = if ccw { 1.0 } else { -1.0 };
    let face_normal: Vec<Vec3> = faces
        .iter()
        .map(|face| {
            let c: Vec<Vec3> = face.clone().map(|k| points[index[k] as usize]).collect();
            let n = (0..c.len()).map(|i| c[i].cross(c[(i + 1) % c.len()])).sum::<Vec3>();
            sign * 0.5 * n
        })
        .collect();
    let mut faces_of: Vec<Vec<u32>> = vec![Vec::new(); points.len()];
    for (f, face) in faces.iter().enumerate() {
        for k in face.clone() {
            faces_of[index[k] as usize].push(f as u32);
        }
    }
    // Each corner compares its face with every face at its point: Σ degree² comparisons. A
    // hostile (or merely fan-shaped) file could make that quadratic, so it is bounded.
    let work: u64 = faces_of.iter().map(|f| (f.len() as u64).pow(2)).sum();
    if work > MAX_CREASE_WORK {
        warn.push(format!(
            "creaseAngle: too many faces share a point ({work} comparisons > {MAX_CREASE_WORK}); normals not generated, the face set is faceted"
        ));
        return Ok(None);
    }
    let cos_crease = crease.min(PI).cos();
    for (f, face) in faces.iter().enumerate() {
        let nf = face_normal[f].normalize_or_zero();
        for k in face.clone() {
            count_steps(faces_of[index[k] as usize].len());
            let sum: Vec3 = faces_of[index[k] as usize]
                .iter()
                .map(|&o| face_normal[o as usize])
                .filter(|n| n.normalize_or_zero().dot(nf) >= cos_crease)
                .sum();
            normals[k] = Some(if sum == Vec3::ZERO { nf } else { sum });
        }
    }
    Ok(Some(normals))
}

/// Gives every corner of `mesh` (triangles of point indices, triangulated from `index`) its own
/// normal: a point is split into one vertex per distinct normal it has at its corners.
fn split_by_normal(mesh: &mut LocalMesh, index: &[i32], corner_normal: &[Option<Vec3>]) {
    // The normal of each (face, point): faces are runs of `index`; a triangle's corners are
    // points of the face it came from, found in the face's run.
    let mut vertex_of: std::collections::HashMap<(u32, [u32; 3]), u32> = std::collections::HashMap::new();
    let (mut positions, mut normals) = (Vec::new(), Vec::new());
    let mut face_start = 0usize;
    let mut tri = 0usize;
    let counts = triangles_per_face(index, &mesh.positions);
    let mut triangles = std::mem::take(&mut mesh.triangles);
    for (face_len, ntri) in counts {
        let run = &index[face_start..face_start + face_len];
        // Long faces look their corners up in a map: a linear search would be quadratic.
        let corner_of: std::collections::HashMap<u32, usize> = if face_len > 32 {
            run.iter().enumerate().rev().map(|(k, &i)| (i as u32, k)).collect()
        } else {
            Default::default()
        };
        for t in &mut triangles[tri..tri + ntri] {
            for p in t.iter_mut() {
                let local = if face_len > 32 {
                    count_steps(1);
                    corner_of.get(p).copied()
                } else {
                    let found = run.iter().position(|&i| i as u32 == *p);
                    count_steps(found.map_or(face_len, |k| k + 1));
                    found
                };
                let k = face_start + local.unwrap_or(0);
                let n = corner_normal[k].unwrap_or(Vec3::Y);
                let key = (*p, n.to_array().map(f32::to_bits));
                let next = positions.len() as u32;
                let v = *vertex_of.entry(key).or_insert(next);
                if v == next {
                    positions.push(mesh.positions[*p as usize]);
                    normals.push(n);
                }
                *p = v;
            }
        }
        face_start += face_len + 1;
        tri += ntri;
    }
    mesh.triangles = triangles;
    mesh.positions = positions;
    mesh.normals = normals;
}

/// (corners, triangles) of each face of `index`, as [`indexed_face_set`] triangulated them.
fn triangles_per_face(index: &[i32], points: &[Vec3]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut scratch = Vec::new();
    for run in index.split(|&i| i == -1) {
        let poly: Vec<u32> = run.iter().map(|&i| i as u32).collect();
        scratch.clear();
        if poly.len() >= 3 {
            triangulate(points, &poly, &mut scratch);
        }
        out.push((run.len(), scratch.len()));
    }
    out
}

fn elevation_grid(g: &Node) -> Result<LocalMesh, GeometryError> {
    let (nx, nz) = (g.int("xDimension", 0), g.int("zDimension", 0));
    let (dx, dz) = (g.float("xSpacing", 1.0), g.float("zSpacing", 1.0));
    let heights: &[f32] = match g.get("height") {
        Some(FieldValue::Floats(h)) => h,
        _ => &[],
    };
    if nx < 0 || nz < 0 {
        return Err(GeometryError::NegativeDimension { x: nx, z: nz });
    }
    let (nx, nz) = (nx as usize, nz as usize);
    if nx.checked_mul(nz) != Some(heights.len()) {
        return Err(GeometryError::HeightCount { heights: heights.len(), x: nx, z: nz });
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
    Ok(LocalMesh { positions, triangles, solid: g.bool("solid", true), ..Default::default() })
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
    if r > 0.0 {
        m.normals = m.positions.clone(); // radial: the true sphere's normal
    }
    m
}

/// A surface of revolution about y through the profile `(radius, y)` from bottom to top, with
/// optional side and caps (bottom, top). Used for cylinders and cones.
fn revolved(profile: &[(f32, f32); 2], side: bool, caps: [bool; 2]) -> LocalMesh {
    let mut m = LocalMesh { solid: true, ..Default::default() };
    // The side's smooth normal at angle φ: (dy·sin φ, r0 − r1, dy·cos φ) (zero if degenerate).
    let ((r0, y0), (r1, y1)) = (profile[0], profile[1]);
    let slope = Vec3::new(y1 - y0, r0 - r1, y1 - y0);
    let smooth = slope.x > 0.0 && r0 >= 0.0 && r1 >= 0.0;
    let ring = |m: &mut LocalMesh, (r, y): (f32, f32), normal: Option<Vec3>| -> u32 {
        let base = m.positions.len() as u32;
        for i in 0..SEGMENTS {
            let phi = 2.0 * PI * i as f32 / SEGMENTS as f32;
            m.positions.push(Vec3::new(r * phi.sin(), y, r * phi.cos()));
            m.normals.push(normal.unwrap_or(slope * Vec3::new(phi.sin(), 1.0, phi.cos())));
        }
        base
    };
    let next = |b: u32, i: usize| b + ((i + 1) % SEGMENTS) as u32;
    if side {
        let (lo, hi) = (ring(&mut m, profile[0], None), ring(&mut m, profile[1], None));
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
            let axis = Vec3::new(0.0, if k == 0 { -1.0 } else { 1.0 }, 0.0);
            let b = ring(&mut m, profile[k], Some(axis));
            let centre = m.positions.len() as u32;
            m.positions.push(Vec3::new(0.0, profile[k].1, 0.0));
            m.normals.push(axis);
            for i in 0..SEGMENTS {
                push_outward(&mut m, [centre, b + i as u32, next(b, i)]);
            }
        }
    }
    if !smooth {
        m.normals.clear();
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

    /// The (only) mesh of a VRML `body` loaded whole (parse, convert), the load's warnings, and
    /// the work its normal generation counted.
    fn counted(body: &str) -> (opticks_core::scene::MeshDesc, Vec<String>, u64) {
        let path = std::path::Path::new("t.wrl");
        STEPS.with(|s| s.set(0));
        let mut loaded = super::super::load_str(&format!("#VRML V2.0 utf8\n{body}"), path).unwrap();
        (loaded.description.meshes.remove(0), loaded.warnings, STEPS.with(|s| s.get()))
    }

    #[test]
    fn a_huge_smooth_face_takes_linear_work() {
        // One 200 000-corner polygon with per-point normals: fanned, one vertex per point, and
        // each triangle corner finds its corner of the face in one look-up (a linear search
        // would take ~10¹⁰ steps).
        let n = 200_000;
        let points: String = (0..n)
            .map(|k| {
                let a = k as f32 / n as f32 * std::f32::consts::TAU;
                format!("{} {} 0,", a.cos(), a.sin())
            })
            .collect();
        let normals = "0 0 1,".repeat(n);
        let index: String = (0..n).map(|k| format!("{k} ")).collect();
        let (m, warn, steps) = counted(&format!(
            "Shape {{ geometry IndexedFaceSet {{ coord Coordinate {{ point [ {points} ] }} normal Normal {{ vector [ {normals} ] }} coordIndex [ {index} ] }} }}"
        ));
        assert_eq!((m.triangles.len(), m.positions.len(), m.normals.len()), (n - 2, n, n));
        assert!(warn.iter().any(|w| w.contains("fanned")), "{warn:?}");
        assert_eq!(steps, 3 * (n as u64 - 2));
    }

    #[test]
    fn crease_angle_work_is_refused_before_it_is_done() {
        // A fan of 20 000 triangles around one centre point would need Σ degree² ≈ 4·10⁸ face
        // comparisons: refused (faceted, a warning) before any is made.
        let n = 20_000;
        let mut points = String::from("0 0 0,");
        let mut index = String::new();
        for k in 0..=n {
            let a = k as f32 / n as f32 * std::f32::consts::TAU;
            points += &format!("{} {} 0,", a.cos(), a.sin());
            if k < n {
                index += &format!("0 {} {} -1 ", k + 1, k + 2);
            }
        }
        let (m, warn, steps) = counted(&format!(
            "Shape {{ geometry IndexedFaceSet {{ creaseAngle 1 coord Coordinate {{ point [ {points} ] }} coordIndex [ {index} ] }} }}"
        ));
        assert!(m.normals.is_empty() && warn.iter().any(|w| w.contains("too many faces")), "{warn:?}");
        assert_eq!(steps, 0);
        // The counter counts: a smooth cube compares each of its 24 corners with the 3 faces at
        // its point (72 steps) and finds the 6 corners of each quad's two triangles in the quad's
        // run of 4 by linear search (16 steps a quad, 96 in all).
        let (m, _, steps) = counted(
            "Shape { geometry IndexedFaceSet { creaseAngle 2 coord Coordinate { point [ -1 -1 -1, 1 -1 -1, \
             1 1 -1, -1 1 -1, -1 -1 1, 1 -1 1, 1 1 1, -1 1 1 ] } coordIndex [ 0 3 2 1 -1, 4 5 6 7 -1, \
             0 1 5 4 -1, 3 7 6 2 -1, 0 4 7 3 -1, 1 2 6 5 -1 ] } }",
        );
        assert!(!m.normals.is_empty());
        assert_eq!(steps, 72 + 96);
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
    fn index_errors_read_as_they_always_did() {
        let e = GeometryError::CoordIndex { position: 4, index: 7, points: 3 };
        assert_eq!(
            e.to_string(),
            "coordIndex[4] = 7 is out of range: the Coordinate node has 3 points (0..2)"
        );
        let e = GeometryError::CoordIndex { position: 0, index: 0, points: 0 };
        assert_eq!(
            e.to_string(),
            "coordIndex[0] = 0 is out of range: the Coordinate node has 0 points (0..0)"
        );
        let e = GeometryError::NormalIndex { field: "face", position: 2, index: 2, vectors: 1 };
        assert_eq!(e.to_string(), "face[2] = 2 is out of range: the Normal node has 1 vectors");
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
