//! One scene, five formats: the Cornell box written in VRML97 (by hand, with the Opticks
//! extension), OBJ/MTL, glTF 2.0 and Radiance (`testdata/radiance/make_cornell.py`; its light
//! reflects nothing, as a Radiance `light` does) must render to the same image as its Mitsuba XML — the same
//! up to noise: their relative MSE against each other is what two independent traces of the
//! XML scene show between themselves.

use opticks_testkit as common;

use common::*;
use opticks_core::bsdf::{Bsdf, Lambert, Material};
use opticks_core::math::Rgb;
use opticks_core::scene::Scene;
use opticks_core::sensor::Pinhole;
use opticks_io::compare::compare;
use std::path::Path;

const PATHS: u64 = 1_000_000;

fn render(path: &Path, seed: u64, camera: &Pinhole) -> Vec<f32> {
    let loaded = opticks_io::scene_formats::load_scene(path).unwrap();
    let scene = Scene::build(&loaded.description).unwrap();
    trace_and_render(&scene, camera, PATHS, seed).to_rgb_f32()
}

#[test]
fn vrml_obj_gltf_and_radiance_cornell_boxes_render_like_the_mitsuba_xml() {
    let xml = scene_file("cornell", "scene.xml");
    // The XML's camera for every format (OBJ has none; glTF's image is 512 px high).
    let camera = camera(&load("cornell"));
    let a = render(&xml, 1, &camera);
    let b = render(&xml, 2, &camera);
    let noise = compare(&a, &b).relmse;
    eprintln!("XML vs XML (two seeds): relMSE {noise:.3e}");
    // A Radiance light reflects nothing: the XML with its light black is the Radiance box's
    // reference (with it reflecting, the Radiance image is 1% darker in red).
    let mut dark = opticks_io::scene_formats::load_scene(&xml).unwrap().description;
    dark.materials.push(Material {
        name: "black".into(),
        bsdf: Bsdf::Lambert(Lambert::new(Rgb::ZERO).unwrap()),
        two_sided: false,
    });
    for m in dark.meshes.iter_mut().filter(|m| m.emission.is_some()) {
        m.material = dark.materials.len() - 1;
    }
    let dark = trace_and_render(&Scene::build(&dark).unwrap(), &camera, PATHS, 1).to_rgb_f32();
    for (i, file) in [
        "testdata/vrml/cornell.wrl",
        "testdata/obj/cornell.obj",
        "testdata/gltf/cornell.gltf",
        "testdata/radiance/cornell.rad",
    ]
    .iter()
    .enumerate()
    {
        let other = render(&repo().join(file), 10 + i as u64, &camera);
        let c = compare(&other, if file.ends_with(".rad") { &dark } else { &a });
        eprintln!("{file} vs XML: relMSE {:.3e}, mean ratio {:?}", c.relmse, c.mean_ratio);
        // Two independent estimates of the same image: relMSE ≈ the XML-vs-XML level (±15%).
        assert!(c.relmse < 1.15 * noise, "{file}: relMSE {} vs noise {noise}", c.relmse);
        for r in c.mean_ratio {
            assert!((r - 1.0).abs() < 0.01, "{file}: mean ratio {r}");
        }
    }
}

/// Mean of the RGB values of pixel rows `y0..y1` and columns `x0..x1` of a `width`-wide image.
fn block_mean(rgb: &[f32], width: usize, (x0, x1): (usize, usize), (y0, y1): (usize, usize)) -> f64 {
    let mut sum = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            sum +=
                rgb[3 * (y * width + x)..3 * (y * width + x) + 3].iter().map(|&v| f64::from(v)).sum::<f64>();
        }
    }
    sum / (3 * (x1 - x0) * (y1 - y0)) as f64
}

/// VTK's vtkVRMLExporter output (testdata/vrml/vtk-scene.wrl, see testdata/README.md): its
/// meshes, camera and spot light arrive, and the traced image shows the lit floor and sphere
/// below a black sky (no environment).
#[test]
fn vtk_exported_scene_loads_and_renders() {
    use opticks_core::light::EmissionProfile;
    use opticks_core::math::Vec3;
    let loaded = opticks_io::scene_formats::load_scene(&repo().join("testdata/vrml/vtk-scene.wrl")).unwrap();
    let w = loaded.warnings.join("\n");
    eprintln!("{w}");
    assert!(w.contains("cutOffAngle 40 is beyond"), "{w}");
    let mut d = loaded.description;
    // Sphere (16 × 8: 2·16 cap + 2·16·5 band triangles), one quad plane, a cube of 6 quads.
    let tris: Vec<usize> = d.meshes.iter().map(|m| m.triangles.len()).collect();
    assert_eq!(tris, [192, 2, 12]);
    assert!(d.meshes[0].positions.iter().all(|p| (*p - Vec3::new(0.0, 0.5, 0.0)).length() < 0.5 + 1e-5));
    assert_eq!(d.directional_lights.len(), 0, "the ambient DirectionalLight (intensity 0) emits nothing");
    assert_eq!(d.point_lights.len(), 1);
    let spot = &d.point_lights[0];
    assert_eq!(spot.position, Vec3::new(1.0, 3.0, 2.0));
    assert!((spot.orientation.unwrap().n - Vec3::new(-1.0, -3.0, -2.0).normalize()).length() < 1e-5);
    let half_pi = std::f32::consts::FRAC_PI_2;
    assert_eq!(spot.profile, Some(EmissionProfile::Spot { cutoff_angle: half_pi, beam_width: half_pi }));
    let cam = d.camera.as_mut().unwrap();
    assert_eq!(cam.eye, Vec3::new(0.0, 2.0, 5.0));
    // VTK's camera looks from (0, 2, 5) at (0, 0.3, 0), down by atan(1.7/5) = 0.3277 rad, but the
    // exporter writes `orientation 1 0 0 0.3277`, which in VRML97 turns the view *up* (it writes
    // the inverse rotation): read as the file says, the view direction rises.
    let forward = (cam.target - cam.eye).normalize();
    assert!((forward - Vec3::new(0.0, 0.3277f32.sin(), -0.3277f32.cos())).length() < 1e-4, "{forward}");
    assert!((cam.fov_x_degrees - 30.0).abs() < 1e-3, "fieldOfView 0.523599 on a square image");
    // Render what VTK showed: aim at its focal point.
    cam.target = Vec3::new(0.0, 0.3, 0.0);
    (cam.width, cam.height) = (48, 48);
    let scene = Scene::build(&d).unwrap();
    let img = trace_and_render(&scene, &camera(&scene), 200_000, 5).to_rgb_f32();
    // The camera looks down at the floor: the bottom rows are lit, the top rows are sky.
    let (floor, sky) = (block_mean(&img, 48, (0, 48), (40, 48)), block_mean(&img, 48, (0, 48), (0, 3)));
    let centre = block_mean(&img, 48, (20, 28), (20, 28));
    eprintln!("VTK scene: floor {floor:.4}, centre {centre:.4}, sky {sky:.4}");
    assert!(floor > 0.0 && centre > 0.0, "floor {floor}, centre {centre}");
    assert_eq!(sky, 0.0);
}

/// OpenCTM ctmconv's VRML97 icosphere (testdata/vrml/icosphere-ctmconv.wrl) under a lamp above
/// it: the sphere is lit where it faces the lamp and the background stays black.
#[test]
fn ctmconv_icosphere_renders_lit_from_above() {
    use opticks_core::math::{Rgb, Vec3};
    use opticks_core::scene::{CameraDesc, CameraKind, PointLightDesc};
    let loaded =
        opticks_io::scene_formats::load_scene(&repo().join("testdata/vrml/icosphere-ctmconv.wrl")).unwrap();
    let mut d = loaded.description;
    assert_eq!(d.meshes[0].triangles.len(), 80);
    d.point_lights.push(PointLightDesc {
        name: "lamp".into(),
        position: Vec3::new(0.0, 3.0, 0.0),
        intensity: Rgb::splat(10.0),
        ..Default::default()
    });
    d.camera = Some(CameraDesc {
        eye: Vec3::new(0.0, 0.0, 4.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_x_degrees: 40.0,
        width: 40,
        height: 40,
        kind: CameraKind::Perspective,
        film: Default::default(),
    });
    let scene = Scene::build(&d).unwrap();
    let img = trace_and_render(&scene, &camera(&scene), 200_000, 6).to_rgb_f32();
    // The sphere (radius 1 at 4 m, 40° view) spans the middle ~30 pixels.
    let top = block_mean(&img, 40, (16, 24), (10, 16));
    let bottom = block_mean(&img, 40, (16, 24), (26, 30));
    let corner = block_mean(&img, 40, (0, 4), (0, 4));
    eprintln!("ctmconv icosphere: top {top:.4}, bottom {bottom:.4}, corner {corner:.4}");
    assert!(top > 0.0, "the side facing the lamp is lit");
    assert_eq!(bottom, 0.0, "the underside faces away from the lamp (one light, no other surface)");
    assert_eq!(corner, 0.0);
}
