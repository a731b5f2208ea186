//! What the binary mesh readers share ([`super::ply`], [`super::serialized`]): the mesh they
//! produce ([`MeshData`]), their located error ([`MeshFileError`]: a byte offset, or a line for
//! text), and [`Bytes`], a cursor over a byte slice that reads little- or big-endian numbers and
//! says at which offset it ran out.
//!
//! Robustness rule of both readers: a count read from a file is checked against the bytes that
//! can hold it ([`Bytes::check_count`]) before anything is allocated for it, so a header
//! declaring 10¹² vertices is an error, not an allocation.

use super::{FileLocation, SceneFileError};
use opticks_core::math::{Vec2, Vec3};
use opticks_core::scene::MeshAttribute;
use std::path::Path;

/// A triangle mesh as a mesh file stores it, before any transform.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Triangles, 0-based, counter-clockwise as written (polygons fanned).
    pub triangles: Vec<[u32; 3]>,
    /// One vertex normal per position, or empty.
    pub normals: Vec<Vec3>,
    /// One texture coordinate per position, or empty (read, kept for textures; not used by the
    /// renderer yet).
    pub uvs: Vec<Vec2>,
    /// The attributes asked for that the file has (Mitsuba's PLY attributes), one value per
    /// vertex or per triangle (a polygon's value on each of its triangles).
    pub attributes: Vec<MeshAttribute>,
}

/// What is wrong with a mesh file, and where.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MeshFileError {
    /// Byte offset in the file where the problem is.
    pub offset: u64,
    /// 1-based line for text (a PLY header, ASCII PLY), 0 for binary data.
    pub line: u32,
    /// What is wrong.
    pub message: String,
}

impl MeshFileError {
    /// The scene error of this problem in mesh file `path`, loaded by the scene element
    /// `referenced_from` (its description and location).
    pub fn in_file(self, path: &Path, referenced_from: Option<(String, FileLocation)>) -> SceneFileError {
        SceneFileError::MeshData {
            at: FileLocation { file: path.to_path_buf(), line: self.line, column: 0 },
            offset: self.offset,
            message: self.message,
            referenced_from,
        }
    }
}

/// Reads the mesh file `path` (a regular file: `crate::input_file`) and parses it with `parse`; errors name the file, the byte offset
/// and `referenced_from` (the scene element that loads it, and where).
pub fn read_mesh_file(
    path: &Path,
    referenced_from: Option<(String, FileLocation)>,
    parse: impl FnOnce(&[u8]) -> Result<MeshData, MeshFileError>,
) -> Result<MeshData, SceneFileError> {
    let data = read_bytes(path, referenced_from.as_ref())?;
    parse(&data).map_err(|e| e.in_file(path, referenced_from))
}

/// The bytes of mesh file `path`, loaded by `referenced_from` (the scene element and where it
/// is, for the error), of every mesh reader (OBJ too).
pub fn read_bytes(
    path: &Path,
    referenced_from: Option<&(String, FileLocation)>,
) -> Result<Vec<u8>, SceneFileError> {
    crate::input_file::read(path).map_err(|source| match referenced_from.cloned() {
        Some((element, at)) => SceneFileError::MeshFile { at, element, mesh: path.to_path_buf(), source },
        None => SceneFileError::Read { path: path.to_path_buf(), source },
    })
}

/// A cursor over `data`, whose first byte is at offset `origin` of the file (for messages).
pub struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
    origin: u64,
    /// Whether multi-byte numbers are big-endian.
    pub big_endian: bool,
}

impl<'a> Bytes<'a> {
    /// A cursor at the start of `data`, which starts at file offset `origin`.
    pub fn new(data: &'a [u8], origin: u64, big_endian: bool) -> Self {
        Bytes { data, pos: 0, origin, big_endian }
    }

    /// The file offset of the next byte.
    pub fn offset(&self) -> u64 {
        self.origin + self.pos as u64
    }

    /// The bytes left.
    pub fn rest(&self) -> &'a [u8] {
        &self.data[self.pos..]
    }

    /// Bytes left.
    pub fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    /// An error at the current offset.
    pub fn error(&self, message: impl Into<String>) -> MeshFileError {
        MeshFileError { offset: self.offset(), line: 0, message: message.into() }
    }

    /// An error unless `count` records of at least `min_bytes` bytes each fit in the bytes
    /// left; `what` names the records (`"vertices"`). Call it before allocating for `count`.
    pub fn check_count(&self, count: u64, min_bytes: u64, what: &str) -> Result<(), MeshFileError> {
        let needed = count.checked_mul(min_bytes);
        if needed.is_none_or(|n| n > self.remaining() as u64) {
            return Err(self.error(format!(
                "the file declares {count} {what} of at least {min_bytes} bytes each, but only {} bytes follow",
                self.remaining()
            )));
        }
        Ok(())
    }

    /// The next `n` bytes.
    pub fn take(&mut self, n: usize) -> Result<&'a [u8], MeshFileError> {
        if n > self.remaining() {
            return Err(self.error(format!("the file ends here ({n} more bytes expected)")));
        }
        let s = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], MeshFileError> {
        let mut a: [u8; N] = self.take(N)?.try_into().expect("N bytes");
        if self.big_endian {
            a.reverse();
        }
        Ok(a)
    }

    /// A `u8`.
    pub fn u8(&mut self) -> Result<u8, MeshFileError> {
        Ok(self.take(1)?[0])
    }

    /// A `u16`.
    pub fn u16(&mut self) -> Result<u16, MeshFileError> {
        self.array().map(u16::from_le_bytes)
    }

    /// A `u32`.
    pub fn u32(&mut self) -> Result<u32, MeshFileError> {
        self.array().map(u32::from_le_bytes)
    }

    /// A `u64`.
    pub fn u64(&mut self) -> Result<u64, MeshFileError> {
        self.array().map(u64::from_le_bytes)
    }

    /// An `i8`, `i16` or `i32` (by `bytes`), widened.
    pub fn signed(&mut self, bytes: usize) -> Result<i64, MeshFileError> {
        Ok(match bytes {
            1 => self.u8()? as i8 as i64,
            2 => self.u16()? as i16 as i64,
            _ => self.u32()? as i32 as i64,
        })
    }

    /// An `f32`.
    pub fn f32(&mut self) -> Result<f32, MeshFileError> {
        self.array().map(f32::from_le_bytes)
    }

    /// An `f64`.
    pub fn f64(&mut self) -> Result<f64, MeshFileError> {
        self.array().map(f64::from_le_bytes)
    }
}

/// Checks what every mesh file must satisfy once read: one normal and one texture coordinate
/// per vertex (or none), one value per vertex (`vertex_…`) or per triangle (`face_…`) for each
/// attribute, finite positions (and normals and texture coordinates), indices below the vertex
/// count. `at` gives the error's offset.
pub fn check_mesh(mesh: &MeshData, at: u64) -> Result<(), MeshFileError> {
    let err = |message: String| MeshFileError { offset: at, line: 0, message };
    let vertices = mesh.positions.len();
    for (what, len) in [("normals", mesh.normals.len()), ("texture coordinates", mesh.uvs.len())] {
        if len != 0 && len != vertices {
            return Err(err(format!("{len} {what} for {vertices} vertices (one per vertex, or none)")));
        }
    }
    for a in &mesh.attributes {
        let (per, n) = if a.name.starts_with("face_") {
            ("triangle", mesh.triangles.len())
        } else {
            ("vertex", vertices)
        };
        if a.values.len() != n {
            return Err(err(format!(
                "attribute {} has {} values for {n} (one per {per})",
                a.name,
                a.values.len()
            )));
        }
    }
    if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(err(format!("vertex {i} has a non-finite position {}", mesh.positions[i])));
    }
    if let Some(i) = mesh.normals.iter().position(|p| !p.is_finite()) {
        return Err(err(format!("vertex {i} has a non-finite normal {}", mesh.normals[i])));
    }
    if let Some(i) = mesh.uvs.iter().position(|p| !p.is_finite()) {
        return Err(err(format!("vertex {i} has non-finite texture coordinates {}", mesh.uvs[i])));
    }
    let n = mesh.positions.len() as u64;
    if let Some((f, t)) = mesh.triangles.iter().enumerate().find(|(_, t)| t.iter().any(|&i| i as u64 >= n)) {
        return Err(err(format!("face {f} refers to vertex {:?}, but the mesh has {n} vertices", t)));
    }
    Ok(())
}
