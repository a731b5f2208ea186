//! The Radiance scene loader through the public API: errors with file:line:column, each
//! surface's geometry, `mesh` primitives from their `.obj`, each material's mapping, `!xform`
//! includes with their transforms, include cycles, commands and unknown primitives refused,
//! views, and the example room.

use opticks_core::bsdf::Bsdf;
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::{CameraKind, MeshDesc, Photometry, Scene};
use opticks_io::scene_formats::{LoadOptions, load_scene, load_scene_with};
use opticks_testkit::files::{error_of, load_ok, testdata};

fn area(m: &MeshDesc) -> f64 {
    m.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            0.5 * (b - a).cross(c - a).length() as f64
        })
        .sum()
}

/// Σ over triangles of area × the unit face normal: zero for a closed surface, A·n for a
/// flat one facing n.
fn vector_area(m: &MeshDesc) -> Vec3 {
    m.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            0.5 * (b - a).cross(c - a)
        })
        .sum()
}

const MAT: &str = "void plastic grey\n0\n0\n5 0.5 0.5 0.5 0 0\n";

fn one(text: &str) -> opticks_io::scene_formats::LoadedScene {
    load_ok(&[("a.rad", format!("{MAT}{text}").as_bytes())])
}

#[test]
fn each_surface_has_its_geometry() {
    let s = one("grey polygon quad 0 0 12 0 0 0 2 0 0 2 1 0 0 1 0\n\
         grey polygon concave 0 0 18 0 0 1 2 0 1 2 1 1 1 1 1 1 2 1 0 2 1\n\
         grey sphere ball 0 0 4 1 2 3 0.5\n\
         grey bubble inside 0 0 4 0 0 0 2\n\
         grey cone c 0 0 8 0 0 0 0 0 2 1 0.5\n\
         grey cup u 0 0 8 0 0 0 0 0 2 1 0\n\
         grey cylinder cy 0 0 7 0 0 0 0 3 0 0.25\n\
         grey tube tu 0 0 7 0 0 0 0 3 0 0.25\n\
         grey ring r 0 0 8 0 0 0 0 0 -1 0.5 1.5\n\
         void light l 0 0 3 1 1 1\n\
         l polygon lamp 0 0 9 0 0 5 0 1 5 1 0 5\n");
    let d = &s.description;
    let m = |name: &str| d.meshes.iter().find(|m| m.name == name).unwrap_or_else(|| panic!("{name}"));
    let pi = std::f64::consts::PI;
    // Polygons: as many vertices as written, triangulated (the concave L by ear clipping).
    assert_eq!((m("quad").positions.len(), m("quad").triangles.len()), (4, 2));
    assert!(
        (vector_area(m("quad")) - Vec3::new(0.0, 0.0, 2.0)).length() < 1e-6,
        "front by the right-hand rule"
    );
    assert_eq!((m("concave").positions.len(), m("concave").triangles.len()), (6, 4));
    assert!((area(m("concave")) - 3.0).abs() < 1e-6);
    // Curved surfaces: finely tessellated, the analytic area, smooth normals.
    assert!((area(m("ball")) / (4.0 * pi * 0.25) - 1.0).abs() < 1e-4, "{}", area(m("ball")));
    assert!(m("ball").triangles.len() > 10_000 && m("ball").normals.len() == m("ball").positions.len());
    let centre = Vec3::new(1.0, 2.0, 3.0);
    assert!(m("ball").positions.iter().all(|p| ((*p - centre).length() - 0.5).abs() < 1e-3));
    let slant = (4.0f64 + 0.25).sqrt();
    assert!((area(m("c")) / (pi * 1.5 * slant) - 1.0).abs() < 3e-4, "{}", area(m("c")));
    assert!((area(m("u")) / (pi * (4.0f64 + 1.0).sqrt()) - 1.0).abs() < 3e-4);
    assert!((area(m("cy")) / (2.0 * pi * 0.25 * 3.0) - 1.0).abs() < 1e-5);
    assert!((area(m("r")) / (pi * (1.5 * 1.5 - 0.25)) - 1.0).abs() < 1e-5);
    assert!(
        (vector_area(m("r")).normalize() - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-5,
        "the ring faces its normal"
    );
    // Outward for sphere, cone, cylinder; inward for bubble, cup, tube (normals and fronts).
    let outward = |mesh: &MeshDesc, axis_point: &dyn Fn(Vec3) -> Vec3| {
        mesh.triangles.iter().all(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let g = (b - a).cross(c - a);
            let out = (a + b + c) / 3.0 - axis_point((a + b + c) / 3.0);
            g.dot(out) > 0.0 && t.iter().all(|&i| mesh.normals[i as usize].dot(g) > 0.0)
        })
    };
    let z_axis = |p: Vec3| Vec3::new(0.0, 0.0, p.z);
    assert!(outward(m("ball"), &|_| centre));
    assert!(outward(m("c"), &z_axis));
    assert!(outward(m("cy"), &|p| Vec3::new(0.0, p.y, 0.0)));
    let inverted =
        |mesh: &MeshDesc, axis_point: &dyn Fn(Vec3) -> Vec3| outward(mesh, &|p| 2.0 * p - axis_point(p));
    assert!(inverted(m("inside"), &|_| Vec3::ZERO));
    assert!(inverted(m("u"), &z_axis));
    assert!(inverted(m("tu"), &|p| Vec3::new(0.0, p.y, 0.0)));
    // Every mesh builds.
    let scene = Scene::build(d).unwrap();
    assert_eq!(scene.dropped_triangles, 0);
}

/// One material of every kind Radiance has, each defined on `void`.
const MATERIALS: &str = "void plastic matte 0 0 5 0.5 0.4 0.3 0 0.1
void plastic shiny 0 0 5 0.5 0.4 0.3 0.05 0.1
void plastic gloss 0 0 5 0.5 0.4 0.3 0.05 0
void metal steel 0 0 5 0.8 0.6 0.4 0.9 0.2
void trans tr 0 0 7 0.6 0.6 0.6 0 0 0.5 1
void glass gl 0 0 3 0.9 0.8 0.7
void glass gl14 0 0 4 0.9 0.9 0.9 1.4
void dielectric water 0 0 5 0.5 0.5 0.5 1.33 0
void mirror mi 0 0 3 0.9 0.9 0.9
void light lamp 0 0 3 10 9 8
void glow gw 0 0 4 1 2 3 0
void alias again matte
void illum win 0 0 3 5 5 5
void illum win2 1 gl 0 3 5 5 5
";

#[test]
fn each_material_maps_to_the_closest_core_material() {
    let s = load_ok(&[("a.rad", MATERIALS.as_bytes())]);
    let d = &s.description;
    assert!(
        d.meshes.is_empty() && d.materials.is_empty(),
        "materials enter the scene when a surface uses them"
    );
    let mut text = String::new();
    for (i, name) in [
        "matte", "shiny", "gloss", "steel", "tr", "gl", "gl14", "water", "mi", "lamp", "gw", "again", "win",
        "win2",
    ]
    .iter()
    .enumerate()
    {
        text += &format!("{name} polygon p{i} 0 0 9 0 0 0 1 0 0 0 1 0\n");
    }
    let all = format!("{MATERIALS}{text}");
    let s = load_ok(&[("c.rad", all.as_bytes())]);
    let w = s.warnings.join("\n");
    assert!(w.contains("c.rad:5:1: trans tr: transmission is not modelled yet"), "{w}");
    assert!(w.contains("1 surface(s) modified by void"), "{w}");
    let d = &s.description;
    // The illum without an alternate is left out; the one with `gl` is glass.
    assert_eq!(d.meshes.len(), 13);
    let bsdf = |name: &str| {
        let m = d.meshes.iter().find(|m| m.name == name).unwrap();
        (&d.materials[m.material], m.emission.as_ref().map(|e| e.radiance))
    };
    let rgb = Rgb::new(0.5, 0.4, 0.3);
    match bsdf("p0") {
        (m, None) if m.two_sided => {
            assert_eq!(m.bsdf, Bsdf::Lambert(opticks_core::bsdf::Lambert::new(rgb).unwrap()))
        }
        other => panic!("{other:?}"),
    }
    match &bsdf("p1").0.bsdf {
        Bsdf::ModifiedPhong(p) => {
            assert!((p.kd - rgb * 0.95).length() < 1e-6 && p.ks == Rgb::splat(0.05));
            assert!((p.exponent - (2.0 / 0.01 - 2.0)).abs() < 1e-3, "{}", p.exponent);
        }
        other => panic!("{other:?}"),
    }
    match &bsdf("p2").0.bsdf {
        Bsdf::Blend(b) => assert_eq!(b.weight, 0.05),
        other => panic!("{other:?}"),
    }
    // A white plastic with a perfect highlight stays within the core's bounds (its base is not
    // recomputed from the (1 − s)-scaled colour, which rounds above 1).
    let w = one(
        "void plastic white 0 0 5 1 1 1 0.07 0\ngrey polygon q 0 0 9 0 0 0 1 0 0 0 1 0\nwhite polygon p 0 0 9 0 0 0 1 0 0 0 1 0\n",
    );
    assert!(
        matches!(&w.description.materials[1].bsdf, Bsdf::Blend(b) if b.max_albedo().max_element() <= 1.0)
    );
    for spec in 1..100 {
        let s = format!("void plastic w 0 0 5 1 1 1 0.{spec:02} 0.1\nw polygon p 0 0 9 0 0 0 1 0 0 0 1 0\n");
        let w = load_ok(&[("a.rad", s.as_bytes())]);
        assert!(matches!(&w.description.materials[0].bsdf, Bsdf::ModifiedPhong(_)), "{spec}");
    }
    match &bsdf("p3").0.bsdf {
        Bsdf::ModifiedPhong(p) => {
            let metal = Rgb::new(0.8, 0.6, 0.4);
            assert!(
                (p.kd - metal * 0.1).length() < 1e-6 && (p.ks - metal * 0.9).length() < 1e-6,
                "coloured highlight"
            );
        }
        other => panic!("{other:?}"),
    }
    match &bsdf("p4").0.bsdf {
        Bsdf::Lambert(l) => assert!((l.reflectance - Rgb::splat(0.3)).length() < 1e-6),
        other => panic!("{other:?}"),
    }
    match &bsdf("p5").0.bsdf {
        Bsdf::ThinDielectric(t) => {
            assert_eq!((t.eta, t.specular_transmittance), (1.52, Rgb::new(0.9, 0.8, 0.7)));
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(&bsdf("p6").0.bsdf, Bsdf::ThinDielectric(t) if t.eta == 1.4));
    match &bsdf("p7").0.bsdf {
        Bsdf::SmoothDielectric(t) => {
            assert_eq!(t.eta, 1.33);
            assert!((t.absorption - Rgb::splat(2f32.ln())).length() < 1e-6, "{}", t.absorption);
        }
        other => panic!("{other:?}"),
    }
    assert!(
        matches!(&bsdf("p8").0.bsdf, Bsdf::SmoothConductor(c) if c.specular_reflectance == Rgb::splat(0.9) && c.ior.is_none())
    );
    let (lamp, emission) = bsdf("p9");
    assert_eq!(emission, Some(Rgb::new(10.0, 9.0, 8.0)));
    assert!(!lamp.two_sided && lamp.bsdf.max_albedo() == Rgb::ZERO);
    assert_eq!(bsdf("p10").1, Some(Rgb::new(1.0, 2.0, 3.0)));
    // An alias is the material it names (one material, shared).
    assert_eq!(d.meshes.iter().find(|m| m.name == "p11").unwrap().material, d.meshes[0].material);
    assert!(matches!(&bsdf("p13").0.bsdf, Bsdf::ThinDielectric(_)));
    assert!(d.meshes.iter().all(|m| m.name != "p12"));
}

#[test]
fn impossible_and_unsupported_materials_name_the_line() {
    let e = error_of(&[("a.rad", b"\n void plastic hot 0 0 5 1.5 0 0 0 0\n")]);
    assert!(e.starts_with("TMP/a.rad:2:2: plastic hot: invalid material:"), "{e}");
    let e = error_of(&[("a.rad", b"void plastic p 0 0 4 1 1 1 0\n")]);
    assert!(
        e.contains(
            "a.rad:1:1: plastic p: plastic takes 0 string, 0 integer and 5 real arguments, not 0, 0 and 4"
        ),
        "{e}"
    );
    let e = error_of(&[("a.rad", b"void mirror m 1 other 0 3 1 1 1\n")]);
    assert!(e.contains("mirror m: mirror takes 0 string"), "{e}");
    let e = error_of(&[("a.rad", b"void dielectric d 0 0 5 0 0.5 0.5 1.5 0\n")]);
    assert!(e.contains("dielectric d: the transmission per unit length"), "{e}");
    let e = error_of(&[("a.rad", b"pat plastic p 0 0 5 1 1 1 0 0\n")]);
    assert!(e.contains("a.rad:1:1: plastic p: modifier \"pat\""), "{e}");
    let e = error_of(&[("a.rad", b"void light l 0 0 3 -1 1 1\n")]);
    assert!(e.contains("must not be negative"), "{e}");
}

#[test]
fn unknown_and_unsupported_primitives_are_refused_naming_file_line_and_primitive() {
    let e = error_of(&[("a.rad", format!("{MAT}\ngrey teapot t 0 0 0\n").as_bytes())]);
    assert!(e.starts_with("TMP/a.rad:6:1: teapot t: unknown primitive type \"teapot\""), "{e}");
    assert!(e.contains("polygon, sphere, bubble, cone, cup, cylinder, tube, ring"), "{e}");
    for (text, what) in [
        ("void brightfunc skyfunc 2 skybright skybright.cal 0 0\n", "brightfunc is a pattern"),
        ("void texfunc wave 4 dx dy dz wave.cal 0 0\n", "texfunc is a texture"),
        ("grey instance i 1 chair.oct 0 0\n", "instance is a surface"),
        ("grey source sun 0 0 4 0 0 1 0.5\n", "emits nothing: a source takes a light or glow"),
        ("void spotlight s 0 0 7 1 1 1 30 0 0 -1\n", "spotlight is a material"),
    ] {
        let e = error_of(&[("a.rad", format!("{MAT}{text}").as_bytes())]);
        assert!(e.starts_with("TMP/a.rad:5:1: ") && e.contains(what), "{e}");
    }
    let e =
        error_of(&[("a.rad", b"void plastic p 0 0 5 1 1 1 0 0\nnone polygon x 0 0 9 0 0 0 1 0 0 0 1 0\n")]);
    assert!(e.contains("a.rad:2:1: polygon x: undefined modifier \"none\""), "{e}");
    let e = error_of(&[("a.rad", format!("{MAT}grey polygon x 0 0 6 0 0 0 1 0 0\n").as_bytes())]);
    assert!(
        e.contains("a.rad:5:1: polygon x: a polygon takes 3 reals per vertex and at least 3 vertices"),
        "{e}"
    );
    let e = error_of(&[("a.rad", format!("{MAT}grey sphere s 0 0 4 0 0 0 0\n").as_bytes())]);
    assert!(e.contains("sphere s: the radius 0 must be positive"), "{e}");
    let e = error_of(&[("a.rad", format!("{MAT}grey ring r 0 0 8 0 0 0 0 0 1 2 1\n").as_bytes())]);
    assert!(e.contains("ring r: needs a non-zero normal and radii"), "{e}");
    let e = error_of(&[("a.rad", format!("{MAT}grey cone c 0 0 8 0 0 0 0 0 0 1 1\n").as_bytes())]);
    assert!(e.contains("cone c: its two end points are the same"), "{e}");
}

#[test]
fn parse_errors_give_file_line_and_column() {
    let e = error_of(&[("a.rad", b"# comment\nvoid plastic p\n0\n0\n5 0.5 0.5 oops 0 0\n")]);
    assert_eq!(e, "TMP/a.rad:5:11: syntax: expected a real argument of plastic p, found \"oops\"");
    let e = error_of(&[("a.rad", b"void plastic p 0 0 5 0.5 0.5")]);
    assert!(
        e.starts_with("TMP/a.rad:1:29: syntax: the file ends before a real argument of plastic p"),
        "{e}"
    );
    let e = error_of(&[("a.rad", b"void plastic p three")]);
    assert!(
        e.starts_with("TMP/a.rad:1:16: syntax: expected the number of string arguments of plastic p"),
        "{e}"
    );
    // In an included file, the error is located there.
    let e = error_of(&[
        ("a.rad", b"!xform -t 1 0 0 sub/b.rad\n"),
        ("sub/b.rad", b"\n\nvoid glass g 0 0 3 x 1 1\n"),
    ]);
    assert!(e.starts_with("TMP/sub/b.rad:3:20: syntax: expected a real argument of glass g"), "{e}");
}

#[test]
fn commands_are_never_executed() {
    let dir = tempfile::tempdir().unwrap();
    let marker = dir.path().join("ran");
    let scene = dir.path().join("a.rad");
    std::fs::write(&scene, format!("{MAT}!touch {}\n", marker.display())).unwrap();
    let e = load_scene(&scene).unwrap_err().to_string();
    assert!(e.contains("a.rad:5:1: !touch: commands in a scene file are never executed"), "{e}");
    assert!(!marker.exists());
    let e = error_of(&[("a.rad", b"\n  !gensky 13 21 12 +s\n")]);
    assert!(e.starts_with("TMP/a.rad:2:3: !gensky: bad month: \"!gensky 13 21 12 +s\""), "{e}");
    // A malformed !gendaylit names the file, the line and the line itself.
    let e = error_of(&[("a.rad", b"# sky\n!gendaylit 3 21 12 -W 800\n")]);
    assert!(
        e.starts_with("TMP/a.rad:2:1: !gendaylit: -W needs a value: \"!gendaylit 3 21 12 -W 800\""),
        "{e}"
    );
    let e = error_of(&[("a.rad", b"!gendaylit 3 21 12\n")]);
    assert!(e.starts_with("TMP/a.rad:1:1: !gendaylit: the sky's levels are missing"), "{e}");
    let e = error_of(&[("a.rad", b"!xform b.rad | xform -t 1 0 0\n"), ("b.rad", b"")]);
    assert!(e.contains("!xform: shell syntax ('|')"), "{e}");
    let e = error_of(&[("a.rad", b"!xform -a 5 -t 1 0 0 b.rad\n"), ("b.rad", b"")]);
    assert!(e.contains("a.rad:1:1: !xform: unsupported xform option -a"), "{e}");
    let e = error_of(&[("a.rad", b"!xform -t 1 0 0\n")]);
    assert!(e.contains("standard input"), "{e}");
    let e = error_of(&[("a.rad", b"!xform missing.rad\n")]);
    assert!(e.contains("a.rad:1:1: !xform: cannot read TMP/missing.rad"), "{e}");
}

#[test]
fn xform_includes_relative_to_the_including_file_transformed() {
    let s = load_ok(&[
        (
            "a.rad",
            format!("{MAT}!xform -n outer -rz 90 -t 10 0 0 parts/b.rad\n!xform -mx -s 2 parts/b.rad\n")
                .as_bytes(),
        ),
        // b.rad includes c.rad beside it, moved up by 1.
        ("parts/b.rad", b"grey polygon tri 0 0 9 1 0 0 2 0 0 1 1 0\n!xform -n inner -t 0 0 1 c.rad\n"),
        ("parts/c.rad", b"grey sphere ball 0 0 4 1 0 0 0.5\ngrey ring r 0 0 8 0 0 0 1 0 0 0 1\n"),
    ]);
    let d = &s.description;
    let names: Vec<&str> = d.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["outer.tri", "outer.inner.ball", "outer.inner.r", "tri", "inner.ball", "inner.r"]);
    let near = |a: Vec3, b: Vec3| (a - b).length() < 1e-5;
    // -rz 90 then -t 10 0 0: (1, 0, 0) → (0, 1, 0) → (10, 1, 0).
    assert!(near(d.meshes[0].positions[0], Vec3::new(10.0, 1.0, 0.0)), "{:?}", d.meshes[0].positions);
    let centre = |m: &MeshDesc| {
        let lo = m.positions.iter().fold(Vec3::splat(f32::MAX), |a, p| a.min(*p));
        let hi = m.positions.iter().fold(Vec3::splat(f32::MIN), |a, p| a.max(*p));
        (lo + hi) / 2.0
    };
    assert!(near(centre(&d.meshes[1]), Vec3::new(10.0, 1.0, 1.0)), "{}", centre(&d.meshes[1]));
    assert!((area(&d.meshes[1]) / std::f64::consts::PI - 1.0).abs() < 1e-4);
    // The ring's normal turns with the transform: +x → +y.
    assert!(near(vector_area(&d.meshes[2]).normalize(), Vec3::Y));
    // -mx -s 2: mirrored and doubled; the mirrored polygon is reversed, so it still faces +z
    // (the mirrored normal), and the sphere's radius doubles.
    let tri = &d.meshes[3];
    assert!(
        near(tri.positions[2], Vec3::new(-2.0, 0.0, 0.0))
            || near(tri.positions[0], Vec3::new(-2.0, 2.0, 0.0)),
        "{:?}",
        tri.positions
    );
    assert!(vector_area(tri).z > 0.0 && (vector_area(tri).z - 2.0).abs() < 1e-5);
    assert!(near(centre(&d.meshes[4]), Vec3::new(-2.0, 0.0, 2.0)));
    assert!((area(&d.meshes[4]) / (4.0 * std::f64::consts::PI) - 1.0).abs() < 1e-4);
    assert!(near(vector_area(&d.meshes[5]).normalize(), -Vec3::X), "the mirrored normal");
    // A material defined in an included file is visible after the include (xform passes it on).
    let s = load_ok(&[
        ("a.rad", b"!xform m.rad\nred polygon p 0 0 9 0 0 0 1 0 0 0 1 0\n"),
        ("m.rad", b"void plastic red 0 0 5 1 0 0 0 0\n"),
    ]);
    assert_eq!(s.description.materials[0].name, "red");
    // -m replaces the included surfaces' modifier; -I turns them inside out.
    let s = load_ok(&[
        ("a.rad", format!("{MAT}void light hot 0 0 3 1 1 1\n!xform -m hot -I b.rad\n").as_bytes()),
        ("b.rad", b"grey sphere s 0 0 4 0 0 0 1\ngrey polygon p 0 0 9 0 0 0 1 0 0 0 1 0\n"),
    ]);
    let d = &s.description;
    assert!(d.meshes.iter().all(|m| m.emission.is_some()));
    assert!(vector_area(&d.meshes[1]).z < 0.0, "-I reverses the polygon");
    let m = &d.meshes[0];
    let t = m.triangles[100];
    let [a, b, c] = t.map(|i| m.positions[i as usize]);
    assert!((b - a).cross(c - a).dot(a) < 0.0, "-I makes the sphere a bubble");
}

/// The corners of every triangle of `d`, each triangle's rotated to start at its least corner
/// (the winding kept), sorted: the same set for the same triangles facing the same way.
fn corners(d: &opticks_core::scene::SceneDescription) -> Vec<[[i64; 3]; 3]> {
    let key = |p: Vec3| p.to_array().map(|x| (x * 1e4).round() as i64);
    let mut out: Vec<[[i64; 3]; 3]> = d
        .meshes
        .iter()
        .flat_map(|m| m.triangles.iter().map(|t| t.map(|i| key(m.positions[i as usize]))))
        .map(|mut t| {
            let least = (0..3).min_by_key(|&i| t[i]).unwrap();
            t.rotate_left(least);
            t
        })
        .collect();
    out.sort();
    out
}

/// A light for scenes that must build.
const LAMP: &str = "void light l 0 0 3 1 1 1\nl polygon lamp 0 0 9 0 0 5 0 1 5 1 0 5\n";

#[test]
fn a_mesh_is_its_obj_triangles_transformed_as_polygons_are() {
    // A quad and a triangle; the .obj's material is ignored (the mesh's modifier wins).
    let obj: &[u8] =
        b"mtllib none.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nusemtl other\nf 1 2 3 4\nf 2 5 3\n";
    // The same as polygons: the quad as the two triangles of its fan (OBJ's, which a polygon's
    // ear clipping may cut along the other diagonal).
    let polygons: &[u8] =
        b"grey polygon q1 0 0 9 0 0 0 1 0 0 1 1 0\ngrey polygon q2 0 0 9 0 0 0 1 1 0 0 1 0\n\
        grey polygon t 0 0 9 1 0 0 2 0 0 1 1 0\n";
    // The mesh's own transform (a mirror among it), and one under an !xform: the mesh's
    // transform first, then the include's.
    let meshed = load_ok(&[
        (
            "a.rad",
            format!(
                "{MAT}grey mesh m 8 parts/shape.obj -rz 90 -t 1 2 3 -mx 0 0\n!xform -s 2 parts/b.rad\n{LAMP}"
            )
            .as_bytes(),
        ),
        ("parts/b.rad", b"grey mesh n 5 shape.obj -t 0 0 1 0 0\n"),
        ("parts/shape.obj", obj),
    ]);
    let written = load_ok(&[
        (
            "a.rad",
            format!("{MAT}!xform -rz 90 -t 1 2 3 -mx p.rad\n!xform -t 0 0 1 -s 2 p.rad\n{LAMP}").as_bytes(),
        ),
        ("p.rad", polygons),
    ]);
    let (m, w) = (&meshed.description, &written.description);
    assert_eq!(m.meshes.len(), 3);
    assert_eq!(m.meshes[..2].iter().map(|m| m.triangles.len()).sum::<usize>(), 6);
    assert_eq!(corners(m), corners(w), "the same triangles, facing the same way");
    assert!(m.meshes.iter().all(|x| x.normals.is_empty()), "an .obj without vn is faceted");
    assert_eq!(m.materials[0].name, "grey");
    assert_eq!((m.meshes[0].source.line, m.meshes[1].source.line), (5, 1));
    let (a, b) = (Scene::build(m).unwrap(), Scene::build(w).unwrap());
    opticks_testkit::files::assert_same_scene(&a, &b);
}

#[test]
fn a_mesh_without_its_obj_is_an_error_naming_the_line() {
    let e = error_of(&[("a.rad", format!("{MAT}\ngrey mesh chair 1 chair.rtm 0 0\n").as_bytes())]);
    assert!(
        e.starts_with("TMP/a.rad:6:1: mesh chair: chair.rtm is obj2mesh's compiled mesh")
            && e.contains("name the .obj file it was made from instead"),
        "{e}"
    );
    let e = error_of(&[("a.rad", format!("{MAT}\ngrey mesh chair 1 sub/chair.obj 0 0\n").as_bytes())]);
    assert!(e.starts_with("TMP/a.rad:6:1: mesh chair: cannot read mesh file TMP/sub/chair.obj: "), "{e}");
    let e = error_of(&[
        ("a.rad", format!("{MAT}grey mesh chair 1 chair.obj 0 0\n").as_bytes()),
        ("chair.obj", b"v 0 0 0\nv 1 0 0\nf 1 2 3\n"),
    ]);
    assert!(e.starts_with("TMP/chair.obj:3:") && e.ends_with("(mesh of mesh chair at TMP/a.rad:5:1)"), "{e}");
    let obj: (&str, &[u8]) = ("c.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    for (text, what) in [
        ("void mesh m 1 c.obj 0 0\n", "a void mesh takes the .obj's own materials"),
        ("grey mesh m 3 c.obj -n x 0 0\n", "its transform: \"-n\" is not a transform option"),
        ("grey mesh m 2 c.obj -t 0 0\n", "its transform: -t needs a number"),
        ("grey mesh m 1 c.obj 0 1 1\n", "mesh takes 1 or more string arguments"),
        ("grey mesh m 0 0 0\n", "mesh takes 1 or more string arguments"),
        ("grey mesh m 1 c.ply 0 0\n", "a mesh is read from a Wavefront .obj file"),
    ] {
        let e = error_of(&[("a.rad", format!("{MAT}{text}").as_bytes()), obj]);
        assert!(e.starts_with("TMP/a.rad:5:1: mesh m: ") && e.contains(what), "{e}");
    }
}

#[test]
fn include_cycles_and_depth_are_bounded() {
    let e = error_of(&[("a.rad", b"!xform b.rad\n"), ("b.rad", b"\n!xform -t 1 0 0 a.rad\n")]);
    assert!(e.starts_with("TMP/b.rad:2:1: !xform: TMP/a.rad includes itself"), "{e}");
    let e = error_of(&[("a.rad", b"!xform a.rad\n")]);
    assert!(e.contains("includes itself"), "{e}");
    // A chain of 20 distinct files stops at the depth limit.
    let names: Vec<String> = (0..20).map(|i| format!("f{i}.rad")).collect();
    let texts: Vec<String> = (0..20).map(|i| format!("!xform f{}.rad\n", i + 1)).collect();
    let files: Vec<(&str, &[u8])> =
        names.iter().zip(&texts).map(|(n, t)| (n.as_str(), t.as_bytes())).collect();
    let e = error_of(&files);
    assert!(e.contains("includes nest deeper than 16 files"), "{e}");
}

#[test]
fn views_come_from_the_camera_option() {
    let room = testdata("radiance/room.rad");
    // Without a view, inside a room: from the centre of its bounding box, looking north, z up.
    let s = load_scene(&room).unwrap();
    let c = s.description.camera.unwrap();
    assert_eq!((c.up, c.width, c.height, c.fov_x_degrees), (Vec3::Z, 512, 512, 90.0));
    assert!(
        (c.eye - Vec3::new(2.0, 2.5, 1.5)).length() < 0.01 && (c.target - c.eye - Vec3::Y).length() < 1e-5
    );
    // Around an object (not enclosed): an overview from the south-west, above.
    let s = one("grey sphere ball 0 0 4 1 2 3 0.5\n");
    let c = s.description.camera.unwrap();
    assert!(
        c.eye.x < 1.0
            && c.eye.y < 2.0
            && c.eye.z > 3.5
            && (c.target - Vec3::new(1.0, 2.0, 3.0)).length() < 0.01
    );
    let vf = testdata("radiance/room.vf");
    let options = LoadOptions { camera: Some(vf.display().to_string()), ..Default::default() };
    let c = load_scene_with(&room, &options).unwrap().description.camera.unwrap();
    assert_eq!((c.eye, c.fov_x_degrees, c.kind), (Vec3::new(2.0, 4.6, 1.6), 75.0, CameraKind::Perspective));
    let options = LoadOptions {
        camera: Some("-vtl -vp 2 2.5 10 -vd 0 0 -1 -vu 0 1 0 -vh 4 -vv 5".into()),
        ..Default::default()
    };
    let c = load_scene_with(&room, &options).unwrap().description.camera.unwrap();
    assert_eq!((c.width, c.height), (512, 640));
    let options = LoadOptions { camera: Some("-vth".into()), ..Default::default() };
    let e = load_scene_with(&room, &options).unwrap_err().to_string();
    assert!(e.contains("--camera \"-vth\": Radiance view: view type -vth is not supported"), "{e}");
    let options = LoadOptions { gltf_scene: Some("1".into()), ..Default::default() };
    assert!(load_scene_with(&room, &options).unwrap_err().to_string().contains("one scene"));
}

#[test]
fn the_example_room_loads_and_builds() {
    let s = load_scene(&testdata("radiance/room.rad")).unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let d = &s.description;
    let lights: Vec<&str> =
        d.meshes.iter().filter(|m| m.emission.is_some()).map(|m| m.name.as_str()).collect();
    assert_eq!(lights, ["ceiling_panel"]);
    assert!(d.meshes.iter().any(|m| m.name == "desk.bowl"));
    let window = d.meshes.iter().find(|m| m.name == "window").unwrap();
    assert!(matches!(d.materials[window.material].bsdf, Bsdf::ThinDielectric(_)));
    let scene = Scene::build(d).unwrap();
    assert_eq!(scene.dropped_triangles, 0);
}

/// Issue 27: a sky in either format. `<emitter type="gensky">` (and `gendaylit`) in Mitsuba XML
/// carries the sky a `.rad` file's `!gensky` line and its sky and ground domes describe: the
/// same radiance toward every texel (the domes' maps summed: their shared horizon row counts
/// once) and the same sun; `to_world` turns Radiance's z-up frame into the scene's.
#[test]
fn a_mitsuba_sky_emitter_is_the_rad_files_sky() {
    use opticks_core::scene::EnvironmentRadiance;
    let domes = "skyfunc glow sky_glow 0 0 4 1 1 1 0\nsky_glow source sky 0 0 4 0 0 1 180\n\
                 skyfunc glow ground_glow 0 0 4 1 1 1 0\nground_glow source ground 0 0 4 0 0 -1 180\n";
    let texels = |r: &EnvironmentRadiance| match r {
        EnvironmentRadiance::Map { texels, .. } => texels.clone(),
        _ => panic!("a sky is a map"),
    };
    for (program, args) in
        [("gensky", "3 21 12 +s -a 52 -o 0 -m 0"), ("gendaylit", "-ang 40 20 -W 600 120 -O 1")]
    {
        let rad = load_ok(&[("a.rad", format!("!{program} {args}\n{domes}").as_bytes())]).description;
        let xml = format!(
            "<scene version=\"3.0.0\"><emitter type=\"{program}\" id=\"day\">\
             <string name=\"arguments\" value=\"{args}\"/></emitter></scene>"
        );
        let xml = load_ok(&[("a.xml", xml.as_bytes())]).description;
        let (sky, ground) = (&rad.environment_lights[0], &rad.environment_lights[1]);
        let one = &xml.environment_lights[0];
        assert_eq!(
            (one.name.as_str(), one.to_world, one.sky.clone()),
            ("day", sky.to_world, sky.sky.clone())
        );
        let (a, b, c) = (texels(&sky.radiance), texels(&ground.radiance), texels(&one.radiance));
        let mut horizon = 0;
        for ((a, b), c) in a.iter().zip(&b).zip(&c) {
            let sum = *a + *b;
            assert!(
                (sum - *c).abs().max_element() <= 1e-6 * c.max_element().max(1e-3),
                "{program}: {sum} vs {c}"
            );
            horizon += usize::from(*a != Rgb::ZERO && *b != Rgb::ZERO);
        }
        assert_eq!(horizon, 512, "{program}: the domes share the horizon row only");
        let (sun, xsun) = (&rad.directional_lights[0], &xml.directional_lights[0]);
        assert_eq!(
            (xsun.name.as_str(), xsun.direction, xsun.irradiance),
            ("day.sun", sun.direction, sun.irradiance)
        );
    }

    // A y-up scene: the zenith and the sun turn with to_world.
    let xml = "<scene version=\"3.0.0\"><emitter type=\"gensky\" id=\"s\">\
               <string name=\"arguments\" value=\"-ang 30 0 +s\"/>\
               <transform name=\"to_world\"><rotate x=\"1\" angle=\"-90\"/></transform></emitter></scene>";
    let d = load_ok(&[("y.xml", xml.as_bytes())]).description;
    let pole = d.environment_lights[0].to_world * Vec3::Y;
    assert!((pole - Vec3::Y).length() < 1e-6, "the zenith is the scene's +y: {pole}");
    let toward_sun = -d.directional_lights[0].direction;
    assert!((toward_sun.y - 0.5).abs() < 1e-6, "the sun 30° above the scene's horizon: {toward_sun}");

    // Bad input is an error at the element; nested in a shape, it is refused as the other skies.
    let e = error_of(&[(
        "b.xml",
        b"<scene version=\"3.0.0\">\n<emitter type=\"gensky\">\n<string name=\"arguments\" value=\"3 21 12 -a\"/>\n</emitter></scene>",
    )]);
    assert!(e.contains("b.xml:3:") && e.contains("gensky"), "{e}");
    let e = error_of(&[("c.xml", b"<scene version=\"3.0.0\"><emitter type=\"gendaylit\"/></scene>")]);
    assert!(e.contains("arguments"), "{e}");
}

/// `<emitter type="ciesky">`: a CIE general sky whose map is the type's closed form
/// (`CieGeneralSky` evaluated directly) texel for texel, scaled by gensky's `-b`/`-B`, with the
/// sun gensky's `-R` states and the ground ρ·E/π; bad types and arguments are errors at the
/// element.
#[test]
fn a_ciesky_emitter_is_the_cie_general_sky() {
    use opticks_core::scene::{EnvironmentRadiance, SkyModel as Recorded};
    use opticks_io::scene_formats::radiance::sky::map_to_world;
    use opticks_io::scene_formats::radiance::{CieGeneralSky, SkyModel};
    let deg = std::f64::consts::PI / 180.0;
    let xml = |n: i64, args: &str| {
        format!(
            "<scene version=\"3.0.0\">\n<emitter type=\"ciesky\" id=\"sky\">\n<integer name=\"type\" value=\"{n}\"/>\n\
             <string name=\"arguments\" value=\"{args}\"/>\n</emitter></scene>"
        )
    };
    // Type 1 (overcast, steep gradation) at -B 100 without a sun; type 12 (clear) at -b 20 with
    // a sun of 500 W/m² on the horizontal, its position from a date and a site as gensky's.
    for (n, args) in [(1, "-ang 40 20 -B 100"), (12, "3 21 12 -a 52 -o 0 -m 0 -b 20 -R 500")] {
        let d = load_ok(&[("a.xml", xml(n, args).as_bytes())]).description;
        let light = &d.environment_lights[0];
        assert_eq!(light.name, "sky");
        assert_eq!(light.sky, Some(Recorded::Other(format!("a CIE general sky of type {n} (ciesky)"))));
        let EnvironmentRadiance::Map { width, height, texels, .. } = &light.radiance else {
            panic!("a sky is a map")
        };
        let model = SkyModel::CieGeneral(CieGeneralSky::new(n as u8).unwrap());
        let toward_sun = match d.directional_lights.first() {
            Some(sun) => {
                assert_eq!((n, sun.name.as_str()), (12, "sky.sun"));
                -sun.direction.as_dvec3()
            }
            None => {
                glam::DVec3::new(-(20.0 * deg).sin(), -(20.0 * deg).cos(), 0.0) * (40.0 * deg).cos()
                    + glam::DVec3::Z * (40.0 * deg).sin()
            }
        };
        if n == 12 {
            let sun = &d.directional_lights[0];
            let horizontal = sun.irradiance.x as f64 * toward_sun.z;
            assert!(
                (horizontal / 500.0 - 1.0).abs() < 1e-5,
                "-R is the sun's horizontal irradiance: {horizontal}"
            );
        }
        let zenith = texels[0].x as f64;
        let expected = if n == 1 { model.zenith_for(100.0, toward_sun) } else { 20.0 };
        assert!((zenith / expected - 1.0).abs() < 1e-5, "type {n}: zenith {zenith} vs {expected}");
        for j in 0..*height {
            let theta = std::f64::consts::PI * j as f64 / (*height - 1) as f64;
            for i in 0..*width {
                let phi = 2.0 * std::f64::consts::PI * (i as f64 + 0.5) / *width as f64;
                let dir = map_to_world(phi, theta);
                let t = texels[j * width + i];
                assert!(t.x == t.y && t.y == t.z, "a grey sky");
                if dir.z > 0.0 {
                    // Relative: the sun's direction is read back as f32, and the circumsolar
                    // peak is steep.
                    let closed = zenith * model.relative_luminance(dir, toward_sun);
                    assert!(
                        (t.x as f64 - closed).abs() <= 1e-5 * closed.max(zenith),
                        "type {n} at ({i}, {j}): {} vs {closed}",
                        t.x
                    );
                }
            }
        }
        // The gradation: toward the horizon (θ = 85°, far from the sun's azimuth for type 1,
        // whose indicatrix is flat) the sky is φ(85°)/φ(0) of the zenith.
        if n == 1 {
            let t = CieGeneralSky::new(1).unwrap();
            let d = glam::DVec3::new((85.0 * deg).sin(), 0.0, (85.0 * deg).cos());
            let ratio = model.relative_luminance(d, toward_sun);
            assert!((ratio - t.gradation(85.0 * deg) / t.gradation(0.0)).abs() < 1e-12);
            assert!(ratio < 0.4 && t.gradation(0.0) > 2.9, "the overcast's darker horizon: {ratio}");
            // Below: the ground, ρ = 0.2 of the 100 W/m² on the horizontal, over π.
            let ground = texels[(height - 1) * width].x as f64;
            assert!((ground / (0.2 * 100.0 / std::f64::consts::PI) - 1.0).abs() < 1e-3, "ground {ground}");
        }
    }
    for (n, args, at, what) in [
        (0, "-ang 40 20 -B 100", "a.xml:3:", "CIE general sky type 0: the types are 1 to 15"),
        (16, "-ang 40 20 -B 100", "a.xml:3:", "CIE general sky type 16"),
        (3, "-ang 40 20", "a.xml:4:", "the sky's level is missing: give -b"),
        (3, "-ang 40 20 -B 100 -c", "a.xml:4:", "-c: gensky's sky options"),
        (3, "13 21 12 -B 100", "a.xml:4:", "bad month"),
    ] {
        let e = error_of(&[("a.xml", xml(n, args).as_bytes())]);
        assert!(e.starts_with(&format!("TMP/{at}")) && e.contains(what), "{e}");
    }
    let e = error_of(&[(
        "a.xml",
        b"<scene version=\"3.0.0\">\n<emitter type=\"ciesky\">\n<string name=\"arguments\" value=\"-ang 40 20 -B 1\"/>\n</emitter></scene>",
    )]);
    assert!(e.starts_with("TMP/a.xml:2:") && e.contains("needs its CIE general sky type"), "{e}");
}

/// Photometry is the format's: a `.rad` scene's description and built scene carry Radiance's
/// rule (179 lm/W, its primaries), the other formats' the default (683 lm/W, Rec. 709).
#[test]
fn a_radiance_scene_carries_radiances_photometry() {
    let rad = load_scene(&testdata("radiance/photometry.rad")).unwrap().description;
    assert_eq!(rad.photometry, Photometry::RADIANCE);
    assert_eq!(Scene::build(&rad).unwrap().photometry, Photometry::RADIANCE);
    assert_eq!(one("grey sphere s 0 0 4 0 0 0 1\n").description.photometry, Photometry::RADIANCE);
    for other in ["scenes/cornell/scene.xml", "obj/cornell.obj", "gltf/cornell.gltf"] {
        let d = load_scene(&testdata(other)).unwrap().description;
        assert_eq!(d.photometry, Photometry::REC709_683, "{other}");
    }
}

/// Several files are one scene read in order, as `oconv a.rad b.rad` reads them: a modifier of
/// an earlier file modifies surfaces of a later one, a later definition of a name replaces the
/// earlier from there on (as within one file), errors name the file and line they are in, a
/// missing file is named, and only `.rad` files are joined.
#[test]
fn several_files_are_one_scene_read_in_order() {
    use opticks_io::scene_source::{self, SceneRef};
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let mats = write("mats.rad", "void plastic wall 0 0 5 0.5 0.5 0.5 0 0\nvoid light lamp 0 0 3 1 1 1\n");
    let geo = write(
        "geo.rad",
        "wall polygon a 0 0 9 0 0 0 1 0 0 0 1 0\nvoid plastic wall 0 0 5 0.2 0.2 0.2 0 0\n\
         wall polygon b 0 0 9 0 0 1 1 0 1 0 1 1\nlamp polygon l 0 0 9 0 0 5 0 1 5 1 0 5\n",
    );
    let load = |files: &[&std::path::Path]| {
        let given = files.iter().map(|f| SceneRef::parse(f.to_str().unwrap()).unwrap()).collect();
        scene_source::load(&SceneRef::joined(given).unwrap(), &LoadOptions::default())
    };
    let s = load(&[&mats, &geo]).unwrap_or_else(|e| panic!("{e}"));
    let d = &s.description;
    let albedo = |name: &str| {
        let m = d.meshes.iter().find(|m| m.name == name).unwrap();
        match &d.materials[m.material].bsdf {
            Bsdf::Lambert(l) => l.reflectance,
            b => panic!("{b:?}"),
        }
    };
    assert!((albedo("a") - Rgb::splat(0.5)).length() < 1e-6, "the first file's wall");
    assert!((albedo("b") - Rgb::splat(0.2)).length() < 1e-6, "redefined from there on");
    assert_eq!(d.photometry, Photometry::RADIANCE);
    // The same text in one file is the same scene.
    let one = write(
        "one.rad",
        &(std::fs::read_to_string(&mats).unwrap() + &std::fs::read_to_string(&geo).unwrap()),
    );
    let single = load_scene(&one).unwrap();
    let shape = |d: &opticks_core::scene::SceneDescription| {
        let m =
            d.meshes.iter().map(|m| (m.name.clone(), m.positions.clone(), m.triangles.clone(), m.material));
        m.collect::<Vec<_>>()
    };
    assert_eq!(shape(&single.description), shape(d));
    // The geometry alone: its first use of `wall` is undefined, at its own line.
    let e = load(&[&geo]).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("geo.rad:1:1") && e.contains("undefined modifier \"wall\""), "{e}");
    let bad = write("bad.rad", "\nwall sphere s 0 0 3 0 0 0\n");
    let e = load(&[&mats, &bad]).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("bad.rad:2:1: sphere s"), "{e}");
    let missing = dir.path().join("missing.rad");
    let e = load(&[&mats, &missing]).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("missing.rad: cannot open a scene file"), "{e}");
}

/// A sphere that emits (`light`, `glow`; Radiance's point source) is tessellated on the grid
/// that keeps its intensity within 0.1 % (64 × 32: 3,968 triangles, checked against the
/// analytic sphere in `tessellate`), with the analytic area (its power); any other sphere, seen
/// in images, on the fine 128 × 64 grid (16,128).
#[test]
fn a_light_sphere_is_tessellated_for_its_intensity() {
    let s = one("void light l 0 0 3 1 1 1\nvoid glow g 0 0 4 1 1 1 0\n\
         l sphere bulb 0 0 4 0 0 3 0.01\ng sphere globe 0 0 4 1 0 3 0.2\n\
         grey sphere ball 0 0 4 1 2 3 0.5\n");
    let m = |name: &str| s.description.meshes.iter().find(|m| m.name == name).unwrap();
    let pi = std::f64::consts::PI;
    for (name, r, triangles) in [("bulb", 0.01f64, 3968), ("globe", 0.2, 3968), ("ball", 0.5, 16128)] {
        assert_eq!(m(name).triangles.len(), triangles, "{name}");
        assert!((area(m(name)) / (4.0 * pi * r * r) - 1.0).abs() < 1e-5, "{name}: {}", area(m(name)));
    }
}
