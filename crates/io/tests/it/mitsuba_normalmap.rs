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
    assert!(e.contains("must be a bitmap (or rawconstant) texture"), "{e}");
    let e = err(&format!(
        r#"<shape type="rectangle"><bsdf type="normalmap">{MAP}<bsdf type="normalmap">{MAP}<bsdf type="diffuse"/></bsdf></bsdf></shape>"#
    ));
    assert!(e.contains("a normalmap inside a normalmap"), "{e}");
}

/// Mitsuba's `rawconstant` (its test scenes give a normal map the identity this way): a raw
/// value everywhere, a `<vector>`, an `<rgb>` or a `<float>`; as a normal map of (0.5, 0.5, 1)
/// it leaves every shading normal as the nested BSDF alone has it, bit for bit; as a
/// roughness it is that number; a bad value is a located error.
#[test]
fn a_rawconstant_is_a_raw_value_everywhere() {
    use opticks_core::scene::Scene;
    let light = r#"<shape type="rectangle"><transform name="to_world"><translate z="2"/></transform>
        <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>"#;
    let conductor = r#"<bsdf type="roughconductor"><float name="alpha_u" value="0.25"/>
        <float name="alpha_v" value="0.05"/></bsdf>"#;
    let mapped = format!(
        r#"<shape type="sphere"><bsdf type="normalmap"><texture name="normalmap" type="rawconstant">
        <vector name="value" value="0.5, 0.5, 1.0"/></texture>{conductor}
        <boolean name="flip_invalid_normals" value="false"/><boolean name="use_shadowing_function" value="false"/>
        </bsdf></shape>{light}"#
    );
    let bare = format!(r#"<shape type="sphere">{conductor}</shape>{light}"#);
    let (mapped, bare) = (load(&mapped).unwrap(), load(&bare).unwrap());
    assert!(mapped.warnings.is_empty(), "{:?}", mapped.warnings);
    assert_eq!(mapped.description.textures.len(), 1);
    assert_eq!(mapped.description.textures[0].slot, ColourSlot::NormalMap);
    let (mapped, bare) =
        (Scene::build(&mapped.description).unwrap(), Scene::build(&bare.description).unwrap());
    for prim in [0u32, 100, 2000] {
        let p = mapped.triangles[prim as usize].point(0.2, 0.3);
        assert_eq!(mapped.normals_at(prim, p), bare.normals_at(prim, p), "triangle {prim}");
        assert!(mapped.normals_at(prim, p).tangent.is_some(), "an anisotropic frame follows dp/du");
    }
    // A float, as a roughness: that number.
    let rough = load(&format!(
        r#"<shape type="rectangle"><bsdf type="roughconductor"><texture name="alpha" type="rawconstant">
        <float name="value" value="0.3"/></texture></bsdf></shape>{light}"#
    ))
    .unwrap();
    assert_eq!(
        rough.description.textures[0].texture.eval_1(opticks_core::math::Vec2::ZERO, Default::default()),
        0.3
    );
    let e =
        err(r#"<shape type="rectangle"><bsdf type="diffuse"><texture name="reflectance" type="rawconstant">
        <float name="value" value="-1"/></texture></bsdf></shape>"#);
    assert!(e.contains("test.xml:3:"), "{e}");
    let e =
        err(r#"<shape type="rectangle"><bsdf type="diffuse"><texture name="reflectance" type="rawconstant"/>
        </bsdf></shape>"#);
    assert!(e.contains("missing <float name=\"value\"") && e.contains("test.xml:2:"), "{e}");
}
