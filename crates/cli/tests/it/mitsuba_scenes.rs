//! The Mitsuba 3 scene elements of issue 12 against Mitsuba's own renders: each scene of
//! `testdata/mitsuba/NAME/` below (written for the test; its `make_scene.py` and the reference's
//! `reference_stats.json` say how it was made, `tools/mitsuba/render_reference.py` rendered it
//! with Mitsuba 3.9's particle tracer `ptracer`, `llvm_ad_rgb`) is loaded, traced and rendered
//! by Opticks at the path count of Mitsuba's competitor run, and must agree with the reference
//!
//! * in the image mean and in the mean of each region of a 4 × 4 grid, per channel, within
//!   Z = 5 standard errors of the difference. Opticks's standard errors are measured: the trace's
//!   chunks are dealt into K = 16 disjoint batches rendered on their own (`common::regions`).
//!   The reference's are derived from them: the same estimator with `light_paths` paths instead
//!   of ours has standard errors √(ours / theirs) times ours (¼ at 16× the paths). With 17
//!   comparisons × 3 channels per scene, a false alarm at 5σ (Student t, 15 degrees of
//!   freedom) has a chance below 0.2%;
//! * in relMSE: at most 1.25× Mitsuba's own ptracer at the same path count (its two seeds'
//!   mean; Opticks's energy-driven roulette costs ~2–5% of noise per path on diffuse scenes,
//!   and a single seed's relMSE scatters by a few per cent).
//!
//! A region's mean measures what the shapes, normals and materials put there, so a wrong
//! tessellation area, a flipped normal, a mesh read with the wrong byte order or a missed
//! mesh (each moves a region by far more than 5σ) fails the test.
//!
//! `shapes` (96 × 72, 884,736 paths): the Mitsuba shapes read by `scene_formats::mitsuba`
//! — tessellated `sphere` (diffuse, and as an area light) and open `cylinder`, a `disk` area
//! light, a binary big-endian `ply` with normals, an ASCII `ply` without (generated smooth
//! normals), mesh 1 of a two-mesh `serialized` file — and `<path>`, `<include>`, `<default>`.
//!
//! `plastic` (96 × 72, 884,736 paths): Mitsuba's smooth `plastic` on three spheres (the
//! defaults; a saturated `nonlinear` base under int_ior 1.9; half-strength coating of BK7) on a
//! grey floor: their diffuse part seen by the camera, the light their coatings reflect onto the
//! floor, the energy their coatings take from the base.
//!
//! `roughplastic` (64 × 48, 393,216 paths): Mitsuba's `roughplastic` on three spheres (the
//! defaults, Beckmann α 0.1; a saturated `nonlinear` base under a GGX α 0.3 coating of int_ior
//! 1.9; a blue base under a GGX α 0.12 coating of BK7 at 0.6 strength, sampled without visible
//! normals) on a grey floor: the glossy coatings and their diffuse bases seen by the camera, the
//! light the coatings reflect onto the floor, the energy the rough coatings take from the base
//! (the transmittance table and R_int).
//!
//! `thin` (96 × 72, 884,736 paths): two `thindielectric` panes (int_ior 2.4; a blue-tinted
//! transmittance) between a disk light, a floor and a wall: the light each pane transmits
//! straight through and the light it reflects, with the internal reflections' R = 2r/(1 + r).
//!
//! `textures` (96 × 72, 884,736 paths): colour parameters as textures — a `checkerboard` floor
//! (the rectangle's UVs, `to_uv`), an sRGB `bitmap` on a diffuse sphere (the sphere's UVs,
//! bilinear, repeat), a `bitmap` on a cube (its UVs; nearest, mirror, a shifted and scaled
//! `to_uv`), a plastic whose `diffuse_reflectance` is a top-level bitmap by `<ref>`, an OBJ
//! quad with `vt` (flipped v, clamp): a wrong UV, wrap, filter or sRGB decoding moves the
//! regions the shape covers (`testdata/mitsuba/textures/make_textures.py` made the images).
//!
//! `cameras` (64 × 48, 2²⁰ paths): Mitsuba's `thinlens` (focused on the middle of three cubes at
//! three depths, `fov_axis` y) and `orthographic` (a film scaled by `to_world`) sensors, against
//! Mitsuba `path` references (`orthographic` has no light-tracing connection in Mitsuba, so
//! no `ptracer` render exists; the thin lens uses the same reference kind). Checked in the mean
//! and the 4 × 4 regions as above; the reference's own standard errors come from its halves'
//! relMSE (per pixel, over a region's pixels), a few per cent of ours. Finer regions (8 × 8)
//! than above, because defocus moves light only locally. Measured on mutated scene files: the
//! thin lens focused 10% (5%) nearer fails at 7.6σ (5.7σ), `fov_axis` x for y at 13.5σ, the
//! orthographic film's height taken without the aspect at 67σ, the film 5% wider at 16σ.
//! `cameras/scene-filter.xml` (a 96 × 72 film cropped to 64 × 48, the gaussian filter): the
//! same check against a Mitsuba `path` reference of the crop window.
//! `textures2` (64 × 48, 393,216 paths): roughness and mesh attributes as textures — a rough
//! conductor sphere whose `alpha` is a raw grey `bitmap` (eval_1: its luminance), a rough
//! conductor floor whose `alpha` is a `checkerboard` (eval_1: a colour's mean, the squares of
//! Mitsuba's eval_1 swapped against its eval), a PLY wall coloured by its float vertex colours
//! (`mesh_attribute` `vertex_color`, blended by the barycentrics), a PLY octahedron whose
//! `specular_reflectance` and `alpha` are its face attributes (`face_color`, `face_rough`, by
//! `<ref>`): a wrong eval_1, attribute grouping, blend or face order moves the regions the shape
//! covers or reflects into (`testdata/mitsuba/textures2/make_textures2.py` made the files).
//!
//! `mask` (96 × 72, 2²⁰ paths): Mitsuba's opacity `mask` — a twosided leaf whose opacity is a
//! checkerboard (opaque and 0.25 squares), a one-sided card of opacity 0.5 seen from its back,
//! a twosided quad of the default opacity (0.5) — against a Mitsuba `path` reference (its null
//! lobe is a delta its `ptracer` cannot connect through; Opticks's stochastic transparency lets
//! the light estimator see through, so the light estimator is checked), 8 × 8 regions as for
//! `cameras`: the shadows' pattern and what is seen through each surface. A mask read as opaque
//! or as fully open moves the regions it covers by far more than 5.5σ.
//!
//! `normalmap` (96 × 72, 2²⁰ paths): Mitsuba's `normalmap` — a diffuse floor and a rough-plastic
//! card shaded by a raw bitmap of 4 × 4 cells of normals tilted 25° toward four azimuths (flat on
//! the diagonal; `testdata/mitsuba/normalmap/make_scene.py`) — against a Mitsuba `path`
//! reference, light estimator, 8 × 8 regions as for `mask`: a tangent frame swapped or mirrored,
//! a map read as sRGB or upside down, or a lost adjoint correction moves the cells' regions.
//!
//! `bumpmap` (96 × 72, 2²⁰ paths): Mitsuba's `bumpmap` — the same floor and card bump-mapped by a
//! raw grey height field of two tilted sinusoids with no mirror symmetry
//! (`testdata/mitsuba/bumpmap/make_scene.py`), scales 0.3 and 0.15 — against a Mitsuba `path`
//! reference, light estimator, 8 × 8 regions as for `normalmap`: a gradient of the wrong sign,
//! axes swapped, a wrong dp/du or dp/dv or a lost scale moves the slopes' regions.
//!
//! `principled` (96 × 72, 2²⁰ paths): Mitsuba's `principled` BSDF (reflective lobes) — three
//! spheres (sheen and flatness; a metal; a clearcoat with spec_tint and eta) and a card whose
//! metallic, base colour and clearcoat are checkerboards — against a Mitsuba `path` reference,
//! light estimator, 8 × 8 regions: a lobe's weight, a Fresnel blend or a texture's slot wrong,
//! or sampling weights not adjoint-correct, moves the spheres' or the card's regions.
//!
//! `principled_trans` (96 × 72, 2²⁰ paths): the `principled` BSDF's transmission lobe — a
//! glassy sphere (spec_trans 1) and a half-transmitting one (spec_trans 0.5, η 1.4), roughness
//! 0.3, the floor and wall seen through them and their rough caustics on the floor — against a
//! Mitsuba `path` reference, light estimator, 8 × 8 regions: the light tracer sees the spheres
//! only through light paths refracted by them, so a transmission weight that is not the adjoint
//! (Mitsuba's radiance-mode 1/η² kept in light paths), a missing √base_color or a wrong lobe
//! probability moves the spheres' or the caustics' regions.
//!
//! `principledthin` (96 × 72, 2²⁰ paths): Mitsuba's thin principled sheet — a leaf-like square
//! lit from behind (diffuse transmission) and a sphere of glassy sheets (spec_trans 0.7, rough
//! unbent transmission through both faces) — against a Mitsuba `path` reference, light
//! estimator, 8 × 8 regions: the light tracer sees the leaf only through light transmitted by it,
//! so a wrong transmission weight, lobe probability or one-way masking moves the leaf's or the
//! sphere's regions.
//!
//! `anisotropic` (96 × 72, 2²⁰ paths): brushed metal (Beckmann, α_u 0.08, α_v 0.4) on a sphere
//! and on a turned, tilted card — against a Mitsuba `path` reference, light estimator, 8 × 8
//! regions: Mitsuba orients α_u along ∂p/∂u where a shape has texture coordinates (the sphere's
//! parallels, the card's own x axis), so a frame that ignores them turns the highlights.
//!
//! `emitter_texture` (64 × 48, 2²⁰ paths): area emitters whose radiance is a texture — a bilinear
//! bitmap with a black column and a checkerboard — seen by the camera and lighting a floor,
//! against a Mitsuba `path` reference, light estimator, 8 × 8 regions: a texture flipped or
//! shifted on the emitter, a power that is not the texture's integral or start weights that
//! do not average to 1 move the panels' or the floor's regions.
//!
//! `spot_texture` (64 × 48, 2²⁰ paths): spots projecting a texture — a bilinear bitmap with a
//! black texel obliquely onto a floor and a cube, a hard-edged checkerboard onto a wall —
//! against a Mitsuba `path` reference, light estimator, 8 × 8 regions: a projection mirrored or
//! rotated, or light paths weighted as if the spot were untextured, move the floor's or the
//! wall's regions (mirrored in u: the mean 14% off).
//!
//! Measured (printed): see the module's rows in `docs/scene-formats.md`.

use opticks_testkit as common;

use common::regions::{self, Estimate};
use opticks_core::scene::Scene;
use opticks_core::sensor::{Filter, Pinhole, Sensor};
use opticks_core::trace::TraceSettings;
use opticks_io::compare::compare;
use std::path::PathBuf;

const K: usize = 16;
const GRID: usize = 4;
const Z: f64 = 5.0;
const RELMSE_TOL: f64 = 1.25;

fn dir(name: &str) -> PathBuf {
    common::repo().join("testdata/mitsuba").join(name)
}

/// Checks scene `name` (module docs) with seed `seed`.
fn check(name: &str, seed: u64) {
    let loaded = opticks_io::scene_formats::load_scene(&dir(name).join("scene.xml")).unwrap();
    assert!(loaded.warnings.is_empty(), "{name}: {:?}", loaded.warnings);
    let scene = Scene::build(&loaded.description).unwrap();
    let cam = Pinhole::new(scene.camera.as_ref().expect("a camera")).unwrap();
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir(name).join("reference_stats.json")).unwrap())
            .unwrap();
    let (w, h) =
        (stats["reference"]["width"].as_u64().unwrap(), stats["reference"]["height"].as_u64().unwrap());
    let ref_paths = stats["reference"]["light_paths"].as_f64().unwrap();
    let paths = stats["competitor"]["light_paths"].as_u64().unwrap();
    let competitor = stats["competitor"]["relmse"].as_f64().unwrap();

    let ours = regions::estimate(&scene, cam, &TraceSettings { paths, seed, ..Default::default() }, K, GRID);
    let image = opticks_io::image_file::read_exr_rgb(&dir(name).join("reference.exr")).unwrap().2;
    assert_eq!(image.len() as u64, 3 * w * h);
    let scale = (paths as f64 / ref_paths).sqrt();
    let reference = Estimate {
        mean: regions::region_means(&image, w as usize, GRID),
        err: ours.err.iter().map(|e| e.map(|x| x * scale)).collect(),
        image,
        grid: GRID,
    };
    regions::assert_same_expectation(name, &ours, &reference, Z);
    let relmse = compare(&ours.image, &reference.image).relmse;
    eprintln!("{name}: relMSE {relmse:.4e}, Mitsuba's ptracer at {paths} paths {competitor:.4e}");
    assert!(relmse <= RELMSE_TOL * competitor, "{name}: relMSE {relmse:.4e} vs Mitsuba's {competitor:.4e}");
}

#[test]
fn mitsuba_shapes_and_mesh_files_match_mitsuba() {
    check("shapes", 1);
}

#[test]
fn mitsuba_plastic_matches_mitsuba() {
    check("plastic", 1);
}

#[test]
fn mitsuba_roughplastic_matches_mitsuba() {
    check("roughplastic", 1);
}

#[test]
fn mitsuba_thin_dielectric_matches_mitsuba() {
    check("thin", 1);
}

#[test]
fn mitsuba_textures_match_mitsuba() {
    check("textures", 1);
}

/// Checks the scene file `scene` of folder `name` (its camera as `Sensor::new` builds it, the
/// light estimator, `paths` paths) against the Mitsuba `path` reference `stem`.exr beside it.
fn check_path_reference(name: &str, scene: &str, stem: &str, paths: u64, seed: u64) -> Sensor {
    // Finer regions than `check`'s, so that a blur confined to edges is seen; more batches, so
    // that 65 × 3 comparisons at 5.5σ (Student t, 31 degrees of freedom) raise a false alarm
    // with a chance below 0.2%.
    const GRID: usize = 8;
    const K: usize = 32;
    const Z: f64 = 5.5;
    let loaded = opticks_io::scene_formats::load_scene(&dir(name).join(scene)).unwrap();
    assert!(loaded.warnings.is_empty(), "{name}/{scene}: {:?}", loaded.warnings);
    let scene = Scene::build(&loaded.description).unwrap();
    let sensor = Sensor::new(scene.camera.as_ref().expect("a camera")).unwrap();
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir(name).join(format!("{stem}_stats.json"))).unwrap())
            .unwrap();
    let ours =
        regions::estimate(&scene, sensor, &TraceSettings { paths, seed, ..Default::default() }, K, GRID);
    let (w, h, image) = opticks_io::image_file::read_exr_rgb(&dir(name).join(format!("{stem}.exr"))).unwrap();
    assert_eq!((w, h), (sensor.width(), sensor.height()));
    // The reference's relative noise per pixel, √relMSE, averaged down over a region's pixels.
    let rel = stats["reference"]["relmse_reference_est"].as_f64().unwrap().sqrt();
    let mean = regions::region_means(&image, w as usize, GRID);
    let pixels = |r: usize| if r == 0 { (w * h) as f64 } else { (w * h) as f64 / (GRID * GRID) as f64 };
    let err = mean.iter().enumerate().map(|(r, m)| m.map(|x| x * rel / pixels(r).sqrt())).collect();
    let reference = Estimate { mean, err, image, grid: GRID };
    regions::assert_same_expectation(&format!("{name}/{stem}"), &ours, &reference, Z);
    eprintln!(
        "{name}/{stem}: relMSE {:.4e} against Mitsuba path",
        compare(&ours.image, &reference.image).relmse
    );
    sensor
}

#[test]
fn mitsuba_thinlens_matches_mitsuba() {
    let s = check_path_reference("cameras", "scene-thinlens.xml", "reference-thinlens", 1 << 20, 1);
    assert!(matches!(s, Sensor::ThinLens(t) if t.radius == 0.3));
}

#[test]
fn mitsuba_orthographic_matches_mitsuba() {
    let s = check_path_reference("cameras", "scene-ortho.xml", "reference-ortho", 1 << 20, 1);
    assert!(matches!(s, Sensor::Orthographic(_)));
}

/// A 96 × 72 film cropped to its 64 × 48 window at (20, 10), through Mitsuba's default gaussian
/// filter (σ ½ pixel): the crop keeps the full film's projection, the filter blurs by Mitsuba's
/// definition (`sample_border`, so that its edge pixels weigh the plane as Opticks's do).
#[test]
fn mitsuba_crop_and_gaussian_filter_match_mitsuba() {
    let s = check_path_reference("cameras", "scene-filter.xml", "reference-filter", 1 << 20, 1);
    assert_eq!((s.width(), s.height()), (64, 48));
    let r = s.raster();
    assert_eq!((r.full_width, r.full_height, r.window.x, r.window.y), (96, 72, 20, 10));
    assert_eq!(r.filter, Filter::Gaussian { stddev: 0.5 });
}

#[test]
fn mitsuba_roughness_and_mesh_attribute_textures_match_mitsuba() {
    check("textures2", 1);
}

#[test]
fn mitsuba_mask_matches_mitsuba() {
    check_path_reference("mask", "scene.xml", "reference-path", 1 << 20, 1);
}

#[test]
fn mitsuba_normalmap_matches_mitsuba() {
    check_path_reference("normalmap", "scene.xml", "reference-path", 1 << 20, 1);
}

#[test]
fn mitsuba_bumpmap_matches_mitsuba() {
    check_path_reference("bumpmap", "scene.xml", "reference-path", 1 << 20, 1);
}

#[test]
fn mitsuba_principled_matches_mitsuba() {
    check_path_reference("principled", "scene.xml", "reference-path", 1 << 20, 1);
}

#[test]
fn mitsuba_principled_transmission_matches_mitsuba() {
    check_path_reference("principled_trans", "scene.xml", "reference-path", 1 << 20, 1);
}

#[test]
fn mitsuba_principledthin_matches_mitsuba() {
    check_path_reference("principledthin", "scene.xml", "reference-path", 1 << 20, 1);
}

#[test]
fn mitsuba_anisotropy_follows_dp_du_as_in_mitsuba() {
    check_path_reference("anisotropic", "scene.xml", "reference-path", 1 << 20, 1);
}

#[test]
fn mitsuba_textured_area_emitters_match_mitsuba() {
    check_path_reference("emitter_texture", "scene.xml", "reference-path", 1 << 20, 1);
}

#[test]
fn mitsuba_spots_projecting_textures_match_mitsuba() {
    check_path_reference("spot_texture", "scene.xml", "reference-path", 1 << 20, 1);
}
