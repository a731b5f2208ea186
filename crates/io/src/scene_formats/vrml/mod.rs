//! VRML97 scenes (ISO/IEC 14772-1), the format the thesis stores its scenes and lights in
//! ("a modified VRML file", §6.1.3), with the Opticks extension for physical units
//! ([`extension`]). The user-facing description — what each node becomes, the units, the
//! extension — is `docs/scene-formats.md`, section VRML97.
//!
//! | file | job |
//! |---|---|
//! | [`lexer`] | text → tokens with line:column |
//! | [`parser`] | tokens → generic node tree ([`tree`]), typed by [`nodes`]; PROTOs expanded by [`proto`] |
//! | [`convert`] | node tree → [`SceneDescription`](opticks_core::scene::SceneDescription) ([`geometry`], [`triangulate`], [`appearance`], [`lights`], [`viewpoint`]) |
//! | [`writer`] | [`SceneDescription`](opticks_core::scene::SceneDescription) → VRML97 with the extension |
//!
//! `.wrl`, `.wrz` and `.wrl.gz` files are read; gzip compression is recognised by its magic
//! bytes whatever the extension. Inflating stops at [`MAX_INFLATED_BYTES`]: a gzip bomb (a few
//! KB that inflate to gigabytes) is an error naming the file, not an allocation until memory
//! runs out.
//!
//! # Why a hand-written parser
//!
//! No maintained Rust crate reads VRML97: the few on crates.io are abandoned, read VRML 1.0 or
//! X3D only, or stop at a syntax tree without PROTO expansion. VRML's grammar is small
//! (Annex A) but not self-describing — a field's value can only be read knowing the field's
//! type, from the standard node table or a PROTO interface — so a parser that is exact, gives
//! `file:line:col` for every error and warning, bounds recursion and expansion against hostile
//! input, and parses a 40 MB mesh at hundreds of MB/s is less code written here than adapted. Lexing,
//! parsing and conversion are kept apart so that each can be tested (and fuzzed) on its own.

pub mod appearance;
pub mod convert;
pub mod extension;
pub mod geometry;
pub mod lexer;
pub mod lights;
pub mod nodes;
pub mod parser;
pub mod proto;
pub mod tree;
pub mod triangulate;
pub mod viewpoint;
pub mod writer;

use super::{FileLocation, LoadedScene, SceneFileError};
use std::io::Read;
use std::path::Path;
use tree::NodeRef;

pub use writer::{write_vrml, write_vrml_file};

/// Whether `path` names a VRML file: `.wrl`, `.wrz` or `.wrl.gz` (any case).
pub fn is_vrml_path(path: &Path) -> bool {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("").to_ascii_lowercase();
    name.ends_with(".wrl") || name.ends_with(".wrz") || name.ends_with(".wrl.gz")
}

/// The local file a VRML `url` names relative to `dir` (`file://` accepted; other schemes are
/// not fetched), with its `#fragment` (empty if none); `None` unless it is an existing file.
/// Used by `Inline` and `EXTERNPROTO`.
pub fn local_url<'u>(dir: &Path, url: &'u str) -> Option<(std::path::PathBuf, &'u str)> {
    let (file, fragment) = url.split_once('#').unwrap_or((url, ""));
    if file.is_empty() || (file.contains("://") && !file.starts_with("file://")) {
        return None;
    }
    let path = dir.join(file.strip_prefix("file://").unwrap_or(file));
    path.is_file().then_some((path, fragment))
}

/// Loads a VRML97 file (gzip-compressed or not).
pub fn load(path: &Path) -> Result<LoadedScene, SceneFileError> {
    load_with_camera(path, None)
}

/// [`load`], the camera being the `Viewpoint` whose `description` or DEF name is `camera`
/// (an error listing the Viewpoints' names if none is), or the first one for `None`.
pub fn load_with_camera(path: &Path, camera: Option<&str>) -> Result<LoadedScene, SceneFileError> {
    let text = read_source(path)?;
    let (nodes, warnings) = parse_text(&text, path)?;
    convert::convert_sized(&nodes, path, warnings, text.len(), camera)
}

/// Loads VRML97 text; `path` names it in messages and resolves `Inline` URLs.
pub fn load_str(text: &str, path: &Path) -> Result<LoadedScene, SceneFileError> {
    let (nodes, warnings) = parse_text(text, path)?;
    convert::convert_sized(&nodes, path, warnings, text.len(), None)
}

/// Most bytes a gzip-compressed VRML file (or Inline) may inflate to: 1 GiB, ten times the text
/// of a 1 M-triangle mesh. Beyond it the file is refused.
pub const MAX_INFLATED_BYTES: u64 = 1 << 30;

/// Reads a file's text, gunzipping it if it starts with the gzip magic bytes.
pub fn read_source(path: &Path) -> Result<String, SceneFileError> {
    read_source_capped(path, MAX_INFLATED_BYTES)
}

/// [`read_source`] with the inflated size bounded by `cap` bytes.
fn read_source_capped(path: &Path, cap: u64) -> Result<String, SceneFileError> {
    let read_err = |source| SceneFileError::Read { path: path.to_path_buf(), source };
    let bytes = crate::input_file::read(path).map_err(read_err)?;
    let bytes = if bytes.starts_with(&[0x1f, 0x8b]) {
        let mut out = Vec::new();
        let reserve = usize::try_from(cap).unwrap_or(usize::MAX).min(bytes.len().saturating_mul(4));
        out.try_reserve(reserve).map_err(|e| read_err(std::io::Error::other(e)))?;
        flate2::read::MultiGzDecoder::new(&bytes[..])
            .take(cap.saturating_add(1))
            .read_to_end(&mut out)
            .map_err(read_err)?;
        if out.len() as u64 > cap {
            return Err(read_err(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!(
                    "the gzip-compressed file ({} bytes) inflates to more than {cap} bytes, the most a VRML file may have",
                    bytes.len()
                ),
            )));
        }
        out
    } else {
        bytes
    };
    String::from_utf8(bytes).map_err(|e| {
        let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = valid.iter().filter(|&&b| b == b'\n').count() as u32 + 1;
        let column = (valid.len() - valid.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1)) as u32 + 1;
        SceneFileError::Invalid {
            at: FileLocation { file: path.to_path_buf(), line, column },
            element: "VRML".into(),
            message: "the file is not UTF-8 text (VRML97 files are `#VRML V2.0 utf8`)".into(),
        }
    })
}

/// Parses VRML97 text into its top-level nodes and the parser's warnings (as
/// `file:line:col: message` lines).
pub fn parse_text(text: &str, path: &Path) -> Result<(Vec<NodeRef>, Vec<String>), SceneFileError> {
    let loc = |pos: lexer::Pos| FileLocation { file: path.to_path_buf(), line: pos.line, column: pos.col };
    let parsed = parser::parse_file(text, path).map_err(|e| SceneFileError::Invalid {
        at: loc(e.pos),
        element: "VRML syntax".into(),
        message: e.message,
    })?;
    let warnings = parsed.warnings.into_iter().map(|(pos, m)| format!("{}: {m}", loc(pos))).collect();
    Ok((parsed.nodes, warnings))
}

#[cfg(test)]
mod tests {
    use super::*;
    use flate2::{Compression, write::GzEncoder};
    use std::io::Write;

    /// One gzip member of `n` zero bytes.
    fn zeros_gz(n: usize) -> Vec<u8> {
        let mut e = GzEncoder::new(Vec::new(), Compression::best());
        e.write_all(&vec![0u8; n]).unwrap();
        e.finish().unwrap()
    }

    #[test]
    fn a_gzip_bomb_is_refused_at_the_bound_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        // 16 members of 4 MiB of zeros: ~65 KB that inflate to 64 MiB.
        let member = zeros_gz(4 << 20);
        let bomb: Vec<u8> = (0..16).flat_map(|_| member.iter().copied()).collect();
        assert!(bomb.len() < 100_000, "{}", bomb.len());
        let path = dir.path().join("bomb.wrz");
        std::fs::write(&path, &bomb).unwrap();
        let e = read_source_capped(&path, 8 << 20).unwrap_err().to_string();
        assert!(e.contains("bomb.wrz") && e.contains("inflates to more than 8388608 bytes"), "{e}");
        // Under the bound, the same stream reads whole (as text of zero bytes).
        assert_eq!(read_source_capped(&path, 64 << 20).unwrap().len(), 64 << 20);
    }

    #[test]
    fn a_gzipped_scene_under_the_bound_loads() {
        let dir = tempfile::tempdir().unwrap();
        let text = "#VRML V2.0 utf8\nShape { geometry Box {} }\n";
        let mut e = GzEncoder::new(Vec::new(), Compression::default());
        e.write_all(text.as_bytes()).unwrap();
        let path = dir.path().join("box.wrz");
        std::fs::write(&path, e.finish().unwrap()).unwrap();
        assert_eq!(read_source(&path).unwrap(), text);
        assert_eq!(MAX_INFLATED_BYTES, 1 << 30, "documented in docs/scene-formats.md");
    }
}
