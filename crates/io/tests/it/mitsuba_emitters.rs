//! The Mitsuba 3 XML loader's emitters: point, spot, area and directional lights, and the
//! `constant` and `envmap` environments (their parameters, defaults and located errors).

use crate::mitsuba::scene;
use opticks_core::math::{Mat3, Rgb, Vec3};
use opticks_core::scene::{EnvironmentRadiance, Source};
use opticks_io::LoadOptions;
use opticks_io::scene_formats::mitsuba::parse;

#[test]
fn emitters() {
    let s = scene(
        r#"<emitter type="point"><point name="position" x="1" y="2" z="3"/><rgb name="intensity" value="4 5 6"/></emitter>
               <emitter type="point" id="lamp">
                 <transform name="to_world"><translate value="7, 8, 9"/></transform><float name="intensity" value="2"/>
               </emitter>
               <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="3"/></emitter></shape>"#,
    );
    let p = &s.description.point_lights;
    assert_eq!(
        (p[0].name.as_str(), p[0].position, p[0].intensity),
        ("point_0", Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0))
    );
    assert_eq!(
        (p[1].name.as_str(), p[1].position, p[1].intensity),
        ("lamp", Vec3::new(7.0, 8.0, 9.0), Rgb::splat(2.0))
    );
    assert_eq!(p[1].source, Source { file: "dir/test.xml".into(), line: 3 });
    assert_eq!(s.description.meshes[0].emission.as_ref().map(|e| e.radiance), Some(Rgb::splat(3.0)));
}

/// `constant` and `envmap`: their parameters, defaults and names, the map read from the XML
/// file's folder, and the lights they become.
#[test]
fn environment_emitters() {
    let folder = opticks_io_test_folder("env");
    let map = folder.join("map.exr");
    // 3 × 2 texels, row-major from the top row.
    let texels: Vec<f32> = (0..6).flat_map(|i| [i as f32, 0.5, 2.0]).collect();
    opticks_io::image_file::write_image(&map, 3, 2, &texels, 0.0).unwrap();
    let xml = r#"<scene version="3.0.0">
        <emitter type="constant"><rgb name="radiance" value="0.5, 1, 2"/></emitter>
        <emitter type="constant" id="grey"/>
        <emitter type="envmap" id="sky">
            <string name="filename" value="map.exr"/><float name="scale" value="3"/>
            <boolean name="mis_compensation" value="true"/>
            <transform name="to_world"><rotate y="1" angle="90"/><translate x="5"/></transform>
        </emitter>
        <emitter type="envmap"><string name="filename" value="map.exr"/></emitter>
        <shape type="rectangle"/>
    </scene>"#;
    let s = parse(xml, &folder.join("scene.xml"), &LoadOptions::default()).unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let e = &s.description.environment_lights;
    assert_eq!(e.len(), 4);
    let names: Vec<&str> = e.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["constant_0", "grey", "sky", "envmap_3"]);
    assert_eq!(e[0].radiance, EnvironmentRadiance::Constant(Rgb::new(0.5, 1.0, 2.0)));
    assert_eq!(e[1].radiance, EnvironmentRadiance::Constant(Rgb::ONE));
    assert_eq!(e[0].to_world, Mat3::IDENTITY);
    assert_eq!(e[2].source.line, 4);
    match &e[2].radiance {
        EnvironmentRadiance::Map { width, height, texels, scale, file } => {
            assert_eq!((*width, *height, *scale), (3, 2, 3.0));
            assert_eq!(texels[4], Rgb::new(4.0, 0.5, 2.0));
            assert!(file.as_ref().unwrap().ends_with("map.exr"));
        }
        other => panic!("{other:?}"),
    }
    // rotate y by 90°: the map's -z (u = 0) is the world's -x; the translation is ignored.
    assert!((e[2].to_world * Vec3::NEG_Z - Vec3::NEG_X).length() < 1e-6, "{}", e[2].to_world);
    assert!(matches!(&e[3].radiance, EnvironmentRadiance::Map { scale, .. } if *scale == 1.0));
    let scene = opticks_core::scene::Scene::build(&s.description).unwrap();
    assert_eq!(scene.lights.len(), 4);
    assert!(scene.lights.iter().all(|l| matches!(l, opticks_core::light::Light::Environment(_))));
}

/// The errors of environment emitters, located at the element that gave the value.
#[test]
fn bad_environment_emitters_are_located() {
    let folder = opticks_io_test_folder("bad-env");
    let negative = folder.join("negative.exr");
    opticks_io::image_file::write_image(&negative, 2, 1, &[1.0, 1.0, 1.0, 0.0, -2.0, 0.0], 0.0).unwrap();
    let load = |body: &str| {
        let xml = format!("<scene version=\"3.0.0\">\n{body}\n</scene>");
        match parse(&xml, &folder.join("scene.xml"), &LoadOptions::default()) {
            Ok(_) => panic!("should fail:\n{xml}"),
            Err(e) => e.to_string(),
        }
    };
    let cases: [(&str, &str); 9] = [
        (
            r#"<emitter type="envmap"/>"#,
            "scene.xml:2:1: <emitter type=\"envmap\">: an envmap emitter needs a `filename`",
        ),
        (
            r#"<emitter type="envmap"><string name="filename" value="missing.exr"/></emitter>"#,
            "missing.exr: cannot read",
        ),
        (
            r#"<emitter type="envmap"><string name="filename" value="negative.exr"/></emitter>"#,
            "negative.exr: environment map: texel (1, 0) is [0.0, -2.0, 0.0]: texels must be finite and non-negative",
        ),
        (
            r#"<emitter type="envmap"><string name="filename" value="negative.exr"/><float name="scale" value="-1"/></emitter>"#,
            "scene.xml:2:70: <float name=\"scale\">: `scale` -1 must be finite and non-negative",
        ),
        (
            r#"<emitter type="envmap"><string name="filename" value="x.exr"/><transform name="to_world"><scale value="2"/></transform></emitter>"#,
            "the to_world of an environment must be a rotation",
        ),
        (
            r#"<emitter type="envmap"><string name="filename" value="x.exr"/><transform name="to_world"><rotate y="1" z="1" angle="30"/></transform></emitter>"#,
            "a <rotate> axis must have unit length",
        ),
        (
            r#"<emitter type="constant"><rgb name="radiance" value="-1"/></emitter>"#,
            "<rgb name=\"radiance\">: emission [-1.0, -1.0, -1.0] must be finite and non-negative",
        ),
        (
            r#"<shape type="rectangle"><emitter type="envmap"><string name="filename" value="negative.exr"/></emitter></shape>"#,
            "a envmap emitter lights the scene from infinity and cannot be nested inside a shape",
        ),
        (
            r#"<emitter type="constant"><bsdf type="diffuse"/></emitter>"#,
            "unsupported element inside a constant emitter",
        ),
    ];
    for (body, want) in cases {
        let e = load(body);
        assert!(e.contains(want), "{body}:\n  got  {e}\n  want {want}");
    }
}

/// A spot's `texture` (nested or a `<ref>`) reaches the light; a missing file, a foreign
/// element, a cone of 90° or more, a mirrored frame and a mesh attribute are errors at their
/// element.
#[test]
fn spot_textures_load_and_bad_ones_are_located() {
    let folder = opticks_io_test_folder("spot-texture");
    let checker = r#"<texture type="checkerboard" name="texture"><rgb name="color0" value="0.2"/></texture>"#;
    let xml = format!(
        r#"<scene version="3.0.0"><texture type="checkerboard" id="c"/>
        <emitter type="spot">{checker}</emitter>
        <emitter type="spot"><ref name="texture" id="c"/></emitter><shape type="rectangle"/></scene>"#
    );
    let s = parse(&xml, &folder.join("scene.xml"), &LoadOptions::default()).unwrap();
    assert!(s.description.point_lights.iter().all(|l| l.texture.is_some()));
    let load = |body: &str| {
        let xml = format!("<scene version=\"3.0.0\">\n{body}\n</scene>");
        match parse(&xml, &folder.join("scene.xml"), &LoadOptions::default()) {
            Ok(_) => panic!("should fail:\n{xml}"),
            Err(e) => e.to_string(),
        }
    };
    let bitmap = |file: &str| {
        format!(r#"<texture type="bitmap" name="texture"><string name="filename" value="{file}"/></texture>"#)
    };
    let cases = [
        (format!(r#"<emitter type="spot">{}</emitter>"#, bitmap("missing.png")), "missing.png"),
        (format!(r#"<emitter type="spot"><bsdf type="diffuse"/>{checker}</emitter>"#), "scene.xml:2:22: <bsdf type=\"diffuse\">: unsupported element inside a spot emitter"),
        (r#"<emitter type="spot"><bsdf type="diffuse" name="texture"/></emitter>"#.to_string(), "scene.xml:2:22: <bsdf type=\"diffuse\" name=\"texture\">: unsupported element inside a spot emitter"),
        (
            format!(r#"<emitter type="spot"><float name="cutoff_angle" value="90"/>{checker}</emitter>"#),
            "scene.xml:2:22: <float name=\"cutoff_angle\">: a spot projecting a texture needs a cutoff_angle below 90°",
        ),
        (
            format!(r#"<emitter type="spot"><transform name="to_world"><scale x="-1"/></transform>{checker}</emitter>"#),
            "needs a to_world that is a rotation",
        ),
        (
            r#"<emitter type="spot"><texture type="mesh_attribute" name="texture"><string name="name" value="vertex_color"/></texture></emitter>"#.to_string(),
            "scene.xml:2:22: <texture type=\"mesh_attribute\" name=\"texture\">: a spot emitter cannot project a mesh_attribute texture",
        ),
    ];
    for (body, want) in cases {
        let e = load(&body);
        assert!(e.contains(want), "{body}:\n  got  {e}\n  want {want}");
    }
}

/// A folder of its own for files a test writes.
fn opticks_io_test_folder(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("opticks-mitsuba-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}
