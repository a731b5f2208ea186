//! Opticks against an independent renderer: each scene of `testdata/scenes` is traced, rendered
//! through its own camera and compared with Mitsuba 3's converged `reference.exr`.
//!
//! What must hold (issue #2):
//! * at 4,194,304 light paths the per-channel mean is within 1% of the reference and the
//!   relative MSE is no worse than 1.05 × Mitsuba's own particle tracer (`ptracer`) at the same
//!   path count (its mean over eight seeds);
//! * four times the paths divides the error (less the reference's own noise) by about four: no
//!   bias floor; and the mean is then within 0.5%.
//!
//! Where the 5% comes from: relMSE at 4,194,304 paths over seeds 0–7 (mean ± standard deviation
//! of a single run; Mitsuba 3.9.1 `llvm_ad_rgb` via `benches/mitsuba_ptracer.py`, Opticks
//! `trace` + `render`):
//!
//! | scene | Mitsuba `ptracer` | Opticks | Opticks / Mitsuba |
//! |---|---|---|---|
//! | cornell | 3.979e-3 ± 0.044e-3 (1.1%), 3.898–4.036e-3 | 4.069e-3 ± 0.021e-3 (0.5%), 4.032–4.095e-3 | 1.023 |
//! | furnace | 1.705e-3 ± 0.021e-3 (1.2%), 1.679–1.745e-3 | 1.690e-3 ± 0.028e-3 (1.7%), 1.637–1.728e-3 | 0.991 |
//!
//! On the Cornell box Opticks is 2.3% noisier than Mitsuba, significantly (the means differ by
//! 5 standard errors); on the furnace the two agree (−0.9%, 1.2 standard errors). The bound
//! 1.05 × Mitsuba's mean is 5.6 of Opticks's standard deviations above its Cornell mean and 4.1
//! above its furnace mean, so the seed-to-seed spread cannot fail the test, while a loss of
//! efficiency of a few percent would. A single Mitsuba run (the SCENE.md figures) carries ±1.2%
//! noise of its own, hence the eight-seed means here.

use opticks_testkit as common;

use common::*;
use opticks_io::compare::compare;

const PATHS: u64 = 4_194_304;

/// Averages the films of independent traces (the merge law: equal N_k, so a plain mean).
fn mean_image(films: &[Vec<f32>]) -> Vec<f32> {
    let n = films.len() as f32;
    (0..films[0].len()).map(|i| films.iter().map(|f| f[i]).sum::<f32>() / n).collect()
}

fn check_scene(name: &str, mitsuba_ptracer_relmse: f64) {
    let scene = load(name);
    let cam = camera(&scene);
    let reference = reference(name);
    let reference_noise = reference_stat(name, "relmse_reference_est");
    let films: Vec<Vec<f32>> =
        (1..=4).map(|seed| trace_and_render(&scene, &cam, PATHS, seed).to_rgb_f32()).collect();

    let one = compare(&films[0], &reference);
    eprintln!("{name} {PATHS} paths: relMSE {:.3e}, mean ratio {:?}", one.relmse, one.mean_ratio);
    for (c, r) in one.mean_ratio.iter().enumerate() {
        assert!((r - 1.0).abs() < 0.01, "{name}: channel {c} mean ratio {r} is off by more than 1%");
    }
    assert!(
        one.relmse <= mitsuba_ptracer_relmse * 1.05,
        "{name}: relMSE {:.3e} is worse than Mitsuba's ptracer ({mitsuba_ptracer_relmse:.3e}) at the same path count",
        one.relmse
    );

    let four = compare(&mean_image(&films), &reference);
    let ratio = (one.relmse - reference_noise) / (four.relmse - reference_noise);
    eprintln!(
        "{name} 4×{PATHS} paths: relMSE {:.3e} (error ratio {ratio:.2}), mean ratio {:?}",
        four.relmse, four.mean_ratio
    );
    assert!((3.3..4.7).contains(&ratio), "{name}: 4× the paths divided the error by {ratio:.2}, not ~4");
    for (c, r) in four.mean_ratio.iter().enumerate() {
        assert!(
            (r - 1.0).abs() < 0.005,
            "{name}: channel {c} mean ratio {r} is off by more than 0.5% at 16M paths"
        );
    }
}

#[test]
fn cornell_box_matches_mitsuba() {
    // Mitsuba's ptracer, 4.19 M light paths, mean of seeds 0–7 (module docs; SCENE.md's single
    // run: 3.99e-3).
    check_scene("cornell", 3.979e-3);
}

#[test]
fn furnace_matches_mitsuba() {
    // Mitsuba's ptracer, 4.19 M light paths, mean of seeds 0–7 (module docs; SCENE.md's two
    // seeds: 1.74e-3, 1.70e-3).
    check_scene("furnace", 1.705e-3);
}
