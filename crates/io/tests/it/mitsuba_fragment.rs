//! A Mitsuba scene body loaded as a file in one of `testdata/mitsuba`'s folders (so that the
//! textures it names resolve there): what the loader tests of the `normalmap` and `bumpmap`
//! BSDFs share.

use opticks_io::scene_formats::mitsuba::parse;
use opticks_io::{LoadOptions, LoadedScene, SceneFileError};
use std::path::PathBuf;

/// `body` wrapped in a version-3 `<scene>`, parsed as `testdata/mitsuba/FOLDER/test.xml`.
pub fn load_in(folder: &str, body: &str) -> Result<LoadedScene, SceneFileError> {
    let xml = format!("<scene version=\"3.0.0\">\n{body}\n</scene>");
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/mitsuba").join(folder);
    parse(&xml, &dir.join("test.xml"), &LoadOptions::default())
}

/// The error [`load_in`] gives; a panic if `body` loads.
pub fn err_in(folder: &str, body: &str) -> String {
    match load_in(folder, body) {
        Ok(_) => panic!("should fail:\n{body}"),
        Err(e) => e.to_string(),
    }
}

/// The first material's BSDF of [`load_in`]'s scene, which must load without warnings.
pub fn first_bsdf(folder: &str, body: &str) -> opticks_core::bsdf::Bsdf {
    let loaded = load_in(folder, body).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    loaded.description.materials.into_iter().next().expect("a material").bsdf
}
