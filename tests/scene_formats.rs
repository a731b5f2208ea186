//! One scene, four formats: the Cornell box written in VRML97 (by hand, with the Opticks
//! extension), OBJ/MTL and glTF 2.0 must render to the same image as its Mitsuba XML — the same
//! up to noise: their relative MSE against each other is what two independent traces of the
//! XML scene show between themselves.

mod common;

use common::*;
use opticks_core::scene::{Pinhole, Scene};
use opticks_io::compare::compare;
use std::path::Path;

const PATHS: u64 = 1_000_000;

fn render(path: &Path, seed: u64, camera: &Pinhole) -> Vec<f32> {
    let loaded = opticks_io::scene_formats::load_scene(path).unwrap();
    let scene = Scene::build(&loaded.description).unwrap();
    trace_and_render(&scene, camera, PATHS, seed).to_rgb_f32()
}

#[test]
fn vrml_obj_and_gltf_cornell_boxes_render_like_the_mitsuba_xml() {
    let xml = scene_file("cornell", "scene.xml");
    // The XML's camera for every format (OBJ has none; glTF's image is 512 px high).
    let camera = camera(&load("cornell"));
    let a = render(&xml, 1, &camera);
    let b = render(&xml, 2, &camera);
    let noise = compare(&a, &b).relmse;
    eprintln!("XML vs XML (two seeds): relMSE {noise:.3e}");
    for (i, file) in ["testdata/vrml/cornell.wrl", "testdata/obj/cornell.obj", "testdata/gltf/cornell.gltf"]
        .iter()
        .enumerate()
    {
        let other = render(&repo().join(file), 10 + i as u64, &camera);
        let c = compare(&other, &a);
        eprintln!("{file} vs XML: relMSE {:.3e}, mean ratio {:?}", c.relmse, c.mean_ratio);
        // Two independent estimates of the same image: relMSE ≈ the XML-vs-XML level (±15%).
        assert!(c.relmse < 1.15 * noise, "{file}: relMSE {} vs noise {noise}", c.relmse);
        for r in c.mean_ratio {
            assert!((r - 1.0).abs() < 0.01, "{file}: mean ratio {r}");
        }
    }
}
