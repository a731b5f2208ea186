//! The Mitsuba 3 XML loader, element by element, through its public API
//! ([`opticks_io::scene_formats::mitsuba::parse`]): transforms, the sensor, each BSDF, shapes and
//! their normals, interior media, emitters, parameters, warnings, and the located errors of
//! broken scenes. Scenes read from files (the reference scenes, OBJ meshes next to the XML) are
//! in `scene_loading.rs`; the light extensions' physics in `crates/cli/tests/it/lights.rs`.

use opticks_core::bsdf::{Bsdf, RoughConductor, RoughDielectric, SmoothConductor, SmoothDielectric};
use opticks_core::math::{Mat3, Rgb, Vec3};
use opticks_core::sampling::microfacet::{Distribution, Microfacet};
use opticks_core::scene::{CameraKind, EnvironmentRadiance, MeshDesc, Source};
use opticks_io::scene_formats::mitsuba::{fov_to_x, parse};
use opticks_io::{LoadOptions, LoadedScene, SceneFileError};
use std::path::Path;

fn load_str(xml: &str) -> Result<LoadedScene, SceneFileError> {
    parse(xml, Path::new("dir/test.xml"), &LoadOptions::default())
}

fn scene(body: &str) -> LoadedScene {
    let xml = format!("<scene version=\"3.0.0\">\n{body}\n</scene>");
    load_str(&xml).unwrap_or_else(|e| panic!("{e}\n{xml}"))
}

fn err(body: &str) -> String {
    let xml = format!("<scene version=\"3.0.0\">\n{body}\n</scene>");
    match load_str(&xml) {
        Ok(_) => panic!("should fail:\n{xml}"),
        Err(e) => e.to_string(),
    }
}

/// World positions of a `rectangle` under `transform` (the inner XML of `<transform>`).
fn rect(transform: &str) -> Vec<Vec3> {
    let s = scene(&format!(
        "<shape type=\"rectangle\"><transform name=\"to_world\">{transform}</transform></shape>"
    ));
    s.description.meshes[0].positions.clone()
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[track_caller]
fn assert_close(a: Vec3, b: Vec3) {
    assert!(close(a, b), "{a} != {b}");
}

fn normal(m: &MeshDesc, t: usize) -> Vec3 {
    let [a, b, c] = m.triangles[t].map(|i| m.positions[i as usize]);
    (b - a).cross(c - a).normalize()
}

#[test]
fn transforms_compose_in_mitsuba_order() {
    // Vertex 0 of the rectangle is (-1, -1, 0).
    let v0 = |t: &str| rect(t)[0];
    assert_close(v0(r#"<translate x="1" y="2" z="3"/><scale value="2"/>"#), Vec3::new(0.0, 2.0, 6.0));
    assert_close(v0(r#"<scale value="2"/><translate value="1, 2, 3"/>"#), Vec3::new(-1.0, 0.0, 3.0));
    assert_close(v0(r#"<scale x="3"/>"#), Vec3::new(-3.0, -1.0, 0.0));
    assert_close(v0(r#"<scale value="1 2 3"/>"#), Vec3::new(-1.0, -2.0, 0.0));
    // +90° about y maps (x, y, z) to (z, y, −x).
    assert_close(v0(r#"<rotate y="1" angle="90"/>"#), Vec3::new(0.0, -1.0, 1.0));
    // Mitsuba does not normalise the axis: (0, 2, 0) by 90° is a·aᵀ + [a]×, which maps
    // (-1, -1, 0) to (0, -4, 2) (Mitsuba 3.9.1 gives (5, -4, 2) after the translation).
    assert_close(v0(r#"<rotate value="0, 2, 0" angle="90"/><translate x="5"/>"#), Vec3::new(5.0, -4.0, 2.0));
    assert_close(v0(r#"<translate x="5"/><rotate y="1" angle="90"/>"#), Vec3::new(0.0, -1.0, -4.0));
    assert_close(
        v0(r#"<matrix value="1 0 0 10  0 1 0 20  0 0 1 30  0 0 0 1"/>"#),
        Vec3::new(9.0, 19.0, 30.0),
    );
    assert_close(v0(r#"<matrix value="0,-1,0, 1,0,0, 0,0,1"/>"#), Vec3::new(1.0, -1.0, 0.0));
    // lookat looking down +z from (1, 2, 3): left = up × dir = +x, so a pure translation.
    assert_close(v0(r#"<lookat origin="1, 2, 3" target="1, 2, 4" up="0, 1, 0"/>"#), Vec3::new(0.0, 1.0, 3.0));
    // Looking down −z: local +x (image left) is world −x, local +z is world −z.
    let p = rect(r#"<lookat origin="0, 0, 0" target="0, 0, -1" up="0, 1, 0"/>"#);
    assert_close(p[2], Vec3::new(-1.0, 1.0, 0.0));
    // Without `up`, any perpendicular frame: still a rigid motion.
    let p = rect(r#"<lookat origin="0, 0, 0" target="3, 0, 0"/>"#);
    assert!(((p[0] - p[2]).length() - 8f32.sqrt()).abs() < 1e-5 && p.iter().all(|q| q.x.abs() < 1e-6));
}

#[test]
fn canonical_shapes_face_the_right_way() {
    let s = scene(
        r#"<shape type="rectangle"/>
               <shape type="rectangle"><boolean name="flip_normals" value="true"/></shape>
               <shape type="rectangle"><transform name="to_world"><scale x="-1"/></transform></shape>
               <shape type="cube" id="box"><transform name="to_world"><translate x="10"/></transform></shape>"#,
    );
    let m = &s.description.meshes;
    assert_eq!(m[0].name, "rectangle_0");
    assert_eq!(m[3].name, "box");
    assert_close(normal(&m[0], 0), Vec3::Z);
    assert_close(normal(&m[0], 1), Vec3::Z);
    assert_close(normal(&m[1], 0), -Vec3::Z);
    assert_close(normal(&m[2], 0), Vec3::Z); // mirrored, normal kept as Mitsuba transforms it
    assert_eq!(m[3].triangles.len(), 12);
    let centre = Vec3::new(10.0, 0.0, 0.0);
    for t in 0..12 {
        let [a, b, c] = m[3].triangles[t].map(|i| m[3].positions[i as usize]);
        let mid = (a + b + c) / 3.0 - centre;
        assert!(normal(&m[3], t).dot(mid) > 0.5, "cube triangle {t} faces inward");
        assert!(m[3].positions.iter().all(|p| (*p - centre).abs().max_element() == 1.0));
    }
}

#[test]
fn fov_axis_conversions() {
    let tan = |deg: f64| (deg.to_radians() / 2.0).tan();
    let atan2x = |t: f64| 2.0 * t.atan().to_degrees();
    // 200×100: aspect 2.
    assert_eq!(fov_to_x(60.0, "x", 200, 100), Some(60.0));
    let y = fov_to_x(60.0, "y", 200, 100).unwrap();
    assert!((y - atan2x(2.0 * tan(60.0))).abs() < 1e-9 && (y - 98.2132).abs() < 1e-3);
    assert_eq!(fov_to_x(60.0, "smaller", 200, 100), Some(y));
    assert_eq!(fov_to_x(60.0, "larger", 200, 100), Some(60.0));
    // Portrait: the smaller side is x.
    assert_eq!(fov_to_x(60.0, "smaller", 100, 200), Some(60.0));
    assert!((fov_to_x(60.0, "larger", 100, 200).unwrap() - atan2x(0.5 * tan(60.0))).abs() < 1e-9);
    // Diagonal 90°: half-diagonal tangent 1 = hypot(tx, tx/2).
    let d = fov_to_x(90.0, "diagonal", 200, 100).unwrap();
    assert!((d - atan2x(1.0 / 1.25f64.sqrt())).abs() < 1e-9, "{d}");
    assert_eq!(fov_to_x(60.0, "z", 1, 1), None);

    let cam = |axis: &str| {
        scene(&format!(
                r#"<sensor type="perspective"><float name="fov" value="60"/><string name="fov_axis" value="{axis}"/>
                   <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/>
                   <rfilter type="box"/></film></sensor>"#
            ))
            .description
            .camera
            .unwrap()
    };
    assert!((cam("Y").fov_x_degrees as f64 - y).abs() < 1e-4);
    assert_eq!(cam("x").fov_x_degrees, 60.0);
    assert_eq!((cam("x").width, cam("x").height), (200, 100));
}

#[test]
fn sensor_frames_match_mitsuba() {
    let cam = |t: &str| {
        scene(&format!(
            r#"<sensor type="perspective"><float name="fov" value="45"/>
                   <transform name="to_world">{t}</transform></sensor>"#
        ))
        .description
        .camera
        .unwrap()
    };
    let c = cam(r#"<lookat origin="1, 2, 3" target="4, 6, 3" up="0, 0, 1"/>"#);
    assert_close(c.eye, Vec3::new(1.0, 2.0, 3.0));
    assert_close(c.target, Vec3::new(4.0, 6.0, 3.0));
    assert_close(c.up, Vec3::Z);
    assert_eq!((c.width, c.height), (768, 576)); // Mitsuba's default film
    // lookat then a world translation: everything moves.
    let c = cam(r#"<lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/><translate y="1"/>"#);
    assert_close(c.eye, Vec3::new(0.0, 1.0, 5.0));
    assert_close(c.target, Vec3::new(0.0, 1.0, 0.0));
    // Rotating the default camera (looking down +z) by 180° about y = lookat down −z.
    let c = cam(r#"<rotate y="1" angle="180"/><translate z="5"/>"#);
    assert_close(c.eye, Vec3::new(0.0, 0.0, 5.0));
    assert_close((c.target - c.eye).normalize(), -Vec3::Z);
    assert_close(c.up, Vec3::Y);
    // Image right = forward × up = +x, as Mitsuba's image right (−local x) is.
    assert_close((c.target - c.eye).cross(c.up).normalize(), Vec3::X);

    let e = err(r#"<sensor type="perspective"><float name="fov" value="45"/>
               <transform name="to_world"><scale x="-1"/></transform></sensor>"#);
    assert!(e.starts_with("dir/test.xml:3:16: <transform name=\"to_world\">:"), "{e}");
    assert!(e.contains("mirror"), "{e}");
    let s = scene(
        r#"<sensor type="perspective"><float name="fov" value="45"/>
               <transform name="to_world"><scale value="2"/></transform></sensor>"#,
    );
    assert!(s.warnings.iter().any(|w| w.contains("scale or shear")), "{:?}", s.warnings);
}

#[test]
fn thinlens_reads_aperture_focus_and_the_perspective_parameters() {
    let cam = |params: &str| {
        scene(&format!(
            r#"<sensor type="thinlens">{params}
                   <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
                   <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/>
                   <rfilter type="box"/></film></sensor>"#
        ))
        .description
        .camera
        .unwrap()
    };
    let c = cam(r#"<float name="aperture_radius" value="0.2"/><float name="focus_distance" value="4.5"/>
                   <float name="fov" value="30"/><string name="fov_axis" value="y"/>"#);
    assert_eq!(c.kind, CameraKind::ThinLens { aperture_radius: 0.2, focus_distance: 4.5 });
    assert!((c.fov_x_degrees as f64 - fov_to_x(30.0, "y", 200, 100).unwrap()).abs() < 1e-4);
    assert_close(c.eye, Vec3::new(0.0, 0.0, 5.0));
    assert_close(c.target, Vec3::ZERO);
    // focus_distance defaults to far_clip (Mitsuba's), the field of view to 50 mm.
    let c = cam(r#"<float name="aperture_radius" value="0.1"/><float name="far_clip" value="300"/>"#);
    assert_eq!(c.kind, CameraKind::ThinLens { aperture_radius: 0.1, focus_distance: 300.0 });
    let diag = 2.0 * (43.2666f64 / 100.0).atan().to_degrees();
    assert!((c.fov_x_degrees as f64 - fov_to_x(diag, "diagonal", 200, 100).unwrap()).abs() < 1e-3);
    let c = cam(r#"<float name="aperture_radius" value="0.1"/>"#);
    assert_eq!(c.kind, CameraKind::ThinLens { aperture_radius: 0.1, focus_distance: 1e4 });
    for (params, message) in [
        ("", "needs `aperture_radius`"),
        (r#"<float name="aperture_radius" value="-0.1"/>"#, "aperture_radius: lens radius -0.1"),
        (
            r#"<float name="aperture_radius" value="0.1"/><float name="focus_distance" value="0"/>"#,
            "focus_distance: focus distance 0",
        ),
    ] {
        let e = err(&format!(r#"<sensor type="thinlens">{params}</sensor>"#));
        assert!(e.contains(message) && e.starts_with("dir/test.xml:"), "{e}");
    }
}

#[test]
fn orthographic_film_is_to_worlds_image_of_the_unit_square() {
    let cam = |t: &str, extra: &str| {
        scene(&format!(
            r#"<sensor type="orthographic">{extra}<transform name="to_world">{t}</transform>
                   <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/>
                   <rfilter type="box"/></film></sensor>"#
        ))
        .description
        .camera
        .unwrap()
    };
    // Mitsuba's example: a lookat after a scale of the film to 20 × 20 world units (local x
    // ∈ [-1, 1] → 20 units wide; local y ∈ [-1/aspect, 1/aspect] → 10 units high at 2:1).
    let c = cam(r#"<scale x="10" y="10"/><lookat origin="1, 1, 1" target="1, 2, 1" up="0, 0, 1"/>"#, "");
    assert_eq!(c.kind, CameraKind::Orthographic { half_width: 10.0, half_height: 5.0 });
    // The film starts at the near plane (0.01 along the view), as Mitsuba's rays do.
    assert_close(c.eye, Vec3::new(1.0, 1.01, 1.0));
    assert_close((c.target - c.eye).normalize(), Vec3::Y);
    assert_close(c.up, Vec3::Z);
    // Image right = forward × up = +x: Mitsuba's (local +x is the image left).
    assert_close((c.target - c.eye).cross(c.up).normalize(), Vec3::X);
    let c = cam(
        r#"<lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/>"#,
        r#"<float name="near_clip" value="0.5"/>"#,
    );
    assert_eq!(c.kind, CameraKind::Orthographic { half_width: 1.0, half_height: 0.5 });
    assert_close(c.eye, Vec3::new(0.0, 0.0, 4.5));
    for (t, message) in [
        (r#"<scale x="-1"/>"#, "mirrors space"),
        (r#"<matrix value="1 0.5 0 0  0 1 0 0  0 0 1 0  0 0 0 1"/>"#, "perpendicular"),
        (r#"<scale z="0"/>"#, "singular"),
    ] {
        let e = err(&format!(
            r#"<sensor type="orthographic"><transform name="to_world">{t}</transform></sensor>"#
        ));
        assert!(e.contains(message) && e.contains("<transform name=\"to_world\">"), "{e}");
    }
    let e = err(r#"<sensor type="orthographic"><float name="near_clip" value="0"/></sensor>"#);
    assert!(e.contains("near_clip 0 must be"), "{e}");
}

#[test]
fn focal_length_default_is_50mm_diagonal() {
    let c = scene(r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="box"/></film></sensor>"#)
        .description
        .camera
        .unwrap();
    let diag = 2.0 * (43.2666f64 / 100.0).atan().to_degrees();
    let expect = fov_to_x(diag, "diagonal", 768, 576).unwrap();
    assert!((c.fov_x_degrees as f64 - expect).abs() < 1e-3, "{}", c.fov_x_degrees);
    // 4:3 film: the horizontal extent is 4/5 of the 43.27 mm diagonal of a 36×24 mm frame.
    assert!((c.fov_x_degrees as f64 - 2.0 * (0.8 * 43.2666f64 / 100.0).atan().to_degrees()).abs() < 1e-3);
}

#[test]
fn parameters_are_substituted() {
    let xml = r#"<scene version="3.0.0">
            <default name="spp" value="64"/>
            <default name="w" value="32"/>
            <sensor type="perspective"><float name="fov" value="$w.5"/>
              <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
              <film type="hdrfilm"><integer name="width" value="$w"/><integer name="height" value="$w"/>
              <rfilter type="box"/></film></sensor>
        </scene>"#;
    let c = load_str(xml).unwrap().description.camera.unwrap();
    assert_eq!((c.width, c.height, c.fov_x_degrees), (32, 32, 32.5));
    let opts = LoadOptions { defines: vec![("w".into(), "16".into())], ..Default::default() };
    let c = parse(xml, Path::new("x.xml"), &opts).unwrap().description.camera.unwrap();
    assert_eq!((c.width, c.fov_x_degrees), (16, 16.5));
    let e = err(r#"<shape type="rectangle" id="$name"/>"#);
    assert!(
        e.starts_with(
            "dir/test.xml:2:29: <shape type=\"rectangle\" id=\"$name\">: undefined parameter $name"
        ),
        "{e}"
    );
}

#[test]
fn materials_follow_mitsuba_sidedness_and_references() {
    let s = scene(
        r#"<shape type="rectangle" id="a"><ref id="late"/></shape>
               <shape type="rectangle" id="b"><ref name="bsdf" id="late"/></shape>
               <shape type="rectangle" id="c"><bsdf type="diffuse"><float name="reflectance" value="0.25"/></bsdf></shape>
               <shape type="rectangle" id="d"/>
               <shape type="rectangle" id="e"/>
               <bsdf type="diffuse" id="base"><spectrum name="reflectance" value="0.75"/></bsdf>
               <bsdf type="twosided" id="late"><ref id="base"/></bsdf>
               <bsdf type="twosided" id="unused"><bsdf type="diffuse"/></bsdf>"#,
    );
    let d = &s.description;
    let mat = |mesh: usize| &d.materials[d.meshes[mesh].material];
    let rho = |mesh: usize| match &mat(mesh).bsdf {
        Bsdf::Lambert(l) => l.reflectance,
        other => panic!("{other:?}"),
    };
    assert_eq!(d.meshes[0].material, d.meshes[1].material);
    assert_eq!((mat(0).name.as_str(), mat(0).two_sided, rho(0)), ("late", true, Rgb::splat(0.75)));
    assert_eq!((mat(2).name.as_str(), mat(2).two_sided, rho(2)), ("c.bsdf", false, Rgb::splat(0.25)));
    assert_eq!((mat(3).name.as_str(), mat(3).two_sided, rho(3)), ("default", false, Rgb::splat(0.5)));
    assert_eq!(d.meshes[3].material, d.meshes[4].material);
    assert_eq!(d.materials.len(), 3);
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
    assert!(s.warnings[0].contains("id=\"unused\">: this BSDF is never used"), "{:?}", s.warnings);
}

#[test]
fn phong_bsdf_is_read_with_mitsuba_06_parameters() {
    let s = scene(
        r#"<shape type="rectangle" id="a">
                 <bsdf type="phong">
                   <rgb name="diffuseReflectance" value="0.3, 0.2, 0.1"/>
                   <spectrum name="specularReflectance" value="0.6"/>
                   <float name="exponent" value="250"/>
                 </bsdf>
               </shape>
               <shape type="rectangle" id="b"><ref id="shiny"/></shape>
               <shape type="rectangle" id="c"><bsdf type="phong"/></shape>
               <bsdf type="twosided" id="shiny">
                 <bsdf type="phong"><float name="diffuseReflectance" value="0"/><integer name="exponent" value="1000"/></bsdf>
               </bsdf>"#,
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let d = &s.description;
    let phong = |mesh: usize| {
        let m = &d.materials[d.meshes[mesh].material];
        match &m.bsdf {
            Bsdf::ModifiedPhong(p) => (m.name.clone(), m.two_sided, p.kd, p.ks, p.exponent),
            other => panic!("{other:?}"),
        }
    };
    assert_eq!(phong(0), ("a.bsdf".into(), false, Rgb::new(0.3, 0.2, 0.1), Rgb::splat(0.6), 250.0));
    assert_eq!(phong(1), ("shiny".into(), true, Rgb::ZERO, Rgb::splat(0.2), 1000.0));
    // Mitsuba 0.6's defaults: kd 0.5, ks 0.2, exponent 30; one-sided.
    assert_eq!(phong(2), ("c.bsdf".into(), false, Rgb::splat(0.5), Rgb::splat(0.2), 30.0));
    let sum = d.materials[0].bsdf.max_albedo();
    assert!((sum - Rgb::new(0.9, 0.8, 0.7)).abs().max_element() < 1e-6, "{sum}");
    // kd + ks = 1 exactly is allowed (the decimal pair rounds to at most 1 in f32).
    scene(
        r#"<shape type="rectangle"><bsdf type="phong"><float name="diffuseReflectance" value="0.35"/>
               <float name="specularReflectance" value="0.65"/></bsdf></shape>"#,
    );
}

#[test]
fn impossible_phong_parameters_are_located() {
    let at = |body: &str| err(&format!("<bsdf type=\"phong\" id=\"p\">\n  {body}\n</bsdf>"));
    // kd + ks > 1 involves both parameters: reported at the <bsdf>.
    let e = at(
        r#"<rgb name="diffuseReflectance" value="0.5, 0.7, 0.5"/><float name="specularReflectance" value="0.4"/>"#,
    );
    assert!(
        e.starts_with("dir/test.xml:2:1: <bsdf type=\"phong\" id=\"p\">: invalid material: kd + ks = "),
        "{e}"
    );
    assert!(e.contains("create energy"), "{e}");
    // With the default ks = 0.2, kd = 0.9 is already too much.
    let e = at(r#"<float name="diffuseReflectance" value="0.9"/>"#);
    assert!(e.starts_with("dir/test.xml:2:1: <bsdf type=\"phong\" id=\"p\">: invalid material:"), "{e}");
    let e = at(r#"<float name="exponent" value="NaN"/>"#);
    assert_eq!(
        e,
        "dir/test.xml:3:33: <float name=\"exponent\">: attribute `value`: \"NaN\" is not a finite number"
    );
    // Each impossible value is reported at its own element: (parameters, the error's start).
    let cases = [
        (
            r#"<float name="exponent" value="2e6"/>"#,
            "dir/test.xml:3:3: <float name=\"exponent\">: invalid material: exponent = 2000000 exceeds",
        ),
        (
            r#"<float name="exponent" value="-1"/>"#,
            "dir/test.xml:3:3: <float name=\"exponent\">: invalid material: exponent must not be negative",
        ),
        (
            r#"<rgb name="specularReflectance" value="0.1, -0.1, 0.1"/>"#,
            "dir/test.xml:3:3: <rgb name=\"specularReflectance\">: invalid material: ks must not be negative",
        ),
        (
            r#"<rgb name="diffuseReflectance" value="-0.1"/>"#,
            "dir/test.xml:3:3: <rgb name=\"diffuseReflectance\">: invalid material: kd must not be negative",
        ),
    ];
    for (body, want) in cases {
        let e = at(body);
        assert!(e.starts_with(want), "{body}\n→ {e}\nwant {want}");
    }
    // Its colours may be textures (crates/io/tests/it/mitsuba_textures.rs), read with their rules.
    let e = at(r#"<texture type="bitmap" name="diffuseReflectance"/>"#);
    assert!(e.contains("missing <string name=\"filename\""), "{e}");
    let e = at(r#"<string name="exponent" value="30"/>"#);
    assert!(e.contains("wrong property type"), "{e}");
    // Mitsuba 3 spellings are not Mitsuba 0.6's: a warning, not silently right.
    let s = scene(
        r#"<bsdf type="phong" id="p"><float name="diffuse_reflectance" value="0.1"/></bsdf>
                         <shape type="rectangle"><ref id="p"/></shape>"#,
    );
    assert!(
        s.warnings.iter().any(|w| w.contains("`diffuse_reflectance` is not supported")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn conductor_and_dielectric_bsdfs_follow_mitsuba_3() {
    let s = scene(
        r#"<shape type="rectangle"><bsdf type="conductor"/></shape>
               <shape type="rectangle"><bsdf type="twosided"><bsdf type="conductor">
                 <rgb name="specular_reflectance" value="0.9, 0.8, 0.7"/>
                 <rgb name="eta" value="0.2, 0.4, 1.4"/><rgb name="k" value="4, 2.4, 1.6"/></bsdf></bsdf></shape>
               <shape type="rectangle"><bsdf type="dielectric"/></shape>
               <shape type="rectangle"><bsdf type="dielectric">
                 <string name="int_ior" value="water"/><float name="ext_ior" value="1"/>
                 <float name="specular_reflectance" value="0.5"/></bsdf></shape>
               <shape type="rectangle"><bsdf type="roughconductor">
                 <string name="distribution" value="ggx"/><float name="alpha" value="0.3"/></bsdf></shape>
               <shape type="rectangle"><bsdf type="roughdielectric">
                 <string name="distribution" value="ggx"/><float name="alpha_u" value="0.2"/>
                 <float name="alpha_v" value="0.2"/><boolean name="sample_visible" value="true"/></bsdf></shape>
               <shape type="rectangle"><bsdf type="roughconductor"/></shape>
               <shape type="rectangle"><bsdf type="roughdielectric">
                 <string name="distribution" value="GGX"/><float name="alpha_u" value="0.05"/>
                 <float name="alpha_v" value="0.4"/></bsdf></shape>"#,
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let d = &s.description;
    let m = |i: usize| &d.materials[d.meshes[i].material];
    assert_eq!(m(0).bsdf, Bsdf::SmoothConductor(SmoothConductor::new(Rgb::ONE, None).unwrap()));
    assert!(!m(0).two_sided && m(1).two_sided);
    let gold = (Rgb::new(0.2, 0.4, 1.4), Rgb::new(4.0, 2.4, 1.6));
    assert_eq!(
        m(1).bsdf,
        Bsdf::SmoothConductor(SmoothConductor::new(Rgb::new(0.9, 0.8, 0.7), Some(gold)).unwrap())
    );
    let glass = SmoothDielectric::new(1.5046, 1.000277, Rgb::ONE, Rgb::ONE).unwrap();
    assert_eq!(m(2).bsdf, Bsdf::SmoothDielectric(glass));
    let water = SmoothDielectric::new(1.333, 1.0, Rgb::splat(0.5), Rgb::ONE).unwrap();
    assert_eq!(m(3).bsdf, Bsdf::SmoothDielectric(water));
    assert_eq!(m(4).bsdf, Bsdf::RoughConductor(RoughConductor::new(0.3, Rgb::ONE, None).unwrap()));
    let rough = RoughDielectric::new(1.5046, 1.000277, 0.2, Rgb::ONE, Rgb::ONE).unwrap();
    assert_eq!(m(5).bsdf, Bsdf::RoughDielectric(rough.clone()));
    // Mitsuba's defaults: Beckmann, α = 0.1; anisotropic α along the frame's axes.
    let beckmann = RoughConductor::with_microfacet(Microfacet::beckmann(0.1), Rgb::ONE, None).unwrap();
    assert_eq!(m(6).bsdf, Bsdf::RoughConductor(beckmann));
    let aniso = rough.with_microfacet(Microfacet::anisotropic(Distribution::Ggx, 0.05, 0.4)).unwrap();
    assert_eq!(m(7).bsdf, Bsdf::RoughDielectric(aniso));
}

#[test]
fn named_conductors_are_mitsubas_rgb_values() {
    // The values Mitsuba 3.9's scalar_rgb `conductor` plugin reports for these materials.
    for (name, eta, k) in [
        ("Au", Rgb::new(0.143036, 0.375307, 1.44205), Rgb::new(3.983, 2.38556, 1.60336)),
        ("Cu", Rgb::new(0.201005, 0.923749, 1.10221), Rgb::new(3.91326, 2.45304, 2.14209)),
    ] {
        for ty in ["conductor", "roughconductor"] {
            let s = scene(&format!(
                r#"<shape type="cube"><bsdf type="{ty}"><string name="material" value="{name}"/></bsdf></shape>"#
            ));
            let ior = match &s.description.materials[0].bsdf {
                Bsdf::SmoothConductor(c) => c.ior,
                Bsdf::RoughConductor(c) => c.ior,
                b => panic!("{b:?}"),
            };
            let (e, kk) = ior.unwrap();
            let near = |a: Vec3, b: Vec3| (a - b).abs().max_element() <= 1e-4 * b.max_element();
            assert!(near(e, eta) && near(kk, k), "{name}: {e} {kk}");
        }
    }
}

#[test]
fn plastic_takes_mitsubas_parameters() {
    let s = scene(
        r#"<shape type="cube"><bsdf type="plastic"/></shape>
           <shape type="cube"><bsdf type="plastic"><rgb name="diffuse_reflectance" value="0.2, 0.4, 0.6"/>
             <string name="int_ior" value="bk7"/><float name="ext_ior" value="1.2"/>
             <boolean name="nonlinear" value="true"/><rgb name="specular_reflectance" value="0.5"/></bsdf></shape>"#,
    );
    let p = |i: usize| match &s.description.materials[i].bsdf {
        Bsdf::Plastic(p) => p.clone(),
        b => panic!("{b:?}"),
    };
    let (a, b) = (p(0), p(1));
    assert!(!s.description.materials[0].two_sided);
    assert_eq!(
        (a.diffuse_reflectance, a.specular_reflectance, a.nonlinear),
        (Rgb::splat(0.5), Rgb::ONE, false)
    );
    assert!((a.eta - 1.49 / 1.000277).abs() < 1e-6);
    assert_eq!(
        (b.diffuse_reflectance, b.specular_reflectance, b.nonlinear),
        (Rgb::new(0.2, 0.4, 0.6), Rgb::splat(0.5), true)
    );
    assert!((b.eta - 1.5046 / 1.2).abs() < 1e-6);
    let e = err(
        r#"<shape type="cube"><bsdf type="plastic"><rgb name="diffuse_reflectance" value="1.5"/></bsdf></shape>"#,
    );
    assert!(
        e.contains("<rgb name=\"diffuse_reflectance\">: invalid material: diffuse_reflectance exceeds 1"),
        "{e}"
    );
}

#[test]
fn roughplastic_takes_mitsubas_parameters() {
    let s = scene(
        r#"<shape type="cube"><bsdf type="roughplastic"/></shape>
           <shape type="cube"><bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="0.2, 0.4, 0.6"/>
             <string name="int_ior" value="bk7"/><float name="ext_ior" value="1.2"/>
             <string name="distribution" value="ggx"/><float name="alpha" value="0.3"/>
             <boolean name="sample_visible" value="false"/>
             <boolean name="nonlinear" value="true"/><rgb name="specular_reflectance" value="0.5"/></bsdf></shape>"#,
    );
    let p = |i: usize| match &s.description.materials[i].bsdf {
        Bsdf::RoughPlastic(p) => p.clone(),
        b => panic!("{b:?}"),
    };
    let (a, b) = (p(0), p(1));
    assert!(!s.description.materials[0].two_sided);
    assert_eq!(
        (a.diffuse_reflectance, a.specular_reflectance, a.microfacet, a.sample_visible, a.nonlinear),
        (Rgb::splat(0.5), Rgb::ONE, Microfacet::beckmann(0.1), true, false)
    );
    assert!((a.eta - 1.49 / 1.000277).abs() < 1e-6);
    assert_eq!(
        (b.diffuse_reflectance, b.specular_reflectance, b.microfacet, b.sample_visible, b.nonlinear),
        (Rgb::new(0.2, 0.4, 0.6), Rgb::splat(0.5), Microfacet::ggx(0.3), false, true)
    );
    assert!((b.eta - 1.5046 / 1.2).abs() < 1e-6);
    for (xml, want) in [
        (
            r#"<rgb name="diffuse_reflectance" value="1.5"/>"#,
            "dir/test.xml:2:46: <rgb name=\"diffuse_reflectance\">: invalid material: diffuse_reflectance exceeds 1",
        ),
        (
            r#"<float name="alpha" value="0"/>"#,
            "dir/test.xml:2:46: <float name=\"alpha\">: invalid material: alpha must be positive",
        ),
        (
            r#"<float name="int_ior" value="1.2"/><float name="ext_ior" value="1.2"/>"#,
            "dir/test.xml:2:20: <bsdf type=\"roughplastic\">: invalid material: int_ior = ext_ior = 1.2",
        ),
        (
            r#"<float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.2"/>"#,
            "dir/test.xml:2:46: <float name=\"alpha_u\">: roughplastic is isotropic in Mitsuba 3",
        ),
        (
            r#"<string name="distribution" value="phong"/>"#,
            "dir/test.xml:2:46: <string name=\"distribution\">: unknown microfacet distribution \"phong\"",
        ),
    ] {
        let e = err(&format!(r#"<shape type="cube"><bsdf type="roughplastic">{xml}</bsdf></shape>"#));
        assert!(e.contains(want), "{e}\nwanted: {want}");
    }
    // Equal alphas are isotropic.
    let s = scene(
        r#"<shape type="cube"><bsdf type="roughplastic"><float name="alpha_u" value="0.2"/>
           <float name="alpha_v" value="0.2"/></bsdf></shape>"#,
    );
    assert!(
        matches!(&s.description.materials[0].bsdf, Bsdf::RoughPlastic(p) if p.microfacet == Microfacet::beckmann(0.2))
    );
}

#[test]
fn blendbsdf_blends_two_nested_bsdfs() {
    let s = scene(
        r#"<bsdf type="conductor" id="metal"/>
           <shape type="cube"><bsdf type="blendbsdf"><float name="weight" value="0.25"/>
             <bsdf type="diffuse"><rgb name="reflectance" value="0.2"/></bsdf><ref id="metal"/></bsdf></shape>
           <shape type="cube"><bsdf type="twosided"><bsdf type="blendbsdf"><float name="weight" value="1"/>
             <bsdf type="diffuse"/><bsdf type="roughplastic"/></bsdf></bsdf></shape>"#,
    );
    let m = &s.description.materials;
    let Bsdf::Blend(b) = &m[0].bsdf else { panic!("{:?}", m[0].bsdf) };
    assert_eq!(b.weight, 0.25);
    assert!(matches!(b.bsdfs[0], Bsdf::Lambert(ref l) if l.reflectance == Rgb::splat(0.2)));
    assert!(matches!(b.bsdfs[1], Bsdf::SmoothConductor(_)));
    assert!(!m[0].two_sided && m[1].two_sided);
    assert!(matches!(&m[1].bsdf, Bsdf::Blend(b) if matches!(b.bsdfs[1], Bsdf::RoughPlastic(_))));
    for (xml, want) in [
        (
            r#"<bsdf type="diffuse"/><bsdf type="diffuse"/>"#,
            "dir/test.xml:2:20: <bsdf type=\"blendbsdf\">: a blendbsdf needs its weight",
        ),
        (
            r#"<float name="weight" value="1.5"/><bsdf type="diffuse"/><bsdf type="diffuse"/>"#,
            "dir/test.xml:2:43: <float name=\"weight\">: invalid material: weight exceeds 1",
        ),
        (
            r#"<float name="weight" value="0.5"/><bsdf type="diffuse"/>"#,
            "dir/test.xml:2:20: <bsdf type=\"blendbsdf\">: a blendbsdf blends exactly two nested BSDFs (given 1)",
        ),
        (
            r#"<float name="weight" value="0.5"/><bsdf type="diffuse"/><bsdf type="diffuse"/><bsdf type="diffuse"/>"#,
            "dir/test.xml:2:121: <bsdf type=\"diffuse\">: a blendbsdf blends exactly two nested BSDFs (given 3)",
        ),
        (
            r#"<float name="weight" value="0.5"/><bsdf type="diffuse"/><bsdf type="dielectric"/>"#,
            "dir/test.xml:2:20: <bsdf type=\"blendbsdf\">: invalid material: a blend of a dielectric",
        ),
        (
            r#"<float name="weight" value="0.5"/><bsdf type="conductor"/><bsdf type="plastic"/>"#,
            "invalid material: a blend of two BSDFs that both have delta lobes is not supported",
        ),
        (
            r#"<texture type="checkerboard" name="weight"><rgb name="color0" value="1.5"/></texture><bsdf type="diffuse"/><bsdf type="diffuse"/>"#,
            "dir/test.xml:2:43: <texture type=\"checkerboard\" name=\"weight\">: weight must lie in [0, 1]",
        ),
        (
            r#"<float name="weight" value="0.5"/><bsdf type="diffuse"><texture type="checkerboard" name="reflectance"/></bsdf><bsdf type="diffuse"/>"#,
            "dir/test.xml:2:77: <bsdf type=\"diffuse\">: textures inside a blendbsdf are not supported yet",
        ),
        (
            r#"<float name="weight" value="0.5"/><bsdf type="diffuse"/><bsdf type="twosided"><bsdf type="diffuse"/></bsdf>"#,
            "a blendbsdf of a twosided and a one-sided BSDF is not supported",
        ),
    ] {
        let e = err(&format!(r#"<shape type="cube"><bsdf type="blendbsdf">{xml}</bsdf></shape>"#));
        assert!(e.contains(want), "{e}\nwanted: {want}");
    }
}

#[test]
fn interior_media_make_absorbing_glass() {
    let s = scene(
        r#"<medium type="homogeneous" id="ink"><float name="albedo" value="0"/>
                 <rgb name="sigma_t" value="1, 2, 3"/><float name="scale" value="0.5"/>
                 <phase type="isotropic"/></medium>
               <bsdf type="dielectric" id="glass"/>
               <shape type="cube"><ref id="glass"/><ref name="interior" id="ink"/></shape>
               <shape type="cube"><ref name="interior" id="ink"/><ref id="glass"/></shape>
               <shape type="cube"><bsdf type="roughdielectric"><string name="distribution" value="ggx"/></bsdf>
                 <medium name="interior" type="homogeneous"><rgb name="albedo" value="0, 0, 0"/></medium></shape>
               <shape type="cube"><ref id="glass"/></shape>"#,
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let d = &s.description;
    let m = |i: usize| &d.materials[d.meshes[i].material];
    assert_eq!(m(0).bsdf.absorption(), Rgb::new(0.5, 1.0, 1.5));
    assert_eq!(m(0).name, "glass+ink");
    assert_eq!(d.meshes[0].material, d.meshes[1].material, "the same glass and ink share a material");
    assert_eq!(m(2).bsdf.absorption(), Rgb::ONE);
    assert!(matches!(m(2).bsdf, Bsdf::RoughDielectric(_)));
    assert_eq!(m(3).bsdf.absorption(), Rgb::ZERO);
}

#[test]
fn unsupported_media_are_located_errors() {
    let ink = |params: &str| {
        format!(
            "<bsdf type=\"dielectric\" id=\"g\"/>\n<medium type=\"homogeneous\" id=\"m\">\n  {params}</medium>\n\
                 <shape type=\"cube\"><ref id=\"g\"/><ref name=\"interior\" id=\"m\"/></shape>"
        )
    };
    let cases = [
            (ink(r#"<float name="albedo" value="0.5"/>"#), "dir/test.xml:4:3: <float name=\"albedo\">: a scattering medium"),
            (ink(""), "dir/test.xml:3:1: <medium type=\"homogeneous\" id=\"m\">: a homogeneous medium scatters by default"),
            (
                ink(r#"<float name="albedo" value="0"/><float name="scale" value="-1"/>"#),
                "dir/test.xml:4:35: <float name=\"scale\">: invalid material: absorption must not be negative",
            ),
            (
                ink(r#"<float name="albedo" value="0"/><float name="sigma_t" value="nan"/>"#),
                "dir/test.xml:4:64: <float name=\"sigma_t\">: attribute `value`: \"nan\" is not a finite number",
            ),
            (
                "<shape type=\"cube\"><medium name=\"interior\" type=\"heterogeneous\"/></shape>".into(),
                "unsupported medium type \"heterogeneous\"",
            ),
            (
                "<shape type=\"cube\"><medium name=\"interior\" type=\"homogeneous\"><float name=\"albedo\" value=\"0\"/></medium></shape>"
                    .into(),
                "needs a dielectric BSDF on the shape (this shape has none)",
            ),
            (
                "<shape type=\"cube\"><bsdf type=\"diffuse\"/>\n<medium name=\"interior\" type=\"homogeneous\"><float name=\"albedo\" value=\"0\"/></medium></shape>"
                    .into(),
                "dir/test.xml:3:1: <medium type=\"homogeneous\" name=\"interior\">: an interior medium needs a dielectric BSDF",
            ),
            (
                "<shape type=\"cube\"><ref name=\"exterior\" id=\"x\"/></shape>".into(),
                "exterior media are not supported",
            ),
        ];
    for (body, expected) in cases {
        let e = err(&body);
        assert!(e.contains(expected), "{e}\nexpected: {expected}\n{body}");
    }
}

#[test]
fn impossible_specular_parameters_are_located() {
    let cases: &[(&str, &str)] = &[
        (
            "<bsdf type=\"dielectric\">\n  <float name=\"int_ior\" value=\"-1\"/></bsdf>",
            "dir/test.xml:3:3: <float name=\"int_ior\">: invalid material: int_ior must be positive",
        ),
        (
            "<bsdf type=\"dielectric\">\n  <string name=\"ext_ior\" value=\"unobtainium\"/></bsdf>",
            "dir/test.xml:3:33: <string name=\"ext_ior\">: unknown index of refraction \"unobtainium\" (known: vacuum,",
        ),
        (
            "<bsdf type=\"dielectric\">\n  <rgb name=\"specular_transmittance\" value=\"1, 1.1, 1\"/></bsdf>",
            "dir/test.xml:3:3: <rgb name=\"specular_transmittance\">: invalid material: specular_transmittance exceeds 1",
        ),
        (
            "<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/>\n  <float name=\"alpha\" value=\"0\"/></bsdf>",
            "dir/test.xml:3:3: <float name=\"alpha\">: invalid material: alpha must be positive",
        ),
        (
            "<bsdf type=\"roughdielectric\"><string name=\"distribution\" value=\"ggx\"/>\n  <float name=\"alpha\" value=\"3\"/></bsdf>",
            "dir/test.xml:3:3: <float name=\"alpha\">: invalid material: alpha = 3 exceeds the supported maximum 1",
        ),
        (
            "<bsdf type=\"roughconductor\">\n  <string name=\"distribution\" value=\"phong\"/></bsdf>",
            "dir/test.xml:3:3: <string name=\"distribution\">: unknown microfacet distribution \"phong\" (known: beckmann, ggx)",
        ),
        (
            "<bsdf type=\"roughconductor\"><float name=\"alpha\" value=\"0.1\"/>\n  <float name=\"alpha_v\" value=\"0.2\"/></bsdf>",
            "dir/test.xml:3:3: <float name=\"alpha_v\">: give either alpha or alpha_u and alpha_v, not both",
        ),
        (
            "<bsdf type=\"roughdielectric\">\n  <float name=\"alpha_u\" value=\"0.2\"/></bsdf>",
            "dir/test.xml:3:3: <float name=\"alpha_u\">: alpha_u and alpha_v must be given together",
        ),
        (
            "<bsdf type=\"roughdielectric\"><float name=\"alpha_u\" value=\"0.2\"/>\n  <float name=\"alpha_v\" value=\"-1\"/></bsdf>",
            "dir/test.xml:3:3: <float name=\"alpha_v\">: invalid material: alpha_v must be positive",
        ),
        (
            "<bsdf type=\"conductor\"><string name=\"material\" value=\"Gold\"/></bsdf>",
            "dir/test.xml:2:55: <string name=\"material\">: unknown conductor \"Gold\" (known: none, Ag, Al,",
        ),
        (
            "<bsdf type=\"conductor\"><string name=\"material\" value=\"Au\"/>\n <rgb name=\"k\" value=\"1\"/></bsdf>",
            "dir/test.xml:3:2: <rgb name=\"k\">: give either `material` or `eta` and `k`, not both",
        ),
        ("<bsdf type=\"conductor\">\n <rgb name=\"eta\" value=\"nan\"/></bsdf>", "not a finite number"),
        ("<bsdf type=\"twosided\"><bsdf type=\"dielectric\"/></bsdf>", "already scatters on both faces"),
        (
            "<bsdf type=\"roughdielectric\"><string name=\"distribution\" value=\"ggx\"/><float name=\"int_ior\" value=\"1\"/><float name=\"ext_ior\" value=\"1\"/></bsdf>",
            "a rough interface needs different indices",
        ),
    ];
    for (body, want) in cases {
        let e = err(body);
        assert!(e.contains(want), "{body}\n→ {e}\nwant {want}");
    }
}

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

/// A folder of its own for files a test writes.
fn opticks_io_test_folder(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("opticks-mitsuba-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn ignored_features_are_warnings() {
    let s = scene(
        r#"<integrator type="path"><integer name="max_depth" value="5"/></integrator>
               <sensor type="perspective"><float name="fov" value="45"/><float name="near_clip" value="0.1"/>
                 <film type="hdrfilm"></film></sensor>
               <shape type="rectangle"><float name="bogus" value="1"/></shape>"#,
    );
    let w = s.warnings.join("\n");
    assert_eq!(s.warnings.len(), 3, "{w}");
    assert!(w.contains("dir/test.xml:2:25: <integer name=\"max_depth\">: max_depth = 5 is ignored"), "{w}");
    assert!(w.contains("<film type=\"hdrfilm\">: no <rfilter>: Opticks uses the box filter"), "{w}");
    assert!(w.contains("<float name=\"bogus\">: parameter `bogus` is not supported"), "{w}");
}

/// Issue 12: the film's crop window and filter reach the camera (no warnings).
#[test]
fn crop_and_filters_are_read() {
    let s = scene(
        r#"<sensor type="perspective"><float name="fov" value="45"/>
                 <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="30"/>
                   <integer name="crop_offset_x" value="2"/><integer name="crop_offset_y" value="3"/>
                   <integer name="crop_width" value="10"/><integer name="crop_height" value="20"/>
                   <rfilter type="gaussian"><float name="stddev" value="0.7"/></rfilter></film></sensor>
               <shape type="rectangle"/>"#,
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let c = s.description.camera.unwrap();
    assert_eq!((c.width, c.height), (40, 30));
    let crop = opticks_core::sensor::Crop { x: 2, y: 3, width: 10, height: 20 };
    assert_eq!(c.film.crop, Some(crop));
    assert_eq!(c.film.filter, opticks_core::sensor::Filter::Gaussian { stddev: 0.7 });
    let tent = scene(
        r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="tent"/></film></sensor>
               <shape type="rectangle"/>"#,
    );
    let c = tent.description.camera.unwrap();
    assert_eq!((c.film.crop, c.film.filter), (None, opticks_core::sensor::Filter::Tent { radius: 1.0 }));
}

#[test]
fn bad_scenes_name_file_line_and_element() {
    let cases: &[(&str, &str)] = &[
        (
            r#"<bsdf type="hair" id="p"/>"#,
            "dir/test.xml:2:13: <bsdf type=\"hair\" id=\"p\">: unsupported BSDF type \"hair\" (supported: diffuse, phong (Opticks extension), twosided, conductor, roughconductor, dielectric, roughdielectric, thindielectric, plastic, roughplastic, blendbsdf, mask, normalmap, bumpmap, principled)",
        ),
        (
            r#"<shape type="teapot"/>"#,
            "dir/test.xml:2:14: <shape type=\"teapot\">: unsupported shape type \"teapot\" (supported: obj, ply, serialized, rectangle, cube, sphere, disk, cylinder)",
        ),
        (r#"<alias id="a"/>"#, "dir/test.xml:2:1: <alias id=\"a\">: unsupported element <alias>"),
        (r#"<emitter type="sunsky"/>"#, "unsupported emitter type \"sunsky\""),
        (r#"<emitter type="area"/>"#, "must be nested inside a <shape>"),
        (
            "<shape type=\"rectangle\">\n<ref id=\"nope\"/></shape>\n<bsdf type=\"diffuse\" id=\"yes\"/>",
            "dir/test.xml:3:10: <ref id=\"nope\">: reference to unknown id \"nope\" (BSDF ids in this file: yes)",
        ),
        (
            "<shape type=\"rectangle\" id=\"s\"/>\n<shape type=\"rectangle\"><ref id=\"s\"/></shape>",
            "id \"s\" is a <shape> (at dir/test.xml:2:1), not a <bsdf>",
        ),
        (
            "<bsdf type=\"diffuse\" id=\"x\"/><bsdf type=\"diffuse\" id=\"x\"/>",
            "duplicate id \"x\" (first declared at dir/test.xml:2:1)",
        ),
        (
            "<bsdf type=\"diffuse\">\n  <rgb name=\"reflectance\" value=\"0.5, 1.2, 0.5\"/></bsdf>",
            "dir/test.xml:3:3: <rgb name=\"reflectance\">: invalid material:",
        ),
        ("<bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"-0.1\"/></bsdf>", "must not be negative"),
        (
            "<shape type=\"rectangle\"><transform name=\"to_world\">\n<translate x=\"1\" y=\"nan\"/></transform></shape>",
            "dir/test.xml:3:21: <translate>: attribute `y`: \"nan\" is not a finite number",
        ),
        (
            "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"1e400\"/></transform></shape>",
            "not a finite number",
        ),
        (
            "<shape type=\"rectangle\"><transform name=\"to_world\"><shear/></transform></shape>",
            "unsupported transform element <shear>",
        ),
        (
            "<shape type=\"rectangle\"><transform name=\"to_world\"><matrix value=\"1 2 3\"/></transform></shape>",
            "a matrix needs 16 numbers",
        ),
        (
            "<shape type=\"rectangle\"><transform name=\"to_world\"><lookat origin=\"0,0,0\" target=\"0,1,0\" up=\"0,1,0\"/></transform></shape>",
            "parallel",
        ),
        ("<bsdf type=\"twosided\" id=\"t\"><ref id=\"t\"/></bsdf>", "refers to itself"),
        (
            "<bsdf type=\"twosided\"><bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/></bsdf>",
            "different front and back",
        ),
        (
            "<sensor type=\"fisheye\"/>",
            "unsupported sensor type \"fisheye\" (supported: perspective, thinlens, orthographic)",
        ),
        ("<sensor type=\"perspective\"><float name=\"fov\" value=\"180\"/></sensor>", "outside (0°, 180°)"),
        (
            "<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/><string name=\"fov_axis\" value=\"z\"/></sensor>",
            "unsupported fov_axis \"z\"",
        ),
        (
            "<sensor type=\"perspective\"><film type=\"hdrfilm\"><integer name=\"width\" value=\"0\"/></film></sensor>",
            "width 0 must be an integer from 1 to 32768",
        ),
        ("<shape type=\"obj\"/>", "missing <string name=\"filename\""),
        (
            "<shape type=\"rectangle\"><string name=\"flip_normals\" value=\"true\"/></shape>",
            "wrong property type: expected <boolean>",
        ),
        (
            "<shape type=\"rectangle\"><float name=\"a\" value=\"1\"/><float name=\"a\" value=\"1\"/></shape>",
            "given twice",
        ),
    ];
    for (body, expect) in cases {
        let e = err(body);
        assert!(e.contains(expect), "error for {body}\n  was: {e}\n  expected: {expect}");
        assert!(e.starts_with("dir/test.xml:"), "{e}");
    }
}

#[test]
fn malformed_xml_and_missing_root_attributes() {
    let e = load_str("<scene version=\"3.0.0\">\n  <shape type=\"rectangle\">\n</scene>").unwrap_err();
    assert!(matches!(e, SceneFileError::Xml { .. }));
    assert!(e.to_string().starts_with("dir/test.xml:3:"), "{e}");
    let e = load_str("<scene version=\"3.0.0\">\n  <shape type=\"rectangle\"/>\n").unwrap_err().to_string();
    assert!(e.starts_with("dir/test.xml:3:") && e.contains("malformed XML"), "{e}");
    let e = load_str("<scene>\n</scene>").unwrap_err().to_string();
    assert!(e.contains("missing `version`"), "{e}");
    let e = load_str("<scene version=\"0.6.0\">\n</scene>").unwrap_err().to_string();
    assert!(e.contains("Mitsuba 0.x"), "{e}");
    let e = load_str("<world version=\"3.0.0\"/>").unwrap_err().to_string();
    assert!(e.contains("root element must be <scene"), "{e}");
}

#[test]
fn references_reach_emitters_and_samplers() {
    let s = scene(
        r#"<emitter type="area" id="glow"><rgb name="radiance" value="2"/></emitter>
           <sampler type="independent" id="smp"><integer name="sample_count" value="4"/></sampler>
           <sensor type="perspective"><float name="fov" value="40"/><ref id="smp"/></sensor>
           <shape type="rectangle"><ref id="glow"/></shape>"#,
    );
    assert!(s.warnings.iter().all(|w| !w.contains("never used")), "{:?}", s.warnings);
    let m = &s.description.meshes[0];
    assert_eq!(m.emission.as_ref().unwrap().radiance, Rgb::splat(2.0));
    assert!(err(r#"<emitter type="area"/>"#).contains("must be nested inside a <shape> (or have an id"));
    let e = err(r#"<bsdf type="diffuse" id="b"/><sensor type="perspective"><ref id="b"/></sensor>"#);
    assert!(e.contains("may name a <sampler>; this one names a <bsdf>"), "{e}");
}
