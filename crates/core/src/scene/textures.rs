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

#[cfg(test)]
mod tests {
    use super::super::{Scene, cornell_box};
    use super::*;
    use crate::bsdf::{Lambert, Plastic};
    use crate::math::{Rgb, Vec2, Vec3};
    use crate::texture::{Checkerboard, TextureBinding, UvTransform};

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
}
