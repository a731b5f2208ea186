//! The document's file structure, expanded before anything else reads the records:
//! `<include filename="…"/>` is replaced by the records of the file it names, and
//! `<path value="…"/>` adds a folder in which file names are searched
//! ([`super::xml::Document::resolve`]).
//!
//! Mitsuba's rules, which this follows:
//! * an included file's root is a `<scene>`, whose children take the `<include>`'s place, or a
//!   single object (a `<bsdf>`, a `<shape>`, …), which does; it needs a `version` like any root;
//! * the file name is searched relative to the including file's folder first, then in the
//!   `<path>` folders and the main scene's folder; it may use `$name` parameters, with the
//!   values known at that point (the caller's defines and the `<default>`s met before it);
//! * `<path>` is allowed only as a child of a root `<scene>`; a relative folder is taken
//!   relative to the file it is in, else searched like a file name (the `<path>` folders so
//!   far, the main scene's folder), and must exist;
//! * includes nest at most [`MAX_INCLUDE_DEPTH`] deep (Mitsuba's limit).
//!
//! Beyond Mitsuba, a file that includes itself (directly or not) is an error naming the chain,
//! and a document may include at most [`MAX_INCLUDES`] files in all, so that a few small files
//! including each other twice at every level cannot make loading exponential. Every error is
//! located at the `<include>` or `<path>` it is about; errors inside an included file name
//! that file, line and column.

use super::Result;
use super::xml::{self, Element};
use crate::scene_formats::LoadOptions;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// How deep includes may nest (the main file is depth 0), as Mitsuba's `max_include_depth`.
pub const MAX_INCLUDE_DEPTH: usize = 15;

/// How many `<include>`s a document may expand in all.
pub const MAX_INCLUDES: usize = 1000;

/// Replaces the `<include>`s of `root` (the main file `path`'s records) by what they include,
/// recursively, and removes its `<path>`s; returns the `<path>` folders in file order.
pub fn expand(root: &mut Element, path: &Path, options: &LoadOptions) -> Result<Vec<PathBuf>> {
    let mut x = Expander {
        vars: options.defines.iter().cloned().collect(),
        stack: vec![canonical(path)],
        includes: 0,
        search: Vec::new(),
        main_dir: path.parent().unwrap_or(Path::new("")).to_path_buf(),
    };
    x.children(root, true, true)?;
    Ok(x.search)
}

struct Expander {
    /// Parameter values known so far: the caller's, then the first `<default>` of each name.
    vars: HashMap<String, String>,
    /// The files being expanded, outermost first (canonical paths, for cycles).
    stack: Vec<PathBuf>,
    /// `<include>`s expanded so far.
    includes: usize,
    /// `<path>` folders so far.
    search: Vec<PathBuf>,
    main_dir: PathBuf,
}

impl Expander {
    /// Expands the children of `e`. `top`: they become children of the document's `<scene>`;
    /// `root`: `e` is the root `<scene>` of its file (where `<path>` may appear).
    fn children(&mut self, e: &mut Element, top: bool, root: bool) -> Result<()> {
        let mut out = Vec::with_capacity(e.children.len());
        for mut c in std::mem::take(&mut e.children) {
            c.top_level = top;
            match c.tag.as_str() {
                "include" => out.extend(self.include(&c, top)?),
                "path" if root => self.path(&c)?,
                "path" => return Err(c.err("<path> is allowed only directly inside <scene>")),
                _ => {
                    if top
                        && c.tag == "default"
                        && let (Some(n), Some(v)) = (c.raw("name"), c.raw("value"))
                    {
                        self.vars.entry(n.to_string()).or_insert_with(|| v.to_string());
                    }
                    self.children(&mut c, false, false)?;
                    out.push(c);
                }
            }
        }
        e.children = out;
        Ok(())
    }

    /// The value of attribute `attr` of `e` with the parameters known so far substituted.
    fn value(&self, e: &Element, attr: &str) -> Result<String> {
        let raw = e.raw_required(attr)?;
        xml::substitute(raw, &self.vars).map_err(|undefined| {
            e.attr_err(
                attr,
                format!(
                    "{undefined} in attribute `{attr}` (declare it with a <default> \
                     before this element, or define it when loading)"
                ),
            )
        })
    }

    /// The records an `<include>` stands for.
    fn include(&mut self, e: &Element, top: bool) -> Result<Vec<Element>> {
        let name = self.value(e, "filename")?;
        let depth = self.stack.len();
        if depth > MAX_INCLUDE_DEPTH {
            return Err(e.err(format!("includes nest more than {MAX_INCLUDE_DEPTH} deep")));
        }
        self.includes += 1;
        if self.includes > MAX_INCLUDES {
            return Err(e.err(format!("the scene includes more than {MAX_INCLUDES} files in all")));
        }
        let own = e.resolve(&name);
        let file = if Path::new(&name).is_absolute() || own.exists() {
            own
        } else {
            let mut dirs = self.search.iter().rev().chain([&self.main_dir]);
            match dirs.find(|d| d.join(&name).exists()) {
                Some(d) => d.join(&name),
                None => {
                    return Err(e.attr_err(
                        "filename",
                        format!("included file \"{name}\" not found (looked for {})", own.display()),
                    ));
                }
            }
        };
        let key = canonical(&file);
        if let Some(i) = self.stack.iter().position(|p| *p == key) {
            let chain: Vec<String> =
                self.stack[i..].iter().chain([&key]).map(|p| p.display().to_string()).collect();
            return Err(e.attr_err("filename", format!("include cycle: {}", chain.join(" → "))));
        }
        // Through `input_file`: a device (`/dev/zero`) or a FIFO is refused before it is read.
        let text = crate::input_file::read_to_string(&file).map_err(|err| {
            e.attr_err("filename", format!("cannot read included file {}: {err}", file.display()))
        })?;
        let mut inc = xml::parse_root(&text, &file)?;
        self.stack.push(key);
        let result = if inc.tag == "scene" {
            self.children(&mut inc, top, true).map(|()| inc.children)
        } else {
            inc.top_level = top;
            self.children(&mut inc, false, false).map(|()| vec![inc])
        };
        self.stack.pop();
        result
    }

    /// Records a `<path>`'s folder.
    fn path(&mut self, e: &Element) -> Result<()> {
        let value = self.value(e, "value")?;
        let own = e.resolve(&value);
        // Relative to the file it is in, else (Mitsuba's fallback) to the folders searched so far.
        let dir = if own.is_dir() || Path::new(&value).is_absolute() {
            own
        } else {
            let mut dirs = self.search.iter().rev().chain([&self.main_dir]);
            dirs.find(|d| d.join(&value).is_dir()).map_or(own, |d| d.join(&value))
        };
        if !dir.is_dir() {
            return Err(e.attr_err("value", format!("folder \"{}\" not found", dir.display())));
        }
        self.search.push(dir);
        Ok(())
    }
}

/// `path` made absolute and free of `..` and links where possible (for cycle checks).
fn canonical(path: &Path) -> PathBuf {
    path.canonicalize().unwrap_or_else(|_| path.to_path_buf())
}
