//! Mitsuba's `principledthin` BSDF through the loader: Mitsuba's defaults, every parameter read
//! under its name (floats and textures; `diff_trans` in [0, 2]), the sheet scattering from both
//! faces, and the located errors of bad or unsupported input. The rendered result against
//! Mitsuba is `crates/cli/tests/it/mitsuba_scenes.rs` (`principledthin`).

use opticks_core::bsdf::{Bsdf, PrincipledThin};
use opticks_core::math::Rgb;
use opticks_core::texture::{ColourSlot, PrincipledWeight};
use opticks_io::{LoadedScene, SceneFileError};

fn load(body: &str) -> Result<LoadedScene, SceneFileError> {
    crate::mitsuba_fragment::load_in("principledthin", body)
}

fn err(body: &str) -> String {
    crate::mitsuba_fragment::err_in("principledthin", body)
}

/// The thin principled BSDF of a rectangle whose `<bsdf>` holds `inner` (the element is on
/// line 2).
fn shape(inner: &str) -> String {
    format!("<shape type=\"rectangle\">\n<bsdf type=\"principledthin\">{inner}</bsdf></shape>")
}

fn thin(body: &str) -> PrincipledThin {
    match crate::mitsuba_fragment::first_bsdf("principledthin", body) {
        Bsdf::PrincipledThin(p) => p,
        other => panic!("{other:?}"),
    }
}

#[test]
fn defaults_are_mitsubas_and_both_faces_scatter() {
    let p = thin(&shape(""));
    assert_eq!(p, PrincipledThin::default());
    assert_eq!((p.base_color, p.roughness, p.eta, p.diff_trans), (Rgb::splat(0.5), 0.5, 1.5, 0.0));
    assert!(Bsdf::PrincipledThin(p).transmits(), "a sheet: oriented by nothing, both faces");
}

#[test]
fn every_parameter_is_read_under_its_name() {
    let p = thin(&shape(
        r#"<rgb name="base_color" value="0.2, 0.8, 0.1"/>
        <float name="roughness" value="0.15"/><float name="anisotropic" value="0.3"/>
        <float name="spec_trans" value="0.7"/><float name="eta" value="1.33"/>
        <float name="spec_tint" value="0.4"/><float name="sheen" value="0.6"/>
        <float name="sheen_tint" value="0.2"/><float name="flatness" value="0.25"/>
        <float name="diff_trans" value="1.6"/>
        <float name="specular_reflectance_sampling_rate" value="0.5"/>
        <float name="specular_transmittance_sampling_rate" value="2"/>
        <float name="diffuse_reflectance_sampling_rate" value="3"/>
        <float name="diffuse_transmittance_sampling_rate" value="4"/>"#,
    ));
    let want = PrincipledThin {
        base_color: Rgb::new(0.2, 0.8, 0.1),
        roughness: 0.15,
        anisotropic: 0.3,
        spec_trans: 0.7,
        eta: 1.33,
        spec_tint: 0.4,
        sheen: 0.6,
        sheen_tint: 0.2,
        flatness: 0.25,
        diff_trans: 1.6,
        spec_reflect_rate: 0.5,
        spec_trans_rate: 2.0,
        diffuse_reflect_rate: 3.0,
        diffuse_trans_rate: 4.0,
    };
    assert_eq!(p, want);
}

/// Each weight and the base colour may be a texture (`diff_trans`'s values up to 2), and the
/// scene builds with them.
#[test]
fn textures_bind_each_weight_and_the_base_colour() {
    let checker = |name: &str, hi: f32| {
        format!(
            r#"<texture type="checkerboard" name="{name}"><float name="color0" value="0.05"/>
            <float name="color1" value="{hi}"/></texture>"#
        )
    };
    let mut inner: String = PrincipledWeight::THIN.iter().map(|w| checker(w.name(), 0.8 * w.max())).collect();
    inner.push_str(&checker("base_color", 0.8));
    let light =
        r#"<shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>"#;
    let loaded = load(&format!("{}\n{light}", shape(&inner))).unwrap();
    let d = &loaded.description;
    let mut slots: Vec<ColourSlot> = d.textures.iter().map(|t| t.slot).collect();
    slots.sort_by_key(|s| s.name());
    let mut want: Vec<ColourSlot> = PrincipledWeight::THIN.map(ColourSlot::Principled).to_vec();
    want.push(ColourSlot::BaseColor);
    want.sort_by_key(|s| s.name());
    assert_eq!(slots, want);
    let Bsdf::PrincipledThin(p) = &d.materials[0].bsdf else { panic!() };
    assert_eq!(p.diff_trans, 1.6, "the texture's largest value");
    opticks_core::scene::Scene::build(d).unwrap();
}

#[test]
fn bad_and_unsupported_values_are_located_errors() {
    let e = err(&shape("\n<float name=\"spec_trans\" value=\"1.5\"/>"));
    assert!(e.contains("spec_trans = 1.5 is not in [0, 1]") && e.contains("test.xml:4:"), "{e}");
    let e = err(&shape("\n<float name=\"diff_trans\" value=\"2.5\"/>"));
    assert!(
        e.contains("diff_trans = 2.5 exceeds the supported maximum 2") && e.contains("test.xml:4:"),
        "{e}"
    );
    let e = err(&shape(
        r#"<texture type="checkerboard" name="diff_trans"><float name="color0" value="2.3"/></texture>"#,
    ));
    assert!(e.contains("diff_trans must lie in [0, 2]") && e.contains("test.xml:3:"), "{e}");
    let e = err(&shape(
        r#"<texture type="checkerboard" name="sheen"><float name="color0" value="1.3"/></texture>"#,
    ));
    assert!(e.contains("sheen must lie in [0, 1]") && e.contains("test.xml:3:"), "{e}");
    let e = err(&shape("\n<float name=\"eta\" value=\"-1\"/>"));
    assert!(e.contains("eta must be positive") && e.contains("test.xml:4:"), "{e}");
    let e = err(&shape("\n<rgb name=\"base_color\" value=\"1.2, 0.5, 0.5\"/>"));
    assert!(e.contains("base_color") && e.contains("exceeds 1") && e.contains("test.xml:4:"), "{e}");
    let e = err(&shape(r#"<texture type="checkerboard" name="metallic"/>"#));
    assert!(e.contains("unsupported element inside <bsdf type=\"principledthin\">"), "{e}");
}
