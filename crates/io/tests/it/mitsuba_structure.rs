//! The file structure of Mitsuba 3 documents, read from files written into a temporary folder:
//! `<include>` (relative to the including file, a scene or a single object, `$name` in its file
//! name, cycles and depth bounded), `<path>` search folders, and `<default>` versus the caller's
//! defines across files. Element-by-element behaviour is in `mitsuba.rs`.

use opticks_testkit::files as common;

use common::{error_of, load_files, load_ok};
use opticks_core::bsdf::Bsdf;
use opticks_core::math::Vec3;
use opticks_io::{LoadOptions, load_scene_with};

const BSDF: &str = r#"<bsdf type="diffuse" id="grey"><rgb name="reflectance" value="0.25"/></bsdf>"#;
const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

fn scene(body: &str) -> Vec<u8> {
    format!("<scene version=\"3.0.0\">\n{body}\n</scene>\n").into_bytes()
}

#[test]
fn includes_splice_scenes_and_single_objects_relative_to_the_including_file() {
    let s = load_ok(&[
        (
            "main.xml",
            &scene(r#"<include filename="parts/shapes.xml"/><shape type="cube"><ref id="grey"/></shape>"#),
        ),
        // Included by parts/shapes.xml as "bsdfs.xml": relative to parts/, not to main.xml.
        (
            "parts/shapes.xml",
            &scene(
                r#"<include filename="bsdfs.xml"/>
            <shape type="obj" id="tri"><string name="filename" value="tri.obj"/>
              <include filename="white.xml"/></shape>"#,
            ),
        ),
        ("parts/bsdfs.xml", &scene(BSDF)),
        (
            "parts/white.xml",
            br#"<bsdf type="diffuse" version="3.0.0"><rgb name="reflectance" value="0.75"/></bsdf>"#,
        ),
        ("parts/tri.obj", TRIANGLE.as_bytes()),
    ]);
    let d = &s.description;
    assert_eq!(d.meshes.len(), 2);
    assert_eq!((d.meshes[0].name.as_str(), d.meshes[0].triangles.len()), ("tri", 1));
    let albedo = |i: usize| match &d.materials[d.meshes[i].material].bsdf {
        Bsdf::Lambert(l) => l.reflectance.x,
        b => panic!("{b:?}"),
    };
    assert_eq!((albedo(0), albedo(1)), (0.75, 0.25));
    // Locations inside included files name those files.
    assert!(d.meshes[0].source.file.ends_with("parts/shapes.xml"), "{:?}", d.meshes[0].source);
    assert_eq!(d.meshes[0].source.line, 3);
}

#[test]
fn include_errors_are_located_and_bounded() {
    let e = error_of(&[("main.xml", &scene("\n  <include filename=\"nope.xml\"/>"))]);
    assert!(e.starts_with("TMP/main.xml:3:22: <include>: included file \"nope.xml\" not found"), "{e}");

    let e = error_of(&[
        ("main.xml", &scene(r#"<include filename="a.xml"/>"#)),
        ("a.xml", &scene(r#"<include filename="b.xml"/>"#)),
        ("b.xml", &scene(r#"<include filename="a.xml"/>"#)),
    ]);
    assert!(e.starts_with("TMP/b.xml:2:20: <include>: include cycle: "), "{e}");
    assert!(e.contains("a.xml → ") && e.contains("b.xml → ") && e.ends_with("a.xml"), "{e}");
    let e = error_of(&[("main.xml", &scene(r#"<include filename="main.xml"/>"#))]);
    assert!(e.contains("include cycle") && e.contains("main.xml → "), "{e}");

    // A chain deeper than Mitsuba's 15 levels.
    let mut files: Vec<(String, Vec<u8>)> = (0..20)
        .map(|i| (format!("f{i}.xml"), scene(&format!("<include filename=\"f{}.xml\"/>", i + 1))))
        .collect();
    files.push(("f20.xml".into(), scene("")));
    let refs: Vec<(&str, &[u8])> = files.iter().map(|(n, t)| (n.as_str(), t.as_slice())).collect();
    let e = error_of(&refs);
    assert!(e.contains("f15.xml:2:1: <include>: includes nest more than 15 deep"), "{e}");
    // 15 levels are fine.
    let e = error_of(&refs[4..]);
    assert!(e.contains("f19.xml"), "the chain from f4 is 16 files deep: {e}");
    load_ok(&refs[5..]);

    // Doubling at every level: 2^11 includes of a small file are refused, not expanded.
    let mut files: Vec<(String, Vec<u8>)> = (0..11)
        .map(|i| {
            let inc = format!("<include filename=\"g{}.xml\"/>", i + 1);
            (format!("g{i}.xml"), scene(&format!("{inc}{inc}")))
        })
        .collect();
    files.push(("g11.xml".into(), scene("<shape type=\"cube\"/>")));
    let refs: Vec<(&str, &[u8])> = files.iter().map(|(n, t)| (n.as_str(), t.as_slice())).collect();
    let e = error_of(&refs);
    assert!(e.contains("the scene includes more than 1000 files in all"), "{e}");

    // Errors inside an included file name it; an included file needs a version.
    let e = error_of(&[
        ("main.xml", &scene(r#"<include filename="bad.xml"/>"#)),
        ("bad.xml", &scene("<shape type=\"teapot\"/>")),
    ]);
    assert!(e.starts_with("TMP/bad.xml:2:14: <shape type=\"teapot\">: unsupported shape type"), "{e}");
    let e = error_of(&[("main.xml", &scene(r#"<include filename="v.xml"/>"#)), ("v.xml", b"<scene/>")]);
    assert!(e.starts_with("TMP/v.xml:1:1: <scene>: missing `version`"), "{e}");
    let e = error_of(&[("main.xml", &scene(r#"<include filename="x.xml"/>"#)), ("x.xml", b"<scene")]);
    assert!(e.starts_with("TMP/x.xml:1:"), "{e}");
}

#[test]
fn paths_are_search_folders() {
    let s = load_ok(&[
        (
            "main.xml",
            &scene(
                r#"<path value="meshes"/><path value="more"/>
            <shape type="obj"><string name="filename" value="tri.obj"/></shape>
            <shape type="obj"><string name="filename" value="quad.obj"/></shape>"#,
            ),
        ),
        ("meshes/tri.obj", TRIANGLE.as_bytes()),
        ("meshes/quad.obj", b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"),
        // The latest <path> is searched first (Mitsuba prepends them).
        ("more/quad.obj", b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2 0\nf 1 2 3 4 5\n"),
    ]);
    let tris: Vec<usize> = s.description.meshes.iter().map(|m| m.triangles.len()).collect();
    assert_eq!(tris, [1, 3]);

    let e = error_of(&[("main.xml", &scene(r#"<path value="missing"/>"#))]);
    assert!(e.starts_with("TMP/main.xml:2:14: <path>: folder \"TMP/missing\" not found"), "{e}");
    let e = error_of(&[("main.xml", &scene(r#"<shape type="cube"><path value="."/></shape>"#))]);
    assert!(e.contains("<path> is allowed only directly inside <scene>"), "{e}");
}

#[test]
fn parameters_reach_included_files_and_the_first_default_wins() {
    let files: &[(&str, &[u8])] = &[
        (
            "main.xml",
            &scene(
                r#"<default name="part" value="a"/><default name="r" value="0.5"/>
            <include filename="$part.xml"/>"#,
            ),
        ),
        (
            "a.xml",
            &scene(
                r#"<default name="r" value="0.9"/>
            <shape type="cube"><bsdf type="diffuse"><float name="reflectance" value="$r"/></bsdf></shape>"#,
            ),
        ),
        ("b.xml", &scene(r#"<shape type="rectangle"/>"#)),
    ];
    let s = load_ok(files);
    assert_eq!(s.description.meshes[0].name, "cube_0");
    let (dir, _) = load_files(files);
    let albedo = |defines: &[(&str, &str)]| {
        let opts = LoadOptions {
            defines: defines.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect(),
            ..Default::default()
        };
        let s = load_scene_with(&dir.path().join("main.xml"), &opts).unwrap();
        match &s.description.materials[0].bsdf {
            Bsdf::Lambert(l) => (s.description.meshes[0].name.clone(), l.reflectance.x),
            b => panic!("{b:?}"),
        }
    };
    assert_eq!(albedo(&[]), ("cube_0".into(), 0.5));
    assert_eq!(albedo(&[("r", "0.125")]), ("cube_0".into(), 0.125));
    assert_eq!(albedo(&[("part", "b")]).0, "rectangle_0");
    let opts = LoadOptions { defines: vec![("nope".into(), "1".into())], ..Default::default() };
    let s = load_scene_with(&dir.path().join("main.xml"), &opts).unwrap();
    assert!(
        s.warnings.iter().any(|w| w.ends_with("parameter nope is defined but the scene never uses $nope")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn analytic_shapes_take_mitsuba_parameters() {
    let s = load_ok(&[(
        "s.xml",
        &scene(
            r#"<shape type="sphere"><point name="center" x="1" y="2" z="3"/><float name="radius" value="0.5"/></shape>
               <shape type="cylinder"><point name="p0" x="0" y="0" z="0"/><point name="p1" x="0" y="2" z="0"/></shape>
               <shape type="disk"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>"#,
        ),
    )]);
    let m = &s.description.meshes;
    let far = |i: usize, c: Vec3| m[i].positions.iter().map(|p| (*p - c).length()).fold(0.0f32, f32::max);
    assert!((far(0, Vec3::new(1.0, 2.0, 3.0)) - 0.5).abs() < 1e-3 && !m[0].normals.is_empty());
    assert!(m[1].positions.iter().all(|p| (0.0..=2.0).contains(&p.y) && (p.x.hypot(p.z) - 1.0).abs() < 1e-3));
    assert!(m[2].normals.is_empty() && m[2].emission.is_some());
    // An emitter shape without a BSDF is black, as in Mitsuba; others get diffuse 0.5.
    let albedo = |i: usize| match &s.description.materials[m[i].material].bsdf {
        Bsdf::Lambert(l) => l.reflectance.x,
        b => panic!("{b:?}"),
    };
    assert_eq!((albedo(0), albedo(2)), (0.5, 0.0));

    for (body, msg) in [
        (
            r#"<shape type="sphere"><float name="radius" value="0"/></shape>"#,
            "2:22: <float name=\"radius\">: radius must be > 0",
        ),
        (
            r#"<shape type="cylinder"><point name="p1" x="0" y="0" z="0"/></shape>"#,
            "2:24: <point name=\"p1\">: the cylinder's p0 and p1 are the same point",
        ),
        (
            r#"<shape type="serialized"><string name="filename" value="x"/><integer name="shape_index" value="-1"/></shape>"#,
            "shape_index must be ≥ 0",
        ),
    ] {
        let e = error_of(&[("s.xml", &scene(body))]);
        assert!(e.contains(msg), "{msg}: {e}");
    }
}

#[test]
fn mesh_file_errors_name_the_file_the_byte_and_the_shape() {
    let shape = |ty: &str, file: &str| {
        scene(&format!(r#"<shape type="{ty}" id="m"><string name="filename" value="{file}"/></shape>"#))
    };
    let ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    let mut good = ply.to_vec();
    for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        good.extend(v.to_le_bytes());
    }
    good.push(3);
    for i in [0i32, 1, 2] {
        good.extend(i.to_le_bytes());
    }
    let s = load_ok(&[("s.xml", &shape("ply", "m.ply")), ("m.ply", &good)]);
    let m = &s.description.meshes[0];
    assert_eq!(
        (m.positions.len(), m.triangles.len(), m.normals.len()),
        (3, 1, 3),
        "smooth normals generated"
    );
    let bad = &good[..good.len() - 2];
    let e = error_of(&[("s.xml", &shape("ply", "m.ply")), ("m.ply", bad)]);
    let at = good.len() - 4;
    assert!(e.starts_with(&format!("TMP/m.ply: byte {at}: the file ends here")), "{e}");
    assert!(e.ends_with("(mesh of <shape type=\"ply\" id=\"m\"> at TMP/s.xml:2:1)"), "{e}");
    let huge = String::from_utf8_lossy(ply).replace("vertex 3", "vertex 1000000000000");
    let e = error_of(&[("s.xml", &shape("ply", "m.ply")), ("m.ply", huge.as_bytes())]);
    assert!(
        e.starts_with("TMP/m.ply:3: byte 36: 1000000000000 vertices is more than a mesh can index"),
        "{e}"
    );
    let e =
        error_of(&[("s.xml", &shape("serialized", "m.serialized")), ("m.serialized", b"\x1c\x04\x09\x00")]);
    assert!(e.starts_with("TMP/m.serialized: byte 2: unsupported serialized format version 9"), "{e}");
    let e = error_of(&[("s.xml", &shape("ply", "none.ply"))]);
    assert!(e.contains("cannot read mesh file TMP/none.ply"), "{e}");
}

#[test]
fn spectra_become_mitsubas_rgb() {
    let s = load_ok(&[
        (
            "s.xml",
            &scene(
                r#"<shape type="cube"><bsdf type="diffuse"><spectrum name="reflectance" value="400:0.1, 500:0.9, 600:0.3, 700:0.5"/></bsdf>
                     <emitter type="area"><spectrum name="radiance" value="2"/></emitter></shape>
                   <shape type="cube"><bsdf type="diffuse"><spectrum name="reflectance" filename="grey.spd"/></bsdf></shape>"#,
            ),
        ),
        ("grey.spd", b"# flat\n360 0.5\n830 0.5\n"),
    ]);
    let d = &s.description;
    let albedo = |i: usize| match &d.materials[d.meshes[i].material].bsdf {
        Bsdf::Lambert(l) => l.reflectance,
        b => panic!("{b:?}"),
    };
    // Mitsuba 3.9's spectrum_list_to_srgb(…, bounded, d65) of the same spectrum.
    let near = |a: Vec3, b: Vec3, tol: f32| (a - b).abs().max_element() < tol;
    assert!(near(albedo(0), Vec3::new(0.173511, 0.683318, 0.524217), 2e-5), "{}", albedo(0));
    assert!(near(albedo(1), Vec3::splat(0.5), 2e-3), "{}", albedo(1));
    // A constant emission spectrum is Mitsuba's equal-energy colour in RGB.
    let l = d.meshes[0].emission.as_ref().unwrap().radiance;
    assert!(near(l, Vec3::new(1.204794, 0.948291, 0.908916) * 2.0, 1e-4), "{l}");
    for (body, msg) in [
        (r#"<spectrum name="reflectance" value="500:0.5, 400:0.5"/>"#, "400 nm follows 500 nm"),
        (r#"<spectrum name="reflectance" value="500:0.5, x"/>"#, "\"x\" is not wavelength:value"),
        (r#"<spectrum name="reflectance" filename="none.spd"/>"#, "cannot read spectrum file"),
        (r#"<spectrum name="reflectance"/>"#, "needs either `value` or `filename`"),
    ] {
        let e = error_of(&[(
            "s.xml",
            &scene(&format!("<shape type=\"cube\"><bsdf type=\"diffuse\">{body}</bsdf></shape>")),
        )]);
        assert!(e.contains(msg), "{msg}: {e}");
    }
}
