//! The Mitsuba 3 XML loader, element by element, through its public API
//! ([`opticks_io::scene_formats::mitsuba::parse`]): transforms, each BSDF, shapes and their
//! normals, interior media, parameters, warnings, and the located errors of broken scenes.
//! Sensors and films are in `mitsuba_sensors.rs`, emitters in `mitsuba_emitters.rs`. Scenes read
//! from files (the reference scenes, OBJ meshes next to the XML) are in `scene_loading.rs`; the
//! light extensions' physics in `crates/cli/tests/it/lights.rs`.

use opticks_core::bsdf::{Bsdf, RoughConductor, RoughDielectric, SmoothConductor, SmoothDielectric};
use opticks_core::math::{Rgb, Vec3};
use opticks_core::sampling::microfacet::{Distribution, Microfacet};
use opticks_core::scene::MeshDesc;
use opticks_io::scene_formats::mitsuba::parse;
use opticks_io::{LoadOptions, LoadedScene, SceneFileError};
use std::path::Path;

pub(crate) fn load_str(xml: &str) -> Result<LoadedScene, SceneFileError> {
    parse(xml, Path::new("dir/test.xml"), &LoadOptions::default())
}

pub(crate) fn scene(body: &str) -> LoadedScene {
    let xml = format!("<scene version=\"3.0.0\">\n{body}\n</scene>");
    load_str(&xml).unwrap_or_else(|e| panic!("{e}\n{xml}"))
}

pub(crate) fn err(body: &str) -> String {
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

pub(crate) fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[track_caller]
pub(crate) fn assert_close(a: Vec3, b: Vec3) {
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

#[test]
fn bad_scenes_name_file_line_and_element() {
    let cases: &[(&str, &str)] = &[
        (
            r#"<bsdf type="hair" id="p"/>"#,
            "dir/test.xml:2:13: <bsdf type=\"hair\" id=\"p\">: unsupported BSDF type \"hair\" (supported: diffuse, phong (Opticks extension), twosided, conductor, roughconductor, dielectric, roughdielectric, thindielectric, plastic, roughplastic, blendbsdf, mask, normalmap, bumpmap, principled, principledthin)",
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
