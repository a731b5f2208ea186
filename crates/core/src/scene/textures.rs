//! The texture stage of [`super::Scene::build`]: each [`TextureBinding`] of the description is
//! checked against its material (the material exists, has that parameter, and every value the
//! texture takes is one the parameter accepts — a reflectance in [0, 1], a roughness in
//! [0, 1] (raised to [`MIN_TEXTURED_ALPHA`] as Mitsuba does), a weight of `principled` in
//! [0, 1], Phong's kd + ks ≤ 1 at the
//! textures' maxima; a mesh attribute's values are those of every mesh of the material, which
//! must all have it) and gathered per material, for [`super::Scene::material_at`]. The slots
//! that shape the surface instead of the BSDF ([`ColourSlot::shapes_surface`]) are checked
//! here too, so that [`super::Scene::normals_at`] need not: a normal or bump map is a bitmap
//! (only a bitmap has directions to read or a bilinear gradient to take), a bump's scale a
//! finite constant beside its map, and a surface has at most one map ([`ShadingMap`]).

use super::attributes::AttributeTable;
use super::{SceneDescription, SceneError};
use crate::bsdf::{Bsdf, MAX_ALPHA, Material, ModifiedPhong, check_unit_colour};
use crate::math::{Rgb, Vec2};
use crate::texture::{
    ColourSlot, MIN_TEXTURED_ALPHA, PrincipledWeight, Texture, set_colour, set_principled, set_roughness,
    set_weight,
};
use std::sync::Arc;

/// A texture bound to a parameter of a material, ready to evaluate.
#[derive(Clone, Debug)]
pub(super) struct Bound {
    /// The parameter it replaces.
    pub slot: ColourSlot,
    /// The texture.
    pub texture: Arc<Texture>,
    /// For a mesh attribute texture: its table in the scene's attributes (`None` if no
    /// triangle of the material has one: every such mesh was empty).
    pub attribute: Option<usize>,
}

/// Per material, the textures in place of its parameters (empty for an untextured material).
pub(super) type MaterialTextures = Vec<Vec<Bound>>;

/// Why a mesh attribute cannot feed a texture of a material: one of its meshes lacks it, or
/// has the wrong channel count for the parameter.
#[derive(Debug, thiserror::Error)]
enum AttributeError {
    /// A mesh of the material has no attribute of that name.
    #[error("mesh '{mesh}' ({at}) has no attribute \"{name}\"")]
    Missing { mesh: String, at: super::Source, name: String },
    /// A roughness texture's attribute has more than one channel.
    #[error("attribute \"{name}\" of mesh '{mesh}' has {channels} channels; a roughness needs one")]
    NotSingle { name: String, mesh: String, channels: u8 },
}

/// The smallest and largest value (per channel) of mesh attribute `name` times `scale` over the
/// meshes of material `material`, each of which must have it (with one channel if `single`).
fn attribute_range(
    desc: &SceneDescription,
    material: usize,
    name: &str,
    scale: f32,
    single: bool,
) -> Result<(Rgb, Rgb), AttributeError> {
    let (mut lo, mut hi) = (Rgb::splat(f32::INFINITY), Rgb::splat(f32::NEG_INFINITY));
    for mesh in desc.meshes.iter().filter(|m| m.material == material) {
        let Some(a) = mesh.attributes.iter().find(|a| a.name == name) else {
            let (mesh, at) = (mesh.name.clone(), mesh.source.clone());
            return Err(AttributeError::Missing { mesh, at, name: name.into() });
        };
        if single && a.channels != 1 {
            let (name, mesh) = (name.into(), mesh.name.clone());
            return Err(AttributeError::NotSingle { name, mesh, channels: a.channels });
        }
        for v in &a.values {
            lo = lo.min(*v * scale);
            hi = hi.max(*v * scale);
        }
    }
    Ok((lo.min(hi), hi.max(lo)))
}

/// The description's textures, checked and gathered per material (`tables`: the flattened
/// meshes' attributes).
pub(super) fn bind(
    desc: &SceneDescription,
    tables: &[AttributeTable],
) -> Result<MaterialTextures, SceneError> {
    let mut out: MaterialTextures = vec![Vec::new(); desc.materials.len()];
    // Per binding, the largest value of each channel (for Phong's joint bound below).
    let mut maxima = vec![Rgb::ZERO; desc.textures.len()];
    for (k, b) in desc.textures.iter().enumerate() {
        let bad = |material: String, message: String| SceneError::BadTexture {
            material,
            slot: b.slot.name(),
            message,
        };
        let Some(m) = desc.materials.get(b.material) else {
            return Err(bad(
                format!("#{}", b.material),
                format!("no such material (the scene has {})", desc.materials.len()),
            ));
        };
        let range = match &*b.texture {
            Texture::MeshAttribute(a) => {
                let (lo, hi) = attribute_range(desc, b.material, &a.name, a.scale, !b.slot.is_colour())
                    .map_err(|e| bad(m.name.clone(), e.to_string()))?;
                (lo, hi)
            }
            t if b.slot.is_colour() => (Rgb::ZERO, t.max_value()),
            t => {
                let (lo, hi) = t.range_1();
                (Rgb::splat(lo), Rgb::splat(hi))
            }
        };
        let (lo, hi) = range;
        if b.slot.shapes_surface() {
            check_shading_map(b.slot, &b.texture).map_err(|e| bad(m.name.clone(), e.into()))?;
        } else if matches!(b.slot, ColourSlot::Opacity | ColourSlot::Weight) {
            if !(lo.x >= 0.0 && hi.x <= 1.0) {
                return Err(bad(
                    m.name.clone(),
                    format!("the texture's values {}..{} are not in [0, 1]", lo.x, hi.x),
                ));
            }
            if b.slot == ColourSlot::Weight && !set_weight(&mut m.bsdf.clone(), hi.x) {
                return Err(bad(m.name.clone(), "this material is not a blend".into()));
            }
        } else if let ColourSlot::Principled(w) = b.slot {
            if !(lo.x >= 0.0 && hi.x <= w.max()) {
                return Err(bad(
                    m.name.clone(),
                    format!("the texture's values {}..{} are not in [0, {}]", lo.x, hi.x, w.max()),
                ));
            }
            if !set_principled(&mut m.bsdf.clone(), w, hi.x) {
                return Err(bad(
                    m.name.clone(),
                    format!("this material is not a principled BSDF with a {} parameter", w.name()),
                ));
            }
        } else if b.slot.is_colour() {
            if lo.min_element() < 0.0 {
                return Err(bad(m.name.clone(), format!("the texture's smallest value {lo} is negative")));
            }
            check_unit_colour(b.slot.name(), hi)
                .map_err(|e| bad(m.name.clone(), format!("the texture's largest value {hi}: {e}")))?;
            if !set_colour(&mut m.bsdf.clone(), b.slot, hi) {
                return Err(bad(m.name.clone(), "this material has no such colour parameter".into()));
            }
        } else {
            if !(lo.x >= 0.0 && hi.x <= MAX_ALPHA) {
                return Err(bad(
                    m.name.clone(),
                    format!(
                        "the texture's values {}..{} are not a roughness in [0, {MAX_ALPHA}]",
                        lo.x, hi.x
                    ),
                ));
            }
            if !set_roughness(&mut m.bsdf.clone(), b.slot, hi.x) {
                return Err(bad(m.name.clone(), "this material has no such roughness".into()));
            }
        }
        maxima[k] = hi;
        let list = &mut out[b.material];
        if list.iter().any(|x| x.slot == b.slot) {
            return Err(bad(m.name.clone(), "the parameter has two textures".into()));
        }
        let map = |s: ColourSlot| matches!(s, ColourSlot::NormalMap | ColourSlot::BumpMap);
        if map(b.slot) && list.iter().any(|x| map(x.slot)) {
            return Err(bad(m.name.clone(), "a surface takes one normal or bump map".into()));
        }
        let isotropic = |s: ColourSlot| s == ColourSlot::Alpha;
        let roughness =
            |s: ColourSlot| matches!(s, ColourSlot::Alpha | ColourSlot::AlphaU | ColourSlot::AlphaV);
        if roughness(b.slot)
            && list.iter().any(|x| roughness(x.slot) && isotropic(x.slot) != isotropic(b.slot))
        {
            return Err(bad(m.name.clone(), "alpha and alpha_u/alpha_v cannot both be textured".into()));
        }
        let attribute = match &*b.texture {
            Texture::MeshAttribute(a) => tables.iter().position(|t| t.name == a.name),
            _ => None,
        };
        list.push(Bound { slot: b.slot, texture: b.texture.clone(), attribute });
    }
    for (m, list) in desc.materials.iter().zip(&out) {
        let has = |slot| list.iter().any(|b| b.slot == slot);
        if has(ColourSlot::BumpScale) && !has(ColourSlot::BumpMap) {
            return Err(SceneError::BadTexture {
                material: m.name.clone(),
                slot: ColourSlot::BumpScale.name(),
                message: "a bump map's scale without its bump map".into(),
            });
        }
    }
    // Phong's energy bound holds at every point if it holds for the channels' maxima.
    for (i, (m, list)) in desc.materials.iter().zip(&out).enumerate() {
        if let Bsdf::ModifiedPhong(p) = &m.bsdf
            && !list.is_empty()
        {
            let mut at_max = Bsdf::ModifiedPhong(p.clone());
            for (b, max) in desc.textures.iter().zip(&maxima).filter(|(b, _)| b.material == i) {
                set_colour(&mut at_max, b.slot, *max);
            }
            if let Bsdf::ModifiedPhong(q) = at_max {
                ModifiedPhong::new(q.kd, q.ks, q.exponent).map_err(|e| SceneError::BadTexture {
                    material: m.name.clone(),
                    slot: list[0].slot.name(),
                    message: format!("at the textures' largest values: {e}"),
                })?;
            }
        }
    }
    Ok(out)
}

/// Per material, the index in its list of its [`ColourSlot::Opacity`] texture (a masked
/// surface, Mitsuba's `mask`), if it has one.
pub(super) fn opacities(textures: &MaterialTextures) -> Vec<Option<u8>> {
    textures
        .iter()
        .map(|list| list.iter().position(|b| b.slot == ColourSlot::Opacity).map(|k| k as u8))
        .collect()
}

/// What perturbs a material's shading normal: its texture's index in the material's list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum ShadingMap {
    /// A [`ColourSlot::NormalMap`].
    Normal(u8),
    /// A [`ColourSlot::BumpMap`] and its scale (the [`ColourSlot::BumpScale`], else 1).
    Bump(u8, f32),
}

/// Why a texture cannot be in a [`ColourSlot::shapes_surface`] slot.
fn check_shading_map(slot: ColourSlot, texture: &Texture) -> Result<(), &'static str> {
    match (slot, texture) {
        // A normal map's colours are directions (2c − 1, normalised where used) and a bump
        // map's gradient is its bilinear interpolation's: only a bitmap has either.
        (ColourSlot::NormalMap, Texture::Bitmap(_)) | (ColourSlot::BumpMap, Texture::Bitmap(_)) => Ok(()),
        (ColourSlot::NormalMap, _) => Err("a normal map must be a bitmap"),
        (ColourSlot::BumpMap, _) => Err("a bump map must be a bitmap"),
        (_, Texture::Constant(v)) if v.is_finite() => Ok(()),
        _ => Err("a bump map's scale must be a finite constant"),
    }
}

/// Per material, whether its BSDF depends on the azimuth about the normal: anisotropic as
/// given (`Bsdf::is_anisotropic`), or given a texture on a parameter that can make it so
/// (`alpha_u`, `alpha_v`, a principled BSDF's `anisotropic`). Its frame then follows ∂p/∂u.
pub(super) fn anisotropic(materials: &[Material], textures: &MaterialTextures) -> Vec<bool> {
    let oriented = |slot: ColourSlot| {
        matches!(
            slot,
            ColourSlot::AlphaU | ColourSlot::AlphaV | ColourSlot::Principled(PrincipledWeight::Anisotropic)
        )
    };
    (materials.iter().zip(textures))
        .map(|(m, t)| m.bsdf.is_anisotropic() || t.iter().any(|b| oriented(b.slot)))
        .collect()
}

/// Per material, its [`ShadingMap`], if it has one (at most one: [`bind`] checks).
pub(super) fn shading_maps(textures: &MaterialTextures) -> Vec<Option<ShadingMap>> {
    textures
        .iter()
        .map(|list| {
            let at = |slot| list.iter().position(|b| b.slot == slot).map(|k| k as u8);
            let scale = at(ColourSlot::BumpScale)
                .map_or(1.0, |k| list[k as usize].texture.eval_1(Vec2::ZERO, Rgb::ZERO));
            at(ColourSlot::NormalMap)
                .map(ShadingMap::Normal)
                .or(at(ColourSlot::BumpMap).map(|k| ShadingMap::Bump(k, scale)))
        })
        .collect()
}

/// The opacity of `bound` (an [`opacities`] entry) at triangle `prim`'s point of barycentrics
/// (b1, b2) and texture coordinates `uv`, in [0, 1].
#[inline]
pub(super) fn opacity_at(
    bound: &Bound,
    tables: &[AttributeTable],
    prim: u32,
    (b1, b2): (f32, f32),
    uv: Vec2,
) -> f32 {
    let attribute = bound.attribute.map_or(Rgb::ZERO, |k| tables[k].at(prim, b1, b2));
    bound.texture.eval_1(uv, attribute).clamp(0.0, 1.0)
}

/// `material` with its textured parameters evaluated at triangle `prim`'s point of barycentrics
/// (b1, b2) and texture coordinates `uv` (a copy without a name: nothing allocated).
#[inline]
pub(super) fn resolve(
    material: &Material,
    textures: &[Bound],
    tables: &[AttributeTable],
    prim: u32,
    (b1, b2): (f32, f32),
    uv: Vec2,
) -> Material {
    let mut bsdf = material.bsdf.clone();
    for b in textures.iter().filter(|b| b.slot.is_bsdf_parameter()) {
        let attribute = b.attribute.map_or(Rgb::ZERO, |k| tables[k].at(prim, b1, b2));
        if b.slot.is_colour() {
            set_colour(&mut bsdf, b.slot, b.texture.eval(uv, attribute));
        } else if b.slot == ColourSlot::Weight {
            set_weight(&mut bsdf, b.texture.eval_1(uv, attribute).clamp(0.0, 1.0));
        } else if let ColourSlot::Principled(w) = b.slot {
            set_principled(&mut bsdf, w, b.texture.eval_1(uv, attribute).clamp(0.0, w.max()));
        } else {
            let alpha = b.texture.eval_1(uv, attribute).clamp(MIN_TEXTURED_ALPHA, MAX_ALPHA);
            set_roughness(&mut bsdf, b.slot, alpha);
        }
    }
    Material { name: String::new(), bsdf, two_sided: material.two_sided }
}

#[cfg(test)]
mod tests {
    use super::super::{Scene, cornell_box};
    use super::*;
    use crate::bsdf::{Lambert, Plastic, RoughConductor};
    use crate::math::{Rgb, Vec2, Vec3};
    use crate::sampling::microfacet::{Distribution, Microfacet};
    use crate::scene::MeshAttribute;
    use crate::texture::{Checkerboard, MeshAttributeTexture, TextureBinding, UvTransform};

    fn checker(a: f32, b: f32) -> Arc<Texture> {
        Arc::new(Texture::Checkerboard(
            Checkerboard::new(Rgb::splat(a), Rgb::splat(b), UvTransform::IDENTITY).unwrap(),
        ))
    }

    /// The Cornell box with its floor's triangles given UVs, the red wall without, and the
    /// white material textured.
    fn textured_box(texture: Arc<Texture>) -> crate::scene::SceneDescription {
        let mut d = cornell_box();
        let white = &mut d.meshes[0];
        // UV = (x, z) mapped from [-1, 1]² to [0, 1]² for every white vertex.
        white.uvs = white.positions.iter().map(|p| Vec2::new((p.x + 1.0) / 2.0, (p.z + 1.0) / 2.0)).collect();
        d.textures.push(TextureBinding { material: 0, slot: ColourSlot::Reflectance, texture });
        d
    }

    #[test]
    fn untextured_materials_are_borrowed_and_textured_ones_evaluated_at_the_uv() {
        let plain = Scene::build(&cornell_box()).unwrap();
        assert!(!plain.has_textures());
        let mut slot = None;
        let m = plain.material_at(0, Vec3::new(0.1, -1.0, 0.2), &mut slot);
        assert!(std::ptr::eq(m, &plain.materials[0]));
        assert!(slot.is_none(), "an untextured material is not copied");
        let scene = Scene::build(&textured_box(checker(0.8, 0.1))).unwrap();
        assert!(scene.has_textures());
        // Floor triangle 0: its UV is the interpolation of its vertices' (x, z) → [0, 1]².
        let p = Vec3::new(-0.5, -1.0, -0.5);
        let uv = scene.uv_at(0, p);
        assert!((uv - Vec2::new(0.25, 0.25)).length() < 1e-6, "{uv}");
        assert_eq!(
            scene.material_at(0, p, &mut None).bsdf,
            Bsdf::Lambert(Lambert::new(Rgb::splat(0.8)).unwrap())
        );
        let q = Vec3::new(0.5, -1.0, -0.5); // uv (0.75, 0.25): the other colour
        assert_eq!(
            scene.material_at(0, q, &mut None).bsdf,
            Bsdf::Lambert(Lambert::new(Rgb::splat(0.1)).unwrap())
        );
        // The red wall (no UVs, untextured material) is borrowed; its UV is the barycentrics.
        let red = (0..scene.triangles.len() as u32).find(|&t| scene.material(t).name == "red").unwrap();
        let tri = scene.triangles[red as usize];
        let c = tri.point(0.2, 0.3);
        assert!((scene.uv_at(red, c) - Vec2::new(0.2, 0.3)).length() < 1e-5);
        assert!(std::ptr::eq(scene.material_at(red, c, &mut None), &scene.materials[1]));
    }

    /// The Cornell box whose white material (floor UV (x, z) → [0, 1]²: dp/du = +x, t = n × s =
    /// −z on the floor of normal +y) has a one-texel normal map of colour `c`.
    fn normal_mapped_box(c: Rgb) -> (Scene, Scene) {
        let bitmap = crate::texture::Bitmap::new(
            1,
            1,
            vec![c],
            crate::texture::FilterType::Bilinear,
            crate::texture::WrapMode::Repeat,
            UvTransform::IDENTITY,
        )
        .unwrap();
        let mut d = textured_box(checker(0.5, 0.5));
        d.textures[0] = TextureBinding {
            material: 0,
            slot: ColourSlot::NormalMap,
            texture: Arc::new(Texture::Bitmap(bitmap)),
        };
        let mut plain = d.clone();
        plain.textures.clear();
        (Scene::build(&d).unwrap(), Scene::build(&plain).unwrap())
    }

    /// A flat normal map ((0.5, 0.5, 1): the normal (0, 0, 1)) changes nothing, bit for bit:
    /// normals, the material and so every BSDF value and sample.
    #[test]
    fn a_flat_normal_map_changes_nothing() {
        let (mapped, plain) = normal_mapped_box(Rgb::new(0.5, 0.5, 1.0));
        for prim in 0..mapped.triangles.len() as u32 {
            for (b1, b2) in [(0.1, 0.1), (0.3, 0.5), (0.7, 0.2)] {
                let p = mapped.triangles[prim as usize].point(b1, b2);
                assert_eq!(mapped.normals_at(prim, p), plain.normals_at(prim, p), "triangle {prim}");
                assert_eq!(mapped.material_at(prim, p, &mut None), plain.material_at(prim, p, &mut None));
            }
        }
    }

    /// A tilted normal map tilts the shading normal in the frame (dp/du, n × dp/du, n), and the
    /// geometric normal stays.
    #[test]
    fn a_tilted_normal_map_tilts_the_shading_normal_in_the_uv_frame() {
        let (a, b) = (0.4f32.sin(), 0.4f32.cos());
        let (mapped, _) = normal_mapped_box((Rgb::new(a, 0.3, b) + 1.0) / 2.0);
        let floor = (0..mapped.triangles.len() as u32)
            .find(|&t| mapped.normal(t).y > 0.9 && mapped.material(t).name == "white")
            .unwrap();
        let p = mapped.triangles[floor as usize].point(0.2, 0.3);
        let n = mapped.normals_at(floor, p);
        assert_eq!(n.geometric, mapped.normal(floor));
        let want = Vec3::new(a, b, -0.3).normalize();
        assert!((n.shading - want).length() < 1e-5, "{} vs {want}", n.shading);
    }

    /// Only a bitmap can be a normal map.
    #[test]
    fn a_normal_map_must_be_a_bitmap() {
        let mut d = textured_box(checker(0.5, 0.5));
        d.textures[0].slot = ColourSlot::NormalMap;
        let e = Scene::build(&d).unwrap_err().to_string();
        assert!(e.contains("must be a bitmap"), "{e}");
    }

    /// The Cornell box whose white material (floor UV (x, z) → [0, 1]²: dp/du = (2, 0, 0), dp/dv
    /// = (0, 0, 2)) is bump-mapped by a 4 × 1 grey ramp 0, ¼, ½, ¾ (clamped) at `scale`, and the
    /// same box without it.
    fn bump_mapped_box(scale: f32) -> (Scene, Scene) {
        let mut d = textured_box(checker(0.5, 0.5));
        let bind = |slot, texture| TextureBinding { material: 0, slot, texture: Arc::new(texture) };
        d.textures[0] = bind(ColourSlot::BumpMap, ramp());
        d.textures.push(bind(ColourSlot::BumpScale, Texture::Constant(scale)));
        let mut plain = d.clone();
        plain.textures.clear();
        (Scene::build(&d).unwrap(), Scene::build(&plain).unwrap())
    }

    /// A 4 × 1 grey ramp 0, ¼, ½, ¾, clamped.
    fn ramp() -> Texture {
        let texels = (0..4).map(|i| Rgb::splat(0.25 * i as f32)).collect();
        let (filter, wrap) = (crate::texture::FilterType::Bilinear, crate::texture::WrapMode::Clamp);
        Texture::Bitmap(
            crate::texture::Bitmap::new(4, 1, texels, filter, wrap, UvTransform::IDENTITY).unwrap(),
        )
    }

    /// A bump map of scale 0 is the nested BSDF alone, bit for bit (normals and material); a
    /// scale tilts the floor's normal to normalize(dp/du' × dp/dv') on the geometric side:
    /// ∝ (−g_u/2, 1, −g_v/2) for the floor's tangents, g the height's gradient times the scale
    /// (¼ per texel, 4 texels: 1 per unit of u between the texel centres, 0 beyond them).
    #[test]
    fn a_bump_map_tilts_the_normal_down_its_gradient_and_scale_0_changes_nothing() {
        let (flat, plain) = bump_mapped_box(0.0);
        let (bumped, _) = bump_mapped_box(0.5);
        let mut tilted = 0;
        for prim in 0..flat.triangles.len() as u32 {
            for (b1, b2) in [(0.1, 0.1), (0.3, 0.5), (0.7, 0.2), (0.2, 0.6)] {
                let p = flat.triangles[prim as usize].point(b1, b2);
                assert_eq!(flat.normals_at(prim, p), plain.normals_at(prim, p), "triangle {prim}");
                assert_eq!(flat.material_at(prim, p, &mut None), plain.material_at(prim, p, &mut None));
                if bumped.normal(prim).y < 0.9 || bumped.material(prim).name != "white" {
                    continue;
                }
                let u = bumped.uv_at(prim, p).x;
                let g = if (0.125..0.875).contains(&u) { 0.5 } else { 0.0 };
                let want = Vec3::new(-g / 2.0, 1.0, 0.0).normalize();
                let n = bumped.normals_at(prim, p);
                assert!((n.shading - want).length() < 1e-5, "u {u}: {} vs {want}", n.shading);
                assert_eq!(n.geometric, bumped.normal(prim));
                tilted += usize::from(g > 0.0);
            }
        }
        assert!(tilted > 0, "some points must lie on the ramp");
    }

    /// A bump map must be a bitmap with a finite scale, its scale needs it, and a surface takes
    /// one normal or bump map.
    #[test]
    fn bad_bump_maps_are_refused() {
        let refused = |d: &crate::scene::SceneDescription| Scene::build(d).unwrap_err().to_string();
        let mut d = textured_box(checker(0.5, 0.5));
        d.textures[0].slot = ColourSlot::BumpMap;
        assert!(refused(&d).contains("a bump map must be a bitmap"), "{}", refused(&d));
        d.textures[0] = TextureBinding {
            material: 0,
            slot: ColourSlot::BumpScale,
            texture: Arc::new(Texture::Constant(2.0)),
        };
        assert!(refused(&d).contains("scale without its bump map"), "{}", refused(&d));
        d.textures[0].texture = Arc::new(Texture::Constant(f32::NAN));
        assert!(refused(&d).contains("finite"), "{}", refused(&d));
        d.textures[0] = TextureBinding { material: 0, slot: ColourSlot::BumpMap, texture: Arc::new(ramp()) };
        d.textures.push(TextureBinding { slot: ColourSlot::NormalMap, ..d.textures[0].clone() });
        assert!(refused(&d).contains("one normal or bump map"), "{}", refused(&d));
    }

    #[test]
    fn a_plastic_resolved_at_a_point_is_the_plastic_of_that_colour() {
        let mut d = cornell_box();
        d.materials[0].bsdf =
            Bsdf::Plastic(Plastic::new(Rgb::splat(0.8), Rgb::ONE, 1.49, 1.0, false).unwrap());
        d.textures.push(TextureBinding {
            material: 0,
            slot: ColourSlot::DiffuseReflectance,
            texture: checker(0.8, 0.2),
        });
        let scene = Scene::build(&d).unwrap();
        let mut slot = None;
        let m = scene.material_at(0, scene.triangles[0].point(0.1, 0.1), &mut slot); // barycentric uv (0.1, 0.1)
        assert_eq!(m.bsdf, Bsdf::Plastic(Plastic::new(Rgb::splat(0.8), Rgb::ONE, 1.49, 1.0, false).unwrap()));
        let mut slot = None;
        let m = scene.material_at(0, scene.triangles[0].point(0.6, 0.1), &mut slot);
        assert_eq!(m.bsdf, Bsdf::Plastic(Plastic::new(Rgb::splat(0.2), Rgb::ONE, 1.49, 1.0, false).unwrap()));
    }

    #[test]
    fn impossible_bindings_are_refused() {
        let bad = |d: crate::scene::SceneDescription| match Scene::build(&d) {
            Err(SceneError::BadTexture { message, .. }) => message,
            other => panic!("{other:?}"),
        };
        let mut d = textured_box(checker(0.5, 0.5));
        d.textures[0].material = 7;
        assert!(bad(d).contains("no such material"));
        let mut d = textured_box(checker(0.5, 0.5));
        d.textures[0].slot = ColourSlot::SpecularTransmittance;
        assert!(bad(d).contains("no such colour"));
        assert!(bad(textured_box(checker(1.5, 0.5))).contains("exceeds 1"));
        let mut d = textured_box(checker(0.5, 0.5));
        d.textures.push(d.textures[0].clone());
        assert!(bad(d).contains("two textures"));
        // Phong: kd + ks ≤ 1 at the textures' maxima.
        let mut d = textured_box(checker(0.8, 0.1));
        d.materials[0].bsdf =
            Bsdf::ModifiedPhong(ModifiedPhong::new(Rgb::splat(0.2), Rgb::splat(0.3), 10.0).unwrap());
        d.textures[0].slot = ColourSlot::DiffuseReflectance;
        assert!(bad(d).contains("kd + ks"));
    }

    /// A principled weight's texture sets that weight at the point (its `eval_1`), and its
    /// base colour the colour; values outside [0, 1] and a weight on another BSDF are refused.
    #[test]
    fn principled_weights_and_base_colour_are_set_at_the_point() {
        use crate::bsdf::Principled;
        use crate::texture::PrincipledWeight;
        let principled = |d: &mut crate::scene::SceneDescription| {
            d.materials[0].bsdf = Bsdf::Principled(Principled::default());
        };
        let (a, b) = (Vec3::new(-0.5, -1.0, -0.5), Vec3::new(0.5, -1.0, -0.5)); // uv (¼, ¼), (¾, ¼)
        let of = |scene: &Scene, p: Vec3| match &scene.material_at(0, p, &mut None).bsdf {
            Bsdf::Principled(q) => q.clone(),
            other => panic!("{other:?}"),
        };
        let mut d = textured_box(checker(0.9, 0.2));
        principled(&mut d);
        d.textures[0].slot = ColourSlot::Principled(PrincipledWeight::Metallic);
        d.textures.push(TextureBinding {
            material: 0,
            slot: ColourSlot::BaseColor,
            texture: checker(0.3, 0.7),
        });
        let scene = Scene::build(&d).unwrap();
        let (pa, pb) = (of(&scene, a), of(&scene, b));
        // eval_1 of a grey checkerboard: the mean of its channels, squares swapped (Mitsuba's).
        assert!((pa.metallic - 0.2).abs() < 1e-6 && (pb.metallic - 0.9).abs() < 1e-6);
        // eval (a colour) has the squares the other way round: Mitsuba's.
        assert_eq!((pa.base_color, pb.base_color), (Rgb::splat(0.3), Rgb::splat(0.7)));
        assert_eq!(pa.roughness, Principled::default().roughness, "the others keep their value");
        let refused = |d: &crate::scene::SceneDescription| Scene::build(d).unwrap_err().to_string();
        let mut d = textured_box(checker(1.5, 0.2));
        principled(&mut d);
        d.textures[0].slot = ColourSlot::Principled(PrincipledWeight::Sheen);
        assert!(refused(&d).contains("not in [0, 1]"), "{}", refused(&d));
        let mut d = textured_box(checker(0.5, 0.2));
        d.textures[0].slot = ColourSlot::Principled(PrincipledWeight::Clearcoat);
        assert!(refused(&d).contains("not a principled BSDF"), "{}", refused(&d));
    }

    #[test]
    fn fingerprints_change_with_textures_and_uvs_only_where_textured() {
        let plain = Scene::build(&cornell_box()).unwrap().fingerprint;
        // UVs on an untextured mesh change nothing (old datasets keep matching).
        let mut d = cornell_box();
        d.meshes[1].uvs = vec![Vec2::splat(0.3); d.meshes[1].positions.len()];
        assert_eq!(Scene::build(&d).unwrap().fingerprint, plain);
        let a = Scene::build(&textured_box(checker(0.8, 0.1))).unwrap().fingerprint;
        let b = Scene::build(&textured_box(checker(0.8, 0.2))).unwrap().fingerprint;
        assert_ne!(a.geometry, plain.geometry);
        assert_ne!(a.geometry, b.geometry);
        let mut moved = textured_box(checker(0.8, 0.1));
        moved.meshes[0].uvs[0].x += 0.25;
        assert_ne!(Scene::build(&moved).unwrap().fingerprint.geometry, a.geometry);
        assert_eq!(a.lights, plain.lights);
    }

    /// The Cornell box with its white material a rough conductor.
    fn rough_box(texture: Arc<Texture>, slot: ColourSlot) -> crate::scene::SceneDescription {
        let mut d = textured_box(texture);
        d.materials[0].bsdf = Bsdf::RoughConductor(
            RoughConductor::with_microfacet(
                Microfacet::anisotropic(Distribution::Beckmann, 0.3, 0.2),
                Rgb::ONE,
                None,
            )
            .unwrap(),
        );
        d.textures[0].slot = slot;
        d
    }

    fn alphas(scene: &Scene, prim: u32, p: Vec3) -> (f32, f32) {
        match &scene.material_at(prim, p, &mut None).bsdf {
            Bsdf::RoughConductor(c) => (c.microfacet.alpha_u, c.microfacet.alpha_v),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_roughness_texture_sets_alpha_at_the_point_as_mitsubas_eval_1() {
        // A checkerboard's eval_1 is the mean of its colour's channels, its squares swapped
        // (Mitsuba's): color1 at uv (¼, ¼), color0 at (¾, ¼).
        let cb = Arc::new(Texture::Checkerboard(
            Checkerboard::new(Rgb::new(0.1, 0.2, 0.3), Rgb::splat(0.05), UvTransform::IDENTITY).unwrap(),
        ));
        let (a, b) = (Vec3::new(-0.5, -1.0, -0.5), Vec3::new(0.5, -1.0, -0.5)); // uv (¼, ¼), (¾, ¼)
        let scene = Scene::build(&rough_box(cb.clone(), ColourSlot::Alpha)).unwrap();
        let (u, v) = alphas(&scene, 0, b);
        assert!((u - 0.2).abs() < 1e-6 && u == v, "{u} {v}");
        assert_eq!(alphas(&scene, 0, a), (0.05, 0.05));
        let scene = Scene::build(&rough_box(cb.clone(), ColourSlot::AlphaV)).unwrap();
        assert_eq!(alphas(&scene, 0, a), (0.3, 0.05));
        // Zero is raised to Mitsuba's 1e-4; above 1 or negative is refused.
        let zero = Scene::build(&rough_box(checker(0.0, 0.5), ColourSlot::Alpha)).unwrap();
        assert_eq!(alphas(&zero, 0, b).0, MIN_TEXTURED_ALPHA);
        let refused = |t, slot| match Scene::build(&rough_box(t, slot)) {
            Err(SceneError::BadTexture { message, .. }) => message,
            other => panic!("{other:?}"),
        };
        assert!(refused(checker(1.5, 0.5), ColourSlot::Alpha).contains("not a roughness"));
        // A material without roughness, and alpha with alpha_u.
        let mut d = textured_box(checker(0.2, 0.5));
        d.textures[0].slot = ColourSlot::Alpha;
        assert!(Scene::build(&d).is_err());
        let mut d = rough_box(cb.clone(), ColourSlot::Alpha);
        d.textures.push(TextureBinding { material: 0, slot: ColourSlot::AlphaU, texture: cb });
        assert!(Scene::build(&d).unwrap_err().to_string().contains("cannot both"));
    }

    /// The Cornell box's white mesh with attribute `name`: vertex i's value (i, 2i, 3i)/200 if
    /// per vertex, triangle j's (j/200) if per face (the light, white too, gets its own copy).
    fn attributed_box(name: &str, channels: u8, slot: ColourSlot) -> crate::scene::SceneDescription {
        let mut d = cornell_box();
        d.materials.push(d.materials[0].clone());
        let light = d.meshes.iter_mut().find(|m| m.name == "light").unwrap();
        assert_eq!(light.material, 0);
        light.material = d.materials.len() - 1;
        let white = &mut d.meshes[0];
        let n = if name.starts_with("vertex_") { white.positions.len() } else { white.triangles.len() };
        let values = (0..n)
            .map(|i| {
                let i = i as f32 / 200.0;
                if channels == 1 { Rgb::splat(i) } else { Rgb::new(i, 2.0 * i, 3.0 * i) }
            })
            .collect();
        white.attributes.push(MeshAttribute { name: name.into(), channels, values });
        let texture = Arc::new(Texture::MeshAttribute(MeshAttributeTexture::new(name.into(), 1.0).unwrap()));
        d.textures.push(TextureBinding { material: 0, slot, texture });
        d
    }

    #[test]
    fn mesh_attributes_blend_vertex_values_and_keep_face_values() {
        let d = attributed_box("vertex_color", 3, ColourSlot::Reflectance);
        let scene = Scene::build(&d).unwrap();
        let white = &d.meshes[0];
        for prim in [0u32, 1, 3] {
            let t = white.triangles[prim as usize];
            let corners = t.map(|i| white.attributes[0].values[i as usize]);
            let p = scene.triangles[prim as usize].point(0.2, 0.3);
            let want = 0.5 * corners[0] + 0.2 * corners[1] + 0.3 * corners[2];
            let Bsdf::Lambert(l) = scene.material_at(prim, p, &mut None).bsdf.clone() else { panic!() };
            assert!((l.reflectance - want).abs().max_element() < 1e-6, "{} {want}", l.reflectance);
        }
        let d = attributed_box("face_color", 1, ColourSlot::Reflectance);
        let scene = Scene::build(&d).unwrap();
        let p = scene.triangles[5].point(0.7, 0.1);
        let Bsdf::Lambert(l) = scene.material_at(5, p, &mut None).bsdf.clone() else { panic!() };
        assert_eq!(l.reflectance, Rgb::splat(0.025));
        // A roughness from a one-channel attribute; three channels are refused there.
        let mut d = attributed_box("face_rough", 1, ColourSlot::Alpha);
        d.materials[0].bsdf = Bsdf::RoughConductor(RoughConductor::new(0.3, Rgb::ONE, None).unwrap());
        let scene = Scene::build(&d).unwrap();
        assert_eq!(alphas(&scene, 2, scene.triangles[2].point(0.1, 0.1)), (0.01, 0.01));
        d.meshes[0].attributes[0].channels = 3;
        assert!(Scene::build(&d).unwrap_err().to_string().contains("needs one"));
    }

    #[test]
    fn impossible_attributes_are_refused_naming_mesh_and_attribute() {
        let err = |d: &crate::scene::SceneDescription| Scene::build(d).unwrap_err().to_string();
        // A mesh of the material without the attribute.
        let mut d = attributed_box("vertex_color", 3, ColourSlot::Reflectance);
        d.meshes[0].attributes[0].name = "vertex_other".into();
        assert!(err(&d).contains("has no attribute \"vertex_color\""), "{}", err(&d));
        let mut d = attributed_box("vertex_color", 3, ColourSlot::Reflectance);
        d.meshes[0].attributes[0].values.pop();
        assert!(err(&d).contains("59 values for 60 vertices"), "{}", err(&d));
        let mut d = attributed_box("vertex_color", 3, ColourSlot::Reflectance);
        d.meshes[0].attributes[0].values[1].y = f32::NAN;
        assert!(err(&d).contains("not finite"));
        let mut d = attributed_box("vertex_color", 3, ColourSlot::Reflectance);
        d.meshes[0].attributes[0].name = "color".into();
        assert!(err(&d).contains("must start with"));
        let mut d = attributed_box("vertex_color", 3, ColourSlot::Reflectance);
        d.meshes[0].attributes[0].values[2] = Rgb::new(0.2, 1.5, 0.0);
        assert!(err(&d).contains("largest value"), "{}", err(&d));
        d.meshes[0].attributes[0].values[2] = Rgb::new(0.2, -0.5, 0.0);
        assert!(err(&d).contains("negative"), "{}", err(&d));
    }

    #[test]
    fn attribute_values_enter_the_fingerprint_only_where_textured() {
        let plain = Scene::build(&cornell_box()).unwrap().fingerprint;
        let mut d = cornell_box();
        let values = vec![Rgb::splat(0.5); d.meshes[1].positions.len()];
        d.meshes[1].attributes.push(MeshAttribute { name: "vertex_color".into(), channels: 1, values });
        assert_eq!(Scene::build(&d).unwrap().fingerprint, plain);
        let d = attributed_box("vertex_color", 3, ColourSlot::Reflectance);
        let a = Scene::build(&d).unwrap().fingerprint;
        assert_ne!(a.geometry, plain.geometry);
        let mut e = d.clone();
        e.meshes[0].attributes[0].values[3].z += 0.01;
        assert_ne!(Scene::build(&e).unwrap().fingerprint.geometry, a.geometry);
        let mut e = d.clone();
        e.textures[0].texture =
            Arc::new(Texture::MeshAttribute(MeshAttributeTexture::new("vertex_color".into(), 0.5).unwrap()));
        assert_ne!(Scene::build(&e).unwrap().fingerprint.geometry, a.geometry);
        assert!(MeshAttributeTexture::new("color".into(), 1.0).is_err());
    }
}
