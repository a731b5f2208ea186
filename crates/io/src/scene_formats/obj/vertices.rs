//! Meshes from an OBJ file's resolved vertex data: the vertices the faces use, split by normal
//! ([`ObjVertices::gather`], for the OBJ/MTL loader's groups and for Mitsuba's `obj` shape) or
//! by texture coordinate as Mitsuba's reader splits them ([`split_by_uv`]), and Mitsuba 3's
//! angle-weighted smooth normals for a mesh without any ([`generated_vertex_normals`]). Apart
//! from the parsing, since these run on whole meshes once the file is read.

use super::ObjMesh;
use super::geometry::NORMAL_CORNER;
use opticks_core::math::{Vec2, Vec3};

/// `mesh` (without `uvs`) with one vertex per distinct (vertex, texture-coordinate index) pair
/// of its triangles' corners, in order of first use, as Mitsuba's OBJ reader makes them, and
/// their `uvs` (`values[index]`, checked in range; (0, 0) for a corner without one).
pub(super) fn split_by_uv(mesh: ObjMesh, texcoords: &[[u32; 3]], values: &[Vec2]) -> ObjMesh {
    let mut vertex_of = std::collections::HashMap::new();
    let mut out = ObjMesh { triangles: Vec::with_capacity(mesh.triangles.len()), ..Default::default() };
    for (t, tc) in mesh.triangles.iter().zip(texcoords) {
        out.triangles.push(std::array::from_fn(|j| {
            *vertex_of.entry((t[j], tc[j])).or_insert_with(|| {
                out.positions.push(mesh.positions[t[j] as usize]);
                if !mesh.normals.is_empty() {
                    out.normals.push(mesh.normals[t[j] as usize]);
                }
                out.uvs.push(values.get(tc[j] as usize).copied().unwrap_or(Vec2::ZERO));
                out.positions.len() as u32 - 1
            })
        }));
    }
    out
}

/// An OBJ file's vertex data, resolved once the whole file is read; faces refer to it by corner
/// ids (a position index, or `NORMAL_CORNER | k` for the k-th (position, normal) pair).
pub(in crate::scene_formats) struct ObjVertices {
    /// Positions, in file order.
    pub(in crate::scene_formats) positions: Vec<Vec3>,
    /// Vertex normals (`vn`), in file order.
    pub(super) normals: Vec<Vec3>,
    /// The distinct (position, normal) pairs of `v//vn` corners (see [`NORMAL_CORNER`]).
    pub(super) pairs: Vec<(u32, u32)>,
    /// The `vt` values.
    pub(super) texcoords: Vec<Vec2>,
}

impl ObjVertices {
    /// Whether any face corner has a normal.
    pub(in crate::scene_formats) fn has_normals(&self) -> bool {
        !self.pairs.is_empty()
    }

    /// A table for [`ObjVertices::gather`]: one unmapped entry per position and pair.
    pub(in crate::scene_formats) fn remap_table(&self) -> Vec<u32> {
        vec![u32::MAX; self.positions.len() + self.pairs.len()]
    }

    /// The mesh of the triangles of `runs` (corner ids), in order: the vertices they use, in
    /// order of first use, with one normal each if the file has normals (see the module docs).
    /// `remap` comes from [`ObjVertices::remap_table`] and is left unmapped again, so it can be
    /// reused.
    pub(in crate::scene_formats) fn gather(&self, runs: &[&[[u32; 3]]], remap: &mut [u32]) -> ObjMesh {
        let with_normals = self.has_normals();
        let count = runs.iter().map(|r| r.len()).sum();
        let mut mesh = ObjMesh { triangles: Vec::with_capacity(count), ..Default::default() };
        let mut used = Vec::new();
        let p_count = self.positions.len();
        for t in runs.iter().copied().flatten() {
            let position = |c: u32| {
                let p = if c & NORMAL_CORNER != 0 { self.pairs[(c & !NORMAL_CORNER) as usize].0 } else { c };
                self.positions[p as usize]
            };
            let [a, b, c] = t.map(position);
            // Corners without a normal, in a file with normals, are shaded flat.
            let face = (b - a).cross(c - a).try_normalize().unwrap_or(Vec3::Z);
            let local = t.map(|c| {
                let (slot, normal) = if c & NORMAL_CORNER != 0 {
                    let k = (c & !NORMAL_CORNER) as usize;
                    (p_count + k, self.normals[self.pairs[k].1 as usize])
                } else if with_normals {
                    mesh.positions.push(position(c));
                    mesh.normals.push(face);
                    return mesh.positions.len() as u32 - 1;
                } else {
                    (c as usize, Vec3::ZERO)
                };
                if remap[slot] == u32::MAX {
                    remap[slot] = mesh.positions.len() as u32;
                    mesh.positions.push(position(c));
                    if with_normals {
                        mesh.normals.push(normal);
                    }
                    used.push(slot);
                }
                remap[slot]
            });
            mesh.triangles.push(local);
        }
        for slot in used {
            remap[slot] = u32::MAX;
        }
        mesh
    }
}

/// Smooth vertex normals as Mitsuba 3 generates them for a mesh without normals
/// (`Mesh::recompute_vertex_normals`, after Thürmer and Wüthrich, "Computing Vertex Normals from
/// Polygonal Facets", JGT 1998): a vertex's normal is the sum of the unit normals of the
/// triangles using it, each weighted by the triangle's angle at that vertex, normalised.
/// Zero-area triangles add nothing; a vertex whose sum is zero gets Mitsuba's placeholder +x.
///
/// The vertices are the mesh's: Mitsuba's OBJ reader shares a vertex between corners with the
/// same (position, texture coordinate) indices, which [`super::parse_obj`] has already split them by,
/// so each copy is smoothed over its own triangles only, as in Mitsuba. `positions` should
/// already be in world space, as Mitsuba computes the normals
/// after `to_world` (angles are not preserved by a non-uniform scale).
pub fn generated_vertex_normals(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> ObjMesh {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for t in &triangles {
        let v = t.map(|i| positions[i as usize]);
        let Some(n) = (v[1] - v[0]).cross(v[2] - v[0]).try_normalize() else { continue };
        for j in 0..3 {
            let angle = unit_angle(
                (v[(j + 1) % 3] - v[j]).normalize_or_zero(),
                (v[(j + 2) % 3] - v[j]).normalize_or_zero(),
            );
            normals[t[j] as usize] += n * angle;
        }
    }
    for n in &mut normals {
        *n = n.try_normalize().unwrap_or(Vec3::X);
    }
    ObjMesh { positions, triangles, normals, ..Default::default() }
}

/// The angle between unit vectors `a` and `b`, accurate also near 0 and π (as Mitsuba's
/// `unit_angle`).
fn unit_angle(a: Vec3, b: Vec3) -> f32 {
    if a.dot(b) < 0.0 {
        std::f32::consts::PI - 2.0 * ((a + b).length() / 2.0).min(1.0).asin()
    } else {
        2.0 * ((a - b).length() / 2.0).min(1.0).asin()
    }
}
