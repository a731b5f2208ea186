//! Tests of the sky's direct term at meter targets: the guide, the pilot, the stratified
//! estimate and its error, against the closed form of a roof opening under a uniform sky.

use super::*;
use crate::scene::{EnvironmentLightDesc, EnvironmentRadiance, MeshDesc, SceneDescription};
use crate::sensor::meter::area::tests::parallel_rectangle;
use crate::sensor::meter::connect::tests::read_direct_only;
use crate::sensor::meter::{ConnectedSettings, MeterPoint, Reading};
use crate::sensor::meter::{black_room, check_reading};

#[test]
fn the_square_of_a_direction_inverts_the_cosine_map() {
    let mut rng = RandomStream::new(1, &[2]);
    for _ in 0..100_000 {
        let u = rng.next_2d();
        let back = square_of_local(square_to_cosine_hemisphere(u));
        assert!((back - u).abs().max_element() < 2e-4, "{u} -> {back}");
    }
}

/// A guide with uneven weights (a quarter of the bins 0) around a tilted normal.
fn uneven_guide() -> Guide {
    let mut rng = RandomStream::new(3, &[4]);
    let weights: Vec<f64> =
        (0..BINS).map(|_| if rng.next_f32() < 0.25 { 0.0 } else { (8.0 * rng.next_f32()) as f64 }).collect();
    Guide::new(Vec3::new(0.3, 0.8, -0.5).normalize(), &weights).unwrap()
}

/// The guide's density integrates to 1 over the sphere (a midpoint rule in world θ, φ,
/// whose cells straddle the bins' borders: hence the tolerance), and its samples fall into
/// 8 × 16 world regions as its density says (χ²), each with the density it reports.
#[test]
fn the_guide_is_a_density_its_samples_follow() {
    let g = uneven_guide();
    let (nt, np) = (8 * 150, 16 * 150);
    let (dt, dp) = (PI / nt as f64, 2.0 * PI / np as f64);
    let dir =
        |t: f64, p: f64| Vec3::new((t.sin() * p.cos()) as f32, t.cos() as f32, (t.sin() * p.sin()) as f32);
    let mut region = vec![0.0f64; 8 * 16];
    for i in 0..nt {
        let t = (i as f64 + 0.5) * dt;
        for j in 0..np {
            let p = (j as f64 + 0.5) * dp;
            region[(i / 150) * 16 + j / 150] += g.pdf(dir(t, p)) * t.sin() * dt * dp;
        }
    }
    let total: f64 = region.iter().sum();
    assert!((total - 1.0).abs() < 2e-3, "∫p dω = {total}");
    let n = 400_000;
    let mut counts = vec![0u64; 8 * 16];
    let mut rng = RandomStream::new(5, &[6]);
    let mut mismatched = 0;
    for _ in 0..n {
        let (omega, pdf) = g.sample(rng.next_f64(), rng.next_f32());
        assert!(pdf > 0.0 && (omega.length() - 1.0).abs() < 1e-5);
        if (g.pdf(omega) / pdf - 1.0).abs() > 1e-3 {
            mismatched += 1; // a direction rounded across a bin border
        }
        let t = (omega.y as f64).clamp(-1.0, 1.0).acos();
        let p = (omega.z as f64).atan2(omega.x as f64).rem_euclid(2.0 * PI);
        let (i, j) = (((t / PI * 8.0) as usize).min(7), ((p / (2.0 * PI) * 16.0) as usize).min(15));
        counts[i * 16 + j] += 1;
    }
    assert!(mismatched < n / 1000, "{mismatched} samples whose pdf differs from the drawn one");
    let (mut chi2, mut dof) = (0.0, 0usize);
    for (c, p) in counts.iter().zip(&region) {
        let expected = p * n as f64;
        if expected > 20.0 {
            chi2 += (*c as f64 - expected).powi(2) / expected;
            dof += 1;
        } else {
            assert!(
                (*c as f64) < expected + 5.0 * expected.sqrt() + 5.0,
                "{c} where {expected} were expected"
            );
        }
    }
    let dof = dof as f64 - 1.0;
    assert!(chi2 < dof + 5.0 * (2.0 * dof).sqrt(), "χ² {chi2} for {dof} degrees of freedom");
}

/// Height of the box's roof; the roof's opening [X0, X1] × [Z0, Z1].
const H: f32 = 3.0;
const OPENING: [f32; 4] = [-0.4, 0.4, -0.2, 0.3];

/// A closed black box (x, z ∈ [−2, 2], y ∈ [0, H]) with a rectangular opening in its roof,
/// under a uniform sky of radiance 1.
fn roof_box() -> Scene {
    let quad = |name: &str, c: [Vec3; 4]| MeshDesc {
        name: name.into(),
        positions: c.to_vec(),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material: 0,
        ..Default::default()
    };
    // A horizontal rectangle at height y.
    let flat = |name: &str, y: f32, x0: f32, x1: f32, z0: f32, z1: f32| {
        quad(name, [Vec3::new(x0, y, z0), Vec3::new(x0, y, z1), Vec3::new(x1, y, z1), Vec3::new(x1, y, z0)])
    };
    let [x0, x1, z0, z1] = OPENING;
    let c = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let meshes = vec![
        flat("floor", 0.0, -2.0, 2.0, -2.0, 2.0),
        flat("roof south", H, -2.0, 2.0, -2.0, z0),
        flat("roof north", H, -2.0, 2.0, z1, 2.0),
        flat("roof west", H, -2.0, x0, z0, z1),
        flat("roof east", H, x1, 2.0, z0, z1),
        quad("wall -x", [c(-2.0, 0.0, -2.0), c(-2.0, H, -2.0), c(-2.0, H, 2.0), c(-2.0, 0.0, 2.0)]),
        quad("wall +x", [c(2.0, 0.0, -2.0), c(2.0, 0.0, 2.0), c(2.0, H, 2.0), c(2.0, H, -2.0)]),
        quad("wall -z", [c(-2.0, 0.0, -2.0), c(2.0, 0.0, -2.0), c(2.0, H, -2.0), c(-2.0, H, -2.0)]),
        quad("wall +z", [c(-2.0, 0.0, 2.0), c(-2.0, H, 2.0), c(2.0, H, 2.0), c(2.0, 0.0, 2.0)]),
    ];
    let desc = SceneDescription {
        environment_lights: vec![EnvironmentLightDesc {
            name: "sky".into(),
            source: Default::default(),
            radiance: EnvironmentRadiance::Constant(Rgb::ONE),
            to_world: glam::Mat3::IDENTITY,
            sky: None,
        }],
        ..black_room(meshes)
    };
    Scene::build(&desc).unwrap()
}

/// The irradiance at a floor point (x, z) from the opening under a sky of radiance 1: the
/// parallel rectangle's configuration factor (times π).
fn closed_form(x: f64, z: f64) -> f64 {
    parallel_rectangle(H as f64, OPENING.map(|v| v as f64), x, z)
}

/// Floor points (x, z): under the opening, under its corner, off to the side, near a corner
/// of the room.
const FLOOR: [(f32, f32); 4] = [(0.0, 0.0), (0.4, -0.2), (1.3, 0.9), (-1.8, -1.5)];

/// The box's meter points: [`FLOOR`]'s, then one facing the floor.
fn box_points() -> MeterLayout {
    let mut points: Vec<MeterPoint> =
        FLOOR.iter().map(|&(x, z)| MeterPoint::new(Vec3::new(x, 0.0, z), Vec3::Y).unwrap()).collect();
    // Facing the floor: it sees no sky.
    points.push(MeterPoint::new(Vec3::new(0.0, 1.0, 0.0), Vec3::NEG_Y).unwrap());
    MeterLayout::points(points).unwrap()
}

/// The box's sky, on at its own power.
fn box_lights(scene: &Scene) -> RenderLights {
    let power = scene.lights[0].power();
    RenderLights::new(scene, &["sky"], &[power / 100.0], &[100])
}

/// The box's points read with meter seed `seed` and `direct_samples`, no stored samples.
fn read_box(scene: &Scene, seed: u64, direct_samples: Option<u32>) -> Reading {
    let layout = box_points();
    let lights = box_lights(scene);
    let settings = ConnectedSettings { direct_samples, seed, ..Default::default() };
    read_direct_only(scene, &lights, &layout, settings)
}

/// Default settings read the sky through a small roof opening within max(1 %, 4 SE) of the
/// closed form with an SE of at most 1 %; the point facing the floor reads 0 ± 0; the mean
/// over seeds agrees with the closed form within 4 of its SEs (no bias the single readings'
/// tolerance could hide); a reading does not depend on the thread count.
#[test]
fn the_sky_through_a_roof_opening_reads_its_closed_form_by_default() {
    let scene = roof_box();
    let seeds = 8;
    let mut sums = [(0.0f64, 0.0f64); FLOOR.len()];
    for seed in 0..seeds {
        let r = read_box(&scene, seed, None);
        for (k, &(x, z)) in FLOOR.iter().enumerate() {
            let exact = closed_form(x as f64, z as f64);
            let (v, se2) = check_reading("sky", seed, (x, z), (r.value[k][1], r.std_error[k][1]), exact);
            sums[k].0 += v;
            sums[k].1 += se2;
        }
        assert_eq!((r.value[4], r.std_error[4]), ([0.0; 4], [0.0; 4]), "facing the floor");
    }
    for (k, &(x, z)) in FLOOR.iter().enumerate() {
        let exact = closed_form(x as f64, z as f64);
        let (mean, se) = (sums[k].0 / seeds as f64, sums[k].1.sqrt() / seeds as f64);
        assert!((mean - exact).abs() <= 4.0 * se, "({x}, {z}): mean {mean} ± {se} vs {exact}");
    }
    let on = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| read_box(&scene, 7, None))
    };
    let (one, two) = (on(1), on(2));
    assert_eq!((one.value, one.std_error), (two.value, two.std_error));
}

/// The fresh samples are stratified in pairs (module docs, 2): at a point under the opening's
/// corner, over 48 seeds of 512 samples, the readings' errors against the closed form in
/// units of their own standard errors have a mean square near 1 (the pairs' variance is
/// honest: neither too small, which would overstate the precision, nor far too large), and
/// the standard error is well below what as many independent draws of the mixture give
/// (√(V/n), V the pilot's one-sample variance: the strata do their work).
#[test]
fn the_stratified_sky_samples_report_an_honest_error_below_independent_draws() {
    let scene = roof_box();
    let (layout, lights) = (box_points(), box_lights(&scene));
    let sky = Sky::new(&scene, &lights).unwrap();
    let (x, z) = FLOOR[1];
    let exact = closed_form(x as f64, z as f64);
    let (seeds, n) = (48u64, 512u32);
    let (mut z2, mut ratio) = (0.0, 0.0);
    for seed in 0..seeds {
        let (mix, wanted, _) = sky.pilot(&layout, 1, (coarse_side(SIDE), SIDE), seed, &|| false).unwrap();
        let (v, se) = sky.estimate(&layout, 1, &mix, n, seed, &|| false).unwrap();
        z2 += ((v[1] - exact) / se[1]).powi(2);
        // The pilot's count for 0.5 % is V/(0.005·μ)², so √(V/n) = 0.005·μ·√(wanted/n).
        ratio += se[1] / (budget::TARGET_RELATIVE_SE * exact * (wanted / n as f64).sqrt());
    }
    let (z2, ratio) = (z2 / seeds as f64, ratio / seeds as f64);
    eprintln!("mean z² {z2:.3}, SE ÷ independent draws' {ratio:.3}");
    assert!((0.55..1.7).contains(&z2), "mean z² {z2}");
    assert!(ratio < 0.75, "SE ÷ independent draws' {ratio}");
}

/// An explicit count fixes the samples: fewer of them, a larger SE, the same expectation.
#[test]
fn an_explicit_count_fixes_the_sky_samples() {
    let scene = roof_box();
    let (auto, fixed) = (read_box(&scene, 1, None), read_box(&scene, 1, Some(300)));
    for (k, &(x, z)) in FLOOR.iter().enumerate() {
        let exact = closed_form(x as f64, z as f64);
        let (v, se) = (fixed.value[k][1], fixed.std_error[k][1]);
        assert!(se > auto.std_error[k][1], "({x}, {z}): {se} vs {}", auto.std_error[k][1]);
        assert!((v - exact).abs() <= 4.0 * se, "({x}, {z}): {v} ± {se} vs {exact}");
    }
}

/// The defensive component is what keeps a guide that misses part of the sky unbiased: with
/// the pilot's guide cut to the half-square i < SIDE/2 (half of the opening above (0, 0)),
/// α = ALPHA still reads the closed form within 4 SE, α = 0 reads about half of it.
#[test]
fn the_defensive_component_covers_what_the_guide_misses() {
    let scene = roof_box();
    let (layout, lights) = (box_points(), box_lights(&scene));
    let sky = Sky::new(&scene, &lights).unwrap();
    let (mix, _, _) = sky.pilot(&layout, 0, (coarse_side(SIDE), SIDE), 0, &|| false).unwrap();
    let mut cut = mix.guide.unwrap().prob;
    for (b, w) in cut.iter_mut().enumerate() {
        if b % SIDE >= SIDE / 2 {
            *w = 0.0;
        }
    }
    let exact = closed_form(0.0, 0.0);
    let read = |alpha| {
        let mix = Mixture { guide: Guide::new(Vec3::Y, &cut), alpha };
        let (v, se) = sky.estimate(&layout, 0, &mix, 1 << 20, 0, &|| false).unwrap();
        (v[1], se[1])
    };
    let (v, se) = read(ALPHA);
    eprintln!("α = {ALPHA}: {v} ± {se} vs {exact}");
    assert!((v - exact).abs() < 4.0 * se && se < 0.1 * exact, "α = {ALPHA}: {v} ± {se} vs {exact}");
    let (v, se) = read(0.0);
    eprintln!("α = 0: {v} ± {se} vs {exact}");
    assert!(v < 0.7 * exact && exact - v > 10.0 * se, "α = 0: {v} ± {se} vs {exact}");
}

/// The pilot of a 100 × 100-cell plane over the box's floor traces at most PILOT_BUDGET
/// directions in all (16² bins a cell, not 64², and fewer than one pass over them: the
/// opening is a small part of each cell's sky); a meter of few targets keeps the full grid;
/// the largest meter stays within the budget at the floor.
#[test]
fn the_pilot_of_a_large_meter_is_bounded() {
    assert_eq!((pilot_side(1), pilot_side(100), pilot_side(800)), (SIDE, SIDE, SIDE));
    assert_eq!(pilot_side(10_000), 16);
    let most = crate::sensor::meter::MAX_TARGETS;
    assert!(pilot_side(most) == MIN_PILOT_SIDE);
    assert!((PILOT_PER_BIN * MIN_PILOT_SIDE * MIN_PILOT_SIDE * most) as u64 <= PILOT_BUDGET);
    let scene = roof_box();
    let lights = box_lights(&scene);
    let sky = Sky::new(&scene, &lights).unwrap();
    let grid = crate::sensor::meter::IlluminanceMeter::new(
        Vec3::new(-2.0, 0.0, 2.0),
        Vec3::X * 4.0,
        Vec3::Z * -4.0,
        100,
        100,
    )
    .unwrap();
    let layout = MeterLayout::Grid(grid);
    let side = pilot_side(layout.len());
    let total: u64 = (0..layout.len())
        .map(|t| sky.pilot(&layout, t, (coarse_side(side), side), 0, &|| false).unwrap().2 as u64)
        .sum();
    assert!(total <= PILOT_BUDGET, "{total} pilot directions");
    assert!(total < (layout.len() * PILOT_PER_BIN * 16 * 16) as u64, "{total}: not fewer than one pass");
}

/// The two-pass pilot (module docs, 1) traces under 60 % of the one pass's directions at
/// the box's floor points, which see the sky through the opening only, and its guide aims
/// as well: the fresh samples' SE at a fixed count is within 10 % of the one-pass guide's (a
/// coarse pass that missed part of the opening would leave it to the defensive component,
/// at a far larger SE).
#[test]
fn the_two_pass_pilot_traces_less_and_aims_as_well() {
    let scene = roof_box();
    let (layout, lights) = (box_points(), box_lights(&scene));
    let sky = Sky::new(&scene, &lights).unwrap();
    for (k, &(x, z)) in FLOOR.iter().enumerate() {
        let (one, _, one_drawn) = sky.pilot(&layout, k, (SIDE, SIDE), 0, &|| false).unwrap();
        let (two, _, two_drawn) = sky.pilot(&layout, k, (coarse_side(SIDE), SIDE), 0, &|| false).unwrap();
        let se = |mix: &Mixture| sky.estimate(&layout, k, mix, 1 << 16, 1, &|| false).unwrap().1[1];
        let (se_one, se_two) = (se(&one), se(&two));
        eprintln!("({x}, {z}): {two_drawn} vs {one_drawn} directions, SE {se_two} vs {se_one}");
        assert!((two_drawn as f64) < 0.6 * one_drawn as f64, "({x}, {z}): {two_drawn} vs {one_drawn}");
        assert!(se_two < 1.1 * se_one, "({x}, {z}): SE {se_two} vs {se_one}");
    }
}

/// A coarse pilot (the floor's 8² bins) still reads the closed form at the box's points
/// within max(1 %, 4 SE): its guide is coarser, the estimate as unbiased.
#[test]
fn a_coarse_pilot_still_reads_the_closed_form() {
    let scene = roof_box();
    let (layout, lights) = (box_points(), box_lights(&scene));
    let sky = Sky::new(&scene, &lights).unwrap();
    for (k, &(x, z)) in FLOOR.iter().enumerate() {
        let (mix, wanted, drawn) =
            sky.pilot(&layout, k, (MIN_PILOT_SIDE, MIN_PILOT_SIDE), 0, &|| false).unwrap();
        assert_eq!(drawn as usize, PILOT_PER_BIN * MIN_PILOT_SIDE * MIN_PILOT_SIDE);
        let n = budget::count(None, wanted, budget::MAX_SAMPLES);
        let (v, se) = sky.estimate(&layout, k, &mix, n, 0, &|| false).unwrap();
        let (v, se, exact) = (v[1], se[1], closed_form(x as f64, z as f64));
        eprintln!("coarse ({x}, {z}): {v} ± {se} vs {exact}, {n} samples");
        assert!((v - exact).abs() <= (4.0 * se).max(0.01 * exact), "({x}, {z}): {v} ± {se} vs {exact}");
    }
}
