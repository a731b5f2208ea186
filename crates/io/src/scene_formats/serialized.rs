//! Mitsuba's `.serialized` meshes (`<shape type="serialized">`), file-format versions 3 and 4
//! (the ones Mitsuba 0.5–3 write with `Mesh::write_serialized` before 3.9, and the files of
//! Mitsuba's scene collections). Version 5, the packed layout Mitsuba 3.9 writes, is refused
//! with a clear error (convert the mesh to PLY).
//!
//! Layout (little-endian): per mesh, `u16` magic `0x041C`, `u16` version, then a zlib stream of
//! `u32` flags (`0x1` normals, `0x2` texture coordinates, `0x8` vertex colours, `0x2000` double
//! precision), the shape name (version 4: NUL-terminated), `u64` vertex count V, `u64` triangle
//! count F, V positions, V normals, V texture coordinates, V colours (as flagged), and 3F `u32`
//! indices. Several meshes are concatenated; the file ends with the offset of each mesh (`u64`
//! in version 4, `u32` in version 3) and their `u32` count, which `shape_index` selects from.
//!
//! # Robustness
//!
//! The counts come from the compressed stream, so they cannot be checked against the file's
//! size directly; instead nothing is allocated from them: the stream is decompressed only up to
//! the bytes the counts call for, into a buffer that grows as data actually arrives (so a
//! count of 10¹² ends with "the stream ends after …", having allocated what the stream held),
//! and a mesh of more than 2³² vertices is refused. Zlib expands zeros about a thousandfold, so
//! a stream's real data can still be far larger than the file (a 391 KB file of zeros claiming
//! 2²⁴ vertices took 794 MB): the bytes the counts call for are also bounded by a limit times
//! the compressed bytes of the mesh ([`MAX_EXPANSION`] by default; [`parse_serialized_within`]
//! and [`LoadLimits::max_mesh_expansion`](crate::scene_formats::LoadLimits::max_mesh_expansion)
//! set another, the CLI's `--max-mesh-expansion`), checked before anything is decompressed, and
//! the buffer is reserved once at that size. A mesh's memory is then at most about twice that
//! limit times its compressed bytes (the decompressed bytes, and the mesh read from them). Errors give the byte offset in
//! the file (for the compressed part: where the mesh's stream starts, and the offset inside the
//! decompressed data).
//!
//! The dictionary's offsets must increase strictly (each mesh starts after the one before and
//! before the dictionary): offsets that alias one another (two `shape_index` values naming the
//! same mesh) are refused, and a mesh's stream is read no further than where the next one
//! starts.

use super::mesh_bytes::{Bytes, MeshData, MeshFileError, check_mesh};
use opticks_core::math::{Vec2, Vec3};
use std::io::Read;

const MAGIC: u16 = 0x041C;

/// The most bytes a mesh's header may call for per compressed byte of its stream unless the
/// caller says otherwise (the decompressed mesh is at most this many times the compressed one).
/// Real meshes compress 2–10 times; zlib's own limit is about 1032 (long runs of one byte),
/// which only forged files, or meshes of one repeated value, reach.
pub const MAX_EXPANSION: u64 = 128;

/// Reads mesh `shape_index` of a `.serialized` file's bytes, expanding at most
/// [`MAX_EXPANSION`] times.
pub fn parse_serialized(data: &[u8], shape_index: u64) -> Result<MeshData, MeshFileError> {
    parse_serialized_within(data, shape_index, MAX_EXPANSION)
}

/// [`parse_serialized`] with a mesh's counts allowed to call for at most `max_expansion` bytes
/// per byte of its compressed stream (instead of [`MAX_EXPANSION`]); more is an error before
/// anything is decompressed.
pub fn parse_serialized_within(
    data: &[u8],
    shape_index: u64,
    max_expansion: u64,
) -> Result<MeshData, MeshFileError> {
    let mut head = Bytes::new(data, 0, false);
    let (version, start) = {
        let magic = head.u16()?;
        if magic != MAGIC {
            return Err(MeshFileError {
                offset: 0,
                line: 0,
                message: format!("not a Mitsuba serialized mesh (magic {magic:#06x}, expected 0x041c)"),
            });
        }
        let version = head.u16()?;
        (version, 0usize)
    };
    if version == 5 {
        return Err(head.error(
            "serialized format version 5 (Mitsuba 3.9's packed meshes) is not supported; \
             use a version 3/4 file or convert the mesh to PLY",
        ));
    }
    if version != 3 && version != 4 {
        return Err(MeshFileError {
            offset: 2,
            line: 0,
            message: format!("unsupported serialized format version {version} (supported: 3, 4)"),
        });
    }
    let (start, end) =
        if shape_index == 0 { (start, data.len()) } else { sub_mesh_offset(data, version, shape_index)? };
    let mut h = Bytes::new(&data[start..end], start as u64, false);
    if h.u16()? != MAGIC || h.u16()? != version {
        return Err(h.error(format!("mesh {shape_index} does not start with the serialized header")));
    }
    let stream_at = h.offset();
    let compressed = &data[stream_at as usize..end];
    decode(compressed, version, stream_at, max_expansion)
}

/// The file offsets where mesh `index` starts and where its bytes end (the next mesh, or the
/// dictionary), from the dictionary at the end of the file, whose offsets must increase.
fn sub_mesh_offset(data: &[u8], version: u16, index: u64) -> Result<(usize, usize), MeshFileError> {
    let n = data.len();
    let err = |offset: usize, message: String| MeshFileError { offset: offset as u64, line: 0, message };
    if n < 8 {
        return Err(err(n, "the file is too short for its mesh dictionary".into()));
    }
    let count = Bytes::new(&data[n - 4..], (n - 4) as u64, false).u32()? as u64;
    if index >= count {
        return Err(err(
            n - 4,
            format!(
                "shape_index {index} is out of range: the file holds {count} meshes (0..{})",
                count.max(1) - 1
            ),
        ));
    }
    let width = if version >= 4 { 8 } else { 4 };
    let dictionary = (count as usize).checked_mul(width).and_then(|d| d.checked_add(4)).filter(|&d| d <= n);
    let Some(dictionary) = dictionary else {
        return Err(err(n - 4, format!("the dictionary of {count} meshes does not fit in the file")));
    };
    // Every entry up to the one after `index` (bounded by the file's size, checked above).
    let dict_at = n - dictionary;
    let mut b = Bytes::new(&data[dict_at..n - 4], dict_at as u64, false);
    let mut previous: Option<u64> = None;
    let mut start = 0;
    for k in 0..=index.saturating_add(1).min(count - 1) {
        let at = b.offset() as usize;
        let offset = if width == 8 { b.u64()? } else { b.u32()? as u64 };
        if offset >= dict_at as u64 {
            return Err(err(
                at,
                format!("mesh {k} starts at {offset}, not before the dictionary (at {dict_at})"),
            ));
        }
        if let Some(p) = previous.filter(|&p| offset <= p) {
            return Err(err(
                at,
                format!(
                    "mesh {k} starts at {offset}, not after mesh {} (at {p}): the dictionary's offsets must increase",
                    k - 1
                ),
            ));
        }
        if k == index {
            start = offset as usize;
        } else if k == index + 1 {
            return Ok((start, offset as usize));
        }
        previous = Some(offset);
    }
    Ok((start, dict_at))
}

/// Decompresses and reads one mesh stream starting at file offset `at`, expanding at most
/// `max_expansion` times.
fn decode(compressed: &[u8], version: u16, at: u64, max_expansion: u64) -> Result<MeshData, MeshFileError> {
    let mut z = flate2::read::ZlibDecoder::new(compressed);
    let mut buf = Vec::new();
    let mut fill = |buf: &mut Vec<u8>, total: u64| -> Result<(), MeshFileError> {
        let want = total.saturating_sub(buf.len() as u64);
        let got = (&mut z).take(want).read_to_end(buf).map_err(|e| MeshFileError {
            offset: at,
            line: 0,
            message: format!("the compressed mesh stream starting here is corrupt: {e}"),
        })?;
        if (got as u64) < want {
            return Err(MeshFileError {
                offset: at,
                line: 0,
                message: format!(
                    "the compressed mesh stream starting here ends after {} bytes; its header calls for {total}",
                    buf.len()
                ),
            });
        }
        Ok(())
    };
    // Flags, the name, the counts: read a little at a time (the name's length is not known).
    fill(&mut buf, 4)?;
    if version == 4 {
        loop {
            let len = buf.len() as u64;
            fill(&mut buf, len + 1)?;
            if buf.last() == Some(&0) {
                break;
            }
            if len > 1 << 16 {
                return Err(MeshFileError {
                    offset: at,
                    line: 0,
                    message: "the shape name is not terminated".into(),
                });
            }
        }
    }
    let head_len = buf.len() as u64 + 16;
    fill(&mut buf, head_len)?;
    let mut b = Bytes::new(&buf, 0, false);
    let flags = b.u32()?;
    if version == 4 {
        while b.u8()? != 0 {}
    }
    let (v, f) = (b.u64()?, b.u64()?);
    let located = |e: MeshFileError| MeshFileError {
        offset: at,
        line: 0,
        message: format!("{} (at byte {} of the decompressed mesh)", e.message, e.offset),
    };
    if v > u32::MAX as u64 {
        return Err(located(b.error(format!("{v} vertices is more than a mesh can index (2³²)"))));
    }
    let real = if flags & 0x2000 != 0 { 8u64 } else { 4 };
    let per_vertex =
        real * (3 + 3 * (flags & 1 != 0) as u64 + 2 * (flags & 2 != 0) as u64 + 3 * (flags & 8 != 0) as u64);
    let total = v
        .checked_mul(per_vertex)
        .and_then(|x| f.checked_mul(12).and_then(|y| x.checked_add(y)))
        .and_then(|x| x.checked_add(head_len))
        .ok_or_else(|| located(b.error(format!("{v} vertices and {f} triangles overflow"))))?;
    let limit = max_expansion.saturating_mul(compressed.len() as u64);
    if total > limit {
        return Err(located(b.error(format!(
            "{v} vertices and {f} triangles call for {total} bytes, {:.1} times the {} compressed bytes \
             of the mesh; the limit is {max_expansion} times (--max-mesh-expansion raises it)",
            total as f64 / compressed.len().max(1) as f64,
            compressed.len()
        ))));
    }
    let counts_at = b.offset();
    buf.try_reserve_exact((total as usize).saturating_sub(buf.len())).map_err(|e| {
        let message = format!("{total} bytes for {v} vertices and {f} triangles: {e}");
        located(MeshFileError { offset: counts_at, line: 0, message })
    })?;
    fill(&mut buf, total)?;
    let mut b = Bytes::new(&buf[head_len as usize..], head_len, false);
    let read_vec = |b: &mut Bytes, dim: usize| -> Result<Vec<[f32; 3]>, MeshFileError> {
        let mut out = Vec::with_capacity(v as usize); // the bytes are in `buf`
        for _ in 0..v {
            let mut x = [0.0f32; 3];
            for c in x.iter_mut().take(dim) {
                *c = if real == 8 { b.f64()? as f32 } else { b.f32()? };
            }
            out.push(x);
        }
        Ok(out)
    };
    let mut mesh = MeshData {
        positions: read_vec(&mut b, 3).map_err(located)?.into_iter().map(Vec3::from_array).collect(),
        ..Default::default()
    };
    if flags & 1 != 0 {
        mesh.normals = read_vec(&mut b, 3).map_err(located)?.into_iter().map(Vec3::from_array).collect();
    }
    if flags & 2 != 0 {
        mesh.uvs = read_vec(&mut b, 2).map_err(located)?.into_iter().map(|x| Vec2::new(x[0], x[1])).collect();
    }
    if flags & 8 != 0 {
        read_vec(&mut b, 3).map_err(located)?; // vertex colours: not used
    }
    mesh.triangles = Vec::with_capacity(f as usize);
    for _ in 0..f {
        mesh.triangles.push([
            b.u32().map_err(located)?,
            b.u32().map_err(located)?,
            b.u32().map_err(located)?,
        ]);
    }
    check_mesh(&mesh, at)?;
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    /// A mesh to write: positions, triangles, whether to store (+z) normals.
    type TestMesh<'a> = (&'a [[f32; 3]], &'a [[u32; 3]], bool);

    /// A version-4 file of `meshes` and its dictionary.
    pub fn write_v4(meshes: &[TestMesh]) -> Vec<u8> {
        let mut out = Vec::new();
        let mut offsets = Vec::new();
        for (p, t, normals) in meshes {
            offsets.push(out.len() as u64);
            out.extend(MAGIC.to_le_bytes());
            out.extend(4u16.to_le_bytes());
            let mut raw = Vec::new();
            raw.extend((0x1000u32 | *normals as u32).to_le_bytes());
            raw.extend(b"mesh\0");
            raw.extend((p.len() as u64).to_le_bytes());
            raw.extend((t.len() as u64).to_le_bytes());
            p.iter().flatten().for_each(|x| raw.extend(x.to_le_bytes()));
            if *normals {
                p.iter().for_each(|_| [0.0f32, 0.0, 1.0].iter().for_each(|x| raw.extend(x.to_le_bytes())));
            }
            t.iter().flatten().for_each(|i| raw.extend(i.to_le_bytes()));
            let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
            z.write_all(&raw).unwrap();
            out.extend(z.finish().unwrap());
        }
        offsets.iter().for_each(|o| out.extend(o.to_le_bytes()));
        out.extend((meshes.len() as u32).to_le_bytes());
        out
    }

    const TRI: &[[f32; 3]] = &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    const QUAD: &[[f32; 3]] = &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];

    #[test]
    fn reads_each_mesh_of_a_file() {
        let d = write_v4(&[(TRI, &[[0, 1, 2]], false), (QUAD, &[[0, 1, 2], [0, 2, 3]], true)]);
        let a = parse_serialized(&d, 0).unwrap();
        assert_eq!((a.positions.len(), a.triangles.len(), a.normals.len()), (3, 1, 0));
        let b = parse_serialized(&d, 1).unwrap();
        assert_eq!(
            (b.positions[2], b.triangles[1], b.normals[3]),
            (Vec3::new(1.0, 1.0, 0.0), [0, 2, 3], Vec3::Z)
        );
        let e = parse_serialized(&d, 2).unwrap_err();
        assert!(e.message.contains("shape_index 2 is out of range: the file holds 2 meshes"), "{e:?}");
    }

    #[test]
    fn bad_files_are_located_errors() {
        let d = write_v4(&[(TRI, &[[0, 1, 3]], false)]);
        let e = parse_serialized(&d, 0).unwrap_err();
        assert!(
            e.message.contains("face 0 refers to vertex [0, 1, 3], but the mesh has 3 vertices"),
            "{e:?}"
        );
        assert_eq!(e.offset, 4);
        let e = parse_serialized(b"\x1c\x04\x05\x00", 0).unwrap_err();
        assert!(e.message.contains("version 5"), "{e:?}");
        assert!(parse_serialized(b"PK\x03\x04", 0).unwrap_err().message.contains("not a Mitsuba serialized"));
        // A header claiming 10¹² vertices in a stream of a few bytes: an error, no allocation.
        let mut raw = Vec::new();
        raw.extend(0x1000u32.to_le_bytes());
        raw.extend(b"\0");
        raw.extend(1_000_000_000_000u64.to_le_bytes());
        raw.extend(0u64.to_le_bytes());
        let mut z = flate2::write::ZlibEncoder::new(vec![0x1c, 0x04, 4, 0], flate2::Compression::default());
        z.write_all(&raw).unwrap();
        let e = parse_serialized(&z.finish().unwrap(), 0).unwrap_err();
        assert!(e.message.contains("more than a mesh can index"), "{e:?}");
        let mut raw = Vec::new();
        raw.extend(0x1000u32.to_le_bytes());
        raw.extend(b"\0");
        raw.extend(1000u64.to_le_bytes());
        raw.extend(1_000_000_000_000u64.to_le_bytes());
        let mut z = flate2::write::ZlibEncoder::new(vec![0x1c, 0x04, 4, 0], flate2::Compression::default());
        z.write_all(&raw).unwrap();
        let e = parse_serialized(&z.finish().unwrap(), 0).unwrap_err();
        assert!(e.message.contains("the limit is 128 times"), "{e:?}");
        let mut raw = Vec::new();
        raw.extend(0x1000u32.to_le_bytes());
        raw.extend(b"\0");
        raw.extend(3u64.to_le_bytes());
        raw.extend(1u64.to_le_bytes());
        let mut z = flate2::write::ZlibEncoder::new(vec![0x1c, 0x04, 4, 0], flate2::Compression::default());
        z.write_all(&raw).unwrap();
        let e = parse_serialized(&z.finish().unwrap(), 0).unwrap_err();
        assert!(e.message.contains("ends after 21 bytes; its header calls for 69"), "{e:?}");
        // Corrupt compressed data.
        let mut d = write_v4(&[(TRI, &[[0, 1, 2]], false)]);
        d[8] ^= 0xff;
        d[9] ^= 0xff;
        assert!(parse_serialized(&d, 0).is_err());
    }

    /// Issue 26: a dictionary whose entries alias one another loaded mesh 0 for shape_index 2.
    #[test]
    fn aliased_or_decreasing_dictionary_offsets_are_refused() {
        let three = [
            (TRI, &[[0, 1, 2]][..], false),
            (QUAD, &[[0, 1, 2], [0, 2, 3]][..], false),
            (TRI, &[[0, 2, 1]][..], false),
        ];
        let good = write_v4(&three);
        assert_eq!(parse_serialized(&good, 2).unwrap().triangles, [[0, 2, 1]]);
        let n = good.len();
        // Entry 2 := entry 0.
        let mut d = good.clone();
        let (e0, e2) = (n - 4 - 24, n - 4 - 8);
        d.copy_within(e0..e0 + 8, e2);
        let e = parse_serialized(&d, 2).unwrap_err();
        assert_eq!(e.offset, e2 as u64, "{e:?}");
        assert!(e.message.contains("mesh 2 starts at 0, not after mesh 1"), "{e:?}");
        // Entry 1 past the dictionary's start.
        let mut d = good.clone();
        d[e0 + 8..e0 + 16].copy_from_slice(&((n - 10) as u64).to_le_bytes());
        let e = parse_serialized(&d, 1).unwrap_err();
        assert!(e.message.contains("not before the dictionary"), "{e:?}");
        // Mesh 1's stream is read no further than mesh 2's start: cut it short there.
        let mut d = good;
        let m2 = u64::from_le_bytes(d[e2..e2 + 8].try_into().unwrap());
        d[e0 + 16..e0 + 24].copy_from_slice(&(m2 - 20).to_le_bytes());
        assert!(parse_serialized(&d, 1).is_err());
    }

    /// Issue 26: zlib of zeros claiming 2²⁴ vertices (391 KB) took 794 MB; counts calling for
    /// more than MAX_EXPANSION times the compressed bytes are refused before decompressing.
    #[test]
    fn counts_beyond_the_expansion_limit_are_refused() {
        let v = 1u64 << 20;
        let mut z = flate2::write::ZlibEncoder::new(vec![0x1c, 0x04, 4, 0], flate2::Compression::best());
        let mut raw = Vec::new();
        raw.extend(0x1000u32.to_le_bytes());
        raw.extend(b"\0");
        raw.extend(v.to_le_bytes());
        raw.extend(0u64.to_le_bytes());
        z.write_all(&raw).unwrap();
        z.write_all(&vec![0u8; 12 << 20]).unwrap();
        let d = z.finish().unwrap();
        assert!(d.len() < (12 << 20) / 200, "{} bytes", d.len());
        let e = parse_serialized(&d, 0).unwrap_err();
        assert!(e.message.contains(&format!("{v} vertices and 0 triangles call for")), "{e:?}");
        assert!(e.message.contains("the limit is 128 times"), "{e:?}");
        assert!(e.message.contains("--max-mesh-expansion raises it"), "{e:?}");
    }

    /// The expansion limit is the caller's: a real mesh of one triangle repeated (zlib shrinks
    /// it about 700 times) is refused by default and loads with the limit raised; a plain mesh
    /// that loads by default is refused with the limit lowered below its own expansion.
    #[test]
    fn the_expansion_limit_is_the_callers() {
        let repeated = vec![[0, 1, 2]; 100_000];
        let d = write_v4(&[(TRI, &repeated, false)]);
        let e = parse_serialized(&d, 0).unwrap_err();
        assert!(e.message.contains("100000 triangles call for"), "{e:?}");
        assert!(e.message.contains("the limit is 128 times"), "{e:?}");
        assert_eq!(parse_serialized_within(&d, 0, 2000).unwrap().triangles.len(), 100_000);
        let d = write_v4(&[(QUAD, &[[0, 1, 2], [0, 2, 3]], true)]);
        assert!(parse_serialized(&d, 0).is_ok());
        let e = parse_serialized_within(&d, 0, 1).unwrap_err();
        assert!(e.message.contains("the limit is 1 times"), "{e:?}");
    }
}
