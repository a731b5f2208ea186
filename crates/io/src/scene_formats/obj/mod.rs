//! Wavefront OBJ: the one reader of OBJ text. `parse_obj_file` reads every statement Opticks
//! uses in one pass; the OBJ/MTL scene loader ([`super::wavefront`]) makes meshes of its groups
//! and materials, and Mitsuba's `<shape type="obj">` reads the whole file as one mesh
//! ([`read_obj`], [`parse_obj`]), with Mitsuba's generated vertex normals when it has none
//! ([`generated_vertex_normals`], below).
//!
//! | statement | handling |
//! |---|---|
//! | `v x y z [w] [r g b]` | a position; `w` and vertex colours are ignored |
//! | `vn x y z` | a vertex normal (a shading normal, normalised by the core) |
//! | `f i j k …` | a polygon, triangulated as a fan `(i, j, k), (i, k, l), …`; each corner may be `v`, `v/vt`, `v//vn` or `v/vt/vn` (for Mitsuba's `obj` shape, corners are split by `vt` as Mitsuba splits them, see below) |
//! | indices | 1-based; negative indices count back from the last vertex (or normal) defined so far (`-1` = the latest) |
//! | `vt u [v [w]]` | a texture coordinate (`w` ignored; v = 0 if absent); Mitsuba's `obj` shape reads them, the OBJ/MTL loader ignores them |
//! | `o name`, `g name …` | starts a group (the rest of the line is its name; empty = no group) |
//! | `usemtl name` | later faces use that material (empty = none) |
//! | `mtllib a.mtl …` | material libraries (the rest of the line, as written) |
//! | `#…` | a comment, from `#` to the end of the line, wherever it starts |
//! | `vp`, `s`, `l`, `p`, curves, anything else | ignored |
//!
//! Vertex normals: a corner `v//vn` is a vertex of its own (position v, normal vn; corners
//! sharing both share the vertex). In a file that uses normals, a face corner without one is
//! shaded flat: it gets a vertex of its own with its face's geometric normal. Normal indices
//! on faces before the first `vn` are ignored. `s` (smoothing groups) does not generate normals. A file without `vn` gives exactly the mesh it gave before.
//!
//! Texture coordinates and generated normals (for Mitsuba's `<shape type="obj">`): [`parse_obj`]
//! makes one vertex per distinct (vertex, `vt`) pair of the face corners, as Mitsuba's reader
//! does, each with its (u, v) ([`ObjMesh::uvs`]; a corner without `vt`, or whose `vt` index is 0
//! or not a number, gets (0, 0); an index past the file's last `vt` is an error, and indices
//! in a file without `vt` are ignored, like normal indices before the first `vn`);
//! [`generated_vertex_normals`] computes Mitsuba 3's angle-weighted smooth normals over those
//! vertices.

//! Winding is kept as written: a triangle's front face is the one from which it is
//! counter-clockwise (normal `(v1 − v0) × (v2 − v0)`). Degenerate (zero-area) triangles are kept;
//! the core scene builder drops them.
//!
//! Errors carry the OBJ line: a coordinate that is not a number or not finite, a face with fewer
//! than three corners, index 0, a relative index reaching before the first vertex, an index past
//! the last vertex of the file (forward references to vertices defined later in the file are
//! accepted, as most readers do).
//!
//! # Why not `tobj`
//!
//! `tobj` (used by the tests as an independent reader to cross-check this one) reports errors as a bare enum (`FaceVertexOutOfBounds`,
//! `PositionParseError`) without a line number, accepts `nan`/`inf` coordinates silently, and
//! allocates a `String` per line. This reader is a single pass over the file's bytes that
//! allocates nothing per vertex or face line (tokens are sub-slices; numbers use the standard
//! library's allocation-free parsers), so a million-triangle file loads in well under a second
//! and every error names its line.
//!
//! The reader is split by responsibility: `geometry` reads the `v`, `vn`, `vt` and `f`
//! statements (tokens, numbers, index resolution and the end-of-file range checks), and
//! `vertices` turns the resolved vertex data into meshes (vertices split by normal or texture
//! coordinate, Mitsuba's generated normals). This file holds the statement loop, the public
//! types and entry points.

mod geometry;
mod vertices;

pub use vertices::generated_vertex_normals;

use super::{FileLocation, SceneFileError};
use geometry::{ObjGeometry, line_tokens};
use opticks_core::math::{Vec2, Vec3};
use std::path::Path;
use vertices::{ObjVertices, split_by_uv};

/// An OBJ file's triangles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjMesh {
    /// Vertex positions, in file order.
    pub positions: Vec<Vec3>,
    /// Triangles (0-based indices into `positions`), polygons fanned.
    pub triangles: Vec<[u32; 3]>,
    /// One vertex normal per position (as written, not normalised), or empty if the file has
    /// no `v//vn` corners.
    pub normals: Vec<Vec3>,
    /// One texture coordinate per position, as written (`vt u v`), for a file whose faces use
    /// `v/vt` corners (a corner without one gets (0, 0)); empty otherwise.
    pub uvs: Vec<Vec2>,
}

/// A corner without a (readable) texture-coordinate index.
pub const NO_TEXCOORD: u32 = u32::MAX;

/// What is wrong with an OBJ file's content, and on which line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ObjError {
    /// 1-based line.
    pub line: u32,
    /// What is wrong.
    pub message: String,
}

/// Everything an OBJ file says that Opticks uses, as [`parse_obj_file`] reads it.
pub(super) struct ObjFile {
    /// The vertex data the triangles' corner ids refer to.
    pub(super) vertices: ObjVertices,
    /// Every face's triangles (corner ids, see [`ObjVertices`]), polygons fanned, in file order.
    pub(super) triangles: Vec<[u32; 3]>,
    /// If asked for: each triangle's 0-based texture-coordinate indices ([`NO_TEXCOORD`] for a
    /// corner without one).
    pub(super) texcoords: Vec<[u32; 3]>,
    /// The faces in runs that share the group and material statements in force (a new run starts
    /// at the first face after an `o`, `g` or `usemtl`), in file order; none before the first face.
    pub(super) runs: Vec<FaceRun>,
    /// `mtllib` arguments with their lines.
    pub(super) mtllibs: Vec<(String, u32)>,
}

/// Consecutive faces read under the same `o`/`g` and `usemtl` statements.
pub(super) struct FaceRun {
    /// Index of the run's first triangle in [`ObjFile::triangles`] (it ends where the next begins).
    pub(super) start: usize,
    /// The group in force (`o` or `g`): `None` before any, or after one without a name.
    pub(super) group: Option<String>,
    /// The material in force and the line of its `usemtl`: `None` before any, or after one
    /// without a name.
    pub(super) material: Option<(String, u32)>,
}

impl ObjFile {
    /// The triangles of run `i`.
    pub(super) fn run_triangles(&self, i: usize) -> &[[u32; 3]] {
        let end = self.runs.get(i + 1).map_or(self.triangles.len(), |r| r.start);
        &self.triangles[self.runs[i].start..end]
    }
}

/// Reads OBJ text in one pass (see the module docs for what is read); with `texcoords`, also
/// each corner's texture-coordinate index (for [`generated_vertex_normals`]).
pub(super) fn parse_obj_file(data: &[u8], texcoords: bool) -> Result<ObjFile, ObjError> {
    let mut geometry = ObjGeometry::new(u32::MAX);
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut tri_texcoords: Vec<[u32; 3]> = Vec::new();
    let mut runs: Vec<FaceRun> = Vec::new();
    let mut mtllibs = Vec::new();
    let mut group: Option<String> = None;
    let mut material: Option<(String, u32)> = None;
    // Whether an `o`, `g` or `usemtl` came since the last face (the next face starts a run).
    let mut new_run = true;
    let mut line_no = 0u32;

    for raw in data.split(|&b| b == b'\n') {
        line_no = line_no.saturating_add(1);
        let raw = match raw.iter().position(|&b| b == b'#') {
            Some(p) => &raw[..p],
            None => raw,
        };
        let mut tokens = line_tokens(raw);
        let Some(keyword) = tokens.next() else { continue };
        match keyword {
            b"v" => geometry.vertex(tokens, line_no)?,
            b"vn" => geometry.normal(tokens, line_no)?,
            // Texture coordinates matter only to a caller that asks for them (Mitsuba's `obj`).
            b"vt" if texcoords => geometry.texcoord(tokens, line_no)?,
            b"vt" => geometry.texcoord_count = geometry.texcoord_count.saturating_add(1),
            b"f" => {
                if new_run {
                    runs.push(FaceRun {
                        start: triangles.len(),
                        group: group.clone(),
                        material: material.clone(),
                    });
                    new_run = false;
                }
                geometry.face(tokens, line_no, &mut triangles, texcoords.then_some(&mut tri_texcoords))?;
            }
            b"o" | b"g" => {
                let name = rest_of_line(raw, keyword);
                group = (!name.is_empty()).then_some(name);
                new_run = true;
            }
            b"usemtl" => {
                let name = rest_of_line(raw, keyword);
                material = (!name.is_empty()).then_some((name, line_no));
                new_run = true;
            }
            b"mtllib" => {
                let name = rest_of_line(raw, keyword);
                if !name.is_empty() {
                    mtllibs.push((name, line_no));
                }
            }
            _ => {}
        }
    }
    let vertices = geometry.finish()?;
    Ok(ObjFile { vertices, triangles, texcoords: tri_texcoords, runs, mtllibs })
}

/// The text after the keyword, trimmed (names may contain spaces).
fn rest_of_line(raw: &[u8], keyword: &[u8]) -> String {
    let start = raw.windows(keyword.len()).position(|w| w == keyword).map_or(0, |p| p + keyword.len());
    String::from_utf8_lossy(&raw[start..]).trim().to_string()
}

/// Parses OBJ text as one mesh, all its faces in file order (as Mitsuba's `obj` shape reads a
/// file): the vertices as written if no corner has a normal (with the texture-coordinate
/// indices, if any corner has one), else those the faces use, split by normal.
pub fn parse_obj(data: &[u8]) -> Result<ObjMesh, ObjError> {
    let ObjFile { mut vertices, triangles, texcoords, .. } = parse_obj_file(data, true)?;
    let values = std::mem::take(&mut vertices.texcoords);
    let mesh = if vertices.has_normals() {
        let mut remap = vertices.remap_table();
        vertices.gather(&[&triangles], &mut remap)
    } else {
        ObjMesh { positions: vertices.positions, triangles, ..Default::default() }
    };
    if values.is_empty() || texcoords.iter().all(|t| *t == [NO_TEXCOORD; 3]) {
        return Ok(mesh);
    }
    Ok(split_by_uv(mesh, &texcoords, &values))
}

/// Reads and parses an OBJ file. `referenced_from` (the scene element and where it is) is added
/// to error messages.
pub fn read_obj(
    path: &Path,
    referenced_from: Option<(String, FileLocation)>,
) -> Result<ObjMesh, SceneFileError> {
    let data = super::mesh_bytes::read_bytes(path, referenced_from.as_ref())?;
    parse_obj(&data).map_err(|e| SceneFileError::Obj {
        at: FileLocation { file: path.to_path_buf(), line: e.line, column: 0 },
        message: e.message,
        referenced_from,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_vertices_and_fans_polygons() {
        let src = b"# comment\no quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\r\nv 0 1 0 1.0\nvt 0 0\nvn 0 0 1\ns off\nusemtl x\n\
                    f 1/1/1 2/1/1 3/1/1 4/1/1\nf -4//1 -2//1 -1//1 # tail comment\n\tf\t1 2 3\n";
        let m = parse_obj(src).unwrap();
        // Four (position, normal, vt) corners, three (position, normal) corners without a `vt`
        // (Mitsuba's vertices differ by texture coordinate too), then the three flat corners of
        // `f 1 2 3`.
        assert_eq!(m.positions.len(), 10);
        assert_eq!(m.positions[2], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(m.positions[5], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [7, 8, 9]]);
    }

    #[test]
    fn vertex_normals_split_corners_and_unnormalled_corners_are_flat() {
        let src = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 2\nvn 0.1 0 1\n\
                    f 1//1 2//2 3//1\nf 2//2 4//1 3//1\nf 1 2 4\n";
        let m = parse_obj(src).unwrap();
        // Corners (1,1) (2,2) (3,1) (4,1), then three flat corners of their own.
        assert_eq!(m.triangles, vec![[0, 1, 2], [1, 3, 2], [4, 5, 6]]);
        assert_eq!(m.positions.len(), 7);
        assert_eq!(m.normals.len(), 7);
        assert_eq!(m.normals[1], Vec3::new(0.1, 0.0, 1.0));
        assert_eq!(m.positions[5], Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(m.normals[6], Vec3::Z); // the face normal
        // Without vn the mesh is what it always was.
        assert!(parse_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap().normals.is_empty());
        for (src, text) in [
            (
                &b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//2 3//1\n"[..],
                "normal 2, but the file defines only 1",
            ),
            (b"v 0 0 0\nvn 0 0 0\n", "zero"),
            (b"v 0 0 0\nvn 0 nan 1\n", "not finite"),
            (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//x 2 3\n", "normal index"),
        ] {
            let e = parse_obj(src).unwrap_err();
            assert!(e.message.contains(text), "{e:?} should mention {text:?}");
        }
    }

    #[test]
    fn a_comment_runs_from_any_hash_to_the_end_of_the_line() {
        let m = parse_obj(b"v 0 0 0#a\nv 1 0 0 # b\nv 0 1 0\n#f 9 9 9\nf 1 2 3# c\n").unwrap();
        assert_eq!((m.positions.len(), m.triangles.clone()), (3, vec![[0, 1, 2]]));
        let e = parse_obj(b"v 0 0 0\nv 1 #0 0\n").unwrap_err();
        assert_eq!((e.line, e.message.as_str()), (2, "vertex has 1 coordinates, expected 3"));
    }

    #[test]
    fn faces_come_in_runs_of_their_group_and_material() {
        let src = b"mtllib a.mtl  b c.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nusemtl red # c\nf 1 2 3 1\n\
                    o lid top\ng\nusemtl \nf 1 2 3\nusemtl x\nusemtl y\nf 1 2 3\nf 1 2 3\n";
        let obj = parse_obj_file(src, false).unwrap();
        let runs: Vec<String> =
            obj.runs.iter().map(|r| format!("{} {:?} {:?}", r.start, r.group, r.material)).collect();
        assert_eq!(
            runs,
            ["0 None None", "1 None Some((\"red\", 6))", "3 None None", "4 None Some((\"y\", 13))"]
        );
        assert_eq!(obj.run_triangles(1).len(), 2);
        assert_eq!(obj.run_triangles(3).len(), 2);
        assert_eq!(obj.mtllibs, [("a.mtl  b c.mtl".to_string(), 1)]);
        assert!(obj.texcoords.is_empty(), "not asked for");
        let obj = parse_obj_file(b"o lid top\nv 0 0 0\nf 1 1 1\n", true).unwrap();
        assert_eq!(obj.runs[0].group.as_deref(), Some("lid top"));
        assert_eq!(obj.texcoords, [[NO_TEXCOORD; 3]]);
    }

    #[test]
    fn forward_references_are_accepted() {
        let m = parse_obj(b"f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn degenerate_triangles_are_kept() {
        let m = parse_obj(b"v 0 0 0\nv 1 0 0\nf 1 2 2\n").unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 1]]);
    }

    #[test]
    fn errors_name_the_line() {
        let cases: &[(&[u8], u32, &str)] = &[
            (b"v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 9\n", 5, "vertex 9, but the file defines only 3"),
            (b"v 0 0 0\nf 1 -2 1\n", 2, "relative vertex -2"),
            (b"v 0 0 0\nv 0 0 0\nf 0 1 2\n", 3, "vertex 0"),
            (b"v 0 0\n", 1, "2 coordinates"),
            (b"v 0 nan 0\n", 1, "not finite"),
            (b"v 0 0 1e39\n", 1, "not finite"),
            (b"v 0 0 abc\n", 1, "not a number"),
            (b"v 0 0 0\nv 0 0 0\nf 1 2\n", 3, "2 corners"),
            (b"v 0 0 0\nf a b c\n", 2, "vertex index"),
        ];
        for (src, line, text) in cases {
            let e = parse_obj(src).unwrap_err();
            assert_eq!(e.line, *line, "{e:?}");
            assert!(e.message.contains(text), "{e:?} should mention {text:?}");
        }
    }

    /// A big file parses to exactly its triangles (its speed is a benchmark's business:
    /// `bench_a_million_triangles` in `tests/obj_mtl.rs`).
    #[test]
    fn a_million_triangles_parse() {
        // 501×1001 grid = 501 501 vertices, 1 000 000 triangles, as quads (fanned) and triangles.
        let (nx, ny) = (1001usize, 501usize);
        let mut s = String::with_capacity(50_000_000);
        use std::fmt::Write;
        for j in 0..ny {
            for i in 0..nx {
                writeln!(s, "v {:.6} {:.6} {:.6}", i as f32 * 0.001, j as f32 * 0.002, (i * j) as f32 * 1e-6)
                    .unwrap();
            }
        }
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let a = j * nx + i + 1;
                if i % 2 == 0 {
                    writeln!(s, "f {} {} {} {}", a, a + 1, a + 1 + nx, a + nx).unwrap();
                } else {
                    writeln!(
                        s,
                        "f {}/1/1 {}/1/1 {}/1/1\nf {} {} {}",
                        a,
                        a + 1,
                        a + 1 + nx,
                        a,
                        a + 1 + nx,
                        a + nx
                    )
                    .unwrap();
                }
            }
        }
        let m = parse_obj(s.as_bytes()).unwrap();
        assert_eq!(m.triangles.len(), 1_000_000);
        assert_eq!(m.positions.len(), nx * ny);
    }

    #[test]
    fn vertices_are_split_by_texture_coordinate_and_carry_their_uvs() {
        let src = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0.5\nf 1/1 2/2 3/-1 4\nf 1 2 3/x\n";
        let m = parse_obj(src).unwrap();
        // (vertex, vt) pairs in order of first use: (1,1) (2,2) (3,2) (1,-) (4,-) (2,-) (3,-).
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3], [4, 5, 6]]);
        let (z, h) = (Vec2::ZERO, Vec2::new(1.0, 0.5));
        assert_eq!(m.uvs, vec![z, h, h, z, z, z, z]);
        assert_eq!(m.positions[3], Vec3::new(1.0, 1.0, 0.0));
        assert!(parse_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap().uvs.is_empty());
        // With normals too: a vertex per (position, normal, texture coordinate).
        let with_vn = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.75\nvt 1 1\nvn 0 0 1\nf 1/1/1 2/1/1 3/2/1\nf 1/2/1 2/1/1 3/2/1\n";
        let m = parse_obj(with_vn).unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2], [3, 1, 2]]);
        assert_eq!(m.uvs, vec![Vec2::new(0.25, 0.75), Vec2::new(0.25, 0.75), Vec2::ONE, Vec2::ONE]);
        assert_eq!(m.normals, vec![Vec3::Z; 4]);
        // Bad texture coordinates are errors on their line.
        let e = parse_obj(b"v 0 0 0\nvt 0 nan\n").unwrap_err();
        assert_eq!(e.line, 2, "{}", e.message);
        let e = parse_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n").unwrap_err();
        assert_eq!(e.line, 5);
        assert!(e.message.contains("texture coordinate 2"), "{}", e.message);
    }

    /// The three faces of a unit cube meeting at its corner at the origin, outward (−z, −x, −y),
    /// split unevenly around the corner: −x and −y by two triangles of area ½, −z by three
    /// small ones (26.6°, 18.4° and 45°, of total area ¼).
    fn uneven_corner() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let v = |x, y, z| Vec3::new(x, y, z);
        let positions = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            v(0.0, 1.0, 1.0),
            v(1.0, 0.0, 1.0),
            v(0.5, 0.25, 0.0),
            v(0.5, 0.5, 0.0),
            v(0.5, 0.0, 0.0),
            v(0.0, 0.5, 0.0),
        ];
        let triangles = vec![[0, 6, 8], [0, 7, 6], [0, 9, 7], [0, 3, 4], [0, 4, 2], [0, 1, 5], [0, 5, 3]];
        (positions, triangles)
    }

    #[test]
    fn generated_normals_are_angle_weighted() {
        // Each face spans a right angle at the corner however it is split, so the angle-weighted
        // normal is the diagonal; weighting by triangle count (3:2:2) would tilt it towards −z,
        // by area (¼:1:1) away from it.
        let (positions, triangles) = uneven_corner();
        let m = generated_vertex_normals(positions, triangles);
        let d = -Vec3::ONE.normalize();
        assert!((m.normals[0] - d).length() < 1e-6, "{} != {d}", m.normals[0]);
        // (0.5, 0.5, 0) is only on −z.
        assert!((m.normals[7] - -Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn generated_normals_split_vertices_by_texcoord() {
        let (positions, triangles) = uneven_corner();
        // The −z triangles use texture coordinate 1 at the corner, the others 2: the corner
        // becomes two vertices, each smoothed over its own triangles.
        let mut src = String::new();
        positions.iter().for_each(|p| src += &format!("v {} {} {}\n", p.x, p.y, p.z));
        src += "vt 0 0\nvt 1 1\n";
        for (i, t) in triangles.iter().enumerate() {
            let k = if i < 3 { 1 } else { 2 };
            src += &format!("f {}/{k} {}/{k} {}/{k}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        let split = parse_obj(src.as_bytes()).unwrap();
        let m = generated_vertex_normals(split.positions, split.triangles);
        let corners: Vec<u32> = m.triangles.iter().map(|t| t[0]).collect();
        let (z, xy) = (corners[0], corners[3]);
        assert_eq!(corners, [vec![z; 3], vec![xy; 4]].concat());
        assert_ne!(z, xy);
        let (z, xy) = (z as usize, xy as usize);
        assert_eq!(m.positions[z], m.positions[xy]);
        assert!((m.normals[z] - -Vec3::Z).length() < 1e-6);
        let d = -Vec3::new(1.0, 1.0, 0.0).normalize();
        assert!((m.normals[xy] - d).length() < 1e-6, "{}", m.normals[xy]);
        // A vertex no triangle with area uses gets Mitsuba's placeholder.
        let m = generated_vertex_normals(vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0], vec![[0, 1, 2]]);
        assert_eq!(m.normals, vec![Vec3::X; 3]);
    }
}
