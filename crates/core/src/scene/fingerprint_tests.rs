//! Tests of `fingerprint.rs`.

use super::{material_hash, material_v2};
use crate::bsdf::{
    Blend, Bsdf, Lambert, Material, ModifiedPhong, Plastic, RoughConductor, RoughDielectric, RoughPlastic,
    SmoothConductor, SmoothDielectric, ThinDielectric,
};
use crate::light::EmissionProfile;
use crate::math::{Frame, Rgb, Vec3};
use crate::sampling::microfacet::{Distribution, Microfacet};
use crate::scene::{PointLightDesc, Scene, demo::cornell_box};

fn material(bsdf: Bsdf, two_sided: bool) -> Material {
    Material { name: "m".into(), bsdf, two_sided }
}

fn mf(distribution: Distribution, alpha_u: f32, alpha_v: f32) -> Microfacet {
    Microfacet { distribution, alpha_u, alpha_v }
}

fn phong() -> ModifiedPhong {
    ModifiedPhong { kd: Rgb::new(0.3, 0.2, 0.1), ks: Rgb::new(0.1, 0.2, 0.3), exponent: 20.0 }
}

fn mirror() -> SmoothConductor {
    let ior = Some((Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.9, 2.4, 1.6e17)));
    SmoothConductor { specular_reflectance: Rgb::new(0.9, 0.8, 0.7), ior }
}

fn glass() -> SmoothDielectric {
    SmoothDielectric {
        eta: 1.0 / 1.5,
        specular_reflectance: Rgb::ONE,
        specular_transmittance: Rgb::new(1.0, 0.95, 0.9),
        absorption: Rgb::new(0.1, 2.5e-5, 0.0),
    }
}

fn rough_metal() -> RoughConductor {
    RoughConductor {
        microfacet: mf(Distribution::Beckmann, 0.1, 0.3),
        specular_reflectance: Rgb::ONE,
        ior: None,
    }
}

fn rough_glass() -> RoughDielectric {
    RoughDielectric {
        eta: 1.5,
        microfacet: mf(Distribution::Ggx, 0.25, 0.25),
        specular_reflectance: Rgb::new(1.0, 0.99, 0.98),
        specular_transmittance: Rgb::ONE,
        absorption: Rgb::new(0.0, 0.5, 12.0),
    }
}

fn rough_plastic(d: Rgb, s: Rgb, dist: Distribution, alpha: f32, visible: bool, nonlinear: bool) -> Bsdf {
    Bsdf::RoughPlastic(RoughPlastic::new(d, s, 1.49, 1.0, dist, alpha, visible, nonlinear).unwrap())
}

/// A blend of a diffuse of reflectance `rho` and a mirror.
fn blend(weight: f32, rho: Rgb) -> Bsdf {
    let mirror = Bsdf::SmoothConductor(SmoothConductor::new(Rgb::ONE, None).unwrap());
    Bsdf::Blend(Blend::new(weight, Bsdf::Lambert(Lambert::new(rho).unwrap()), mirror).unwrap())
}

fn plastic(d: Rgb, s: Rgb, eta: f32, nonlinear: bool) -> Plastic {
    Plastic::new(d, s, eta, 1.0, nonlinear).unwrap()
}

fn thin() -> ThinDielectric {
    ThinDielectric {
        eta: 1.5,
        specular_reflectance: Rgb::new(1.0, 0.5, 0.25),
        specular_transmittance: Rgb::ONE,
    }
}

/// One material of every BSDF variant, with every option used.
fn one_of_each() -> Vec<Material> {
    vec![
        material(Bsdf::Lambert(Lambert { reflectance: Rgb::new(0.885809, 1e-7, -0.0) }), true),
        material(Bsdf::ModifiedPhong(phong()), false),
        material(Bsdf::SmoothConductor(mirror()), true),
        material(Bsdf::SmoothDielectric(glass()), false),
        material(Bsdf::RoughConductor(rough_metal()), false),
        material(Bsdf::RoughDielectric(rough_glass()), true),
        material(Bsdf::Plastic(plastic(Rgb::new(0.5, 0.25, 0.0), Rgb::ONE, 1.49, true)), false),
        material(Bsdf::ThinDielectric(thin()), false),
    ]
}

/// The version-2 text is frozen (module docs): these are the bytes datasets' hashes cover.
#[test]
fn material_text_of_every_variant_is_pinned() {
    let texts: Vec<String> = one_of_each().iter().map(material_v2).collect();
    assert_eq!(
        texts,
        [
            "Lambert(Lambert { reflectance: Vec3(0.885809, 1e-7, -0.0) })|true",
            "ModifiedPhong(ModifiedPhong { kd: Vec3(0.3, 0.2, 0.1), ks: Vec3(0.1, 0.2, 0.3), exponent: 20.0 })|false",
            "SmoothConductor(SmoothConductor { specular_reflectance: Vec3(0.9, 0.8, 0.7), ior: Some((Vec3(0.2, 0.9, \
             1.1), Vec3(3.9, 2.4, 1.6e17))) })|true",
            "SmoothDielectric(SmoothDielectric { eta: 0.6666667, specular_reflectance: Vec3(1.0, 1.0, 1.0), \
             specular_transmittance: Vec3(1.0, 0.95, 0.9), absorption: Vec3(0.1, 2.5e-5, 0.0) })|false",
            "RoughConductor(RoughConductor { microfacet: Microfacet { distribution: Beckmann, alpha_u: 0.1, alpha_v: \
             0.3 }, specular_reflectance: Vec3(1.0, 1.0, 1.0), ior: None })|false",
            "RoughDielectric(RoughDielectric { eta: 1.5, microfacet: Microfacet { distribution: Ggx, alpha_u: 0.25, \
             alpha_v: 0.25 }, specular_reflectance: Vec3(1.0, 0.99, 0.98), specular_transmittance: Vec3(1.0, 1.0, \
             1.0), absorption: Vec3(0.0, 0.5, 12.0) })|true",
            "Plastic(Plastic { diffuse_reflectance: Vec3(0.5, 0.25, 0.0), specular_reflectance: Vec3(1.0, 1.0, \
             1.0), eta: 1.49, nonlinear: 1.0 })|false",
            "ThinDielectric(ThinDielectric { eta: 1.5, specular_reflectance: Vec3(1.0, 0.5, 0.25), \
             specular_transmittance: Vec3(1.0, 1.0, 1.0) })|false",
        ]
    );
    let lambert = &one_of_each()[0];
    let digest = blake3::hash(format!("opticks material{}", texts[0]).as_bytes());
    assert_eq!(material_hash(lambert), digest.as_bytes()[..16], "BLAKE3(\"opticks material\" ‖ text)");
    assert_eq!(super::hex(&material_hash(lambert)), "2b5c37adb4b9dd7bdd34ecb807e063ee");
}

/// Every parameter of every variant, and the sidedness, reaches the hash; equal materials
/// (whatever their names) hash equal.
#[test]
fn material_hash_changes_with_every_parameter_and_only_with_them() {
    let base = one_of_each();
    for m in &base {
        let twin = Material { name: "another name".into(), ..m.clone() };
        assert_eq!(material_hash(&twin), material_hash(m), "{m:?}");
    }
    let rgb = Rgb::new;
    let (p, c, g, rc, rg) = (phong(), mirror(), glass(), rough_metal(), rough_glass());
    // Each variant with one parameter changed: every field, the presence of a conductor
    // index, the distribution, a roughness along each axis, a sign of zero.
    let changed = [
        Bsdf::Lambert(Lambert { reflectance: rgb(0.885809, 1e-7, 0.0) }),
        Bsdf::Lambert(Lambert { reflectance: rgb(0.885809, 2e-7, -0.0) }),
        Bsdf::ModifiedPhong(ModifiedPhong { kd: rgb(0.3, 0.2, 0.11), ..p.clone() }),
        Bsdf::ModifiedPhong(ModifiedPhong { ks: rgb(0.1, 0.21, 0.3), ..p.clone() }),
        Bsdf::ModifiedPhong(ModifiedPhong { exponent: 21.0, ..p }),
        Bsdf::SmoothConductor(SmoothConductor { specular_reflectance: rgb(0.91, 0.8, 0.7), ..c.clone() }),
        Bsdf::SmoothConductor(SmoothConductor { ior: None, ..c.clone() }),
        Bsdf::SmoothConductor(SmoothConductor {
            ior: Some((rgb(0.21, 0.9, 1.1), rgb(3.9, 2.4, 1.6e17))),
            ..c.clone()
        }),
        Bsdf::SmoothConductor(SmoothConductor {
            ior: Some((rgb(0.2, 0.9, 1.1), rgb(3.9, 2.4, 1.6e16))),
            ..c
        }),
        Bsdf::SmoothDielectric(SmoothDielectric { eta: 1.5, ..g.clone() }),
        Bsdf::SmoothDielectric(SmoothDielectric { specular_reflectance: rgb(1.0, 0.9, 1.0), ..g.clone() }),
        Bsdf::SmoothDielectric(SmoothDielectric {
            specular_transmittance: rgb(1.0, 0.95, 0.91),
            ..g.clone()
        }),
        Bsdf::SmoothDielectric(SmoothDielectric { absorption: rgb(0.2, 2.5e-5, 0.0), ..g }),
        Bsdf::RoughConductor(RoughConductor {
            microfacet: mf(Distribution::Beckmann, 0.11, 0.3),
            ..rc.clone()
        }),
        Bsdf::RoughConductor(RoughConductor {
            microfacet: mf(Distribution::Beckmann, 0.1, 0.1),
            ..rc.clone()
        }),
        Bsdf::RoughConductor(RoughConductor { microfacet: mf(Distribution::Ggx, 0.1, 0.3), ..rc.clone() }),
        Bsdf::RoughConductor(RoughConductor { specular_reflectance: rgb(1.0, 1.0, 0.5), ..rc.clone() }),
        Bsdf::RoughConductor(RoughConductor { ior: Some((Rgb::ONE, Rgb::ONE)), ..rc }),
        Bsdf::RoughDielectric(RoughDielectric { eta: 1.33, ..rg.clone() }),
        Bsdf::RoughDielectric(RoughDielectric { microfacet: mf(Distribution::Ggx, 0.3, 0.25), ..rg.clone() }),
        Bsdf::RoughDielectric(RoughDielectric { microfacet: mf(Distribution::Ggx, 0.25, 0.3), ..rg.clone() }),
        Bsdf::RoughDielectric(RoughDielectric {
            microfacet: mf(Distribution::Beckmann, 0.25, 0.25),
            ..rg.clone()
        }),
        Bsdf::RoughDielectric(RoughDielectric { specular_reflectance: rgb(1.0, 0.5, 0.98), ..rg.clone() }),
        Bsdf::RoughDielectric(RoughDielectric { specular_transmittance: rgb(0.5, 1.0, 1.0), ..rg.clone() }),
        Bsdf::RoughDielectric(RoughDielectric { absorption: rgb(0.0, 0.5, 0.0), ..rg }),
        Bsdf::Plastic(plastic(rgb(0.5, 0.25, 0.01), Rgb::ONE, 1.49, true)),
        Bsdf::Plastic(plastic(rgb(0.5, 0.25, 0.0), rgb(1.0, 0.5, 1.0), 1.49, true)),
        Bsdf::Plastic(plastic(rgb(0.5, 0.25, 0.0), Rgb::ONE, 1.5, true)),
        Bsdf::Plastic(plastic(rgb(0.5, 0.25, 0.0), Rgb::ONE, 1.49, false)),
        Bsdf::ThinDielectric(ThinDielectric { eta: 1.33, ..thin() }),
        Bsdf::ThinDielectric(ThinDielectric { specular_reflectance: Rgb::ONE, ..thin() }),
        Bsdf::ThinDielectric(ThinDielectric { specular_transmittance: rgb(1.0, 1.0, 0.9), ..thin() }),
        rough_plastic(Rgb::splat(0.5), Rgb::ONE, Distribution::Beckmann, 0.1, true, false),
        rough_plastic(Rgb::splat(0.4), Rgb::ONE, Distribution::Beckmann, 0.1, true, false),
        rough_plastic(Rgb::splat(0.5), Rgb::splat(0.9), Distribution::Beckmann, 0.1, true, false),
        rough_plastic(Rgb::splat(0.5), Rgb::ONE, Distribution::Ggx, 0.1, true, false),
        rough_plastic(Rgb::splat(0.5), Rgb::ONE, Distribution::Beckmann, 0.2, true, false),
        rough_plastic(Rgb::splat(0.5), Rgb::ONE, Distribution::Beckmann, 0.1, false, false),
        rough_plastic(Rgb::splat(0.5), Rgb::ONE, Distribution::Beckmann, 0.1, true, true),
        blend(0.5, Rgb::splat(0.5)),
        blend(0.25, Rgb::splat(0.5)),
        blend(0.5, Rgb::splat(0.6)),
    ];
    let mut all = base.clone();
    all.extend(base.iter().map(|m| Material { two_sided: !m.two_sided, ..m.clone() }));
    all.extend(changed.into_iter().map(|bsdf| material(bsdf, false)));
    all.extend(all.clone().into_iter().skip(2 * base.len()).map(|m| Material { two_sided: true, ..m }));
    // Every one hashes differently from every other.
    let hashes: Vec<[u8; 16]> = all.iter().map(material_hash).collect();
    for i in 0..all.len() {
        for j in 0..i {
            assert_ne!(hashes[i], hashes[j], "{:?}\nand\n{:?}", all[i], all[j]);
        }
    }
}

#[test]
fn a_light_shape_covers_where_and_how_it_emits_not_how_much() {
    let mut d = cornell_box();
    let axis = Frame::from_normal(Vec3::new(0.0, -1.0, 0.0));
    let spot = EmissionProfile::Spot { cutoff_angle: 0.6, beam_width: 0.4 };
    d.point_lights.push(PointLightDesc {
        name: "spot".into(),
        position: Vec3::new(0.0, 1.5, 0.0),
        intensity: Rgb::ONE,
        profile: Some(spot),
        orientation: Some(axis),
        ..Default::default()
    });
    let shape = |d: &crate::scene::SceneDescription| Scene::build(d).unwrap().light_shapes[1];
    let original = shape(&d);
    let mut brighter = d.clone();
    brighter.point_lights[0].intensity = Rgb::new(2.0, 1.0, 3.0);
    assert_eq!(shape(&brighter), original, "power and colour are not shape");
    let mut wider = d.clone();
    wider.point_lights[0].profile = Some(EmissionProfile::Spot { cutoff_angle: 0.7, beam_width: 0.4 });
    assert_ne!(shape(&wider), original, "the cone is");
    let mut tilted = d.clone();
    tilted.point_lights[0].orientation = Some(Frame::from_normal(Vec3::new(0.1, -1.0, 0.0).normalize()));
    assert_ne!(shape(&tilted), original, "the axis is");
    let mut moved = d.clone();
    moved.point_lights[0].position.x += 1e-3;
    assert_ne!(shape(&moved), original, "the position is");
    let mut uniform = d;
    uniform.point_lights[0].profile = Some(EmissionProfile::Uniform);
    assert_ne!(shape(&uniform), original, "the profile is");
}

#[test]
fn emission_is_not_geometry_but_reflectance_and_triangles_are() {
    let base = cornell_box();
    let fp = |d: &crate::scene::SceneDescription| Scene::build(d).unwrap().fingerprint;
    let original = fp(&base);
    let non_emitting = base.meshes.iter().position(|m| m.emission.is_none()).unwrap();

    let mut glowing = base.clone();
    glowing.meshes[non_emitting].emission = Some(crate::scene::AreaEmission::lambertian(Rgb::splat(0.5)));
    assert_eq!(fp(&glowing).geometry, original.geometry, "a surface turned light is the same geometry");
    assert_ne!(fp(&glowing).lights, original.lights, "but the lights changed");

    let mut extra_material = base.clone();
    extra_material.materials.push(extra_material.materials[0].clone());
    assert_eq!(fp(&extra_material).geometry, original.geometry, "an unused material changes nothing");

    let mut repainted = base.clone();
    let m = repainted.meshes[non_emitting].material;
    repainted.materials[m].bsdf = Bsdf::Lambert(Lambert { reflectance: Rgb::splat(0.123) });
    assert_ne!(fp(&repainted).geometry, original.geometry, "another reflectance is another scene");

    let mut moved = base.clone();
    moved.meshes[non_emitting].positions[0].x += 1e-3;
    assert_ne!(fp(&moved).geometry, original.geometry, "moved triangles are another scene");
}
