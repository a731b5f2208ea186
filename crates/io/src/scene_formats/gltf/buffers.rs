//! glTF buffer data: the GLB `BIN` chunk, `data:` URIs (base64) and external files (relative to
//! the glTF file's folder, percent-decoded), and bounds-checked reads of accessors from them.
//!
//! The `gltf` crate's own `import` feature is not used: its URI decoding panics on malformed
//! percent-escapes (`urlencoding::decode(..).unwrap()`), its I/O errors do not say which file is
//! missing, and it drags in JPEG/PNG decoders for textures Opticks ignores. Its accessor iterators
//! are not used either: they `debug_assert!` that the accessor's type matches the one asked for,
//! which malformed files break. Every read here is checked and ends in an error message instead.

use ::gltf::accessor::{Accessor, DataType, Dimensions};
use ::gltf::buffer::Source;
use std::path::{Path, PathBuf};

/// Why a buffer could not be loaded.
#[derive(Debug)]
pub enum BufferError {
    /// An external buffer file cannot be read.
    File {
        /// The file as resolved.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// Anything else (bad URI, bad base64, missing BIN chunk, too short), as a message.
    Other(String),
}

/// Loads the data of every buffer of `doc`, in index order.
pub fn load_buffers(
    doc: &::gltf::Document,
    blob: Option<&[u8]>,
    folder: &Path,
) -> Result<Vec<Vec<u8>>, (usize, BufferError)> {
    let mut out = Vec::new();
    for buffer in doc.buffers() {
        let i = buffer.index();
        let data = match buffer.source() {
            Source::Bin => blob.map(<[u8]>::to_vec).ok_or_else(|| {
                (i, BufferError::Other("refers to the GLB binary chunk, but the file has none".into()))
            })?,
            Source::Uri(uri) => read_uri(uri, folder).map_err(|e| (i, e))?,
        };
        if data.len() < buffer.length() {
            return Err((
                i,
                BufferError::Other(format!(
                    "has {} bytes, but byteLength says {}",
                    data.len(),
                    buffer.length()
                )),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// The data a buffer's or an image's `uri` refers to: a base64 `data:` URI, or a file relative
/// to `folder` (percent-escapes decoded, `file:` allowed); other schemes are errors.
pub fn read_uri(uri: &str, folder: &Path) -> Result<Vec<u8>, BufferError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((_, b64)) = rest.split_once(";base64,") else {
            return Err(BufferError::Other("data: URI is not base64-encoded".into()));
        };
        decode_base64(b64).map_err(|m| BufferError::Other(format!("data: URI: {m}")))
    } else if uri.contains(':') && !uri.starts_with("file:") {
        Err(BufferError::Other(format!("unsupported URI scheme in {uri:?}")))
    } else {
        let rel = uri.strip_prefix("file://").or_else(|| uri.strip_prefix("file:")).unwrap_or(uri);
        let rel = percent_decode(rel)
            .ok_or_else(|| BufferError::Other(format!("malformed percent-escape in URI {uri:?}")))?;
        let path = folder.join(rel);
        crate::input_file::read(&path).map_err(|source| BufferError::File { path, source })
    }
}

/// The bytes of buffer view `view`, bounds-checked (an image stored in a buffer).
pub fn view_bytes<'a>(view: &::gltf::buffer::View<'_>, buffers: &'a [Vec<u8>]) -> Result<&'a [u8], String> {
    let data = buffers.get(view.buffer().index()).ok_or("buffer view refers to a missing buffer")?;
    let end = view.offset().checked_add(view.length()).ok_or("buffer view is too large")?;
    data.get(view.offset()..end).ok_or_else(|| {
        format!(
            "buffer view {} (bytes {}..{end}) lies outside buffer {} ({} bytes)",
            view.index(),
            view.offset(),
            view.buffer().index(),
            data.len()
        )
    })
}

/// Standard base64 (RFC 4648, `+/`, optional `=` padding; whitespace is not allowed).
pub fn decode_base64(s: &str) -> Result<Vec<u8>, String> {
    let s = s.trim_end_matches('=');
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    let mut acc = 0u32;
    let mut bits = 0u32;
    for (pos, c) in s.bytes().enumerate() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => return Err(format!("invalid base64 character {:?} at offset {pos}", c as char)),
        };
        acc = (acc << 6) | v as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    if bits >= 6 {
        return Err("truncated base64 data".into());
    }
    Ok(out)
}

/// `%XX` escapes decoded; `None` if an escape is malformed or the result is not UTF-8.
pub fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = b.get(i + 1..i + 3)?;
            let hex = std::str::from_utf8(hex).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Largest element count of an accessor without a buffer view (such an accessor reads as zeros).
const MAX_VIEWLESS_COUNT: usize = 1 << 24;

/// The bytes of each element of `acc` (`count` slices of `elem_size` bytes), bounds-checked.
/// `None` elements (an accessor without a buffer view) read as zeros.
fn elements<'a>(
    acc: &Accessor<'_>,
    buffers: &'a [Vec<u8>],
    elem_size: usize,
) -> Result<Option<(&'a [u8], usize)>, String> {
    if acc.sparse().is_some() {
        return Err("sparse accessors are not supported".into());
    }
    let Some(view) = acc.view() else {
        // All zeros; refuse absurd counts rather than allocate them.
        return if acc.count() <= MAX_VIEWLESS_COUNT {
            Ok(None)
        } else {
            Err(format!("accessor {} has no buffer view and {} elements", acc.index(), acc.count()))
        };
    };
    let view_data = view_bytes(&view, buffers)?;
    let stride = view.stride().unwrap_or(elem_size);
    if stride < elem_size {
        return Err(format!("byteStride {stride} is smaller than the element size {elem_size}"));
    }
    let count = acc.count();
    if count == 0 {
        return Ok(Some((&[], stride)));
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(elem_size))
        .and_then(|x| x.checked_add(acc.offset()))
        .ok_or("accessor is too large")?;
    let bytes = view_data.get(acc.offset()..end).ok_or_else(|| {
        format!(
            "accessor {} needs bytes {}..{end} of buffer view {}, which has {} bytes",
            acc.index(),
            acc.offset(),
            view.index(),
            view_data.len()
        )
    })?;
    Ok(Some((bytes, stride)))
}

/// Reads a `VEC3`/`FLOAT` accessor.
pub fn read_vec3(acc: &Accessor<'_>, buffers: &[Vec<u8>]) -> Result<Vec<[f32; 3]>, String> {
    if acc.dimensions() != Dimensions::Vec3 || acc.data_type() != DataType::F32 {
        return Err(format!(
            "accessor {} is {:?} of {:?}; positions must be Vec3 of F32 (quantized positions are not supported)",
            acc.index(),
            acc.dimensions(),
            acc.data_type()
        ));
    }
    let count = acc.count();
    let Some((bytes, stride)) = elements(acc, buffers, 12)? else { return Ok(vec![[0.0; 3]; count]) };
    let f = |b: &[u8], k: usize| f32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]]);
    Ok((0..count).map(|i| &bytes[i * stride..i * stride + 12]).map(|b| [f(b, 0), f(b, 1), f(b, 2)]).collect())
}

/// Reads a `VEC2` texture-coordinate accessor: `FLOAT`, or normalized `UNSIGNED_BYTE` /
/// `UNSIGNED_SHORT` (divided by 255 or 65535, as glTF's `TEXCOORD_n` allows).
pub fn read_vec2(acc: &Accessor<'_>, buffers: &[Vec<u8>]) -> Result<Vec<[f32; 2]>, String> {
    let size = match (acc.dimensions(), acc.data_type(), acc.normalized()) {
        (Dimensions::Vec2, DataType::F32, _) => 4,
        (Dimensions::Vec2, DataType::U8, true) => 1,
        (Dimensions::Vec2, DataType::U16, true) => 2,
        (d, t, n) => {
            return Err(format!(
                "accessor {} is {d:?} of {t:?}{}; texture coordinates must be Vec2 of F32, or of normalized U8 or U16",
                acc.index(),
                if n { " (normalized)" } else { "" }
            ));
        }
    };
    let count = acc.count();
    let Some((bytes, stride)) = elements(acc, buffers, 2 * size)? else { return Ok(vec![[0.0; 2]; count]) };
    let c = |b: &[u8], k: usize| match size {
        1 => b[k] as f32 / 255.0,
        2 => u16::from_le_bytes([b[2 * k], b[2 * k + 1]]) as f32 / 65535.0,
        _ => f32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]]),
    };
    Ok((0..count).map(|i| &bytes[i * stride..i * stride + 2 * size]).map(|b| [c(b, 0), c(b, 1)]).collect())
}

/// Reads a `SCALAR` index accessor of unsigned bytes, shorts or ints.
pub fn read_indices(acc: &Accessor<'_>, buffers: &[Vec<u8>]) -> Result<Vec<u32>, String> {
    let size = match (acc.dimensions(), acc.data_type()) {
        (Dimensions::Scalar, DataType::U8) => 1,
        (Dimensions::Scalar, DataType::U16) => 2,
        (Dimensions::Scalar, DataType::U32) => 4,
        (d, t) => {
            return Err(format!(
                "index accessor {} is {d:?} of {t:?}; indices must be scalars of U8, U16 or U32",
                acc.index()
            ));
        }
    };
    let count = acc.count();
    let Some((bytes, stride)) = elements(acc, buffers, size)? else { return Ok(vec![0; count]) };
    Ok((0..count)
        .map(|i| {
            let b = &bytes[i * stride..i * stride + size];
            match size {
                1 => b[0] as u32,
                2 => u16::from_le_bytes([b[0], b[1]]) as u32,
                _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips_known_vectors() {
        assert_eq!(decode_base64("").unwrap(), b"");
        assert_eq!(decode_base64("Zg==").unwrap(), b"f");
        assert_eq!(decode_base64("Zm8=").unwrap(), b"fo");
        assert_eq!(decode_base64("Zm9v").unwrap(), b"foo");
        assert_eq!(decode_base64("Zm9vYmFy").unwrap(), b"foobar");
        assert!(decode_base64("Zm9v!").is_err());
        assert!(decode_base64("Z").is_err());
    }

    #[test]
    fn percent_escapes() {
        assert_eq!(percent_decode("a%20b.bin").as_deref(), Some("a b.bin"));
        assert_eq!(percent_decode("plain.bin").as_deref(), Some("plain.bin"));
        assert_eq!(percent_decode("bad%2"), None);
        assert_eq!(percent_decode("bad%zz"), None);
        assert_eq!(percent_decode("%ff"), None);
    }
}
