//! glTF metallic-roughness materials → Opticks materials (Lambert or Modified Phong) and emitted
//! radiance. The mapping, with m = metallic, r = roughness, b = baseColor (linear RGB):
//!
//! ```text
//! F0  = 0.04 · specularFactor · specularColorFactor    (dielectric reflectance at normal incidence;
//!                                                       0.04 is ((ior−1)/(ior+1))² for ior = 1.5,
//!                                                       KHR_materials_ior changes it: ior ≥ 1,
//!                                                       or 0 for F0 = 1; other values are errors)
//! ks  = (1 − m) · F0 + m · b                           (metals reflect their base colour)
//! kd  = (1 − m) · (1 − F0) · b                         (what the dielectric's Fresnel layer lets through)
//! α   = r²,  n = 2/α² − 2  (clamped to [0, 10⁶])       (Phong exponent of the GGX/Beckmann roughness α)
//! ```
//!
//! kd + ks ≤ 1 in every channel follows from b ≤ 1 and F0 ≤ 1 (both are clamped to [0, 1]), so
//! the result always conserves energy. ks = 0 (a dielectric with `specularFactor` 0, as
//! `KHR_materials_specular` allows) gives a pure [`Lambert`] of albedo (1 − m)·b; otherwise it is
//! [`ModifiedPhong`]`(kd, ks, n)`. Phong has no Fresnel term, so grazing reflections are weaker
//! than in a glTF viewer. `doubleSided` → [`Material::two_sided`]. `alphaMode` other than
//! `OPAQUE`, normal and occlusion textures are ignored with a warning.
//!
//! **Textures** ([`super::textures`]). `baseColorTexture` (sRGB) times `baseColorFactor` gives b
//! per texel, and `metallicRoughnessTexture` (linear; metallic in its blue channel) times
//! `metallicFactor` gives m per texel; kd and ks are then computed per texel by the mapping
//! above and become bitmap textures on Phong's `kd` and `ks` (or Lambert's reflectance), over
//! the base colour's texels (the metallic texture resampled bilinearly onto them when the sizes
//! differ). A colour that does not vary stays a constant. Two cases fall back to the mean over
//! the texture (a warning says so): the metallic texture read through other texture
//! coordinates or another transform than the base colour, and a metallic texture whose kd and
//! ks maxima sum above 1 (the core checks Phong's energy bound at the textures' maxima, which a
//! varying metallic breaks). Phong has one exponent per material: the roughness (green
//! channel) is `roughnessFactor` × the texture's mean (warning).
//!
//! **Transmission** (`KHR_materials_transmission`, with `KHR_materials_ior` and
//! `KHR_materials_volume`): a `transmissionFactor` of at least ½ makes the surface glass of
//! index `ior` (1.5), its transmission tinted by the base colour: without
//! `KHR_materials_volume` (or with `thicknessFactor` 0) the glTF surface is thin-walled —
//! a thin dielectric sheet, no refraction (core `ThinDielectric`); with a thickness, a
//! refracting dielectric (smooth for roughness 0, else GGX of α = r², both faces). Below ½
//! the surface stays opaque. A factor strictly between 0 and 1 is a mix Opticks does not
//! represent: the nearer of the two is used (warning); a `transmissionTexture`, and the
//! volume's attenuation, are ignored (warning).
//!
//! Emission: `emissiveFactor × KHR_materials_emissive_strength` (strength 1 if absent) is taken as
//! the radiance in **W/(m²·sr)**. glTF defines emission in relative, display-referred units
//! ("nits-like", no absolute scale); Opticks needs a physical one, and identity is the only
//! assumption that needs no exposure constant. An `emissiveTexture` makes the factor a multiplier
//! of a texture Opticks cannot read: the material then does not emit (warning), as in the OBJ
//! loader with `map_Ke`. Emission is one-sided (front, counter-clockwise face), even for
//! `doubleSided` materials.

use super::Report;
use super::textures::{ImageError, Images, TextureUse};
use crate::scene_formats::SceneFileError;
use opticks_core::bsdf::{
    Bsdf, Lambert, Material, MaterialError, ModifiedPhong, RoughDielectric, SmoothDielectric, ThinDielectric,
};
use opticks_core::light::LightError;
use opticks_core::light::check::check_emission;
use opticks_core::math::{Rgb, Vec2};
use opticks_core::scene::SceneDescription;
use opticks_core::texture::{Bitmap, ColourSlot, Texture, TextureBinding, TextureError, UvTransform};
use std::sync::Arc;

/// Why a glTF material cannot be converted: a value out of its range, an unreadable image, or
/// a texture or glass the core refuses. The messages name the glTF property.
#[derive(Debug, thiserror::Error)]
pub enum ConvertError {
    /// A base colour, metallic or roughness factor that is negative or not finite.
    #[error("{0} must be finite and non-negative")]
    Factor(&'static str),
    /// An index of refraction `KHR_materials_ior` does not allow.
    #[error(
        "KHR_materials_ior: ior {0} is invalid (the extension allows a finite value ≥ 1, or 0 for a Fresnel term of 1)"
    )]
    Ior(f32),
    /// `KHR_materials_specular` factors that give a non-finite F0.
    #[error("KHR_materials_specular factors must be finite")]
    Specular,
    /// A texture's image cannot be had.
    #[error(transparent)]
    Image(#[from] ImageError),
    /// The metallic-roughness texture is not a valid bitmap.
    #[error("metallicRoughnessTexture: {0}")]
    MetallicRoughnessTexture(TextureError),
    /// The baked base-colour texture is not a valid bitmap.
    #[error("baseColorTexture: {0}")]
    BaseColorTexture(TextureError),
    /// The emitted radiance is negative or not finite.
    #[error("emissiveFactor × emissiveStrength: {0}")]
    Emission(LightError),
    /// A `transmissionFactor` outside [0, 1].
    #[error("KHR_materials_transmission: transmissionFactor {0} is not in [0, 1]")]
    TransmissionFactor(f32),
    /// The glass the transmission extension describes is one the core refuses.
    #[error("KHR_materials_transmission: {0}")]
    Transmission(MaterialError),
}

/// A converted glTF material.
#[derive(Clone, Debug, PartialEq)]
pub struct Converted {
    /// The core material.
    pub material: Material,
    /// Emitted radiance, W/(m²·sr), if any.
    pub emission: Option<Rgb>,
    /// Things ignored (messages without location; the caller adds it).
    pub notes: Vec<String>,
    /// Textures in place of the material's colours.
    pub textures: Vec<(ColourSlot, Arc<Texture>)>,
    /// The `TEXCOORD_n` set the textures read (`None` without textures).
    pub tex_coord: Option<u32>,
}

/// Phong exponent for a glTF roughness: α = r², n = 2/α² − 2 ([`ModifiedPhong::exponent_for_slope`]).
pub fn phong_exponent(roughness: f32) -> f32 {
    let r = roughness.clamp(0.0, 1.0);
    ModifiedPhong::exponent_for_slope(r * r)
}

/// The BSDF parameters of the mapping in the module docs: (kd, ks, exponent).
pub fn metallic_roughness_to_phong(base: Rgb, metallic: f32, roughness: f32, f0: Rgb) -> (Rgb, Rgb, f32) {
    let b = base.clamp(Rgb::ZERO, Rgb::ONE);
    let m = metallic.clamp(0.0, 1.0);
    let f0 = f0.clamp(Rgb::ZERO, Rgb::ONE);
    let ks = (1.0 - m) * f0 + m * b;
    let kd = (1.0 - m) * (Rgb::ONE - f0) * b;
    (kd, ks, phong_exponent(roughness))
}

/// The material used for primitives without one: glTF's default (white, metallic 1, roughness 1),
/// one-sided.
pub fn default_material() -> Converted {
    let (kd, ks, n) = metallic_roughness_to_phong(Rgb::ONE, 1.0, 1.0, Rgb::splat(0.04));
    Converted {
        material: build("default", kd, ks, n, false),
        emission: None,
        notes: Vec::new(),
        textures: Vec::new(),
        tex_coord: None,
    }
}

fn build(name: &str, kd: Rgb, ks: Rgb, n: f32, two_sided: bool) -> Material {
    let bsdf = make_bsdf(kd, ks, n).unwrap_or_else(|_| {
        // Unreachable for finite clamped inputs; rounding could push kd + ks a hair over 1.
        let s = 1.0 / (kd + ks).max_element().max(1.0) * (1.0 - f32::EPSILON);
        make_bsdf(kd * s, ks * s, n).unwrap_or(Bsdf::Lambert(Lambert { reflectance: Rgb::ZERO }))
    });
    Material { name: name.to_string(), bsdf, two_sided }
}

fn make_bsdf(kd: Rgb, ks: Rgb, n: f32) -> Result<Bsdf, MaterialError> {
    if ks.max_element() <= 0.0 {
        Lambert::new(kd).map(Bsdf::Lambert)
    } else {
        ModifiedPhong::new(kd, ks, n).map(Bsdf::ModifiedPhong)
    }
}

/// How the primitives of one glTF material use it once converted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialUse {
    /// Index of the material in the scene description's materials.
    pub index: usize,
    /// Emitted radiance, W/(m²·sr), if any.
    pub emission: Option<Rgb>,
    /// The `TEXCOORD_n` set its textures read (`None` without textures).
    pub tex_coord: Option<u32>,
}

/// The document's materials, each converted on first use and added to the scene description
/// once (with its textures and its notes as warnings).
pub struct MaterialTable<'a> {
    /// By glTF material index + 1 (0: the default material), once converted.
    used: Vec<Option<MaterialUse>>,
    /// The document's images, decoded on first use.
    images: Images<'a>,
}

impl<'a> MaterialTable<'a> {
    /// The materials of `doc`, whose buffers are `buffers` and whose files are in `folder`,
    /// their images of at most `max_texels` texels each.
    pub fn new(
        doc: &'a ::gltf::Document,
        buffers: &'a [Vec<u8>],
        folder: &'a std::path::Path,
        max_texels: u64,
    ) -> Self {
        MaterialTable {
            used: vec![None; doc.materials().len() + 1],
            images: Images::new(doc, buffers, folder, max_texels),
        }
    }

    /// `mat` as the scene uses it, converted and added to `desc` the first time; an invalid
    /// value is an error at the material.
    pub(super) fn resolve(
        &mut self,
        mat: &::gltf::Material<'_>,
        desc: &mut SceneDescription,
        report: &mut Report,
    ) -> Result<MaterialUse, SceneFileError> {
        let key = mat.index().map_or(0, |i| i + 1);
        if let Some(used) = self.used.get(key).copied().flatten() {
            return Ok(used);
        }
        let (name, c) = match mat.index() {
            None => ("default".to_string(), default_material()),
            Some(i) => {
                let name = mat.name().map_or_else(|| format!("material {i}"), str::to_string);
                let c = convert(mat, &name, &mut self.images)
                    .map_err(|e| report.invalid(format!("material {i} ({name})"), e))?;
                (name, c)
            }
        };
        for note in c.notes {
            report.warn(&format!("material {name:?}"), note);
        }
        desc.materials.push(c.material);
        let index = desc.materials.len() - 1;
        for (slot, texture) in c.textures {
            desc.textures.push(TextureBinding { material: index, slot, texture });
        }
        let used = MaterialUse { index, emission: c.emission, tex_coord: c.tex_coord };
        if let Some(s) = self.used.get_mut(key) {
            *s = Some(used);
        }
        Ok(used)
    }
}

/// Converts one glTF material (see the module docs), its textures decoded from `images`.
/// Errors are non-finite or negative values and unreadable images ([`ConvertError`]).
pub fn convert(
    mat: &::gltf::Material<'_>,
    name: &str,
    images: &mut Images<'_>,
) -> Result<Converted, ConvertError> {
    let mut notes = Vec::new();
    let pbr = mat.pbr_metallic_roughness();
    let [r, g, b, _] = pbr.base_color_factor();
    let base = Rgb::new(r, g, b);
    let (metallic, roughness) = (pbr.metallic_factor(), pbr.roughness_factor());
    for (what, v) in [
        ("baseColorFactor", base.min_element()),
        ("metallicFactor", metallic),
        ("roughnessFactor", roughness),
    ] {
        if !v.is_finite() || v < 0.0 {
            return Err(ConvertError::Factor(what));
        }
    }
    // KHR_materials_ior allows ior ≥ 1 and the special value 0, "the Fresnel term evaluates to
    // 1": ((0 − 1)/(0 + 1))² = 1 gives that F0. Anything else breaks the schema.
    let ior = mat.ior().unwrap_or(1.5);
    if !(ior == 0.0 || (ior.is_finite() && ior >= 1.0)) {
        return Err(ConvertError::Ior(ior));
    }
    let f0_ior = ((ior - 1.0) / (ior + 1.0)).powi(2);
    let f0 = match mat.specular() {
        Some(s) => {
            let [cr, cg, cb] = s.specular_color_factor();
            if s.specular_texture().is_some() || s.specular_color_texture().is_some() {
                notes.push("specular textures are not supported; the factors are used".into());
            }
            (Rgb::new(cr, cg, cb) * f0_ior).min(Rgb::ONE) * s.specular_factor()
        }
        None => Rgb::splat(f0_ior),
    };
    if !f0.is_finite() {
        return Err(ConvertError::Specular);
    }
    if base.max_element() > 1.0 {
        notes.push("baseColorFactor above 1 clamped to 1".into());
    }
    let ignored: Vec<&str> = [
        ("normalTexture", mat.normal_texture().is_some()),
        ("occlusionTexture", mat.occlusion_texture().is_some()),
    ]
    .iter()
    .filter(|t| t.1)
    .map(|t| t.0)
    .collect();
    if !ignored.is_empty() {
        notes.push(format!("not supported, ignored: {}", ignored.join(", ")));
    }
    let textured = textured_colours(&pbr, base, metallic, roughness, f0, images, &mut notes)?;
    let two_sided = mat.double_sided();
    let (material, textures, tex_coord) = match transmission(mat, base, roughness, ior, &mut notes)? {
        Some(glass) => (Material { name: name.to_string(), bsdf: glass, two_sided: true }, Vec::new(), None),
        None => match textured {
            Textured::Constant { kd, ks, exponent } => {
                (build(name, kd, ks, exponent, two_sided), Vec::new(), None)
            }
            Textured::Maps { kd, ks, exponent, tex_coord } => {
                let max = |c: &Colour| match c {
                    Colour::Constant(v) => *v,
                    Colour::Map(t) => t.max_value(),
                };
                let material = build(name, max(&kd), max(&ks), exponent, two_sided);
                let lambert = matches!(material.bsdf, Bsdf::Lambert(_));
                let mut textures = Vec::new();
                if let Colour::Map(t) = kd {
                    let slot = if lambert { ColourSlot::Reflectance } else { ColourSlot::DiffuseReflectance };
                    textures.push((slot, t));
                }
                if let (Colour::Map(t), false) = (ks, lambert) {
                    textures.push((ColourSlot::SpecularReflectance, t));
                }
                let tex_coord = (!textures.is_empty()).then_some(tex_coord);
                (material, textures, tex_coord)
            }
        },
    };
    if mat.alpha_mode() != ::gltf::material::AlphaMode::Opaque {
        notes.push(format!("alphaMode {:?} is not supported; the surface is opaque", mat.alpha_mode()));
    }

    let [er, eg, eb] = mat.emissive_factor();
    let strength = mat.emissive_strength().unwrap_or(1.0);
    let radiance = Rgb::new(er, eg, eb) * strength;
    check_emission(radiance).map_err(ConvertError::Emission)?;
    let emission = if radiance.max_element() <= 0.0 {
        None
    } else if mat.emissive_texture().is_some() {
        notes.push("emissiveTexture is not supported, and emissiveFactor only multiplies it: the material does not emit".into());
        None
    } else {
        Some(radiance)
    };
    Ok(Converted { material, emission, notes, textures, tex_coord })
}

/// A colour of the material: one value, or a texture.
enum Colour {
    Constant(Rgb),
    Map(Arc<Texture>),
}

/// The opaque material's parameters, with or without textures.
enum Textured {
    /// No texture: the mapping of the module docs on the factors.
    Constant { kd: Rgb, ks: Rgb, exponent: f32 },
    /// kd and ks per texel, read through `TEXCOORD_<tex_coord>`.
    Maps { kd: Colour, ks: Colour, exponent: f32, tex_coord: u32 },
}

/// The opaque part's kd, ks and exponent, with the base-colour and metallic-roughness textures
/// baked per texel (module docs).
fn textured_colours(
    pbr: &::gltf::material::PbrMetallicRoughness<'_>,
    base: Rgb,
    metallic: f32,
    roughness: f32,
    f0: Rgb,
    images: &mut Images<'_>,
    notes: &mut Vec<String>,
) -> Result<Textured, ConvertError> {
    let base_use = pbr.base_color_texture().map(|i| TextureUse::of(&i, notes, "baseColorTexture"));
    let mr_use =
        pbr.metallic_roughness_texture().map(|i| TextureUse::of(&i, notes, "metallicRoughnessTexture"));
    if base_use.is_none() && mr_use.is_none() {
        let (kd, ks, exponent) = metallic_roughness_to_phong(base, metallic, roughness, f0);
        return Ok(Textured::Constant { kd, ks, exponent });
    }
    // The metallic (blue) and roughness (green) channels, as a bitmap of their own.
    let mr = match &mr_use {
        Some(u) => {
            let image = images.get(u.image, true)?;
            let bitmap = Bitmap::new(
                image.width,
                image.height,
                image.texels.clone(),
                u.filter,
                u.wrap,
                UvTransform::IDENTITY,
            )
            .map_err(ConvertError::MetallicRoughnessTexture)?;
            Some((u.clone(), bitmap))
        }
        None => None,
    };
    let mean = |b: &Bitmap, channel: fn(Rgb) -> f32| {
        let t = b.texels();
        t.iter().map(|&c| channel(c) as f64).sum::<f64>() / t.len() as f64
    };
    let roughness = match &mr {
        Some((_, b)) => {
            notes.push("the roughness texture is averaged: Phong has one exponent per material".into());
            roughness * mean(b, |c| c.y) as f32
        }
        None => roughness,
    };
    // The texel grid the colours are baked on (the base colour's, else the metallic texture's),
    // with its base colours.
    let (carrier, grid_base, (w, h)) = match (&base_use, &mr) {
        (Some(u), _) => {
            let image = images.get(u.image, false)?;
            let size = (image.width, image.height);
            (u.clone(), Some(image), size)
        }
        (None, Some((u, b))) => (u.clone(), None, b.size()),
        (None, None) => unreachable!("one texture at least"),
    };
    // Metallic per texel of the grid, or the texture's mean where it cannot be.
    let per_texel_metallic = match &mr {
        Some((u, _)) if u.tex_coord != carrier.tex_coord || u.to_uv != carrier.to_uv => {
            notes.push("metallicRoughnessTexture reads other texture coordinates than baseColorTexture: its mean metallic is used".into());
            false
        }
        Some(_) => true,
        None => false,
    };
    let mean_metallic = mr.as_ref().map_or(1.0, |(_, b)| mean(b, |c| c.z) as f32) * metallic;
    let metallic_at = |k: usize| -> f32 {
        let (i, j) = (k % w, k / w);
        match &mr {
            Some((_, b)) if b.size() == (w, h) => b.texels()[k].z * metallic,
            Some((_, b)) => {
                b.eval(Vec2::new((i as f32 + 0.5) / w as f32, (j as f32 + 0.5) / h as f32)).z * metallic
            }
            None => metallic,
        }
    };
    let base_at = |k: usize| grid_base.as_ref().map_or(base, |img| img.texels[k] * base);
    let bake = |per_texel: bool| -> (Vec<Rgb>, Vec<Rgb>) {
        (0..w * h)
            .map(|k| {
                let m = if per_texel { metallic_at(k) } else { mean_metallic };
                let (kd, ks, _) = metallic_roughness_to_phong(base_at(k), m, roughness, f0);
                (kd, ks)
            })
            .unzip()
    };
    let max_of = |t: &[Rgb]| t.iter().fold(Rgb::ZERO, |a, &c| a.max(c));
    let (mut kd, mut ks) = bake(per_texel_metallic);
    if per_texel_metallic && (max_of(&kd) + max_of(&ks)).max_element() > 1.0 + 1e-5 {
        notes.push(
            "the metallic texture's kd and ks maxima sum above 1 (Phong's energy bound is checked at the maxima): its mean metallic is used".into(),
        );
        (kd, ks) = bake(false);
    }
    let colour = |texels: Vec<Rgb>| -> Result<Colour, ConvertError> {
        if texels.iter().all(|&c| c == texels[0]) {
            return Ok(Colour::Constant(texels[0]));
        }
        let bitmap = Bitmap::new(w, h, texels, carrier.filter, carrier.wrap, carrier.to_uv)
            .map_err(ConvertError::BaseColorTexture)?;
        Ok(Colour::Map(Arc::new(Texture::Bitmap(bitmap))))
    };
    Ok(Textured::Maps {
        kd: colour(kd)?,
        ks: colour(ks)?,
        exponent: phong_exponent(roughness),
        tex_coord: carrier.tex_coord,
    })
}

/// The glass of `KHR_materials_transmission`, if the material is one (module docs).
fn transmission(
    mat: &::gltf::Material<'_>,
    base: Rgb,
    roughness: f32,
    ior: f32,
    notes: &mut Vec<String>,
) -> Result<Option<Bsdf>, ConvertError> {
    let Some(t) = mat.transmission() else { return Ok(None) };
    let factor = t.transmission_factor();
    if !(factor.is_finite() && (0.0..=1.0).contains(&factor)) {
        return Err(ConvertError::TransmissionFactor(factor));
    }
    if t.transmission_texture().is_some() {
        notes.push("transmissionTexture is not supported; transmissionFactor is used".into());
    }
    if factor > 0.0 && factor < 1.0 {
        let used = if factor >= 0.5 { "glass" } else { "opaque" };
        notes.push(format!(
            "transmissionFactor {factor}: a mix of glass and the opaque surface is not supported; the surface is {used}"
        ));
    }
    if factor < 0.5 {
        return Ok(None);
    }
    // ior 0 (Fresnel term 1) would be a mirror; glass needs a real index.
    let ior = if ior >= 1.0 { ior } else { 1.5 };
    let tint = base.clamp(Rgb::ZERO, Rgb::ONE);
    let thickness = mat.volume().map_or(0.0, |v| v.thickness_factor());
    if mat.volume().is_some_and(|v| v.attenuation_distance().is_finite() || v.attenuation_color() != [1.0; 3])
    {
        notes.push("KHR_materials_volume attenuation is not supported; the glass is clear".into());
    }
    let err = ConvertError::Transmission;
    let r = roughness.clamp(0.0, 1.0);
    Ok(Some(if thickness <= 0.0 {
        if r > 0.0 {
            notes.push("a thin-walled glass (no KHR_materials_volume thickness) is smooth in Opticks: roughness ignored".into());
        }
        Bsdf::ThinDielectric(ThinDielectric::new(ior, 1.0, Rgb::ONE, tint).map_err(err)?)
    } else if r * r < 1e-4 || (ior - 1.0).abs() < 1e-3 {
        Bsdf::SmoothDielectric(SmoothDielectric::new(ior, 1.0, Rgb::ONE, tint).map_err(err)?)
    } else {
        Bsdf::RoughDielectric(RoughDielectric::new(ior, 1.0, r * r, Rgb::ONE, tint).map_err(err)?)
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponent_follows_roughness() {
        assert_eq!(phong_exponent(1.0), 0.0);
        assert_eq!(phong_exponent(0.0), ModifiedPhong::MAX_EXPONENT);
        // r = 0.5: α = 0.25, n = 2/0.0625 − 2 = 30.
        assert!((phong_exponent(0.5) - 30.0).abs() < 1e-4);
        assert!(phong_exponent(0.01) <= ModifiedPhong::MAX_EXPONENT);
    }

    #[test]
    fn dielectric_metal_and_pure_diffuse() {
        let b = Rgb::new(0.8, 0.4, 0.2);
        let (kd, ks, _) = metallic_roughness_to_phong(b, 0.0, 0.5, Rgb::splat(0.04));
        assert!((kd - b * 0.96).abs().max_element() < 1e-6 && ks == Rgb::splat(0.04));
        let (kd, ks, _) = metallic_roughness_to_phong(b, 1.0, 0.5, Rgb::splat(0.04));
        assert_eq!((kd, ks), (Rgb::ZERO, b));
        let (kd, ks, _) = metallic_roughness_to_phong(b, 0.0, 1.0, Rgb::ZERO);
        assert_eq!((kd, ks), (b, Rgb::ZERO));
        // Energy is conserved for every combination.
        for m in [0.0, 0.3, 0.7, 1.0] {
            for f in [0.0, 0.04, 0.5, 1.0] {
                let (kd, ks, _) = metallic_roughness_to_phong(Rgb::ONE, m, 0.2, Rgb::splat(f));
                assert!((kd + ks).max_element() <= 1.0 + 1e-6, "m {m} f0 {f}");
            }
        }
    }
}
