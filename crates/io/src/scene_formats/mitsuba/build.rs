//! Stage 2 of the Mitsuba loader: the records of [`super::xml`] become a
//! [`SceneDescription`]. This file holds the walk over the top-level elements, in file order
//! (the table [`TOP_LEVEL`] maps each element to its handler), and the [`Builder`] the plugin
//! builders share: the scene being filled, the warnings, the named BSDFs already built and the
//! ids referred to (references may point forward, so a named object is built where it is first
//! used, not where it is declared).
//!
//! The plugins themselves are built in one file each: [`super::sensor`], [`super::bsdf`],
//! [`super::shape`] (with [`super::medium`]) and [`super::emitter`].

use super::Result;
use super::bsdf::{self, ParsedBsdf};
use super::properties::Props;
use super::texture::BsdfTextures;
use super::xml::{Document, Element};
use super::{emitter, sensor, shape};
use crate::scene_formats::LoadedScene;
use crate::scene_formats::mesh_bytes::MeshData;
use opticks_core::scene::{SceneDescription, Source};
use opticks_core::texture::Texture;
use std::collections::{HashMap, HashSet};
use std::fmt::Display;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// What the builders share while the scene is built.
pub struct Builder<'d> {
    /// The records.
    pub doc: &'d Document,
    /// The scene so far.
    pub desc: SceneDescription,
    /// Things read but not reproduced, as `file:line:column: <element>: message` lines.
    pub warnings: Vec<String>,
    /// Top-level BSDFs already built, by id.
    pub bsdfs: HashMap<String, ParsedBsdf>,
    /// Ids of top-level BSDFs being built (reference cycles).
    pub in_progress: HashSet<String>,
    /// Index in `desc.materials` of a material, by key (a BSDF's id, or a BSDF's and a
    /// medium's), once a shape uses it.
    pub material_of: HashMap<String, usize>,
    /// Ids some `<ref>` pointed to.
    pub used: HashSet<String>,
    /// Top-level textures already built, by id.
    pub textures: HashMap<String, Arc<Texture>>,
    /// The textures read for the BSDF being built ([`super::texture::colour`] adds to them,
    /// [`super::bsdf::bsdf`] collects them).
    pub bsdf_textures: BsdfTextures,
    /// Shapegroups already built (where first instanced), by id.
    pub groups: HashMap<String, super::instance::Group>,
    /// Mesh files named by more than one `<shape>` (a scene placing one mesh many times),
    /// parsed once: the mesh by (kind and parse options, canonical path), and how many shapes
    /// still name each `filename` value (the last one takes the mesh instead of copying it).
    pub mesh_files: MeshFiles,
    /// How many shapes and top-level emitters have been read (their default names count them).
    shapes: usize,
    emitters: usize,
}

impl<'d> Builder<'d> {
    /// Records a warning about `e`.
    pub fn warn(&mut self, e: &Element, message: impl Display) {
        self.warnings.push(e.warning(message));
    }

    /// Warns about the parameters of `p` no builder read.
    pub fn finish(&mut self, p: &Props) {
        p.finish(&mut self.warnings);
    }

    /// The scene-file location of `e` kept on the scene's objects.
    pub fn source(e: &Element) -> Source {
        Source { file: e.at.file.display().to_string(), line: e.at.line }
    }
}

/// Mesh files read once for all the shapes naming them ([`Builder::mesh_files`]).
#[derive(Default)]
pub struct MeshFiles {
    /// Shapes not yet built that name each `filename` value (after `$parameters`).
    uses: HashMap<String, usize>,
    /// Meshes as read, before any transform, by parse options and canonical path.
    meshes: HashMap<(String, PathBuf), MeshData>,
}

impl MeshFiles {
    /// Counts the `filename` values of the `<shape>`s of `doc`.
    fn of(doc: &Document) -> Self {
        fn walk(e: &Element, uses: &mut HashMap<String, usize>) {
            if e.tag == "shape" {
                for c in &e.children {
                    if c.tag == "string"
                        && c.raw("name") == Some("filename")
                        && let Ok(Some(v)) = c.attr("value")
                    {
                        *uses.entry(v.to_string()).or_default() += 1;
                    }
                }
            }
            e.children.iter().for_each(|c| walk(c, uses));
        }
        let mut uses = HashMap::new();
        walk(&doc.root, &mut uses);
        uses.retain(|_, n| *n > 1);
        MeshFiles { uses, meshes: HashMap::new() }
    }

    /// The mesh of file `path` (`file` as the shape wrote it) parsed with `options` (the
    /// reader and what it was asked for): `read` parses it the first time, later shapes naming
    /// the same file with the same options get a copy. A mesh is the same data however often
    /// it is read, so the scene (and its fingerprint) is the same as when every shape reads
    /// its own.
    pub fn get(
        &mut self,
        file: &str,
        path: &Path,
        options: String,
        read: impl FnOnce() -> Result<MeshData>,
    ) -> Result<MeshData> {
        let Some(left) = self.uses.get_mut(file) else { return read() };
        *left -= 1;
        let last = *left == 0;
        if last {
            self.uses.remove(file);
        }
        let key = (options, std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()));
        if last {
            return match self.meshes.remove(&key) {
                Some(mesh) => Ok(mesh),
                None => read(),
            };
        }
        if let Some(mesh) = self.meshes.get(&key) {
            return Ok(mesh.clone());
        }
        let mesh = read()?;
        self.meshes.insert(key, mesh.clone());
        Ok(mesh)
    }
}

/// A handler of a top-level element.
type TopLevel = for<'d> fn(&mut Builder<'d>, &'d Element) -> Result<()>;

/// The elements allowed directly inside `<scene>`, in the order the error message lists them.
const TOP_LEVEL: &[(&str, TopLevel)] = &[
    ("default", |_, _| Ok(())), // read by the record stage
    ("integrator", integrator),
    ("sensor", top_sensor),
    ("bsdf", top_bsdf),
    ("texture", |_, _| Ok(())), // built where a BSDF refers to it
    ("medium", |_, _| Ok(())),  // read where a shape refers to it
    ("sampler", |_, _| Ok(())), // a sensor may refer to it; sampling is Opticks's own
    ("shape", top_shape),
    ("emitter", top_emitter),
];

/// Builds the scene of `doc`.
pub fn build(doc: &Document) -> Result<LoadedScene> {
    let mut b = Builder {
        doc,
        desc: SceneDescription::default(),
        warnings: doc.warnings.clone(),
        bsdfs: HashMap::new(),
        in_progress: HashSet::new(),
        material_of: HashMap::new(),
        used: HashSet::new(),
        textures: HashMap::new(),
        bsdf_textures: Vec::new(),
        groups: HashMap::new(),
        mesh_files: MeshFiles::of(doc),
        shapes: 0,
        emitters: 0,
    };
    for e in &doc.root.children {
        let Some((_, handle)) = TOP_LEVEL.iter().find(|(tag, _)| *tag == e.tag) else {
            let names: Vec<&str> = TOP_LEVEL.iter().map(|(tag, _)| *tag).collect();
            return Err(e.err(format!(
                "unsupported element <{}> (supported at the top level of <scene>: {})",
                e.tag,
                names.join(", ")
            )));
        };
        handle(&mut b, e)?;
    }
    if let Some(wanted) = doc.camera.as_deref()
        && b.desc.camera.is_none()
    {
        return Err(no_such_sensor(doc, wanted));
    }
    // Unused named BSDFs and media: Mitsuba would not mind either, but it is usually a typo.
    for e in &doc.root.children {
        let area = e.tag == "emitter" && e.raw("type") == Some("area");
        let group = e.tag == "shape" && e.raw("type") == Some("shapegroup");
        if (area || group || matches!(e.tag.as_str(), "bsdf" | "medium" | "sampler"))
            && e.raw("id").is_some_and(|id| !b.used.contains(id))
        {
            let what = match e.tag.as_str() {
                "bsdf" => "BSDF",
                "shape" => "shapegroup",
                other => other,
            };
            b.warn(e, format!("this {what} is never used"));
        }
    }
    Ok(LoadedScene { description: b.desc, warnings: b.warnings })
}

/// `<integrator>`: read and ignored (Opticks always traces unbounded paths).
fn integrator<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<()> {
    let mut p = Props::of(e)?;
    if let Some((d, node)) = p.int("max_depth")?
        && d != -1
    {
        b.warn(
            node,
            format!("max_depth = {d} is ignored: Opticks always traces unbounded paths (Mitsuba's -1)"),
        );
    }
    // Everything else about the integrator is Mitsuba's business.
    Ok(())
}

/// A `<sensor>`: the camera if it is the first one (or the one [`Document::camera`] names),
/// else a warning.
fn top_sensor<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<()> {
    match b.doc.camera.as_deref() {
        Some(wanted) if e.raw("id") == Some(wanted) => b.desc.camera = Some(sensor::sensor(b, e)?),
        Some(_) => b.warn(e, "not the <sensor> --camera names; ignored"),
        None if b.desc.camera.is_none() => b.desc.camera = Some(sensor::sensor(b, e)?),
        None => {
            b.warn(e, "only the first <sensor> is used (--camera ID chooses another); this one is ignored")
        }
    }
    Ok(())
}

/// The error for a [`Document::camera`] that no `<sensor>` has as its `id`, listing the ids.
fn no_such_sensor(doc: &Document, wanted: &str) -> crate::scene_formats::SceneFileError {
    let ids: Vec<String> = doc
        .root
        .children
        .iter()
        .filter(|c| c.tag == "sensor")
        .map(|c| c.raw("id").map_or_else(|| "(one without an id)".to_string(), |id| format!("{id:?}")))
        .collect();
    let has = if ids.is_empty() {
        "the scene has no <sensor>".to_string()
    } else {
        format!("the scene's sensors: {}", ids.join(", "))
    };
    doc.root.err(format!("--camera {wanted:?}: no <sensor> has that id ({has})"))
}

fn top_bsdf<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<()> {
    let parsed = bsdf::bsdf(b, e)?;
    if e.attr("id")?.is_none() {
        b.warn(e, format!("a top-level BSDF without an id cannot be used ({})", parsed.name));
    }
    Ok(())
}

fn top_shape<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<()> {
    match e.raw("type") {
        // Built where an instance first uses it.
        Some("shapegroup") => {
            e.required("id")?;
        }
        Some("instance") => {
            let meshes = super::instance::instance(b, e, b.shapes)?;
            b.desc.meshes.extend(meshes);
        }
        _ => {
            let mesh = shape::shape(b, e, b.shapes)?;
            b.desc.meshes.push(mesh);
        }
    }
    b.shapes += 1;
    Ok(())
}

fn top_emitter<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<()> {
    emitter::top_emitter(b, e, b.emitters)?;
    b.emitters += 1;
    Ok(())
}
