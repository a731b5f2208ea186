//! Mitsuba's `<texture>` elements through the loader's public API: where textures may stand
//! (nested in a BSDF under a colour's name, or by `<ref>` to a top-level one, shared), what the
//! scene description records (the bindings, the constant given to the core as the texture's
//! largest value, the shapes' UVs, OBJ `vt` with Mitsuba's flipped v), and the located errors
//! of bad textures and bad or huge image files; textured roughness; `mesh_attribute` textures
//! and the PLY attributes they keep. The rendered results against Mitsuba are
//! `crates/cli/tests/it/mitsuba_scenes.rs` (`textures`, `textures2`).

use opticks_core::bsdf::Bsdf;
use opticks_core::math::{Rgb, Vec2};
use opticks_core::scene::Scene;
use opticks_core::texture::{ColourSlot, Texture};
use opticks_io::scene_formats::mitsuba::parse;
use opticks_io::{LoadOptions, LoadedScene, SceneFileError};
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn load_in(dir: &Path, body: &str) -> Result<LoadedScene, SceneFileError> {
    let xml = format!("<scene version=\"3.0.0\">\n{body}\n</scene>");
    parse(&xml, &dir.join("test.xml"), &LoadOptions::default())
}

fn scene(body: &str) -> LoadedScene {
    load_in(Path::new("dir"), body).unwrap_or_else(|e| panic!("{e}\n{body}"))
}

fn err_in(dir: &Path, body: &str) -> String {
    match load_in(dir, body) {
        Ok(_) => panic!("should fail:\n{body}"),
        Err(e) => e.to_string(),
    }
}

fn err(body: &str) -> String {
    err_in(Path::new("dir"), body)
}

/// A folder of its own for files a test writes.
fn folder(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("opticks-mitsuba-textures-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

const CHECKER: &str = r#"<texture type="checkerboard" name="reflectance">
    <rgb name="color0" value="0.8, 0.1, 0.1"/><rgb name="color1" value="0.2, 0.6, 0.3"/>
</texture>"#;

#[test]
fn nested_and_referenced_textures_are_bound_to_their_colour() {
    let s = scene(&format!(
        r#"<texture type="checkerboard" id="shared"><rgb name="color0" value="0.5"/></texture>
        <shape type="rectangle"><bsdf type="diffuse">{CHECKER}</bsdf></shape>
        <shape type="rectangle"><bsdf type="plastic"><ref name="diffuse_reflectance" id="shared"/></bsdf></shape>
        <shape type="rectangle"><bsdf type="twosided"><bsdf type="conductor">
            <ref name="specular_reflectance" id="shared"/></bsdf></bsdf></shape>
        <emitter type="point"><point name="position" x="0" y="0" z="1"/></emitter>"#
    ));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let d = &s.description;
    let slots: Vec<(usize, ColourSlot)> = d.textures.iter().map(|b| (b.material, b.slot)).collect();
    assert_eq!(
        slots,
        [
            (0, ColourSlot::Reflectance),
            (1, ColourSlot::DiffuseReflectance),
            (2, ColourSlot::SpecularReflectance)
        ]
    );
    // The constant the core's constructor checked is the texture's largest value.
    match &d.materials[0].bsdf {
        Bsdf::Lambert(l) => assert_eq!(l.reflectance, Rgb::new(0.8, 0.6, 0.3)),
        other => panic!("{other:?}"),
    }
    assert!(d.materials[2].two_sided);
    // One top-level texture, shared.
    assert!(Arc::ptr_eq(&d.textures[1].texture, &d.textures[2].texture));
    assert!(matches!(*d.textures[0].texture, Texture::Checkerboard(_)));
    // Mitsuba's rectangle UVs.
    assert_eq!(d.meshes[0].uvs, [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]);
    // The scene builds, and evaluates the checkerboard at the hit's UV.
    let scene = Scene::build(d).expect("builds");
    let mut slot = None;
    let m = scene.material_at(0, opticks_core::math::Vec3::new(-0.5, -0.5, 0.0), &mut slot); // uv (0.25, 0.25)
    assert_eq!(m.bsdf.max_albedo(), Rgb::new(0.8, 0.1, 0.1));
    let mut slot = None;
    let m = scene.material_at(0, opticks_core::math::Vec3::new(0.5, -0.5, 0.0), &mut slot); // uv (0.75, 0.25)
    assert_eq!(m.bsdf.max_albedo(), Rgb::new(0.2, 0.6, 0.3));
}

#[test]
fn bitmaps_read_their_file_and_obj_vt_is_flipped_as_mitsuba() {
    let dir = folder("bitmap");
    let mut img = image::RgbImage::new(2, 1);
    img.put_pixel(0, 0, image::Rgb([255, 255, 255]));
    img.put_pixel(1, 0, image::Rgb([0, 128, 255]));
    img.save(dir.join("t.png")).unwrap();
    std::fs::write(
        dir.join("q.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0.25\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    let body = |raw: &str, flip: &str| {
        format!(
            r#"<shape type="obj"><string name="filename" value="q.obj"/>{flip}
            <bsdf type="diffuse"><texture type="bitmap" name="reflectance">
                <string name="filename" value="t.png"/>{raw}
                <string name="filter_type" value="nearest"/><string name="wrap_mode" value="clamp"/>
            </texture></bsdf></shape>"#
        )
    };
    let s = load_in(&dir, &body("", "")).unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    assert_eq!(s.description.meshes[0].uvs, [Vec2::new(0.0, 0.75), Vec2::new(1.0, 1.0), Vec2::new(0.0, 0.0)]);
    let Texture::Bitmap(b) = &*s.description.textures[0].texture else { panic!() };
    assert_eq!(b.size(), (2, 1));
    // sRGB 128 → linear 0.2158.
    assert!((b.texels()[1].y - 0.215_860_5).abs() < 1e-5, "{}", b.texels()[1]);
    let raw = load_in(&dir, &body(r#"<boolean name="raw" value="true"/>"#, "")).unwrap();
    let Texture::Bitmap(b) = &*raw.description.textures[0].texture else { panic!() };
    assert!((b.texels()[1].y - 128.0 / 255.0).abs() < 1e-6);
    let kept = load_in(&dir, &body("", r#"<boolean name="flip_tex_coords" value="false"/>"#)).unwrap();
    assert_eq!(kept.description.meshes[0].uvs[0], Vec2::new(0.0, 0.25));
}

#[test]
fn bad_textures_are_located_errors() {
    let e = err(
        r#"<shape type="rectangle"><bsdf type="diffuse"><texture type="noise" name="reflectance"/></bsdf></shape>"#,
    );
    assert!(
        e.contains("unsupported texture type \"noise\" (supported: bitmap, checkerboard, mesh_attribute, rawconstant)"),
        "{e}"
    );
    assert!(e.contains("test.xml:2:"), "{e}");
    let e = err(
        r#"<shape type="rectangle"><bsdf type="diffuse"><texture type="checkerboard" name="albedo"/></bsdf></shape>"#,
    );
    assert!(e.contains("a texture needs name=\"reflectance\""), "{e}");
    let e =
        err(r#"<shape type="rectangle"><bsdf type="diffuse"><texture type="checkerboard" name="reflectance">
        <rgb name="color0" value="2"/></texture></bsdf></shape>"#);
    assert!(e.contains("reflectance") && e.contains("exceeds 1"), "{e}");
    let e = err(
        r#"<bsdf type="diffuse" id="b"/><shape type="rectangle"><bsdf type="diffuse"><ref name="reflectance" id="b"/></bsdf></shape>"#,
    );
    assert!(e.contains("\"b\" is not the id of a top-level <texture>"), "{e}");
    let e = err(r#"<shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.5"/>
        <texture type="checkerboard" name="reflectance"/></bsdf></shape>"#);
    assert!(e.contains("given twice"), "{e}");
    let e = err(r#"<shape type="rectangle"><bsdf type="diffuse"><texture type="bitmap" name="reflectance">
        <string name="filename" value="t.png"/><string name="wrap_mode" value="tile"/></texture></bsdf></shape>"#);
    assert!(e.contains("unknown wrap_mode \"tile\""), "{e}");
}

#[test]
fn bad_and_huge_image_files_are_errors_naming_the_file() {
    let dir = folder("bad");
    let tex = |file: &str| {
        format!(
            r#"<shape type="rectangle"><bsdf type="diffuse"><texture type="bitmap" name="reflectance">
            <string name="filename" value="{file}"/></texture></bsdf></shape>"#
        )
    };
    let e = err_in(&dir, &tex("missing.png"));
    assert!(e.contains("missing.png") && e.contains("cannot read"), "{e}");
    std::fs::write(dir.join("junk.png"), b"not an image").unwrap();
    let e = err_in(&dir, &tex("junk.png"));
    assert!(e.contains("junk.png"), "{e}");
    std::fs::write(dir.join("junk.exr"), b"not an exr").unwrap();
    let e = err_in(&dir, &tex("junk.exr"));
    assert!(e.contains("junk.exr"), "{e}");
    let e = err_in(&dir, &tex("image.tga"));
    assert!(e.contains("image.tga"), "{e}");
    // A JPEG whose header claims 60000 × 60000 pixels: refused from the header, no decode.
    let mut jpeg = vec![0xFF, 0xD8, 0xFF, 0xC0, 0x00, 0x11, 0x08];
    jpeg.extend(60000u16.to_be_bytes());
    jpeg.extend(60000u16.to_be_bytes());
    jpeg.extend([3, 1, 0x11, 0, 2, 0x11, 0, 3, 0x11, 0, 0xFF, 0xD9]);
    std::fs::write(dir.join("huge.jpg"), &jpeg).unwrap();
    let e = err_in(&dir, &tex("huge.jpg"));
    assert!(e.contains("huge.jpg"), "{e}");
    assert!(e.contains("60000 × 60000") || e.contains("header"), "{e}");
}

/// A rough plastic's colours take textures: the texel's colour at the hit, the coating's tables
/// and sampling weight those of the material as loaded (Mitsuba's weight is its texture's mean).
#[test]
fn roughplastic_colours_take_textures() {
    let s = scene(
        r#"<shape type="rectangle"><bsdf type="roughplastic">
             <texture type="checkerboard" name="diffuse_reflectance"><rgb name="color0" value="0.8, 0.1, 0.1"/>
               <rgb name="color1" value="0.2, 0.6, 0.3"/></texture></bsdf></shape>
           <emitter type="point"><point name="position" x="0" y="0" z="1"/></emitter>"#,
    );
    let scene = Scene::build(&s.description).expect("builds");
    let at = |x: f32| {
        let mut slot = None;
        match &scene.material_at(0, opticks_core::math::Vec3::new(x, -0.5, 0.0), &mut slot).bsdf {
            Bsdf::RoughPlastic(p) => p.clone(),
            other => panic!("{other:?}"),
        }
    };
    let (a, b) = (at(-0.5), at(0.5));
    assert_eq!(
        (a.diffuse_reflectance, b.diffuse_reflectance),
        (Rgb::new(0.8, 0.1, 0.1), Rgb::new(0.2, 0.6, 0.3))
    );
    assert_eq!(a.internal_reflectance(), b.internal_reflectance());
}

#[test]
fn roughness_textures_are_bound_and_checked_at_their_element() {
    let s = scene(
        r#"<shape type="rectangle"><bsdf type="roughconductor">
            <texture type="checkerboard" name="alpha_u"><float name="color0" value="0.05"/><float name="color1" value="0.3"/></texture>
            <texture type="checkerboard" name="alpha_v"><rgb name="color0" value="0.1, 0.2, 0.6"/></texture>
        </bsdf></shape>
        <shape type="rectangle"><bsdf type="roughdielectric"><texture type="checkerboard" name="alpha"/></bsdf></shape>
        <emitter type="point"><point name="position" x="0" y="0" z="1"/></emitter>"#,
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let d = &s.description;
    let slots: Vec<(usize, ColourSlot)> = d.textures.iter().map(|b| (b.material, b.slot)).collect();
    assert_eq!(slots, [(0, ColourSlot::AlphaU), (0, ColourSlot::AlphaV), (1, ColourSlot::Alpha)]);
    // The constructor saw the textures' largest eval_1 (a colour's mean: 0.3 for rgb 0.1, 0.2, 0.6).
    match &d.materials[0].bsdf {
        Bsdf::RoughConductor(c) => {
            assert_eq!(c.microfacet.alpha_u, 0.3);
            assert!((c.microfacet.alpha_v - 0.3).abs() < 1e-6, "{}", c.microfacet.alpha_v);
        }
        other => panic!("{other:?}"),
    }
    let scene = Scene::build(d).expect("builds");
    let mut slot = None;
    // uv (¾, ¼): color0 (Mitsuba's eval_1 swaps the squares of eval).
    let m = scene.material_at(0, opticks_core::math::Vec3::new(0.5, -0.5, 0.0), &mut slot);
    let Bsdf::RoughConductor(c) = &m.bsdf else { panic!() };
    assert_eq!(c.microfacet.alpha_u, 0.05);
    assert!((c.microfacet.alpha_v - 0.3).abs() < 1e-6, "{}", c.microfacet.alpha_v);
    let mut slot = None;
    let m = scene.material_at(0, opticks_core::math::Vec3::new(-0.5, -0.5, 0.0), &mut slot); // uv (¼, ¼)
    let Bsdf::RoughConductor(c) = &m.bsdf else { panic!() };
    assert_eq!(c.microfacet.alpha_u, 0.3);
    assert!((c.microfacet.alpha_v - 0.2).abs() < 1e-6, "{}", c.microfacet.alpha_v); // Mitsuba's default color1 0.2
    let e = err(r#"<shape type="rectangle"><bsdf type="roughconductor">
        <texture type="checkerboard" name="alpha"><float name="color0" value="1.5"/></texture></bsdf></shape>"#);
    assert!(e.contains("test.xml:3:9") && e.contains("not a roughness in [0, 1]"), "{e}");
    let e = err(r#"<shape type="rectangle"><bsdf type="roughconductor"><float name="alpha" value="0.1"/>
        <texture type="checkerboard" name="alpha"/></bsdf></shape>"#);
    assert!(e.contains("given twice"), "{e}");
    let e = err(
        r#"<shape type="rectangle"><bsdf type="conductor"><texture type="checkerboard" name="alpha"/></bsdf></shape>"#,
    );
    assert!(e.contains("name=\"alpha\""), "{e}");
}

#[test]
fn an_area_emitters_radiance_takes_a_texture_on_shapes_with_uvs() {
    // A checkerboard radiance on a rectangle: the light's power is its exact mean (half of
    // each colour) times π·A (A = 4).
    let s = scene(
        r#"<shape type="rectangle"><emitter type="area"><texture type="checkerboard" name="radiance">
        <rgb name="color0" value="2, 0, 1"/><rgb name="color1" value="0, 4, 1"/></texture></emitter></shape>"#,
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let emission = s.description.meshes[0].emission.as_ref().unwrap();
    assert!(matches!(emission.texture.as_deref(), Some(Texture::Checkerboard(_))));
    let built = Scene::build(&s.description).unwrap();
    let want = Rgb::new(1.0, 2.0, 1.0) * (4.0 * std::f32::consts::PI);
    assert!((built.lights[0].power() - want).abs().max_element() < 1e-4, "{}", built.lights[0].power());
    // Given twice: an error at the texture.
    let e = err(r#"<shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/>
        <texture type="checkerboard" name="radiance"/></emitter></shape>"#);
    assert!(e.contains("given twice"), "{e}");
    // A mesh attribute the shape does not have: the scene's error, at the shape.
    let s = scene(
        r#"<shape type="rectangle" id="panel"><emitter type="area">
        <texture type="mesh_attribute" name="radiance"><string name="name" value="vertex_c"/></texture>
        </emitter></shape>"#,
    );
    let e = Scene::build(&s.description).unwrap_err().to_string();
    assert!(e.contains("test.xml:2") && e.contains("mesh attribute \"vertex_c\""), "{e}");
    // A shape without texture coordinates (an OBJ without `vt`): an error at its emitter.
    let dir = folder("emitter-uvs");
    std::fs::write(dir.join("q.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let e = err_in(
        &dir,
        r#"<shape type="obj" id="panel"><string name="filename" value="q.obj"/>
        <emitter type="area"><texture type="checkerboard" name="radiance"/></emitter></shape>"#,
    );
    assert!(e.contains("test.xml:3:9") && e.contains("'panel' has no texture coordinates"), "{e}");
}

/// A PLY quad (two triangles) with a float vertex colour `color_0..2`, a uchar `red green blue`
/// face colour... as Mitsuba groups them, and a one-channel face attribute `rough_0`.
fn attributed_ply(dir: &Path) {
    std::fs::write(
        dir.join("q.ply"),
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
         property float color_0\nproperty float color_1\nproperty float color_2\nelement face 2\n\
         property list uchar int vertex_indices\nproperty float rough_0\nproperty uchar r\nproperty uchar g\n\
         property uchar b\nend_header\n\
         -1 -1 0 0.1 0.2 0.3\n1 -1 0 0.4 0.5 0.6\n1 1 0 0.7 0.8 0.9\n-1 1 0 0 0 0\n\
         3 0 1 2 0.25 1 0 0\n3 0 2 3 0.5 0 1 0\n",
    )
    .unwrap();
}

#[test]
fn an_area_emitters_radiance_may_be_a_mesh_attribute() {
    // The PLY quad's vertex colours, scaled by 2, as the radiance: each triangle's mean is its
    // corners' mean (the attribute is linear over it): (0.4, 0.5, 0.6) and (0.8, 1, 1.2)/3 on
    // two triangles of area 2, so Φ = π·4·2·(1/3, 5/12, 1/2).
    let dir = folder("emitter-attributes");
    attributed_ply(&dir);
    let s = load_in(
        &dir,
        r#"<shape type="ply"><string name="filename" value="q.ply"/><emitter type="area">
        <texture type="mesh_attribute" name="radiance"><string name="name" value="vertex_color"/>
        <float name="scale" value="2"/></texture></emitter></shape>"#,
    )
    .unwrap();
    assert_eq!(s.description.meshes[0].attributes.len(), 1);
    let scene = Scene::build(&s.description).unwrap();
    let want = Rgb::new(1.0 / 3.0, 5.0 / 12.0, 0.5) * (8.0 * std::f32::consts::PI);
    assert!((scene.lights[0].power() - want).abs().max_element() < 1e-4, "{}", scene.lights[0].power());
}

#[test]
fn mesh_attribute_textures_read_the_plys_attributes_they_name() {
    let dir = folder("attributes");
    attributed_ply(&dir);
    let body = |bsdf: &str| {
        format!(
            r#"<texture type="mesh_attribute" id="rough"><string name="name" value="face_rough"/></texture>
            <bsdf type="twosided" id="b">{bsdf}</bsdf>
            <shape type="ply"><string name="filename" value="q.ply"/><ref id="b"/></shape>
            <emitter type="point"><point name="position" x="0" y="0" z="1"/></emitter>"#
        )
    };
    let s = load_in(
        &dir,
        &body(
            r#"<bsdf type="diffuse"><texture type="mesh_attribute" name="reflectance">
            <string name="name" value="vertex_color"/><float name="scale" value="0.5"/></texture></bsdf>"#,
        ),
    )
    .unwrap();
    let mesh = &s.description.meshes[0];
    // Only the attribute a texture reads is kept.
    let names: Vec<&str> = mesh.attributes.iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["vertex_color"]);
    assert_eq!(mesh.attributes[0].channels, 3);
    assert_eq!(mesh.attributes[0].values[1], Rgb::new(0.4, 0.5, 0.6));
    let scene = Scene::build(&s.description).unwrap();
    // Vertex 1 (1, -1, 0) of triangle 0: its colour × 0.5.
    let mut slot = None;
    let m = scene.material_at(0, opticks_core::math::Vec3::new(1.0, -1.0, 0.0), &mut slot);
    assert!(
        (m.bsdf.max_albedo() - Rgb::new(0.2, 0.25, 0.3)).abs().max_element() < 1e-6,
        "{}",
        m.bsdf.max_albedo()
    );
    // A face attribute on a roughness, through a <ref> to a top-level texture.
    let s =
        load_in(&dir, &body(r#"<bsdf type="roughconductor"><ref name="alpha" id="rough"/></bsdf>"#)).unwrap();
    let names: Vec<&str> = s.description.meshes[0].attributes.iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["face_rough"]);
    let scene = Scene::build(&s.description).unwrap();
    let mut slot = None;
    let m = scene.material_at(1, opticks_core::math::Vec3::new(-0.5, 0.5, 0.0), &mut slot);
    let Bsdf::RoughConductor(c) = &m.bsdf else { panic!() };
    assert_eq!((c.microfacet.alpha_u, c.microfacet.alpha_v), (0.5, 0.5));
    // Mitsuba keeps integer colours as written (255, not 1): as a reflectance that exceeds 1.
    let s = load_in(
        &dir,
        &body(
            r#"<bsdf type="diffuse"><texture type="mesh_attribute" name="reflectance">
            <string name="name" value="face_color"/></texture></bsdf>"#,
        ),
    )
    .unwrap();
    assert_eq!(s.description.meshes[0].attributes[0].values, [Rgb::X, Rgb::Y]);
    // An attribute the mesh does not have, a bad name: errors naming them.
    let s = load_in(
        &dir,
        &body(
            r#"<bsdf type="diffuse"><texture type="mesh_attribute" name="reflectance">
            <string name="name" value="vertex_missing"/></texture></bsdf>"#,
        ),
    )
    .unwrap();
    let e = Scene::build(&s.description).unwrap_err().to_string();
    assert!(e.contains("has no attribute \"vertex_missing\""), "{e}");
    let e = err_in(
        &dir,
        &body(
            r#"<bsdf type="diffuse"><texture type="mesh_attribute" name="reflectance">
            <string name="name" value="color"/></texture></bsdf>"#,
        ),
    );
    assert!(e.contains("must start with \"vertex_\" or \"face_\""), "{e}");
    let e = err_in(
        &dir,
        &body(r#"<bsdf type="diffuse"><texture type="mesh_attribute" name="reflectance"/></bsdf>"#),
    );
    assert!(e.contains("missing <string name=\"name\""), "{e}");
}

/// Issue 26: the texel limit is the caller's ([`opticks_io::LoadLimits::max_texels`]), for
/// bitmap textures (PNG) and environment maps (EXR) alike: a file over a lowered limit is
/// refused naming the file, its size, the limit and the option that raises it; the same file
/// loads at a limit of exactly its size.
#[test]
fn the_texel_limit_is_the_callers_for_textures_and_environment_maps() {
    let dir = folder("limits");
    image::RgbImage::from_pixel(64, 32, image::Rgb([200, 100, 50])).save(dir.join("t.png")).unwrap();
    opticks_io::image_file::write_image(&dir.join("sky.exr"), 64, 32, &[0.5; 64 * 32 * 3], 0.0).unwrap();
    let bitmap = r#"<shape type="rectangle"><bsdf type="diffuse"><texture type="bitmap" name="reflectance">
        <string name="filename" value="t.png"/></texture></bsdf></shape>"#;
    let envmap = r#"<emitter type="envmap"><string name="filename" value="sky.exr"/></emitter>"#;
    let load = |body: &str, max_texels: u64| {
        let xml = format!("<scene version=\"3.0.0\">\n{body}\n</scene>");
        let limits = opticks_io::LoadLimits { max_texels, ..Default::default() };
        parse(&xml, &dir.join("test.xml"), &LoadOptions { limits, ..Default::default() })
    };
    for (body, file) in [(bitmap, "t.png"), (envmap, "sky.exr")] {
        let e = load(body, 2047).map(|_| ()).unwrap_err().to_string();
        for part in [file, "64 × 32 = 2048 texels", "the limit of 2047", "--max-texels"] {
            assert!(e.contains(part), "{part:?} missing: {e}");
        }
        load(body, 2048).unwrap_or_else(|e| panic!("{e}"));
        assert!(load_in(&dir, body).is_ok(), "the default limit admits it");
    }
}

/// `mask`: its opacity (a float, default 0.5, or a texture) is bound as the material's
/// [`ColourSlot::Opacity`] beside the nested BSDF's own textures, `twosided` passes through
/// either way round, an opacity of 1 masks nothing; a bad mask is a located error.
#[test]
fn masks_bind_their_opacity_and_bad_ones_are_located() {
    let s = scene(&format!(
        r#"<shape type="rectangle"><bsdf type="mask"><bsdf type="diffuse">{CHECKER}</bsdf></bsdf></shape>
        <shape type="rectangle"><bsdf type="mask"><float name="opacity" value="0.3"/>
            <bsdf type="twosided"><bsdf type="diffuse"/></bsdf></bsdf></shape>
        <shape type="rectangle"><bsdf type="mask">
            <texture type="checkerboard" name="opacity"><rgb name="color0" value="1"/><rgb name="color1" value="0"/></texture>
            <bsdf type="diffuse"/></bsdf></shape>
        <shape type="rectangle"><bsdf type="mask"><float name="opacity" value="1"/><bsdf type="diffuse"/></bsdf></shape>
        <emitter type="point"><point name="position" x="0" y="0" z="1"/></emitter>"#
    ));
    let d = &s.description;
    let opacity = |m: usize| -> Vec<f32> {
        d.textures
            .iter()
            .filter(|t| t.material == m && t.slot == ColourSlot::Opacity)
            .map(|t| t.texture.eval_1(Vec2::new(0.1, 0.1), Rgb::ZERO))
            .collect()
    };
    let material = |shape: usize| d.meshes[shape].material;
    assert_eq!(opacity(material(0)), [0.5], "Mitsuba's default");
    assert!(d.textures.iter().any(|t| t.material == material(0) && t.slot == ColourSlot::Reflectance));
    assert_eq!(opacity(material(1)), [0.3]);
    assert!(d.materials[material(1)].two_sided);
    assert_eq!(opacity(material(2)).len(), 1);
    assert!(opacity(material(3)).is_empty(), "opacity 1: nothing masked");
    Scene::build(d).unwrap();

    let e = err(
        r#"<shape type="rectangle"><bsdf type="mask"><float name="opacity" value="1.5"/><bsdf type="diffuse"/></bsdf></shape>"#,
    );
    assert!(e.starts_with("dir/test.xml:2:") && e.contains("opacity must lie in [0, 1]"), "{e}");
    let e = err(r#"<shape type="rectangle"><bsdf type="mask"/></shape>"#);
    assert!(e.contains("a mask BSDF needs one nested <bsdf> or <ref>"), "{e}");
    let e = err(
        r#"<shape type="rectangle"><bsdf type="mask"><bsdf type="mask"><bsdf type="diffuse"/></bsdf></bsdf></shape>"#,
    );
    assert!(e.contains("a mask inside a mask"), "{e}");
}

/// A `blendbsdf` weight given as a texture is bound as [`ColourSlot::Weight`], the blend built
/// with its largest value, and the scene blends by the texture's value at each point: here a
/// checkerboard of weights 0.2 and 0.9 over a diffuse red and a diffuse blue.
#[test]
fn a_textured_blend_weight_varies_over_the_surface() {
    let s = scene(
        r#"<shape type="rectangle"><bsdf type="blendbsdf">
            <texture type="checkerboard" name="weight"><rgb name="color0" value="0.2"/><rgb name="color1" value="0.9"/></texture>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0, 0"/></bsdf>
            <bsdf type="diffuse"><rgb name="reflectance" value="0, 0, 0.8"/></bsdf>
        </bsdf></shape>
        <emitter type="point"><point name="position" x="0" y="0" z="1"/></emitter>"#,
    );
    let d = &s.description;
    assert!(d.textures.iter().any(|t| t.slot == ColourSlot::Weight));
    let Bsdf::Blend(b) = &d.materials[d.meshes[0].material].bsdf else { panic!("a blend") };
    assert!((b.weight - 0.9).abs() < 1e-6, "built with the largest weight: {}", b.weight);
    let scene = Scene::build(d).unwrap();
    let weight_at = |x: f32, y: f32| {
        let p = opticks_core::math::Vec3::new(x, y, 0.0);
        let prim = (0..scene.triangles.len() as u32)
            .find(|&t| {
                let (b1, b2) = scene.triangles[t as usize].barycentrics(p);
                b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0
            })
            .unwrap();
        let mut resolved = None;
        match &scene.material_at(prim, p, &mut resolved).bsdf {
            Bsdf::Blend(b) => b.weight,
            _ => panic!("a blend"),
        }
    };
    let mut seen = [weight_at(-0.5, -0.5), weight_at(0.5, -0.5)];
    seen.sort_by(f32::total_cmp);
    assert!((seen[0] - 0.2).abs() < 1e-6 && (seen[1] - 0.9).abs() < 1e-6, "{seen:?}");
    let e = err(r#"<shape type="rectangle"><bsdf type="blendbsdf">
            <texture type="checkerboard" name="weight"><rgb name="color0" value="1.5"/></texture>
            <bsdf type="diffuse"/><bsdf type="diffuse"/></bsdf></shape>"#);
    assert!(e.contains("weight must lie in [0, 1]"), "{e}");
}
