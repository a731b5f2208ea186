//! Helpers shared by the scene-format integration tests: the test data folder, the files of a
//! kind below a folder, loading files written into a temporary folder, comparing two built
//! scenes triangle by triangle, and a tiny generator for mangling inputs.

use opticks_core::bsdf::{Bsdf, Material};
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::Scene;
use opticks_io::{LoadedScene, SceneFileError, load_scene};
use std::path::{Path, PathBuf};

/// Appends every file below `dir` (its subfolders too) whose extension is `ext` to `out`.
pub fn files_with_extension(dir: &Path, ext: &str, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files_with_extension(&path, ext, out);
        } else if path.extension().is_some_and(|e| e == ext) {
            out.push(path);
        }
    }
}

/// `testdata/REL` at the repository root.
pub fn testdata(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata").join(rel)
}

/// Writes `files` into a fresh folder (names may contain folders) and loads the first one.
pub fn load_files(files: &[(&str, &[u8])]) -> (tempfile::TempDir, Result<LoadedScene, SceneFileError>) {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        let path = dir.path().join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    let r = load_scene(&dir.path().join(files[0].0));
    (dir, r)
}

/// Loads and returns the scene with the temporary folder replaced by `TMP` in the warnings.
pub fn load_ok(files: &[(&str, &[u8])]) -> LoadedScene {
    let (dir, r) = load_files(files);
    let mut s = r.unwrap_or_else(|e| panic!("{e}"));
    let tmp = dir.path().display().to_string();
    for w in &mut s.warnings {
        *w = w.replace(&tmp, "TMP");
    }
    s
}

/// Loads files that must fail and returns the message with the temporary folder replaced by `TMP`.
pub fn error_of(files: &[(&str, &[u8])]) -> String {
    let (dir, r) = load_files(files);
    r.expect_err("should fail").to_string().replace(&dir.path().display().to_string(), "TMP")
}

/// (centroid, unit normal, diffuse albedo, two-sided, emits) of every triangle.
fn triangles_of(s: &Scene) -> Vec<(Vec3, Vec3, Rgb, bool, bool)> {
    (0..s.triangles.len() as u32)
        .map(|i| {
            let t = &s.triangles[i as usize];
            let m: &Material = s.material(i);
            let albedo = match &m.bsdf {
                Bsdf::Lambert(l) => l.reflectance,
                other => panic!("expected Lambert, got {other:?}"),
            };
            (t.point(1.0 / 3.0, 1.0 / 3.0), t.normal(), albedo, m.two_sided, s.light_of(i).is_some())
        })
        .collect()
}

/// Asserts that two built scenes have the same triangles (position, orientation, material,
/// emission) in any order and the same light power.
pub fn assert_same_scene(a: &Scene, b: &Scene) {
    assert_eq!(a.triangles.len(), b.triangles.len());
    let (ta, tb) = (triangles_of(a), triangles_of(b));
    for x in &ta {
        let y = tb
            .iter()
            .find(|y| (x.0 - y.0).abs().max_element() < 1e-5 && x.1.dot(y.1) > 0.99999)
            .unwrap_or_else(|| panic!("no triangle at {:?} facing {:?}", x.0, x.1));
        assert_eq!((x.2, x.3, x.4), (y.2, y.3, y.4), "triangle at {:?}", x.0);
    }
    let power = |s: &Scene| s.light_powers().iter().fold(Rgb::ZERO, |acc, p| acc + *p);
    let (pa, pb) = (power(a), power(b));
    assert!(((pa - pb) / pb).abs().max_element() < 1e-4, "light power {pa:?} vs {pb:?}");
}

/// A tiny deterministic generator for mangling inputs.
pub struct Lcg(pub u64);
impl Lcg {
    /// The next pseudo-random number (31 bits).
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        self.0 >> 33
    }
}
