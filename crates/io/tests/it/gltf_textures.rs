//! The glTF 2.0 loader, continued (`gltf.rs` holds the geometry, lights, cameras and errors):
//! textures against their Mitsuba twin, the texel limit, choosing scenes and cameras by name,
//! baked base-colour and metallic textures, transmission, orthographic cameras.

use super::gltf::{base64, close, doc, doc_with, load_ok, quad_buffer};
use opticks_core::bsdf::Bsdf;
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::{Scene, SceneDescription};
use opticks_io::{LoadedScene, SceneFileError, load_scene};
use opticks_testkit::files::*;

/// The reflectance of a Lambertian material at world point `p` on the floor (triangles whose
/// normal is ±y at height 0).
fn floor_albedo(s: &Scene, p: Vec3) -> Rgb {
    let prim = (0..s.triangles.len() as u32)
        .find(|&i| {
            let t = &s.triangles[i as usize];
            let (b1, b2) = t.barycentrics(p);
            t.normal().y.abs() > 0.99
                && t.point(0.0, 0.0).y.abs() < 1e-6
                && b1 >= 0.0
                && b2 >= 0.0
                && b1 + b2 <= 1.0
        })
        .unwrap_or_else(|| panic!("no floor triangle under {p:?}"));
    let mut slot = None;
    match &s.material_at(prim, p, &mut slot).bsdf {
        Bsdf::Lambert(l) => l.reflectance,
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_textured_gltf_builds_the_same_scene_as_its_mitsuba_twin() {
    // testdata/gltf/make_textured.py: an external PNG sampled nearest with a
    // KHR_texture_transform, and the same room in Mitsuba XML (OBJ `vt`, bitmap `to_uv`).
    let g = load_scene(&testdata("gltf/textured.gltf")).unwrap();
    let x = load_scene(&testdata("gltf/textured.xml")).unwrap();
    assert!(x.warnings.is_empty(), "{:?}", x.warnings);
    assert_eq!(g.description.textures.len(), 1);
    let (a, b) = (Scene::build(&g.description).unwrap(), Scene::build(&x.description).unwrap());
    assert!(a.has_textures());
    let colours: Vec<Rgb> = (0..64)
        .map(|k| {
            let p = Vec3::new(-0.97 + 0.0301 * k as f32, 0.0, 0.93 - 0.0297 * k as f32);
            let (ca, cb) = (floor_albedo(&a, p), floor_albedo(&b, p));
            assert!(close(ca, cb, 1e-6), "at {p:?}: glTF {ca} vs Mitsuba {cb}");
            ca
        })
        .collect();
    // Both checker colours are seen (sRGB-decoded), and nothing else.
    let srgb = |c: [u8; 3]| {
        Rgb::new(c[0] as f32, c[1] as f32, c[2] as f32)
            .map(|v| opticks_io::texture_file::srgb_to_linear(v / 255.0))
    };
    let (c0, c1) = (srgb([230, 60, 40]), srgb([40, 120, 220]));
    assert!(colours.iter().all(|&c| close(c, c0, 1e-6) || close(c, c1, 1e-6)), "{colours:?}");
    assert!(colours.iter().any(|&c| close(c, c0, 1e-6)) && colours.iter().any(|&c| close(c, c1, 1e-6)));
    // The transform's offset: UV (0, 0) (the floor's corner (−1, 0, 1)) maps to (0.25, 0), the
    // second texel of the first row, which is colour 1; without the offset it would be colour 0.
    assert!(close(floor_albedo(&a, Vec3::new(-0.999, 0.0, 0.999)), c1, 1e-6));
    // The lamp: the same radiance.
    let lamp = |d: &SceneDescription| d.meshes.iter().find_map(|m| m.emission.as_ref().map(|e| e.radiance));
    assert_eq!(lamp(&g.description), Some(Rgb::new(8.0, 6.0, 4.0)));
    assert_eq!(lamp(&g.description), lamp(&x.description));
}

fn load_textured(options: &opticks_io::LoadOptions) -> Result<LoadedScene, SceneFileError> {
    opticks_io::load_scene_with(&testdata("gltf/textured.gltf"), options)
}

/// Issue 26: a glTF file's images are held to the caller's texel limit, like Mitsuba's bitmaps.
#[test]
fn gltf_images_are_held_to_the_callers_texel_limit() {
    let limits = opticks_io::LoadLimits { max_texels: 1, ..Default::default() };
    let e = load_textured(&opticks_io::LoadOptions { limits, ..Default::default() }).unwrap_err().to_string();
    assert!(
        e.contains("textured.gltf") && e.contains("the limit of 1 ") && e.contains("--max-texels"),
        "{e}"
    );
}

#[test]
fn scenes_and_cameras_are_chosen_by_name_and_unknown_names_list_the_choices() {
    use opticks_io::LoadOptions;
    let day = load_textured(&LoadOptions::default()).unwrap();
    let eye = |s: &LoadedScene| s.description.camera.unwrap().eye;
    assert!(close(eye(&day), Vec3::new(0.0, 2.0, 2.5), 1e-6), "the default scene's first camera");
    assert_eq!(day.description.meshes.len(), 2);
    let w = day.warnings.join("\n");
    assert!(w.contains("node 4 (\"Detail\"): camera 1: another camera comes first"), "{w}");
    // By node name or by the camera's own name.
    for name in ["Detail", "close"] {
        let opts = LoadOptions { camera: Some(name.into()), ..Default::default() };
        let s = load_textured(&opts).unwrap();
        let c = s.description.camera.unwrap();
        assert!(close(c.eye, Vec3::new(0.0, 0.6, 1.2), 1e-6), "{name}");
        assert_eq!((c.width, c.height), (768, 512), "aspect 1.5");
        assert!(
            s.warnings.iter().any(|w| w.contains("\"Overview\"") && w.contains("not the one --camera names"))
        );
    }
    let e = load_textured(&LoadOptions { camera: Some("Attic".into()), ..Default::default() })
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("--camera \"Attic\"")
            && e.contains("\"Overview\" (camera \"wide\"), \"Detail\" (camera \"close\")"),
        "{e}"
    );
    // The other scene, by name or index: a point light, the glass pane, its own camera.
    for which in ["Night", "1"] {
        let s = load_textured(&LoadOptions { gltf_scene: Some(which.into()), ..Default::default() }).unwrap();
        let d = &s.description;
        assert_eq!((d.point_lights.len(), d.meshes.len()), (1, 2), "{which}");
        assert!(close(eye(&s), Vec3::new(0.0, 0.6, 1.2), 1e-6));
        let pane = d.meshes.iter().find(|m| m.name == "pane").unwrap();
        match &d.materials[pane.material].bsdf {
            Bsdf::ThinDielectric(t) => {
                assert!((t.eta - 1.5).abs() < 1e-6 && t.specular_transmittance == Rgb::ONE)
            }
            other => panic!("thin-walled glass expected: {other:?}"),
        }
        Scene::build(d).unwrap();
    }
    let e = load_textured(&LoadOptions { gltf_scene: Some("Evening".into()), ..Default::default() })
        .unwrap_err()
        .to_string();
    assert!(e.contains("--gltf-scene \"Evening\"") && e.contains("0 (\"Day\"), 1 (\"Night\")"), "{e}");
    // Formats without named cameras or scenes refuse the options instead of ignoring them.
    let e = opticks_io::load_scene_with(
        &testdata("gltf/textured-floor.obj"),
        &LoadOptions { camera: Some("x".into()), ..Default::default() },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("--camera \"x\"") && e.contains("no cameras"), "{e}");
}

#[test]
fn a_mitsuba_sensor_is_chosen_by_its_id() {
    use opticks_io::LoadOptions;
    let xml = br#"<scene version="3.0.0">
  <sensor type="perspective" id="front"><float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
  <sensor type="perspective" id="side"><float name="fov" value="30"/>
    <transform name="to_world"><lookat origin="5, 0, 0" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>"#;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("two.xml");
    std::fs::write(&path, xml).unwrap();
    let first = load_scene(&path).unwrap();
    assert!(close(first.description.camera.unwrap().eye, Vec3::new(0.0, 0.0, 5.0), 1e-6));
    let side = opticks_io::load_scene_with(
        &path,
        &LoadOptions { camera: Some("side".into()), ..Default::default() },
    )
    .unwrap();
    assert!(close(side.description.camera.unwrap().eye, Vec3::new(5.0, 0.0, 0.0), 1e-6));
    let e =
        opticks_io::load_scene_with(&path, &LoadOptions { camera: Some("top".into()), ..Default::default() })
            .unwrap_err()
            .to_string();
    assert!(e.contains("--camera \"top\"") && e.contains("\"front\", \"side\""), "{e}");
}

/// Builds `d` with a point light added (the core refuses a scene without light), so that the
/// core's own checks of its materials and textures run.
fn build_lit(d: &SceneDescription) -> Scene {
    let mut d = d.clone();
    d.point_lights.push(opticks_core::scene::PointLightDesc {
        position: Vec3::new(0.5, 0.5, 1.0),
        intensity: Rgb::ONE,
        ..Default::default()
    });
    Scene::build(&d).unwrap()
}

/// A 2 × 1 RGB PNG of `texels` (8-bit), base64 for a `data:` URI.
fn png_2x1(texels: [[u8; 3]; 2]) -> String {
    let mut img = image::RgbImage::new(2, 1);
    img.put_pixel(0, 0, image::Rgb(texels[0]));
    img.put_pixel(1, 0, image::Rgb(texels[1]));
    let mut bytes = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png).unwrap();
    base64(&bytes)
}

/// A quad buffer with TEXCOORD_0 (accessor 3): (0,0), (1,0), (1,1), (0,1).
fn textured_quad_doc(materials: &str, images: &str) -> String {
    let mut b = quad_buffer();
    for uv in [[0.0f32, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]] {
        for c in uv {
            b.extend_from_slice(&c.to_le_bytes());
        }
    }
    let body = format!(
        r#""materials": [{materials}],
  "textures": [{{"source": 0}}, {{"source": 1}}],
  "images": [{images}],
  "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 3}}, "indices": 1, "material": 0}}]}}]"#
    );
    doc_with(&b, &body)
        .replace(
            r#"{"buffer": 0, "byteOffset": 48, "byteLength": 12}]"#,
            r#"{"buffer": 0, "byteOffset": 48, "byteLength": 12}, {"buffer": 0, "byteOffset": 60, "byteLength": 32}]"#,
        )
        .replace(
            r#""max": [1, 1, 0]}
  ],"#,
            r#""max": [1, 1, 0]},
    {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}
  ],"#,
        )
}

fn textures_of(s: &LoadedScene) -> Vec<(opticks_core::texture::ColourSlot, Vec<Rgb>)> {
    s.description
        .textures
        .iter()
        .map(|t| match &*t.texture {
            opticks_core::texture::Texture::Bitmap(b) => (t.slot, b.texels().to_vec()),
            other => panic!("{other:?}"),
        })
        .collect()
}

#[test]
fn base_colour_and_metallic_textures_are_baked_into_kd_and_ks_per_texel() {
    use opticks_core::texture::ColourSlot;
    let images = format!(
        r#"{{"uri": "data:image/png;base64,{}"}}, {{"uri": "data:image/png;base64,{}"}}"#,
        png_2x1([[255, 255, 255], [255, 255, 255]]),
        // Metallic (blue) 0 then 1; roughness (green) 0 then 1 (mean ½).
        png_2x1([[0, 0, 0], [0, 255, 255]])
    );
    // White base times a factor; the metallic texture: kd = 0.96·b, ks = 0.04 where m = 0, and
    // kd = 0, ks = b where m = 1 — maxima 0.96·0.5 + 0.5 ≤ 1 in every channel: kept per texel.
    let s = load_ok(
        "t.gltf",
        textured_quad_doc(
            r#"{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "baseColorTexture": {"index": 0},
              "metallicRoughnessTexture": {"index": 1}, "metallicFactor": 1, "roughnessFactor": 1}}"#,
            &images,
        )
        .as_bytes(),
    );
    let t = textures_of(&s);
    assert_eq!(t.len(), 2, "{t:?}");
    assert_eq!(t[0].0, ColourSlot::DiffuseReflectance);
    assert!(close(t[0].1[0], Rgb::splat(0.48), 1e-6) && t[0].1[1] == Rgb::ZERO, "{:?}", t[0].1);
    assert_eq!(t[1].0, ColourSlot::SpecularReflectance);
    assert!(
        close(t[1].1[0], Rgb::splat(0.04), 1e-6) && close(t[1].1[1], Rgb::splat(0.5), 1e-6),
        "{:?}",
        t[1].1
    );
    assert_eq!(s.description.meshes[0].uvs.len(), 4);
    // One exponent: roughness ½ (the green channel's mean) → n = 30, with a warning.
    match &s.description.materials[0].bsdf {
        Bsdf::ModifiedPhong(p) => assert!((p.exponent - 30.0).abs() < 1e-3, "{}", p.exponent),
        other => panic!("{other:?}"),
    }
    assert!(s.warnings.iter().any(|w| w.contains("roughness texture is averaged")), "{:?}", s.warnings);
    build_lit(&s.description);

    // A full-white base: maxima 0.96 + 1 > 1, so the mean metallic (½) is used, and nothing
    // varies any more: constant kd = 0.48, ks = 0.52.
    let s = load_ok(
        "u.gltf",
        textured_quad_doc(
            r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 1}}}"#,
            &images,
        )
        .as_bytes(),
    );
    assert!(s.description.textures.is_empty());
    match &s.description.materials[0].bsdf {
        Bsdf::ModifiedPhong(p) => {
            assert!(close(p.kd, Rgb::splat(0.48), 1e-6) && close(p.ks, Rgb::splat(0.52), 1e-6))
        }
        other => panic!("{other:?}"),
    }
    assert!(s.warnings.iter().any(|w| w.contains("its mean metallic is used")), "{:?}", s.warnings);
}

#[test]
fn texture_errors_name_the_image_and_the_primitive() {
    let mat = r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}"#;
    let e = error_of(&[(
        "a.gltf",
        textured_quad_doc(mat, r#"{"uri": "missing.png"}, {"uri": "x.png"}"#).as_bytes(),
    )]);
    assert!(e.contains("image 0: cannot read image file TMP/missing.png"), "{e}");
    let e = error_of(&[(
        "b.gltf",
        textured_quad_doc(mat, r#"{"uri": "data:image/png;base64,AAAA"}, {"uri": "x.png"}"#).as_bytes(),
    )]);
    assert!(e.contains("image 0") && e.contains("not a PNG or JPEG"), "{e}");
    // A textured material on a primitive without TEXCOORD_0.
    let images = format!(
        r#"{{"uri": "data:image/png;base64,{0}"}}, {{"uri": "data:image/png;base64,{0}"}}"#,
        png_2x1([[9, 9, 9], [200, 200, 200]])
    );
    let doc = textured_quad_doc(
        r#"{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}}}"#,
        &images,
    );
    let e = error_of(&[("c.gltf", doc.as_bytes())]);
    assert!(e.contains("primitive 0") && e.contains("TEXCOORD_1, which the primitive does not have"), "{e}");
}

#[test]
fn transmission_makes_thin_or_refracting_glass() {
    let with = |ext: &str| {
        let body = format!(
            r#""extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume"],
  "materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [0.9, 0.8, 0.7, 1], "roughnessFactor": 0.5}}, "extensions": {{{ext}}}}}],
  "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "material": 0}}]}}]"#
        );
        load_ok("g.gltf", doc(&body).as_bytes())
    };
    let tint = Rgb::new(0.9, 0.8, 0.7);
    let thin = with(r#""KHR_materials_transmission": {"transmissionFactor": 1}"#);
    match &thin.description.materials[0].bsdf {
        Bsdf::ThinDielectric(t) => {
            assert!(close(t.specular_transmittance, tint, 1e-6) && (t.eta - 1.5).abs() < 1e-6)
        }
        other => panic!("{other:?}"),
    }
    assert!(thin.warnings.iter().any(|w| w.contains("roughness ignored")), "{:?}", thin.warnings);
    let solid = with(
        r#""KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_volume": {"thicknessFactor": 0.1}"#,
    );
    match &solid.description.materials[0].bsdf {
        Bsdf::RoughDielectric(r) => {
            assert!((r.microfacet.alpha_u - 0.25).abs() < 1e-6 && close(r.specular_transmittance, tint, 1e-6))
        }
        other => panic!("{other:?}"),
    }
    assert!(solid.description.materials[0].two_sided);
    let mostly_opaque = with(r#""KHR_materials_transmission": {"transmissionFactor": 0.3}"#);
    assert!(matches!(mostly_opaque.description.materials[0].bsdf, Bsdf::ModifiedPhong(_)));
    assert!(
        mostly_opaque.warnings.iter().any(|w| w.contains("transmissionFactor 0.3") && w.contains("opaque"))
    );
    for s in [thin, solid, mostly_opaque] {
        build_lit(&s.description);
    }
}

#[test]
fn an_orthographic_camera_keeps_its_magnification() {
    use opticks_core::scene::CameraKind;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("o.gltf");
    let body = r#""cameras": [{"name": "plan", "type": "orthographic", "orthographic": {"xmag": 2, "ymag": 1, "znear": 0.1, "zfar": 10}}],
  "scenes": [{"nodes": [0]}], "nodes": [{"camera": 0, "translation": [0, 0, 5]}]"#;
    std::fs::write(&path, doc(body)).unwrap();
    for camera in [None, Some("plan".to_string())] {
        let s = opticks_io::load_scene_with(&path, &opticks_io::LoadOptions { camera, ..Default::default() })
            .unwrap();
        let c = s.description.camera.unwrap();
        assert_eq!((c.width, c.height), (1024, 512));
        assert_eq!(c.kind, CameraKind::Orthographic { half_width: 2.0, half_height: 1.0 });
        assert!(close(c.eye, Vec3::new(0.0, 0.0, 5.0), 1e-6) && close(c.target - c.eye, -Vec3::Z, 1e-6));
    }
}
