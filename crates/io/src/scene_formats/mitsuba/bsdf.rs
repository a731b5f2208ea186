//! `<bsdf>` elements and the scene's materials. [`BSDF_TYPES`] maps each supported Mitsuba BSDF
//! type to its builder; adding a BSDF is an entry there and its function (the "unsupported BSDF
//! type" error lists the table).
//!
//! The physical checks are the core's constructors' ([`Lambert::new`], [`ModifiedPhong::new`],
//! …); this file only reads Mitsuba's parameters with Mitsuba's defaults and maps the core's
//! [`MaterialError`] to the element of the offending parameter ([`material_error`]). Top-level
//! BSDFs with an `id` are built once, where first used, and each becomes one material however
//! many shapes refer to it ([`material_index`]).

use super::Result;
use super::build::Builder;
use super::properties::Props;
use super::texture::{BsdfTextures, colour, roughness};
use super::xml::Element;
use crate::scene_formats::SceneFileError;
use opticks_core::bsdf::{
    Blend, Bsdf, Lambert, Material, MaterialError, ModifiedPhong, Plastic, RoughConductor, RoughDielectric,
    RoughPlastic, SmoothConductor, SmoothDielectric, ThinDielectric, fresnel,
};
use opticks_core::math::Rgb;
use opticks_core::sampling::microfacet::{Distribution, Microfacet};
use opticks_core::texture::{ColourSlot, TextureBinding};

/// A BSDF as read: its material name, the core's BSDF and whether it scatters on both faces.
#[derive(Clone, Debug)]
pub struct ParsedBsdf {
    /// The material's name: the BSDF's id, else its type (shapes name theirs `shape.bsdf`).
    pub name: String,
    /// The BSDF.
    pub bsdf: Bsdf,
    /// Whether the back face scatters like the front (`twosided`).
    pub two_sided: bool,
    /// The colours given as textures ([`super::texture`]).
    pub textures: BsdfTextures,
}

/// A BSDF builder: the `<bsdf>` element, its type and its properties; returns the BSDF and
/// whether it is two-sided.
type BuildBsdf = for<'d> fn(&mut Builder<'d>, &'d Element, &str, &mut Props<'d>) -> Result<(Bsdf, bool)>;

/// A supported BSDF type.
struct BsdfType {
    name: &'static str,
    /// Not a Mitsuba 3 plugin (the error message says so).
    extension: bool,
    build: BuildBsdf,
}

/// The supported BSDF types, in the order the error message lists them.
const BSDF_TYPES: &[BsdfType] = &[
    BsdfType { name: "diffuse", extension: false, build: diffuse },
    BsdfType { name: "phong", extension: true, build: phong },
    BsdfType { name: "twosided", extension: false, build: twosided },
    BsdfType { name: "conductor", extension: false, build: specular },
    BsdfType { name: "roughconductor", extension: false, build: specular },
    BsdfType { name: "dielectric", extension: false, build: specular },
    BsdfType { name: "roughdielectric", extension: false, build: specular },
    BsdfType { name: "thindielectric", extension: false, build: thindielectric },
    BsdfType { name: "plastic", extension: false, build: plastic },
    BsdfType { name: "roughplastic", extension: false, build: roughplastic },
    BsdfType { name: "blendbsdf", extension: false, build: blendbsdf },
    BsdfType { name: "mask", extension: false, build: mask },
    BsdfType { name: "normalmap", extension: false, build: normalmap },
    BsdfType { name: "bumpmap", extension: false, build: bumpmap },
    BsdfType { name: "principled", extension: false, build: super::principled::principled },
    BsdfType { name: "principledthin", extension: false, build: super::principled::principledthin },
];

/// A `<bsdf>` element. Top-level BSDFs with an id are built once and cached.
pub fn bsdf<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<ParsedBsdf> {
    let id = e.attr("id")?.map(str::to_string);
    let cached_id = id.as_ref().filter(|_| e.top_level);
    if let Some(id) = cached_id {
        if let Some(done) = b.bsdfs.get(id) {
            return Ok(done.clone());
        }
        if !b.in_progress.insert(id.clone()) {
            return Err(e.err(format!("BSDF \"{id}\" refers to itself")));
        }
    }
    let ty = e.required("type")?;
    let name = id.clone().unwrap_or_else(|| ty.to_string());
    let mut p = Props::of(e)?;
    let Some(t) = BSDF_TYPES.iter().find(|t| t.name == ty) else {
        let names: Vec<String> = BSDF_TYPES
            .iter()
            .map(|t| if t.extension { format!("{} (Opticks extension)", t.name) } else { t.name.to_string() })
            .collect();
        return Err(
            e.attr_err("type", format!("unsupported BSDF type \"{ty}\" (supported: {})", names.join(", ")))
        );
    };
    let outer = std::mem::take(&mut b.bsdf_textures);
    let built = (t.build)(b, e, ty, &mut p);
    let textures = std::mem::replace(&mut b.bsdf_textures, outer);
    let (bsdf, two_sided) = built?;
    let parsed = ParsedBsdf { name, bsdf, two_sided, textures };
    b.finish(&p);
    if let Some(id) = cached_id {
        b.in_progress.remove(id);
        b.bsdfs.insert(id.clone(), parsed.clone());
    }
    Ok(parsed)
}

/// `<ref id="…"/>` to a top-level BSDF; the material is named by the id.
pub fn bsdf_ref<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<ParsedBsdf> {
    let id = e.required("id")?;
    let Some(target) = e.target.map(|i| b.doc.top(i)) else {
        let mut known: Vec<&str> =
            b.doc.ids.iter().filter(|(_, i)| b.doc.top(**i).tag == "bsdf").map(|(k, _)| k.as_str()).collect();
        known.sort_unstable();
        return Err(e.attr_err(
            "id",
            format!("reference to unknown id \"{id}\" (BSDF ids in this file: {})", known.join(", ")),
        ));
    };
    if target.tag != "bsdf" {
        return Err(e.err(format!("id \"{id}\" is a <{}> (at {}), not a <bsdf>", target.tag, target.at)));
    }
    let mut parsed = bsdf(b, target)?;
    b.used.insert(id.to_string());
    parsed.name = id.to_string();
    Ok(parsed)
}

/// The index in the scene's materials of `parsed`, added unless the material of `key` (a
/// top-level BSDF's id, or a key combining it with a medium's) is already there.
pub fn material_index(b: &mut Builder, parsed: &ParsedBsdf, key: Option<&str>) -> usize {
    if let Some(&i) = key.and_then(|k| b.material_of.get(k)) {
        return i;
    }
    let materials = &mut b.desc.materials;
    materials.push(Material {
        name: parsed.name.clone(),
        bsdf: parsed.bsdf.clone(),
        two_sided: parsed.two_sided,
    });
    let i = materials.len() - 1;
    for (slot, texture) in &parsed.textures {
        b.desc.textures.push(TextureBinding { material: i, slot: *slot, texture: texture.clone() });
    }
    if let Some(k) = key {
        b.material_of.insert(k.to_string(), i);
    }
    i
}

/// The material of a shape without a BSDF: Mitsuba's default, a one-sided `diffuse` of
/// reflectance 0.5, shared by all such shapes — black (reflectance 0) for an `emitter` shape,
/// as Mitsuba's `Shape` constructor makes it.
pub fn default_material(b: &mut Builder, emitter: bool) -> usize {
    let (key, name, rho) = if emitter {
        ("\u{0}default-emitter", "default-emitter", 0.0)
    } else {
        ("\u{0}default", "default", 0.5)
    };
    let parsed = ParsedBsdf {
        name: name.into(),
        bsdf: Bsdf::Lambert(Lambert::new(Rgb::splat(rho)).expect("valid albedo")),
        two_sided: false,
        textures: Vec::new(),
    };
    material_index(b, &parsed, Some(key))
}

/// The core's [`MaterialError`] located at the element of the parameter it names (`params`:
/// the core's parameter names and their elements), else at `fallback`.
pub fn material_error(
    source: MaterialError,
    params: &[(&str, &Element)],
    fallback: &Element,
) -> SceneFileError {
    let key = match &source {
        MaterialError::NotFinite(k)
        | MaterialError::Negative(k)
        | MaterialError::NotPositive(k)
        | MaterialError::AboveOne(k)
        | MaterialError::OutOfUnitRange(k, _)
        | MaterialError::TooLarge { name: k, .. } => Some(*k),
        _ => None,
    };
    let e = key.and_then(|k| params.iter().find(|(name, _)| *name == k).map(|p| p.1)).unwrap_or(fallback);
    SceneFileError::Material { at: e.at.clone(), element: e.describe(), source }
}

/// `diffuse`: Lambertian, one-sided.
fn diffuse<'d>(b: &mut Builder<'d>, _: &'d Element, _: &str, p: &mut Props<'d>) -> Result<(Bsdf, bool)> {
    let (rho, node) = colour(b, p, "reflectance", Rgb::splat(0.5), ColourSlot::Reflectance)?;
    if let Some(c) = p.objects().first() {
        return Err(c.err(
            "unsupported element inside <bsdf type=\"diffuse\"> (a texture needs name=\"reflectance\")",
        ));
    }
    let lambert = Lambert::new(rho).map_err(|source| material_error(source, &[], node))?;
    Ok((Bsdf::Lambert(lambert), false))
}

/// `phong` (Opticks extension, Mitsuba 0.6's parameter names), validated by
/// [`ModifiedPhong::new`]; an impossible value is reported at its element (kd + ks > 1 at the
/// `<bsdf>`, which both parameters belong to).
fn phong<'d>(b: &mut Builder<'d>, e: &'d Element, _: &str, p: &mut Props<'d>) -> Result<(Bsdf, bool)> {
    let (kd, kd_node) = colour(b, p, "diffuseReflectance", Rgb::splat(0.5), ColourSlot::DiffuseReflectance)?;
    let (ks, ks_node) =
        colour(b, p, "specularReflectance", Rgb::splat(0.2), ColourSlot::SpecularReflectance)?;
    if let Some(c) = p.objects().first() {
        return Err(c.err(
            "unsupported element inside <bsdf type=\"phong\"> (textures need the name of a colour \
             parameter: diffuseReflectance, specularReflectance)",
        ));
    }
    let (exponent, e_node) = p.float_or("exponent", 30.0)?;
    let phong = ModifiedPhong::new(kd, ks, exponent as f32).map_err(|source| {
        material_error(source, &[("kd", kd_node), ("ks", ks_node), ("exponent", e_node)], e)
    })?;
    Ok((Bsdf::ModifiedPhong(phong), false))
}

/// The one BSDF nested in a `what` BSDF (`e`, properties `p`): a `<bsdf>` or a `<ref>`.
fn one_nested<'d>(b: &mut Builder<'d>, e: &'d Element, p: &mut Props<'d>, what: &str) -> Result<ParsedBsdf> {
    let inner = p.objects();
    match inner.len() {
        0 => return Err(e.err(format!("a {what} BSDF needs one nested <bsdf> or <ref>"))),
        1 => {}
        _ if what == "twosided" => {
            return Err(
                inner[1].err("twosided with different front and back BSDFs is not supported (give one BSDF)")
            );
        }
        _ => return Err(inner[1].err(format!("a {what} BSDF takes one nested BSDF"))),
    }
    let c = inner[0];
    match c.tag.as_str() {
        "bsdf" => bsdf(b, c),
        "ref" => bsdf_ref(b, c),
        other => {
            Err(c.err(format!("unsupported element <{other}> inside a {what} BSDF (supported: bsdf, ref)")))
        }
    }
}

/// `twosided` around one nested BSDF (not a dielectric, not another `twosided`).
fn twosided<'d>(b: &mut Builder<'d>, e: &'d Element, _: &str, p: &mut Props<'d>) -> Result<(Bsdf, bool)> {
    let nested = one_nested(b, e, p, "twosided")?;
    let c = p.objects()[0];
    if nested.two_sided {
        return Err(c.err("a twosided BSDF cannot wrap another twosided BSDF"));
    }
    if nested.bsdf.transmits() {
        return Err(c.err(
            "a dielectric already scatters on both faces (its inside is behind the normal); \
             do not wrap it in a twosided BSDF",
        ));
    }
    b.bsdf_textures.extend(nested.textures);
    Ok((nested.bsdf, true))
}

/// `mask` (Mitsuba 3's opacity mask) around one nested BSDF: a ray meets the surface with
/// probability `opacity` (a float, default 0.5, or a texture) and then scatters by the nested
/// BSDF, else passes straight through — in expectation Mitsuba's α·f + (1 − α)·(null), done as
/// stochastic transparency in the scene's ray queries (core `Scene`'s masked intersection), so
/// shadow rays and the light estimator's splats pass through the open parts too.
fn mask<'d>(b: &mut Builder<'d>, e: &'d Element, _: &str, p: &mut Props<'d>) -> Result<(Bsdf, bool)> {
    // The opacity first: a texture given as it is one of the nested objects.
    super::texture::opacity(b, p, e)?;
    let nested = one_nested(b, e, p, "mask")?;
    if nested.textures.iter().any(|(slot, _)| *slot == ColourSlot::Opacity) {
        return Err(p.objects()[0].err("a mask inside a mask is not supported (give one opacity)"));
    }
    b.bsdf_textures.extend(nested.textures);
    Ok((nested.bsdf, nested.two_sided))
}

/// `normalmap` (Mitsuba 3's) around one nested BSDF: the nested BSDF shaded with the normal of
/// an RGB `normalmap` bitmap read raw ([`super::texture::normal_map`]; the scene perturbs the
/// shading normal, `opticks_core::scene::Scene::normals_at`), as [`shading_map`] reads it.
fn normalmap<'d>(b: &mut Builder<'d>, e: &'d Element, _: &str, p: &mut Props<'d>) -> Result<(Bsdf, bool)> {
    let Some(map) = p.take_object("normalmap") else {
        return Err(e.err(
            "a normalmap BSDF needs its normal map: <texture name=\"normalmap\" type=\"bitmap\"> \
             with <boolean name=\"raw\" value=\"true\"/>",
        ));
    };
    super::texture::normal_map(b, p, map)?;
    shading_map(b, e, p, "normalmap")
}

/// `bumpmap` (Mitsuba 3's) around one nested BSDF: the nested BSDF shaded with the normal of a
/// height field, one nested `bitmap` texture (or `<ref>` to one) under any name, whose UV
/// gradient times `scale` (a finite float, default 1) tilts the shading frame
/// ([`super::texture::bump_map`]; the scene perturbs the shading normal,
/// `opticks_core::scene::Scene::normals_at`), as [`shading_map`] reads it. The shape must have
/// texture coordinates (`super::shape` checks).
fn bumpmap<'d>(b: &mut Builder<'d>, e: &'d Element, _: &str, p: &mut Props<'d>) -> Result<(Bsdf, bool)> {
    let is_texture = |o: &&Element| {
        o.tag == "texture" || o.tag == "ref" && o.target.is_some_and(|i| b.doc.top(i).tag == "texture")
    };
    let textures: Vec<&Element> = p.objects().iter().copied().filter(is_texture).collect();
    let Some(&height) = textures.first() else {
        return Err(e.err(
            "a bumpmap BSDF needs its height: a nested <texture type=\"bitmap\"> (usually with \
             <boolean name=\"raw\" value=\"true\"/>) or a <ref> to one",
        ));
    };
    if let Some(extra) = textures.get(1) {
        return Err(extra.err("a bumpmap BSDF takes one texture (its height)"));
    }
    let (scale, _) = p.float_or("scale", 1.0)?;
    // Out of the objects, so that the nested BSDF is the only one left.
    let height = p.remove_object(height);
    super::texture::bump_map(b, p, height, scale)?;
    shading_map(b, e, p, "bumpmap")
}

/// The rest of a `normalmap` or `bumpmap` (`what`) BSDF once its map is recorded: Mitsuba's
/// `flip_invalid_normals` and `use_shadowing_function` are read but only their `false` is
/// Mitsuba's behaviour here (normals facing away from the viewer are not flipped and no
/// shadowing term is applied: a warning otherwise, docs/scene-formats.md), then the one nested
/// BSDF, which must not carry a map of its own.
fn shading_map<'d>(
    b: &mut Builder<'d>,
    e: &'d Element,
    p: &mut Props<'d>,
    what: &str,
) -> Result<(Bsdf, bool)> {
    let flip = p.bool("flip_invalid_normals")?;
    let shadowing = p.bool("use_shadowing_function")?;
    if flip != Some(false) || shadowing != Some(false) {
        b.warn(
            e,
            format!(
                "Opticks's {what} neither flips normals facing away from the viewer nor applies \
                 Mitsuba's shadowing term (it renders as flip_invalid_normals and \
                 use_shadowing_function false; Mitsuba's defaults are true)"
            ),
        );
    }
    let nested = one_nested(b, e, p, what)?;
    let inner = nested.textures.iter().find_map(|(slot, _)| match slot {
        ColourSlot::NormalMap => Some("normalmap"),
        ColourSlot::BumpMap => Some("bumpmap"),
        _ => None,
    });
    if let Some(inner) = inner {
        return Err(p.objects()[0].err(format!("a {inner} inside a {what} is not supported (give one map)")));
    }
    b.bsdf_textures.extend(nested.textures);
    Ok((nested.bsdf, nested.two_sided))
}

/// `conductor`, `roughconductor`, `dielectric`, `roughdielectric` (Mitsuba 3's parameters and
/// defaults); an impossible value is reported at its element.
fn specular<'d>(b: &mut Builder<'d>, e: &'d Element, ty: &str, p: &mut Props<'d>) -> Result<(Bsdf, bool)> {
    let mut nodes: Vec<(&'static str, &'d Element)> = Vec::new();
    let rough = ty.starts_with("rough");
    let (r, rnode) = colour(b, p, "specular_reflectance", Rgb::ONE, ColourSlot::SpecularReflectance)?;
    let t = if ty.ends_with("dielectric") {
        Some(colour(b, p, "specular_transmittance", Rgb::ONE, ColourSlot::SpecularTransmittance)?)
    } else {
        None
    };
    nodes.push(("specular_reflectance", rnode));
    let microfacet = if rough {
        microfacet(b, p, &mut nodes)?
    } else {
        Microfacet::ggx(0.1) // unused
    };
    no_other_objects(p, ty)?;
    let result = if ty.ends_with("conductor") {
        let (material, mnode) = p.string_or("material", "none")?;
        let eta = p.color("eta")?;
        let k = p.color("k")?;
        if let Some((_, en)) = eta {
            nodes.push(("eta", en));
        }
        if let Some((_, kn)) = k {
            nodes.push(("k", kn));
        }
        let ior = if material == "none" {
            eta.map(|(e, _)| (e, k.map_or(Rgb::ONE, |(k, _)| k)))
        } else {
            if let Some((_, n)) = eta.or(k) {
                return Err(n.err("give either `material` or `eta` and `k`, not both (Mitsuba's rule)"));
            }
            let named = super::conductors::named(&material).ok_or_else(|| {
                let names: Vec<&str> = super::conductors::CONDUCTORS.iter().map(|c| c.0).collect();
                mnode.attr_err(
                    "value",
                    format!("unknown conductor \"{material}\" (known: none, {})", names.join(", ")),
                )
            })?;
            nodes.push(("eta", mnode));
            nodes.push(("k", mnode));
            Some(named)
        };
        if rough {
            RoughConductor::with_microfacet(microfacet, r, ior).map(Bsdf::RoughConductor)
        } else {
            SmoothConductor::new(r, ior).map(Bsdf::SmoothConductor)
        }
    } else {
        let (t, tnode) = t.unwrap_or((Rgb::ONE, e));
        nodes.push(("specular_transmittance", tnode));
        let (int_ior, inode) = ior(p, "int_ior", 1.5046)?;
        let (ext_ior, enode) = ior(p, "ext_ior", 1.000277)?;
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
    Ok((result.map_err(|source| material_error(source, &nodes, e))?, false))
}

/// `thindielectric`: Mitsuba 3's thin sheet (`int_ior` BK7, `ext_ior` air,
/// `specular_reflectance`, `specular_transmittance` 1).
fn thindielectric<'d>(
    b: &mut Builder<'d>,
    e: &'d Element,
    ty: &str,
    p: &mut Props<'d>,
) -> Result<(Bsdf, bool)> {
    let (r, rnode) = colour(b, p, "specular_reflectance", Rgb::ONE, ColourSlot::SpecularReflectance)?;
    let (t, tnode) = colour(b, p, "specular_transmittance", Rgb::ONE, ColourSlot::SpecularTransmittance)?;
    no_other_objects(p, ty)?;
    let (int_ior, inode) = ior(p, "int_ior", 1.5046)?;
    let (ext_ior, enode) = ior(p, "ext_ior", 1.000277)?;
    let nodes = [
        ("int_ior", inode),
        ("ext_ior", enode),
        ("specular_reflectance", rnode),
        ("specular_transmittance", tnode),
    ];
    let b =
        ThinDielectric::new(int_ior, ext_ior, r, t).map_err(|source| material_error(source, &nodes, e))?;
    Ok((Bsdf::ThinDielectric(b), false))
}

/// `plastic`: Mitsuba 3's smooth plastic (`diffuse_reflectance` 0.5, `specular_reflectance` 1,
/// `int_ior` polypropylene = 1.49, `ext_ior` air, `nonlinear` false), one-sided.
fn plastic<'d>(b: &mut Builder<'d>, e: &'d Element, ty: &str, p: &mut Props<'d>) -> Result<(Bsdf, bool)> {
    let (d, dnode) = colour(b, p, "diffuse_reflectance", Rgb::splat(0.5), ColourSlot::DiffuseReflectance)?;
    let (s, snode) = colour(b, p, "specular_reflectance", Rgb::ONE, ColourSlot::SpecularReflectance)?;
    no_other_objects(p, ty)?;
    let (int_ior, inode) = ior(p, "int_ior", 1.49)?;
    let (ext_ior, enode) = ior(p, "ext_ior", 1.000277)?;
    let nonlinear = p.bool("nonlinear")?.unwrap_or(false);
    let nodes = [
        ("diffuse_reflectance", dnode),
        ("specular_reflectance", snode),
        ("int_ior", inode),
        ("ext_ior", enode),
    ];
    let b = Plastic::new(d, s, int_ior, ext_ior, nonlinear)
        .map_err(|source| material_error(source, &nodes, e))?;
    Ok((Bsdf::Plastic(b), false))
}

/// `roughplastic`: Mitsuba 3's rough plastic (the defaults of `plastic`, and `distribution`
/// Beckmann, `alpha` 0.1 — isotropic only, as Mitsuba's —, `sample_visible` true), one-sided.
fn roughplastic<'d>(
    b: &mut Builder<'d>,
    e: &'d Element,
    ty: &str,
    p: &mut Props<'d>,
) -> Result<(Bsdf, bool)> {
    let (d, dnode) = colour(b, p, "diffuse_reflectance", Rgb::splat(0.5), ColourSlot::DiffuseReflectance)?;
    let (s, snode) = colour(b, p, "specular_reflectance", Rgb::ONE, ColourSlot::SpecularReflectance)?;
    no_other_objects(p, ty)?;
    let (int_ior, inode) = ior(p, "int_ior", 1.49)?;
    let (ext_ior, enode) = ior(p, "ext_ior", 1.000277)?;
    let nonlinear = p.bool("nonlinear")?.unwrap_or(false);
    let sample_visible = p.bool("sample_visible")?.unwrap_or(true);
    let mut nodes = vec![
        ("diffuse_reflectance", dnode),
        ("specular_reflectance", snode),
        ("int_ior", inode),
        ("ext_ior", enode),
    ];
    let mf = microfacet(b, p, &mut nodes)?;
    if mf.alpha_u != mf.alpha_v {
        let at = nodes.iter().find(|(n, _)| *n == "alpha_u").map_or(e, |n| n.1);
        return Err(at.err("roughplastic is isotropic in Mitsuba 3: give one alpha (alpha_u = alpha_v)"));
    }
    let b = RoughPlastic::new(d, s, int_ior, ext_ior, mf.distribution, mf.alpha_u, sample_visible, nonlinear)
        .map_err(|source| material_error(source, &nodes, e))?;
    Ok((Bsdf::RoughPlastic(b), false))
}

/// `blendbsdf`: (1 − weight)·first + weight·second (Mitsuba 3's), `weight` a number in [0, 1]
/// or a texture (its eval_1; required, as Mitsuba's), two nested BSDFs (`<bsdf>` or `<ref>`)
/// without textures, both one-sided or both `twosided`.
fn blendbsdf<'d>(b: &mut Builder<'d>, e: &'d Element, _: &str, p: &mut Props<'d>) -> Result<(Bsdf, bool)> {
    let Some((weight, wnode)) = super::texture::weight(b, p)? else {
        return Err(e.err("a blendbsdf needs its weight (<float name=\"weight\"> in [0, 1], or a texture)"));
    };
    let inner = p.objects().to_vec();
    if inner.len() != 2 {
        let at = inner.get(2).copied().unwrap_or(e);
        return Err(at.err(format!("a blendbsdf blends exactly two nested BSDFs (given {})", inner.len())));
    }
    let mut children = Vec::with_capacity(2);
    for c in &inner {
        let nested = match c.tag.as_str() {
            "bsdf" => bsdf(b, c)?,
            "ref" => bsdf_ref(b, c)?,
            other => {
                return Err(c.err(format!(
                    "unsupported element <{other}> inside a blendbsdf (supported: bsdf, ref)"
                )));
            }
        };
        if !nested.textures.is_empty() {
            return Err(c.err("textures inside a blendbsdf are not supported yet"));
        }
        children.push((nested, *c));
    }
    let [(first, _), (second, second_node)] = <[_; 2]>::try_from(children).expect("two children");
    if first.two_sided != second.two_sided {
        return Err(second_node.err(
            "a blendbsdf of a twosided and a one-sided BSDF is not supported (wrap the blend in twosided)",
        ));
    }
    let two_sided = first.two_sided;
    let blend = Blend::new(weight as f32, first.bsdf, second.bsdf)
        .map_err(|source| material_error(source, &[("weight", wnode)], e))?;
    Ok((Bsdf::Blend(blend), two_sided))
}

/// An error at the first nested object no parameter took (a texture without the name of one of
/// the BSDF's colours or roughnesses, or another element).
fn no_other_objects(p: &Props, ty: &str) -> Result<()> {
    match p.objects().first() {
        Some(c) => Err(c.err(format!(
            "unsupported element inside <bsdf type=\"{ty}\"> (textures need the name of one of its \
             colour or roughness parameters, e.g. name=\"specular_reflectance\" or name=\"alpha\")"
        ))),
        None => Ok(()),
    }
}

/// The microfacet distribution of a rough BSDF: `distribution` (Beckmann by default), `alpha`
/// (0.1) or both `alpha_u` and `alpha_v`, each a number or a texture ([`roughness`]); records the
/// roughness parameters' elements in `nodes`.
fn microfacet<'d>(
    b: &mut Builder<'d>,
    p: &mut Props<'d>,
    nodes: &mut Vec<(&'static str, &'d Element)>,
) -> Result<Microfacet> {
    let (dist, dnode) = p.string_or("distribution", "beckmann")?;
    let distribution = match dist.trim().to_ascii_lowercase().as_str() {
        "beckmann" => Distribution::Beckmann,
        "ggx" => Distribution::Ggx,
        _ => {
            return Err(
                dnode.err(format!("unknown microfacet distribution \"{dist}\" (known: beckmann, ggx)"))
            );
        }
    };
    let _ = p.bool("sample_visible")?; // a sampling strategy: same expectation (taken before by
    // roughplastic, whose pdf Mitsuba defines by it)
    let a = roughness(b, p, "alpha", ColourSlot::Alpha)?;
    let au = roughness(b, p, "alpha_u", ColourSlot::AlphaU)?;
    let av = roughness(b, p, "alpha_v", ColourSlot::AlphaV)?;
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
            return Err(xn.err("give either alpha or alpha_u and alpha_v, not both"));
        }
        (None, Some((_, xn)), None) | (None, None, Some((_, xn))) => {
            return Err(xn.err("alpha_u and alpha_v must be given together"));
        }
    };
    Ok(Microfacet::anisotropic(distribution, u as f32, v as f32))
}

/// An index of refraction: a number or one of Mitsuba's names (`"bk7"`, `"water"`, …), or
/// `default` located at the `<bsdf>`.
fn ior<'d>(p: &mut Props<'d>, name: &str, default: f32) -> Result<(f32, &'d Element)> {
    let Some(node) = p.take_as(name, &["float", "integer", "string"])? else {
        return Ok((default, p.owner()));
    };
    let v = node.required("value")?;
    if node.tag == "string" {
        let ior = fresnel::named_ior(v).ok_or_else(|| {
            let names: Vec<&str> = fresnel::NAMED_IORS.iter().map(|(n, _)| *n).collect();
            node.attr_err(
                "value",
                format!("unknown index of refraction \"{v}\" (known: {})", names.join(", ")),
            )
        })?;
        return Ok((ior, node));
    }
    Ok((node.number("value", v)? as f32, node))
}
