//! Mitsuba's `normalmap` BSDF through the loader: what the description records (the nested
//! BSDF, its textures and the [`ColourSlot::NormalMap`] binding), the warning about Mitsuba's
//! defaults Opticks does not follow, and the located errors of bad input. The rendered result
//! against Mitsuba is `crates/cli/tests/it/mitsuba_scenes.rs` (`normalmap`).

use opticks_core::bsdf::Bsdf;
use opticks_core::texture::ColourSlot;
use opticks_io::{LoadedScene, SceneFileError};

fn load(body: &str) -> Result<LoadedScene, SceneFileError> {
    crate::mitsuba_fragment::load_in("normalmap", body)
}

fn err(body: &str) -> String {
    crate::mitsuba_fragment::err_in("normalmap", body)
}

const MAP: &str = r#"<texture type="bitmap" name="normalmap"><string name="filename" value="normalmap.png"/>
    <boolean name="raw" value="true"/></texture>"#;

#[test]
fn a_normalmap_binds_its_map_beside_the_nested_bsdfs_textures() {
    let body = format!(
        r#"<shape type="rectangle"><bsdf type="normalmap">{MAP}
        <boolean name="flip_invalid_normals" value="false"/><boolean name="use_shadowing_function" value="false"/>
        <bsdf type="twosided"><bsdf type="diffuse"><texture type="checkerboard" name="reflectance"/></bsdf></bsdf>
        </bsdf></shape>
        <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>"#
    );
    let loaded = load(&body).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let d = &loaded.description;
    assert!(matches!(d.materials[0].bsdf, Bsdf::Lambert(_)));
    assert!(d.materials[0].two_sided);
    let mut slots: Vec<_> = d.textures.iter().map(|t| t.slot).collect();
    slots.sort_by_key(|s| s.name());
    assert_eq!(slots, [ColourSlot::NormalMap, ColourSlot::Reflectance]);
    opticks_core::scene::Scene::build(d).unwrap();
    // Mitsuba's defaults (flip, shadowing term) are not followed: said once, at the element.
    let body = format!(
        r#"<shape type="rectangle"><bsdf type="normalmap">{MAP}<bsdf type="diffuse"/></bsdf></shape>"#
    );
    let loaded = load(&body).unwrap();
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    assert!(loaded.warnings[0].contains("flip_invalid_normals"), "{:?}", loaded.warnings);
}

#[test]
fn bad_normal_maps_are_located_errors() {
    let e = err(r#"<shape type="rectangle"><bsdf type="normalmap"><texture type="bitmap" name="normalmap">
        <string name="filename" value="normalmap.png"/></texture><bsdf type="diffuse"/></bsdf></shape>"#);
    assert!(e.contains("must be read raw") && e.contains("test.xml:2:"), "{e}");
    let e = err(r#"<shape type="rectangle"><bsdf type="normalmap"><texture type="bitmap" name="normalmap">
        <string name="filename" value="grey.png"/><boolean name="raw" value="true"/></texture>
        <bsdf type="diffuse"/></bsdf></shape>"#);
    assert!(e.contains("grey.png") && e.contains("must be an RGB image") && e.contains("test.xml:3:"), "{e}");
    let e = err(&format!(r#"<shape type="rectangle"><bsdf type="normalmap">{MAP}</bsdf></shape>"#));
    assert!(
        e.contains("a normalmap BSDF needs one nested <bsdf> or <ref>") && e.contains("test.xml:2:"),
        "{e}"
    );
    let e = err(r#"<shape type="rectangle"><bsdf type="normalmap"><bsdf type="diffuse"/></bsdf></shape>"#);
    assert!(e.contains("needs its normal map") && e.contains("test.xml:2:"), "{e}");
    let e = err(
        r#"<shape type="rectangle"><bsdf type="normalmap"><texture type="checkerboard" name="normalmap"/>
        <bsdf type="diffuse"/></bsdf></shape>"#,
    );
    assert!(e.contains("must be a bitmap texture"), "{e}");
    let e = err(&format!(
        r#"<shape type="rectangle"><bsdf type="normalmap">{MAP}<bsdf type="normalmap">{MAP}<bsdf type="diffuse"/></bsdf></bsdf></shape>"#
    ));
    assert!(e.contains("a normalmap inside a normalmap"), "{e}");
}
