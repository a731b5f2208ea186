//! The texture stage of [`super::Scene::build`]: each [`TextureBinding`] of the description is
//! checked against its material (the material exists, has that colour, and every value the
//! texture takes is one the parameter accepts — a reflectance in [0, 1], Phong's kd + ks ≤ 1 at
//! the textures' maxima) and gathered per material, for [`super::Scene::material_at`].

use super::{SceneDescription, SceneError};
use crate::bsdf::{Bsdf, Material, ModifiedPhong, check_unit_colour};
use crate::texture::{ColourSlot, Texture, set_colour};
use std::sync::Arc;

/// Per material, the textures in place of its colours (empty for an untextured material).
pub(super) type MaterialTextures = Vec<Vec<(ColourSlot, Arc<Texture>)>>;

/// The description's textures, checked and gathered per material.
pub(super) fn bind(desc: &SceneDescription) -> Result<MaterialTextures, SceneError> {
    let mut out: MaterialTextures = vec![Vec::new(); desc.materials.len()];
    for b in &desc.textures {
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
        let max = b.texture.max_value();
        check_unit_colour(b.slot.name(), max)
            .map_err(|e| bad(m.name.clone(), format!("the texture's largest value {max}: {e}")))?;
        if !set_colour(&mut m.bsdf.clone(), b.slot, max) {
            return Err(bad(m.name.clone(), "this material has no such colour parameter".into()));
        }
        let list = &mut out[b.material];
        if list.iter().any(|(s, _)| *s == b.slot) {
            return Err(bad(m.name.clone(), "the parameter has two textures".into()));
        }
        list.push((b.slot, b.texture.clone()));
    }
    // Phong's energy bound holds at every point if it holds for the channels' maxima.
    for (m, list) in desc.materials.iter().zip(&out) {
        if let Bsdf::ModifiedPhong(p) = &m.bsdf
            && !list.is_empty()
        {
            let mut at_max = Bsdf::ModifiedPhong(p.clone());
            for (slot, t) in list {
                set_colour(&mut at_max, *slot, t.max_value());
            }
            if let Bsdf::ModifiedPhong(q) = at_max {
                ModifiedPhong::new(q.kd, q.ks, q.exponent).map_err(|e| SceneError::BadTexture {
                    material: m.name.clone(),
                    slot: list[0].0.name(),
                    message: format!("at the textures' largest values: {e}"),
                })?;
            }
        }
    }
    Ok(out)
}

/// `material` with its textured colours evaluated at `uv` (a copy without a name: nothing
/// allocated).
#[inline]
pub(super) fn resolve(
    material: &Material,
    textures: &[(ColourSlot, Arc<Texture>)],
    uv: glam::Vec2,
) -> Material {
    let mut bsdf = material.bsdf.clone();
    for (slot, t) in textures {
        set_colour(&mut bsdf, *slot, t.eval(uv));
    }
    Material { name: String::new(), bsdf, two_sided: material.two_sided }
}
