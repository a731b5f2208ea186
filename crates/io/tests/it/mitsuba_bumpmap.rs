//! Mitsuba's `bumpmap` BSDF through the loader: what the description records (the nested BSDF,
//! its textures, the [`ColourSlot::BumpMap`] binding and its scale), the warning about
//! Mitsuba's defaults Opticks does not follow, and the located errors of bad input. The
//! rendered result against Mitsuba is `crates/cli/tests/it/mitsuba_scenes.rs` (`bumpmap`).

use opticks_core::bsdf::Bsdf;
use opticks_core::texture::{ColourSlot, Texture};
use opticks_io::{LoadedScene, SceneFileError};

fn load(body: &str) -> Result<LoadedScene, SceneFileError> {
    crate::mitsuba_fragment::load_in("bumpmap", body)
}

fn err(body: &str) -> String {
    crate::mitsuba_fragment::err_in("bumpmap", body)
}

const HEIGHT: &str = r#"<texture type="bitmap" name="arbitrary"><string name="filename" value="height.png"/>
    <boolean name="raw" value="true"/></texture>"#;
const FLAGS: &str = r#"<boolean name="flip_invalid_normals" value="false"/>
    <boolean name="use_shadowing_function" value="false"/>"#;

#[test]
fn a_bumpmap_binds_its_height_and_scale_beside_the_nested_bsdfs_textures() {
    let body = format!(
        r#"<texture type="bitmap" id="h"><string name="filename" value="height.png"/></texture>
        <shape type="rectangle"><bsdf type="bumpmap">{HEIGHT}<float name="scale" value="0.25"/>{FLAGS}
        <bsdf type="twosided"><bsdf type="diffuse"><texture type="checkerboard" name="reflectance"/></bsdf></bsdf>
        </bsdf></shape>
        <shape type="rectangle"><bsdf type="bumpmap"><ref id="h"/>{FLAGS}<bsdf type="roughplastic"/></bsdf></shape>
        <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>"#
    );
    let loaded = load(&body).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let d = &loaded.description;
    assert!(matches!(d.materials[0].bsdf, Bsdf::Lambert(_)));
    assert!(d.materials[0].two_sided);
    assert!(matches!(d.materials[1].bsdf, Bsdf::RoughPlastic(_)));
    let slots = |m: usize| {
        let mut s: Vec<_> = d.textures.iter().filter(|t| t.material == m).map(|t| t.slot).collect();
        s.sort_by_key(|s| s.name());
        s
    };
    assert_eq!(slots(0), [ColourSlot::BumpMap, ColourSlot::BumpScale, ColourSlot::Reflectance]);
    // The default scale, 1, is not recorded; a referred texture under no name is the height.
    assert_eq!(slots(1), [ColourSlot::BumpMap]);
    let scale = d.textures.iter().find(|t| t.slot == ColourSlot::BumpScale).unwrap();
    assert_eq!(*scale.texture, Texture::Constant(0.25));
    opticks_core::scene::Scene::build(d).unwrap();
    // Mitsuba's defaults (flip, shadowing term) are not followed: said once, at the element.
    let body = format!(
        r#"<shape type="rectangle"><bsdf type="bumpmap">{HEIGHT}<bsdf type="diffuse"/></bsdf></shape>"#
    );
    let loaded = load(&body).unwrap();
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    assert!(loaded.warnings[0].contains("bumpmap neither flips"), "{:?}", loaded.warnings);
}

#[test]
fn bad_bump_maps_are_located_errors() {
    let shape = |inner: &str| {
        format!(r#"<shape type="rectangle"><bsdf type="bumpmap">{FLAGS}{inner}</bsdf></shape>"#)
    };
    let e = err(&shape(r#"<bsdf type="diffuse"/>"#));
    assert!(e.contains("a bumpmap BSDF needs its height") && e.contains("test.xml:2:"), "{e}");
    let e = err(&shape(HEIGHT));
    assert!(
        e.contains("a bumpmap BSDF needs one nested <bsdf> or <ref>") && e.contains("test.xml:2:"),
        "{e}"
    );
    let e = err(&shape(&format!(r#"{HEIGHT}{HEIGHT}<bsdf type="diffuse"/>"#)));
    assert!(e.contains("takes one texture") && e.contains("test.xml:"), "{e}");
    let e = err(&shape(r#"<texture type="checkerboard" name="h"/><bsdf type="diffuse"/>"#));
    assert!(e.contains("a bump map must be a bitmap (or rawconstant) texture, not \"checkerboard\""), "{e}");
    let e = err(&shape(&format!(r#"{HEIGHT}<float name="scale" value="nan"/><bsdf type="diffuse"/>"#)));
    assert!(
        e.contains("<float name=\"scale\">")
            && e.contains("not a finite number")
            && e.contains("test.xml:4:"),
        "{e}"
    );
    let e = err(&shape(&format!(r#"{HEIGHT}<bsdf type="bumpmap">{HEIGHT}<bsdf type="diffuse"/></bsdf>"#)));
    assert!(e.contains("a bumpmap inside a bumpmap"), "{e}");
    // A mesh without texture coordinates has no gradient to take: refused at its BSDF.
    let e = err(&format!(
        r#"<shape type="obj"><string name="filename" value="../../scenes/cornell/meshes/red.obj"/>
        <bsdf type="bumpmap">{HEIGHT}<bsdf type="diffuse"/></bsdf></shape>"#
    ));
    assert!(
        e.contains("has no texture coordinates, which its bumpmap needs") && e.contains("test.xml:3:"),
        "{e}"
    );
}
