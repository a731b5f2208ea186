//! Mitsuba's `principled` BSDF through the loader: Mitsuba's defaults, every parameter read
//! under its name (floats and textures, `eta` or `specular`), the transmission lobe turned on
//! as Mitsuba turns it on (`spec_trans` a texture or a non-zero float), and the located errors
//! of bad or unsupported input. The rendered result against Mitsuba is
//! `crates/cli/tests/it/mitsuba_scenes.rs` (`principled`, `principled_trans`).

use opticks_core::bsdf::{Bsdf, Principled, eta_of_specular};
use opticks_core::math::Rgb;
use opticks_core::texture::{ColourSlot, PrincipledWeight};
use opticks_io::{LoadedScene, SceneFileError};

fn load(body: &str) -> Result<LoadedScene, SceneFileError> {
    crate::mitsuba_fragment::load_in("principled", body)
}

fn err(body: &str) -> String {
    crate::mitsuba_fragment::err_in("principled", body)
}

/// The principled BSDF of a rectangle whose `<bsdf>` holds `inner` (the element is on line 2).
fn shape(inner: &str) -> String {
    format!("<shape type=\"rectangle\">\n<bsdf type=\"principled\">{inner}</bsdf></shape>")
}

fn principled(body: &str) -> Principled {
    match crate::mitsuba_fragment::first_bsdf("principled", body) {
        Bsdf::Principled(p) => p,
        other => panic!("{other:?}"),
    }
}

#[test]
fn defaults_are_mitsubas() {
    let p = principled(&shape(""));
    assert_eq!(p, Principled::default());
    assert_eq!((p.base_color, p.roughness, p.metallic, p.clearcoat), (Rgb::splat(0.5), 0.5, 0.0, 0.0));
    assert!((p.eta - 1.5).abs() < 1e-6, "specular 0.5: η = 1.5");
    let loaded = load(&shape("")).unwrap();
    assert!(!loaded.description.materials[0].two_sided, "one-sided, as Mitsuba's");
}

#[test]
fn every_parameter_is_read_under_its_name() {
    let p = principled(&shape(
        r#"<rgb name="base_color" value="0.2, 0.8, 0.1"/>
        <float name="roughness" value="0.15"/><float name="anisotropic" value="0.3"/>
        <float name="metallic" value="0.7"/><float name="spec_tint" value="0.4"/>
        <float name="sheen" value="0.6"/><float name="sheen_tint" value="0.2"/>
        <float name="clearcoat" value="0.9"/><float name="clearcoat_gloss" value="0.35"/>
        <float name="flatness" value="0.25"/><float name="spec_trans" value="0"/>
        <float name="specular" value="0.7"/>
        <float name="diffuse_reflectance_sampling_rate" value="0.5"/>
        <float name="main_specular_sampling_rate" value="2"/>
        <float name="clearcoat_sampling_rate" value="3"/>"#,
    ));
    let want = Principled {
        base_color: Rgb::new(0.2, 0.8, 0.1),
        roughness: 0.15,
        anisotropic: 0.3,
        metallic: 0.7,
        spec_tint: 0.4,
        eta: eta_of_specular(0.7),
        sheen: 0.6,
        sheen_tint: 0.2,
        clearcoat: 0.9,
        clearcoat_gloss: 0.35,
        flatness: 0.25,
        diffuse_rate: 0.5,
        specular_rate: 2.0,
        clearcoat_rate: 3.0,
        spec_trans: 0.0,
        has_spec_trans: false,
    };
    assert_eq!(p, want, "spec_trans 0 as a float: no transmission lobe (Mitsuba's get_flag)");
    assert_eq!(principled(&shape(r#"<float name="eta" value="1.33"/>"#)).eta, 1.33);
}

#[test]
fn textures_bind_each_weight_and_the_base_colour() {
    let checker = |name: &str| {
        format!(
            r#"<texture type="checkerboard" name="{name}"><float name="color0" value="0.05"/>
            <float name="color1" value="0.8"/></texture>"#
        )
    };
    let mut inner: String = PrincipledWeight::ALL.iter().map(|w| checker(w.name())).collect();
    inner.push_str(&checker("base_color"));
    let light =
        r#"<shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>"#;
    let loaded = load(&format!("{}\n{light}", shape(&inner))).unwrap();
    let d = &loaded.description;
    let mut slots: Vec<ColourSlot> = d.textures.iter().map(|t| t.slot).collect();
    slots.sort_by_key(|s| s.name());
    let mut want: Vec<ColourSlot> = PrincipledWeight::ALL.map(ColourSlot::Principled).to_vec();
    want.push(ColourSlot::BaseColor);
    want.sort_by_key(|s| s.name());
    assert_eq!(slots, want);
    opticks_core::scene::Scene::build(d).unwrap();
    // A texture given by reference, too.
    let body =
        format!(r#"<texture type="checkerboard" id="c"/>{}"#, shape(r#"<ref name="metallic" id="c"/>"#));
    let loaded = load(&body).unwrap();
    assert_eq!(loaded.description.textures[0].slot, ColourSlot::Principled(PrincipledWeight::Metallic));
}

/// `spec_trans` as Mitsuba reads it: a non-zero float or any texture (even one that is 0
/// everywhere) turns the lobe on, which makes the BSDF transmit (oriented, two-sided) and
/// raises η = 1 to 1.001 and `specular` 0 to 10⁻³; a float 0 leaves it off.
#[test]
fn spec_trans_turns_the_transmission_lobe_on() {
    let p = principled(&shape(r#"<float name="spec_trans" value="0.4"/>"#));
    assert_eq!((p.spec_trans, p.has_spec_trans), (0.4, true));
    assert!(Bsdf::Principled(p).transmits());
    let zero = r#"<texture type="checkerboard" name="spec_trans"><float name="color0" value="0"/>
        <float name="color1" value="0"/></texture>"#;
    let loaded = load(&shape(zero)).unwrap();
    assert_eq!(loaded.description.textures[0].slot, ColourSlot::Principled(PrincipledWeight::SpecTrans));
    let Bsdf::Principled(p) = &loaded.description.materials[0].bsdf else { panic!() };
    assert!(p.has_spec_trans && p.spec_trans == 0.0);
    let p = principled(&shape(r#"<float name="spec_trans" value="1"/><float name="eta" value="1"/>"#));
    assert_eq!(p.eta, 1.001);
    let p = principled(&shape(r#"<float name="spec_trans" value="1"/><float name="specular" value="0"/>"#));
    assert_eq!(p.eta, eta_of_specular(1e-3));
    let p = principled(&shape(r#"<float name="spec_trans" value="0"/><float name="eta" value="1"/>"#));
    assert_eq!((p.eta, p.has_spec_trans), (1.0, false));
}

#[test]
fn bad_and_unsupported_values_are_located_errors() {
    let e = err(&shape("\n<float name=\"spec_trans\" value=\"1.5\"/>"));
    assert!(e.contains("spec_trans = 1.5 is not in [0, 1]") && e.contains("test.xml:4:"), "{e}");
    let e = err(&shape(
        r#"<texture type="checkerboard" name="spec_trans"><float name="color0" value="1.3"/></texture>"#,
    ));
    assert!(e.contains("spec_trans must lie in [0, 1]") && e.contains("test.xml:3:"), "{e}");
    let e = err(&shape(r#"<float name="eta" value="1.4"/><float name="specular" value="0.3"/>"#));
    assert!(e.contains("either eta or specular") && e.contains("test.xml:3:"), "{e}");
    let e = err(&shape("\n<float name=\"metallic\" value=\"1.5\"/>"));
    assert!(e.contains("metallic = 1.5 is not in [0, 1]") && e.contains("test.xml:4:"), "{e}");
    let e = err(&shape("\n<rgb name=\"base_color\" value=\"1.2, 0.5, 0.5\"/>"));
    assert!(e.contains("base_color") && e.contains("exceeds 1") && e.contains("test.xml:4:"), "{e}");
    let e = err(&shape(r#"<float name="specular" value="3"/>"#));
    assert!(e.contains("specular must lie in [0, 1]"), "{e}");
    let e = err(&shape(r#"<float name="main_specular_sampling_rate" value="0"/>"#));
    assert!(e.contains("main_specular_sampling_rate must be positive"), "{e}");
    let e = err(&shape(
        r#"<texture type="checkerboard" name="sheen"><float name="color0" value="2"/></texture>"#,
    ));
    assert!(e.contains("sheen must lie in [0, 1]") && e.contains("test.xml:3:"), "{e}");
    let e = err(&shape(r#"<texture type="checkerboard" name="colour"/>"#));
    assert!(e.contains("unsupported element inside <bsdf type=\"principled\">"), "{e}");
}
