//! Caustics, rough materials and generated smooth normals against Mitsuba 3's particle tracer
//! (issue #5): the two caustic showcase scenes (`scenes/caustics`, a glass sphere;
//! `scenes/ring`, a mirror ring), copied with their references into `testdata/mitsuba/NAME/`, and the test-only `testdata/mitsuba/rough`
//! (a GGX gold sphere and a Beckmann rough-glass sphere, see the end of these docs) are traced and
//! rendered by Opticks and compared with Mitsuba's `ptracer` reference (`reference.exr`, made by
//! `tools/mitsuba/render_reference.py`; spp, time, self-noise and the competitor figure are in
//! `reference_stats.json`).
//!
//! What must hold, at 64 light paths per pixel of the film (exactly the count of Mitsuba's
//! competitor runs; PATHS = 64 × 320 × 240 = 4,915,200 for the caustics), for four seeds:
//! * per-channel mean within MEAN_TOL = 2% of the reference for every seed. Measured seed-to-seed
//!   standard deviation of the image mean at PATHS: 0.4% on the ring (seeds 1–4: −0.27%, +0.41%,
//!   −0.18%, −0.50%; Mitsuba's two competitor seeds +0.12%, −0.16%) and 0.015% on the sphere
//!   (Opticks −0.04%, −0.03%, −0.06%, −0.05%; Mitsuba −0.05%, 0.00%). 2% is five standard
//!   deviations on the ring and still catches a missing Fresnel term, a wrong sidedness or a
//!   lost bounce, each of which moves the mean by far more;
//! * the mean relMSE over the four seeds is at most 1.1× Mitsuba's own ptracer at the same path
//!   count (`competitor.relmse`, the mean of two seeds): same estimator, so the same noise.
//!   Measured: sphere 1.978e-2 vs 1.997e-2 (0.99×), ring 1.842e-1 vs 1.838e-1 (1.00×); the
//!   single-seed relMSE varies by about ±1% on both scenes, so 10% is ten spreads. (Seeds are
//!   fixed: the figures are exactly reproducible.)
//! * the average of the four images (4× the paths) divides the error, less the reference's own
//!   noise (`relmse_reference_est`, ~1/128 of the 1× error), by 3.5–4.5 (measured 3.96 and
//!   4.03): no bias floor; and its mean is within MEAN_TOL_4 = 1% (measured −0.05%, −0.13%);
//! * the caustic itself matches, not just the image average: over the brightest 1% of pixels
//!   (chosen on seed 1's image, so the selection is independent of the images measured) the
//!   mean of seeds 2–4 is within CAUSTIC_TOL = 5% of the reference's. (Choosing the pixels on
//!   the reference instead would bias the ratio low by the reference's own noise.) Measured at
//!   19.7 M paths with the same method: 1.0019 (sphere), 0.9999 (ring); in this test 0.9994 and
//!   0.9917 (the ring's bright pixels have about 1% noise at 3 × 4.9 M paths).
//!
//! **Rough materials** (`rough`, 128 × 128, 64 × 128² = 1,048,576 paths): a rough gold conductor
//! (GGX, α = 0.25, gold's η + iκ) and a rough glass sphere (Beckmann, Mitsuba's default, α = 0.2,
//! η = 1.5) on a grey floor, side-lit; both spheres are seen by the camera, so their microfacet
//! BSDFs are tested both in the tracer's sampling and in the sensor's connection. Reference:
//! 8192 spp (134 M paths, 167 s on 2 busy cores), self-noise 2.0e-3 (≈ 1/140 of the 1× error).
//! Light traced through rough glass is heavy-tailed (camera connections to vertices inside
//! the glass), so relMSE scatters much more from seed to seed than on the other scenes:
//! Mitsuba at 64 spp, ten seeds: 2.677e-1 ± 0.510e-1 (19%; 1.90–3.47e-1), mean ratio within
//! ±1.4%; Opticks, seeds 1–4: 3.116, 2.858, 2.682, 2.814e-1 (mean 2.868e-1 ± 0.18e-1, 1.07×
//! Mitsuba's mean), mean ratio −0.85% … +0.67%. The difference of the means, 7%, is 1.0
//! standard error of the comparison (Mitsuba's ten-seed mean is known to ±6%, Opticks's
//! four-seed mean to ±3%), so the bound is ROUGH_RELMSE_TOL = 1.25× (3 standard errors) rather
//! than 1.1×. 4×: error ÷ 4.05, mean within 0.37%; the brightest 1% of pixels (the spheres'
//! highlights and the glass's caustic) 0.987 of the reference's. Opticks's G₂ is the
//! height-correlated Smith term while Mitsuba's is the separable G₁·G₁ (with Walter's rational
//! fit for Beckmann): at these roughnesses the difference is below this test's resolution.
//!
//! **Generated smooth normals** (`smooth`, 64 × 64): a 224-triangle diffuse sphere
//! (8 rings × 16 segments, `make_scene.py`) whose OBJ has no `vn` and whose `face_normals` is left
//! at Mitsuba's default, so Mitsuba and Opticks both shade it with generated angle-weighted vertex
//! normals; lit by a point light. The point light sends only ~3% of its paths to the sphere, so
//! the test runs Mitsuba's competitor count of 1024 spp (4.2 M paths). Reference: 16 × 16384 spp
//! (1.07 G paths, 47 s), self-noise 1.5e-5 (≈ 1/250 of the 1× error). Measured, seeds 1–4:
//! relMSE 3.847, 3.767, 3.328, 3.645e-3 (mean 3.647e-3, 0.97× Mitsuba's 3.755e-3, whose two seeds
//! are 3.94 and 3.57e-3), mean ratio −0.43% … +0.48%; 4×: error ÷ 4.02, mean within 0.001%;
//! brightest 1% 0.997. The same scene kept faceted (`face_normals` true) has relMSE 1.04e-2
//! (2.8× Mitsuba's) while its mean moves by only ~1%: the relMSE bound is what catches missing
//! or wrong generated normals.
//!
//! Runtime: two scenes × 4 × 4.9 M paths plus 4 × 1 M and 4 × 4.2 M (mostly missing the sphere),
//! about 40 s on 2 busy cores.

use opticks_testkit as common;

use opticks_core::scene::Scene;
use opticks_core::sensor::Pinhole;
use opticks_io::compare::compare;
use std::path::PathBuf;

const MEAN_TOL: f64 = 0.02;
const MEAN_TOL_4: f64 = 0.01;
const CAUSTIC_TOL: f64 = 0.05;

/// Mean over the pixels whose `mask_image` luminance (channel mean) is in its top 1%, of
/// `image` (channel mean).
fn brightest_mean(mask_image: &[f32], image: &[f32]) -> f64 {
    let lum = |img: &[f32]| -> Vec<f64> {
        img.chunks(3).map(|p| p.iter().map(|&v| v as f64).sum::<f64>() / 3.0).collect()
    };
    let (mask, values) = (lum(mask_image), lum(image));
    let mut sorted = mask.clone();
    sorted.sort_by(f64::total_cmp);
    let threshold = sorted[sorted.len() * 99 / 100];
    let chosen: Vec<f64> =
        values.iter().zip(&mask).filter(|(_, m)| **m >= threshold).map(|(v, _)| *v).collect();
    chosen.iter().sum::<f64>() / chosen.len() as f64
}

fn dir(name: &str) -> PathBuf {
    common::repo().join("testdata/mitsuba").join(name)
}

fn stats(name: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir(name).join("reference_stats.json")).unwrap()).unwrap()
}

fn mean_image(films: &[Vec<f32>]) -> Vec<f32> {
    let n = films.len() as f32;
    (0..films[0].len()).map(|i| films.iter().map(|f| f[i]).sum::<f32>() / n).collect()
}

fn check_scene(name: &str, relmse_tol: f64) {
    let loaded = opticks_io::scene_formats::load_scene(&dir(name).join("scene.xml")).unwrap();
    let scene = Scene::build(&loaded.description).unwrap();
    let cam = Pinhole::new(scene.camera.as_ref().expect("scene has a camera")).unwrap();
    let reference = opticks_io::image_file::read_exr_rgb(&dir(name).join("reference.exr")).unwrap().2;
    let stats = stats(name);
    let reference_noise = stats["reference"]["relmse_reference_est"].as_f64().unwrap();
    let competitor = stats["competitor"]["relmse"].as_f64().unwrap();
    // The competitor's path count: its spp (64, `smooth`: 1024) of the scene's film.
    let paths = stats["competitor"]["light_paths"].as_u64().unwrap();
    let (w, h) =
        (stats["reference"]["width"].as_u64().unwrap(), stats["reference"]["height"].as_u64().unwrap());
    assert_eq!(paths, stats["competitor"]["spp"].as_u64().unwrap() * w * h);

    let films: Vec<Vec<f32>> =
        (1..=4).map(|seed| common::trace_and_render(&scene, &cam, paths, seed).to_rgb_f32()).collect();
    let mut single = 0.0;
    for (k, film) in films.iter().enumerate() {
        let c = compare(film, &reference);
        eprintln!("{name} seed {}: relMSE {:.4e}, mean ratio {:?}", k + 1, c.relmse, c.mean_ratio);
        for (ch, r) in c.mean_ratio.iter().enumerate() {
            assert!(
                (r - 1.0).abs() < MEAN_TOL,
                "{name} seed {}: channel {ch} mean ratio {r} is off by more than {MEAN_TOL}",
                k + 1
            );
        }
        single += c.relmse / films.len() as f64;
    }
    eprintln!("{name}: mean relMSE {single:.4e}; Mitsuba ptracer at the same paths {competitor:.4e}");
    assert!(
        single <= relmse_tol * competitor,
        "{name}: relMSE {single:.4e} is above {relmse_tol}× Mitsuba's ptracer ({competitor:.4e}) at {paths} paths"
    );

    let four = compare(&mean_image(&films), &reference);
    let ratio = (single - reference_noise) / (four.relmse - reference_noise);
    eprintln!(
        "{name} 4×: relMSE {:.4e} (error ratio {ratio:.2}), mean ratio {:?}",
        four.relmse, four.mean_ratio
    );
    assert!((3.5..4.5).contains(&ratio), "{name}: 4× the paths divided the error by {ratio:.2}, not ~4");
    let caustic = brightest_mean(&films[0], &mean_image(&films[1..])) / brightest_mean(&films[0], &reference);
    eprintln!("{name}: brightest 1% of pixels (the caustic), seeds 2-4 / reference: {caustic:.4}");
    assert!(
        (caustic - 1.0).abs() < CAUSTIC_TOL,
        "{name}: the caustic's brightness is off by more than {CAUSTIC_TOL}: ratio {caustic:.4}"
    );
    for (ch, r) in four.mean_ratio.iter().enumerate() {
        assert!(
            (r - 1.0).abs() < MEAN_TOL_4,
            "{name} 4×: channel {ch} mean ratio {r} is off by more than {MEAN_TOL_4}"
        );
    }
}

#[test]
fn glass_sphere_caustic_matches_mitsuba() {
    check_scene("caustics", 1.1);
}

#[test]
fn mirror_ring_caustic_matches_mitsuba() {
    check_scene("ring", 1.1);
}

/// Rough scene's relMSE bound (module docs): 3 standard errors of the two measured means.
const ROUGH_RELMSE_TOL: f64 = 1.25;

#[test]
fn rough_gold_and_glass_match_mitsuba() {
    check_scene("rough", ROUGH_RELMSE_TOL);
}

#[test]
fn smooth_low_poly_sphere_matches_mitsuba() {
    check_scene("smooth", 1.1);
}
