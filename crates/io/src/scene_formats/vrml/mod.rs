//! VRML97 scenes (ISO/IEC 14772-1), the format the thesis stores its scenes and lights in
//! ("a modified VRML file", §6.1.3), with the Opticks extension for physical units
//! ([`extension`]). The user-facing description — what each node becomes, the units, the
//! extension — is `docs/scene-formats.md`, section VRML97.
//!
//! | file | job |
//! |---|---|
//! | [`lexer`] | text → tokens with line:column |
//! | [`parser`] | tokens → generic node tree ([`tree`]), typed by [`nodes`]; PROTOs expanded by [`proto`] |
//! | [`convert`] | node tree → [`SceneDescription`](opticks_core::scene::SceneDescription) ([`geometry`], [`triangulate`], [`lights`]) |
//! | [`writer`] | [`SceneDescription`](opticks_core::scene::SceneDescription) → VRML97 with the extension |
//!
//! `.wrl`, `.wrz` and `.wrl.gz` files are read; gzip compression is recognised by its magic
//! bytes whatever the extension.
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
    let text = read_source(path)?;
    load_str(&text, path)
}

/// Loads VRML97 text; `path` names it in messages and resolves `Inline` URLs.
pub fn load_str(text: &str, path: &Path) -> Result<LoadedScene, SceneFileError> {
    let (nodes, warnings) = parse_text(text, path)?;
    convert::convert_sized(&nodes, path, warnings, text.len())
}

/// Reads a file's text, gunzipping it if it starts with the gzip magic bytes.
pub fn read_source(path: &Path) -> Result<String, SceneFileError> {
    let read_err = |source| SceneFileError::Read { path: path.to_path_buf(), source };
    let bytes = crate::input_file::read(path).map_err(read_err)?;
    let bytes = if bytes.starts_with(&[0x1f, 0x8b]) {
        let mut out = Vec::with_capacity(bytes.len() * 4);
        flate2::read::MultiGzDecoder::new(&bytes[..]).read_to_end(&mut out).map_err(read_err)?;
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
