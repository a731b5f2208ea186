//! The file structure of Mitsuba 3 documents, read from files written into a temporary folder:
//! `<include>` (relative to the including file, a scene or a single object, `$name` in its file
//! name, cycles and depth bounded), `<path>` search folders, and `<default>` versus the caller's
//! defines across files. Element-by-element behaviour is in `mitsuba.rs`.

mod common;

use common::{error_of, load_files, load_ok};
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
        opticks_core::bsdf::Bsdf::Lambert(l) => l.reflectance.x,
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
        let opts =
            LoadOptions { defines: defines.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect() };
        let s = load_scene_with(&dir.path().join("main.xml"), &opts).unwrap();
        match &s.description.materials[0].bsdf {
            opticks_core::bsdf::Bsdf::Lambert(l) => (s.description.meshes[0].name.clone(), l.reflectance.x),
            b => panic!("{b:?}"),
        }
    };
    assert_eq!(albedo(&[]), ("cube_0".into(), 0.5));
    assert_eq!(albedo(&[("r", "0.125")]), ("cube_0".into(), 0.125));
    assert_eq!(albedo(&[("part", "b")]).0, "rectangle_0");
    let opts = LoadOptions { defines: vec![("nope".into(), "1".into())] };
    let s = load_scene_with(&dir.path().join("main.xml"), &opts).unwrap();
    assert!(
        s.warnings.iter().any(|w| w.ends_with("parameter nope is defined but the scene never uses $nope")),
        "{:?}",
        s.warnings
    );
}
