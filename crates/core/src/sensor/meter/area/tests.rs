//! The area lights' direct term against closed forms: CIE 171's rectangle (5.3), the same
//! source behind a parallel obstruction (5.7) and seen through a small opening, with no stored
//! samples (the floor is black: the direct term is the whole reading); relighting; the stated
//! errors against the spread over seeds; explicit counts.

use super::*;
use crate::math::Vec3;
use crate::scene::{AreaEmission, MeshDesc};
use crate::sensor::meter::connect::tests::read_direct_only;
use crate::sensor::meter::{ConnectedSettings, MeterPoint, Reading};
use crate::sensor::meter::{black_room, check_reading};

/// E/L at a point (x, z) facing up, under the parallel rectangle [x0, x1] × [z0, z1] (`rect`)
/// at height `h` above it, facing down: ½[X/√(1+X²)·atan(Y/√(1+X²)) + Y/√(1+Y²)·atan(X/√(1+Y²))]
/// (X = a/h, Y = b/h) from a point under a corner, odd in a and b, combined over the four
/// corners (tools/validation/cie171/closed_forms.py's closed form).
pub(in crate::sensor::meter) fn parallel_rectangle(h: f64, rect: [f64; 4], x: f64, z: f64) -> f64 {
    let f = |a: f64, b: f64| {
        let (x, y) = (a / h, b / h);
        let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
        0.5 * (x / sx * (y / sx).atan() + y / sy * (x / sy).atan())
    };
    let [x0, x1, z0, z1] = rect;
    f(x1 - x, z1 - z) - f(x0 - x, z1 - z) - f(x1 - x, z0 - z) + f(x0 - x, z0 - z)
}

/// The light's radiance, height and extent (CIE 171 5.3: 2 m × 1 m, 2 m up).
const L: f32 = 1.5;
const H: f32 = 2.0;
const LIGHT: [f32; 4] = [-1.0, 1.0, -0.5, 0.5];
/// The 5.7 obstruction: [0.1, 0.7] × [−0.3, 0.9] at 1.2 m.
const HO: f32 = 1.2;
const OCCLUDER: [f32; 4] = [0.1, 0.7, -0.3, 0.9];

/// A horizontal rectangle [x0, x1] × [z0, z1] at height y facing down (−y), of material 0.
fn facing_down(name: &str, y: f32, r: [f32; 4], emission: Option<Rgb>) -> MeshDesc {
    let [x0, x1, z0, z1] = r;
    MeshDesc {
        name: name.into(),
        positions: vec![
            Vec3::new(x0, y, z0),
            Vec3::new(x1, y, z0),
            Vec3::new(x1, y, z1),
            Vec3::new(x0, y, z1),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        emission: emission.map(AreaEmission::lambertian),
        ..Default::default()
    }
}

/// A black floor, the light "light" (and a second one, "other", of radiance `other` over
/// [2, 3] × [−0.5, 0.5] if given) and the black rectangles `blockers` at their heights.
fn scene_with(other: Option<f32>, blockers: &[(f32, [f32; 4])]) -> Scene {
    let mut meshes = vec![
        MeshDesc::square_at("floor".into(), 0.0, 0),
        facing_down("light", H, LIGHT, Some(Rgb::splat(L))),
    ];
    if let Some(l) = other {
        meshes.push(facing_down("other", H, [2.0, 3.0, -0.5, 0.5], Some(Rgb::splat(l))));
    }
    meshes.extend(blockers.iter().enumerate().map(|(k, &(y, r))| facing_down(&format!("b{k}"), y, r, None)));
    Scene::build(&black_room(meshes)).unwrap()
}

/// Every area light of `scene` on at its own power times `scale` (100 paths each).
fn on(scene: &Scene, scale: f32) -> RenderLights {
    let names: Vec<&str> = scene.lights.iter().map(|l| l.name()).collect();
    let flux: Vec<Rgb> = scene.lights.iter().map(|l| l.power() * scale / 100.0).collect();
    RenderLights::new(scene, &names, &flux, &vec![100; names.len()])
}

/// Floor points facing up: under the centre, a corner and an edge of the light, off its side,
/// far out; in 5.7's penumbra.
const POINTS: [(f32, f32); 8] =
    [(0.0, 0.0), (1.0, 0.5), (0.0, 0.5), (1.5, 0.0), (2.0, 2.0), (0.5, 0.0), (0.3, -0.5), (0.8, 0.6)];

fn points() -> MeterLayout {
    MeterLayout::points(
        POINTS.iter().map(|&(x, z)| MeterPoint::new(Vec3::new(x, 0.0, z), Vec3::Y).unwrap()).collect(),
    )
    .unwrap()
}

fn read(scene: &Scene, scale: f32, seed: u64, direct_samples: Option<u32>) -> Reading {
    let settings = ConnectedSettings { seed, direct_samples, ..Default::default() };
    read_direct_only(scene, &on(scene, scale), &points(), settings)
}

/// E at (x, z) from the light, with the parallel black rectangles `blockers` (each at height
/// y, below the light) between: what a blocker hides from P is its central projection from P
/// onto the light's plane (scaled by H/y about P), intersected with the light; E is additive
/// over the light's area. The hidden parts must not overlap (true of the cases here).
fn closed_form(x: f64, z: f64, blockers: &[(f32, [f32; 4])]) -> f64 {
    let h = H as f64;
    let light = LIGHT.map(|v| v as f64);
    let mut e = parallel_rectangle(h, light, x, z);
    for &(y, r) in blockers {
        let s = h / y as f64;
        let [x0, x1, z0, z1] = r.map(|v| v as f64);
        let hidden = [
            (x + (x0 - x) * s).max(light[0]),
            (x + (x1 - x) * s).min(light[1]),
            (z + (z0 - z) * s).max(light[2]),
            (z + (z1 - z) * s).min(light[3]),
        ];
        if hidden[0] < hidden[1] && hidden[2] < hidden[3] {
            e -= parallel_rectangle(h, hidden, x, z);
        }
    }
    L as f64 * e
}

/// Reads `scene` with default settings over `seeds` seeds: every point within max(1 %, 4 SE)
/// of the closed form with an SE of at most 1 %, and the mean over seeds within 4 of its SEs.
fn reads_its_closed_form(what: &str, scene: &Scene, blockers: &[(f32, [f32; 4])], seeds: u64) {
    let mut sums = [(0.0f64, 0.0f64); POINTS.len()];
    for seed in 0..seeds {
        let r = read(scene, 1.0, seed, None);
        for (k, &(x, z)) in POINTS.iter().enumerate() {
            let exact = closed_form(x as f64, z as f64, blockers);
            let (v, se2) = check_reading(what, seed, (x, z), (r.value[k][0], r.std_error[k][0]), exact);
            sums[k].0 += v;
            sums[k].1 += se2;
        }
    }
    for (k, &(x, z)) in POINTS.iter().enumerate() {
        let exact = closed_form(x as f64, z as f64, blockers);
        let (mean, se) = (sums[k].0 / seeds as f64, sums[k].1.sqrt() / seeds as f64);
        assert!((mean - exact).abs() <= 4.0 * se, "{what} ({x}, {z}): mean {mean} ± {se} vs {exact}");
    }
}

/// CIE 171 5.3: a Lambertian rectangle over a black floor, read from the points alone.
#[test]
fn a_rectangle_light_reads_its_closed_form() {
    reads_its_closed_form("5.3", &scene_with(None, &[]), &[], 4);
}

/// CIE 171 5.7: the rectangle behind a parallel black obstruction, points in its penumbra.
#[test]
fn an_obstructed_light_reads_its_closed_form() {
    let blockers = [(HO, OCCLUDER)];
    reads_its_closed_form("5.7", &scene_with(None, &blockers), &blockers, 4);
}

/// The light seen only through a small opening: a black sheet at 1.5 m with a 0.2 m × 0.1 m hole
/// (four rectangles around it, whose hidden parts do not overlap only if cut so: the closed
/// form takes the visible part directly, the opening projected onto the light).
#[test]
fn a_light_seen_through_a_small_opening_reads_its_closed_form() {
    let (y, hole) = (1.5f32, [0.1f32, 0.3, -0.05, 0.05]);
    let sheet = [
        (y, [-9.0, 9.0, -9.0, hole[2]]),
        (y, [-9.0, 9.0, hole[3], 9.0]),
        (y, [-9.0, hole[0], hole[2], hole[3]]),
        (y, [hole[1], 9.0, hole[2], hole[3]]),
    ];
    let scene = scene_with(None, &sheet);
    let opening = [(0.2f32, 0.0f32), (0.0, 0.0), (0.5, 0.2)];
    let layout = MeterLayout::points(
        opening.iter().map(|&(x, z)| MeterPoint::new(Vec3::new(x, 0.0, z), Vec3::Y).unwrap()).collect(),
    )
    .unwrap();
    let lights = on(&scene, 1.0);
    for seed in 0..3 {
        let r = read_direct_only(&scene, &lights, &layout, ConnectedSettings { seed, ..Default::default() });
        for (k, &(x, z)) in opening.iter().enumerate() {
            let (x, z) = (x as f64, z as f64);
            let s = H as f64 / y as f64;
            let seen = hole.map(|v| v as f64);
            let seen =
                [x + (seen[0] - x) * s, x + (seen[1] - x) * s, z + (seen[2] - z) * s, z + (seen[3] - z) * s];
            let exact = L as f64 * parallel_rectangle(H as f64, seen, x, z);
            let (v, se) = (r.value[k][0], r.std_error[k][0]);
            eprintln!("opening seed {seed} ({x}, {z}): {v} ± {se} vs {exact}");
            assert!(se > 0.0 && (v - exact).abs() <= 4.0 * se, "({x}, {z}): {v} ± {se} vs {exact}");
        }
    }
}

/// Relighting: every light scaled by s scales every reading and error by s (to rounding), with
/// the same sample count (the pilot's relative variance does not change); a light switched off
/// is not sampled (the other light alone reads as if it were the only one).
#[test]
fn relighting_scales_the_direct_term_exactly() {
    let scene = scene_with(Some(4.0), &[]);
    let (one, three) = (read(&scene, 1.0, 5, None), read(&scene, 3.0, 5, None));
    for k in 0..POINTS.len() {
        for c in 0..4 {
            let (a, b) = (one.value[k][c], three.value[k][c]);
            assert!((b - 3.0 * a).abs() <= 1e-6 * b, "{k}.{c}: {b} vs 3 × {a}");
            let (a, b) = (one.std_error[k][c], three.std_error[k][c]);
            assert!((b - 3.0 * a).abs() <= 1e-6 * b, "SE {k}.{c}: {b} vs 3 × {a}");
        }
    }
    let names = ["light", "other"];
    let own = |k: usize| scene.lights[scene.light_index(names[k]).unwrap()].power() / 100.0;
    let first_only = RenderLights::new(&scene, &names, &[own(0), Rgb::ZERO], &[100, 100]);
    let alone = scene_with(None, &[]);
    let settings = ConnectedSettings { seed: 2, ..Default::default() };
    let (a, b) = (
        read_direct_only(&scene, &first_only, &points(), settings),
        read_direct_only(&alone, &on(&alone, 1.0), &points(), settings),
    );
    assert_eq!(a, b, "a light switched off adds nothing, and changes nothing");
}

/// The stated error is the spread's: at a penumbra point, over 64 seeds at a fixed count, the
/// readings' standard deviation is the mean stated SE within the 4σ band of a 64-sample
/// standard deviation (±36 %).
#[test]
fn the_stated_error_is_the_spread_over_seeds() {
    let blockers = [(HO, OCCLUDER)];
    let scene = scene_with(None, &blockers);
    let lights = on(&scene, 1.0);
    let layout =
        MeterLayout::points(vec![MeterPoint::new(Vec3::new(0.3, 0.0, -0.5), Vec3::Y).unwrap()]).unwrap();
    let (mut values, mut se2) = (Vec::new(), 0.0);
    for seed in 0..64 {
        let settings = ConnectedSettings { seed, direct_samples: Some(64), ..Default::default() };
        let r = read_direct_only(&scene, &lights, &layout, settings);
        values.push(r.value[0][0]);
        se2 += r.std_error[0][0].powi(2);
    }
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let sd = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    let stated = (se2 / n).sqrt();
    eprintln!("spread {sd} vs stated {stated}");
    assert!((sd / stated - 1.0).abs() < 0.36, "spread {sd} vs stated {stated}");
}

/// An explicit count fixes the samples: fewer of them, a larger SE, the same expectation.
#[test]
fn an_explicit_count_fixes_the_area_samples() {
    let blockers = [(HO, OCCLUDER)];
    let scene = scene_with(None, &blockers);
    let (auto, fixed) = (read(&scene, 1.0, 1, None), read(&scene, 1.0, 1, Some(128)));
    for (k, &(x, z)) in POINTS.iter().enumerate() {
        let exact = closed_form(x as f64, z as f64, &blockers);
        let (v, se) = (fixed.value[k][0], fixed.std_error[k][0]);
        assert!(se > auto.std_error[k][0], "({x}, {z}): {se} vs {}", auto.std_error[k][0]);
        assert!((v - exact).abs() <= 4.0 * se, "({x}, {z}): {v} ± {se} vs {exact}");
    }
}

/// The strata tile the square: their areas sum to 1, n of them rounded down to even (1 for
/// n < 2), every row of an even number of columns (none straddles u.x = ½).
#[test]
fn the_strata_tile_the_square() {
    for n in [1u32, 2, 3, 7, 32, 128, 129, 1000] {
        let strata = Strata::new(n);
        let s: Vec<_> = strata.iter().collect();
        assert_eq!(s.len(), if n < 2 { 1 } else { (n - n % 2) as usize }, "{n}");
        assert_eq!(s.len(), strata.len() as usize);
        let area: f64 = s.iter().map(|(_, a)| a).sum();
        assert!((area - 1.0).abs() < 1e-12, "{n}: {area}");
        for ((x, y, w, h), a) in s {
            assert!(x >= 0.0 && y >= 0.0 && x + w <= 1.0 + 1e-6 && y + h <= 1.0 + 1e-6);
            assert!(((w * h) as f64 - a).abs() < 1e-6);
            assert!(n < 2 || x >= 0.5 || x + w <= 0.5 + 1e-6, "{n}: a stratum straddles ½");
        }
    }
}
