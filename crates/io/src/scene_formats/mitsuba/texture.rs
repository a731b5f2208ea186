//! `<texture>` elements: the colour and roughness parameters of BSDFs given as textures, nested
//! in the BSDF (`<texture type="…" name="reflectance">`) or by `<ref name="reflectance" id="…"/>`
//! to a top-level `<texture id="…">` (built once, where first used, and shared).
//! [`TEXTURE_TYPES`] maps each supported Mitsuba type to its builder: `bitmap` (an image file
//! read by [`crate::texture_file`]), `checkerboard` and `mesh_attribute` (the hit mesh's own
//! values, [`attribute_names`] tells a shape which of its file's attributes to keep), with
//! Mitsuba's parameters and defaults.
//!
//! A BSDF builder reads a colour through [`colour`], a roughness through [`roughness`], a
//! `mask`'s opacity through [`opacity`] (and the maps that tilt the shading normal through
//! [`normal_map`] and [`bump_map`], which must be bitmaps): a
//! constant as before, or a texture, which is recorded on the [`super::bsdf::ParsedBsdf`] and
//! given to the core's constructor as its largest value (so the constructor's range checks hold
//! at every point, and report at the texture's element; a mesh attribute's values are the
//! meshes', checked by the core); the scene evaluates the texture at each hit
//! (`opticks_core::scene::Scene::material_at`).

use super::Result;
use super::build::Builder;
use super::properties::Props;
use super::xml::{Document, Element};
use crate::texture_file::read_texture_within;
use glam::DVec3;
use opticks_core::bsdf::MAX_ALPHA;
use opticks_core::math::Rgb;
use opticks_core::texture::{
    Bitmap, Checkerboard, ColourSlot, FilterType, MIN_TEXTURED_ALPHA, MeshAttributeTexture, Texture,
    UvTransform, WrapMode,
};
use std::sync::Arc;

/// The textures of one BSDF: which colour each replaces.
pub type BsdfTextures = Vec<(ColourSlot, Arc<Texture>)>;

/// A texture builder: the `<texture>` element and its properties.
type BuildTexture = for<'d> fn(&mut Builder<'d>, &'d Element, &mut Props<'d>) -> Result<Texture>;

/// The supported texture types, in the order the error message lists them.
const TEXTURE_TYPES: &[(&str, BuildTexture)] = &[
    ("bitmap", bitmap),
    ("checkerboard", checkerboard),
    ("mesh_attribute", mesh_attribute),
    ("rawconstant", rawconstant),
];

/// The colour parameter `name` of the BSDF whose properties are `p`: a texture nested in it or
/// referred to under that name (recorded as `slot` in the builder's textures of the BSDF being
/// built; its largest value is returned, located at its element), else [`Props::color_or`]
/// with `default`.
pub fn colour<'d>(
    b: &mut Builder<'d>,
    p: &mut Props<'d>,
    name: &str,
    default: Rgb,
    slot: ColourSlot,
) -> Result<(Rgb, &'d Element)> {
    let Some(e) = p.take_object(name) else { return p.color_or(name, default) };
    let texture = parameter_texture(b, p, name, e)?;
    let max = texture.max_value();
    b.bsdf_textures.push((slot, texture));
    Ok((max, e))
}

/// The roughness parameter `name` (`alpha`, `alpha_u`, `alpha_v`) of the BSDF whose properties
/// are `p`, if given: a `<float>`, or a texture nested in it or referred to under that name
/// (recorded as `slot`; returned as its largest value, raised to [`MIN_TEXTURED_ALPHA`] as
/// Mitsuba raises every α, so that the constructor's check holds; a bitmap or checkerboard
/// whose values leave [0, 1] is an error at its element).
pub fn roughness<'d>(
    b: &mut Builder<'d>,
    p: &mut Props<'d>,
    name: &str,
    slot: ColourSlot,
) -> Result<Option<(f64, &'d Element)>> {
    let Some(e) = p.take_object(name) else { return p.float(name) };
    let texture = parameter_texture(b, p, name, e)?;
    let (lo, hi) = texture.range_1();
    if !(lo >= 0.0 && hi <= MAX_ALPHA) {
        return Err(e.err(format!(
            "the texture's values {lo}..{hi} (Mitsuba's eval_1: a bitmap's luminance, a colour's mean) \
             are not a roughness in [0, {MAX_ALPHA}]"
        )));
    }
    b.bsdf_textures.push((slot, texture));
    Ok(Some((hi.clamp(MIN_TEXTURED_ALPHA, MAX_ALPHA) as f64, e)))
}

/// The `opacity` of a `mask` BSDF whose properties are `p`: a `<float>` (default 0.5, as
/// Mitsuba's), or a texture (its `eval_1`: a bitmap's luminance) nested in it or referred to,
/// recorded as [`ColourSlot::Opacity`] unless it is 1 everywhere (then nothing is masked).
/// Values outside [0, 1] are an error at their element.
pub fn opacity<'d>(b: &mut Builder<'d>, p: &mut Props<'d>, at: &'d Element) -> Result<()> {
    let texture = match p.take_object("opacity") {
        Some(e) => unit_texture(b, p, "opacity", e, 1.0)?,
        None => {
            let (v, e) = p.float("opacity")?.unwrap_or((0.5, at));
            if !(0.0..=1.0).contains(&v) {
                return Err(e.err(format!("an opacity must lie in [0, 1], not {v}")));
            }
            Arc::new(Texture::Constant(v as f32))
        }
    };
    if texture.range_1().0 < 1.0 {
        b.bsdf_textures.push((ColourSlot::Opacity, texture));
    }
    Ok(())
}

/// The `weight` of a `blendbsdf` whose properties are `p`, if given: a `<float>`, or a texture
/// (its `eval_1`) nested in it or referred to, recorded as [`ColourSlot::Weight`] and returned
/// as its largest value (what the blend is built with; the scene evaluates it at each hit).
pub fn weight<'d>(b: &mut Builder<'d>, p: &mut Props<'d>) -> Result<Option<(f64, &'d Element)>> {
    unit_float(b, p, "weight", ColourSlot::Weight)
}

/// The float parameter `name` of the BSDF whose properties are `p`, a weight in [0, 1], if
/// given: a `<float>` (returned as it is: the caller checks its range), or a texture (its
/// `eval_1`) nested in it or referred to, whose values must lie in [0, 1], recorded as `slot`
/// and returned as its largest value.
pub fn unit_float<'d>(
    b: &mut Builder<'d>,
    p: &mut Props<'d>,
    name: &str,
    slot: ColourSlot,
) -> Result<Option<(f64, &'d Element)>> {
    bounded_float(b, p, name, slot, 1.0)
}

/// [`unit_float`] for a weight in [0, `max`] (`principledthin`'s `diff_trans` lies in [0, 2]).
pub fn bounded_float<'d>(
    b: &mut Builder<'d>,
    p: &mut Props<'d>,
    name: &str,
    slot: ColourSlot,
    max: f64,
) -> Result<Option<(f64, &'d Element)>> {
    let Some(e) = p.take_object(name) else { return p.float(name) };
    let texture = unit_texture(b, p, name, e, max)?;
    let hi = texture.range_1().1;
    b.bsdf_textures.push((slot, texture));
    Ok(Some((hi as f64, e)))
}

/// The `normalmap` of a `normalmap` BSDF: the texture `e` (nested or referred to), which must be
/// a `bitmap` read `raw` (its colours are directions, not sRGB-encoded reflectances) of an RGB
/// image; recorded as [`ColourSlot::NormalMap`].
pub fn normal_map<'d>(b: &mut Builder<'d>, p: &mut Props<'d>, e: &'d Element) -> Result<()> {
    if let Some(t) = bitmap_element(b, e, "a normal map")? {
        let is = |c: &Element, tag: &str, name: &str| c.tag == tag && c.raw("name") == Some(name);
        let raw = t.children.iter().find(|c| is(c, "boolean", "raw"));
        if !raw.and_then(|c| c.raw("value")).is_some_and(|v| v.trim().eq_ignore_ascii_case("true")) {
            return Err(t.err(
                "a normal map must be read raw: add <boolean name=\"raw\" value=\"true\"/> to its bitmap \
                 (its colours are directions, not sRGB-encoded colours)",
            ));
        }
        if let Some(f) = t.children.iter().find(|c| is(c, "string", "filename"))
            && let Some(file) = f.raw("value")
        {
            let path = b.doc.resolve(f, file);
            if crate::texture_file::is_grey(&path) {
                return Err(f.attr_err(
                    "value",
                    format!("{}: a normal map must be an RGB image, not a grey one", path.display()),
                ));
            }
        }
    }
    let texture = parameter_texture(b, p, "normalmap", e)?;
    b.bsdf_textures.push((ColourSlot::NormalMap, texture));
    Ok(())
}

/// The height of a `bumpmap` BSDF: the texture `e` (nested or referred to, under any name, as
/// Mitsuba takes it), which must be a `bitmap` (its gradient is that of its bilinear
/// interpolation: Mitsuba's `eval_1_grad`, of the luminance; `raw` or not, grey or RGB, as
/// Mitsuba's RGB variants accept), with its `scale` (`scale_node`: the `<float>`, if given);
/// recorded as [`ColourSlot::BumpMap`] and [`ColourSlot::BumpScale`] (unless 1).
pub fn bump_map<'d>(b: &mut Builder<'d>, p: &mut Props<'d>, e: &'d Element, scale: f64) -> Result<()> {
    bitmap_element(b, e, "a bump map")?;
    let name = e.raw("name").unwrap_or("bumpmap").to_string();
    let texture = parameter_texture(b, p, &name, e)?;
    b.bsdf_textures.push((ColourSlot::BumpMap, texture));
    if scale != 1.0 {
        b.bsdf_textures.push((ColourSlot::BumpScale, Arc::new(Texture::Constant(scale as f32))));
    }
    Ok(())
}

/// The `<texture>` that `e` is or refers to if it is a `bitmap` (`None` for a `rawconstant`,
/// raw by definition, and for a reference to no texture: reported by [`parameter_texture`]);
/// any other type is an error (`what`, e.g. "a normal map", names it).
fn bitmap_element<'d>(b: &Builder<'d>, e: &'d Element, what: &str) -> Result<Option<&'d Element>> {
    let t = match e.tag.as_str() {
        "ref" => e.target.map(|i| b.doc.top(i)).filter(|t| t.tag == "texture").unwrap_or(e),
        _ => e,
    };
    if t.tag != "texture" {
        return Ok(None);
    }
    match t.raw("type") {
        Some("bitmap") => Ok(Some(t)),
        Some("rawconstant") => Ok(None),
        other => Err(t.err(format!(
            "{what} must be a bitmap (or rawconstant) texture, not \"{}\"",
            other.unwrap_or("")
        ))),
    }
}

/// The texture `e` given as the float parameter `name`, whose `eval_1` must lie in [0, 1] (an
/// error at `e` otherwise).
fn unit_texture<'d>(
    b: &mut Builder<'d>,
    p: &mut Props<'d>,
    name: &str,
    e: &'d Element,
    max: f64,
) -> Result<Arc<Texture>> {
    let texture = parameter_texture(b, p, name, e)?;
    let (lo, hi) = texture.range_1();
    if !(lo >= 0.0 && f64::from(hi) <= max) {
        return Err(e.err(format!(
            "{name} must lie in [0, {max}] (Mitsuba's eval_1: a bitmap's luminance, a colour's mean); \
             this texture's values are {lo}..{hi}"
        )));
    }
    Ok(texture)
}

/// An area emitter's `radiance` given as the texture `e` (a `<texture>` or a `<ref>` to one):
/// any texture type (a mesh attribute's values are the shape's, checked by the scene).
pub fn emitter_radiance<'d>(b: &mut Builder<'d>, p: &mut Props<'d>, e: &'d Element) -> Result<Arc<Texture>> {
    parameter_texture(b, p, "radiance", e)
}

/// A spot emitter's `texture` (projected along the spot: [`opticks_core::light::spot_texture`]).
pub fn spot_texture<'d>(b: &mut Builder<'d>, p: &mut Props<'d>, e: &'d Element) -> Result<Arc<Texture>> {
    let texture = parameter_texture(b, p, "texture", e)?;
    if matches!(*texture, Texture::MeshAttribute(_)) {
        return Err(e.err("a spot emitter cannot project a mesh_attribute texture (it has no mesh)"));
    }
    Ok(texture)
}

/// The texture `e` (a `<texture>` or a `<ref>` to one) given as parameter `name`, which must not
/// also be given as a value.
fn parameter_texture<'d>(
    b: &mut Builder<'d>,
    p: &mut Props<'d>,
    name: &str,
    e: &'d Element,
) -> Result<Arc<Texture>> {
    if let Some(given) = p.take(name) {
        return Err(given.err(format!("`{name}` is given twice (also as a texture at {})", e.at)));
    }
    let texture = match e.tag.as_str() {
        "texture" => texture(b, e)?,
        "ref" => {
            let id = e.required("id")?;
            let target = e.target.map(|i| b.doc.top(i)).filter(|t| t.tag == "texture").ok_or_else(|| {
                e.attr_err("id", format!("\"{id}\" is not the id of a top-level <texture>"))
            })?;
            b.used.insert(id.to_string());
            texture(b, target)?
        }
        other => {
            return Err(
                e.err(format!("a <{other}> cannot be the parameter `{name}` (use <texture> or a value)"))
            );
        }
    };
    Ok(texture)
}

/// The mesh attributes that the `mesh_attribute` textures reachable from `e` (nested, or through
/// `<ref>`s to top-level elements) read: what a shape must keep of its mesh file's attributes.
pub fn attribute_names(doc: &Document, e: &Element) -> Vec<String> {
    fn walk(doc: &Document, e: &Element, depth: usize, out: &mut Vec<String>) {
        // References nest no deeper than a scene's BSDFs do; a cycle is reported elsewhere.
        if depth > 32 {
            return;
        }
        if e.tag == "texture" && e.raw("type") == Some("mesh_attribute") {
            let name = e.children.iter().find(|c| c.tag == "string" && c.raw("name") == Some("name"));
            if let Some(Ok(v)) =
                name.and_then(|c| c.attributes.iter().find(|a| a.name == "value")).map(|a| &a.value)
                && !out.contains(v)
            {
                out.push(v.clone());
            }
        }
        if let Some(t) = e.target.filter(|_| e.tag == "ref") {
            walk(doc, doc.top(t), depth + 1, out);
        }
        for c in &e.children {
            walk(doc, c, depth + 1, out);
        }
    }
    let mut out = Vec::new();
    walk(doc, e, 0, &mut out);
    out
}

/// A `<texture>` element; top-level ones (with an id) are built once.
fn texture<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<Arc<Texture>> {
    let id = e.attr("id")?.filter(|_| e.top_level).map(str::to_string);
    if let Some(done) = id.as_ref().and_then(|id| b.textures.get(id)) {
        return Ok(done.clone());
    }
    let ty = e.required("type")?;
    let Some((_, build)) = TEXTURE_TYPES.iter().find(|(n, _)| *n == ty) else {
        let names: Vec<&str> = TEXTURE_TYPES.iter().map(|(n, _)| *n).collect();
        return Err(e.attr_err(
            "type",
            format!("unsupported texture type \"{ty}\" (supported: {})", names.join(", ")),
        ));
    };
    let mut p = Props::of(e)?;
    if let Some(c) = p.objects().first() {
        return Err(c.err("nested objects inside a <texture> are not supported (give colours as <rgb>)"));
    }
    let t = Arc::new(build(b, e, &mut p)?);
    b.finish(&p);
    if let Some(id) = id {
        b.textures.insert(id, t.clone());
    }
    Ok(t)
}

/// `to_uv`: Mitsuba's 3×3 affine map of the texture coordinates, taken from the `<transform>`'s
/// 4×4 matrix as Mitsuba extracts it (rows x and y; columns x, y and the translation).
fn to_uv<'d>(p: &mut Props<'d>) -> Result<UvTransform> {
    let Some((t, _)) = p.transform("to_uv")? else { return Ok(UvTransform::IDENTITY) };
    let m = t.matrix;
    let row = |i: usize| [m.col(0)[i] as f32, m.col(1)[i] as f32, m.col(3)[i] as f32];
    Ok(UvTransform([row(0), row(1)]))
}

/// `bitmap`: `filename` (PNG, JPEG, HDR, EXR), `raw` (false: sRGB-encoded files are decoded to
/// linear), `filter_type` (`bilinear`, `nearest`), `wrap_mode` (`repeat`, `mirror`, `clamp`),
/// `to_uv`.
fn bitmap<'d>(b: &mut Builder<'d>, e: &'d Element, p: &mut Props<'d>) -> Result<Texture> {
    let (file, fnode) =
        p.string("filename")?.ok_or_else(|| e.err("missing <string name=\"filename\" value=\"...\"/>"))?;
    let raw = p.bool("raw")?.unwrap_or(false);
    let (filter, node) = p.string_or("filter_type", "bilinear")?;
    let filter = match filter.as_str() {
        "bilinear" => FilterType::Bilinear,
        "nearest" => FilterType::Nearest,
        _ => return Err(node.err(format!("unknown filter_type \"{filter}\" (known: bilinear, nearest)"))),
    };
    let (wrap, node) = p.string_or("wrap_mode", "repeat")?;
    let wrap = match wrap.as_str() {
        "repeat" => WrapMode::Repeat,
        "mirror" => WrapMode::Mirror,
        "clamp" => WrapMode::Clamp,
        _ => return Err(node.err(format!("unknown wrap_mode \"{wrap}\" (known: repeat, mirror, clamp)"))),
    };
    let to_uv = to_uv(p)?;
    p.ignore(&["format"]); // a storage precision: the same values
    let path = b.doc.resolve(fnode, &file);
    let image = read_texture_within(&path, raw, b.doc.limits.max_texels)
        .map_err(|m| fnode.attr_err("value", format!("{}: {m}", path.display())))?;
    let bitmap = Bitmap::new(image.width, image.height, image.texels, filter, wrap, to_uv)
        .map_err(|m| fnode.attr_err("value", format!("{}: {m}", path.display())))?;
    Ok(Texture::Bitmap(bitmap))
}

/// `mesh_attribute`: `name` (`vertex_…` or `face_…`, required), `scale` (1). The values are the
/// hit mesh's ([`attribute_names`]).
fn mesh_attribute<'d>(_: &mut Builder<'d>, e: &'d Element, p: &mut Props<'d>) -> Result<Texture> {
    let (name, node) =
        p.string("name")?.ok_or_else(|| e.err("missing <string name=\"name\" value=\"vertex_…\"/>"))?;
    let (scale, snode) = p.float_or("scale", 1.0)?;
    let t = MeshAttributeTexture::new(name, scale as f32).map_err(|m| match m {
        opticks_core::texture::TextureError::BadScale(_) => snode.attr_err("value", m.to_string()),
        _ => node.attr_err("value", m.to_string()),
    })?;
    Ok(Texture::MeshAttribute(t))
}

/// `rawconstant`: `value`, a `<float>` or a `<vector>`/`<point>`/`<rgb>` taken as it is (Mitsuba
/// converts no colour space here), everywhere. It is held as a 1 × 1 bitmap, so it stands
/// wherever a bitmap can — Mitsuba's test scenes give a normal map the identity (0.5, 0.5, 1)
/// this way — and a bitmap's checks apply (finite values ≥ 0).
fn rawconstant<'d>(_: &mut Builder<'d>, e: &'d Element, p: &mut Props<'d>) -> Result<Texture> {
    let node = p
        .take_as("value", &["float", "integer", "vector", "point", "rgb"])?
        .ok_or_else(|| e.err("missing <float name=\"value\" …/> or <vector name=\"value\" …/>"))?;
    let v = match node.tag.as_str() {
        "vector" | "point" => node.xyz(0.0, false)?,
        // One number (grey) or three, as `<rgb>` anywhere; a value is required.
        "rgb" => node.required("value").and_then(|_| node.xyz(0.0, true))?,
        _ => DVec3::splat(node.number("value", node.required("value")?)?),
    }
    .as_vec3();
    Bitmap::new(1, 1, vec![v], FilterType::Nearest, WrapMode::Repeat, UvTransform::IDENTITY)
        .map(Texture::Bitmap)
        .map_err(|m| node.attr_err("value", m.to_string()))
}

/// `checkerboard`: `color0` (0.4), `color1` (0.2), `to_uv`.
fn checkerboard<'d>(_: &mut Builder<'d>, e: &'d Element, p: &mut Props<'d>) -> Result<Texture> {
    let (c0, _) = p.color_or("color0", Rgb::splat(0.4))?;
    let (c1, _) = p.color_or("color1", Rgb::splat(0.2))?;
    let to_uv = to_uv(p)?;
    Checkerboard::new(c0, c1, to_uv).map(Texture::Checkerboard).map_err(|m| e.err(m.to_string()))
}
