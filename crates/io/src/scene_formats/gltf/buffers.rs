//! glTF buffer data: the GLB `BIN` chunk, `data:` URIs (base64) and external files (relative to
//! the glTF file's folder, percent-decoded), and bounds-checked reads of accessors from them.
//!
//! The `gltf` crate's own `import` feature is not used: its URI decoding panics on malformed
//! percent-escapes (`urlencoding::decode(..).unwrap()`), its I/O errors do not say which file is
//! missing, and it drags in JPEG/PNG decoders for textures Opticks ignores. Its accessor iterators
//! are not used either: they `debug_assert!` that the accessor's type matches the one asked for,
//! which malformed files break. Every read here is checked and ends in an error instead: a
//! [`BufferError`] for a buffer's data, a [`ReadError`] for a buffer view's or an accessor's
//! bytes, a [`Base64Error`] for a `data:` URI.

use ::gltf::accessor::{Accessor, DataType, Dimensions};
use ::gltf::buffer::Source;
use std::path::{Path, PathBuf};

/// Why a buffer's (or an image's `uri`'s) data could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum BufferError {
    /// An external buffer file cannot be read.
    #[error("cannot read buffer file {}: {source}", path.display())]
    File {
        /// The file as resolved.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The buffer is the GLB binary chunk, and the file has none.
    #[error("refers to the GLB binary chunk, but the file has none")]
    NoBinChunk,
    /// The data is shorter than the buffer's `byteLength`.
    #[error("has {len} bytes, but byteLength says {byte_length}")]
    TooShort {
        /// Bytes found.
        len: usize,
        /// The buffer's `byteLength`.
        byte_length: usize,
    },
    /// A `data:` URI without `;base64,`.
    #[error("data: URI is not base64-encoded")]
    NotBase64,
    /// A `data:` URI whose base64 text does not decode.
    #[error("data: URI: {0}")]
    Base64(Base64Error),
    /// A URI of a scheme other than `data:` and `file:`.
    #[error("unsupported URI scheme in {uri:?}")]
    UnsupportedScheme {
        /// The URI.
        uri: String,
    },
    /// A file URI with a malformed percent-escape.
    #[error("malformed percent-escape in URI {uri:?}")]
    PercentEscape {
        /// The URI.
        uri: String,
    },
}

/// Why the bytes of a buffer view or an accessor cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReadError {
    /// A buffer view names a buffer the document does not have.
    #[error("buffer view refers to a missing buffer")]
    MissingBuffer,
    /// A buffer view's offset plus length overflows.
    #[error("buffer view is too large")]
    ViewTooLarge,
    /// A buffer view's bytes run past its buffer.
    #[error("buffer view {view} (bytes {start}..{end}) lies outside buffer {buffer} ({len} bytes)")]
    ViewOutside {
        /// The buffer view.
        view: usize,
        /// Its first byte in the buffer.
        start: usize,
        /// One past its last byte.
        end: usize,
        /// The buffer.
        buffer: usize,
        /// The buffer's length.
        len: usize,
    },
    /// The accessor is sparse.
    #[error("sparse accessors are not supported")]
    Sparse,
    /// An accessor without a buffer view (all zeros) with more elements than are allowed.
    #[error("accessor {accessor} has no buffer view and {count} elements")]
    ViewlessTooLong {
        /// The accessor.
        accessor: usize,
        /// Its element count.
        count: usize,
    },
    /// A buffer view's stride is smaller than the accessor's elements.
    #[error("byteStride {stride} is smaller than the element size {element}")]
    StrideTooSmall {
        /// The view's byte stride.
        stride: usize,
        /// The element size in bytes.
        element: usize,
    },
    /// The accessor's extent overflows.
    #[error("accessor is too large")]
    AccessorTooLarge,
    /// An accessor's bytes run past its buffer view.
    #[error("accessor {accessor} needs bytes {start}..{end} of buffer view {view}, which has {len} bytes")]
    AccessorOutside {
        /// The accessor.
        accessor: usize,
        /// Its first byte in the view.
        start: usize,
        /// One past its last byte.
        end: usize,
        /// The buffer view.
        view: usize,
        /// The view's length.
        len: usize,
    },
    /// A position accessor is not `VEC3` of `FLOAT`.
    #[error(
        "accessor {accessor} is {dimensions:?} of {data_type:?}; positions must be Vec3 of F32 (quantized positions are not supported)"
    )]
    NotPositions {
        /// The accessor.
        accessor: usize,
        /// Its type.
        dimensions: Dimensions,
        /// Its component type.
        data_type: DataType,
    },
    /// A texture-coordinate accessor is not `VEC2` of `FLOAT` or of normalized bytes or shorts.
    #[error(
        "accessor {accessor} is {dimensions:?} of {data_type:?}{}; texture coordinates must be Vec2 of F32, or of normalized U8 or U16",
        if *normalized { " (normalized)" } else { "" }
    )]
    NotTexCoords {
        /// The accessor.
        accessor: usize,
        /// Its type.
        dimensions: Dimensions,
        /// Its component type.
        data_type: DataType,
        /// Whether it is normalized.
        normalized: bool,
    },
    /// An index accessor is not scalars of unsigned bytes, shorts or ints.
    #[error(
        "index accessor {accessor} is {dimensions:?} of {data_type:?}; indices must be scalars of U8, U16 or U32"
    )]
    NotIndices {
        /// The accessor.
        accessor: usize,
        /// Its type.
        dimensions: Dimensions,
        /// Its component type.
        data_type: DataType,
    },
}

/// Why base64 text does not decode.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Base64Error {
    /// A character outside the base64 alphabets.
    #[error("invalid base64 character {character:?} at offset {offset}")]
    InvalidCharacter {
        /// The character.
        character: char,
        /// Its byte offset in the text.
        offset: usize,
    },
    /// The text stops one character into a byte.
    #[error("truncated base64 data")]
    Truncated,
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
            Source::Bin => blob.map(<[u8]>::to_vec).ok_or((i, BufferError::NoBinChunk))?,
            Source::Uri(uri) => read_uri(uri, folder).map_err(|e| (i, e))?,
        };
        if data.len() < buffer.length() {
            return Err((i, BufferError::TooShort { len: data.len(), byte_length: buffer.length() }));
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
            return Err(BufferError::NotBase64);
        };
        decode_base64(b64).map_err(BufferError::Base64)
    } else if uri.contains(':') && !uri.starts_with("file:") {
        Err(BufferError::UnsupportedScheme { uri: uri.to_string() })
    } else {
        let rel = uri.strip_prefix("file://").or_else(|| uri.strip_prefix("file:")).unwrap_or(uri);
        let rel = percent_decode(rel).ok_or_else(|| BufferError::PercentEscape { uri: uri.to_string() })?;
        let path = folder.join(rel);
        crate::input_file::read(&path).map_err(|source| BufferError::File { path, source })
    }
}

/// The bytes of buffer view `view`, bounds-checked (an image stored in a buffer).
pub fn view_bytes<'a>(
    view: &::gltf::buffer::View<'_>,
    buffers: &'a [Vec<u8>],
) -> Result<&'a [u8], ReadError> {
    let data = buffers.get(view.buffer().index()).ok_or(ReadError::MissingBuffer)?;
    let end = view.offset().checked_add(view.length()).ok_or(ReadError::ViewTooLarge)?;
    data.get(view.offset()..end).ok_or_else(|| ReadError::ViewOutside {
        view: view.index(),
        start: view.offset(),
        end,
        buffer: view.buffer().index(),
        len: data.len(),
    })
}

/// Standard base64 (RFC 4648, `+/`, optional `=` padding; whitespace is not allowed).
pub fn decode_base64(s: &str) -> Result<Vec<u8>, Base64Error> {
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
            _ => return Err(Base64Error::InvalidCharacter { character: c as char, offset: pos }),
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
        return Err(Base64Error::Truncated);
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
) -> Result<Option<(&'a [u8], usize)>, ReadError> {
    if acc.sparse().is_some() {
        return Err(ReadError::Sparse);
    }
    let Some(view) = acc.view() else {
        // All zeros; refuse absurd counts rather than allocate them.
        return if acc.count() <= MAX_VIEWLESS_COUNT {
            Ok(None)
        } else {
            Err(ReadError::ViewlessTooLong { accessor: acc.index(), count: acc.count() })
        };
    };
    let view_data = view_bytes(&view, buffers)?;
    let stride = view.stride().unwrap_or(elem_size);
    if stride < elem_size {
        return Err(ReadError::StrideTooSmall { stride, element: elem_size });
    }
    let count = acc.count();
    if count == 0 {
        return Ok(Some((&[], stride)));
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(elem_size))
        .and_then(|x| x.checked_add(acc.offset()))
        .ok_or(ReadError::AccessorTooLarge)?;
    let bytes = view_data.get(acc.offset()..end).ok_or_else(|| ReadError::AccessorOutside {
        accessor: acc.index(),
        start: acc.offset(),
        end,
        view: view.index(),
        len: view_data.len(),
    })?;
    Ok(Some((bytes, stride)))
}

/// Reads a `VEC3`/`FLOAT` accessor.
pub fn read_vec3(acc: &Accessor<'_>, buffers: &[Vec<u8>]) -> Result<Vec<[f32; 3]>, ReadError> {
    if acc.dimensions() != Dimensions::Vec3 || acc.data_type() != DataType::F32 {
        return Err(ReadError::NotPositions {
            accessor: acc.index(),
            dimensions: acc.dimensions(),
            data_type: acc.data_type(),
        });
    }
    let count = acc.count();
    let Some((bytes, stride)) = elements(acc, buffers, 12)? else { return Ok(vec![[0.0; 3]; count]) };
    let f = |b: &[u8], k: usize| f32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]]);
    Ok((0..count).map(|i| &bytes[i * stride..i * stride + 12]).map(|b| [f(b, 0), f(b, 1), f(b, 2)]).collect())
}

/// Reads a `VEC2` texture-coordinate accessor: `FLOAT`, or normalized `UNSIGNED_BYTE` /
/// `UNSIGNED_SHORT` (divided by 255 or 65535, as glTF's `TEXCOORD_n` allows).
pub fn read_vec2(acc: &Accessor<'_>, buffers: &[Vec<u8>]) -> Result<Vec<[f32; 2]>, ReadError> {
    let size = match (acc.dimensions(), acc.data_type(), acc.normalized()) {
        (Dimensions::Vec2, DataType::F32, _) => 4,
        (Dimensions::Vec2, DataType::U8, true) => 1,
        (Dimensions::Vec2, DataType::U16, true) => 2,
        (dimensions, data_type, normalized) => {
            return Err(ReadError::NotTexCoords { accessor: acc.index(), dimensions, data_type, normalized });
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
pub fn read_indices(acc: &Accessor<'_>, buffers: &[Vec<u8>]) -> Result<Vec<u32>, ReadError> {
    let size = match (acc.dimensions(), acc.data_type()) {
        (Dimensions::Scalar, DataType::U8) => 1,
        (Dimensions::Scalar, DataType::U16) => 2,
        (Dimensions::Scalar, DataType::U32) => 4,
        (dimensions, data_type) => {
            return Err(ReadError::NotIndices { accessor: acc.index(), dimensions, data_type });
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
        assert_eq!(decode_base64("Zm9v!"), Err(Base64Error::InvalidCharacter { character: '!', offset: 4 }));
        assert_eq!(decode_base64("Z"), Err(Base64Error::Truncated));
    }

    #[test]
    fn accessor_type_messages_say_what_was_found() {
        let e = |normalized| ReadError::NotTexCoords {
            accessor: 3,
            dimensions: Dimensions::Vec3,
            data_type: DataType::U8,
            normalized,
        };
        let tail = "; texture coordinates must be Vec2 of F32, or of normalized U8 or U16";
        assert_eq!(e(true).to_string(), format!("accessor 3 is Vec3 of U8 (normalized){tail}"));
        assert_eq!(e(false).to_string(), format!("accessor 3 is Vec3 of U8{tail}"));
    }

    #[test]
    fn uri_errors_are_typed_and_say_what_is_wrong() {
        let e = |uri: &str| read_uri(uri, Path::new("")).unwrap_err();
        let cases = [
            ("data:application/octet-stream,AAAA", "data: URI is not base64-encoded"),
            ("data:application/octet-stream;base64,Z", "data: URI: truncated base64 data"),
            ("http://example.com/a.bin", "unsupported URI scheme in \"http://example.com/a.bin\""),
            ("a%2.bin", "malformed percent-escape in URI \"a%2.bin\""),
        ];
        for (uri, text) in cases {
            assert_eq!(e(uri).to_string(), text, "{uri}");
        }
        assert!(matches!(e("data:x;base64,Z"), BufferError::Base64(Base64Error::Truncated)));
        assert!(matches!(e("a%zz.bin"), BufferError::PercentEscape { uri } if uri == "a%zz.bin"));
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
