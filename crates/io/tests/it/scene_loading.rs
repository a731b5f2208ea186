//! Loading the reference scenes and a gallery of broken ones through the public API.

use opticks_core::bsdf::Bsdf;
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::Scene;
use opticks_io::{LoadOptions, LoadedScene, SceneFileError, load_scene, load_scene_with};
use std::path::{Path, PathBuf};

fn testdata(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/scenes").join(rel)
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

fn albedo(s: &LoadedScene, mesh: &str) -> (Rgb, bool) {
    let d = &s.description;
    let m = d.meshes.iter().find(|m| m.name == mesh).unwrap_or_else(|| panic!("no mesh {mesh}"));
    let mat = &d.materials[m.material];
    match &mat.bsdf {
        Bsdf::Lambert(l) => (l.reflectance, mat.two_sided),
        other => panic!("{other:?}"),
    }
}

#[test]
fn cornell_box_loads() {
    let s = load_scene(&testdata("cornell/scene.xml")).unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let d = &s.description;
    let names: Vec<&str> = d.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["white_geometry", "red_wall", "green_wall", "light"]);
    // SCENE.md's table: white 2+2+2+12+12, red 2, green 2, light 2 = 36 (its heading says 38).
    let tris: Vec<usize> = d.meshes.iter().map(|m| m.triangles.len()).collect();
    assert_eq!(tris, [30, 2, 2, 2]);
    let emissive: Vec<_> = d.meshes.iter().filter(|m| m.emission.is_some()).collect();
    assert_eq!(emissive.len(), 1);
    assert_eq!(emissive[0].name, "light");
    assert_eq!(emissive[0].emission.as_ref().map(|e| e.radiance), Some(Rgb::new(18.387, 13.9873, 6.75357)));
    assert_eq!(emissive[0].source.line, 64);
    assert!(emissive[0].source.file.ends_with("cornell/scene.xml"));
    assert!(d.point_lights.is_empty());

    let c = d.camera.expect("camera");
    assert!(close(c.eye, Vec3::new(0.0, 0.0, 3.9), 1e-6), "{:?}", c.eye);
    assert!(close(c.target, Vec3::ZERO, 1e-6), "{:?}", c.target);
    assert!(close(c.up, Vec3::Y, 1e-6), "{:?}", c.up);
    assert_eq!((c.fov_x_degrees, c.width, c.height), (39.3077, 256, 256));

    // Three materials (the light reuses `white`), all two-sided.
    assert_eq!(d.materials.len(), 3);
    assert_eq!(albedo(&s, "white_geometry"), (Rgb::new(0.885809, 0.698859, 0.666422), true));
    assert_eq!(albedo(&s, "red_wall"), (Rgb::new(0.570068, 0.0430135, 0.0443706), true));
    assert_eq!(albedo(&s, "green_wall"), (Rgb::new(0.105421, 0.37798, 0.076425), true));
    assert_eq!(albedo(&s, "light"), albedo(&s, "white_geometry"));
    assert_eq!(d.meshes[0].material, d.meshes[3].material);
    // The light faces down (−y).
    let l = emissive[0];
    let [a, b, c] = l.triangles[0].map(|i| l.positions[i as usize]);
    assert!((b - a).cross(c - a).normalize().y < -0.999);
}

#[test]
fn furnace_loads() {
    let s = load_scene(&testdata("furnace/scene.xml")).unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let d = &s.description;
    assert_eq!(d.meshes.len(), 2);
    assert_eq!(d.materials.len(), 1);
    assert_eq!(albedo(&s, "room"), (Rgb::splat(0.5), true));
    assert_eq!(d.meshes[1].emission.as_ref().map(|e| e.radiance), Some(Rgb::splat(10.0)));
    let c = d.camera.unwrap();
    assert_eq!((c.width, c.height, c.fov_x_degrees), (128, 128, 90.0));
    assert!(close(c.eye, Vec3::new(0.25, 0.5, 0.25), 1e-6));
    assert!(close(c.target, Vec3::new(1.0, 0.4, 1.0), 1e-6), "{:?}", c.target);
    // Every room vertex is in the unit cube.
    assert!(d.meshes[0].positions.iter().all(|p| p.min_element() >= 0.0 && p.max_element() <= 1.0));
}

#[test]
fn defines_override_defaults() {
    // The reference scenes use $spp and $max_depth; overriding max_depth is reported.
    let opts = LoadOptions { defines: vec![("max_depth".into(), "8".into())], ..Default::default() };
    let s = load_scene_with(&testdata("cornell/scene.xml"), &opts).unwrap();
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
    assert!(
        s.warnings[0].contains("scene.xml:9:9: <integer name=\"max_depth\">: max_depth = 8"),
        "{:?}",
        s.warnings
    );
}

#[test]
fn bare_obj_is_a_scene() {
    let s = load_scene(&testdata("cornell/meshes/red.obj")).unwrap();
    let d = &s.description;
    assert_eq!((d.meshes.len(), d.meshes[0].name.as_str(), d.meshes[0].triangles.len()), (1, "red-wall", 2));
    assert!(d.camera.is_none() && d.point_lights.is_empty());
    assert!(d.materials[0].two_sided);
    assert!(!s.warnings.is_empty());
}

/// Writes `files` into a fresh folder and loads the first one.
fn load_files(files: &[(&str, &str)]) -> (tempfile::TempDir, Result<LoadedScene, SceneFileError>) {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        let p = dir.path().join(name);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, text).unwrap();
    }
    let r = load_scene(&dir.path().join(files[0].0));
    (dir, r)
}

/// Loads a broken scene and returns its message with the temporary folder replaced by `TMP`.
fn error_of(files: &[(&str, &str)]) -> String {
    let (dir, r) = load_files(files);
    let e = r.expect_err("should fail");
    e.to_string().replace(&dir.path().display().to_string(), "TMP")
}

const HEAD: &str = "<?xml version=\"1.0\"?>\n<scene version=\"3.0.0\">\n";

#[test]
fn malformed_xml() {
    let e = error_of(&[(
        "s.xml",
        &format!("{HEAD}  <shape type=\"obj\">\n    <string name=\"a\" value=\"x\">\n  </shape>\n</scene>\n"),
    )]);
    assert!(e.starts_with("TMP/s.xml:5:3: malformed XML: expected 'string' tag, not 'shape'"), "{e}");
}

#[test]
fn missing_mesh_file() {
    let xml = format!(
        "{HEAD}<shape type=\"obj\" id=\"box\">\n  <string name=\"filename\" value=\"meshes/box.obj\"/>\n</shape>\n</scene>"
    );
    let e = error_of(&[("s.xml", &xml)]);
    assert!(
        e.starts_with(
            "TMP/s.xml:3:1: <shape type=\"obj\" id=\"box\">: cannot read mesh file TMP/meshes/box.obj:"
        ),
        "{e}"
    );
}

#[test]
fn bad_obj_content_names_both_files() {
    let xml = format!(
        "{HEAD}<shape type=\"obj\" id=\"box\">\n  <string name=\"filename\" value=\"m.obj\"/>\n</shape>\n</scene>"
    );
    let e = error_of(&[("s.xml", &xml), ("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")]);
    assert_eq!(
        e,
        "TMP/m.obj:4: face refers to vertex 4, but the file defines only 3 vertices \
         (mesh of <shape type=\"obj\" id=\"box\"> at TMP/s.xml:3:1)"
    );
}

#[test]
fn nan_in_a_transform() {
    let xml = format!(
        "{HEAD}<shape type=\"rectangle\">\n  <transform name=\"to_world\">\n    <scale value=\"1, NaN, 1\"/>\n  </transform>\n</shape>\n</scene>"
    );
    let e = error_of(&[("s.xml", &xml)]);
    assert_eq!(e, "TMP/s.xml:5:19: <scale>: attribute `value`: \"NaN\" is not a finite number");
}

#[test]
fn unknown_plugin_type() {
    let xml = format!("{HEAD}\n  <bsdf type=\"hair\" id=\"shiny\"/>\n</scene>");
    let e = error_of(&[("s.xml", &xml)]);
    assert_eq!(
        e,
        "TMP/s.xml:4:15: <bsdf type=\"hair\" id=\"shiny\">: unsupported BSDF type \"hair\" (supported: diffuse, phong (Opticks extension), twosided, conductor, roughconductor, dielectric, roughdielectric, thindielectric, plastic, roughplastic, blendbsdf, mask, normalmap, bumpmap, principled, principledthin)"
    );
}

#[test]
fn undefined_variable() {
    let xml = format!(
        "{HEAD}<sensor type=\"perspective\">\n  <float name=\"fov\" value=\"$fov\"/>\n</sensor>\n</scene>"
    );
    let e = error_of(&[("s.xml", &xml)]);
    assert!(e.starts_with("TMP/s.xml:4:28: <float name=\"fov\">: undefined parameter $fov"), "{e}");
}

#[test]
fn reflectance_above_one() {
    let xml = format!(
        "{HEAD}<bsdf type=\"twosided\" id=\"w\">\n  <bsdf type=\"diffuse\">\n    <rgb name=\"reflectance\" value=\"0.9, 1.1, 0.9\"/>\n  </bsdf>\n</bsdf>\n</scene>"
    );
    let e = error_of(&[("s.xml", &xml)]);
    assert!(e.starts_with("TMP/s.xml:5:5: <rgb name=\"reflectance\">: invalid material: kd + ks = "), "{e}");
    let (_d, r) = load_files(&[("s.xml", &xml)]);
    assert!(matches!(r, Err(SceneFileError::Material { .. })));
}

#[test]
fn reference_to_unknown_id() {
    let xml = format!(
        "{HEAD}<bsdf type=\"diffuse\" id=\"white\"/>\n<shape type=\"cube\">\n  <ref id=\"whte\"/>\n</shape>\n</scene>"
    );
    let e = error_of(&[("s.xml", &xml)]);
    assert_eq!(
        e,
        "TMP/s.xml:5:12: <ref id=\"whte\">: reference to unknown id \"whte\" (BSDF ids in this file: white)"
    );
}

#[test]
fn unreadable_scene_file_and_error_locations() {
    let e = load_scene(Path::new("no/such/scene.xml")).unwrap_err();
    assert!(e.to_string().starts_with("no/such/scene.xml: cannot read the scene file:"), "{e}");
    assert!(e.location().is_none());
    let xml = format!("{HEAD}<shape type=\"teapot\"/>\n</scene>");
    let (_d, r) = load_files(&[("s.xml", &xml)]);
    let e = r.unwrap_err();
    let at = e.location().unwrap();
    assert_eq!((at.line, at.column), (3, 14));
}

/// The loaded reference scenes build into ray-traceable scenes with the expected geometry and
/// light power (Φ = π·L·A for a one-sided Lambertian emitter).
#[test]
fn reference_scenes_build() {
    let cornell = load_scene(&testdata("cornell/scene.xml")).unwrap();
    let scene = Scene::build(&cornell.description).unwrap();
    assert_eq!(scene.triangles.len(), 36);
    assert_eq!(scene.dropped_triangles, 0);
    let powers = scene.light_powers();
    assert_eq!(powers.len(), 1);
    let want = Rgb::new(10.0972, 7.6811, 3.7087);
    assert!(close(powers[0], want, 1e-3), "cornell Φ = {} W, expected {want}", powers[0]);

    let furnace = load_scene(&testdata("furnace/scene.xml")).unwrap();
    let scene = Scene::build(&furnace.description).unwrap();
    let tris: usize = furnace.description.meshes.iter().map(|m| m.triangles.len()).sum();
    assert_eq!(scene.triangles.len() + scene.dropped_triangles, tris);
    assert_eq!(scene.dropped_triangles, 0);
    let powers = scene.light_powers();
    assert_eq!(powers.len(), 1);
    let want = Rgb::splat(0.4 * std::f32::consts::PI);
    assert!(close(powers[0], want, 1e-3), "furnace Φ = {} W, expected {want}", powers[0]);
}

#[test]
fn phong_material_loads_and_builds() {
    let xml = format!(
        "{HEAD}<bsdf type=\"twosided\" id=\"glossy\">\n  <bsdf type=\"phong\">\n    \
         <rgb name=\"diffuseReflectance\" value=\"0.4, 0.3, 0.2\"/>\n    \
         <float name=\"specularReflectance\" value=\"0.5\"/>\n    \
         <float name=\"exponent\" value=\"120\"/>\n  </bsdf>\n</bsdf>\n\
         <shape type=\"cube\" id=\"box\"><ref id=\"glossy\"/></shape>\n\
         <emitter type=\"point\"><point name=\"position\" x=\"0\" y=\"0\" z=\"0\"/></emitter>\n</scene>"
    );
    let (_dir, r) = load_files(&[("s.xml", &xml)]);
    let s = r.unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let mat = &s.description.materials[s.description.meshes[0].material];
    assert_eq!(mat.name, "glossy");
    assert!(mat.two_sided);
    match &mat.bsdf {
        Bsdf::ModifiedPhong(p) => {
            assert_eq!((p.kd, p.ks, p.exponent), (Rgb::new(0.4, 0.3, 0.2), Rgb::splat(0.5), 120.0))
        }
        other => panic!("{other:?}"),
    }
    let scene = Scene::build(&s.description).unwrap();
    assert_eq!(scene.materials[0].bsdf, mat.bsdf);
}

#[test]
fn impossible_phong_material() {
    let bad = |params: &str| {
        let xml = format!(
            "{HEAD}<shape type=\"cube\">\n  <bsdf type=\"phong\">\n    {params}\n  </bsdf>\n</shape>\n</scene>"
        );
        error_of(&[("s.xml", &xml)])
    };
    let e = bad(
        "<float name=\"diffuseReflectance\" value=\"0.6\"/><float name=\"specularReflectance\" value=\"0.5\"/>",
    );
    assert!(e.starts_with("TMP/s.xml:4:3: <bsdf type=\"phong\">: invalid material: kd + ks = "), "{e}");
    let e = bad("<float name=\"exponent\" value=\"nan\"/>");
    assert_eq!(
        e,
        "TMP/s.xml:5:35: <float name=\"exponent\">: attribute `value`: \"nan\" is not a finite number"
    );
    let e = bad("<float name=\"exponent\" value=\"1e7\"/>");
    assert!(e.starts_with("TMP/s.xml:5:5: <float name=\"exponent\">: invalid material: exponent = "), "{e}");
}

#[test]
fn obj_vertex_normals_follow_face_normals_and_to_world() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 1 0 1\nf 1//1 2//2 3//1\n";
    let xml = |extra: &str| {
        format!(
            "{HEAD}<shape type=\"obj\">\n  <string name=\"filename\" value=\"m.obj\"/>\n{extra}</shape>\n</scene>"
        )
    };
    // Mitsuba's default (face_normals false) uses the file's normals; a non-uniform scale carries
    // them by the inverse transpose: (1, 0, 1) under diag(2, 1, 1) → (0.5, 0, 1).
    let scaled = xml("  <transform name=\"to_world\"><scale x=\"2\"/></transform>\n");
    let (_d, r) = load_files(&[("s.xml", &scaled), ("m.obj", obj)]);
    let m = &r.unwrap().description.meshes[0];
    assert_eq!(m.normals, vec![Vec3::Z, Vec3::new(0.5, 0.0, 1.0), Vec3::Z]);
    let faceted = xml("  <boolean name=\"face_normals\" value=\"true\"/>\n");
    let (_d, r) = load_files(&[("s.xml", &faceted), ("m.obj", obj)]);
    assert!(r.unwrap().description.meshes[0].normals.is_empty());
    // flip_normals turns the normals with the faces.
    let flipped = xml("  <boolean name=\"flip_normals\" value=\"true\"/>\n");
    let (_d, r) = load_files(&[("s.xml", &flipped), ("m.obj", obj)]);
    assert_eq!(r.unwrap().description.meshes[0].normals[0], -Vec3::Z);
}

/// A UV sphere of radius 1 (`segments` × `rings`, one vertex per pole), wound outward, as OBJ
/// text without `vn`.
fn uv_sphere_obj(segments: usize, rings: usize) -> String {
    use std::f32::consts::PI;
    use std::fmt::Write;
    let mut s = String::from("v 0 0 1\n");
    for r in 1..rings {
        let theta = PI * r as f32 / rings as f32;
        for k in 0..segments {
            let phi = 2.0 * PI * k as f32 / segments as f32;
            writeln!(s, "v {} {} {}", theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()).unwrap();
        }
    }
    writeln!(s, "v 0 0 -1").unwrap();
    let south = 1 + segments * (rings - 1) + 1; // 1-based
    let at = |r: usize, k: usize| 2 + (r - 1) * segments + k % segments; // ring r ≥ 1
    for k in 0..segments {
        writeln!(s, "f 1 {} {}", at(1, k), at(1, k + 1)).unwrap();
        for r in 1..rings - 1 {
            writeln!(s, "f {} {} {} {}", at(r, k), at(r + 1, k), at(r + 1, k + 1), at(r, k + 1)).unwrap();
        }
        writeln!(s, "f {} {} {}", at(rings - 1, k), south, at(rings - 1, k + 1)).unwrap();
    }
    s
}

#[test]
fn obj_without_normals_gets_mitsubas_smooth_normals() {
    let obj = uv_sphere_obj(12, 6);
    let xml = |extra: &str| {
        format!(
            "{HEAD}<shape type=\"obj\">\n  <string name=\"filename\" value=\"m.obj\"/>\n{extra}</shape>\n</scene>"
        )
    };
    let (_d, r) = load_files(&[("s.xml", &xml("")), ("m.obj", &obj)]);
    let m = &r.unwrap().description.meshes[0];
    assert_eq!(m.normals.len(), m.positions.len());
    // Every vertex's normal is close to radial (measured: within 2.07°, the rings next to the
    // poles tilting as their triangles and quads differ); the faces are up to 20.8° off it.
    let worst = m.positions.iter().zip(&m.normals).map(|(p, n)| p.angle_between(*n).to_degrees());
    let worst = worst.fold(0.0f32, f32::max);
    let face_worst = (0..m.triangles.len())
        .map(|t| {
            let [a, b, c] = m.triangles[t].map(|i| m.positions[i as usize]);
            a.angle_between((b - a).cross(c - a)).to_degrees()
        })
        .fold(0.0f32, f32::max);
    assert!(worst < 2.5, "generated normals up to {worst}° off radial");
    assert!(face_worst > 15.0, "{face_worst}");
    // flip_normals turns them inward with the faces; face_normals keeps the mesh faceted.
    let (_d, r) = load_files(&[
        ("s.xml", &xml("  <boolean name=\"flip_normals\" value=\"true\"/>\n")),
        ("m.obj", &obj),
    ]);
    let m = &r.unwrap().description.meshes[0];
    assert!(m.positions.iter().zip(&m.normals).all(|(p, n)| p.angle_between(-*n).to_degrees() < 2.5));
    let (_d, r) = load_files(&[
        ("s.xml", &xml("  <boolean name=\"face_normals\" value=\"true\"/>\n")),
        ("m.obj", &obj),
    ]);
    assert!(r.unwrap().description.meshes[0].normals.is_empty());
}

/// A mesh file that several `<shape>`s name is parsed once for all of them (issue 25); each
/// shape still gets its own `to_world`, `flip_normals`, `face_normals`, and the meshes are the
/// ones each shape gives when it is alone in its scene.
#[test]
fn mesh_files_named_twice_give_the_meshes_they_give_alone() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/mitsuba");
    let shapes = [
        ("bunny-box", "<shape type=\"obj\"><string name=\"filename\" value=\"meshes/bunny.obj\"/></shape>"),
        (
            "bunny-box",
            "<shape type=\"obj\"><string name=\"filename\" value=\"meshes/bunny.obj\"/>\
             <transform name=\"to_world\"><rotate y=\"1\" angle=\"30\"/><translate x=\"1\"/></transform></shape>",
        ),
        (
            "bunny-box",
            "<shape type=\"obj\"><string name=\"filename\" value=\"meshes/bunny.obj\"/>\
             <boolean name=\"flip_normals\" value=\"true\"/><boolean name=\"face_normals\" value=\"true\"/></shape>",
        ),
        ("bunny-box", "<shape type=\"obj\"><string name=\"filename\" value=\"./meshes/bunny.obj\"/></shape>"),
        ("shapes", "<shape type=\"ply\"><string name=\"filename\" value=\"meshes/octa.ply\"/></shape>"),
        (
            "shapes",
            "<shape type=\"ply\"><string name=\"filename\" value=\"meshes/octa.ply\"/>\
             <transform name=\"to_world\"><scale value=\"-2\"/></transform></shape>",
        ),
        (
            "shapes",
            "<shape type=\"serialized\"><string name=\"filename\" value=\"meshes/two.serialized\"/>\
             <integer name=\"shape_index\" value=\"1\"/></shape>",
        ),
        (
            "shapes",
            "<shape type=\"serialized\"><string name=\"filename\" value=\"meshes/two.serialized\"/></shape>",
        ),
    ];
    let load = |folder: &str, body: &str| {
        let xml = format!("<scene version=\"3.0.0\">\n{body}\n</scene>");
        opticks_io::scene_formats::mitsuba::parse(
            &xml,
            &dir.join(folder).join("test.xml"),
            &LoadOptions::default(),
        )
        .unwrap_or_else(|e| panic!("{e}\n{xml}"))
        .description
    };
    for folder in ["bunny-box", "shapes"] {
        let bodies: Vec<&str> = shapes.iter().filter(|(f, _)| *f == folder).map(|(_, b)| *b).collect();
        let together = load(folder, &bodies.concat());
        assert_eq!(together.meshes.len(), bodies.len());
        for (m, body) in together.meshes.iter().zip(&bodies) {
            let alone = load(folder, body);
            let a = &alone.meshes[0];
            assert!(!a.triangles.is_empty());
            assert_eq!(
                (&m.positions, &m.triangles, &m.normals, &m.uvs),
                (&a.positions, &a.triangles, &a.normals, &a.uvs),
                "{body}"
            );
        }
    }
}
