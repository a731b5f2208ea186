//! The frame of an anisotropic BSDF follows ∂p/∂u (Mitsuba's `sh_frame`), and nothing else
//! changes: isotropic materials and triangles without texture coordinates keep the frame of the
//! shading normal, bit for bit; the fingerprint takes the coordinates such a frame depends on.

use super::Scene;
use crate::bsdf::{Blend, Bsdf, Lambert, Principled, RoughConductor};
use crate::math::{Vec2, Vec3};
use crate::sampling::microfacet::{Distribution, Microfacet};
use crate::scene::{SceneDescription, cornell_box};

/// The Cornell box with its white material a Beckmann conductor of roughness `alpha` (along
/// the tangent, along the bitangent) and, if `uv` says how, texture coordinates on the white
/// mesh (a function of the vertex position).
fn brushed_box(alpha: (f32, f32), uv: Option<fn(Vec3) -> Vec2>) -> SceneDescription {
    let mut d = cornell_box();
    let microfacet = Microfacet::anisotropic(Distribution::Beckmann, alpha.0, alpha.1);
    d.materials[0].bsdf = Bsdf::RoughConductor(
        RoughConductor::with_microfacet(microfacet, crate::math::Rgb::ONE, None).unwrap(),
    );
    if let Some(uv) = uv {
        let white = &mut d.meshes[0];
        white.uvs = white.positions.iter().map(|&p| uv(p)).collect();
    }
    d
}

/// u along +x (Mitsuba's rectangle), or along +z.
fn u_along_x(p: Vec3) -> Vec2 {
    Vec2::new((p.x + 1.0) / 2.0, (p.z + 1.0) / 2.0)
}
fn u_along_z(p: Vec3) -> Vec2 {
    Vec2::new((p.z + 1.0) / 2.0, (p.x + 1.0) / 2.0)
}

/// The floor's first triangle (facing +y) and a point on it.
fn floor(scene: &Scene) -> (u32, Vec3) {
    let prim = (0..scene.triangles.len() as u32)
        .find(|&i| scene.normal(i).y > 0.99 && scene.triangles[i as usize].v0.y < -0.99)
        .expect("a floor triangle");
    (prim, scene.triangles[prim as usize].point(0.3, 0.3))
}

/// f at the floor point for light from `wi` leaving along `wo`.
fn f(scene: &Scene, wi: Vec3, wo: Vec3) -> f32 {
    let (prim, p) = floor(scene);
    let mut resolved = None;
    let (material, normals) = scene.surface_at(prim, p, &mut resolved);
    material.eval_world(normals, wi.normalize(), wo.normalize()).x
}

#[test]
fn an_anisotropic_frame_follows_dp_du_projected_on_the_shading_normal() {
    let along_x = Scene::build(&brushed_box((0.3, 0.05), Some(u_along_x))).unwrap();
    let along_z = Scene::build(&brushed_box((0.3, 0.05), Some(u_along_z))).unwrap();
    let (prim, p) = floor(&along_x);
    assert!((along_x.normals_at(prim, p).tangent.unwrap() - Vec3::X).length() < 1e-6);
    assert!((along_z.normals_at(prim, p).tangent.unwrap() - Vec3::Z).length() < 1e-6);
    // The same brushed metal: roughness 0.3 along x, whether as (α_u, α_v) with u along x or
    // as (α_v, α_u) with u along z (then the bitangent n × s = y × z is x).
    let swapped = Scene::build(&brushed_box((0.05, 0.3), Some(u_along_z))).unwrap();
    // Pairs whose half vector leans along x, along z, and along both.
    let pairs = [
        (Vec3::new(0.6, 1.0, 0.0), Vec3::new(0.1, 1.0, 0.02)),
        (Vec3::new(0.02, 1.0, 0.6), Vec3::new(0.0, 1.0, 0.1)),
        (Vec3::new(0.5, 1.0, 0.45), Vec3::new(0.1, 1.0, 0.05)),
    ];
    for (wi, wo) in pairs {
        let (a, b, c) = (f(&along_x, wi, wo), f(&swapped, wi, wo), f(&along_z, wi, wo));
        assert!((a - b).abs() <= 1e-4 * a.abs().max(b.abs()), "{wi} → {wo}: {a} vs {b}");
        // Turning the brushing by 90° changes what a pair whose half vector leans sees.
        assert!((a - c).abs() > 0.2 * a.max(c), "{wi} → {wo}: {a} vs {c}: the frame did not turn");
    }
}

#[test]
fn isotropic_materials_and_triangles_without_uvs_keep_the_normal_s_frame() {
    // Isotropic, with UVs: the plain path (no tangent), bit for bit the scene without UVs.
    let iso = Scene::build(&brushed_box((0.2, 0.2), Some(u_along_z))).unwrap();
    let bare = Scene::build(&brushed_box((0.2, 0.2), None)).unwrap();
    let (prim, p) = floor(&iso);
    assert_eq!(iso.normals_at(prim, p).tangent, None);
    let (wi, wo) = (Vec3::new(0.3, 1.0, 0.2), Vec3::new(-0.5, 1.0, 0.1));
    assert_eq!(f(&iso, wi, wo).to_bits(), f(&bare, wi, wo).to_bits());
    // Anisotropic, without UVs: the frame of the normal (Mitsuba's `coordinate_system`).
    let aniso = Scene::build(&brushed_box((0.3, 0.05), None)).unwrap();
    assert_eq!(aniso.normals_at(prim, p).tangent, None);
}

#[test]
fn which_bsdfs_are_anisotropic() {
    let conductor = |a, b| {
        Bsdf::RoughConductor(
            RoughConductor::with_microfacet(
                Microfacet::anisotropic(Distribution::Ggx, a, b),
                crate::math::Rgb::ONE,
                None,
            )
            .unwrap(),
        )
    };
    assert!(conductor(0.3, 0.1).is_anisotropic());
    assert!(!conductor(0.2, 0.2).is_anisotropic());
    let lambert = Bsdf::Lambert(Lambert::new(crate::math::Rgb::splat(0.5)).unwrap());
    assert!(!lambert.is_anisotropic());
    let blend = |b| Bsdf::Blend(Blend::new(0.5, lambert.clone(), b).unwrap());
    assert!(blend(conductor(0.3, 0.1)).is_anisotropic());
    assert!(!blend(conductor(0.2, 0.2)).is_anisotropic());
    let principled = |anisotropic| Bsdf::Principled(Principled { anisotropic, ..Principled::default() });
    assert!(principled(0.5).is_anisotropic());
    assert!(!principled(0.0).is_anisotropic());
}

#[test]
fn the_fingerprint_takes_the_uvs_an_anisotropic_frame_follows() {
    let along_x = Scene::build(&brushed_box((0.3, 0.05), Some(u_along_x))).unwrap().fingerprint;
    let along_z = Scene::build(&brushed_box((0.3, 0.05), Some(u_along_z))).unwrap().fingerprint;
    let bare = Scene::build(&brushed_box((0.3, 0.05), None)).unwrap().fingerprint;
    assert_ne!(along_x.geometry, along_z.geometry);
    assert_ne!(along_x.geometry, bare.geometry);
    // UVs on an isotropic, untextured material still change nothing.
    let iso_uv = Scene::build(&brushed_box((0.2, 0.2), Some(u_along_x))).unwrap().fingerprint;
    let iso_bare = Scene::build(&brushed_box((0.2, 0.2), None)).unwrap().fingerprint;
    assert_eq!(iso_uv, iso_bare);
}
