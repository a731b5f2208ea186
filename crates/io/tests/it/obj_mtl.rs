//! The OBJ/MTL scene loader through the public API: the Cornell box as OBJ/MTL builds the same
//! scene as the Mitsuba XML, the MTL → material mapping, warnings for missing things, errors that
//! name file and line, no panic on mangled input, a grid loaded exactly, and (ignored: a
//! measurement) the loading speed of a 1M-triangle file against a raw read.

use opticks_testkit::files as common;

use common::*;
use opticks_core::bsdf::Bsdf;
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::{AreaEmission, Scene};
use opticks_io::load_scene;
use std::path::{Path, PathBuf};

#[test]
fn cornell_obj_builds_the_same_scene_as_the_mitsuba_xml() {
    let obj = load_scene(&testdata("obj/cornell.obj")).unwrap();
    assert!(obj.warnings.is_empty(), "{:?}", obj.warnings);
    let d = &obj.description;
    let names: Vec<&str> = d.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["white", "red", "green", "light"]);
    let tris: Vec<usize> = d.meshes.iter().map(|m| m.triangles.len()).collect();
    assert_eq!(tris, [30, 2, 2, 2]);
    // Each mesh keeps only the vertices it uses.
    assert_eq!(d.meshes[3].positions.len(), 4);
    assert_eq!(d.meshes[3].emission.as_ref().map(|e| e.radiance), Some(Rgb::new(18.387, 13.9873, 6.75357)));
    assert!(d.meshes[..3].iter().all(|m| m.emission.is_none()));
    assert!(d.materials.iter().all(|m| m.two_sided));
    assert!(d.camera.is_none() && d.point_lights.is_empty());

    let xml = load_scene(&testdata("scenes/cornell/scene.xml")).unwrap();
    let (a, b) = (Scene::build(d).unwrap(), Scene::build(&xml.description).unwrap());
    assert_eq!((a.triangles.len(), a.dropped_triangles), (36, 0));
    assert_same_scene(&a, &b);
}

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

#[test]
fn mtl_maps_to_phong_lambert_and_area_lights() {
    let obj = format!(
        "mtllib m.mtl\n{QUAD}usemtl shiny\nf 1 2 3\nusemtl matte\nf 1 3 4\nusemtl hot\nf 1 2 4\nusemtl tex\nf 2 3 4\n"
    );
    let mtl = b"newmtl shiny\nKd 0.5 0.4 0.3\nKs 0.2 0.2 0.2\nNs 50\n\
                newmtl matte\nKd 0.25\nKs 0 0 0\n\
                newmtl hot\nKd 0.8 0.8 0.8\nKs 0.4 0.1 0.1\nNs 10\nKe 5 4 3\n\
                newmtl tex\nKd 0.5 0.5 0.5\nmap_Kd albedo.png\nKe 1 1 1\nmap_Ke glow.png\nd 0.5\nPr 0.3\n";
    let s = load_ok(&[("a.obj", obj.as_bytes()), ("m.mtl", mtl)]);
    let d = &s.description;
    let names: Vec<&str> = d.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["a[shiny]", "a[matte]", "a[hot]", "a[tex]"]);
    let mat = |i: usize| &d.materials[d.meshes[i].material];
    match &mat(0).bsdf {
        Bsdf::ModifiedPhong(p) => {
            assert_eq!((p.kd, p.ks, p.exponent), (Rgb::new(0.5, 0.4, 0.3), Rgb::splat(0.2), 50.0))
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(mat(1).bsdf, Bsdf::Lambert(opticks_core::bsdf::Lambert::new(Rgb::splat(0.25)).unwrap()));
    // kd + ks = 1.2 in red: both scaled by 1/1.2, with a warning naming the Ks line.
    match &mat(2).bsdf {
        Bsdf::ModifiedPhong(p) => {
            assert!((p.kd + p.ks).max_element() <= 1.0);
            assert!(((p.kd.x + p.ks.x) - 1.0).abs() < 1e-5, "{p:?}");
            assert!((p.kd.x / p.ks.x - 2.0).abs() < 1e-5, "ratio kept: {p:?}");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(d.meshes[2].emission.as_ref().map(|e| e.radiance), Some(Rgb::new(5.0, 4.0, 3.0)));
    // map_Ke: no emission; map_Kd: constant Kd.
    assert_eq!(d.meshes[3].emission, None);
    assert!(mat(3).two_sided && mat(0).two_sided);
    let w = s.warnings.join("\n");
    for expected in [
        "TMP/m.mtl:10: newmtl hot: Kd + Ks = (1.2, 0.90000004, 0.90000004) exceeds 1",
        "TMP/m.mtl:15: map_Kd: textures are not supported; the constant Kd is used",
        "TMP/m.mtl:17: map_Ke: textures are not supported",
        "TMP/m.mtl:18: d 0.5: transparency is not supported",
        "TMP/m.mtl:19: Pr: unsupported statement",
    ] {
        assert!(w.contains(expected), "missing {expected:?} in\n{w}");
    }
}

/// Issue 10, item 16: `Kd 3.3e38 0.5 0.5` hung the loader forever (the energy-conservation
/// scale was an f32 subnormal that the step-down loop could not move). Huge values now scale
/// down to a sum of at most 1, exactly like small excesses, and two huge ones do not overflow.
#[test]
fn huge_kd_and_ks_scale_down_instead_of_hanging() {
    for (mtl, expect) in [
        ("Kd 3.3e38 0.5 0.5\n", Rgb::new(1.0, 0.5 / 3.3e38, 0.5 / 3.3e38)),
        ("Kd 3e38 3e38 3e38\nKs 3e38 3e38 3e38\nNs 10\n", Rgb::splat(0.5)),
    ] {
        let obj = format!("mtllib m.mtl\n{QUAD}usemtl m\nf 1 2 3\n");
        let mtl = format!("newmtl m\n{mtl}");
        let s = load_ok(&[("x.obj", obj.as_bytes()), ("m.mtl", mtl.as_bytes())]);
        let kd = match &s.description.materials[0].bsdf {
            Bsdf::Lambert(l) => l.reflectance,
            Bsdf::ModifiedPhong(p) => p.kd,
            other => panic!("{other:?}"),
        };
        assert!((kd - expect).abs().max_element() < 1e-6, "{mtl}: Kd {kd}");
        assert!(s.warnings.iter().any(|w| w.contains("exceeds 1")), "{:?}", s.warnings);
    }
}

#[test]
fn missing_mtl_and_unknown_material_are_warnings() {
    let obj = format!("mtllib nowhere.mtl\n{QUAD}usemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\n");
    let s = load_ok(&[("x.obj", obj.as_bytes())]);
    let d = &s.description;
    assert_eq!(d.materials.len(), 1, "one shared default material");
    assert_eq!(d.materials[0].name, "default");
    assert!(d.materials[0].two_sided);
    assert_eq!(d.meshes.len(), 2);
    let w = s.warnings.join("\n");
    assert!(w.contains("TMP/x.obj:1: mtllib nowhere.mtl: cannot read TMP/nowhere.mtl"), "{w}");
    assert!(w.contains("TMP/x.obj:6: usemtl a: no material of that name"), "{w}");
    assert!(w.contains("TMP/x.obj:8: usemtl b: no material of that name"), "{w}");
    assert!(w.contains("no material has an emission"), "{w}");

    // A library that exists but lacks the name.
    let obj = format!("mtllib m.mtl\n{QUAD}usemtl missing\nf 1 2 3\n");
    let s = load_ok(&[("y.obj", obj.as_bytes()), ("m.mtl", b"newmtl other\nKd 1 1 1\n")]);
    assert!(s.warnings.iter().any(|w| w.starts_with("TMP/y.obj:6: usemtl missing:")), "{:?}", s.warnings);
}

#[test]
fn groups_and_materials_make_separate_meshes() {
    // Faces of (group, material) pairs that recur are merged; `o` and `g` both start groups.
    let obj = format!(
        "mtllib m.mtl\n{QUAD}f 1 2 3\no box\nusemtl r\nf 1 2 3\ng lid\nf 1 3 4\no box\nf 2 3 4\nusemtl s\nf 1 2 4\n"
    );
    let mtl = b"newmtl r\nKd 1 0 0\nnewmtl s\nKd 0 0 1\n";
    let s = load_ok(&[("scene.obj", obj.as_bytes()), ("m.mtl", mtl)]);
    let d = &s.description;
    let summary: Vec<(&str, usize, &str)> = d
        .meshes
        .iter()
        .map(|m| (m.name.as_str(), m.triangles.len(), d.materials[m.material].name.as_str()))
        .collect();
    assert_eq!(summary, [("scene", 1, "default"), ("box[r]", 2, "r"), ("lid", 1, "r"), ("box[s]", 1, "s")]);
    // Negative (relative) indices and `v/vt/vn` corners.
    let s = load_ok(&[("n.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf -3/1/1 -2/1/1 -1/1/1\n")]);
    assert_eq!(s.description.meshes[0].triangles, [[0, 1, 2]]);
    assert_eq!(s.description.meshes[0].normals, [Vec3::Z; 3]);
}

#[test]
fn vertex_normals_go_to_each_mesh_that_uses_them() {
    // Two groups share positions with different normals; each mesh gets its own vertices.
    let obj =
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0.5 0 1\ng a\nf 1//1 2//2 3//1\ng b\nf 1//2 2//2 3//2\n";
    let s = load_ok(&[("n.obj", obj)]);
    let d = &s.description;
    assert_eq!(d.meshes.len(), 2);
    assert_eq!(d.meshes[0].normals, [Vec3::Z, Vec3::new(0.5, 0.0, 1.0), Vec3::Z]);
    assert_eq!(d.meshes[1].normals, [Vec3::new(0.5, 0.0, 1.0); 3]);
    assert_eq!(d.meshes[1].positions, [Vec3::ZERO, Vec3::X, Vec3::Y]);
}

#[test]
fn errors_name_the_file_and_line() {
    // (files to write, the error expected)
    type Case<'a> = (&'a [(&'a str, &'a [u8])], &'a str);
    let cases: &[Case] = &[
        (&[("a.obj", b"v 0 0 0\nv 1 x 0\n")], "TMP/a.obj:2: vertex coordinate \"x\" is not a number"),
        (
            &[("a.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")],
            "TMP/a.obj:4: face refers to vertex 7, but the file defines only 3",
        ),
        (&[("a.obj", b"v 0 0 0\nf 1 2\n")], "TMP/a.obj:2: face has 2 corners"),
        (&[("a.obj", b"v 0 0 0\nf 0 1 1\n")], "TMP/a.obj:2: face refers to vertex 0"),
        (&[("a.obj", b"v 0 0 inf\n")], "TMP/a.obj:1: vertex coordinate \"inf\" is not finite"),
        (
            &[("a.obj", b"mtllib m.mtl\nv 0 0 0\n"), ("m.mtl", b"# c\nnewmtl x\nKd 1 2\n")],
            "TMP/m.mtl:3: Kd takes 1 or 3 numbers, got 2",
        ),
        (
            &[("a.obj", b"mtllib m.mtl\n"), ("m.mtl", b"newmtl x\nNs lots\n")],
            "TMP/m.mtl:2: Ns value \"lots\" is not a number",
        ),
        (
            &[("a.obj", b"mtllib m.mtl\n"), ("m.mtl", b"newmtl\n")],
            "TMP/m.mtl:1: newmtl without a material name",
        ),
        (
            &[
                ("a.obj", b"mtllib m.mtl\nv 0 0 0\nusemtl x\nf 1 1 1\n"),
                ("m.mtl", b"newmtl x\nKd 0.5 -0.1 0\n"),
            ],
            "TMP/m.mtl:2: newmtl x: invalid material: Kd must not be negative",
        ),
        (
            &[
                ("a.obj", b"mtllib m.mtl\nv 0 0 0\nusemtl x\nf 1 1 1\n"),
                ("m.mtl", b"newmtl x\nKd nan 0.5 0.5\n"),
            ],
            "TMP/m.mtl:2: Kd value \"nan\" is not finite",
        ),
        (
            &[
                ("a.obj", b"mtllib m.mtl\nv 0 0 0\nusemtl x\nf 1 1 1\n"),
                ("m.mtl", b"newmtl x\nKs 0.5\nNs 1e9\n"),
            ],
            "TMP/m.mtl:3: newmtl x: invalid material: Ns = 1000000000 exceeds the supported maximum",
        ),
        (
            &[
                ("a.obj", b"mtllib m.mtl\nv 0 0 0\nusemtl x\nf 1 1 1\n"),
                ("m.mtl", b"newmtl x\nKd 0.5\nKs -0.1 0 0\n"),
            ],
            "TMP/m.mtl:3: newmtl x: invalid material: Ks must not be negative",
        ),
        (
            &[
                ("a.obj", b"mtllib m.mtl\nv 0 0 0\nusemtl x\nf 1 1 1\n"),
                ("m.mtl", b"newmtl x\nKd 0.5\nKe -1 0 0\n"),
            ],
            "TMP/m.mtl:3: newmtl x: Ke: emission [-1.0, 0.0, 0.0] must be finite and non-negative",
        ),
    ];
    for (files, expected) in cases {
        let e = error_of(files);
        assert!(e.starts_with(expected), "{e}\n  should start with\n{expected}");
    }
    let e = load_scene(Path::new("no/such/file.obj")).unwrap_err().to_string();
    assert!(e.starts_with("no/such/file.obj: cannot read the scene file"), "{e}");
}

#[test]
fn mangled_inputs_never_panic() {
    let obj = std::fs::read(testdata("obj/cornell.obj")).unwrap();
    let mtl = std::fs::read(testdata("obj/cornell.mtl")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut rng = Lcg(7);
    let alphabet = b" \n\t/-#0123456789.eE+fvgousemtlKdsNnap_\xff\x00";
    let (mut ok, mut err) = (0, 0);
    for round in 0..300 {
        let (mut o, mut m) = (obj.clone(), mtl.clone());
        for _ in 0..1 + rng.next() % 8 {
            let target = if rng.next().is_multiple_of(2) { &mut o } else { &mut m };
            let at = (rng.next() as usize) % target.len();
            match rng.next() % 3 {
                0 => target[at] = alphabet[(rng.next() as usize) % alphabet.len()],
                1 => {
                    target.remove(at);
                }
                _ => target.truncate(at),
            }
            if target.is_empty() {
                target.push(b'\n');
            }
        }
        std::fs::write(dir.path().join("cornell.obj"), &o).unwrap();
        std::fs::write(dir.path().join("cornell.mtl"), &m).unwrap();
        match load_scene(&dir.path().join("cornell.obj")) {
            Ok(s) => {
                ok += 1;
                // Whatever loads must also be acceptable to (or cleanly refused by) the core.
                let _ = Scene::build(&s.description);
            }
            Err(e) => {
                err += 1;
                assert!(e.to_string().contains("cornell."), "round {round}: {e}");
            }
        }
    }
    assert!(ok > 0 && err > 0, "ok {ok}, err {err}");
}

/// An OBJ grid of `nx` × `ny` vertices, its rows of faces alternating between materials `a`
/// and `b` (the MTL makes `b` emit).
fn grid_obj(nx: usize, ny: usize) -> String {
    let mut s = String::with_capacity(60 * nx * ny);
    use std::fmt::Write;
    s.push_str("mtllib grid.mtl\n");
    for j in 0..ny {
        for i in 0..nx {
            writeln!(s, "v {:.6} {:.6} {:.6}", i as f32 * 0.001, j as f32 * 0.002, (i * j) as f32 * 1e-6)
                .unwrap();
        }
    }
    for j in 0..ny - 1 {
        s.push_str(if j % 2 == 0 { "usemtl a\n" } else { "usemtl b\n" });
        for i in 0..nx - 1 {
            let a = j * nx + i + 1;
            writeln!(s, "f {}/1/1 {}/1/1 {}/1/1\nf {} {} {}", a, a + 1, a + 1 + nx, a, a + 1 + nx, a + nx)
                .unwrap();
        }
    }
    s
}

fn write_grid(dir: &Path, nx: usize, ny: usize) -> (PathBuf, usize) {
    let s = grid_obj(nx, ny);
    let path = dir.join("grid.obj");
    std::fs::write(&path, &s).unwrap();
    std::fs::write(dir.join("grid.mtl"), "newmtl a\nKd 0.5\nnewmtl b\nKd 0.2\nKe 1 1 1\n").unwrap();
    (path, s.len())
}

/// The grid the loading-speed bench reads, small: every triangle, its corners and its group.
#[test]
fn a_grid_loads_exactly() {
    let (nx, ny) = (101usize, 51usize);
    let dir = tempfile::tempdir().unwrap();
    let (path, _) = write_grid(dir.path(), nx, ny);
    let d = load_scene(&path).unwrap().description;
    assert_eq!(d.meshes.len(), 2);
    let total: usize = d.meshes.iter().map(|m| m.triangles.len()).sum();
    assert_eq!(total, 2 * (nx - 1) * (ny - 1));
    // Rows alternate: a gets rows 0, 2, …, b rows 1, 3, …; b emits.
    let (a, b) = (&d.meshes[0], &d.meshes[1]);
    assert_eq!(a.triangles.len(), 2 * (nx - 1) * (ny - 1).div_ceil(2));
    assert_eq!((&a.emission, &b.emission), (&None, &Some(AreaEmission::lambertian(Rgb::ONE))));
    // Every triangle's corners are grid points one step apart: seen from +z, each triangle
    // covers ½·dx·dy, counter-clockwise.
    for m in [a, b] {
        for t in &m.triangles {
            let [p, q, r] = t.map(|i| m.positions[i as usize]);
            let area = 0.5 * (q - p).cross(r - p).z;
            assert!((area / (0.5 * 0.001 * 0.002) - 1.0).abs() < 1e-3, "{area}");
        }
    }
    let first = a.triangles[0].map(|i| a.positions[i as usize]);
    assert_eq!(first[0], Vec3::ZERO);
    assert!((first[2] - Vec3::new(0.001, 0.002, 1e-6)).length() < 1e-7, "{first:?}");
}

/// Loading speed of a 1 M-triangle OBJ against a raw read of the same file, measured in the
/// same run (a figure, not a check: run with `--ignored --nocapture`).
#[test]
#[ignore = "speed measurement; run with --ignored --nocapture"]
fn bench_a_million_triangles() {
    let dir = tempfile::tempdir().unwrap();
    let (path, bytes) = write_grid(dir.path(), 1001, 501);
    let mb = bytes as f64 / 1e6;
    let t = std::time::Instant::now();
    let raw = std::fs::read(&path).unwrap();
    let t_raw = t.elapsed().as_secs_f64();
    drop(raw);
    let t = std::time::Instant::now();
    let scene = load_scene(&path).unwrap();
    let dt = t.elapsed().as_secs_f64();
    assert_eq!(scene.description.meshes.iter().map(|m| m.triangles.len()).sum::<usize>(), 1_000_000);
    println!(
        "1M-triangle OBJ/MTL: {mb:.1} MB loaded at {:.0} MB/s; raw read {:.0} MB/s",
        mb / dt,
        mb / t_raw
    );
}

/// Every OBJ file of the repository (test data and showcase scenes) read by `tobj`, an
/// independent reader, gives exactly the triangles ours gives, as an OBJ/MTL scene and as the one
/// mesh of a Mitsuba `obj` shape: the same corners, bit for bit, in the same winding.
#[test]
fn every_obj_in_the_repository_matches_tobj() {
    // A triangle as its corners' bits, rotated to start at the smallest (winding kept).
    fn key(c: [Vec3; 3]) -> [[u32; 3]; 3] {
        let b = c.map(|v| v.to_array().map(f32::to_bits));
        let i = (0..3).min_by_key(|&i| b[i]).unwrap();
        [b[i], b[(i + 1) % 3], b[(i + 2) % 3]]
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = Vec::new();
    opticks_testkit::files::files_with_extension(&root.join("testdata"), "obj", &mut files);
    opticks_testkit::files::files_with_extension(&root.join("scenes"), "obj", &mut files);
    assert!(files.len() >= 10, "{files:?}");
    for file in files {
        let ours = load_scene(&file).unwrap().description;
        let mut a: Vec<_> = ours
            .meshes
            .iter()
            .flat_map(|m| m.triangles.iter().map(|t| key(t.map(|i| m.positions[i as usize]))))
            .collect();
        let options = tobj::LoadOptions { triangulate: true, ..Default::default() };
        let (models, _) = tobj::load_obj(&file, &options).unwrap();
        let mut b: Vec<_> = models
            .iter()
            .flat_map(|m| {
                let p = |i: u32| Vec3::from_slice(&m.mesh.positions[3 * i as usize..3 * i as usize + 3]);
                m.mesh.indices.chunks(3).map(move |t| key([p(t[0]), p(t[1]), p(t[2])]))
            })
            .collect();
        let mesh = opticks_io::scene_formats::obj::read_obj(&file, None).unwrap();
        let mut c: Vec<_> =
            mesh.triangles.iter().map(|t| key(t.map(|i| mesh.positions[i as usize]))).collect();
        a.sort_unstable();
        b.sort_unstable();
        c.sort_unstable();
        assert!(!a.is_empty(), "{}", file.display());
        assert_eq!(a.len(), b.len(), "{}: triangle count", file.display());
        assert!(a == b, "{}: triangles differ from tobj's", file.display());
        assert!(c == b, "{}: the mesh of a Mitsuba obj shape differs from tobj's", file.display());
    }
}
