//! `<bsdf type="principled">`: Mitsuba 3's principled (Disney) BSDF, read with Mitsuba's
//! parameter names and defaults into the core's [`Principled`]. Its own file because the
//! BSDF has a dozen parameters and rules of its own (`eta` or `specular`, never both; what the
//! transmission lobe changes), which would crowd `super::bsdf`.
//!
//! Every weight (`roughness`, `anisotropic`, `metallic`, `spec_tint`, `sheen`, `sheen_tint`,
//! `clearcoat`, `clearcoat_gloss`, `flatness`, `spec_trans`) is a `<float>` or a texture (its
//! `eval_1`, in [0, 1]) and `base_color` a colour or a texture, as Mitsuba's `get_texture`
//! parameters; `eta`, `specular` and the three sampling rates are plain floats, as in Mitsuba.
//! As in Mitsuba (`get_flag`), `spec_trans` given as a texture or a non-zero float turns the
//! transmission lobe on ([`Principled::has_spec_trans`]): the BSDF is then oriented and
//! two-sided like a dielectric, and η = 1 (`eta` 1 or `specular` 0) is raised to 1.001
//! (`specular` 10⁻³).
//!
//! `<bsdf type="principledthin">` ([`principledthin`]), Mitsuba 3's thin sheet, shares the
//! rules: its weights (`roughness`, `anisotropic`, `spec_trans`, `spec_tint`, `sheen`,
//! `sheen_tint`, `flatness` in [0, 1], `diff_trans` in [0, 2]) are floats or textures,
//! `base_color` a colour or a texture, `eta` (default 1.5) and the four sampling rates plain
//! floats. It is always two-sided (the same from both faces).

use super::Result;
use super::bsdf::material_error;
use super::build::Builder;
use super::properties::Props;
use super::texture::{bounded_float, colour, unit_float};
use super::xml::Element;
use opticks_core::bsdf::{Bsdf, Principled, PrincipledThin, eta_of_specular};
use opticks_core::texture::{ColourSlot, PrincipledWeight};

/// `principled` (module docs), one-sided as Mitsuba's unless it transmits.
pub fn principled<'d>(
    b: &mut Builder<'d>,
    e: &'d Element,
    ty: &str,
    p: &mut Props<'d>,
) -> Result<(Bsdf, bool)> {
    let mut q = Principled::default();
    let mut nodes: Vec<(&'static str, &'d Element)> = Vec::new();
    let (base, bnode) = colour(b, p, "base_color", q.base_color, ColourSlot::BaseColor)?;
    q.base_color = base;
    nodes.push(("base_color", bnode));
    for w in PrincipledWeight::ALL {
        if let Some((v, node)) = unit_float(b, p, w.name(), ColourSlot::Principled(w))? {
            if let Some(field) = w.field(&mut q) {
                *field = v as f32;
            }
            nodes.push((w.name(), node));
            if w == PrincipledWeight::SpecTrans {
                // Mitsuba's `get_flag`: a texture, or a float other than 0.
                q.has_spec_trans = node.tag != "float" || v != 0.0;
            }
        }
    }
    let spec_trans = q.has_spec_trans;
    let eta = p.float("eta")?;
    let specular = p.float("specular")?;
    q.eta = match (eta, specular) {
        (Some(_), Some((_, s))) => {
            return Err(s.err("give either eta or specular, not both (Mitsuba's rule)"));
        }
        (Some((v, node)), None) => {
            nodes.push(("eta", node));
            // Mitsuba raises η = 1 to 1.001 when the transmission lobe is present.
            if v == 1.0 && spec_trans { 1.001 } else { v as f32 }
        }
        (None, Some((s, node))) => {
            nodes.push(("eta", node));
            if !(0.0..=1.0).contains(&s) {
                return Err(node.err(format!("specular must lie in [0, 1], not {s}")));
            }
            // Mitsuba raises specular = 0 to 10⁻³ when the transmission lobe is present.
            let s = if s == 0.0 && spec_trans { 1e-3 } else { s as f32 };
            eta_of_specular(s)
        }
        (None, None) => q.eta,
    };
    for (name, field) in [
        ("diffuse_reflectance_sampling_rate", &mut q.diffuse_rate),
        ("main_specular_sampling_rate", &mut q.specular_rate),
        ("clearcoat_sampling_rate", &mut q.clearcoat_rate),
    ] {
        if let Some((v, node)) = p.float(name)? {
            *field = v as f32;
            nodes.push((name, node));
        }
    }
    if let Some(c) = p.objects().first() {
        return Err(c.err(format!(
            "unsupported element inside <bsdf type=\"{ty}\"> (textures need the name of one of its \
             parameters: base_color, {})",
            PrincipledWeight::ALL.map(PrincipledWeight::name).join(", ")
        )));
    }
    let q = q.checked().map_err(|source| material_error(source, &nodes, e))?;
    Ok((Bsdf::Principled(q), false))
}

/// `principledthin` (module docs): the thin sheet, scattering alike from both faces.
pub fn principledthin<'d>(
    b: &mut Builder<'d>,
    e: &'d Element,
    ty: &str,
    p: &mut Props<'d>,
) -> Result<(Bsdf, bool)> {
    let mut q = PrincipledThin::default();
    let mut nodes: Vec<(&'static str, &'d Element)> = Vec::new();
    let (base, bnode) = colour(b, p, "base_color", q.base_color, ColourSlot::BaseColor)?;
    q.base_color = base;
    nodes.push(("base_color", bnode));
    for w in PrincipledWeight::THIN {
        let slot = ColourSlot::Principled(w);
        if let Some((v, node)) = bounded_float(b, p, w.name(), slot, f64::from(w.max()))? {
            if let Some(field) = w.thin_field(&mut q) {
                *field = v as f32;
            }
            nodes.push((w.name(), node));
        }
    }
    for (name, field) in [
        ("eta", &mut q.eta),
        ("specular_reflectance_sampling_rate", &mut q.spec_reflect_rate),
        ("specular_transmittance_sampling_rate", &mut q.spec_trans_rate),
        ("diffuse_reflectance_sampling_rate", &mut q.diffuse_reflect_rate),
        ("diffuse_transmittance_sampling_rate", &mut q.diffuse_trans_rate),
    ] {
        if let Some((v, node)) = p.float(name)? {
            *field = v as f32;
            nodes.push((name, node));
        }
    }
    if let Some(c) = p.objects().first() {
        return Err(c.err(format!(
            "unsupported element inside <bsdf type=\"{ty}\"> (textures need the name of one of its \
             parameters: base_color, {}; eta is a float)",
            PrincipledWeight::THIN.map(PrincipledWeight::name).join(", ")
        )));
    }
    let q = q.checked().map_err(|source| material_error(source, &nodes, e))?;
    Ok((Bsdf::PrincipledThin(q), false))
}
