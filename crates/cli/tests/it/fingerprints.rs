//! Pinned scene fingerprints: the geometry, lights and legacy (format-version-1) geometry hashes
//! of the shared reference scenes, and a dataset written by an older Opticks that must still
//! render, bit for bit, against its scene.
//!
//! These hashes are a file-format contract (see `crates/core/src/scene/fingerprint.rs`): every
//! dataset on disk records them, and a scene whose hash changes refuses every dataset traced
//! from it. The values below were computed by the Opticks of commit fbd7ee8, before the
//! fingerprint's material and light encodings were written out explicitly; they must never
//! change. A test failing here means datasets on disk would be refused: fix the encoding, not
//! the pin.

use opticks_testkit as common;

use opticks_core::bsdf::{
    Bsdf, Lambert, Material, ModifiedPhong, RoughConductor, RoughDielectric, SmoothConductor,
    SmoothDielectric,
};
use opticks_core::light::EmissionProfile;
use opticks_core::math::{Frame, Rgb, Vec3};
use opticks_core::sampling::microfacet::{Distribution, Microfacet};
use opticks_core::scene::{
    AreaEmission, DirectionalLightDesc, MeshDesc, PointLightDesc, Scene, SceneDescription, cornell_box,
};

/// Loads and builds a scene file given relative to the repository root.
fn build(path: &str) -> Scene {
    let loaded = opticks_io::scene_formats::load_scene(&common::repo().join(path))
        .unwrap_or_else(|e| panic!("{path}: {e}"));
    Scene::build(&loaded.description).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

/// (geometry, lights, legacy format-v1 geometry), in hexadecimal.
fn hashes(scene: &Scene) -> [String; 3] {
    [scene.fingerprint.geometry_hex(), scene.fingerprint.lights_hex(), hex(&scene.geometry_v1)]
}

/// An IES table from testdata.
fn ies(name: &str) -> EmissionProfile {
    let file = opticks_io::ies::load_ies(&common::repo().join("testdata/ies").join(name)).unwrap();
    EmissionProfile::Ies(file.profile)
}

/// A unit quad in the plane y = `y`, facing down, centred on (x, z).
fn quad(name: &str, material: usize, x: f32, y: f32, z: f32) -> MeshDesc {
    let p = |dx: f32, dz: f32| Vec3::new(x + dx, y, z + dz);
    MeshDesc {
        name: name.into(),
        positions: vec![p(-0.5, -0.5), p(0.5, -0.5), p(0.5, 0.5), p(-0.5, 0.5)],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material,
        ..Default::default()
    }
}

/// `mesh` as an area light of `radiance` with `profile` (and horizontal 0° along `tangent`).
fn emitting(
    mut mesh: MeshDesc,
    radiance: Rgb,
    profile: Option<EmissionProfile>,
    tangent: Option<Vec3>,
) -> MeshDesc {
    mesh.emission = Some(AreaEmission { radiance, profile, tangent, power: None, texture: None });
    mesh
}

/// The built-in Cornell box with one quad of every BSDF variant (with and without their
/// options: sidedness, conductor indices, anisotropy, absorption, numbers printed in exponent
/// form) and every kind of light and emission profile.
fn every_kind() -> SceneDescription {
    let mut d = cornell_box();
    let rgb = Rgb::new;
    let bsdfs = [
        (Bsdf::Lambert(Lambert { reflectance: rgb(0.5, 0.25, 0.125) }), true),
        (Bsdf::Lambert(Lambert { reflectance: rgb(0.5, 0.25, 0.125) }), false),
        (Bsdf::Lambert(Lambert { reflectance: rgb(1e-7, -0.0, 0.3) }), true),
        (
            Bsdf::ModifiedPhong(ModifiedPhong {
                kd: rgb(0.3, 0.2, 0.1),
                ks: rgb(0.1, 0.2, 0.3),
                exponent: 20.0,
            }),
            false,
        ),
        (Bsdf::SmoothConductor(SmoothConductor { specular_reflectance: Rgb::ONE, ior: None }), false),
        (
            Bsdf::SmoothConductor(SmoothConductor {
                specular_reflectance: rgb(0.9, 0.8, 0.7),
                ior: Some((rgb(0.2, 0.9, 1.1), rgb(3.9, 2.4, 1.6e17))),
            }),
            true,
        ),
        (
            Bsdf::SmoothDielectric(SmoothDielectric {
                eta: 1.33,
                specular_reflectance: Rgb::ONE,
                specular_transmittance: rgb(1.0, 0.95, 0.9),
                absorption: rgb(0.1, 2.5e-5, 0.0),
            }),
            false,
        ),
        (
            Bsdf::RoughConductor(RoughConductor {
                microfacet: Microfacet { distribution: Distribution::Beckmann, alpha_u: 0.1, alpha_v: 0.3 },
                specular_reflectance: Rgb::ONE,
                ior: Some((rgb(0.143, 0.374, 1.442), rgb(3.983, 2.385, 1.603))),
            }),
            false,
        ),
        (
            Bsdf::RoughConductor(RoughConductor {
                microfacet: Microfacet { distribution: Distribution::Ggx, alpha_u: 0.05, alpha_v: 0.05 },
                specular_reflectance: rgb(0.5, 0.5, 0.5),
                ior: None,
            }),
            true,
        ),
        (
            Bsdf::RoughDielectric(RoughDielectric {
                eta: 1.0 / 1.5,
                microfacet: Microfacet { distribution: Distribution::Ggx, alpha_u: 0.2, alpha_v: 0.02 },
                specular_reflectance: rgb(1.0, 0.99, 0.98),
                specular_transmittance: Rgb::ONE,
                absorption: rgb(0.0, 0.5, 12.0),
            }),
            false,
        ),
    ];
    for (i, (bsdf, two_sided)) in bsdfs.into_iter().enumerate() {
        let m = d.materials.len();
        d.materials.push(Material { name: format!("kind{i}"), bsdf, two_sided });
        d.meshes.push(quad(&format!("quad{i}"), m, 0.1 * i as f32, 0.5, 0.0));
    }
    let emitters = [
        (Some(EmissionProfile::Uniform), None),
        (Some(EmissionProfile::CosinePower { exponent: 5.0 }), None),
        (Some(EmissionProfile::Spot { cutoff_angle: 0.8, beam_width: 0.5 }), None),
        (Some(ies("asymmetric-wallwasher.ies")), Some(Vec3::new(0.0, 0.0, 1.0))),
        (Some(ies("symmetric-3.ies")), None),
    ];
    for (i, (profile, tangent)) in emitters.into_iter().enumerate() {
        let q = quad(&format!("panel{i}"), 0, 0.2 * i as f32, 0.9, 0.5);
        d.meshes.push(emitting(q, Rgb::splat(1.0 + i as f32), profile, tangent));
    }
    let axis = Frame::from_normal(Vec3::new(0.0, -1.0, 0.2).normalize());
    let points = [
        (None, None),
        (Some(EmissionProfile::Uniform), Some(axis)),
        (Some(EmissionProfile::CosinePower { exponent: 3.0 }), Some(axis)),
        (Some(EmissionProfile::Spot { cutoff_angle: 0.6, beam_width: 0.4 }), Some(axis)),
        (Some(ies("asymmetric-wallwasher.ies")), Some(axis)),
    ];
    for (i, (profile, orientation)) in points.into_iter().enumerate() {
        d.point_lights.push(PointLightDesc {
            name: format!("point{i}"),
            position: Vec3::new(0.1 * i as f32, 0.8, -0.3),
            intensity: Rgb::splat(2.0),
            profile,
            orientation,
            ..Default::default()
        });
    }
    d.directional_lights.push(DirectionalLightDesc {
        name: "sun".into(),
        direction: Vec3::new(0.3, -1.0, 0.1),
        irradiance: Rgb::splat(3.0),
        ..Default::default()
    });
    d
}

/// (path, geometry, lights, legacy format-v1 geometry) of the reference scenes, as the Opticks
/// of commit fbd7ee8 computed them.
const PINNED: &[(&str, &str, &str, &str)] = &[
    (
        "testdata/scenes/cornell/scene.xml",
        "77c84d91f561781eaa8a79f307c9408d",
        "22c584c5740ca8433da8128da0592ac8",
        "82d56c19df63ae89750992603b68d29b",
    ),
    (
        "testdata/scenes/furnace/scene.xml",
        "285f93f6b35a23e4de4f05d6a454d8be",
        "92273c3e66943019c2e679bd79f63fc8",
        "7be2c403e7434f09b126e6191fba225a",
    ),
    (
        "testdata/mitsuba/rough/scene.xml",
        "91292b421eedb07227c9dad505d5c2a4",
        "797c7aa6898589e582a1c27b32446959",
        "6667525c429cd1edfc73993f612f9109",
    ),
    (
        "testdata/mitsuba/smooth/scene.xml",
        "e1042efe00f2fe43413ea430b6da8994",
        "c2c7ae77615b2b50f46e6cb22384cd29",
        "0c836599c90a6923ea06682e22490ba8",
    ),
    (
        "testdata/mitsuba/caustics/scene.xml",
        "f75e518a60c61cf13feda5e74c441675",
        "399e9f57b4962cafd3030d5b7208c0bf",
        "a0349d97de5eabd1c68492efef2bf3a8",
    ),
    (
        "testdata/mitsuba/ring/scene.xml",
        "914423309af616c5254da1f649db2441",
        "12bc8f9e7e1ed829d8bd5509d467e039",
        "ef82d4bcde9b2eda3fa1510343f57c91",
    ),
    (
        "testdata/obj/cornell.obj",
        "77c84d91f561781eaa8a79f307c9408d",
        "22c584c5740ca8433da8128da0592ac8",
        "13ddf9564ccc6c753f8a2663642b8d55",
    ),
    (
        "testdata/gltf/cornell.gltf",
        "50d6188c5ea55ca38ac8329440aa64e2",
        "fa1a7e260d18c5fb9c31c430393586a5",
        "af8f0e4c0ed1e5a566ff0ce653e4830b",
    ),
    (
        "testdata/vrml/cornell.wrl",
        "13f7c3ccc8e95b8784264af575e6aa99",
        "3776e2ad6482808dfd173211955cc800",
        "b41d1a7b4ea18eb1d401f121fd65c92c",
    ),
    (
        "testdata/vrml/vtk-scene.wrl",
        "5bd6b068076ba894c5240d3b7f207613",
        "cb87b1ab6c4a0ab8cad9850d8395ffc5",
        "cc8d16386f514198b70549e639d4756f",
    ),
    (
        "scenes/caustics/scene.xml",
        "f75e518a60c61cf13feda5e74c441675",
        "399e9f57b4962cafd3030d5b7208c0bf",
        "a0349d97de5eabd1c68492efef2bf3a8",
    ),
    (
        "scenes/ring/scene.xml",
        "914423309af616c5254da1f649db2441",
        "12bc8f9e7e1ed829d8bd5509d467e039",
        "ef82d4bcde9b2eda3fa1510343f57c91",
    ),
    (
        "scenes/ies/scene.xml",
        "ba0a110a0d08a61a9c4a25ff71cf3b48",
        "16251761cb00311845c3fecd5b12ecce",
        "60b7ef718f174962d6407c0475051852",
    ),
];

#[test]
fn reference_scene_fingerprints_are_pinned() {
    let mut wrong = Vec::new();
    for &(path, geometry, lights, v1) in PINNED {
        let got = hashes(&build(path));
        if got != [geometry, lights, v1] {
            wrong
                .push(format!("{path}: (geometry, lights, v1) {got:?}, pinned {:?}", [geometry, lights, v1]));
        }
    }
    assert!(
        wrong.is_empty(),
        "fingerprints changed (datasets on disk would be refused):\n{}",
        wrong.join("\n")
    );
}

#[test]
fn builtin_cornell_box_fingerprint_is_pinned() {
    let got = hashes(&Scene::build(&cornell_box()).unwrap());
    assert_eq!(
        got,
        [
            "3509506f3869a314c067e4c8309abefb",
            "22c584c5740ca8433da8128da0592ac8",
            "bfb6a9bdd45cab0d0fc229fb2ee70b58"
        ]
    );
}

#[test]
fn every_bsdf_and_light_kind_fingerprint_is_pinned() {
    let scene = Scene::build(&every_kind()).unwrap();
    assert_eq!(
        hashes(&scene),
        [
            "24fd57daa3272e7f778693918db6e564",
            "3f79b911191ff1d9e8a35b3c675d5891",
            "ae0063b48dc75dd72bf69a49b720e5e6"
        ]
    );
    let shapes: Vec<(&str, String)> =
        scene.lights.iter().zip(&scene.light_shapes).map(|(l, s)| (l.name(), hex(s))).collect();
    let pinned = [
        ("light", "2747851a3936e6a93332936e5ce8f39d"),
        ("panel0", "2426743b97f080ea8eba10aaf459e5ef"),
        ("panel1", "f30ada2562ddbaae427c9a01bfeaea71"),
        ("panel2", "b7676bbade44cf5312c01b0a65c437b7"),
        ("panel3", "3b86d8912bc34f1e33967f6889af1664"),
        ("panel4", "41fcdd6798972739b78cac247c635415"),
        ("point0", "2bea377dcba87a34146dca6b1869ba40"),
        ("point1", "52bbe2a7331e06ea5929cb9e3df62e15"),
        ("point2", "7316ba47747d1779eacdd7eabc219b0c"),
        ("point3", "b702a5bfb7daf64a4b68abb8711fd2ea"),
        ("point4", "da476c7096795838ab55b9338bb58dad"),
        ("sun", "655495fdcebd320bbd3218a29581c2f1"),
    ];
    assert_eq!(shapes, pinned.map(|(n, h)| (n, h.to_string())));
}

/// Renders `testdata/datasets/NAME.opds` against `scene` (64×48, one thread, so the sum is in
/// one order) and compares it, pixel for pixel, with `NAME.exr`, rendered from the same dataset
/// by the Opticks that wrote it (commit fbd7ee8). With `upgrade`, the dataset is first
/// upgraded to MIS records (`opticks upgrade`: every pass re-traced to the same paths, the samples kept) and the
/// upgraded file, of the current format, must render the same image.
fn renders_as_when_written(name: &str, scene: &str, upgrade: bool) {
    let repo = common::repo();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.exr");
    let mut dataset = repo.join("testdata/datasets").join(format!("{name}.opds"));
    if upgrade {
        let upgraded = dir.path().join("upgraded.opds");
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_opticks"))
            .args(["upgrade".as_ref(), dataset.as_os_str()])
            .args(["--scene".as_ref(), repo.join(scene).as_os_str()])
            .arg("-o")
            .arg(&upgraded)
            .output()
            .unwrap();
        assert!(run.status.success(), "{name}: {}", String::from_utf8_lossy(&run.stderr));
        let old = opticks_io::dataset_file::DatasetReader::open(&dataset).unwrap();
        assert!(old.header().objects.is_empty(), "{name}: a format-2 dataset has no object hashes");
        let r = opticks_io::dataset_file::DatasetReader::open(&upgraded).unwrap();
        r.verify().unwrap();
        // The scene matched: the upgrade records its object hashes (format 4).
        assert_eq!(r.header().objects, build(scene).objects, "{name}");
        assert!(opticks_core::dataset::mis_compatibility(r.header()).is_ok());
        assert!(
            (0..r.chunk_count())
                .all(|i| r.chunk_records(i).unwrap().len() == r.chunk(i).unwrap().samples.len())
        );
        dataset = upgraded;
    }
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_opticks"))
        .args(["render".as_ref(), dataset.as_os_str()])
        .args(["--scene".as_ref(), repo.join(scene).as_os_str()])
        .args(["--size", "64x48", "--threads", "1", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(run.status.success(), "{name}: {}", String::from_utf8_lossy(&run.stderr));
    let read = |p: &std::path::Path| opticks_io::image_file::read_exr_rgb(p).unwrap();
    let (expected, got) = (read(&repo.join("testdata/datasets").join(format!("{name}.exr"))), read(&out));
    assert_eq!((got.0, got.1), (expected.0, expected.1), "{name}: image size");
    assert!(expected.2.iter().any(|&v| v > 0.0), "{name}: the reference image is not black");
    let differing = got.2.iter().zip(&expected.2).filter(|(a, b)| a.to_bits() != b.to_bits()).count();
    assert_eq!(
        differing, 0,
        "{name}: {differing} channel values differ from the render of the Opticks that wrote it"
    );
}

#[test]
fn a_cornell_dataset_of_format_version_2_still_renders_the_same() {
    renders_as_when_written("cornell-v2", "testdata/scenes/cornell/scene.xml", false);
}

#[test]
fn a_rough_materials_dataset_of_format_version_2_still_renders_the_same() {
    renders_as_when_written("rough-v2", "testdata/mitsuba/rough/scene.xml", false);
}

/// The old datasets re-trace to the same paths with today's tracer (up to rounding: hit points
/// are snapped onto their triangles since), keep their samples and gain their MIS records.
#[test]
fn format_version_2_datasets_upgrade_to_records_and_still_render_the_same() {
    renders_as_when_written("cornell-v2", "testdata/scenes/cornell/scene.xml", true);
    renders_as_when_written("rough-v2", "testdata/mitsuba/rough/scene.xml", true);
}
