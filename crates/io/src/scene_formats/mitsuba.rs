//! Mitsuba 3 XML scenes: the subset Opticks renders, read with Mitsuba's semantics.
//!
//! # Document
//!
//! | element | handling |
//! |---|---|
//! | `<scene version="3.x.y">` | root; `version` is required, 2.x and 3.x accepted (0.x files use other parameter names) |
//! | `<default name="n" value="v"/>` | declares `$n`; [`LoadOptions::defines`](super::LoadOptions) override it (like `mitsuba -Dn=v`) |
//! | `$n` in any attribute value | replaced by the parameter's value; an undefined `$n` is an error |
//! | `<integrator>` | read and ignored: Opticks always traces unbounded paths (`max_depth` other than -1 gives a warning) |
//! | `<sensor>` | the camera (below); only the first sensor is used |
//! | `<bsdf id="…">` | a named material, used by `<ref id="…"/>` inside shapes (references may point forward) |
//! | `<shape>` | a triangle mesh (below) |
//! | `<emitter type="point">`, `"spot"`, `"directional"`, `"ies"` | a light (below) |
//! | `<medium id="…" type="homogeneous">` | an absorbing medium, used as a dielectric shape's `interior` (below) |
//! | anything else (`texture`, `include`, …) | error |
//!
//! Properties are `<float>`, `<integer>`, `<boolean>`, `<string>`, `<rgb>`, `<spectrum>`,
//! `<point>`, `<vector>` and `<transform>` elements with a `name`. Colours are
//! `<rgb value="r, g, b">` (commas and/or spaces; a single value means grey), `<spectrum value="v">`
//! (a constant spectrum only) or `<float value="v">`. Every number must be finite. A parameter the
//! loader does not know is ignored with a warning.
//!
//! # `<sensor type="perspective">`
//!
//! | parameter | type | default | |
//! |---|---|---|---|
//! | `fov` | float | — | full field of view in degrees, along `fov_axis` |
//! | `fov_axis` | string | `x` | `x`, `y`, `smaller`, `larger` or `diagonal`; converted to the horizontal angle with the film's aspect ratio as Mitsuba does |
//! | `focal_length` | string | `50mm` | 35 mm-equivalent focal length (used when `fov` is absent; not both) |
//! | `to_world` | transform | identity | camera-to-world: eye = M·(0,0,0), view direction M·(0,0,1), up M·(0,1,0) |
//! | `near_clip`, `far_clip` | float | | ignored |
//! | `<film type="hdrfilm">` | | 768×576 | `width`, `height`; other film parameters are ignored |
//! | `<rfilter>` inside the film | | | `box` is what Opticks does; another filter (or none: Mitsuba's default is `gaussian`) gives a warning |
//! | `<sampler>` | | | ignored |
//!
//! Mitsuba's camera looks along local +z with +y up and local +x pointing to the image **left**;
//! a `<lookat>` builds exactly that frame, and so does any rotation of it. A `to_world` with a
//! negative determinant (a mirror) would flip the image left-right, which a
//! [`CameraDesc`] cannot express: it is an error. Scale or shear
//! (Mitsuba refuses them) gives a warning; only the directions are used. The camera's `target`
//! is M·(0,0,d), d being the distance from `origin` to `target` of the last `<lookat>` (1 if
//! none), so a plain `<lookat>` round-trips.
//!
//! # `<transform name="to_world">`
//!
//! A sequence of the elements below. Each one is applied **after** the ones before it
//! (M ← T·M), as in Mitsuba.
//!
//! | element | attributes |
//! |---|---|
//! | `<translate>` | `x`, `y`, `z` (default 0) or `value="x, y, z"` |
//! | `<scale>` | `x`, `y`, `z` (default 1) or `value="s"` or `value="x, y, z"` |
//! | `<rotate>` | axis `x`, `y`, `z` (or `value="x, y, z"`) and `angle` in degrees, right-handed |
//! | `<lookat>` | `origin`, `target`, `up` (optional, as Mitsuba: any perpendicular) |
//! | `<matrix>` | `value`: 16 numbers, row-major (or 9 for a 3×3 linear part) |
//!
//! # `<bsdf>`
//!
//! | type | parameters | |
//! |---|---|---|
//! | `diffuse` | `reflectance`: colour, default 0.5 | Lambertian, **one-sided** (black from behind), as in Mitsuba; each channel in [0, 1] |
//! | `phong` | see below | Modified Phong, **one-sided**; an **Opticks extension** |
//! | `twosided` | one nested `<bsdf>` or `<ref>` | the nested BSDF on both faces (not around a dielectric) |
//! | `conductor` | `specular_reflectance` (1), `material` (only `"none"`: a perfect mirror), `eta`, `k` (colours; `k` defaults to 1 when `eta` is given) | ideal mirror, **one-sided**; `eta`/`k` give the conductor's Fresnel reflectance |
//! | `roughconductor` | as `conductor`, plus `distribution` (`"beckmann"`, the default, or `"ggx"`), `alpha` (0.1) or both `alpha_u`, `alpha_v` (anisotropic), `sample_visible` (accepted) | microfacet metal, **one-sided** |
//! | `dielectric` | `int_ior` (`"bk7"` = 1.5046), `ext_ior` (`"air"` = 1.000277): numbers or Mitsuba's named indices; `specular_reflectance`, `specular_transmittance` (1) | smooth glass: Fresnel reflection and refraction, both faces (the inside is behind the normal) |
//! | `roughdielectric` | as `dielectric`, plus `distribution`, `alpha` or `alpha_u`/`alpha_v`, `sample_visible` as for `roughconductor` | microfacet glass |
//!
//! Defaults are Mitsuba 3's, including the Beckmann distribution of the microfacet plugins.
//! Named conductor presets (`material="Au"`) are refused rather than silently approximated
//! (Mitsuba derives their RGB values from spectra); give `eta` and `k`. Anisotropic roughness
//! (`alpha_u` along the local frame's tangent, `alpha_v` along its bitangent) uses the tangent of
//! Duff et al.'s orthonormal basis of the normal, which is what Mitsuba uses on meshes without
//! texture coordinates (its `dp_du` is then `coordinate_system(n)`); on meshes with texture
//! coordinates Mitsuba orients it along ∂p/∂u instead, which Opticks does not follow. Giving
//! `alpha` together with `alpha_u`/`alpha_v`, or only one of the two, is an error. Impossible
//! values (an index ≤ 0, `alpha` ≤ 0 or > 1, a reflectance or transmittance outside [0, 1],
//! NaN) are errors located at the offending parameter.
//!
//! ## `<bsdf type="phong">` (Opticks extension)
//!
//! Mitsuba 3 has no `phong` plugin; Mitsuba 0.6 had one, and it is exactly the energy-normalised
//! Modified Phong of Lafortune & Willems 1994, f_r = kd/π + ks·(n+2)/(2π)·cosⁿα, the thesis's
//! material ([`ModifiedPhong`]). Opticks reads it in version 2.x/3.x scenes with Mitsuba 0.6's
//! parameter names (camelCase, as in 0.6):
//!
//! | parameter | type | default | |
//! |---|---|---|---|
//! | `diffuseReflectance` | colour | 0.5 | kd |
//! | `specularReflectance` | colour | 0.2 | ks |
//! | `exponent` | float | 30 | n, in [0, 10⁶] |
//!
//! Like Mitsuba's `phong` and `diffuse` it is one-sided (black from behind) unless wrapped in a
//! `twosided`. Textures are not supported. Impossible parameters are errors, not silently fixed
//! (Mitsuba 0.6 rescaled them with a warning): a negative or non-finite value, an exponent above
//! 10⁶, or kd + ks > 1 in some channel (the surface would create energy). The error names the
//! offending parameter's element, or the `<bsdf>` itself for kd + ks > 1.
//!
//! # `<shape>`
//!
//! | type | parameters | geometry |
//! |---|---|---|
//! | `obj` | `filename` (relative to the XML file's folder), `face_normals` (default false: the OBJ's `vn` vertex normals are the shading normals, and an OBJ without `vn` gets smooth normals generated as Mitsuba does, below; true: faceted), `flip_normals` (also negates the normals), `to_world` (normals by its inverse transpose) | the OBJ's triangles, transformed ([`super::obj`]) |
//! | `rectangle` | `flip_normals`, `to_world` | [-1, 1]² at z = 0, normal +z |
//! | `cube` | `flip_normals`, `to_world` | [-1, 1]³, normals outward |
//!
//! A shape holds at most one BSDF (inline `<bsdf>`, or `<ref id="…"/>` / `<ref name="bsdf"
//! id="…"/>`); without one it gets Mitsuba's default, a one-sided `diffuse` of reflectance 0.5.
//! `flip_normals` reverses the winding. For the analytic `rectangle` and `cube`, whose normals
//! Mitsuba transforms as normals, a mirroring `to_world` also reverses the winding so that the
//! normal keeps pointing where Mitsuba's does; OBJ meshes keep their winding (their face normals
//! follow the transformed vertices, as in Mitsuba). A shape's name is its `id`, else
//! `<type>_<index>` (index among the scene's shapes, from 0).
//!
//! **Generated normals.** Mitsuba 3 gives an OBJ without `vn` smooth vertex normals unless
//! `face_normals` is true (`Mesh::recompute_vertex_normals`), and so does this loader
//! ([`super::obj::generated_vertex_normals`]): angle-weighted sums of the face normals, over the
//! vertices of Mitsuba's OBJ reader (one per distinct `v`/`vt` index pair), computed after
//! `to_world` on the world positions and before `flip_normals` (which then negates them with the
//! winding). A faceted-looking low-poly OBJ therefore renders smooth here as in Mitsuba.
//!
//! ## Absorbing glass: `interior` media
//!
//! A shape with a `dielectric` or `roughdielectric` BSDF may name its inside medium,
//! `<ref name="interior" id="…"/>` (a top-level `<medium>`) or an inline
//! `<medium name="interior" type="homogeneous">`. Opticks renders **purely absorbing** media
//! only, as the glass's Beer–Lambert absorption σ_a (per metre of path inside the shape, see
//! [`SmoothDielectric`]):
//!
//! | parameter | type | default | |
//! |---|---|---|---|
//! | `albedo` | colour | 0.75 (Mitsuba's) | must be **0**: a scattering medium is an error naming the line |
//! | `sigma_t` | colour | 1 | extinction, 1/(scene unit); with albedo 0 it is all absorption |
//! | `scale` | float | 1 | σ_a = `sigma_t` · `scale`, each channel finite and ≥ 0 |
//! | `<phase>` | | | accepted and ignored (nothing scatters); `sample_emitters` is ignored |
//!
//! An `interior` on a shape whose BSDF is not a dielectric, an `exterior` medium (the outside is
//! always vacuum) and a medium of another type are errors.
//!
//! # `<emitter>`
//!
//! | type | where | parameters |
//! |---|---|---|
//! | `area` | inside a `<shape>` | `radiance`: colour, default 1: one-sided Lambertian emission on the front face; extensions below (`exponent`, `filename`, `tangent`, `power`, `lumens`) |
//! | `point` | top level | `position`: point (or the translation of `to_world`), `intensity`: colour, default 1 (W/sr) |
//! | `spot` | top level | `to_world` (position M·0, axis M·(0,0,1)), `intensity` (W/sr on the axis, 1), `cutoff_angle` (degrees, 20), `beam_width` (¾ cutoff): Mitsuba's linear falloff in angle |
//! | `directional` | top level | `irradiance` (W/m², 1), `direction` or `to_world` (M·(0,0,1)): parallel light over the scene's bounding disk |
//! | `ies` | top level | **Opticks extension**: `filename` (relative to the XML file's folder), `to_world` (vertical 0° along M·(0,0,1), horizontal 0° along M·(1,0,0)), `intensity` (colour scale, 1), `scale`, and `power` (W) or `lumens` overriding the flux of the candela distribution |
//!
//! `area` also takes these **Opticks extensions**:
//!
//! | parameter | type | |
//! |---|---|---|
//! | `exponent` | float | a cosⁿ (focused) emitter, f_e = (n+1)/(2π)·cosⁿθ, with `radiance` the radiance along the normal; n in [0, 10⁶] |
//! | `filename` | string | an IES file (relative to the XML file's folder; not with `exponent`), vertical 0° along the geometric normal, cut at 90°; `radiance` (colour, 1) and `scale` (float, 1) scale it, and Φ defaults to radiance·scale·(the file's front-hemisphere flux)/683 W: the panel is the luminaire |
//! | `tangent` | vector | world direction of the profile's horizontal 0°, projected onto each triangle (default +x; +x then +z where it is parallel to the normal); not transformed by the shape's `to_world` |
//! | `power`, `lumens` | colour, float | Φ in W per channel, or lumens keeping the `radiance` colour (not both); the radiance follows |
//!
//! Lumens are converted at 683 lm/W keeping the colour (683·luminance = lumens). The `ies` and
//! area emitters share one reader for `filename`/`scale` and one for `power`/`lumens`. See
//! `docs/scene-formats.md`, "Mitsuba 3 XML: Opticks extensions", and [`crate::ies`] for the IES
//! subset.

use super::lights;
use super::obj::{generated_vertex_normals, read_obj};
use super::{FileLocation, LoadOptions, LoadedScene, SceneFileError};
use glam::{DMat3, DMat4, DVec3};
use opticks_core::bsdf::{
    Bsdf, Lambert, Material, MaterialError, ModifiedPhong, RoughConductor, RoughDielectric, SmoothConductor,
    SmoothDielectric, fresnel,
};
use opticks_core::light::{EmissionProfile, lumens_to_watts};
use opticks_core::math::Frame;
use opticks_core::math::{Rgb, Vec3};
use opticks_core::sampling::microfacet::{Distribution, Microfacet};
use opticks_core::scene::{
    CameraDesc, DirectionalLightDesc, MeshDesc, PointLightDesc, SceneDescription, Source,
};
use roxmltree::{Document, Node};
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

type Result<T> = std::result::Result<T, SceneFileError>;

const TOP_LEVEL: &str = "default, integrator, sensor, bsdf, medium, shape, emitter";
const BSDF_TYPES: &str =
    "diffuse, phong (Opticks extension), twosided, conductor, roughconductor, dielectric, roughdielectric";
const PROPERTY_TAGS: &[&str] =
    &["float", "integer", "boolean", "string", "rgb", "spectrum", "point", "vector", "transform"];

/// Reads and loads a Mitsuba 3 XML file.
pub fn load(path: &Path, options: &LoadOptions) -> Result<LoadedScene> {
    let text = std::fs::read_to_string(path)
        .map_err(|source| SceneFileError::Read { path: path.to_path_buf(), source })?;
    parse(&text, path, options)
}

/// Loads a Mitsuba 3 scene from its text. `path` is used in messages and to resolve relative mesh
/// file names (against its folder); it is not read.
pub fn parse(text: &str, path: &Path, options: &LoadOptions) -> Result<LoadedScene> {
    let doc = Document::parse_with_options(
        text,
        roxmltree::ParsingOptions { allow_dtd: true, ..Default::default() },
    )
    .map_err(|e| xml_error(text, path, e))?;
    let root = doc.root_element();
    let mut cx = Ctx {
        doc: &doc,
        file: path,
        dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
        vars: HashMap::new(),
        warnings: Vec::new(),
    };
    if root.tag_name().name() != "scene" {
        return Err(cx.err(root, "the root element must be <scene version=\"3.0.0\">"));
    }
    cx.check_version(root)?;

    // Parameters first: `<default>` anywhere at the top level, then the caller's overrides.
    for n in elements(root).filter(|n| n.tag_name().name() == "default") {
        let name = cx.raw_required(n, "name")?;
        let value = cx.raw_required(n, "value")?;
        cx.vars.insert(name.to_string(), value.to_string());
    }
    for (k, v) in &options.defines {
        cx.vars.insert(k.clone(), v.clone());
    }

    // Ids of top-level objects, so references may point forward.
    let mut ids: HashMap<String, Node> = HashMap::new();
    for n in elements(root) {
        if let Some(id) = cx.attr(n, "id")? {
            if let Some(prev) = ids.get(&id) {
                let prev_at = cx.loc(*prev);
                return Err(cx.err(n, format!("duplicate id \"{id}\" (first declared at {prev_at})")));
            }
            ids.insert(id, n);
        }
    }

    let mut b = Builder {
        ids,
        parsed: HashMap::new(),
        in_progress: HashSet::new(),
        material_of: HashMap::new(),
        used: HashSet::new(),
    };
    let mut desc = SceneDescription::default();
    let mut shape_index = 0usize;
    let mut emitter_index = 0usize;
    for n in elements(root) {
        match n.tag_name().name() {
            "default" => {}
            "medium" => {} // read where a shape refers to it
            "integrator" => cx.integrator(n)?,
            "sensor" => {
                if desc.camera.is_none() {
                    desc.camera = Some(cx.sensor(n)?);
                } else {
                    cx.warn(n, "only the first <sensor> is used; this one is ignored");
                }
            }
            "bsdf" => {
                let bsdf = cx.bsdf(n, &mut b)?;
                if cx.attr(n, "id")?.is_none() {
                    cx.warn(n, format!("a top-level BSDF without an id cannot be used ({})", bsdf.name));
                }
            }
            "shape" => {
                let mesh = cx.shape(n, shape_index, &mut b, &mut desc.materials)?;
                desc.meshes.push(mesh);
                shape_index += 1;
            }
            "emitter" => {
                match cx.top_emitter(n, emitter_index)? {
                    TopEmitter::Point(p) => desc.point_lights.push(p),
                    TopEmitter::Directional(d) => desc.directional_lights.push(d),
                }
                emitter_index += 1;
            }
            other => {
                return Err(cx.err(
                    n,
                    format!(
                        "unsupported element <{other}> (supported at the top level of <scene>: {TOP_LEVEL})"
                    ),
                ));
            }
        }
    }
    // Unused named BSDFs and media: Mitsuba would not mind either, but it is usually a typo.
    let mut unused: Vec<Node> = elements(root)
        .filter(|n| matches!(n.tag_name().name(), "bsdf" | "medium"))
        .filter(|n| n.attribute("id").is_some_and(|id| !b.used.contains(id)))
        .collect();
    unused.sort_by_key(|n| n.range().start);
    for n in unused {
        let what = if n.tag_name().name() == "medium" { "medium" } else { "BSDF" };
        cx.warn(n, format!("this {what} is never used"));
    }
    Ok(LoadedScene { description: desc, warnings: cx.warnings })
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

fn elements<'a, 'i>(n: Node<'a, 'i>) -> impl Iterator<Item = Node<'a, 'i>> {
    n.children().filter(|c| c.is_element())
}

/// `<tag type="…" name="…" id="…">` as written in the file.
fn describe(n: Node) -> String {
    let mut s = format!("<{}", n.tag_name().name());
    for key in ["type", "name", "id"] {
        if let Some(v) = n.attribute(key) {
            s.push_str(&format!(" {key}=\"{v}\""));
        }
    }
    s.push('>');
    s
}

/// A parsed BSDF (Lambertian or Modified Phong), one- or two-sided.
#[derive(Clone, Debug)]
struct ParsedBsdf {
    name: String,
    bsdf: Bsdf,
    two_sided: bool,
}

/// A shape's interior medium: its absorption, where it is declared, its id if top-level (for
/// sharing materials) and a name for the material.
/// What a shape's `<emitter type="area">` sets on its mesh (the `emission*` fields of
/// [`MeshDesc`]).
struct AreaEmission {
    radiance: Rgb,
    profile: Option<EmissionProfile>,
    tangent: Option<Vec3>,
    power: Option<Rgb>,
}

/// An IES file's photometric grid and the flux it carries, W per unit colour.
struct Ies {
    profile: opticks_core::light::IesProfile,
    watts: f32,
    /// The file it was read from (kept on point lights, for writers).
    path: std::path::PathBuf,
}

struct Interior<'a, 'i> {
    sigma_a: Rgb,
    node: Node<'a, 'i>,
    id: Option<String>,
    name: String,
}

/// Named objects and the materials made of them.
struct Builder<'a, 'i> {
    ids: HashMap<String, Node<'a, 'i>>,
    /// Top-level BSDFs already parsed, by id.
    parsed: HashMap<String, ParsedBsdf>,
    /// Ids being parsed (reference cycles).
    in_progress: HashSet<String>,
    /// Material index of a top-level BSDF, by id, once a shape uses it.
    material_of: HashMap<String, usize>,
    /// Ids some `<ref>` pointed to.
    used: HashSet<String>,
}

/// Properties of one plugin element, as Mitsuba collects them, plus its nested objects.
struct Props<'a, 'i> {
    entries: Vec<(String, Node<'a, 'i>, bool)>,
    objects: Vec<Node<'a, 'i>>,
}

impl<'a, 'i> Props<'a, 'i> {
    fn take(&mut self, name: &str) -> Option<Node<'a, 'i>> {
        self.entries.iter_mut().find(|(n, _, _)| n == name).map(|e| {
            e.2 = true;
            e.1
        })
    }
    fn ignore(&mut self, names: &[&str]) {
        for n in names {
            self.take(n);
        }
    }
}

struct Ctx<'a, 'i> {
    doc: &'a Document<'i>,
    file: &'a Path,
    dir: PathBuf,
    vars: HashMap<String, String>,
    warnings: Vec<String>,
}

impl<'a, 'i> Ctx<'a, 'i> {
    // ----- locations, errors, warnings -----

    fn at(&self, byte: usize) -> FileLocation {
        let p = self.doc.text_pos_at(byte);
        FileLocation { file: self.file.to_path_buf(), line: p.row, column: p.col }
    }

    fn loc(&self, n: Node) -> FileLocation {
        self.at(n.range().start)
    }

    fn err(&self, n: Node, message: impl Into<String>) -> SceneFileError {
        SceneFileError::Invalid { at: self.loc(n), element: describe(n), message: message.into() }
    }

    /// An error about attribute `attr` of `n`, located at the attribute's value.
    fn attr_err(&self, n: Node, attr: &str, message: impl Into<String>) -> SceneFileError {
        let at = match n.attribute_node(attr) {
            Some(a) => self.at(a.range_value().start),
            None => self.loc(n),
        };
        SceneFileError::Invalid { at, element: describe(n), message: message.into() }
    }

    fn warn(&mut self, n: Node, message: impl std::fmt::Display) {
        let w = format!("{}: {}: {message}", self.loc(n), describe(n));
        self.warnings.push(w);
    }

    fn source(&self, n: Node) -> Source {
        Source { file: self.file.display().to_string(), line: self.loc(n).line }
    }

    // ----- attributes -----

    fn raw_required<'n>(&self, n: Node<'n, 'i>, name: &str) -> Result<&'n str> {
        n.attribute(name).ok_or_else(|| self.err(n, format!("missing attribute `{name}`")))
    }

    /// Attribute value with `$parameters` substituted.
    fn attr(&self, n: Node, name: &str) -> Result<Option<String>> {
        let Some(raw) = n.attribute(name) else { return Ok(None) };
        if !raw.contains('$') {
            return Ok(Some(raw.to_string()));
        }
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
                match self.vars.get(var) {
                    Some(v) => out.push_str(v),
                    None => {
                        return Err(self.attr_err(
                            n,
                            name,
                            format!(
                                "undefined parameter ${var} in attribute `{name}` (declare it with \
                                 <default name=\"{var}\" value=\"...\"/> or define it when loading)"
                            ),
                        ));
                    }
                }
            }
            rest = &after[len..];
        }
        out.push_str(rest);
        Ok(Some(out))
    }

    fn required(&self, n: Node, name: &str) -> Result<String> {
        self.attr(n, name)?.ok_or_else(|| self.err(n, format!("missing attribute `{name}`")))
    }

    fn numbers(&self, n: Node, name: &str, s: &str) -> Result<Vec<f64>> {
        s.split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
            .map(|t| self.number(n, name, t))
            .collect()
    }

    fn number(&self, n: Node, name: &str, t: &str) -> Result<f64> {
        let v: f64 = t
            .trim()
            .parse()
            .map_err(|_| self.attr_err(n, name, format!("attribute `{name}`: \"{t}\" is not a number")))?;
        if !v.is_finite() || (v != 0.0 && !(v as f32).is_finite()) {
            return Err(self.attr_err(
                n,
                name,
                format!("attribute `{name}`: \"{t}\" is not a finite number"),
            ));
        }
        Ok(v)
    }

    fn float_attr(&self, n: Node, name: &str) -> Result<Option<f64>> {
        match self.attr(n, name)? {
            Some(s) => Ok(Some(self.number(n, name, &s)?)),
            None => Ok(None),
        }
    }

    /// `name="x, y, z"` (exactly three numbers).
    fn vec3_attr(&self, n: Node, name: &str) -> Result<Option<DVec3>> {
        let Some(s) = self.attr(n, name)? else { return Ok(None) };
        let v = self.numbers(n, name, &s)?;
        if v.len() != 3 {
            return Err(self.attr_err(
                n,
                name,
                format!("attribute `{name}` needs 3 numbers, found {}", v.len()),
            ));
        }
        Ok(Some(DVec3::new(v[0], v[1], v[2])))
    }

    /// `value="x, y, z"` or `x`/`y`/`z` attributes (each defaulting to `default`).
    fn xyz(&self, n: Node, default: f64, allow_single_value: bool) -> Result<DVec3> {
        if let Some(s) = self.attr(n, "value")? {
            let v = self.numbers(n, "value", &s)?;
            return match v.len() {
                3 => Ok(DVec3::new(v[0], v[1], v[2])),
                1 if allow_single_value => Ok(DVec3::splat(v[0])),
                k => Err(self.attr_err(n, "value", format!("attribute `value` needs 3 numbers, found {k}"))),
            };
        }
        let mut out = [default; 3];
        for (o, a) in out.iter_mut().zip(["x", "y", "z"]) {
            if let Some(v) = self.float_attr(n, a)? {
                *o = v;
            }
        }
        Ok(DVec3::from_array(out))
    }

    fn check_version(&mut self, root: Node) -> Result<()> {
        let v = self.attr(root, "version")?.ok_or_else(|| {
            self.err(
                root,
                "missing `version` attribute (a Mitsuba 3 scene starts with <scene version=\"3.0.0\">)",
            )
        })?;
        let major = v.split('.').next().and_then(|m| m.trim().parse::<u32>().ok());
        match major {
            Some(2 | 3) => Ok(()),
            Some(m) if m < 2 => Err(self.attr_err(
                root,
                "version",
                format!(
                    "scene version {v} is a Mitsuba 0.x file, whose parameter names differ; \
                     upgrade it to version 3 (supported: 2.x, 3.x)"
                ),
            )),
            _ => Err(self.attr_err(
                root,
                "version",
                format!("unsupported scene version \"{v}\" (supported: 2.x, 3.x)"),
            )),
        }
    }

    // ----- properties -----

    fn props(&self, n: Node<'a, 'i>) -> Result<Props<'a, 'i>> {
        let mut p = Props { entries: Vec::new(), objects: Vec::new() };
        for c in elements(n) {
            if PROPERTY_TAGS.contains(&c.tag_name().name()) {
                let name = self.required(c, "name")?;
                if let Some((_, prev, _)) = p.entries.iter().find(|(k, _, _)| *k == name) {
                    let prev_at = self.loc(*prev);
                    return Err(
                        self.err(c, format!("parameter `{name}` is given twice (first at {prev_at})"))
                    );
                }
                p.entries.push((name, c, false));
            } else {
                p.objects.push(c);
            }
        }
        Ok(p)
    }

    /// Warns about parameters nobody read.
    fn finish(&mut self, p: &Props) {
        for (name, node, used) in &p.entries {
            if !used {
                self.warn(*node, format!("parameter `{name}` is not supported by Opticks and is ignored"));
            }
        }
    }

    fn expect_tag(&self, n: Node, tags: &[&str]) -> Result<()> {
        if tags.contains(&n.tag_name().name()) {
            Ok(())
        } else {
            let list: Vec<String> = tags.iter().map(|t| format!("<{t}>")).collect();
            Err(self.err(n, format!("wrong property type: expected {}", list.join(" or "))))
        }
    }

    fn get_float(&self, p: &mut Props<'a, 'i>, name: &str) -> Result<Option<(f64, Node<'a, 'i>)>> {
        let Some(n) = p.take(name) else { return Ok(None) };
        self.expect_tag(n, &["float", "integer"])?;
        let v = self.required(n, "value")?;
        Ok(Some((self.number(n, "value", &v)?, n)))
    }

    fn get_int(&self, p: &mut Props<'a, 'i>, name: &str) -> Result<Option<(i64, Node<'a, 'i>)>> {
        let Some(n) = p.take(name) else { return Ok(None) };
        self.expect_tag(n, &["integer"])?;
        let v = self.required(n, "value")?;
        let i = v.trim().parse::<i64>().map_err(|_| {
            self.attr_err(n, "value", format!("attribute `value`: \"{v}\" is not an integer"))
        })?;
        Ok(Some((i, n)))
    }

    fn get_bool(&self, p: &mut Props<'a, 'i>, name: &str) -> Result<Option<bool>> {
        let Some(n) = p.take(name) else { return Ok(None) };
        self.expect_tag(n, &["boolean"])?;
        let v = self.required(n, "value")?;
        match v.trim().to_ascii_lowercase().as_str() {
            "true" => Ok(Some(true)),
            "false" => Ok(Some(false)),
            _ => Err(self.attr_err(n, "value", format!("attribute `value`: \"{v}\" is not true or false"))),
        }
    }

    fn get_string(&self, p: &mut Props<'a, 'i>, name: &str) -> Result<Option<(String, Node<'a, 'i>)>> {
        let Some(n) = p.take(name) else { return Ok(None) };
        self.expect_tag(n, &["string"])?;
        Ok(Some((self.required(n, "value")?, n)))
    }

    /// `<rgb>`, constant `<spectrum>` or `<float>`.
    fn get_color(&self, p: &mut Props<'a, 'i>, name: &str) -> Result<Option<(Rgb, Node<'a, 'i>)>> {
        let Some(n) = p.take(name) else { return Ok(None) };
        self.expect_tag(n, &["rgb", "spectrum", "float"])?;
        if n.tag_name().name() == "spectrum" {
            if n.attribute("filename").is_some() {
                return Err(self.err(n, "spectra from files are not supported (use <rgb>)"));
            }
            if self.attr(n, "value")?.is_some_and(|v| v.contains(':')) {
                return Err(self.err(
                    n,
                    "wavelength-dependent spectra are not supported: Opticks renders in RGB \
                     (use <rgb> or a constant <spectrum value=\"v\">)",
                ));
            }
        }
        let s = self.required(n, "value")?;
        let v = self.numbers(n, "value", &s)?;
        let c = match (n.tag_name().name(), v.len()) {
            (_, 1) => DVec3::splat(v[0]),
            ("rgb", 3) => DVec3::new(v[0], v[1], v[2]),
            ("rgb", k) => {
                return Err(self.attr_err(
                    n,
                    "value",
                    format!("an RGB value needs 1 or 3 numbers, found {k}"),
                ));
            }
            (_, k) => return Err(self.attr_err(n, "value", format!("expected a single number, found {k}"))),
        };
        Ok(Some((c.as_vec3(), n)))
    }

    fn get_point(&self, p: &mut Props<'a, 'i>, name: &str) -> Result<Option<(DVec3, Node<'a, 'i>)>> {
        let Some(n) = p.take(name) else { return Ok(None) };
        self.expect_tag(n, &["point", "vector"])?;
        Ok(Some((self.xyz(n, 0.0, false)?, n)))
    }

    fn get_transform(&self, p: &mut Props<'a, 'i>, name: &str) -> Result<Option<(Transform, Node<'a, 'i>)>> {
        let Some(n) = p.take(name) else { return Ok(None) };
        self.expect_tag(n, &["transform"])?;
        Ok(Some((self.transform(n)?, n)))
    }

    // ----- transforms -----

    fn transform(&self, n: Node) -> Result<Transform> {
        let mut m = DMat4::IDENTITY;
        let mut focus = None;
        for c in elements(n) {
            let t = match c.tag_name().name() {
                "translate" => DMat4::from_translation(self.xyz(c, 0.0, false)?),
                "scale" => DMat4::from_scale(self.xyz(c, 1.0, true)?),
                "rotate" => {
                    let axis = match self.vec3_attr(c, "value")? {
                        Some(a) => a,
                        None => self.xyz(c, 0.0, false)?,
                    };
                    let angle = self
                        .float_attr(c, "angle")?
                        .ok_or_else(|| self.err(c, "missing attribute `angle`"))?;
                    if axis.length_squared() == 0.0 {
                        return Err(
                            self.err(c, "the rotation axis is zero (give x, y, z or value=\"x, y, z\")")
                        );
                    }
                    DMat4::from_axis_angle(axis.normalize(), angle.to_radians())
                }
                "lookat" => {
                    let origin = self
                        .vec3_attr(c, "origin")?
                        .ok_or_else(|| self.err(c, "missing attribute `origin`"))?;
                    let target = self
                        .vec3_attr(c, "target")?
                        .ok_or_else(|| self.err(c, "missing attribute `target`"))?;
                    let up = self.vec3_attr(c, "up")?;
                    let d = target - origin;
                    if d.length() == 0.0 {
                        return Err(self.err(c, "origin and target are the same point"));
                    }
                    let dir = d.normalize();
                    let up = up.unwrap_or_else(|| coordinate_system(dir).1);
                    let left = up.cross(dir);
                    if left.length() <= 1e-9 * up.length() {
                        return Err(self.err(c, "`up` is zero or parallel to the view direction"));
                    }
                    let left = left.normalize();
                    let new_up = dir.cross(left);
                    focus = Some(d.length());
                    DMat4::from_cols(
                        left.extend(0.0),
                        new_up.extend(0.0),
                        dir.extend(0.0),
                        origin.extend(1.0),
                    )
                }
                "matrix" => {
                    let s = self.required(c, "value")?;
                    let v = self.numbers(c, "value", &s)?;
                    match v.len() {
                        16 => DMat4::from_cols_slice(&v).transpose(),
                        9 => DMat4::from_mat3(DMat3::from_cols_slice(&v).transpose()),
                        k => {
                            return Err(self.attr_err(
                                c,
                                "value",
                                format!("a matrix needs 16 numbers (row-major 4×4) or 9 (3×3), found {k}"),
                            ));
                        }
                    }
                }
                other => {
                    return Err(self.err(
                        c,
                        format!(
                            "unsupported transform element <{other}> (supported: translate, scale, rotate, lookat, matrix)"
                        ),
                    ));
                }
            };
            m = t * m;
            if !m.is_finite() {
                return Err(self.err(c, "the transform overflows (non-finite matrix)"));
            }
        }
        Ok(Transform { matrix: m, focus })
    }

    // ----- plugins -----

    fn integrator(&mut self, n: Node<'a, 'i>) -> Result<()> {
        let mut p = self.props(n)?;
        if let Some((d, node)) = self.get_int(&mut p, "max_depth")? {
            if d != -1 {
                self.warn(
                    node,
                    format!(
                        "max_depth = {d} is ignored: Opticks always traces unbounded paths (Mitsuba's -1)"
                    ),
                );
            }
        }
        // Everything else about the integrator is Mitsuba's business.
        Ok(())
    }

    fn sensor(&mut self, n: Node<'a, 'i>) -> Result<CameraDesc> {
        let ty = self.required(n, "type")?;
        if ty != "perspective" {
            return Err(self.err(n, format!("unsupported sensor type \"{ty}\" (supported: perspective)")));
        }
        let mut p = self.props(n)?;
        let (mut width, mut height) = (768u32, 576u32);
        for c in p.objects.clone() {
            match c.tag_name().name() {
                "film" => (width, height) = self.film(c)?,
                "sampler" => {}
                other => {
                    return Err(self.err(
                        c,
                        format!("unsupported element <{other}> inside <sensor> (supported: film, sampler)"),
                    ));
                }
            }
        }
        let fov = self.get_float(&mut p, "fov")?;
        let focal = self.get_string(&mut p, "focal_length")?;
        let axis = self.get_string(&mut p, "fov_axis")?;
        let (fov, axis_name, fov_node) = match (fov, focal) {
            (Some(_), Some((_, fnode))) => {
                return Err(self.err(fnode, "give either `fov` or `focal_length`, not both"));
            }
            (Some((f, node)), None) => {
                let axis = axis.as_ref().map_or("x".to_string(), |(a, _)| a.to_ascii_lowercase());
                (f, axis, node)
            }
            (None, focal) => {
                let (s, node) = focal.map_or(("50mm".to_string(), n), |(s, node)| (s, node));
                let mm = self.number(node, "value", s.trim().trim_end_matches("mm"))?;
                if mm <= 0.0 {
                    return Err(self.err(node, format!("focal length {s} must be positive")));
                }
                // 35 mm film: 36×24 mm; Mitsuba measures this fov along the diagonal.
                let f = 2.0 * (36f64.hypot(24.0) / (2.0 * mm)).atan().to_degrees();
                (f, "diagonal".to_string(), node)
            }
        };
        if !(fov > 0.0 && fov < 180.0) {
            return Err(self.err(fov_node, format!("field of view {fov}° is outside (0°, 180°)")));
        }
        let fov_x = fov_to_x(fov, &axis_name, width, height).ok_or_else(|| {
            let node = axis.as_ref().map_or(n, |(_, node)| *node);
            self.err(
                node,
                format!("unsupported fov_axis \"{axis_name}\" (supported: x, y, smaller, larger, diagonal)"),
            )
        })?;
        p.ignore(&["near_clip", "far_clip", "shutter_open", "shutter_close"]);
        let (t, tnode) = match self.get_transform(&mut p, "to_world")? {
            Some((t, node)) => (t, node),
            None => (Transform { matrix: DMat4::IDENTITY, focus: None }, n),
        };
        let m = t.matrix;
        let lin = DMat3::from_mat4(m);
        let det = lin.determinant();
        if m.row(3) != glam::DVec4::W {
            return Err(self.err(tnode, "a camera's to_world must be affine (last matrix row 0, 0, 0, 1)"));
        }
        if det == 0.0 {
            return Err(self.err(tnode, "the camera's to_world is singular"));
        }
        if det < 0.0 {
            return Err(self.err(
                tnode,
                "the camera's to_world mirrors space (negative determinant): the image would be flipped \
                 left-right, which Opticks cameras cannot do; use a <lookat> or a rotation",
            ));
        }
        let ortho = (lin.transpose() * lin - DMat3::IDENTITY).to_cols_array().iter().all(|e| e.abs() < 1e-4);
        if !ortho {
            self.warn(
                tnode,
                "the camera's to_world contains scale or shear (Mitsuba refuses this); only its directions are used",
            );
        }
        let eye = m.transform_point3(DVec3::ZERO);
        let target = m.transform_point3(DVec3::new(0.0, 0.0, t.focus.unwrap_or(1.0)));
        let up = m.transform_vector3(DVec3::Y);
        self.finish(&p);
        Ok(CameraDesc {
            eye: eye.as_vec3(),
            target: target.as_vec3(),
            up: up.as_vec3(),
            fov_x_degrees: fov_x as f32,
            width,
            height,
        })
    }

    fn film(&mut self, n: Node<'a, 'i>) -> Result<(u32, u32)> {
        let ty = self.required(n, "type")?;
        if ty != "hdrfilm" {
            return Err(self.err(n, format!("unsupported film type \"{ty}\" (supported: hdrfilm)")));
        }
        let mut p = self.props(n)?;
        let mut size = [768u32, 576u32];
        for (s, name) in size.iter_mut().zip(["width", "height"]) {
            if let Some((v, node)) = self.get_int(&mut p, name)? {
                *s = u32::try_from(v)
                    .ok()
                    .filter(|&v| v > 0)
                    .ok_or_else(|| self.err(node, format!("{name} {v} must be a positive integer")))?;
            }
        }
        p.ignore(&[
            "pixel_format",
            "component_format",
            "file_format",
            "banner",
            "high_quality_edges",
            "sample_border",
        ]);
        let mut filter_seen = false;
        for c in p.objects.clone() {
            match c.tag_name().name() {
                "rfilter" => {
                    filter_seen = true;
                    let ty = self.required(c, "type")?;
                    if ty != "box" {
                        self.warn(
                            c,
                            format!(
                                "reconstruction filter \"{ty}\" is not supported; Opticks uses a box filter"
                            ),
                        );
                    }
                }
                other => {
                    return Err(self.err(
                        c,
                        format!("unsupported element <{other}> inside <film> (supported: rfilter)"),
                    ));
                }
            }
        }
        if !filter_seen {
            self.warn(n, "no <rfilter>: Mitsuba's default is \"gaussian\", Opticks always uses a box filter");
        }
        self.finish(&p);
        Ok((size[0], size[1]))
    }

    /// A BSDF element: `diffuse`, or `twosided` around one. Top-level BSDFs with an id are cached.
    fn bsdf(&mut self, n: Node<'a, 'i>, b: &mut Builder<'a, 'i>) -> Result<ParsedBsdf> {
        let id = self.attr(n, "id")?;
        let top_level = n.parent().is_some_and(|p| p == self.doc.root_element());
        if let (true, Some(id)) = (top_level, &id) {
            if let Some(done) = b.parsed.get(id) {
                return Ok(done.clone());
            }
            if !b.in_progress.insert(id.clone()) {
                return Err(self.err(n, format!("BSDF \"{id}\" refers to itself")));
            }
        }
        let ty = self.required(n, "type")?;
        let name = id.clone().unwrap_or_else(|| ty.clone());
        let mut p = self.props(n)?;
        let parsed = match ty.as_str() {
            "diffuse" => {
                if let Some(c) = p.objects.first() {
                    return Err(self.err(
                        *c,
                        "unsupported element inside <bsdf type=\"diffuse\"> (textures are not supported; \
                         use <rgb name=\"reflectance\">)",
                    ));
                }
                let (rho, node) = self.get_color(&mut p, "reflectance")?.unwrap_or((Rgb::splat(0.5), n));
                let lambert = Lambert::new(rho).map_err(|source| SceneFileError::Material {
                    at: self.loc(node),
                    element: describe(node),
                    source,
                })?;
                ParsedBsdf { name, bsdf: Bsdf::Lambert(lambert), two_sided: false }
            }
            "phong" => ParsedBsdf { name, bsdf: self.phong(n, &mut p)?, two_sided: false },
            "conductor" | "roughconductor" | "dielectric" | "roughdielectric" => {
                ParsedBsdf { name, bsdf: self.specular(n, &ty, &mut p)?, two_sided: false }
            }
            "twosided" => {
                let inner: Vec<Node> = p.objects.clone();
                match inner.len() {
                    0 => return Err(self.err(n, "a twosided BSDF needs one nested <bsdf> or <ref>")),
                    1 => {}
                    _ => {
                        return Err(self.err(
                            inner[1],
                            "twosided with different front and back BSDFs is not supported (give one BSDF)",
                        ));
                    }
                }
                let c = inner[0];
                let nested = match c.tag_name().name() {
                    "bsdf" => self.bsdf(c, b)?,
                    "ref" => self.bsdf_ref(c, b)?,
                    other => {
                        return Err(self.err(
                            c,
                            format!(
                                "unsupported element <{other}> inside a twosided BSDF (supported: bsdf, ref)"
                            ),
                        ));
                    }
                };
                if nested.two_sided {
                    return Err(self.err(c, "a twosided BSDF cannot wrap another twosided BSDF"));
                }
                if nested.bsdf.transmits() {
                    return Err(self.err(
                        c,
                        "a dielectric already scatters on both faces (its inside is behind the normal); \
                         do not wrap it in a twosided BSDF",
                    ));
                }
                ParsedBsdf { name, bsdf: nested.bsdf, two_sided: true }
            }
            other => {
                return Err(self.attr_err(
                    n,
                    "type",
                    format!("unsupported BSDF type \"{other}\" (supported: {BSDF_TYPES})"),
                ));
            }
        };
        self.finish(&p);
        if let (true, Some(id)) = (top_level, id) {
            b.in_progress.remove(&id);
            b.parsed.insert(id, parsed.clone());
        }
        Ok(parsed)
    }

    /// The parameters of `<bsdf type="phong">` (Mitsuba 0.6's names), validated by
    /// [`ModifiedPhong::new`]; an impossible value is reported at its element (kd + ks > 1 at the
    /// `<bsdf>`, which both parameters belong to).
    fn phong(&self, n: Node<'a, 'i>, p: &mut Props<'a, 'i>) -> Result<Bsdf> {
        if let Some(c) = p.objects.first() {
            return Err(self.err(
                *c,
                "unsupported element inside <bsdf type=\"phong\"> (textures are not supported; \
                 use <rgb> or <float> parameters)",
            ));
        }
        let (kd, kd_node) = self.get_color(p, "diffuseReflectance")?.unwrap_or((Rgb::splat(0.5), n));
        let (ks, ks_node) = self.get_color(p, "specularReflectance")?.unwrap_or((Rgb::splat(0.2), n));
        let (exponent, e_node) = self.get_float(p, "exponent")?.unwrap_or((30.0, n));
        ModifiedPhong::new(kd, ks, exponent as f32).map(Bsdf::ModifiedPhong).map_err(|source| {
            let node = match &source {
                MaterialError::NotFinite("kd") | MaterialError::Negative("kd") => kd_node,
                MaterialError::NotFinite("ks") | MaterialError::Negative("ks") => ks_node,
                MaterialError::NotFinite("exponent")
                | MaterialError::Negative("exponent")
                | MaterialError::TooLarge { .. } => e_node,
                _ => n,
            };
            SceneFileError::Material { at: self.loc(node), element: describe(node), source }
        })
    }

    /// An index of refraction: a number or one of Mitsuba's names (`"bk7"`, `"water"`, …).
    fn get_ior(
        &self,
        p: &mut Props<'a, 'i>,
        name: &str,
        default: f32,
        n: Node<'a, 'i>,
    ) -> Result<(f32, Node<'a, 'i>)> {
        let Some(node) = p.take(name) else { return Ok((default, n)) };
        self.expect_tag(node, &["float", "integer", "string"])?;
        let v = self.required(node, "value")?;
        if node.tag_name().name() == "string" {
            let ior = fresnel::named_ior(&v).ok_or_else(|| {
                let names: Vec<&str> = fresnel::NAMED_IORS.iter().map(|(n, _)| *n).collect();
                self.attr_err(
                    node,
                    "value",
                    format!("unknown index of refraction \"{v}\" (known: {})", names.join(", ")),
                )
            })?;
            return Ok((ior, node));
        }
        Ok((self.number(node, "value", &v)? as f32, node))
    }

    /// `conductor`, `roughconductor`, `dielectric`, `roughdielectric` (Mitsuba 3's parameters and
    /// defaults); an impossible value is reported at its element.
    fn specular(&self, n: Node<'a, 'i>, ty: &str, p: &mut Props<'a, 'i>) -> Result<Bsdf> {
        if let Some(c) = p.objects.first() {
            return Err(self.err(
                *c,
                format!(
                    "unsupported element inside <bsdf type=\"{ty}\"> (textures are not supported; \
                     use <rgb>, <float> or <string> parameters)"
                ),
            ));
        }
        let mut nodes: Vec<(&'static str, Node<'a, 'i>)> = Vec::new();
        let rough = ty.starts_with("rough");
        let (r, rnode) = self.get_color(p, "specular_reflectance")?.unwrap_or((Rgb::ONE, n));
        nodes.push(("specular_reflectance", rnode));
        let microfacet = if rough {
            let (dist, dnode) = self.get_string(p, "distribution")?.unwrap_or(("beckmann".into(), n));
            let distribution = match dist.trim().to_ascii_lowercase().as_str() {
                "beckmann" => Distribution::Beckmann,
                "ggx" => Distribution::Ggx,
                _ => {
                    return Err(self.err(
                        dnode,
                        format!("unknown microfacet distribution \"{dist}\" (known: beckmann, ggx)"),
                    ));
                }
            };
            let _ = self.get_bool(p, "sample_visible")?; // a sampling strategy: same expectation
            let a = self.get_float(p, "alpha")?;
            let au = self.get_float(p, "alpha_u")?;
            let av = self.get_float(p, "alpha_v")?;
            // Mitsuba's rules: `alpha`, or both `alpha_u` and `alpha_v`, never a mixture.
            let (u, v) = match (a, au, av) {
                (Some((a, an)), None, None) => {
                    nodes.push(("alpha", an));
                    (a, a)
                }
                (None, None, None) => (0.1, 0.1),
                (None, Some((u, un)), Some((v, vn))) => {
                    nodes.extend([("alpha_u", un), ("alpha_v", vn), ("alpha", un)]);
                    (u, v)
                }
                (Some(_), Some((_, xn)), _) | (Some(_), _, Some((_, xn))) => {
                    return Err(self.err(xn, "give either alpha or alpha_u and alpha_v, not both"));
                }
                (None, Some((_, xn)), None) | (None, None, Some((_, xn))) => {
                    return Err(self.err(xn, "alpha_u and alpha_v must be given together"));
                }
            };
            Microfacet::anisotropic(distribution, u as f32, v as f32)
        } else {
            Microfacet::ggx(0.1) // unused
        };
        let result = if ty.ends_with("conductor") {
            let (material, mnode) = self.get_string(p, "material")?.unwrap_or(("none".into(), n));
            let eta = self.get_color(p, "eta")?;
            let k = self.get_color(p, "k")?;
            if material != "none" {
                return Err(self.err(
                    mnode,
                    format!(
                        "named conductor \"{material}\" is not supported (Mitsuba derives it from \
                         spectra); give <rgb name=\"eta\"> and <rgb name=\"k\">"
                    ),
                ));
            }
            if let Some((_, en)) = eta {
                nodes.push(("eta", en));
            }
            if let Some((_, kn)) = k {
                nodes.push(("k", kn));
            }
            let ior = eta.map(|(e, _)| (e, k.map_or(Rgb::ONE, |(k, _)| k)));
            if rough {
                RoughConductor::with_microfacet(microfacet, r, ior).map(Bsdf::RoughConductor)
            } else {
                SmoothConductor::new(r, ior).map(Bsdf::SmoothConductor)
            }
        } else {
            let (t, tnode) = self.get_color(p, "specular_transmittance")?.unwrap_or((Rgb::ONE, n));
            nodes.push(("specular_transmittance", tnode));
            let (int_ior, inode) = self.get_ior(p, "int_ior", 1.5046, n)?;
            let (ext_ior, enode) = self.get_ior(p, "ext_ior", 1.000277, n)?;
            nodes.push(("int_ior", inode));
            nodes.push(("ext_ior", enode));
            if rough {
                RoughDielectric::new(int_ior, ext_ior, 0.1, r, t)
                    .and_then(|d| d.with_microfacet(microfacet))
                    .map(Bsdf::RoughDielectric)
            } else {
                SmoothDielectric::new(int_ior, ext_ior, r, t).map(Bsdf::SmoothDielectric)
            }
        };
        result.map_err(|source| {
            let key = match &source {
                MaterialError::NotFinite(k)
                | MaterialError::Negative(k)
                | MaterialError::NotPositive(k)
                | MaterialError::AboveOne(k)
                | MaterialError::TooLarge { name: k, .. } => Some(*k),
                _ => None,
            };
            let node = key.and_then(|k| nodes.iter().find(|(name, _)| *name == k).map(|e| e.1)).unwrap_or(n);
            SceneFileError::Material { at: self.loc(node), element: describe(node), source }
        })
    }

    /// `<ref id="…"/>` to a top-level BSDF.
    fn bsdf_ref(&mut self, n: Node<'a, 'i>, b: &mut Builder<'a, 'i>) -> Result<ParsedBsdf> {
        let id = self.required(n, "id")?;
        let Some(&target) = b.ids.get(&id) else {
            let mut known: Vec<&str> = b
                .ids
                .iter()
                .filter(|(_, t)| t.tag_name().name() == "bsdf")
                .map(|(k, _)| k.as_str())
                .collect();
            known.sort_unstable();
            return Err(self.attr_err(
                n,
                "id",
                format!("reference to unknown id \"{id}\" (BSDF ids in this file: {})", known.join(", ")),
            ));
        };
        if target.tag_name().name() != "bsdf" {
            let at = self.loc(target);
            return Err(self
                .err(n, format!("id \"{id}\" is a <{}> (at {at}), not a <bsdf>", target.tag_name().name())));
        }
        let mut parsed = self.bsdf(target, b)?;
        b.used.insert(id.clone());
        parsed.name = id;
        Ok(parsed)
    }

    fn material_index(
        &self,
        parsed: &ParsedBsdf,
        ref_id: Option<&str>,
        b: &mut Builder,
        materials: &mut Vec<Material>,
    ) -> usize {
        if let Some(id) = ref_id {
            if let Some(&i) = b.material_of.get(id) {
                return i;
            }
        }
        materials.push(Material {
            name: parsed.name.clone(),
            bsdf: parsed.bsdf.clone(),
            two_sided: parsed.two_sided,
        });
        let i = materials.len() - 1;
        if let Some(id) = ref_id {
            b.material_of.insert(id.to_string(), i);
        }
        i
    }

    fn shape(
        &mut self,
        n: Node<'a, 'i>,
        index: usize,
        b: &mut Builder<'a, 'i>,
        materials: &mut Vec<Material>,
    ) -> Result<MeshDesc> {
        let ty = self.required(n, "type")?;
        let name = self.attr(n, "id")?.unwrap_or_else(|| format!("{ty}_{index}"));
        let mut p = self.props(n)?;
        let mut normals = Vec::new();
        // An OBJ's texture-coordinate indices, for generated normals (None: not an OBJ).
        let mut obj_texcoords = None;
        let (positions, mut triangles, analytic) = match ty.as_str() {
            "obj" => {
                let (file, _) = self
                    .get_string(&mut p, "filename")?
                    .ok_or_else(|| self.err(n, "missing <string name=\"filename\" value=\"...\"/>"))?;
                let path = self.dir.join(&file);
                let mesh = read_obj(&path, Some((describe(n), self.loc(n))))?;
                if mesh.triangles.is_empty() {
                    self.warn(n, format!("{} has no faces", path.display()));
                }
                normals = mesh.normals;
                obj_texcoords = Some(mesh.texcoords);
                (mesh.positions, mesh.triangles, false)
            }
            "rectangle" => {
                let positions = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .map(|(x, y)| Vec3::new(x, y, 0.0))
                    .to_vec();
                (positions, vec![[0, 1, 2], [2, 3, 0]], true)
            }
            "cube" => {
                let (positions, triangles) = cube();
                (positions, triangles, true)
            }
            other => {
                return Err(self.attr_err(
                    n,
                    "type",
                    format!("unsupported shape type \"{other}\" (supported: obj, rectangle, cube)"),
                ));
            }
        };
        // Mitsuba's default (false) shades with the file's vertex normals when it has them, and
        // generates smooth ones (after `to_world`, below) when it has none.
        let face_normals = self.get_bool(&mut p, "face_normals")?.unwrap_or(false);
        if face_normals {
            normals.clear();
        }
        p.ignore(&["flip_tex_coords"]);
        let flip = self.get_bool(&mut p, "flip_normals")?.unwrap_or(false);
        let mut positions = positions;
        let mut mirrored = false;
        if let Some((t, tnode)) = self.get_transform(&mut p, "to_world")? {
            let m = t.matrix;
            mirrored = DMat3::from_mat4(m).determinant() < 0.0;
            if m != DMat4::IDENTITY {
                let mf = m.as_mat4();
                if m.row(3) == glam::DVec4::W {
                    positions.iter_mut().for_each(|q| *q = mf.transform_point3(*q));
                } else {
                    positions.iter_mut().for_each(|q| *q = mf.project_point3(*q));
                }
                if let Some(i) = positions.iter().position(|q| !q.is_finite()) {
                    return Err(
                        self.err(tnode, format!("to_world maps vertex {} to a non-finite point", i + 1))
                    );
                }
                // Normals transform by the inverse transpose (the core normalises them).
                let nm = glam::Mat3::from_mat4(mf).inverse().transpose();
                normals.iter_mut().for_each(|v| *v = nm * *v);
            }
        }
        if let Some(texcoords) = obj_texcoords.filter(|_| !face_normals && normals.is_empty()) {
            let smooth = generated_vertex_normals(positions, triangles, &texcoords);
            (positions, triangles, normals) = (smooth.positions, smooth.triangles, smooth.normals);
        }
        if flip ^ (analytic && mirrored) {
            triangles.iter_mut().for_each(|t| t.swap(1, 2));
        }
        if flip {
            normals.iter_mut().for_each(|v| *v = -*v);
        }

        let mut chosen = None;
        let mut interior = None;
        let mut emission: Option<AreaEmission> = None;
        for c in p.objects.clone() {
            match (c.tag_name().name(), c.attribute("name")) {
                ("ref" | "medium", Some("interior")) => {
                    if interior.is_some() {
                        return Err(self.err(c, "a shape can have only one interior medium"));
                    }
                    interior = Some(self.interior_medium(c, b)?);
                }
                ("ref" | "medium", Some("exterior")) => {
                    return Err(
                        self.err(c, "exterior media are not supported: the outside of every shape is vacuum")
                    );
                }
                ("medium", _) => {
                    return Err(self.err(c, "a <medium> inside a shape needs name=\"interior\""));
                }
                ("bsdf" | "ref", _) => {
                    if chosen.is_some() {
                        return Err(self.err(c, "a shape can have only one BSDF"));
                    }
                    let (parsed, ref_id) = if c.tag_name().name() == "ref" {
                        let parsed = self.bsdf_ref(c, b)?;
                        let id = parsed.name.clone();
                        (parsed, Some(id))
                    } else {
                        let mut parsed = self.bsdf(c, b)?;
                        if c.attribute("id").is_none() {
                            parsed.name = format!("{name}.bsdf");
                        }
                        (parsed, None)
                    };
                    chosen = Some((parsed, ref_id));
                }
                ("emitter", _) => {
                    if emission.is_some() {
                        return Err(self.err(c, "a shape can have only one emitter"));
                    }
                    emission = Some(self.area_emitter(c)?);
                }
                (other, _) => {
                    return Err(self.err(
                        c,
                        format!(
                            "unsupported element <{other}> inside <shape> (supported: bsdf, ref, emitter, medium)"
                        ),
                    ));
                }
            }
        }
        let material = match (chosen, interior) {
            (Some((parsed, ref_id)), None) => self.material_index(&parsed, ref_id.as_deref(), b, materials),
            (Some((parsed, ref_id)), Some(medium)) => {
                let bsdf = match parsed.bsdf {
                    Bsdf::SmoothDielectric(d) => {
                        d.with_absorption(medium.sigma_a).map(Bsdf::SmoothDielectric)
                    }
                    Bsdf::RoughDielectric(d) => d.with_absorption(medium.sigma_a).map(Bsdf::RoughDielectric),
                    _ => {
                        return Err(self.err(
                            medium.node,
                            format!(
                                "an interior medium needs a dielectric BSDF on the shape (BSDF \"{}\" is not one): \
                                 Opticks models absorbing glass only",
                                parsed.name
                            ),
                        ));
                    }
                };
                let bsdf = bsdf.map_err(|source| SceneFileError::Material {
                    at: self.loc(medium.node),
                    element: describe(medium.node),
                    source,
                })?;
                let name = format!("{}+{}", parsed.name, medium.name);
                let key = ref_id.zip(medium.id).map(|(r, m)| format!("{r}\u{0}{m}"));
                let parsed = ParsedBsdf { name, bsdf, two_sided: parsed.two_sided };
                self.material_index(&parsed, key.as_deref(), b, materials)
            }
            (None, Some(medium)) => {
                return Err(self.err(
                    medium.node,
                    "an interior medium needs a dielectric BSDF on the shape (this shape has none)",
                ));
            }
            (None, None) => {
                // Mitsuba's default: a one-sided diffuse of reflectance 0.5 (shared by all shapes).
                const DEFAULT: &str = "\u{0}default";
                let parsed = ParsedBsdf {
                    name: "default".into(),
                    bsdf: Bsdf::Lambert(Lambert::new(Rgb::splat(0.5)).expect("valid albedo")),
                    two_sided: false,
                };
                self.material_index(&parsed, Some(DEFAULT), b, materials)
            }
        };
        self.finish(&p);
        Ok(MeshDesc {
            name,
            source: self.source(n),
            positions,
            triangles,
            normals,
            material,
            emission: emission.as_ref().map(|e| e.radiance),
            emission_tangent: emission.as_ref().and_then(|e| e.tangent),
            emission_power: emission.as_ref().and_then(|e| e.power),
            emission_profile: emission.and_then(|e| e.profile),
        })
    }

    /// A shape's `<ref name="interior" id="…"/>` or inline `<medium name="interior">`.
    fn interior_medium(&mut self, n: Node<'a, 'i>, b: &mut Builder<'a, 'i>) -> Result<Interior<'a, 'i>> {
        if n.tag_name().name() == "medium" {
            return Ok(Interior {
                sigma_a: self.absorbing_medium(n)?,
                node: n,
                id: None,
                name: "medium".into(),
            });
        }
        let id = self.required(n, "id")?;
        let target = match b.ids.get(&id) {
            Some(&t) if t.tag_name().name() == "medium" => t,
            Some(&t) => {
                let at = self.loc(t);
                return Err(self.err(
                    n,
                    format!("id \"{id}\" is a <{}> (at {at}), not a <medium>", t.tag_name().name()),
                ));
            }
            None => return Err(self.attr_err(n, "id", format!("reference to unknown medium id \"{id}\""))),
        };
        b.used.insert(id.clone());
        Ok(Interior { sigma_a: self.absorbing_medium(target)?, node: target, id: Some(id.clone()), name: id })
    }

    /// σ_a of a purely absorbing `<medium type="homogeneous">` (module docs).
    fn absorbing_medium(&mut self, n: Node<'a, 'i>) -> Result<Rgb> {
        let ty = self.required(n, "type")?;
        if ty != "homogeneous" {
            return Err(self.attr_err(
                n,
                "type",
                format!("unsupported medium type \"{ty}\" (supported: homogeneous, with albedo 0)"),
            ));
        }
        let mut p = self.props(n)?;
        if let Some(c) = p.objects.iter().find(|c| c.tag_name().name() != "phase") {
            return Err(self.err(*c, "unsupported element inside a medium (supported: phase)"));
        }
        let albedo = self.get_color(&mut p, "albedo")?;
        match albedo {
            Some((a, _)) if a == Rgb::ZERO => {}
            Some((a, anode)) => {
                return Err(self.err(
                    anode,
                    format!(
                        "a scattering medium (albedo {a}) is not supported: Opticks renders purely \
                         absorbing interiors only (albedo 0)"
                    ),
                ));
            }
            None => {
                return Err(self.err(
                    n,
                    "a homogeneous medium scatters by default (Mitsuba's albedo is 0.75); Opticks renders \
                     purely absorbing interiors only: give <float name=\"albedo\" value=\"0\"/>",
                ));
            }
        }
        let (sigma_t, tnode) = self.get_color(&mut p, "sigma_t")?.unwrap_or((Rgb::ONE, n));
        let (scale, snode) = self.get_float(&mut p, "scale")?.unwrap_or((1.0, n));
        p.ignore(&["sample_emitters"]);
        self.finish(&p);
        let sigma_a = sigma_t * scale as f32;
        if !sigma_a.is_finite() || sigma_a.min_element() < 0.0 {
            let at = if scale < 0.0 || !scale.is_finite() { snode } else { tnode };
            return Err(self.err(at, format!("sigma_t · scale = {sigma_a} must be finite and not negative")));
        }
        Ok(sigma_a)
    }

    fn area_emitter(&mut self, n: Node<'a, 'i>) -> Result<AreaEmission> {
        let ty = self.required(n, "type")?;
        if ty != "area" {
            return Err(self.attr_err(
                n,
                "type",
                format!("unsupported emitter type \"{ty}\" inside a shape (supported: area)"),
            ));
        }
        let mut p = self.props(n)?;
        if let Some(c) = p.objects.first() {
            return Err(
                self.err(*c, "unsupported element inside an area emitter (textures are not supported)")
            );
        }
        let (radiance, node) = self.get_color(&mut p, "radiance")?.unwrap_or((Rgb::ONE, n));
        if radiance.min_element() < 0.0 {
            return Err(self.err(node, "radiance must not be negative"));
        }
        // Opticks extensions: a cosⁿ (focused) emitter, `radiance` being the radiance along the
        // normal; or an IES file, `radiance` being a colour scale; the horizontal 0° tangent; the
        // power in watts or lumens.
        let exponent = self.get_float(&mut p, "exponent")?;
        let ies = self.ies_file(&mut p, true)?;
        let (profile, colour, default_power) = match (exponent, ies) {
            (Some(_), Some((_, _, fnode))) => {
                return Err(self.err(fnode, "give either `exponent` or `filename`, not both"));
            }
            (Some((e, enode)), None) => {
                if !(0.0..=1e6).contains(&e) {
                    return Err(self.err(enode, format!("exponent {e} must be in [0, 10⁶]")));
                }
                (Some(EmissionProfile::CosinePower { exponent: e as f32 }), radiance, None)
            }
            (None, Some((ies, scale, _))) => {
                let colour = radiance * scale;
                (Some(EmissionProfile::Ies(ies.profile)), colour, Some(colour * ies.watts))
            }
            (None, None) => (None, radiance, None),
        };
        let tangent = match self.get_point(&mut p, "tangent")? {
            Some((t, tnode)) => {
                if t.as_vec3().length() == 0.0 {
                    return Err(self.err(tnode, "the tangent must not be zero"));
                }
                Some(t.as_vec3())
            }
            None => None,
        };
        let power = self.power_or_lumens(&mut p, colour, "radiance")?.or(default_power);
        self.finish(&p);
        Ok(AreaEmission { radiance: colour, profile, tangent, power })
    }

    /// An IES emitter's `filename` (relative to the XML file's folder) and `scale`, if a
    /// `filename` is given: the file, checked (as an area light's profile, cut at 90°, if
    /// `hemisphere`), with the flux its candela distribution carries (in W: lumens/683), the scale
    /// and the `filename` element. Warns when the file's rated lumens differ from that flux.
    fn ies_file(
        &mut self,
        p: &mut Props<'a, 'i>,
        hemisphere: bool,
    ) -> Result<Option<(Ies, f32, Node<'a, 'i>)>> {
        let Some((file, fnode)) = self.get_string(p, "filename")? else { return Ok(None) };
        let path = self.dir.join(&file);
        let ies = lights::ies_luminaire(&path, hemisphere).map_err(|e| self.err(fnode, e))?;
        if let Some(w) = ies.warning {
            self.warn(fnode, w);
        }
        let scale = match self.get_float(p, "scale")? {
            Some((scale, snode)) if scale < 0.0 => return Err(self.err(snode, "scale must not be negative")),
            Some((scale, _)) => scale as f32,
            None => 1.0,
        };
        let path = path.canonicalize().unwrap_or(path); // absolute, for writers
        Ok(Some((Ies { profile: ies.profile, watts: ies.watts, path }, scale, fnode)))
    }

    /// An emitter's `power` (W per channel) or `lumens` (converted keeping the colour `colour`,
    /// the value of the parameter `colour_name`), at most one of them; `None` if neither.
    fn power_or_lumens(&self, p: &mut Props<'a, 'i>, colour: Rgb, colour_name: &str) -> Result<Option<Rgb>> {
        let power = self.get_color(p, "power")?;
        let lumens = self.get_float(p, "lumens")?;
        match (power, lumens) {
            (Some(_), Some((_, lnode))) => Err(self.err(lnode, "give either `power` or `lumens`, not both")),
            (Some((w, pnode)), None) => {
                if w.min_element() < 0.0 {
                    return Err(self.err(pnode, "power must not be negative"));
                }
                Ok(Some(w))
            }
            (None, Some((lm, lnode))) => {
                if lm < 0.0 {
                    return Err(self.err(lnode, "lumens must not be negative"));
                }
                lumens_to_watts(lm as f32, colour).map(Some).ok_or_else(|| {
                    self.err(
                        lnode,
                        format!("`lumens` needs the `{colour_name}` colour to have non-zero luminance"),
                    )
                })
            }
            (None, None) => Ok(None),
        }
    }

    /// The frame of an emitter's `to_world`: z = M·(0,0,1) (the axis), x = M·(1,0,0) made
    /// perpendicular; and the position M·(0,0,0).
    fn emitter_frame(&self, t: &Transform, tnode: Node) -> Result<(Frame, DVec3)> {
        let m = t.matrix;
        let frame = lights::axis_frame(m.transform_vector3(DVec3::Z), m.transform_vector3(DVec3::X))
            .map_err(|_| self.err(tnode, "to_world maps the emitter's axis (0, 0, 1) to zero"))?;
        Ok((frame, m.transform_point3(DVec3::ZERO)))
    }

    fn top_emitter(&mut self, n: Node<'a, 'i>, index: usize) -> Result<TopEmitter> {
        let ty = self.required(n, "type")?;
        match ty.as_str() {
            "point" => self.point_emitter(n, index).map(TopEmitter::Point),
            "spot" | "ies" => self.profiled_emitter(n, index, &ty).map(TopEmitter::Point),
            "directional" => self.directional_emitter(n, index).map(TopEmitter::Directional),
            _ => self.point_emitter(n, index).map(TopEmitter::Point), // reports the error
        }
    }

    fn profiled_emitter(&mut self, n: Node<'a, 'i>, index: usize, ty: &str) -> Result<PointLightDesc> {
        let name = self.attr(n, "id")?.unwrap_or_else(|| format!("{ty}_{index}"));
        let mut p = self.props(n)?;
        if let Some(c) = p.objects.first() {
            return Err(self.err(*c, format!("unsupported element inside a {ty} emitter")));
        }
        let (frame, position) = match self.get_transform(&mut p, "to_world")? {
            Some((t, tnode)) => self.emitter_frame(&t, tnode)?,
            None => (Frame { s: Vec3::X, t: Vec3::Y, n: Vec3::Z }, DVec3::ZERO),
        };
        let (intensity, inode) = self.get_color(&mut p, "intensity")?.unwrap_or((Rgb::ONE, n));
        if intensity.min_element() < 0.0 {
            return Err(self.err(inode, "intensity must not be negative"));
        }
        let mut light = PointLightDesc {
            name,
            source: self.source(n),
            position: position.as_vec3(),
            intensity,
            orientation: Some(frame),
            ..Default::default()
        };
        if ty == "spot" {
            let (cutoff, cnode) = self.get_float(&mut p, "cutoff_angle")?.unwrap_or((20.0, n));
            let (beam, bnode) = self.get_float(&mut p, "beam_width")?.unwrap_or((cutoff * 0.75, n));
            light.profile =
                Some(lights::spot_profile(cutoff.to_radians(), beam.to_radians()).map_err(|e| {
                    if e == lights::LightError::Cutoff {
                        self.err(cnode, format!("cutoff_angle {cutoff}° must be in (0°, 180°]"))
                    } else {
                        self.err(
                            bnode,
                            format!("beam_width {beam}° must be in (0°, cutoff_angle = {cutoff}°]"),
                        )
                    }
                })?);
        } else {
            let (ies, scale, _) = self
                .ies_file(&mut p, false)?
                .ok_or_else(|| self.err(n, "an ies emitter needs a `filename`"))?;
            light.intensity *= scale;
            light.power = self.power_or_lumens(&mut p, light.intensity, "intensity")?;
            light.profile = Some(EmissionProfile::Ies(ies.profile));
            light.ies_file = Some(ies.path);
        }
        self.finish(&p);
        Ok(light)
    }

    fn directional_emitter(&mut self, n: Node<'a, 'i>, index: usize) -> Result<DirectionalLightDesc> {
        let name = self.attr(n, "id")?.unwrap_or_else(|| format!("directional_{index}"));
        let mut p = self.props(n)?;
        if let Some(c) = p.objects.first() {
            return Err(self.err(*c, "unsupported element inside a directional emitter"));
        }
        let direction = self.get_point(&mut p, "direction")?;
        let to_world = self.get_transform(&mut p, "to_world")?;
        let direction = match (direction, to_world) {
            (Some(_), Some((_, tnode))) => {
                return Err(self.err(tnode, "give either `direction` or `to_world`, not both"));
            }
            (Some((d, dnode)), None) => {
                if d.length() <= 0.0 {
                    return Err(self.err(dnode, "direction must not be zero"));
                }
                d
            }
            (None, Some((t, tnode))) => self.emitter_frame(&t, tnode)?.0.n.as_dvec3(),
            (None, None) => DVec3::Z,
        };
        let (irradiance, inode) = self.get_color(&mut p, "irradiance")?.unwrap_or((Rgb::ONE, n));
        self.finish(&p);
        lights::directional_light(name, self.source(n), direction, irradiance)
            .map_err(|_| self.err(inode, "irradiance must not be negative"))
    }

    fn point_emitter(&mut self, n: Node<'a, 'i>, index: usize) -> Result<PointLightDesc> {
        let ty = self.required(n, "type")?;
        match ty.as_str() {
            "point" => {}
            "area" => return Err(self.err(n, "an area emitter must be nested inside a <shape>")),
            other => {
                return Err(self.attr_err(
                    n,
                    "type",
                    format!(
                        "unsupported emitter type \"{other}\" (supported: point, spot, directional, ies at the top level, area inside a shape)"
                    ),
                ));
            }
        }
        let name = self.attr(n, "id")?.unwrap_or_else(|| format!("point_{index}"));
        let mut p = self.props(n)?;
        if let Some(c) = p.objects.first() {
            return Err(self.err(*c, "unsupported element inside a point emitter"));
        }
        let position = self.get_point(&mut p, "position")?;
        let to_world = self.get_transform(&mut p, "to_world")?;
        let position = match (position, to_world) {
            (Some(_), Some((_, tnode))) => {
                return Err(self.err(tnode, "give either `position` or `to_world`, not both"));
            }
            (Some((pos, _)), None) => pos,
            (None, Some((t, _))) => t.matrix.transform_point3(DVec3::ZERO),
            (None, None) => DVec3::ZERO,
        };
        let (intensity, inode) = self.get_color(&mut p, "intensity")?.unwrap_or((Rgb::ONE, n));
        if intensity.min_element() < 0.0 {
            return Err(self.err(inode, "intensity must not be negative"));
        }
        self.finish(&p);
        Ok(PointLightDesc {
            name,
            source: self.source(n),
            position: position.as_vec3(),
            intensity,
            ..Default::default()
        })
    }
}

/// A top-level emitter.
enum TopEmitter {
    Point(PointLightDesc),
    Directional(DirectionalLightDesc),
}

/// A composed `<transform>`: the matrix and the distance to the last `<lookat>`'s target.
#[derive(Clone, Copy, Debug)]
struct Transform {
    matrix: DMat4,
    focus: Option<f64>,
}

/// Mitsuba's `coordinate_system` (Duff et al. 2017): two unit vectors completing `n` to an
/// orthonormal basis; `<lookat>` without `up` uses the second.
fn coordinate_system(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), DVec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// The horizontal full angle (degrees) for a full angle `fov` along `axis`, as Mitsuba's
/// `parse_fov` computes it. `None` for an unknown axis.
pub fn fov_to_x(fov: f64, axis: &str, width: u32, height: u32) -> Option<f64> {
    let aspect = width as f64 / height as f64;
    let axis = match axis {
        "smaller" => {
            if aspect > 1.0 {
                "y"
            } else {
                "x"
            }
        }
        "larger" => {
            if aspect > 1.0 {
                "x"
            } else {
                "y"
            }
        }
        a => a,
    };
    let half = (0.5 * fov).to_radians();
    match axis {
        "x" => Some(fov),
        "y" => Some(2.0 * (half.tan() * aspect).atan().to_degrees()),
        "diagonal" => {
            let diagonal = 2.0 * half.tan();
            let w = diagonal / (1.0 + 1.0 / (aspect * aspect)).sqrt();
            Some(2.0 * (0.5 * w).atan().to_degrees())
        }
        _ => None,
    }
}

/// Mitsuba's cube: [-1, 1]³, four vertices per face, outward normals, counter-clockwise.
fn cube() -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut positions = Vec::with_capacity(24);
    let mut triangles = Vec::with_capacity(12);
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            // Face at coordinate `axis` = sign; (u, v) span it with u × v = sign · e_axis.
            let n = Vec3::from_array(std::array::from_fn(|k| if k == axis { sign } else { 0.0 }));
            let u = Vec3::from_array(std::array::from_fn(|k| if k == (axis + 1) % 3 { 1.0 } else { 0.0 }));
            let v = n.cross(u);
            let base = positions.len() as u32;
            for (a, c) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                positions.push(n + a * u + c * v);
            }
            triangles.push([base, base + 1, base + 2]);
            triangles.push([base, base + 2, base + 3]);
        }
    }
    (positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load_str(xml: &str) -> Result<LoadedScene> {
        parse(xml, Path::new("dir/test.xml"), &LoadOptions::default())
    }

    fn scene(body: &str) -> LoadedScene {
        let xml = format!("<scene version=\"3.0.0\">\n{body}\n</scene>");
        load_str(&xml).unwrap_or_else(|e| panic!("{e}\n{xml}"))
    }

    fn err(body: &str) -> String {
        let xml = format!("<scene version=\"3.0.0\">\n{body}\n</scene>");
        match load_str(&xml) {
            Ok(_) => panic!("should fail:\n{xml}"),
            Err(e) => e.to_string(),
        }
    }

    /// World positions of a `rectangle` under `transform` (the inner XML of `<transform>`).
    fn rect(transform: &str) -> Vec<Vec3> {
        let s = scene(&format!(
            "<shape type=\"rectangle\"><transform name=\"to_world\">{transform}</transform></shape>"
        ));
        s.description.meshes[0].positions.clone()
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    #[track_caller]
    fn assert_close(a: Vec3, b: Vec3) {
        assert!(close(a, b), "{a} != {b}");
    }

    fn normal(m: &MeshDesc, t: usize) -> Vec3 {
        let [a, b, c] = m.triangles[t].map(|i| m.positions[i as usize]);
        (b - a).cross(c - a).normalize()
    }

    #[test]
    fn transforms_compose_in_mitsuba_order() {
        // Vertex 0 of the rectangle is (-1, -1, 0).
        let v0 = |t: &str| rect(t)[0];
        assert_close(v0(r#"<translate x="1" y="2" z="3"/><scale value="2"/>"#), Vec3::new(0.0, 2.0, 6.0));
        assert_close(v0(r#"<scale value="2"/><translate value="1, 2, 3"/>"#), Vec3::new(-1.0, 0.0, 3.0));
        assert_close(v0(r#"<scale x="3"/>"#), Vec3::new(-3.0, -1.0, 0.0));
        assert_close(v0(r#"<scale value="1 2 3"/>"#), Vec3::new(-1.0, -2.0, 0.0));
        // +90° about y maps (x, y, z) to (z, y, −x).
        assert_close(v0(r#"<rotate y="1" angle="90"/>"#), Vec3::new(0.0, -1.0, 1.0));
        assert_close(
            v0(r#"<rotate value="0, 2, 0" angle="90"/><translate x="5"/>"#),
            Vec3::new(5.0, -1.0, 1.0),
        );
        assert_close(v0(r#"<translate x="5"/><rotate y="1" angle="90"/>"#), Vec3::new(0.0, -1.0, -4.0));
        assert_close(
            v0(r#"<matrix value="1 0 0 10  0 1 0 20  0 0 1 30  0 0 0 1"/>"#),
            Vec3::new(9.0, 19.0, 30.0),
        );
        assert_close(v0(r#"<matrix value="0,-1,0, 1,0,0, 0,0,1"/>"#), Vec3::new(1.0, -1.0, 0.0));
        // lookat looking down +z from (1, 2, 3): left = up × dir = +x, so a pure translation.
        assert_close(
            v0(r#"<lookat origin="1, 2, 3" target="1, 2, 4" up="0, 1, 0"/>"#),
            Vec3::new(0.0, 1.0, 3.0),
        );
        // Looking down −z: local +x (image left) is world −x, local +z is world −z.
        let p = rect(r#"<lookat origin="0, 0, 0" target="0, 0, -1" up="0, 1, 0"/>"#);
        assert_close(p[2], Vec3::new(-1.0, 1.0, 0.0));
        // Without `up`, any perpendicular frame: still a rigid motion.
        let p = rect(r#"<lookat origin="0, 0, 0" target="3, 0, 0"/>"#);
        assert!(((p[0] - p[2]).length() - 8f32.sqrt()).abs() < 1e-5 && p.iter().all(|q| q.x.abs() < 1e-6));
    }

    #[test]
    fn canonical_shapes_face_the_right_way() {
        let s = scene(
            r#"<shape type="rectangle"/>
               <shape type="rectangle"><boolean name="flip_normals" value="true"/></shape>
               <shape type="rectangle"><transform name="to_world"><scale x="-1"/></transform></shape>
               <shape type="cube" id="box"><transform name="to_world"><translate x="10"/></transform></shape>"#,
        );
        let m = &s.description.meshes;
        assert_eq!(m[0].name, "rectangle_0");
        assert_eq!(m[3].name, "box");
        assert_close(normal(&m[0], 0), Vec3::Z);
        assert_close(normal(&m[0], 1), Vec3::Z);
        assert_close(normal(&m[1], 0), -Vec3::Z);
        assert_close(normal(&m[2], 0), Vec3::Z); // mirrored, normal kept as Mitsuba transforms it
        assert_eq!(m[3].triangles.len(), 12);
        let centre = Vec3::new(10.0, 0.0, 0.0);
        for t in 0..12 {
            let [a, b, c] = m[3].triangles[t].map(|i| m[3].positions[i as usize]);
            let mid = (a + b + c) / 3.0 - centre;
            assert!(normal(&m[3], t).dot(mid) > 0.5, "cube triangle {t} faces inward");
            assert!(m[3].positions.iter().all(|p| (*p - centre).abs().max_element() == 1.0));
        }
    }

    #[test]
    fn fov_axis_conversions() {
        let tan = |deg: f64| (deg.to_radians() / 2.0).tan();
        let atan2x = |t: f64| 2.0 * t.atan().to_degrees();
        // 200×100: aspect 2.
        assert_eq!(fov_to_x(60.0, "x", 200, 100), Some(60.0));
        let y = fov_to_x(60.0, "y", 200, 100).unwrap();
        assert!((y - atan2x(2.0 * tan(60.0))).abs() < 1e-9 && (y - 98.2132).abs() < 1e-3);
        assert_eq!(fov_to_x(60.0, "smaller", 200, 100), Some(y));
        assert_eq!(fov_to_x(60.0, "larger", 200, 100), Some(60.0));
        // Portrait: the smaller side is x.
        assert_eq!(fov_to_x(60.0, "smaller", 100, 200), Some(60.0));
        assert!((fov_to_x(60.0, "larger", 100, 200).unwrap() - atan2x(0.5 * tan(60.0))).abs() < 1e-9);
        // Diagonal 90°: half-diagonal tangent 1 = hypot(tx, tx/2).
        let d = fov_to_x(90.0, "diagonal", 200, 100).unwrap();
        assert!((d - atan2x(1.0 / 1.25f64.sqrt())).abs() < 1e-9, "{d}");
        assert_eq!(fov_to_x(60.0, "z", 1, 1), None);

        let cam = |axis: &str| {
            scene(&format!(
                r#"<sensor type="perspective"><float name="fov" value="60"/><string name="fov_axis" value="{axis}"/>
                   <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/>
                   <rfilter type="box"/></film></sensor>"#
            ))
            .description
            .camera
            .unwrap()
        };
        assert!((cam("Y").fov_x_degrees as f64 - y).abs() < 1e-4);
        assert_eq!(cam("x").fov_x_degrees, 60.0);
        assert_eq!((cam("x").width, cam("x").height), (200, 100));
    }

    #[test]
    fn sensor_frames_match_mitsuba() {
        let cam = |t: &str| {
            scene(&format!(
                r#"<sensor type="perspective"><float name="fov" value="45"/>
                   <transform name="to_world">{t}</transform></sensor>"#
            ))
            .description
            .camera
            .unwrap()
        };
        let c = cam(r#"<lookat origin="1, 2, 3" target="4, 6, 3" up="0, 0, 1"/>"#);
        assert_close(c.eye, Vec3::new(1.0, 2.0, 3.0));
        assert_close(c.target, Vec3::new(4.0, 6.0, 3.0));
        assert_close(c.up, Vec3::Z);
        assert_eq!((c.width, c.height), (768, 576)); // Mitsuba's default film
        // lookat then a world translation: everything moves.
        let c = cam(r#"<lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/><translate y="1"/>"#);
        assert_close(c.eye, Vec3::new(0.0, 1.0, 5.0));
        assert_close(c.target, Vec3::new(0.0, 1.0, 0.0));
        // Rotating the default camera (looking down +z) by 180° about y = lookat down −z.
        let c = cam(r#"<rotate y="1" angle="180"/><translate z="5"/>"#);
        assert_close(c.eye, Vec3::new(0.0, 0.0, 5.0));
        assert_close((c.target - c.eye).normalize(), -Vec3::Z);
        assert_close(c.up, Vec3::Y);
        // Image right = forward × up = +x, as Mitsuba's image right (−local x) is.
        assert_close((c.target - c.eye).cross(c.up).normalize(), Vec3::X);

        let e = err(r#"<sensor type="perspective"><float name="fov" value="45"/>
               <transform name="to_world"><scale x="-1"/></transform></sensor>"#);
        assert!(e.starts_with("dir/test.xml:3:16: <transform name=\"to_world\">:"), "{e}");
        assert!(e.contains("mirror"), "{e}");
        let s = scene(
            r#"<sensor type="perspective"><float name="fov" value="45"/>
               <transform name="to_world"><scale value="2"/></transform></sensor>"#,
        );
        assert!(s.warnings.iter().any(|w| w.contains("scale or shear")), "{:?}", s.warnings);
    }

    #[test]
    fn focal_length_default_is_50mm_diagonal() {
        let c =
            scene(r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="box"/></film></sensor>"#)
                .description
                .camera
                .unwrap();
        let diag = 2.0 * (43.2666f64 / 100.0).atan().to_degrees();
        let expect = fov_to_x(diag, "diagonal", 768, 576).unwrap();
        assert!((c.fov_x_degrees as f64 - expect).abs() < 1e-3, "{}", c.fov_x_degrees);
        // 4:3 film: the horizontal extent is 4/5 of the 43.27 mm diagonal of a 36×24 mm frame.
        assert!((c.fov_x_degrees as f64 - 2.0 * (0.8 * 43.2666f64 / 100.0).atan().to_degrees()).abs() < 1e-3);
    }

    #[test]
    fn parameters_are_substituted() {
        let xml = r#"<scene version="3.0.0">
            <default name="spp" value="64"/>
            <default name="w" value="32"/>
            <sensor type="perspective"><float name="fov" value="$w.5"/>
              <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
              <film type="hdrfilm"><integer name="width" value="$w"/><integer name="height" value="$w"/>
              <rfilter type="box"/></film></sensor>
        </scene>"#;
        let c = load_str(xml).unwrap().description.camera.unwrap();
        assert_eq!((c.width, c.height, c.fov_x_degrees), (32, 32, 32.5));
        let opts = LoadOptions { defines: vec![("w".into(), "16".into())] };
        let c = parse(xml, Path::new("x.xml"), &opts).unwrap().description.camera.unwrap();
        assert_eq!((c.width, c.fov_x_degrees), (16, 16.5));
        let e = err(r#"<shape type="rectangle" id="$name"/>"#);
        assert!(
            e.starts_with(
                "dir/test.xml:2:29: <shape type=\"rectangle\" id=\"$name\">: undefined parameter $name"
            ),
            "{e}"
        );
    }

    #[test]
    fn materials_follow_mitsuba_sidedness_and_references() {
        let s = scene(
            r#"<shape type="rectangle" id="a"><ref id="late"/></shape>
               <shape type="rectangle" id="b"><ref name="bsdf" id="late"/></shape>
               <shape type="rectangle" id="c"><bsdf type="diffuse"><float name="reflectance" value="0.25"/></bsdf></shape>
               <shape type="rectangle" id="d"/>
               <shape type="rectangle" id="e"/>
               <bsdf type="diffuse" id="base"><spectrum name="reflectance" value="0.75"/></bsdf>
               <bsdf type="twosided" id="late"><ref id="base"/></bsdf>
               <bsdf type="twosided" id="unused"><bsdf type="diffuse"/></bsdf>"#,
        );
        let d = &s.description;
        let mat = |mesh: usize| &d.materials[d.meshes[mesh].material];
        let rho = |mesh: usize| match &mat(mesh).bsdf {
            Bsdf::Lambert(l) => l.reflectance,
            other => panic!("{other:?}"),
        };
        assert_eq!(d.meshes[0].material, d.meshes[1].material);
        assert_eq!((mat(0).name.as_str(), mat(0).two_sided, rho(0)), ("late", true, Rgb::splat(0.75)));
        assert_eq!((mat(2).name.as_str(), mat(2).two_sided, rho(2)), ("c.bsdf", false, Rgb::splat(0.25)));
        assert_eq!((mat(3).name.as_str(), mat(3).two_sided, rho(3)), ("default", false, Rgb::splat(0.5)));
        assert_eq!(d.meshes[3].material, d.meshes[4].material);
        assert_eq!(d.materials.len(), 3);
        assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
        assert!(s.warnings[0].contains("id=\"unused\">: this BSDF is never used"), "{:?}", s.warnings);
    }

    #[test]
    fn phong_bsdf_is_read_with_mitsuba_06_parameters() {
        let s = scene(
            r#"<shape type="rectangle" id="a">
                 <bsdf type="phong">
                   <rgb name="diffuseReflectance" value="0.3, 0.2, 0.1"/>
                   <spectrum name="specularReflectance" value="0.6"/>
                   <float name="exponent" value="250"/>
                 </bsdf>
               </shape>
               <shape type="rectangle" id="b"><ref id="shiny"/></shape>
               <shape type="rectangle" id="c"><bsdf type="phong"/></shape>
               <bsdf type="twosided" id="shiny">
                 <bsdf type="phong"><float name="diffuseReflectance" value="0"/><integer name="exponent" value="1000"/></bsdf>
               </bsdf>"#,
        );
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
        let d = &s.description;
        let phong = |mesh: usize| {
            let m = &d.materials[d.meshes[mesh].material];
            match &m.bsdf {
                Bsdf::ModifiedPhong(p) => (m.name.clone(), m.two_sided, p.kd, p.ks, p.exponent),
                other => panic!("{other:?}"),
            }
        };
        assert_eq!(phong(0), ("a.bsdf".into(), false, Rgb::new(0.3, 0.2, 0.1), Rgb::splat(0.6), 250.0));
        assert_eq!(phong(1), ("shiny".into(), true, Rgb::ZERO, Rgb::splat(0.2), 1000.0));
        // Mitsuba 0.6's defaults: kd 0.5, ks 0.2, exponent 30; one-sided.
        assert_eq!(phong(2), ("c.bsdf".into(), false, Rgb::splat(0.5), Rgb::splat(0.2), 30.0));
        let sum = d.materials[0].bsdf.max_albedo();
        assert!((sum - Rgb::new(0.9, 0.8, 0.7)).abs().max_element() < 1e-6, "{sum}");
        // kd + ks = 1 exactly is allowed (the decimal pair rounds to at most 1 in f32).
        scene(
            r#"<shape type="rectangle"><bsdf type="phong"><float name="diffuseReflectance" value="0.35"/>
               <float name="specularReflectance" value="0.65"/></bsdf></shape>"#,
        );
    }

    #[test]
    fn impossible_phong_parameters_are_located() {
        let at = |body: &str| err(&format!("<bsdf type=\"phong\" id=\"p\">\n  {body}\n</bsdf>"));
        // kd + ks > 1 involves both parameters: reported at the <bsdf>.
        let e = at(
            r#"<rgb name="diffuseReflectance" value="0.5, 0.7, 0.5"/><float name="specularReflectance" value="0.4"/>"#,
        );
        assert!(
            e.starts_with("dir/test.xml:2:1: <bsdf type=\"phong\" id=\"p\">: invalid material: kd + ks = "),
            "{e}"
        );
        assert!(e.contains("create energy"), "{e}");
        // With the default ks = 0.2, kd = 0.9 is already too much.
        let e = at(r#"<float name="diffuseReflectance" value="0.9"/>"#);
        assert!(e.starts_with("dir/test.xml:2:1: <bsdf type=\"phong\" id=\"p\">: invalid material:"), "{e}");
        let e = at(r#"<float name="exponent" value="NaN"/>"#);
        assert_eq!(
            e,
            "dir/test.xml:3:33: <float name=\"exponent\">: attribute `value`: \"NaN\" is not a finite number"
        );
        let e = at(r#"<float name="exponent" value="2e6"/>"#);
        assert!(
            e.starts_with(
                "dir/test.xml:3:3: <float name=\"exponent\">: invalid material: exponent = 2000000 exceeds"
            ),
            "{e}"
        );
        let e = at(r#"<float name="exponent" value="-1"/>"#);
        assert!(
            e.starts_with(
                "dir/test.xml:3:3: <float name=\"exponent\">: invalid material: exponent must not be negative"
            ),
            "{e}"
        );
        let e = at(r#"<rgb name="specularReflectance" value="0.1, -0.1, 0.1"/>"#);
        assert!(e.starts_with("dir/test.xml:3:3: <rgb name=\"specularReflectance\">: invalid material: ks must not be negative"), "{e}");
        let e = at(r#"<rgb name="diffuseReflectance" value="-0.1"/>"#);
        assert!(e.starts_with("dir/test.xml:3:3: <rgb name=\"diffuseReflectance\">: invalid material: kd must not be negative"), "{e}");
        let e = at(r#"<texture type="bitmap" name="diffuseReflectance"/>"#);
        assert!(e.contains("textures are not supported"), "{e}");
        let e = at(r#"<string name="exponent" value="30"/>"#);
        assert!(e.contains("wrong property type"), "{e}");
        // Mitsuba 3 spellings are not Mitsuba 0.6's: a warning, not silently right.
        let s = scene(
            r#"<bsdf type="phong" id="p"><float name="diffuse_reflectance" value="0.1"/></bsdf>
                         <shape type="rectangle"><ref id="p"/></shape>"#,
        );
        assert!(
            s.warnings.iter().any(|w| w.contains("`diffuse_reflectance` is not supported")),
            "{:?}",
            s.warnings
        );
    }

    #[test]
    fn conductor_and_dielectric_bsdfs_follow_mitsuba_3() {
        let s = scene(
            r#"<shape type="rectangle"><bsdf type="conductor"/></shape>
               <shape type="rectangle"><bsdf type="twosided"><bsdf type="conductor">
                 <rgb name="specular_reflectance" value="0.9, 0.8, 0.7"/>
                 <rgb name="eta" value="0.2, 0.4, 1.4"/><rgb name="k" value="4, 2.4, 1.6"/></bsdf></bsdf></shape>
               <shape type="rectangle"><bsdf type="dielectric"/></shape>
               <shape type="rectangle"><bsdf type="dielectric">
                 <string name="int_ior" value="water"/><float name="ext_ior" value="1"/>
                 <float name="specular_reflectance" value="0.5"/></bsdf></shape>
               <shape type="rectangle"><bsdf type="roughconductor">
                 <string name="distribution" value="ggx"/><float name="alpha" value="0.3"/></bsdf></shape>
               <shape type="rectangle"><bsdf type="roughdielectric">
                 <string name="distribution" value="ggx"/><float name="alpha_u" value="0.2"/>
                 <float name="alpha_v" value="0.2"/><boolean name="sample_visible" value="true"/></bsdf></shape>
               <shape type="rectangle"><bsdf type="roughconductor"/></shape>
               <shape type="rectangle"><bsdf type="roughdielectric">
                 <string name="distribution" value="GGX"/><float name="alpha_u" value="0.05"/>
                 <float name="alpha_v" value="0.4"/></bsdf></shape>"#,
        );
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
        let d = &s.description;
        let m = |i: usize| &d.materials[d.meshes[i].material];
        assert_eq!(m(0).bsdf, Bsdf::SmoothConductor(SmoothConductor::new(Rgb::ONE, None).unwrap()));
        assert!(!m(0).two_sided && m(1).two_sided);
        let gold = (Rgb::new(0.2, 0.4, 1.4), Rgb::new(4.0, 2.4, 1.6));
        assert_eq!(
            m(1).bsdf,
            Bsdf::SmoothConductor(SmoothConductor::new(Rgb::new(0.9, 0.8, 0.7), Some(gold)).unwrap())
        );
        let glass = SmoothDielectric::new(1.5046, 1.000277, Rgb::ONE, Rgb::ONE).unwrap();
        assert_eq!(m(2).bsdf, Bsdf::SmoothDielectric(glass));
        let water = SmoothDielectric::new(1.333, 1.0, Rgb::splat(0.5), Rgb::ONE).unwrap();
        assert_eq!(m(3).bsdf, Bsdf::SmoothDielectric(water));
        assert_eq!(m(4).bsdf, Bsdf::RoughConductor(RoughConductor::new(0.3, Rgb::ONE, None).unwrap()));
        let rough = RoughDielectric::new(1.5046, 1.000277, 0.2, Rgb::ONE, Rgb::ONE).unwrap();
        assert_eq!(m(5).bsdf, Bsdf::RoughDielectric(rough.clone()));
        // Mitsuba's defaults: Beckmann, α = 0.1; anisotropic α along the frame's axes.
        let beckmann = RoughConductor::with_microfacet(Microfacet::beckmann(0.1), Rgb::ONE, None).unwrap();
        assert_eq!(m(6).bsdf, Bsdf::RoughConductor(beckmann));
        let aniso = rough.with_microfacet(Microfacet::anisotropic(Distribution::Ggx, 0.05, 0.4)).unwrap();
        assert_eq!(m(7).bsdf, Bsdf::RoughDielectric(aniso));
    }

    #[test]
    fn interior_media_make_absorbing_glass() {
        let s = scene(
            r#"<medium type="homogeneous" id="ink"><float name="albedo" value="0"/>
                 <rgb name="sigma_t" value="1, 2, 3"/><float name="scale" value="0.5"/>
                 <phase type="isotropic"/></medium>
               <bsdf type="dielectric" id="glass"/>
               <shape type="cube"><ref id="glass"/><ref name="interior" id="ink"/></shape>
               <shape type="cube"><ref name="interior" id="ink"/><ref id="glass"/></shape>
               <shape type="cube"><bsdf type="roughdielectric"><string name="distribution" value="ggx"/></bsdf>
                 <medium name="interior" type="homogeneous"><rgb name="albedo" value="0, 0, 0"/></medium></shape>
               <shape type="cube"><ref id="glass"/></shape>"#,
        );
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
        let d = &s.description;
        let m = |i: usize| &d.materials[d.meshes[i].material];
        assert_eq!(m(0).bsdf.absorption(), Rgb::new(0.5, 1.0, 1.5));
        assert_eq!(m(0).name, "glass+ink");
        assert_eq!(d.meshes[0].material, d.meshes[1].material, "the same glass and ink share a material");
        assert_eq!(m(2).bsdf.absorption(), Rgb::ONE);
        assert!(matches!(m(2).bsdf, Bsdf::RoughDielectric(_)));
        assert_eq!(m(3).bsdf.absorption(), Rgb::ZERO);
    }

    #[test]
    fn unsupported_media_are_located_errors() {
        let ink = |params: &str| {
            format!(
                "<bsdf type=\"dielectric\" id=\"g\"/>\n<medium type=\"homogeneous\" id=\"m\">\n  {params}</medium>\n\
                 <shape type=\"cube\"><ref id=\"g\"/><ref name=\"interior\" id=\"m\"/></shape>"
            )
        };
        let cases = [
            (ink(r#"<float name="albedo" value="0.5"/>"#), "dir/test.xml:4:3: <float name=\"albedo\">: a scattering medium"),
            (ink(""), "dir/test.xml:3:1: <medium type=\"homogeneous\" id=\"m\">: a homogeneous medium scatters by default"),
            (
                ink(r#"<float name="albedo" value="0"/><float name="scale" value="-1"/>"#),
                "dir/test.xml:4:35: <float name=\"scale\">: sigma_t · scale",
            ),
            (
                ink(r#"<float name="albedo" value="0"/><float name="sigma_t" value="nan"/>"#),
                "dir/test.xml:4:64: <float name=\"sigma_t\">: attribute `value`: \"nan\" is not a finite number",
            ),
            (
                "<shape type=\"cube\"><medium name=\"interior\" type=\"heterogeneous\"/></shape>".into(),
                "unsupported medium type \"heterogeneous\"",
            ),
            (
                "<shape type=\"cube\"><medium name=\"interior\" type=\"homogeneous\"><float name=\"albedo\" value=\"0\"/></medium></shape>"
                    .into(),
                "needs a dielectric BSDF on the shape (this shape has none)",
            ),
            (
                "<shape type=\"cube\"><bsdf type=\"diffuse\"/>\n<medium name=\"interior\" type=\"homogeneous\"><float name=\"albedo\" value=\"0\"/></medium></shape>"
                    .into(),
                "dir/test.xml:3:1: <medium type=\"homogeneous\" name=\"interior\">: an interior medium needs a dielectric BSDF",
            ),
            (
                "<shape type=\"cube\"><ref name=\"exterior\" id=\"x\"/></shape>".into(),
                "exterior media are not supported",
            ),
        ];
        for (body, expected) in cases {
            let e = err(&body);
            assert!(e.contains(expected), "{e}\nexpected: {expected}\n{body}");
        }
    }

    #[test]
    fn impossible_specular_parameters_are_located() {
        let cases: &[(&str, &str)] = &[
            (
                "<bsdf type=\"dielectric\">\n  <float name=\"int_ior\" value=\"-1\"/></bsdf>",
                "dir/test.xml:3:3: <float name=\"int_ior\">: invalid material: int_ior must be positive",
            ),
            (
                "<bsdf type=\"dielectric\">\n  <string name=\"ext_ior\" value=\"unobtainium\"/></bsdf>",
                "dir/test.xml:3:33: <string name=\"ext_ior\">: unknown index of refraction \"unobtainium\" (known: vacuum,",
            ),
            (
                "<bsdf type=\"dielectric\">\n  <rgb name=\"specular_transmittance\" value=\"1, 1.1, 1\"/></bsdf>",
                "dir/test.xml:3:3: <rgb name=\"specular_transmittance\">: invalid material: specular_transmittance exceeds 1",
            ),
            (
                "<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/>\n  <float name=\"alpha\" value=\"0\"/></bsdf>",
                "dir/test.xml:3:3: <float name=\"alpha\">: invalid material: alpha must be positive",
            ),
            (
                "<bsdf type=\"roughdielectric\"><string name=\"distribution\" value=\"ggx\"/>\n  <float name=\"alpha\" value=\"3\"/></bsdf>",
                "dir/test.xml:3:3: <float name=\"alpha\">: invalid material: alpha = 3 exceeds the supported maximum 1",
            ),
            (
                "<bsdf type=\"roughconductor\">\n  <string name=\"distribution\" value=\"phong\"/></bsdf>",
                "dir/test.xml:3:3: <string name=\"distribution\">: unknown microfacet distribution \"phong\" (known: beckmann, ggx)",
            ),
            (
                "<bsdf type=\"roughconductor\"><float name=\"alpha\" value=\"0.1\"/>\n  <float name=\"alpha_v\" value=\"0.2\"/></bsdf>",
                "dir/test.xml:3:3: <float name=\"alpha_v\">: give either alpha or alpha_u and alpha_v, not both",
            ),
            (
                "<bsdf type=\"roughdielectric\">\n  <float name=\"alpha_u\" value=\"0.2\"/></bsdf>",
                "dir/test.xml:3:3: <float name=\"alpha_u\">: alpha_u and alpha_v must be given together",
            ),
            (
                "<bsdf type=\"roughdielectric\"><float name=\"alpha_u\" value=\"0.2\"/>\n  <float name=\"alpha_v\" value=\"-1\"/></bsdf>",
                "dir/test.xml:3:3: <float name=\"alpha_v\">: invalid material: alpha_v must be positive",
            ),
            (
                "<bsdf type=\"conductor\"><string name=\"material\" value=\"Au\"/></bsdf>",
                "named conductor \"Au\"",
            ),
            ("<bsdf type=\"conductor\">\n <rgb name=\"eta\" value=\"nan\"/></bsdf>", "not a finite number"),
            ("<bsdf type=\"twosided\"><bsdf type=\"dielectric\"/></bsdf>", "already scatters on both faces"),
            (
                "<bsdf type=\"roughdielectric\"><string name=\"distribution\" value=\"ggx\"/><float name=\"int_ior\" value=\"1\"/><float name=\"ext_ior\" value=\"1\"/></bsdf>",
                "a rough interface needs different indices",
            ),
        ];
        for (body, want) in cases {
            let e = err(body);
            assert!(e.contains(want), "{body}\n→ {e}\nwant {want}");
        }
    }

    #[test]
    fn emitters() {
        let s = scene(
            r#"<emitter type="point"><point name="position" x="1" y="2" z="3"/><rgb name="intensity" value="4 5 6"/></emitter>
               <emitter type="point" id="lamp">
                 <transform name="to_world"><translate value="7, 8, 9"/></transform><float name="intensity" value="2"/>
               </emitter>
               <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="3"/></emitter></shape>"#,
        );
        let p = &s.description.point_lights;
        assert_eq!(
            (p[0].name.as_str(), p[0].position, p[0].intensity),
            ("point_0", Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0))
        );
        assert_eq!(
            (p[1].name.as_str(), p[1].position, p[1].intensity),
            ("lamp", Vec3::new(7.0, 8.0, 9.0), Rgb::splat(2.0))
        );
        assert_eq!(p[1].source, Source { file: "dir/test.xml".into(), line: 3 });
        assert_eq!(s.description.meshes[0].emission, Some(Rgb::splat(3.0)));
    }

    #[test]
    fn ignored_features_are_warnings() {
        let s = scene(
            r#"<integrator type="path"><integer name="max_depth" value="5"/></integrator>
               <sensor type="perspective"><float name="fov" value="45"/><float name="near_clip" value="0.1"/>
                 <film type="hdrfilm"><rfilter type="gaussian"/></film></sensor>
               <shape type="rectangle"><float name="bogus" value="1"/></shape>"#,
        );
        let w = s.warnings.join("\n");
        assert_eq!(s.warnings.len(), 3, "{w}");
        assert!(
            w.contains("dir/test.xml:2:25: <integer name=\"max_depth\">: max_depth = 5 is ignored"),
            "{w}"
        );
        assert!(w.contains("<rfilter type=\"gaussian\">: reconstruction filter"), "{w}");
        assert!(w.contains("<float name=\"bogus\">: parameter `bogus` is not supported"), "{w}");
    }

    #[test]
    fn bad_scenes_name_file_line_and_element() {
        let cases: &[(&str, &str)] = &[
            (
                r#"<bsdf type="plastic" id="p"/>"#,
                "dir/test.xml:2:13: <bsdf type=\"plastic\" id=\"p\">: unsupported BSDF type \"plastic\" (supported: diffuse, phong (Opticks extension), twosided, conductor, roughconductor, dielectric, roughdielectric)",
            ),
            (
                r#"<shape type="sphere"/>"#,
                "dir/test.xml:2:14: <shape type=\"sphere\">: unsupported shape type \"sphere\" (supported: obj, rectangle, cube)",
            ),
            (
                r#"<texture type="bitmap"/>"#,
                "dir/test.xml:2:1: <texture type=\"bitmap\">: unsupported element <texture>",
            ),
            (r#"<emitter type="constant"/>"#, "unsupported emitter type \"constant\""),
            (r#"<emitter type="area"/>"#, "must be nested inside a <shape>"),
            (
                "<shape type=\"rectangle\">\n<ref id=\"nope\"/></shape>\n<bsdf type=\"diffuse\" id=\"yes\"/>",
                "dir/test.xml:3:10: <ref id=\"nope\">: reference to unknown id \"nope\" (BSDF ids in this file: yes)",
            ),
            (
                "<shape type=\"rectangle\" id=\"s\"/>\n<shape type=\"rectangle\"><ref id=\"s\"/></shape>",
                "id \"s\" is a <shape> (at dir/test.xml:2:1), not a <bsdf>",
            ),
            (
                "<bsdf type=\"diffuse\" id=\"x\"/><bsdf type=\"diffuse\" id=\"x\"/>",
                "duplicate id \"x\" (first declared at dir/test.xml:2:1)",
            ),
            (
                "<bsdf type=\"diffuse\">\n  <rgb name=\"reflectance\" value=\"0.5, 1.2, 0.5\"/></bsdf>",
                "dir/test.xml:3:3: <rgb name=\"reflectance\">: invalid material:",
            ),
            (
                "<bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"-0.1\"/></bsdf>",
                "must not be negative",
            ),
            (
                "<shape type=\"rectangle\"><transform name=\"to_world\">\n<translate x=\"1\" y=\"nan\"/></transform></shape>",
                "dir/test.xml:3:21: <translate>: attribute `y`: \"nan\" is not a finite number",
            ),
            (
                "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"1e400\"/></transform></shape>",
                "not a finite number",
            ),
            (
                "<shape type=\"rectangle\"><transform name=\"to_world\"><shear/></transform></shape>",
                "unsupported transform element <shear>",
            ),
            (
                "<shape type=\"rectangle\"><transform name=\"to_world\"><matrix value=\"1 2 3\"/></transform></shape>",
                "a matrix needs 16 numbers",
            ),
            (
                "<shape type=\"rectangle\"><transform name=\"to_world\"><lookat origin=\"0,0,0\" target=\"0,1,0\" up=\"0,1,0\"/></transform></shape>",
                "parallel",
            ),
            ("<bsdf type=\"twosided\" id=\"t\"><ref id=\"t\"/></bsdf>", "refers to itself"),
            (
                "<bsdf type=\"twosided\"><bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/></bsdf>",
                "different front and back",
            ),
            ("<sensor type=\"thinlens\"/>", "unsupported sensor type \"thinlens\" (supported: perspective)"),
            (
                "<sensor type=\"perspective\"><float name=\"fov\" value=\"180\"/></sensor>",
                "outside (0°, 180°)",
            ),
            (
                "<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/><string name=\"fov_axis\" value=\"z\"/></sensor>",
                "unsupported fov_axis \"z\"",
            ),
            (
                "<sensor type=\"perspective\"><film type=\"hdrfilm\"><integer name=\"width\" value=\"0\"/></film></sensor>",
                "width 0 must be a positive integer",
            ),
            ("<shape type=\"obj\"/>", "missing <string name=\"filename\""),
            (
                "<shape type=\"rectangle\"><string name=\"flip_normals\" value=\"true\"/></shape>",
                "wrong property type: expected <boolean>",
            ),
            (
                "<shape type=\"rectangle\"><float name=\"a\" value=\"1\"/><float name=\"a\" value=\"1\"/></shape>",
                "given twice",
            ),
        ];
        for (body, expect) in cases {
            let e = err(body);
            assert!(e.contains(expect), "error for {body}\n  was: {e}\n  expected: {expect}");
            assert!(e.starts_with("dir/test.xml:"), "{e}");
        }
    }

    #[test]
    fn malformed_xml_and_missing_root_attributes() {
        let e = load_str("<scene version=\"3.0.0\">\n  <shape type=\"rectangle\">\n</scene>").unwrap_err();
        assert!(matches!(e, SceneFileError::Xml { .. }));
        assert!(e.to_string().starts_with("dir/test.xml:3:"), "{e}");
        let e =
            load_str("<scene version=\"3.0.0\">\n  <shape type=\"rectangle\"/>\n").unwrap_err().to_string();
        assert!(e.starts_with("dir/test.xml:3:") && e.contains("malformed XML"), "{e}");
        let e = load_str("<scene>\n</scene>").unwrap_err().to_string();
        assert!(e.contains("missing `version`"), "{e}");
        let e = load_str("<scene version=\"0.6.0\">\n</scene>").unwrap_err().to_string();
        assert!(e.contains("Mitsuba 0.x"), "{e}");
        let e = load_str("<world version=\"3.0.0\"/>").unwrap_err().to_string();
        assert!(e.contains("root element must be <scene"), "{e}");
    }
}
