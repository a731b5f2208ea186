//! The geometry statements of an OBJ file (`v`, `vn`, `vt`, `f`) as the statement loop of
//! [`super::parse_obj_file`] hands them over: coordinates read and checked finite, face corners'
//! 1-based and relative indices resolved to corner ids (a position, or a (position, normal)
//! pair), polygons fanned, and — once the whole file is read, since faces may refer forward — the
//! check that no face refers past the last vertex, normal or texture coordinate. Kept apart from
//! the loop so the allocation-free token and number parsing lives in one place.

use super::vertices::ObjVertices;
use super::{NO_TEXCOORD, ObjError};
use opticks_core::math::{Vec2, Vec3};

/// Marks a face-corner id that names a (position, normal) pair of [`ObjGeometry`] rather than a
/// bare position.
pub(super) const NORMAL_CORNER: u32 = 1 << 31;

/// The whitespace-separated tokens of one OBJ line.
pub(super) fn line_tokens(raw: &[u8]) -> impl Iterator<Item = &[u8]> {
    raw.split(|&b| b == b' ' || b == b'\t' || b == b'\r').filter(|t| !t.is_empty())
}

/// The `v`, `vn`, `vt` and `f` statements: vertex positions and normals, face-corner index
/// resolution, and the check, once the whole file is read, that no face refers past the last
/// vertex or normal.
pub(super) struct ObjGeometry {
    /// Vertex positions, in file order.
    positions: Vec<Vec3>,
    /// Vertex normals (`vn`), in file order.
    normals: Vec<Vec3>,
    /// The distinct (position, normal) pairs of `v//vn` corners; a corner id
    /// `NORMAL_CORNER | k` names pair k.
    pairs: Vec<(u32, u32)>,
    pair_of: std::collections::HashMap<(u32, u32), u32>,
    /// Largest 0-based normal index referred to and its line (checked like `max_index`).
    max_normal: Option<(u32, u32)>,
    /// Largest 0-based index referred to and its line: checked by [`ObjGeometry::finish`], so
    /// faces may refer to vertices defined further down.
    max_index: Option<(u32, u32)>,
    /// The current face's corners (kept to reuse its allocation).
    corners: Vec<u32>,
    /// The largest 0-based vertex index a face may use (a caller may reserve `u32::MAX`).
    largest_index: u32,
    /// How many `vt` statements were read so far (for relative texture-coordinate indices).
    pub(super) texcoord_count: u32,
    /// The `vt` statements' (u, v), in file order.
    texcoords: Vec<Vec2>,
    /// Largest 0-based texture-coordinate index referred to and its line (checked like
    /// `max_index`).
    max_texcoord: Option<(u32, u32)>,
    /// The current face's texture-coordinate indices (kept to reuse its allocation).
    corner_texcoords: Vec<u32>,
}

impl ObjGeometry {
    /// An empty geometry whose faces may use 0-based indices up to `largest_index`.
    pub(super) fn new(largest_index: u32) -> Self {
        ObjGeometry {
            positions: Vec::new(),
            normals: Vec::new(),
            pairs: Vec::new(),
            pair_of: std::collections::HashMap::new(),
            max_normal: None,
            max_index: None,
            corners: Vec::with_capacity(16),
            largest_index: largest_index.min(NORMAL_CORNER - 1),
            texcoord_count: 0,
            texcoords: Vec::new(),
            max_texcoord: None,
            corner_texcoords: Vec::with_capacity(16),
        }
    }

    /// Reads the arguments of a `v` statement on line `line_no`.
    pub(super) fn vertex<'a>(
        &mut self,
        tokens: impl Iterator<Item = &'a [u8]>,
        line_no: u32,
    ) -> Result<(), ObjError> {
        let p = read_vec3(tokens, line_no, "vertex")?;
        self.positions.push(p);
        Ok(())
    }

    /// Reads the arguments of a `vt` statement on line `line_no`: u and v (0 if absent); a
    /// third coordinate is ignored.
    pub(super) fn texcoord<'a>(
        &mut self,
        mut tokens: impl Iterator<Item = &'a [u8]>,
        line_no: u32,
    ) -> Result<(), ObjError> {
        let mut uv = [0.0f32; 2];
        for (k, c) in uv.iter_mut().enumerate() {
            let Some(tok) = tokens.next() else {
                if k == 0 {
                    return Err(ObjError {
                        line: line_no,
                        message: "texture coordinate has no values".into(),
                    });
                }
                break;
            };
            *c = parse_f32(tok).filter(|x| x.is_finite()).ok_or_else(|| ObjError {
                line: line_no,
                message: format!("texture coordinate {:?} is not a finite number", lossy(tok)),
            })?;
        }
        self.texcoords.push(Vec2::from_array(uv));
        self.texcoord_count = self.texcoord_count.saturating_add(1);
        Ok(())
    }

    /// Reads the arguments of a `vn` statement on line `line_no`.
    pub(super) fn normal<'a>(
        &mut self,
        tokens: impl Iterator<Item = &'a [u8]>,
        line_no: u32,
    ) -> Result<(), ObjError> {
        let n = read_vec3(tokens, line_no, "vertex normal")?;
        if n == Vec3::ZERO {
            return Err(ObjError { line: line_no, message: "vertex normal is zero".into() });
        }
        self.normals.push(n);
        Ok(())
    }

    /// Reads the arguments of an `f` statement on line `line_no` and appends its fan of triangles
    /// (corner ids) to `triangles`, and with `texcoords` their texture-coordinate indices.
    pub(super) fn face<'a>(
        &mut self,
        tokens: impl Iterator<Item = &'a [u8]>,
        line_no: u32,
        triangles: &mut Vec<[u32; 3]>,
        mut texcoords: Option<&mut Vec<[u32; 3]>>,
    ) -> Result<(), ObjError> {
        let corners = &mut self.corners;
        corners.clear();
        self.corner_texcoords.clear();
        for tok in tokens {
            let mut fields = tok.split(|&b| b == b'/');
            let v = fields.next().unwrap_or(tok);
            let vt = fields.next();
            if texcoords.is_some() {
                let k = texcoord_index(vt, self.texcoord_count);
                if k != NO_TEXCOORD && self.max_texcoord.is_none_or(|(m, _)| k > m) {
                    self.max_texcoord = Some((k, line_no));
                }
                self.corner_texcoords.push(k);
            }
            // Normal indices before any `vn` are ignored (as they always were).
            let vn = fields.next().filter(|f| !f.is_empty() && !self.normals.is_empty());
            let i = parse_index(v).ok_or_else(|| ObjError {
                line: line_no,
                message: format!("face corner {:?} does not start with a vertex index", lossy(tok)),
            })?;
            let n = self.positions.len() as i64;
            let idx = match i {
                0 => {
                    return Err(ObjError {
                        line: line_no,
                        message: "face refers to vertex 0 (OBJ indices start at 1)".into(),
                    });
                }
                i if i > 0 => i - 1,
                i if n + i >= 0 => n + i,
                i => {
                    return Err(ObjError {
                        line: line_no,
                        message: format!(
                            "face refers to relative vertex {i}, but only {n} vertices are defined before this line"
                        ),
                    });
                }
            };
            let idx = u32::try_from(idx).ok().filter(|&x| x <= self.largest_index).ok_or_else(|| {
                ObjError { line: line_no, message: format!("face vertex index {i} is too large") }
            })?;
            if self.max_index.is_none_or(|(m, _)| idx > m) {
                self.max_index = Some((idx, line_no));
            }
            let id = match vn {
                None => idx,
                Some(vn) => {
                    let j = parse_index(vn).ok_or_else(|| ObjError {
                        line: line_no,
                        message: format!("face corner {:?}: normal index is not a number", lossy(tok)),
                    })?;
                    let count = self.normals.len() as i64;
                    let jdx = match j {
                        j if j > 0 => j - 1,
                        j if j < 0 && count + j >= 0 => count + j,
                        _ => {
                            return Err(ObjError {
                                line: line_no,
                                message: format!(
                                    "face corner {:?} refers to normal {j}, but only {count} normals are defined before this line",
                                    lossy(tok)
                                ),
                            });
                        }
                    };
                    let jdx = u32::try_from(jdx).ok().filter(|&x| x < NORMAL_CORNER).ok_or_else(|| {
                        ObjError { line: line_no, message: format!("face normal index {j} is too large") }
                    })?;
                    if self.max_normal.is_none_or(|(m, _)| jdx > m) {
                        self.max_normal = Some((jdx, line_no));
                    }
                    let next = self.pairs.len() as u32;
                    let k = *self.pair_of.entry((idx, jdx)).or_insert(next);
                    if k == next {
                        self.pairs.push((idx, jdx));
                    }
                    NORMAL_CORNER | k
                }
            };
            corners.push(id);
        }
        if corners.len() < 3 {
            return Err(ObjError {
                line: line_no,
                message: format!("face has {} corners, at least 3 are needed", corners.len()),
            });
        }
        for k in 1..corners.len() - 1 {
            triangles.push([corners[0], corners[k], corners[k + 1]]);
        }
        if let Some(texcoords) = texcoords.as_mut() {
            let t = &self.corner_texcoords;
            texcoords.extend((1..t.len() - 1).map(|k| [t[0], t[k], t[k + 1]]));
        }
        Ok(())
    }

    /// The vertices, once every face is checked against the number of vertices and normals in
    /// the file.
    pub(super) fn finish(self) -> Result<ObjVertices, ObjError> {
        past_end(self.max_normal, self.normals.len(), "normal", "normals")?;
        past_end(self.max_index, self.positions.len(), "vertex", "vertices")?;
        // Texture-coordinate indices in a file without `vt` are ignored, like normal indices.
        if !self.texcoords.is_empty() {
            past_end(self.max_texcoord, self.texcoords.len(), "texture coordinate", "texture coordinates")?;
        }
        Ok(ObjVertices {
            positions: self.positions,
            normals: self.normals,
            pairs: self.pairs,
            texcoords: self.texcoords,
        })
    }
}

/// The error of a face referring to (0-based) `max` (and the line of that face) when the file
/// defines only `count` of them.
fn past_end(max: Option<(u32, u32)>, count: usize, what: &str, plural: &str) -> Result<(), ObjError> {
    match max {
        Some((m, line)) if m as usize >= count => Err(ObjError {
            line,
            message: format!(
                "face refers to {what} {}, but the file defines only {count} {plural}",
                m as u64 + 1
            ),
        }),
        _ => Ok(()),
    }
}

/// The 0-based texture-coordinate index of a corner's `vt` field given `count` `vt` statements
/// so far, or [`NO_TEXCOORD`] if there is none or it cannot be read (`vt` is otherwise ignored,
/// so a bad one is not an error).
fn texcoord_index(vt: Option<&[u8]>, count: u32) -> u32 {
    match vt.and_then(parse_index) {
        Some(j) if j > 0 => u32::try_from(j - 1).unwrap_or(NO_TEXCOORD),
        Some(j) if j < 0 && i64::from(count) + j >= 0 => (i64::from(count) + j) as u32,
        _ => NO_TEXCOORD,
    }
}

/// Three finite coordinates of a `what` statement (`v`, `vn`) on line `line_no`.
fn read_vec3<'a>(
    mut tokens: impl Iterator<Item = &'a [u8]>,
    line_no: u32,
    what: &str,
) -> Result<Vec3, ObjError> {
    let mut p = [0.0f32; 3];
    for (axis, c) in p.iter_mut().enumerate() {
        let tok = tokens.next().ok_or_else(|| ObjError {
            line: line_no,
            message: format!("{what} has {axis} coordinates, expected 3"),
        })?;
        *c = parse_f32(tok).ok_or_else(|| ObjError {
            line: line_no,
            message: format!("{what} coordinate {:?} is not a number", lossy(tok)),
        })?;
        if !c.is_finite() {
            return Err(ObjError {
                line: line_no,
                message: format!("{what} coordinate {:?} is not finite", lossy(tok)),
            });
        }
    }
    Ok(Vec3::from_array(p))
}

fn lossy(tok: &[u8]) -> String {
    String::from_utf8_lossy(tok).into_owned()
}

#[inline]
fn parse_f32(tok: &[u8]) -> Option<f32> {
    std::str::from_utf8(tok).ok()?.parse().ok()
}

#[inline]
fn parse_index(tok: &[u8]) -> Option<i64> {
    let (neg, digits) = match tok.first()? {
        b'-' => (true, &tok[1..]),
        b'+' => (false, &tok[1..]),
        _ => (false, tok),
    };
    if digits.is_empty() || digits.len() > 12 {
        return None;
    }
    let mut v: i64 = 0;
    for &d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        v = v * 10 + (d - b'0') as i64;
    }
    Some(if neg { -v } else { v })
}
