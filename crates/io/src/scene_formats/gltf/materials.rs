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
//! than in a glTF viewer. `doubleSided` → [`Material::two_sided`]. Textures (base colour,
//! metallic-roughness, normal, occlusion) are ignored with a warning (factors are used),
//! `alphaMode` other than `OPAQUE` and transmission are ignored with a warning.
//!
//! Emission: `emissiveFactor × KHR_materials_emissive_strength` (strength 1 if absent) is taken as
//! the radiance in **W/(m²·sr)**. glTF defines emission in relative, display-referred units
//! ("nits-like", no absolute scale); Opticks needs a physical one, and identity is the only
//! assumption that needs no exposure constant. An `emissiveTexture` makes the factor a multiplier
//! of a texture Opticks cannot read: the material then does not emit (warning), as in the OBJ
//! loader with `map_Ke`. Emission is one-sided (front, counter-clockwise face), even for
//! `doubleSided` materials.

use opticks_core::bsdf::{Bsdf, Lambert, Material, MaterialError, ModifiedPhong};
use opticks_core::light::check::check_emission;
use opticks_core::math::Rgb;

/// Largest Phong exponent produced (the core's limit).
const MAX_EXPONENT: f32 = ModifiedPhong::MAX_EXPONENT;

/// A converted glTF material.
#[derive(Clone, Debug, PartialEq)]
pub struct Converted {
    /// The core material.
    pub material: Material,
    /// Emitted radiance, W/(m²·sr), if any.
    pub emission: Option<Rgb>,
    /// Things ignored (messages without location; the caller adds it).
    pub notes: Vec<String>,
}

/// Phong exponent for a glTF roughness: α = r², n = 2/α² − 2, clamped to [0, 10⁶].
pub fn phong_exponent(roughness: f32) -> f32 {
    let r = roughness.clamp(0.0, 1.0);
    let a2 = (r * r) * (r * r);
    if a2 <= 2.0 / (MAX_EXPONENT + 2.0) { MAX_EXPONENT } else { (2.0 / a2 - 2.0).clamp(0.0, MAX_EXPONENT) }
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
    Converted { material: build("default", kd, ks, n, false), emission: None, notes: Vec::new() }
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

/// Converts one glTF material (see the module docs). Errors are messages for non-finite or
/// negative values.
pub fn convert(mat: &::gltf::Material<'_>, name: &str) -> Result<Converted, String> {
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
            return Err(format!("{what} must be finite and non-negative"));
        }
    }
    // KHR_materials_ior allows ior ≥ 1 and the special value 0, "the Fresnel term evaluates to
    // 1": ((0 − 1)/(0 + 1))² = 1 gives that F0. Anything else breaks the schema.
    let ior = mat.ior().unwrap_or(1.5);
    if !(ior == 0.0 || (ior.is_finite() && ior >= 1.0)) {
        return Err(format!(
            "KHR_materials_ior: ior {ior} is invalid (the extension allows a finite value ≥ 1, or 0 for a Fresnel term of 1)"
        ));
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
        return Err("KHR_materials_specular factors must be finite".into());
    }
    let (kd, ks, n) = metallic_roughness_to_phong(base, metallic, roughness, f0);
    if base.max_element() > 1.0 {
        notes.push("baseColorFactor above 1 clamped to 1".into());
    }
    let textures = [
        ("baseColorTexture", pbr.base_color_texture().is_some()),
        ("metallicRoughnessTexture", pbr.metallic_roughness_texture().is_some()),
        ("normalTexture", mat.normal_texture().is_some()),
        ("occlusionTexture", mat.occlusion_texture().is_some()),
    ];
    let ignored: Vec<&str> = textures.iter().filter(|t| t.1).map(|t| t.0).collect();
    if !ignored.is_empty() {
        notes.push(format!("textures are not supported, the factors are used ({})", ignored.join(", ")));
    }
    if mat.alpha_mode() != ::gltf::material::AlphaMode::Opaque {
        notes.push(format!("alphaMode {:?} is not supported; the surface is opaque", mat.alpha_mode()));
    }

    let [er, eg, eb] = mat.emissive_factor();
    let strength = mat.emissive_strength().unwrap_or(1.0);
    let radiance = Rgb::new(er, eg, eb) * strength;
    check_emission(radiance).map_err(|e| format!("emissiveFactor × emissiveStrength: {e}"))?;
    let emission = if radiance.max_element() <= 0.0 {
        None
    } else if mat.emissive_texture().is_some() {
        notes.push("emissiveTexture is not supported, and emissiveFactor only multiplies it: the material does not emit".into());
        None
    } else {
        Some(radiance)
    };
    Ok(Converted { material: build(name, kd, ks, n, mat.double_sided()), emission, notes })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponent_follows_roughness() {
        assert_eq!(phong_exponent(1.0), 0.0);
        assert_eq!(phong_exponent(0.0), MAX_EXPONENT);
        // r = 0.5: α = 0.25, n = 2/0.0625 − 2 = 30.
        assert!((phong_exponent(0.5) - 30.0).abs() < 1e-4);
        assert!(phong_exponent(0.01) <= MAX_EXPONENT);
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
