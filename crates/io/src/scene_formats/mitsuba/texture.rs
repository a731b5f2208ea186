//! `<texture>` elements: the colour parameters of BSDFs given as textures, nested in the BSDF
//! (`<texture type="…" name="reflectance">`) or by `<ref name="reflectance" id="…"/>` to a
//! top-level `<texture id="…">` (built once, where first used, and shared). [`TEXTURE_TYPES`]
//! maps each supported Mitsuba type to its builder: `bitmap` (an image file read by
//! [`crate::texture_file`]) and `checkerboard`, with Mitsuba's parameters and defaults.
//!
//! A BSDF builder reads a colour through [`colour`]: a constant as before, or a texture, which
//! is recorded on the [`super::bsdf::ParsedBsdf`] and given to the core's constructor as its
//! largest value (so the constructor's range checks hold at every point, and report at the
//! texture's element); the scene evaluates the texture at each hit
//! (`opticks_core::scene::Scene::material_at`).

use super::Result;
use super::build::Builder;
use super::properties::Props;
use super::xml::Element;
use crate::texture_file::read_texture;
use opticks_core::math::Rgb;
use opticks_core::texture::{Bitmap, Checkerboard, ColourSlot, FilterType, Texture, UvTransform, WrapMode};
use std::sync::Arc;

/// The textures of one BSDF: which colour each replaces.
pub type BsdfTextures = Vec<(ColourSlot, Arc<Texture>)>;

/// A texture builder: the `<texture>` element and its properties.
type BuildTexture = for<'d> fn(&mut Builder<'d>, &'d Element, &mut Props<'d>) -> Result<Texture>;

/// The supported texture types, in the order the error message lists them.
const TEXTURE_TYPES: &[(&str, BuildTexture)] = &[("bitmap", bitmap), ("checkerboard", checkerboard)];

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
            return Err(e.err(format!("a <{other}> cannot be the colour `{name}` (use <texture> or <rgb>)")));
        }
    };
    let max = texture.max_value();
    b.bsdf_textures.push((slot, texture));
    Ok((max, e))
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
    let image =
        read_texture(&path, raw).map_err(|m| fnode.attr_err("value", format!("{}: {m}", path.display())))?;
    let bitmap = Bitmap::new(image.width, image.height, image.texels, filter, wrap, to_uv)
        .map_err(|m| fnode.attr_err("value", format!("{}: {m}", path.display())))?;
    Ok(Texture::Bitmap(bitmap))
}

/// `checkerboard`: `color0` (0.4), `color1` (0.2), `to_uv`.
fn checkerboard<'d>(_: &mut Builder<'d>, e: &'d Element, p: &mut Props<'d>) -> Result<Texture> {
    let (c0, _) = p.color_or("color0", Rgb::splat(0.4))?;
    let (c1, _) = p.color_or("color1", Rgb::splat(0.2))?;
    let to_uv = to_uv(p)?;
    Checkerboard::new(c0, c1, to_uv).map(Texture::Checkerboard).map_err(|m| e.err(m.to_string()))
}
