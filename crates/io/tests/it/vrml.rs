//! VRML97 scenes through the public API: the hand-written Cornell box against the Mitsuba XML
//! one, the `--export-scene` round trip, a file from a real exporter (admesh), gzip, concave
//! faces, Inline, error positions, fuzzing (no panic, no hang), a grid loaded exactly, IES point
//! lights (candela vs the file, errors, writer round trips, from Mitsuba XML) and (ignored: a
//! measurement) the loading speed against a raw read.

use opticks_core::bsdf::Bsdf;
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::{PointLightDesc, Scene, Source, cornell_box};
use opticks_core::sensor::Pinhole;
use opticks_io::scene_formats::vrml::{self, extension::DECLARATIONS};
use opticks_io::{LoadedScene, SceneFileError, load_scene};
use proptest::prelude::*;
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};

#[global_allocator]
static ALLOCATOR: alloc_meter::Counting = alloc_meter::Counting;

/// Counts what each thread of this test binary allocates, so that the loader's bounds on work
/// (the mesh and PROTO budgets) are checked as bytes, whatever the machine's load.
mod alloc_meter {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;

    /// The system allocator, counting.
    pub struct Counting;

    thread_local! {
        static LIVE: Cell<isize> = const { Cell::new(0) };
        static PEAK: Cell<isize> = const { Cell::new(0) };
        static TOTAL: Cell<usize> = const { Cell::new(0) };
    }

    /// `freed` bytes released and `taken` bytes allocated by this thread.
    fn note(freed: usize, taken: usize) {
        let _ = LIVE.try_with(|live| {
            live.set(live.get() - freed as isize + taken as isize);
            PEAK.with(|peak| peak.set(peak.get().max(live.get())));
            TOTAL.with(|total| total.set(total.get() + taken));
        });
    }

    // SAFETY: every call is forwarded to the system allocator unchanged (same layout, same
    // pointer); only sizes are counted, in thread-locals that never allocate. A global allocator
    // can only be written as an `unsafe impl`, hence the allowance on this item alone.
    #[allow(unsafe_code)]
    unsafe impl GlobalAlloc for Counting {
        unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
            note(0, layout.size());
            unsafe { System.alloc(layout) }
        }
        unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
            note(0, layout.size());
            unsafe { System.alloc_zeroed(layout) }
        }
        unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
            note(layout.size(), 0);
            unsafe { System.dealloc(ptr, layout) }
        }
        unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
            note(layout.size(), new_size);
            unsafe { System.realloc(ptr, layout, new_size) }
        }
    }

    /// Runs `f` on this thread; returns its value, the most bytes it held at once beyond what
    /// was held before, and the bytes it allocated in all.
    pub fn measure<T>(f: impl FnOnce() -> T) -> (T, usize, usize) {
        let (live, total) = (LIVE.with(Cell::get), TOTAL.with(Cell::get));
        PEAK.with(|peak| peak.set(live));
        let out = f();
        let peak = PEAK.with(Cell::get) - live;
        (out, peak.max(0) as usize, TOTAL.with(Cell::get) - total)
    }
}

fn testdata(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata").join(rel)
}

fn load_text(text: &str) -> Result<LoadedScene, SceneFileError> {
    vrml::load_str(text, Path::new("t.wrl"))
}

fn with_header(body: &str) -> String {
    format!("#VRML V2.0 utf8\n{DECLARATIONS}{body}")
}

/// Total area and area-weighted normal of the non-emitting triangles of each material (by name).
fn area_by_material(s: &Scene) -> HashMap<String, (f32, Vec3)> {
    let mut m: HashMap<String, (f32, Vec3)> = HashMap::new();
    for (i, t) in s.triangles.iter().enumerate() {
        if s.light_of(i as u32).is_some() {
            continue;
        }
        let e = m.entry(s.material(i as u32).name.clone()).or_default();
        e.0 += t.area();
        e.1 += t.area() * t.normal();
    }
    m
}

fn assert_same_camera(a: &Scene, b: &Scene) {
    let (pa, pb) = (Pinhole::new(&a.camera.unwrap()).unwrap(), Pinhole::new(&b.camera.unwrap()).unwrap());
    assert!((pa.eye - pb.eye).length() < 1e-5, "{pa:?} vs {pb:?}");
    assert!((pa.forward - pb.forward).length() < 1e-5, "{pa:?} vs {pb:?}");
    assert!((pa.up - pb.up).length() < 1e-5, "{pa:?} vs {pb:?}");
    assert!((pa.tan_x - pb.tan_x).abs() < 1e-5 && (pa.tan_y - pb.tan_y).abs() < 1e-5, "{pa:?} vs {pb:?}");
    assert_eq!((pa.width, pa.height), (pb.width, pb.height));
}

fn total_power(s: &Scene) -> Rgb {
    s.light_powers().iter().copied().sum()
}

fn assert_power_close(a: Rgb, b: Rgb) {
    assert!(((a - b).abs() / b.max(Rgb::splat(1e-12))).max_element() < 1e-4, "{a:?} vs {b:?}");
}

#[test]
fn hand_written_cornell_box_is_the_mitsuba_scene() {
    let xml = load_scene(&testdata("scenes/cornell/scene.xml")).unwrap();
    let wrl = load_scene(&testdata("vrml/cornell.wrl")).unwrap();
    assert!(wrl.warnings.is_empty(), "{:#?}", wrl.warnings);
    let (a, b) = (Scene::build(&xml.description).unwrap(), Scene::build(&wrl.description).unwrap());
    assert_eq!(a.triangles.len(), b.triangles.len());
    assert_eq!(a.lights.len(), b.lights.len());
    assert_power_close(total_power(&b), total_power(&a));
    assert_same_camera(&a, &b);
    // Every XML material has a VRML one of the same name and BSDF, two-sided like it.
    for m in &xml.description.materials {
        let v = wrl
            .description
            .materials
            .iter()
            .find(|v| v.name == m.name)
            .unwrap_or_else(|| panic!("{}", m.name));
        assert_eq!((&v.bsdf, v.two_sided), (&m.bsdf, m.two_sided), "{}", m.name);
    }
    // Same surface per material, facing the same way (boxes are VRML Boxes: 1e-4 tolerance).
    let (aa, ab) = (area_by_material(&a), area_by_material(&b));
    for (name, (area, n)) in &aa {
        let (area_b, n_b) = ab[name];
        assert!((area - area_b).abs() < 1e-4 * area, "{name}: area {area} vs {area_b}");
        assert!((*n - n_b).length() < 1e-4 * area, "{name}: {n:?} vs {n_b:?}");
    }
    // The light faces down, emitting the same radiance.
    let light = wrl.description.meshes.iter().find(|m| m.emission.is_some()).unwrap();
    assert_eq!(light.emission.as_ref().map(|e| e.radiance), Some(Rgb::new(18.387, 13.9873, 6.75357)));
    let i =
        b.triangles.iter().position(|t| (t.normal() + Vec3::Y).length() < 1e-6 && t.point(0.3, 0.3).y > 0.98);
    assert!(i.is_some());
}

#[test]
fn exported_demo_scene_loads_back_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let desc = cornell_box();
    for name in ["cornell.wrl", "cornell.wrl.gz"] {
        let path = dir.path().join(name);
        vrml::write_vrml_file(&desc, &path).unwrap();
        let loaded = load_scene(&path).unwrap();
        assert!(loaded.warnings.is_empty(), "{:#?}", loaded.warnings);
        let (a, b) = (Scene::build(&desc).unwrap(), Scene::build(&loaded.description).unwrap());
        assert_eq!(a.triangles.len(), b.triangles.len());
        assert_power_close(total_power(&b), total_power(&a));
        assert_same_camera(&a, &b);
        // Positions are written exactly.
        for (m, l) in desc.meshes.iter().zip(&loaded.description.meshes) {
            assert_eq!((&m.positions, &m.triangles, &m.emission), (&l.positions, &l.triangles, &l.emission));
        }
    }
}

#[test]
fn point_lights_and_phong_round_trip() {
    let mut desc = cornell_box();
    desc.point_lights.push(PointLightDesc {
        name: "bulb".into(),
        source: Source::default(),
        position: Vec3::new(0.1, 0.5, -0.2),
        intensity: Rgb::new(1.0, 2.0, 3.0),
        ..Default::default()
    });
    desc.materials[1].bsdf = Bsdf::ModifiedPhong(
        opticks_core::bsdf::ModifiedPhong::new(Rgb::splat(0.3), Rgb::splat(0.6), 42.5).unwrap(),
    );
    desc.camera.as_mut().unwrap().width = 320;
    let mut text = Vec::new();
    vrml::write_vrml(&desc, &mut text).unwrap();
    let loaded = load_text(std::str::from_utf8(&text).unwrap()).unwrap();
    assert_eq!(loaded.description.point_lights[0].intensity, Rgb::new(1.0, 2.0, 3.0));
    assert_eq!(loaded.description.point_lights[0].position, Vec3::new(0.1, 0.5, -0.2));
    let red = loaded.description.materials.iter().find(|m| m.name == "red").unwrap();
    assert_eq!(red.bsdf, desc.materials[1].bsdf);
    let (a, b) = (Scene::build(&desc).unwrap(), Scene::build(&loaded.description).unwrap());
    assert_same_camera(&a, &b);
    // A camera VRML has no node for is refused, not written as a pinhole.
    let camera = desc.camera.unwrap();
    for kind in [
        opticks_core::scene::CameraKind::ThinLens { aperture_radius: 0.1, focus_distance: 2.0 },
        opticks_core::scene::CameraKind::Orthographic { half_width: 1.0, half_height: 0.5 },
    ] {
        desc.camera = Some(opticks_core::scene::CameraDesc { kind, ..camera });
        let e = vrml::write_vrml(&desc, &mut Vec::new()).unwrap_err();
        assert!(e.to_string().contains("the camera is"), "{e}");
    }
    // Nor is a spot's projected texture dropped.
    desc.camera = Some(camera);
    let mut spot =
        PointLightDesc::spot("s".into(), Source::default(), Vec3::Y, -glam::DVec3::Y, Rgb::ONE, 0.5, 0.3);
    spot.as_mut().unwrap().texture = Some(std::sync::Arc::new(opticks_core::texture::Texture::Constant(0.5)));
    desc.point_lights.push(spot.unwrap());
    let e = vrml::write_vrml(&desc, &mut Vec::new()).unwrap_err();
    assert!(e.to_string().contains("spot light s projects a texture"), "{e}");
}

#[test]
fn real_exporter_output_loads() {
    // ADMesh writes VRML 1.0, another format: refused with a clear message.
    let e = load_scene(&testdata("vrml/icosphere-admesh.wrl")).unwrap_err().to_string();
    assert!(e.contains("icosphere-admesh.wrl:1:1") && e.contains("VRML 1.0"), "{e}");
    // OpenCTM's ctmconv writes VRML97: white diffuse 1 + specular 0.8 gets scaled (a warning).
    let mut loaded = load_scene(&testdata("vrml/icosphere-ctmconv.wrl")).unwrap();
    assert!(loaded.warnings.iter().any(|w| w.contains("exceeds 1")), "{:#?}", loaded.warnings);
    assert_eq!(loaded.warnings.len(), 1, "{:#?}", loaded.warnings);
    let d = &mut loaded.description;
    assert_eq!(d.meshes.len(), 1);
    assert_eq!(d.meshes[0].triangles.len(), 80);
    // All corners on the unit sphere, all faces outward.
    for m in &d.meshes {
        assert!(m.positions.iter().all(|p| (p.length() - 1.0).abs() < 1e-4));
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            assert!((b - a).cross(c - a).dot(a + b + c) > 0.0);
        }
    }
    d.point_lights.push(PointLightDesc {
        name: "lamp".into(),
        source: Source::default(),
        position: Vec3::new(0.0, 3.0, 0.0),
        intensity: Rgb::ONE,
        ..Default::default()
    });
    let s = Scene::build(d).unwrap();
    assert_eq!(s.triangles.len(), 80);
}

/// A UTF-8 byte order mark (as Windows editors write) before the header: the file loads, and
/// positions after it are unchanged (regression: the header check skipped it, the lexer did not).
#[test]
fn a_byte_order_mark_is_skipped() {
    let body = "Shape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] } coordIndex [ 0 1 2 ] } }";
    let s = load_text(&format!("\u{feff}#VRML V2.0 utf8\n{body}")).unwrap();
    assert_eq!(s.description.meshes.len(), 1);
    assert_eq!(s.description.meshes[0].name, "Shape_2_1");
    let e = load_text("\u{feff}#VRML V2.0 utf8\nShape { bogus 1 }").unwrap();
    assert!(e.warnings.iter().any(|w| w.starts_with("t.wrl:2:9: ")), "{:?}", e.warnings);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bom.wrl");
    std::fs::write(&path, format!("\u{feff}#VRML V2.0 utf8\n{body}")).unwrap();
    assert_eq!(load_scene(&path).unwrap().description.meshes.len(), 1);
}

/// EXTERNPROTO with a readable local library file: the PROTO (interface defaults and body)
/// comes from it and instances expand; an unreachable URL, a missing PROTO and a library that
/// includes itself are warnings, with the instance skipped.
#[test]
fn externprotos_load_from_local_library_files() {
    let s = load_scene(&testdata("vrml/uses-protolib.wrl")).unwrap();
    let d = &s.description;
    assert_eq!(d.meshes.len(), 2, "{:#?}", s.warnings);
    assert_eq!(d.meshes[1].positions[0], Vec3::new(0.0, 0.0, -1.0));
    let colours: Vec<Rgb> = d
        .materials
        .iter()
        .map(|m| match &m.bsdf {
            Bsdf::Lambert(l) => l.reflectance,
            b => panic!("{b:?}"),
        })
        .collect();
    assert_eq!(
        colours,
        [Rgb::new(0.2, 0.4, 0.6), Rgb::splat(0.5)],
        "the instance's value, then the library default"
    );
    let w = s.warnings.join("\n");
    assert!(w.contains("`Remote` is an EXTERNPROTO"), "{w}");
    assert!(w.contains("EXTERNPROTO Absent") && w.contains("has no PROTO Absent"), "{w}");
    assert!(w.contains("EXTERNPROTO Loop") && w.contains("includes itself"), "{w}");
    // Without a file there is no directory to resolve against: skipped as before.
    let text = std::fs::read_to_string(testdata("vrml/uses-protolib.wrl")).unwrap();
    let parsed = vrml::parser::parse(&text).unwrap();
    assert!(parsed.warnings.iter().any(|(_, m)| m.contains("`Triangle` is an EXTERNPROTO")));
}

#[test]
fn gzip_compressed_files_load() {
    let text = std::fs::read(testdata("vrml/cornell.wrl")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for name in ["c.wrl.gz", "c.wrz", "C.WRL"] {
        let path = dir.path().join(name);
        let mut gz =
            flate2::write::GzEncoder::new(std::fs::File::create(&path).unwrap(), flate2::Compression::fast());
        gz.write_all(&text).unwrap();
        gz.finish().unwrap();
        let l = load_scene(&path).unwrap();
        assert_eq!(l.description.meshes.len(), 6, "{name}");
    }
    let bad = dir.path().join("bad.wrl.gz");
    std::fs::write(&bad, [0x1f, 0x8b, 1, 2, 3]).unwrap();
    assert!(matches!(load_scene(&bad), Err(SceneFileError::Read { .. })));
}

#[test]
fn concave_face_is_triangulated_in_its_plane() {
    // An L of area 3 in a tilted plane, counter-clockwise seen from +n.
    let (ex, ey) = (Vec3::new(0.6, 0.0, -0.8), Vec3::new(0.0, 1.0, 0.0));
    let n = ex.cross(ey);
    let pts: Vec<String> = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
        .iter()
        .map(|&(x, y)| {
            let p = ex * x + ey * y;
            format!("{} {} {}", p.x, p.y, p.z)
        })
        .collect();
    for (ccw, sign) in [("TRUE", 1.0), ("FALSE", -1.0)] {
        let l = load_text(&with_header(&format!(
            "Shape {{ geometry IndexedFaceSet {{ ccw {ccw} coord Coordinate {{ point [ {} ] }} coordIndex [ 3 4 5 0 1 2 -1 ] }} }}",
            pts.join(", ")
        )))
        .unwrap();
        let m = &l.description.meshes[0];
        assert_eq!(m.triangles.len(), 4);
        let mut area = 0.0;
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let an = 0.5 * (b - a).cross(c - a);
            assert!(an.dot(n) * sign > 0.0, "ccw {ccw}: {t:?}");
            area += an.length();
        }
        assert!((area - 3.0).abs() < 1e-5, "{area}");
    }
}

#[test]
fn inline_files_load_relative_and_recursion_is_stopped() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    let tri = "Shape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] } coordIndex [ 0 1 2 ] } }";
    std::fs::write(
        dir.path().join("a.wrl"),
        format!("#VRML V2.0 utf8\nTransform {{ translation 0 0 5 children Inline {{ url \"sub/b.wrl\" }} }}\n{tri}"),
    )
    .unwrap();
    std::fs::write(
        dir.path().join("sub/b.wrl"),
        format!("#VRML V2.0 utf8\nInline {{ url \"../a.wrl\" }}\n{tri}"),
    )
    .unwrap();
    let l = load_scene(&dir.path().join("a.wrl")).unwrap();
    let d = &l.description;
    // a's triangle, b's triangle (moved by 5), and nothing more: b including a is refused.
    assert_eq!(d.meshes.len(), 2, "{:#?}", l.warnings);
    assert!(d.meshes.iter().any(|m| m.positions[0].z == 5.0));
    assert!(
        l.warnings.iter().any(|w| w.contains("Inline recursion") && w.contains("b.wrl:2:1")),
        "{:#?}",
        l.warnings
    );
}

#[test]
fn unknown_nodes_and_fields_are_warnings_with_positions() {
    let l =
        load_text("#VRML V2.0 utf8\nGroup { children [\n  Teapot { size 3 }\n  Box { colour 1 0 0 }\n] }\n")
            .unwrap();
    assert!(
        l.warnings.iter().any(|w| w.starts_with("t.wrl:3:3: unknown node type `Teapot`")),
        "{:#?}",
        l.warnings
    );
    assert!(
        l.warnings.iter().any(|w| w.starts_with("t.wrl:4:9: `Box` has no field `colour`")),
        "{:#?}",
        l.warnings
    );
}

#[test]
fn malformed_files_give_file_line_column_errors() {
    let cases: &[(&str, &str)] = &[
        (
            "#VRML V2.0 utf8\nTransform { translation 1 2 }",
            "t.wrl:2:29: VRML syntax: expected a number, found `}`",
        ),
        (
            "#VRML V2.0 utf8\nGroup { children [ Box { } }",
            "t.wrl:2:28: VRML syntax: expected a node, USE or `]`, found `}`",
        ),
        ("#VRML V2.0 utf8\nShape {\n  geometry USE nothing }", "t.wrl:3:16: VRML syntax: USE of `nothing`"),
        ("#VRML V2.0 utf8\nWorldInfo { title \"open", "t.wrl:2:19: VRML syntax: string not closed"),
        (
            "#VRML V2.0 utf8\nDEF 1 Group {}",
            "t.wrl:2:5: VRML syntax: expected a name after DEF, found number 1",
        ),
        (
            "#VRML V2.0 utf8\nPROTO P [ field SFFoo x 1 ] { Group {} }",
            "t.wrl:2:17: VRML syntax: expected a field type",
        ),
        ("Group {}", "t.wrl:1:1: VRML syntax: expected the header"),
        (
            "#VRML V2.0 utf8\nShape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0 ] } coordIndex [ 0 1 2 ] } }",
            "t.wrl:2:18: IndexedFaceSet: coordIndex[1] = 1 is out of range",
        ),
        (
            "#VRML V2.0 utf8\nShape { appearance Appearance { material Material { diffuseColor -1 0 0 } } geometry Box {} }",
            "t.wrl:2:42: Material: invalid material",
        ),
    ];
    for (text, want) in cases {
        let e = load_text(text).unwrap_err().to_string();
        assert!(e.starts_with(want), "got:  {e}\nwant: {want}…");
    }
}

#[test]
fn deep_nesting_is_an_error() {
    let text = format!("#VRML V2.0 utf8\n{}", "Transform { children ".repeat(50_000));
    let e = load_text(&text).unwrap_err().to_string();
    assert!(e.contains("nested more than"), "{e}");
}

#[test]
fn deep_graphs_through_inlines_are_an_error_not_a_stack_overflow() {
    let dir = tempfile::tempdir().unwrap();
    for i in 0..10 {
        let inner = format!("Inline {{ url \"f{}.wrl\" }}", i + 1);
        let text = format!(
            "#VRML V2.0 utf8\n{}{inner}{}",
            "Transform { translation 0 0 1 children [ ".repeat(150),
            " ] }".repeat(150)
        );
        std::fs::write(dir.path().join(format!("f{i}.wrl")), text).unwrap();
    }
    let e = load_scene(&dir.path().join("f0.wrl")).unwrap_err().to_string();
    assert!(e.contains("f2.wrl") && e.contains("levels deep"), "{e}");
}

/// An `n` × `n` height-field grid as one IndexedFaceSet (two triangles per cell); returns the
/// vertex function used.
fn write_grid(path: &Path, n: usize) -> fn(usize, usize) -> Vec3 {
    fn vertex(i: usize, j: usize) -> Vec3 {
        let (x, z) = (i as f32 * 0.0123456, j as f32 * 0.0123456);
        Vec3::new(x, (x * 3.0).sin() * (z * 2.0).cos(), z)
    }
    let mut w = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    writeln!(w, "#VRML V2.0 utf8\nShape {{ geometry IndexedFaceSet {{ coord Coordinate {{ point [").unwrap();
    for j in 0..n {
        for i in 0..n {
            let p = vertex(i, j);
            writeln!(w, "{:.6} {:.6} {:.6},", p.x, p.y, p.z).unwrap();
        }
    }
    writeln!(w, "] }} coordIndex [").unwrap();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let k = j * n + i;
            writeln!(w, "{} {} {} -1 {} {} {} -1", k, k + n, k + n + 1, k, k + n + 1, k + 1).unwrap();
        }
    }
    writeln!(w, "] }} }}").unwrap();
    w.flush().unwrap();
    vertex
}

/// The grid the loading-speed bench reads, small: every position and every triangle exactly.
#[test]
fn a_grid_loads_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("grid.wrl");
    let n = 60;
    let vertex = write_grid(&path, n);
    let d = load_scene(&path).unwrap().description;
    let m = &d.meshes[0];
    assert_eq!(m.triangles.len(), 2 * (n - 1) * (n - 1));
    assert_eq!(m.positions.len(), n * n);
    for j in 0..n {
        for i in 0..n {
            assert!((m.positions[j * n + i] - vertex(i, j)).abs().max_element() < 1e-6);
        }
    }
    for (c, t) in m.triangles.chunks(2).enumerate() {
        let k = (c / (n - 1) * n + c % (n - 1)) as u32;
        let n = n as u32;
        assert_eq!(t, [[k, k + n, k + n + 1], [k, k + n + 1, k + 1]]);
    }
}

/// Loading speed of a 1 M-triangle VRML IndexedFaceSet, in stages, against a raw read of the
/// same file measured in the same run (a figure, not a check: run with `--ignored --nocapture`).
#[test]
#[ignore = "speed measurement; run with --ignored --nocapture"]
fn bench_a_million_triangles() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.wrl");
    let n = 708usize; // (n-1)² · 2 ≈ 1.0 M triangles
    write_grid(&path, n);
    let mb = std::fs::metadata(&path).unwrap().len() as f64 / 1e6;
    let t = std::time::Instant::now();
    let raw = std::fs::read(&path).unwrap();
    let t_raw = t.elapsed().as_secs_f64();
    drop(raw);
    let t = std::time::Instant::now();
    let l = load_scene(&path).unwrap();
    let total = t.elapsed().as_secs_f64();
    assert_eq!(l.description.meshes[0].triangles.len(), 2 * (n - 1) * (n - 1));
    drop(l);
    // The same in stages: read, parse (lexer + parser), convert (triangulation, transforms).
    let t = std::time::Instant::now();
    let text = vrml::read_source(&path).unwrap();
    let t_read = t.elapsed().as_secs_f64();
    let t = std::time::Instant::now();
    let (nodes, warnings) = vrml::parse_text(&text, &path).unwrap();
    let t_parse = t.elapsed().as_secs_f64();
    let t = std::time::Instant::now();
    let l = vrml::convert::convert(&nodes, &path, warnings).unwrap();
    let t_convert = t.elapsed().as_secs_f64();
    println!(
        "VRML load of {mb:.1} MB ({} triangles): {total:.3} s = {:.0} MB/s \
         [raw read {:.0} MB/s, read + UTF-8 check {:.0} MB/s, parse {:.0} MB/s, convert {:.3} s]",
        l.description.meshes[0].triangles.len(),
        mb / total,
        mb / t_raw,
        mb / t_read,
        mb / t_parse,
        t_convert
    );
}

// ----- fuzzing -----

const SEED_FILE: &str = r#"#VRML V2.0 utf8
PROTO P [ field SFColor c 1 0 0 field MFNode kids [] exposedField SFFloat f 1 ]
{ Group { children [ Shape { appearance Appearance { material Material { diffuseColor IS c } } geometry Sphere { radius IS f } } ] } }
EXTERNPROTO E [ field SFFloat x ] [ "e.wrl#E" ]
DEF T Transform { translation 1 2 3 rotation 0 1 0 0.5 scale 1 2 1 children [
  P { c 0 1 0 } E { x 2 }
  Switch { whichChoice 0 choice [ USE T2 ] }
  Shape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 1 1 0, 0 1 0 ] } coordIndex [ 0 1 2 3 -1 ] ccw FALSE } }
  Viewpoint { position 0 0 5 fieldOfView 0.7 }
  PointLight { location 0 1 0 intensity 0.5 }
  Script { eventIn SFBool go field SFInt32 n 3 url "javascript:" }
] }
ROUTE T.translation_changed TO T.set_translation
PixelTexture { image 1 1 3 0xFF00FF }
ElevationGrid { xDimension 2 zDimension 2 height [ 0 1 2 3 ] }
"#;

const WORDS: &[&str] = &[
    "DEF",
    "USE",
    "PROTO",
    "EXTERNPROTO",
    "IS",
    "ROUTE",
    "TO",
    "NULL",
    "TRUE",
    "FALSE",
    "field",
    "exposedField",
    "eventIn",
    "SFFloat",
    "MFNode",
    "SFColor",
    "Transform",
    "Group",
    "Shape",
    "Box",
    "IndexedFaceSet",
    "Coordinate",
    "coordIndex",
    "point",
    "children",
    "geometry",
    "translation",
    "Switch",
    "Inline",
    "url",
    "A",
    "B",
    "P",
    "{",
    "}",
    "[",
    "]",
    ".",
    "1",
    "-1",
    "0.5",
    "1e30",
    "0x1F",
    "\"s\"",
    "\"",
    "#c\n",
    ",",
    "\\",
    "'",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn token_soup_never_panics(words in prop::collection::vec(0..WORDS.len(), 0..200)) {
        let body: Vec<&str> = words.iter().map(|&i| WORDS[i]).collect();
        let _ = load_text(&format!("#VRML V2.0 utf8\n{}", body.join(" ")));
    }

    #[test]
    fn truncations_never_panic(cut in 0..SEED_FILE.len()) {
        if SEED_FILE.is_char_boundary(cut) {
            let _ = load_text(&SEED_FILE[..cut]);
        }
    }

    #[test]
    fn mutations_never_panic(edits in prop::collection::vec((0..SEED_FILE.len(), 0..WORDS.len(), 0..3u8), 1..8)) {
        let mut text = SEED_FILE.to_string();
        for (at, w, kind) in edits {
            let mut at = at.min(text.len());
            while !text.is_char_boundary(at) { at -= 1; }
            match kind {
                0 => text.insert_str(at, WORDS[w]),
                1 => { let end = (at + 1 + w % 7).min(text.len()); if text.is_char_boundary(end) { text.replace_range(at..end, ""); } }
                _ => text.insert_str(at, &format!(" {} ", WORDS[w])),
            }
        }
        let _ = load_text(&text);
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let text = format!("#VRML V2.0 utf8\n{}", String::from_utf8_lossy(&bytes));
        let _ = load_text(&text);
    }
}

#[test]
fn instancing_bombs_are_bounded() {
    // A few KB of input must be refused before it takes much memory or work: the mesh budget of
    // a file is max(MIN_MESH_BUDGET, MAX_AMPLIFICATION × its size) (64 MB here, 88 MB for the
    // points), and every byte the loader allocates is counted. Measured: the boxes hold at most
    // 2.1 budgets (meshes plus the growing mesh list) and allocate 3.2 in all, the points 1.1.
    let bomb = |first: &str| {
        let mut s = format!("#VRML V2.0 utf8\nDEF L0 {first}\n");
        for i in 1..40 {
            s += &format!("DEF L{i} Group {{ children [ USE L{} USE L{} ] }}\n", i - 1, i - 1);
        }
        s
    };
    // Each level USEs the previous one twice: 2^40 Boxes.
    let boxes = bomb("Shape { geometry Box {} }");
    // The same with a DEF'd IndexedFaceSet of 10 000 points and no faces: no triangle is
    // produced, so only a budget that counts positions stops it.
    let points: String = (0..10_000).map(|i| format!("{i} 0 0,")).collect();
    let empty = bomb(&format!(
        "Shape {{ geometry IndexedFaceSet {{ coord Coordinate {{ point [ {points} ] }} coordIndex [ ] }} }}"
    ));
    for (name, s) in [("boxes", boxes), ("points", empty)] {
        let (e, peak, total) = alloc_meter::measure(|| load_text(&s).unwrap_err().to_string());
        eprintln!(
            "{name}: {} KB refused after {peak} bytes held at most, {total} allocated: {e}",
            s.len() / 1000
        );
        assert!(e.contains("more than") && e.contains("MB"), "{e}");
        let budget = vrml::convert::MIN_MESH_BUDGET.max(vrml::convert::MAX_AMPLIFICATION * s.len());
        assert!(peak < 3 * budget && total < 5 * budget, "{name}: held {peak}, allocated {total} bytes");
    }
}

#[test]
fn proto_expansion_is_bounded_in_bytes_too() {
    // 2^20 copies of a 10 000-point field (120 kB each): the byte limit (MAX_EXPANDED_BYTES,
    // 256 MB of copied field values) stops it after ~2 200 copies (~9 000 nodes, far under the
    // node limit), before 125 GB. Every byte the parser allocates is counted.
    let points: String = (0..10_000).map(|i| format!("{i} 0 0,")).collect();
    let mut s = format!(
        "#VRML V2.0 utf8\nPROTO P0 [ ] {{ Shape {{ geometry IndexedFaceSet {{ coord Coordinate {{ point [ {points} ] }} }} }} }}\n"
    );
    for i in 1..21 {
        let p = i - 1;
        s += &format!("PROTO P{i} [ ] {{ Group {{ children [ P{p} {{}} P{p} {{}} ] }} }}\n");
    }
    s += "P20 {}";
    let (e, peak, total) =
        alloc_meter::measure(|| vrml::parse_text(&s, Path::new("t.wrl")).unwrap_err().to_string());
    eprintln!("refused after {peak} bytes held at most, {total} allocated: {e}");
    assert!(e.contains("MB of field values"), "{e}");
    // Measured: 1.0 limits held at most, 2.0 allocated (each copied value is built, then moved).
    let limit = vrml::proto::MAX_EXPANDED_BYTES;
    assert!(peak < 2 * limit && total < 3 * limit, "held {peak}, allocated {total} bytes");
}

/// The normals of the (only) mesh of a VRML body.
fn mesh_of(body: &str) -> opticks_core::scene::MeshDesc {
    load_text(&with_header(body)).unwrap().description.meshes.remove(0)
}

/// A cube of 8 shared points and 6 quads (outward), with `extra` fields on the IndexedFaceSet.
fn cube(extra: &str) -> String {
    format!(
        "Shape {{ geometry IndexedFaceSet {{ {extra} coord Coordinate {{ point [ -1 -1 -1, 1 -1 -1, 1 1 -1, -1 1 -1, \
         -1 -1 1, 1 -1 1, 1 1 1, -1 1 1 ] }} coordIndex [ 0 3 2 1 -1, 4 5 6 7 -1, 0 1 5 4 -1, 3 7 6 2 -1, \
         0 4 7 3 -1, 1 2 6 5 -1 ] }} }} PointLight {{ location 0 3 0 }}"
    )
}

#[test]
fn indexed_face_set_normals_follow_vrml97() {
    // Given per point (normalPerVertex TRUE, no normalIndex): one normal per position.
    let m = mesh_of(
        "Shape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] } \
         normal Normal { vector [ 0 0 1, 0.2 0 1, 0 0.2 1 ] } coordIndex [ 0 1 2 ] } }",
    );
    assert_eq!(m.normals, vec![Vec3::Z, Vec3::new(0.2, 0.0, 1.0), Vec3::new(0.0, 0.2, 1.0)]);
    // normalIndex per corner, and per face.
    let m = mesh_of(
        "Shape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] } \
         normal Normal { vector [ 0 0 1, 0.2 0 1 ] } coordIndex [ 0 1 2 -1 ] normalIndex [ 1 1 0 -1 ] } }",
    );
    assert_eq!(m.normals, vec![Vec3::new(0.2, 0.0, 1.0), Vec3::new(0.2, 0.0, 1.0), Vec3::Z]);
    let m = mesh_of(
        "Shape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] } \
         normal Normal { vector [ 0 0 1, 0.2 0 1 ] } normalPerVertex FALSE normalIndex [ 1 ] coordIndex [ 0 1 2 ] } }",
    );
    assert_eq!(m.normals, vec![Vec3::new(0.2, 0.0, 1.0); 3]);
    // An index past the Normal node is an error naming the field.
    let e = load_text(&with_header(
        "Shape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] } \
         normal Normal { vector [ 0 0 1 ] } coordIndex [ 0 1 2 ] normalIndex [ 0 0 4 ] } }",
    ))
    .unwrap_err();
    assert!(e.to_string().contains("normalIndex[2] = 4"), "{e}");

    // Without normals: creaseAngle 0 (default) and 1 rad (< the cube's 90° edges) are faceted,
    // 2 rad smooths every corner to the cube's diagonal.
    let build =
        |extra: &str| Scene::build(&load_text(&with_header(&cube(extra))).unwrap().description).unwrap();
    assert!(mesh_of(&cube("")).normals.is_empty());
    assert!(!build("").has_shading_normals() && !build("creaseAngle 1").has_shading_normals());
    let smooth = build("creaseAngle 2");
    assert!(smooth.has_shading_normals());
    let n = smooth.normals_at(0, Vec3::new(-1.0, -1.0, -1.0)).shading;
    assert!((n - Vec3::splat(-1.0).normalize()).length() < 1e-5, "{n}");
    // The faceted cube is the one that was always loaded (same geometry fingerprint).
    let faceted = build("creaseAngle 1");
    assert_eq!(faceted.fingerprint.geometry, build("").fingerprint.geometry);
}

#[test]
fn sphere_and_cylinder_sides_have_smooth_normals() {
    let m = mesh_of("Shape { geometry Sphere { radius 2 } }");
    for (p, n) in m.positions.iter().zip(&m.normals) {
        assert!((p.normalize() - n.normalize()).length() < 1e-6);
    }
    let m = mesh_of("Shape { geometry Cylinder { } }");
    assert_eq!(m.normals.len(), m.positions.len());
    for (p, n) in m.positions.iter().zip(&m.normals) {
        let n = n.normalize();
        // Side: horizontal and radial; caps (|y| = 1 at the centre or the rim): ±y.
        let radial = Vec3::new(p.x, 0.0, p.z).normalize_or_zero();
        assert!((n - radial).length() < 1e-5 || (n.y.abs() - 1.0).abs() < 1e-6, "{p} {n}");
    }
    assert!(mesh_of("Shape { geometry Box { } }").normals.is_empty());
}

/// A folder holding `lum/ww.ies` (the asymmetric wall washer test file) and `scene.wrl` with
/// `body` after the extension's declarations and a floor triangle.
fn ies_scene(body: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("lum")).unwrap();
    std::fs::copy(testdata("ies/asymmetric-wallwasher.ies"), dir.path().join("lum/ww.ies")).unwrap();
    let floor = "Shape { geometry IndexedFaceSet { coord Coordinate { point [ -5 0 -5, 5 0 -5, 0 0 5 ] } coordIndex [ 0 1 2 ] } }";
    let path = dir.path().join("scene.wrl");
    std::fs::write(&path, with_header(&format!("{body}\n{floor}\n"))).unwrap();
    (dir, path)
}

/// Candela of a built point light towards world direction `d` (red channel).
fn candela(l: &opticks_core::light::PointLight, d: Vec3) -> f32 {
    opticks_core::light::LUMENS_PER_WATT * l.intensity.x * l.profile.shape(l.frame.to_local(d.normalize()))
}

#[test]
fn ies_point_lights_carry_the_files_candela_in_their_frame() {
    // Rotated 90° about z: the vertical 0° axis (0 -1 0) points along +x, horizontal 0° along +y.
    let (_dir, path) = ies_scene(
        "Transform { rotation 0 0 1 1.5707963267948966 children [\n\
         DEF ww PhysicalPointLight { location 0 2 0 iesUrl [ \"http://example.com/ww.ies\" \"lum/ww.ies\" ] \
         direction 0 -1 0 horizontal 1 0 0 }\n\
         DEF bright PhysicalPointLight { iesUrl \"lum/ww.ies\" intensity 1 0.5 0.25 lumens 1000 }\n] }",
    );
    let loaded = load_scene(&path).unwrap();
    let lights = &loaded.description.point_lights;
    assert_eq!(lights.len(), 2);
    let file = path.parent().unwrap().join("lum/ww.ies").canonicalize().unwrap();
    assert_eq!(lights[0].ies_file.as_ref(), Some(&file));
    assert_eq!((lights[0].intensity, lights[0].power), (Rgb::ONE, None));
    assert!((lights[0].position - Vec3::new(-2.0, 0.0, 0.0)).length() < 1e-6);
    // lumens set the flux keeping the intensity's colour (683·luminance = lumens).
    let want = opticks_core::light::lumens_to_watts(1000.0, Rgb::new(1.0, 0.5, 0.25)).unwrap();
    assert_eq!(lights[1].power, Some(want));
    let scene = Scene::build(&loaded.description).unwrap();
    let l = match &scene.lights[0] {
        opticks_core::light::Light::Point(l) => l,
        other => panic!("{other:?}"),
    };
    // The file's values × its multiplier 2 at grid angles (θ from the axis, φ = 0 or 180°).
    let (axis, h0) = (Vec3::X, Vec3::Y);
    let at = |theta: f32, phi0: bool| {
        let t = theta.to_radians();
        axis * t.cos() + h0 * (if phi0 { t.sin() } else { -t.sin() })
    };
    for (theta, phi0, cd) in [
        (0.0, true, 800.0),
        (30.0, true, 860.0),
        (30.0, false, 360.0),
        (60.0, true, 400.0),
        (60.0, false, 60.0),
        (120.0, true, 0.0),
    ] {
        let got = candela(l, at(theta, phi0));
        assert!(
            (got - cd).abs() <= 1e-3 * cd.max(1.0),
            "θ {theta}, φ {}: {got} cd, the file {cd}",
            if phi0 { 0 } else { 180 }
        );
    }
}

#[test]
fn bad_ies_urls_and_files_are_errors_at_the_light() {
    let cases: &[(&str, &str, &str)] = &[
        ("PhysicalPointLight { iesUrl \"lum/none.ies\" }", "none of the URLs", ""),
        ("PhysicalPointLight { iesUrl \"lum/bad.ies\" }", "bad.ies", "TILT"),
        ("PhysicalPointLight { iesUrl \"lum/ww.ies\" power 1 1 1 lumens 10 }", "either power or lumens", ""),
    ];
    for (body, want, also) in cases {
        let (dir, path) = ies_scene(&format!("\n\n{body}"));
        std::fs::write(dir.path().join("lum/bad.ies"), "IESNA:LM-63-2002\n[TEST] x\n1 2 3\n").unwrap();
        let e = load_scene(&path).unwrap_err().to_string();
        let line = DECLARATIONS.lines().count() + 4; // the header, the declarations, two blank lines
        let at = format!("{}:{line}:1: ", path.display());
        assert!(
            e.starts_with(&at) && e.contains(want) && e.contains(also),
            "got:  {e}\nwant: {at}… {want} … {also}"
        );
    }
}

#[test]
fn ies_point_lights_round_trip_by_their_file() {
    let (_dir, path) = ies_scene(
        "PhysicalPointLight { location 1 2 3 iesUrl \"lum/ww.ies\" direction 0.3 -1 0.1 horizontal 0 0 1 \
         intensity 0.5 1 2 power 7 8 9 }",
    );
    let a = load_scene(&path).unwrap().description;
    // Written elsewhere: the URL is the file's absolute path.
    let out = tempfile::tempdir().unwrap();
    let written = out.path().join("copy.wrl");
    vrml::write_vrml_file(&a, &written).unwrap();
    let b = load_scene(&written).unwrap().description;
    let (la, lb) = (&a.point_lights[0], &b.point_lights[0]);
    assert_eq!((&la.profile, &la.ies_file, la.position), (&lb.profile, &lb.ies_file, lb.position));
    assert_eq!((la.intensity, la.power), (lb.intensity, lb.power));
    let (fa, fb) = (la.orientation.unwrap(), lb.orientation.unwrap());
    assert!((fa.n - fb.n).length() < 1e-6 && (fa.s - fb.s).length() < 1e-6, "{fa:?} vs {fb:?}");
    // A table whose file is not known cannot be written by reference.
    let mut unknown = a.clone();
    unknown.point_lights[0].ies_file = None;
    let e = vrml::write_vrml(&unknown, &mut Vec::new()).unwrap_err().to_string();
    assert!(e.contains("IES profile but not the file it came from"), "{e}");
}

#[test]
fn mitsuba_ies_emitters_convert_to_vrml_by_their_file() {
    let (dir, _) = ies_scene("");
    let xml = dir.path().join("scene.xml");
    std::fs::write(
        &xml,
        r#"<scene version="3.0.0">
  <emitter type="ies" id="lamp">
    <string name="filename" value="lum/ww.ies"/>
    <transform name="to_world"><lookat origin="1, 2, 0" target="1, 0, 0" up="0, 0, 1"/></transform>
    <float name="lumens" value="683"/>
  </emitter>
  <shape type="rectangle"><bsdf type="diffuse"/></shape>
</scene>"#,
    )
    .unwrap();
    let a = load_scene(&xml).unwrap().description;
    let written = dir.path().join("from-xml.wrl");
    vrml::write_vrml_file(&a, &written).unwrap();
    let b = load_scene(&written).unwrap().description;
    let (la, lb) = (&a.point_lights[0], &b.point_lights[0]);
    assert_eq!(la.ies_file, Some(dir.path().join("lum/ww.ies").canonicalize().unwrap()));
    assert_eq!((&la.profile, &la.ies_file, la.position), (&lb.profile, &lb.ies_file, lb.position));
    assert_eq!((la.intensity, la.power), (lb.intensity, lb.power));
    let (fa, fb) = (la.orientation.unwrap(), lb.orientation.unwrap());
    assert!((fa.n - fb.n).length() < 1e-6 && (fa.s - fb.s).length() < 1e-6, "{fa:?} vs {fb:?}");
}

#[test]
fn a_viewpoint_is_chosen_by_description_or_def_name() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("views.wrl");
    std::fs::write(
        &path,
        "#VRML V2.0 utf8\nViewpoint { position 0 0 5 description \"Front\" }\nDEF SIDE Viewpoint { position 5 0 0 orientation 0 1 0 1.5708 }\n\
         Shape { geometry IndexedFaceSet { coord Coordinate { point [0 0 0, 1 0 0, 0 1 0] } coordIndex [0 1 2 -1] } }",
    )
    .unwrap();
    let eye =
        |camera: Option<&str>| vrml::load_with_camera(&path, camera).unwrap().description.camera.unwrap().eye;
    assert_eq!(eye(None), Vec3::new(0.0, 0.0, 5.0));
    assert_eq!(eye(Some("Front")), Vec3::new(0.0, 0.0, 5.0));
    assert_eq!(eye(Some("SIDE")), Vec3::new(5.0, 0.0, 0.0));
    let e = vrml::load_with_camera(&path, Some("Top")).unwrap_err().to_string();
    assert!(e.contains("--camera \"Top\"") && e.contains("\"Front\", \"SIDE\""), "{e}");
}
