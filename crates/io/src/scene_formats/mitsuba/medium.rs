//! `<medium>` elements, read only as a shape's `interior`: Opticks renders purely absorbing
//! media, as the Beer–Lambert absorption σ_a of the shape's dielectric BSDF (absorbing glass).
//! A scattering medium, another medium type, or an interior on a shape that is not a dielectric
//! is a located error.

use super::Result;
use super::bsdf::{self, ParsedBsdf};
use super::build::Builder;
use super::properties::Props;
use super::xml::Element;
use opticks_core::bsdf::{Bsdf, check_absorption};
use opticks_core::math::Rgb;

/// A shape's interior medium: its absorption, where it is declared, its id if top-level (to
/// share the material of the same BSDF and medium) and a name for the material.
pub struct Interior<'d> {
    /// σ_a per unit of path length, per channel.
    pub sigma_a: Rgb,
    /// The `<medium>` element.
    pub node: &'d Element,
    /// The medium's id, if it is a top-level one.
    pub id: Option<String>,
    /// The medium's part of the material name.
    pub name: String,
}

/// A shape's `<ref name="interior" id="…"/>` or inline `<medium name="interior">`.
pub fn interior_medium<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<Interior<'d>> {
    if e.tag == "medium" {
        return Ok(Interior { sigma_a: absorbing_medium(b, e)?, node: e, id: None, name: "medium".into() });
    }
    let id = e.required("id")?;
    let target = match e.target.map(|i| b.doc.top(i)) {
        Some(t) if t.tag == "medium" => t,
        Some(t) => {
            return Err(e.err(format!("id \"{id}\" is a <{}> (at {}), not a <medium>", t.tag, t.at)));
        }
        None => return Err(e.attr_err("id", format!("reference to unknown medium id \"{id}\""))),
    };
    b.used.insert(id.to_string());
    Ok(Interior {
        sigma_a: absorbing_medium(b, target)?,
        node: target,
        id: Some(id.to_string()),
        name: id.into(),
    })
}

/// The material of a shape with BSDF `parsed` (referred to as `ref_id`, if it is a top-level
/// one) and interior `medium`: the dielectric with the medium's absorption, shared by every
/// shape with the same top-level BSDF and medium.
pub fn absorbing_material(
    b: &mut Builder,
    parsed: ParsedBsdf,
    ref_id: Option<String>,
    medium: Interior,
) -> Result<usize> {
    let bsdf = match parsed.bsdf {
        Bsdf::SmoothDielectric(d) => d.with_absorption(medium.sigma_a).map(Bsdf::SmoothDielectric),
        Bsdf::RoughDielectric(d) => d.with_absorption(medium.sigma_a).map(Bsdf::RoughDielectric),
        _ => {
            return Err(medium.node.err(format!(
                "an interior medium needs a dielectric BSDF on the shape (BSDF \"{}\" is not one): \
                 Opticks models absorbing glass only",
                parsed.name
            )));
        }
    };
    let bsdf = bsdf.map_err(|source| bsdf::material_error(source, &[], medium.node))?;
    let name = format!("{}+{}", parsed.name, medium.name);
    let key = ref_id.zip(medium.id).map(|(r, m)| format!("{r}\u{0}{m}"));
    let parsed = ParsedBsdf { name, bsdf, two_sided: parsed.two_sided, textures: parsed.textures };
    Ok(bsdf::material_index(b, &parsed, key.as_deref()))
}

/// σ_a of a purely absorbing `<medium type="homogeneous">`: `sigma_t`·`scale`, with `albedo`
/// 0 (which must be given: Mitsuba's default scatters).
fn absorbing_medium<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<Rgb> {
    let ty = e.required("type")?;
    if ty != "homogeneous" {
        return Err(e.attr_err(
            "type",
            format!("unsupported medium type \"{ty}\" (supported: homogeneous, with albedo 0)"),
        ));
    }
    let mut p = Props::of(e)?;
    if let Some(c) = p.objects().iter().find(|c| c.tag != "phase") {
        return Err(c.err("unsupported element inside a medium (supported: phase)"));
    }
    match p.color("albedo")? {
        Some((a, _)) if a == Rgb::ZERO => {}
        Some((a, anode)) => {
            return Err(anode.err(format!(
                "a scattering medium (albedo {a}) is not supported: Opticks renders purely \
                 absorbing interiors only (albedo 0)"
            )));
        }
        None => {
            return Err(e.err(
                "a homogeneous medium scatters by default (Mitsuba's albedo is 0.75); Opticks renders \
                 purely absorbing interiors only: give <float name=\"albedo\" value=\"0\"/>",
            ));
        }
    }
    let (sigma_t, tnode) = p.color_or("sigma_t", Rgb::ONE)?;
    let (scale, snode) = p.float_or("scale", 1.0)?;
    p.ignore(&["sample_emitters"]);
    b.finish(&p);
    // The core's rule for σ_a, applied here to point at `scale` if that is the culprit, else at
    // `sigma_t` (the dielectric checks it again when the medium is attached).
    let at = if scale < 0.0 || !scale.is_finite() { snode } else { tnode };
    check_absorption(sigma_t * scale as f32).map_err(|source| bsdf::material_error(source, &[], at))
}
