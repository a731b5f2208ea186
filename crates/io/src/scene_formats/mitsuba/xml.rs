//! Stage 1 of the Mitsuba loader: the XML text becomes plain records, a tree of [`Element`]s
//! that each know their `file:line:column`, with `$name` parameters substituted and `<ref>`s
//! resolved to the top-level element they name.
//!
//! This stage owns everything about the *document*: the XML parser's errors, the `<scene
//! version>` check, the file structure (`<include>`, `<path>`: [`super::include`]),
//! `<default>` parameters and the caller's overrides, substitution, duplicate
//! ids. It knows nothing about plugins; the stages after it ([`super::build`]) read the records
//! and never see `roxmltree`.
//!
//! Errors are raised in the order a reader of the file meets them: the document-level checks
//! here, in file order, and everything about a single element (an undefined `$name` in one of
//! its attributes, a missing attribute) only when a later stage reads it. An undefined parameter is therefore stored in the
//! [`Attribute`], not reported, until the attribute is read: an element Opticks ignores may
//! use a parameter nobody defined.

use super::Result;
use crate::scene_formats::{FileLocation, LoadOptions, SceneFileError};
use std::collections::HashMap;
use std::fmt::Display;
use std::path::{Path, PathBuf};

/// A whole scene file as records.
pub struct Document {
    /// The `<scene>` element; its children are the top-level elements.
    pub root: Element,
    /// The index in `root.children` of each top-level element with an `id`, by id.
    pub ids: HashMap<String, usize>,
    /// The folders of the `<path>` elements, in file order (of every file read).
    pub search_paths: Vec<PathBuf>,
    /// The scene file itself (its folder is searched last by [`Self::resolve`]).
    pub main: PathBuf,
    /// What the document stage had to say (a define the scene never uses).
    pub warnings: Vec<String>,
    /// The `id` of the `<sensor>` to use ([`LoadOptions::camera`]); `None`: the first one.
    pub camera: Option<String>,
    /// Bounds on what the files the scene names may allocate ([`LoadOptions::limits`]).
    pub limits: crate::scene_formats::LoadLimits,
}

impl Document {
    /// The top-level element at `index` of `root.children` (as in [`Self::ids`] and
    /// [`Element::target`]).
    pub fn top(&self, index: usize) -> &Element {
        &self.root.children[index]
    }
}

/// One XML element as written: its tag, where it starts, its attributes and its element
/// children (text and comments dropped), in file order.
#[derive(Debug)]
pub struct Element {
    /// The tag's local name (`bsdf`, `float`, …).
    pub tag: String,
    /// Where the element starts (its `<`).
    pub at: FileLocation,
    /// The attributes, in file order.
    pub attributes: Vec<Attribute>,
    /// The element children, in file order.
    pub children: Vec<Element>,
    /// Whether this is a child of `<scene>` (only those can be referred to by id).
    pub top_level: bool,
    /// For a `<ref>` whose `id` names a top-level element: that element's index in
    /// [`Document::root`]'s children.
    pub target: Option<usize>,
}

/// An attribute of an [`Element`].
#[derive(Debug)]
pub struct Attribute {
    /// Its name.
    pub name: String,
    /// Its value as written (after XML entity decoding).
    pub raw: String,
    /// Its value with `$name` parameters substituted, or the first undefined parameter.
    pub value: std::result::Result<String, UndefinedParameter>,
    /// Where its value starts.
    pub at: FileLocation,
}

/// A `$name` in an attribute that neither a `<default>` nor the caller gives a value.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("undefined parameter ${name}")]
pub struct UndefinedParameter {
    /// The parameter's name (without the `$`).
    pub name: String,
}

/// Parses `text` (the file `path`) into records; `options` gives parameter values overriding
/// the file's `<default>`s. `<include>`s are replaced by the files they name and `<path>`s
/// collected ([`super::include`]).
pub fn read(text: &str, path: &Path, options: &LoadOptions) -> Result<Document> {
    let mut root = parse_root(text, path)?;
    if root.tag != "scene" {
        return Err(root.err("the root element must be <scene version=\"3.0.0\">"));
    }
    let search_paths = super::include::expand(&mut root, path, options)?;

    // Parameters: the caller's, then the first `<default>` of each name at the top level
    // (Mitsuba's rule: a default never overrides a value already given).
    let mut vars: HashMap<String, String> = options.defines.iter().cloned().collect();
    for d in root.children.iter().filter(|c| c.tag == "default") {
        let name = d.raw_required("name")?;
        let value = d.raw_required("value")?;
        vars.entry(name.to_string()).or_insert_with(|| value.to_string());
    }
    root.children.iter_mut().for_each(|c| substitute_tree(c, &vars));
    let mut warnings = Vec::new();
    for (name, _) in &options.defines {
        if !uses_parameter(&root, &format!("${name}")) {
            warnings.push(format!(
                "{}: parameter {name} is defined but the scene never uses ${name}",
                path.display()
            ));
        }
    }

    // Ids of top-level objects, so references may point forward.
    let mut ids: HashMap<String, usize> = HashMap::new();
    for (i, c) in root.children.iter().enumerate() {
        if let Some(id) = c.attr("id")? {
            if let Some(&prev) = ids.get(id) {
                let prev_at = &root.children[prev].at;
                return Err(c.err(format!("duplicate id \"{id}\" (first declared at {prev_at})")));
            }
            ids.insert(id.to_string(), i);
        }
    }
    root.children.iter_mut().for_each(|c| resolve_refs(c, &ids));
    Ok(Document {
        root,
        ids,
        search_paths,
        main: path.to_path_buf(),
        warnings,
        camera: options.camera.clone(),
        limits: options.limits,
    })
}

/// Whether some attribute at or below `e` mentions `var` (`$name`).
fn uses_parameter(e: &Element, var: &str) -> bool {
    e.attributes.iter().any(|a| a.raw.contains(var)) || e.children.iter().any(|c| uses_parameter(c, var))
}

/// The records of one XML file (the scene, or a file it includes), with the root's own
/// attributes substituted (with no parameters: a `$name` there is undefined) and its `version`
/// checked.
pub fn parse_root(text: &str, path: &Path) -> Result<Element> {
    refuse_declared_entities(text, path)?;
    let xml = roxmltree::Document::parse_with_options(
        text,
        roxmltree::ParsingOptions { allow_dtd: true, ..Default::default() },
    )
    .map_err(|e| xml_error(text, path, e))?;
    let mut positions = Positions { text, path, byte: 0, line: 1, column: 1 };
    let mut root = record(xml.root_element(), &mut positions, false, 1)?;
    substitute_attributes(&mut root, &HashMap::new());
    check_version(&root)?;
    Ok(root)
}

impl Document {
    /// The file `file` named in element `e`, found as Mitsuba's file resolver finds it: an
    /// absolute path as it is; else the first existing one of `file` in the `<path>` folders
    /// (the latest first), in the folder of the file `e` is in, in the main scene file's folder.
    /// If none exists, `file` in `e`'s folder (so that the error names a plausible path).
    pub fn resolve(&self, e: &Element, file: &str) -> PathBuf {
        let own = e.resolve(file);
        if Path::new(file).is_absolute() {
            return own;
        }
        let main = self.main.parent().unwrap_or(Path::new(""));
        let candidates = self.search_paths.iter().rev().map(|d| d.join(file));
        candidates.chain([own.clone(), main.join(file)]).find(|p| p.exists()).unwrap_or(own)
    }
}

impl Element {
    /// The attribute `name` as written, if present (no substitution).
    pub fn raw(&self, name: &str) -> Option<&str> {
        self.attribute(name).map(|a| a.raw.as_str())
    }

    /// The attribute `name` with `$parameters` substituted, if present; an undefined parameter
    /// is an error located at the attribute.
    pub fn attr(&self, name: &str) -> Result<Option<&str>> {
        let Some(a) = self.attribute(name) else { return Ok(None) };
        match &a.value {
            Ok(v) => Ok(Some(v)),
            Err(undefined) => Err(self.attr_err(
                name,
                format!(
                    "{undefined} in attribute `{name}` (declare it with \
                     <default name=\"{}\" value=\"...\"/> or define it when loading)",
                    undefined.name
                ),
            )),
        }
    }

    /// [`Self::attr`], which must be present.
    pub fn required(&self, name: &str) -> Result<&str> {
        self.attr(name)?.ok_or_else(|| self.missing(name))
    }

    /// [`Self::raw`], which must be present.
    pub fn raw_required(&self, name: &str) -> Result<&str> {
        self.raw(name).ok_or_else(|| self.missing(name))
    }

    fn missing(&self, name: &str) -> SceneFileError {
        self.err(format!("missing attribute `{name}`"))
    }

    fn attribute(&self, name: &str) -> Option<&Attribute> {
        self.attributes.iter().find(|a| a.name == name)
    }

    /// The file named `file` in this element, resolved against the folder of the scene file
    /// the element is in.
    pub fn resolve(&self, file: &str) -> PathBuf {
        self.at.file.parent().unwrap_or(Path::new("")).join(file)
    }

    /// `<tag type="…" name="…" id="…">` as written in the file, for messages.
    pub fn describe(&self) -> String {
        let mut s = format!("<{}", self.tag);
        for key in ["type", "name", "id"] {
            if let Some(v) = self.raw(key) {
                s.push_str(&format!(" {key}=\"{v}\""));
            }
        }
        s.push('>');
        s
    }

    /// An error about this element, located at its start.
    pub fn err(&self, message: impl Into<String>) -> SceneFileError {
        SceneFileError::Invalid { at: self.at.clone(), element: self.describe(), message: message.into() }
    }

    /// An error about attribute `attr` of this element, located at the attribute's value (at
    /// the element if it has no such attribute).
    pub fn attr_err(&self, attr: &str, message: impl Into<String>) -> SceneFileError {
        let at = self.attribute(attr).map_or(&self.at, |a| &a.at).clone();
        SceneFileError::Invalid { at, element: self.describe(), message: message.into() }
    }

    /// A warning about this element, as a `file:line:column: <element>: message` line.
    pub fn warning(&self, message: impl Display) -> String {
        format!("{}: {}: {message}", self.at, self.describe())
    }
}

/// The record of `node` and its element children.
/// Elements nest at most this deep (`<scene>` is level 1). Real scenes stay below ten levels
/// (scene, shape, a two-sided BSDF, its BSDF, a texture, a transform); the bound keeps every
/// recursive stage after this one — building records, resolving references, nested BSDFs — far
/// from the stack's end (8,500 nested `<bsdf type="twosided">` overflowed it).
pub const MAX_NESTING: usize = 64;

fn record(
    node: roxmltree::Node,
    positions: &mut Positions,
    top_level: bool,
    depth: usize,
) -> Result<Element> {
    let at = positions.at(node.range().start);
    if depth > MAX_NESTING {
        return Err(SceneFileError::Invalid {
            at,
            element: format!("<{}>", node.tag_name().name()),
            message: format!("elements nested more than {MAX_NESTING} levels deep"),
        });
    }
    let attributes = node
        .attributes()
        .filter(|a| a.namespace().is_none())
        .map(|a| Attribute {
            name: a.name().to_string(),
            raw: a.value().to_string(),
            value: Ok(a.value().to_string()),
            at: positions.at(a.range_value().start),
        })
        .collect();
    let is_root = node.parent().is_some_and(|p| p.is_root());
    let children = node
        .children()
        .filter(|c| c.is_element())
        .map(|c| record(c, positions, is_root, depth + 1))
        .collect::<Result<_>>()?;
    Ok(Element { tag: node.tag_name().name().to_string(), at, attributes, children, top_level, target: None })
}

/// Refuses a DTD that declares entities, before the XML parser expands them: expansion is work
/// and memory out of all proportion to the file (one 100 KB entity referenced 1,000 times cost
/// 6 s and 590 MB), and Mitsuba itself does not expand declared entities (its parser knows only
/// XML's five predefined ones and character references, which stay allowed).
fn refuse_declared_entities(text: &str, path: &Path) -> Result<()> {
    let Some(doctype) = text.find("<!DOCTYPE") else { return Ok(()) };
    let Some(at) = text[doctype..].find("<!ENTITY").map(|i| doctype + i) else { return Ok(()) };
    let before = &text[..at];
    let line = before.matches('\n').count() as u32 + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) as u32 + 1;
    Err(SceneFileError::Xml {
        at: FileLocation { file: path.to_path_buf(), line, column },
        message: "<!ENTITY> declarations are not supported (Mitsuba does not expand them either): \
                  write the values out"
            .into(),
    })
}

/// Substitutes `vars` into the attributes of `e` and of everything below it.
pub fn substitute_tree(e: &mut Element, vars: &HashMap<String, String>) {
    substitute_attributes(e, vars);
    e.children.iter_mut().for_each(|c| substitute_tree(c, vars));
}

fn substitute_attributes(e: &mut Element, vars: &HashMap<String, String>) {
    for a in &mut e.attributes {
        a.value = substitute(&a.raw, vars);
    }
}

/// `raw` with each `$name` (letters, digits, `_`) replaced by its value; a `$` not followed by
/// a name stays. `Err` names the first undefined parameter.
pub fn substitute(
    raw: &str,
    vars: &HashMap<String, String>,
) -> std::result::Result<String, UndefinedParameter> {
    let mut out = String::with_capacity(raw.len());
    let mut rest = raw;
    while let Some(i) = rest.find('$') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        let len = after.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(after.len());
        if len == 0 {
            out.push('$');
        } else {
            let var = &after[..len];
            out.push_str(vars.get(var).ok_or_else(|| UndefinedParameter { name: var.to_string() })?);
        }
        rest = &after[len..];
    }
    out.push_str(rest);
    Ok(out)
}

/// Points each `<ref>` at or below `e` to the top-level element its `id` names.
fn resolve_refs(e: &mut Element, ids: &HashMap<String, usize>) {
    if e.tag == "ref"
        && let Ok(Some(id)) = e.attr("id")
    {
        e.target = ids.get(id).copied();
    }
    e.children.iter_mut().for_each(|c| resolve_refs(c, ids));
}

fn check_version(root: &Element) -> Result<()> {
    let v = root.attr("version")?.ok_or_else(|| {
        root.err("missing `version` attribute (a Mitsuba 3 scene starts with <scene version=\"3.0.0\">)")
    })?;
    let major = v.split('.').next().and_then(|m| m.trim().parse::<u32>().ok());
    match major {
        Some(2 | 3) => Ok(()),
        Some(m) if m < 2 => Err(root.attr_err(
            "version",
            format!(
                "scene version {v} is a Mitsuba 0.x file, whose parameter names differ; \
                 upgrade it to version 3 (supported: 2.x, 3.x)"
            ),
        )),
        _ => {
            Err(root.attr_err("version", format!("unsupported scene version \"{v}\" (supported: 2.x, 3.x)")))
        }
    }
}

/// Line and column of byte offsets, as `roxmltree::Document::text_pos_at` counts them (lines
/// split at `\n`, columns in characters, both from 1), computed in one pass when asked in
/// increasing order (which the records are built in), so that locating every element of a large
/// file stays linear.
struct Positions<'t> {
    text: &'t str,
    path: &'t Path,
    byte: usize,
    line: u32,
    column: u32,
}

impl Positions<'_> {
    fn at(&mut self, byte: usize) -> FileLocation {
        let byte = byte.min(self.text.len());
        if byte < self.byte {
            (self.byte, self.line, self.column) = (0, 1, 1);
        }
        for c in self.text[self.byte..byte].chars() {
            if c == '\n' {
                self.line += 1;
                self.column = 1;
            } else {
                self.column += 1;
            }
        }
        self.byte = byte;
        FileLocation { file: self.path.to_path_buf(), line: self.line, column: self.column }
    }
}

fn xml_error(text: &str, path: &Path, e: roxmltree::Error) -> SceneFileError {
    let mut pos = e.pos();
    if matches!(e, roxmltree::Error::UnclosedRootNode | roxmltree::Error::UnexpectedEndOfStream) {
        // roxmltree says 1:1; the end of the file is where something is missing.
        let line = text.split('\n').count() as u32;
        let col = text.rsplit('\n').next().map_or(0, |l| l.chars().count()) as u32 + 1;
        pos = roxmltree::TextPos::new(line, col);
    }
    let mut message = e.to_string();
    for suffix in [format!(" at {}", e.pos()), format!(" at {}", pos)] {
        if let Some(m) = message.strip_suffix(suffix.as_str()) {
            message = m.to_string();
        }
    }
    SceneFileError::Xml {
        at: FileLocation { file: path.to_path_buf(), line: pos.row, column: pos.col },
        message,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc(xml: &str, defines: &[(&str, &str)]) -> Result<Document> {
        let options = LoadOptions {
            defines: defines.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect(),
            ..Default::default()
        };
        read(xml, Path::new("d/s.xml"), &options)
    }

    #[test]
    fn substitution_replaces_names_and_keeps_lone_dollars() {
        let vars: HashMap<String, String> =
            [("w", "32"), ("a_1", "x")].map(|(k, v)| (k.to_string(), v.to_string())).into();
        assert_eq!(substitute("$w.5", &vars), Ok("32.5".into()));
        assert_eq!(substitute("$a_1$w-$", &vars), Ok("x32-$".into()));
        assert_eq!(substitute("$ $$w", &vars), Ok("$ $32".into()));
        assert_eq!(substitute("no parameters", &vars), Ok("no parameters".into()));
        assert_eq!(substitute("$w$nope$also", &vars), Err(UndefinedParameter { name: "nope".into() }));
    }

    #[test]
    fn undefined_parameters_are_reported_only_when_read() {
        let xml = "<scene version=\"3.0.0\">\n<default name=\"v\" value=\"1\"/>\n\
                   <integrator type=\"path\"><integer name=\"max_depth\" value=\"$nope\"/></integrator>\n\
                   <shape type=\"$v\" id=\"s\"/>\n</scene>";
        let d = doc(xml, &[]).unwrap();
        let depth = &d.root.children[1].children[0];
        assert_eq!(depth.attributes[1].value, Err(UndefinedParameter { name: "nope".into() }));
        let e = depth.attr("value").unwrap_err().to_string();
        assert!(
            e.starts_with("d/s.xml:3:58: <integer name=\"max_depth\">: undefined parameter $nope"),
            "{e}"
        );
        assert_eq!(d.root.children[2].attr("type").unwrap(), Some("1"));
        assert_eq!(doc(xml, &[("v", "2")]).unwrap().root.children[2].attr("type").unwrap(), Some("2"));
        // The root is read before the parameters exist.
        let e = doc("<scene version=\"$v\"><default name=\"v\" value=\"3.0.0\"/></scene>", &[]);
        assert!(e.err().unwrap().to_string().contains("undefined parameter $v"));
    }

    #[test]
    fn locations_match_the_xml_parser() {
        let xml = "<scene version=\"3.0.0\">\n  <!-- é -->\t<bsdf type=\"diffuse\" id=\"ü\"><rgb name=\"reflectance\"\n value=\"0.5\"/></bsdf>\n<shape type=\"cube\"><ref id=\"ü\"/></shape></scene>";
        let d = doc(xml, &[]).unwrap();
        let x = roxmltree::Document::parse(xml).unwrap();
        let mut ours = Vec::new();
        fn walk<'a>(e: &'a Element, out: &mut Vec<&'a FileLocation>) {
            out.push(&e.at);
            out.extend(e.attributes.iter().map(|a| &a.at));
            e.children.iter().for_each(|c| walk(c, out));
        }
        walk(&d.root, &mut ours);
        let theirs: Vec<_> = x
            .descendants()
            .filter(|n| n.is_element())
            .flat_map(|n| {
                std::iter::once(n.range().start).chain(n.attributes().map(|a| a.range_value().start))
            })
            .map(|b| x.text_pos_at(b))
            .map(|p| (p.row, p.col))
            .collect();
        assert_eq!(ours.iter().map(|l| (l.line, l.column)).collect::<Vec<_>>(), theirs);
        assert!(ours.iter().all(|l| l.file == Path::new("d/s.xml")));
    }

    #[test]
    fn refs_resolve_to_top_level_elements() {
        let d = doc(
            "<scene version=\"3.0.0\"><shape type=\"cube\"><ref id=\"b\"/><ref id=\"zz\"/></shape>\
             <bsdf type=\"diffuse\" id=\"b\"/></scene>",
            &[],
        )
        .unwrap();
        let shape = &d.root.children[0];
        assert_eq!(shape.children[0].target, Some(1));
        assert_eq!(shape.children[1].target, None);
        assert!(d.top(1).top_level && !shape.children[0].top_level);
        assert_eq!(d.ids["b"], 1);
    }
}
