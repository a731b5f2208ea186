//! Radiance records → the scene: modifiers defined and resolved, surfaces tessellated into
//! meshes (`mesh` primitives read from their `.obj` files: `build/mesh.rs`), `!xform` includes
//! followed (transformed, depth and cycles bounded), every other command refused. The mapping of each primitive and material is the manual's
//! (`docs/scene-formats.md`, "Radiance").

use super::err;
use super::lexer::{self, Primitive, Record};
use super::sky::{self, SkyFunc};
use super::xform::{self, Similarity};
use crate::scene_formats::vrml::triangulate::triangulate;
use crate::scene_formats::{FileLocation, LoadedScene, SceneFileError, tessellate};
use glam::DVec3;
use opticks_core::bsdf::{
    Blend, Bsdf, Lambert, Material, MaterialError, ModifiedPhong, SmoothConductor, SmoothDielectric,
    ThinDielectric,
};
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::{AreaEmission, MeshDesc, Photometry, SceneDescription, Source};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

mod mesh;
mod sources;

/// Includes nest at most this deep.
pub const MAX_INCLUDE_DEPTH: usize = 16;
/// At most this many files are read, includes included (a file included twice counts twice).
pub const MAX_FILES: usize = 10_000;
/// At most this many triangles in the scene (a sphere is 16 384).
pub const MAX_TRIANGLES: usize = 50_000_000;

/// A `source` narrower than this (full angle, degrees) with a constant radiance is a
/// directional light (gensky's sun is 0.5°); a wider one an environment light of its cone.
pub const DIRECTIONAL_SOURCE_DEGREES: f64 = 5.0;

/// The materials Opticks maps (the manual's table).
const MATERIALS: &[&str] =
    &["plastic", "metal", "trans", "glass", "dielectric", "mirror", "light", "glow", "illum"];
/// The surfaces Opticks tessellates.
const SURFACES: &[&str] = &["polygon", "sphere", "bubble", "cone", "cup", "cylinder", "tube", "ring"];
/// Radiance's other primitive types, by what they are (each refused naming it).
const UNSUPPORTED: &[(&str, &[&str])] = &[
    ("a surface", &["instance"]),
    (
        "a material",
        &[
            "spotlight",
            "plastic2",
            "metal2",
            "trans2",
            "ashik2",
            "WGMDfunc",
            "interface",
            "plasfunc",
            "metfunc",
            "transfunc",
            "BRTDfunc",
            "plasdata",
            "metdata",
            "transdata",
            "BSDF",
            "aBSDF",
            "antimatter",
            "prism1",
            "prism2",
            "mist",
        ],
    ),
    ("a texture", &["texfunc", "texdata"]),
    (
        "a pattern",
        &[
            "colorfunc",
            "brightfunc",
            "colordata",
            "brightdata",
            "specfunc",
            "specdata",
            "specpict",
            "colorpict",
        ],
    ),
    ("a text pattern", &["colortext", "brighttext"]),
    ("a mixture", &["mixfunc", "mixdata", "mixpict", "mixtext"]),
];

/// What a modifier name stands for.
#[derive(Clone, Debug)]
enum Modifier {
    /// Surfaces it modifies are not drawn (`void`, an `illum` without an alternate, an alias of
    /// one of them).
    Invisible,
    /// A material: the core's, its emission (`light`, `glow`), and its index in the scene's
    /// materials once a surface uses it.
    Material { material: Material, emission: Option<Rgb>, index: Option<usize> },
    /// gensky's or gendaylit's `skyfunc`: the sky's brightness, for a `glow` to modify.
    Sky(Box<SkyFunc>),
    /// A `glow` modified by a `skyfunc`: colour × the sky's brightness, for a `source`.
    SkyGlow(Box<SkyFunc>, Rgb),
    /// What an earlier definition is (an `illum`'s alternate material): never stored, the
    /// name is mapped to that definition instead.
    Same(usize),
}

/// The include being read: its transform and xform's renaming options, accumulated.
#[derive(Clone, Debug, Default)]
struct Frame {
    transform: Similarity,
    prefix: Option<String>,
    modifier: Option<String>,
    invert: bool,
}

struct Builder {
    desc: SceneDescription,
    warnings: Vec<String>,
    /// Definitions, latest last; `names` maps a name to its latest.
    modifiers: Vec<Modifier>,
    names: HashMap<String, usize>,
    /// The files being read, outermost first (canonical paths, for cycles).
    stack: Vec<PathBuf>,
    files_read: usize,
    triangles: usize,
    void_surfaces: usize,
}

/// Reads `paths` in order, with everything they include, into one scene (no camera: see
/// [`super::view`]); the modifiers each defines are defined in those after it.
pub fn build(paths: &[PathBuf]) -> Result<LoadedScene, SceneFileError> {
    let mut b = Builder {
        // Radiance's numbers are "visible watts": lux by its own rule (179 lm/W, its primaries).
        desc: SceneDescription { photometry: Photometry::RADIANCE, ..Default::default() },
        warnings: Vec::new(),
        modifiers: Vec::new(),
        names: HashMap::new(),
        stack: Vec::new(),
        files_read: 0,
        triangles: 0,
        void_surfaces: 0,
    };
    for path in paths {
        let data = crate::input_file::read(path)
            .map_err(|source| SceneFileError::Read { path: path.to_path_buf(), source })?;
        b.file(path, &data, &Frame::default())?;
    }
    let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    let path = names.join(" ");
    if b.void_surfaces > 0 {
        b.warnings.push(format!(
            "{}: {} surface(s) modified by void (or an illum without an alternate material) are invisible and were left out",
            path,
            b.void_surfaces
        ));
    }
    if b.desc.meshes.is_empty() {
        b.warnings.push(format!("{path}: the scene has no surfaces"));
    } else if b.desc.meshes.iter().all(|m| m.emission.is_none())
        && b.desc.directional_lights.is_empty()
        && b.desc.environment_lights.is_empty()
    {
        b.warnings.push(format!(
            "{path}: no light or glow surface and no source (sun or sky): the scene has no light of its own"
        ));
    }
    Ok(LoadedScene { description: b.desc, warnings: b.warnings })
}

fn at(file: &Path, line: u32, column: u32) -> FileLocation {
    FileLocation { file: file.to_path_buf(), line, column }
}

impl Builder {
    /// The records of one file, under `frame`.
    fn file(&mut self, path: &Path, data: &[u8], frame: &Frame) -> Result<(), SceneFileError> {
        self.files_read += 1;
        self.stack.push(std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()));
        for record in lexer::parse(data, path)? {
            match record {
                Record::Primitive(p) => self.primitive(path, &p, frame)?,
                Record::Command { words, text, line, column } => {
                    self.command(path, &words, &text, at(path, line, column), frame)?
                }
            }
        }
        self.stack.pop();
        Ok(())
    }

    /// A `!` line: `xform` is read as an include, `gensky` and `gendaylit` are interpreted
    /// (`sources.rs`), anything else is refused. Nothing is run.
    fn command(
        &mut self,
        path: &Path,
        words: &[String],
        text: &str,
        here: FileLocation,
        frame: &Frame,
    ) -> Result<(), SceneFileError> {
        let program = words.first().map_or("", |w| w.rsplit('/').next().unwrap_or(w));
        let element = format!("!{program}");
        if let Some(generator) = sky::Generator::named(program) {
            return self.sky(path, generator, words, text, &here, frame);
        }
        match program {
            "xform" => {}
            _ => {
                return Err(err(
                    &here,
                    &element,
                    format!(
                        "commands in a scene file are never executed; only !xform is read (as an include): \"!{text}\""
                    ),
                ));
            }
        }
        if let Some(c) = text.chars().find(|c| "|;&<>`$(){}*?[]~".contains(*c)) {
            return Err(err(
                &here,
                &element,
                format!("shell syntax ('{c}') is not supported in an !xform line: \"!{text}\""),
            ));
        }
        let x = xform::parse(&words[1..]).map_err(|e| err(&here, &element, e.to_string()))?;
        let inner = Frame {
            transform: frame.transform.then_after(&x.transform),
            prefix: match (&frame.prefix, &x.prefix) {
                (Some(o), Some(i)) => Some(format!("{o}.{i}")),
                (o, i) => o.clone().or(i.clone()),
            },
            // The outer xform rewrites what the inner one writes: its -m wins.
            modifier: frame.modifier.clone().or(x.modifier),
            invert: frame.invert != x.invert,
        };
        let folder = path.parent().unwrap_or(Path::new(""));
        for name in &x.files {
            let file = folder.join(name);
            if self.stack.len() >= MAX_INCLUDE_DEPTH {
                return Err(err(
                    &here,
                    &element,
                    format!("includes nest deeper than {MAX_INCLUDE_DEPTH} files"),
                ));
            }
            if self.files_read >= MAX_FILES {
                return Err(err(&here, &element, format!("more than {MAX_FILES} files included")));
            }
            let canonical = std::fs::canonicalize(&file).unwrap_or_else(|_| file.clone());
            if self.stack.contains(&canonical) {
                return Err(err(
                    &here,
                    &element,
                    format!(
                        "{} includes itself (through {} file(s)): an include cycle",
                        file.display(),
                        self.stack.len()
                    ),
                ));
            }
            let data = crate::input_file::read(&file)
                .map_err(|e| err(&here, &element, format!("cannot read {}: {e}", file.display())))?;
            self.file(&file, &data, &inner)?;
        }
        Ok(())
    }

    fn primitive(&mut self, path: &Path, p: &Primitive, frame: &Frame) -> Result<(), SceneFileError> {
        let here = at(path, p.modifier.line, p.modifier.column);
        let kind = p.kind.text.as_str();
        if kind == "alias" {
            return self.alias(p, &here);
        }
        if MATERIALS.contains(&kind) {
            let i = match self.material(p, &here, frame)? {
                Modifier::Same(i) => i,
                m => {
                    self.modifiers.push(m);
                    self.modifiers.len() - 1
                }
            };
            self.names.insert(p.ident.text.clone(), i);
            return Ok(());
        }
        if SURFACES.contains(&kind) {
            return self.surface(path, p, &here, frame);
        }
        if kind == "mesh" {
            return self.mesh(path, p, &here, frame);
        }
        if kind == "source" {
            return self.source(path, p, &here, frame);
        }
        let message = match UNSUPPORTED.iter().find(|(_, names)| names.contains(&kind)) {
            Some((what, _)) => format!("{kind} is {what} Opticks does not read yet"),
            None => format!("unknown primitive type \"{kind}\""),
        };
        Err(err(
            &here,
            &p.describe(),
            format!(
                "{message} (supported: the surfaces {}, mesh (of a .obj file) and the materials {}, with void and alias)",
                SURFACES.join(", "),
                MATERIALS.join(", ")
            ),
        ))
    }

    /// The definition `name` refers to now; `void` is invisibility.
    fn lookup(
        &self,
        name: &str,
        here: &FileLocation,
        element: &str,
    ) -> Result<Option<usize>, SceneFileError> {
        if name == "void" {
            return Ok(None);
        }
        self.names.get(name).map(|&i| Some(i)).ok_or_else(|| {
            err(
                here,
                element,
                format!("undefined modifier \"{name}\" (a modifier must be defined before it is used)"),
            )
        })
    }

    /// `void alias new old`: `new` names what `old` names now.
    fn alias(&mut self, p: &Primitive, here: &FileLocation) -> Result<(), SceneFileError> {
        let element = p.describe();
        if p.modifier.text != "void" {
            return Err(err(
                here,
                &element,
                format!(
                    "an alias with modifier \"{}\" would modify a material by a pattern or texture, which Opticks does not read yet (void alias only)",
                    p.modifier.text
                ),
            ));
        }
        let target = p.alias_of.as_ref().expect("the lexer reads an alias's reference");
        let i = match self.lookup(&target.text, here, &element)? {
            Some(i) => i,
            None => {
                self.modifiers.push(Modifier::Invisible);
                self.modifiers.len() - 1
            }
        };
        self.names.insert(p.ident.text.clone(), i);
        Ok(())
    }

    /// A material definition (the manual's table).
    fn material(
        &mut self,
        p: &Primitive,
        here: &FileLocation,
        frame: &Frame,
    ) -> Result<Modifier, SceneFileError> {
        let element = p.describe();
        let kind = p.kind.text.as_str();
        if kind == "glow"
            && p.modifier.text != "void"
            && let Some(&i) = self.names.get(&p.modifier.text)
            && let Modifier::Sky(g) = &self.modifiers[i]
        {
            if p.reals.len() != 4 || !p.strings.is_empty() || !p.ints.is_empty() {
                return Err(err(
                    here,
                    &element,
                    "glow takes 0 string, 0 integer and 4 real arguments".into(),
                ));
            }
            let r = &p.reals;
            let rgb = Rgb::new(r[0] as f32, r[1] as f32, r[2] as f32);
            if !rgb.is_finite() || rgb.min_element() < 0.0 {
                return Err(err(here, &element, format!("the radiance {rgb} must not be negative")));
            }
            return Ok(Modifier::SkyGlow(g.clone(), rgb));
        }
        if p.modifier.text != "void" {
            return Err(err(
                here,
                &element,
                format!(
                    "modifier \"{}\": a material modified by a pattern or texture is not supported yet (use void)",
                    p.modifier.text
                ),
            ));
        }
        let (strings, reals): (&[usize], &[usize]) = match kind {
            "plastic" | "metal" => (&[0], &[5]),
            "trans" => (&[0], &[7]),
            "glass" => (&[0], &[3, 4]),
            "dielectric" => (&[0], &[5]),
            "mirror" | "light" => (&[0], &[3]),
            "glow" => (&[0], &[4]),
            _ => (&[0, 1], &[3]), // illum
        };
        let counts =
            |allowed: &[usize]| allowed.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(" or ");
        if !strings.contains(&p.strings.len()) || !p.ints.is_empty() || !reals.contains(&p.reals.len()) {
            return Err(err(
                here,
                &element,
                format!(
                    "{kind} takes {} string, 0 integer and {} real arguments, not {}, {} and {}",
                    counts(strings),
                    counts(reals),
                    p.strings.len(),
                    p.ints.len(),
                    p.reals.len()
                ),
            ));
        }
        let r = &p.reals;
        let rgb = Rgb::new(r[0] as f32, r[1] as f32, r[2] as f32);
        let mat = |e: MaterialError| SceneFileError::Material {
            at: here.clone(),
            element: element.clone(),
            source: e,
        };
        let name = p.ident.text.clone();
        let material = |bsdf: Bsdf, two_sided: bool| Material { name: name.clone(), bsdf, two_sided };
        Ok(match kind {
            "plastic" | "metal" | "trans" => {
                let (spec, rough) = (r[3] as f32, r[4] as f32);
                let (trans, tspec) = if kind == "trans" { (r[5] as f32, r[6] as f32) } else { (0.0, 0.0) };
                for (v, what) in
                    [(spec, "specularity"), (trans, "transmissivity"), (tspec, "transmitted specularity")]
                {
                    if !(0.0..=1.0).contains(&v) {
                        return Err(err(here, &element, format!("{what} {v} must be within [0, 1]")));
                    }
                }
                if rough < 0.0 {
                    return Err(err(here, &element, format!("roughness {rough} must not be negative")));
                }
                if trans > 0.0 {
                    self.warnings.push(format!(
                        "{here}: {element}: transmission is not modelled yet: the transmitted fraction {:.3} (diffuse and specular) is absorbed; the surface reflects as {kind} does",
                        trans * (1.0 - spec)
                    ));
                }
                // The colour is a reflectance (the core's check, naming it); then base and
                // highlight sum to at most 1 but for rounding, which the min takes away.
                Lambert::new(rgb).map_err(mat)?;
                let highlight = if kind == "metal" { rgb * spec } else { Rgb::splat(spec) };
                let base = (rgb * ((1.0 - spec) * (1.0 - trans))).min(Rgb::ONE - highlight).max(Rgb::ZERO);
                let bsdf = if spec == 0.0 {
                    Bsdf::Lambert(Lambert::new(base).map_err(mat)?)
                } else if rough == 0.0 {
                    // A perfect highlight: the diffuse base plus a mirror of the highlight's
                    // colour, in Radiance's proportions (the blend's weights give the (1 − s)
                    // and s; the colours are taken as written, so that a white 1 stays 1).
                    let diffuse = rgb * (1.0 - trans);
                    let tint = if kind == "metal" { rgb } else { Rgb::ONE };
                    Bsdf::Blend(
                        Blend::new(
                            spec,
                            Bsdf::Lambert(Lambert::new(diffuse).map_err(mat)?),
                            Bsdf::SmoothConductor(SmoothConductor::new(tint, None).map_err(mat)?),
                        )
                        .map_err(mat)?,
                    )
                } else {
                    Bsdf::ModifiedPhong(
                        ModifiedPhong::new(base, highlight, ModifiedPhong::exponent_for_slope(rough))
                            .map_err(mat)?,
                    )
                };
                Modifier::Material { material: material(bsdf, true), emission: None, index: None }
            }
            "glass" => {
                let n = r.get(3).map_or(1.52, |&n| n as f32);
                let bsdf = ThinDielectric::new(n, 1.0, Rgb::ONE, rgb).map_err(mat)?;
                Modifier::Material {
                    material: material(Bsdf::ThinDielectric(bsdf), true),
                    emission: None,
                    index: None,
                }
            }
            "dielectric" => {
                let (n, hartmann) = (r[3] as f32, r[4]);
                if hartmann != 0.0 {
                    self.warnings.push(format!(
                        "{here}: {element}: the Hartmann constant {hartmann} (dispersion) is ignored: the index is {n} at every wavelength"
                    ));
                }
                if rgb.min_element() <= 0.0 || rgb.max_element() > 1.0 {
                    return Err(err(
                        here,
                        &element,
                        format!(
                            "the transmission per unit length {rgb} must be within (0, 1] in each channel"
                        ),
                    ));
                }
                // Transmission t per unit length: σ_a = −ln t, per unit of the transformed
                // scene (xform writes t^(1/s)).
                let scale = frame.transform.scale as f32;
                let sigma = Rgb::new(-rgb.x.ln(), -rgb.y.ln(), -rgb.z.ln()) / scale;
                let bsdf = SmoothDielectric::new(n, 1.0, Rgb::ONE, Rgb::ONE)
                    .and_then(|d| d.with_absorption(sigma))
                    .map_err(mat)?;
                Modifier::Material {
                    material: material(Bsdf::SmoothDielectric(bsdf), false),
                    emission: None,
                    index: None,
                }
            }
            "mirror" => {
                let bsdf = SmoothConductor::new(rgb, None).map_err(mat)?;
                Modifier::Material {
                    material: material(Bsdf::SmoothConductor(bsdf), true),
                    emission: None,
                    index: None,
                }
            }
            "light" | "glow" => {
                if !rgb.is_finite() || rgb.min_element() < 0.0 {
                    return Err(err(here, &element, format!("the radiance {rgb} must not be negative")));
                }
                let black = Bsdf::Lambert(Lambert::new(Rgb::ZERO).map_err(mat)?);
                let emission = (rgb.max_element() > 0.0).then_some(rgb);
                Modifier::Material { material: material(black, false), emission, index: None }
            }
            _ => match p.strings.first() {
                // illum: a proxy for the direct calculation; what it stands for (the light
                // through a window) is traced anyway, so the surface is its alternate material.
                None => Modifier::Invisible,
                Some(alt) => match self.lookup(&alt.text, here, &element)? {
                    None => Modifier::Invisible,
                    Some(i) => Modifier::Same(i),
                },
            },
        })
    }

    /// The index in the scene of the material of modifier `i`, added on first use.
    fn material_index(&mut self, i: usize) -> Option<(usize, Option<Rgb>)> {
        let Modifier::Material { material, emission, index } = &mut self.modifiers[i] else { return None };
        let index = *index.get_or_insert_with(|| {
            self.desc.materials.push(material.clone());
            self.desc.materials.len() - 1
        });
        Some((index, *emission))
    }

    fn surface(
        &mut self,
        path: &Path,
        p: &Primitive,
        here: &FileLocation,
        frame: &Frame,
    ) -> Result<(), SceneFileError> {
        let element = p.describe();
        let kind = p.kind.text.as_str();
        let modifier = frame.modifier.as_deref().unwrap_or(&p.modifier.text);
        let resolved = self.lookup(modifier, here, &element)?;
        let bad = |m: String| err(here, &element, m);
        if !p.strings.is_empty() || !p.ints.is_empty() {
            return Err(bad(format!("{kind} takes no string or integer arguments")));
        }
        let r = &p.reals;
        let need = |n: usize| -> Result<(), SceneFileError> {
            if r.len() == n {
                Ok(())
            } else {
                Err(bad(format!("{kind} takes {n} real arguments, not {}", r.len())))
            }
        };
        let t = &frame.transform;
        let point = |i: usize| t.point(DVec3::new(r[i], r[i + 1], r[i + 2]));
        let inward = matches!(kind, "bubble" | "cup" | "tube") != frame.invert;
        let mut mesh = match kind {
            "polygon" => {
                if r.len() < 9 || !r.len().is_multiple_of(3) {
                    return Err(bad(format!(
                        "a polygon takes 3 reals per vertex and at least 3 vertices, not {} reals",
                        r.len()
                    )));
                }
                let mut positions: Vec<Vec3> = (0..r.len() / 3).map(|v| point(3 * v).as_vec3()).collect();
                // xform reverses a mirrored (or inverted) polygon so that its front stays where
                // the mirrored normal points.
                if t.mirrors() != frame.invert {
                    positions.reverse();
                }
                let corners: Vec<u32> = (0..positions.len() as u32).collect();
                let mut triangles = Vec::new();
                if !triangulate(&positions, &corners, &mut triangles) {
                    self.warnings.push(format!(
                        "{here}: {element}: a polygon of {} vertices is fanned, not ear-clipped",
                        corners.len()
                    ));
                }
                (positions, triangles, Vec::new(), Vec::new())
            }
            "sphere" | "bubble" => {
                need(4)?;
                let radius = r[3] * t.scale;
                if radius <= 0.0 {
                    return Err(bad(format!("the radius {} must be positive", r[3])));
                }
                // A light's sphere (Radiance's point source is a small one) on the grid that
                // keeps its intensity within 0.1 % (tessellate's module docs), a surface seen in
                // images on the fine grid.
                let emits = resolved.is_some_and(|i| {
                    matches!(self.modifiers[i], Modifier::Material { emission: Some(_), .. })
                });
                let grid =
                    if emits { tessellate::LIGHT_SPHERE } else { (tessellate::SEGMENTS, tessellate::RINGS) };
                tessellate::sphere_grid(point(0).as_vec3(), radius as f32, grid)
            }
            "cone" | "cup" | "cylinder" | "tube" => {
                let cylinder = matches!(kind, "cylinder" | "tube");
                need(if cylinder { 7 } else { 8 })?;
                let (r0, r1) = if cylinder { (r[6], r[6]) } else { (r[6], r[7]) };
                if r0 < 0.0 || r1 < 0.0 || (r0 == 0.0 && r1 == 0.0) || (cylinder && r0 == 0.0) {
                    return Err(bad(format!("the radii {r0} and {r1} must not be negative, nor both 0")));
                }
                tessellate::cone(point(0), point(3), r0 * t.scale, r1 * t.scale)
                    .ok_or_else(|| bad("its two end points are the same".into()))?
            }
            _ => {
                // ring
                need(8)?;
                let (r0, r1) = (r[6], r[7]);
                let normal = t.vector(DVec3::new(r[3], r[4], r[5]));
                let normal = if frame.invert { -normal } else { normal };
                tessellate::ring(point(0), normal, r0 * t.scale, r1 * t.scale).ok_or_else(|| {
                    bad(format!("needs a non-zero normal and radii 0 ≤ inner < outer, not {r0} and {r1}"))
                })?
            }
        };
        if inward && kind != "polygon" && kind != "ring" {
            tessellate::flip(&mut mesh);
        }
        self.add_surface(path, p, here, frame, modifier, resolved, mesh)
    }

    /// Surface `p`'s triangles (transformed) as a mesh of the material its modifier (`modifier`,
    /// resolved to `resolved`) stands for; none for an invisible one.
    #[allow(clippy::too_many_arguments)]
    fn add_surface(
        &mut self,
        path: &Path,
        p: &Primitive,
        here: &FileLocation,
        frame: &Frame,
        modifier: &str,
        resolved: Option<usize>,
        mesh: tessellate::Tessellation,
    ) -> Result<(), SceneFileError> {
        let bad = |m: String| err(here, &p.describe(), m);
        let Some(i) = resolved else {
            self.void_surfaces += 1;
            return Ok(());
        };
        if matches!(self.modifiers[i], Modifier::Sky(_) | Modifier::SkyGlow(..)) {
            return Err(bad(format!(
                "modifier \"{modifier}\" is a sky (gensky's skyfunc, or a glow of it): it lights a source (the sky and ground domes), not a surface"
            )));
        }
        let Some((material, emission)) = self.material_index(i) else {
            self.void_surfaces += 1;
            return Ok(());
        };
        self.triangles += mesh.1.len();
        if self.triangles > MAX_TRIANGLES {
            return Err(bad(format!("the scene would have more than {MAX_TRIANGLES} triangles")));
        }
        let name = match &frame.prefix {
            Some(prefix) => format!("{prefix}.{}", p.ident.text),
            None => p.ident.text.clone(),
        };
        let (positions, triangles, normals, _) = mesh;
        self.desc.meshes.push(MeshDesc {
            name,
            source: Source { file: path.display().to_string(), line: p.modifier.line },
            positions,
            triangles,
            normals,
            uvs: Vec::new(),
            attributes: Vec::new(),
            material,
            emission: emission.map(AreaEmission::lambertian),
        });
        Ok(())
    }
}
