//! Analytic cases: scenes whose answer is known in closed form, so a wrong weight, a missing
//! cosine or a biased roulette shows up as a number that does not match.
//!
//! Tolerances are statistical: each check compares against the standard error it measures
//! (4σ) or against a noise level estimated from the path count, stated next to it.

mod common;

use common::*;
use opticks_core::math::{Rgb, Vec3};
use opticks_core::sampling::RandomStream;
use opticks_core::scene::{CameraDesc, Pinhole, PointLightDesc, Scene, SceneDescription};
use opticks_core::trace::{TraceSettings, trace_path};
use std::f64::consts::PI;

/// furnace/SCENE.md: in the closed grey room (ρ = 0.5) the flux incident on all surfaces over all
/// bounces is Φ/(1−ρ) = 2.513274 W, and the first bounce puts 0.2986325 W on the floor (exact
/// view factor). Per-path sums of Φ·β are independent, so their standard error is measured.
#[test]
fn furnace_energy_balance() {
    let scene = load("furnace");
    let phi = scene.lights[0].power().x as f64;
    assert!((phi - 0.4 * PI).abs() < 1e-5, "Φ = π·L·A = 0.4π, got {phi}");
    let paths = 1_000_000;
    let mut rng = RandomStream::new(11, &[]);
    let mut out = Vec::new();
    let mut stack = Vec::new();
    let settings = TraceSettings::default();
    let mut totals = Vec::with_capacity(paths);
    let mut first_on_floor = Vec::with_capacity(paths);
    for _ in 0..paths {
        out.clear();
        trace_path(&scene, 0, &settings, &mut rng, &mut out, &mut stack);
        assert!(out[0].is_emission());
        totals.push(out[1..].iter().map(|s| phi * s.beta[0] as f64).sum::<f64>());
        first_on_floor.push(if out.len() > 1 && out[1].position[1].abs() < 1e-4 { phi } else { 0.0 });
    }
    let (total, err) = mean_and_error(&totals);
    let expected = phi / (1.0 - 0.5);
    eprintln!("incident flux {total:.5} ± {err:.5} W, expected {expected:.6}");
    assert!((total - expected).abs() < 4.0 * err, "total incident flux {total} ± {err}, expected {expected}");
    assert!((total / expected - 1.0).abs() < 0.005);
    let (floor, err) = mean_and_error(&first_on_floor);
    eprintln!("first-bounce floor flux {floor:.5} ± {err:.5} W, expected 0.2986325");
    assert!((floor - 0.2986325).abs() < 4.0 * err, "first-bounce floor flux {floor} ± {err}");
}

/// A closed box whose every face emits L_e (inward) and reflects with albedo ρ: the radiance
/// everywhere inside, in every direction, is L_e/(1−ρ). Exercises emission vertices, every
/// bounce order and Russian roulette at once.
#[test]
fn emissive_furnace_is_uniform() {
    let (le, rho) = (1.0f32, 0.8f32);
    let desc = emissive_furnace(le, rho, Some(furnace_view(100.0, 32, 32)));
    let scene = Scene::build(&desc).unwrap();
    let cam = camera(&scene);
    let film = trace_and_render(&scene, &cam, 2_000_000, 3);
    let expected = (le / (1.0 - rho)) as f64;
    assert_uniform("mean radiance", &film, expected);
}

/// Radiance of a Lambertian plane lit by a point light of intensity I at height h:
/// L = ρ·I·cosθ/(π·d²) with cosθ = h/d (inverse-square law and Lambert's cosine law).
#[test]
fn point_light_over_lambertian_plane() {
    let (rho, intensity, h) = (0.6f32, 2.0f32, 1.0f32);
    let s = 50.0;
    let plane = quad(
        "plane",
        [Vec3::new(-s, 0.0, -s), Vec3::new(-s, 0.0, s), Vec3::new(s, 0.0, s), Vec3::new(s, 0.0, -s)],
        0,
        None,
    );
    let light_pos = Vec3::new(0.1, h, -0.2);
    let cam_desc = CameraDesc {
        eye: Vec3::new(0.4, 2.5, 0.6),
        target: Vec3::new(0.0, 0.0, 0.0),
        up: Vec3::new(0.0, 0.0, -1.0),
        fov_x_degrees: 70.0,
        width: 48,
        height: 40,
    };
    let desc = SceneDescription {
        materials: vec![lambert("plane", rho, false)],
        meshes: vec![plane],
        point_lights: vec![PointLightDesc {
            name: "bulb".into(),
            source: Default::default(),
            position: light_pos,
            intensity: Rgb::splat(intensity),
            ..Default::default()
        }],
        camera: Some(cam_desc),
        ..Default::default()
    };
    let scene = Scene::build(&desc).unwrap();
    let cam = Pinhole::new(&cam_desc).unwrap();
    let film = trace_and_render(&scene, &cam, 4_000_000, 5);

    // Expected pixel values: the radiance averaged over the pixel's film square (8×8 points).
    let radiance = |sx: f32, sy: f32| {
        let d = cam.direction(sx, sy);
        let t = -cam.eye.y / d.y;
        let x = cam.eye + t * d;
        let to_light = light_pos - x;
        let dist2 = to_light.length_squared() as f64;
        rho as f64 * intensity as f64 * (h as f64 / dist2.sqrt()) / (PI * dist2)
    };
    let (w, hgt) = (cam.width as usize, cam.height as usize);
    let expected: Vec<f64> = (0..w * hgt)
        .map(|p| {
            let (i, j) = (p % w, p / w);
            let mut sum = 0.0;
            for a in 0..8 {
                for b in 0..8 {
                    sum += radiance(
                        (i as f32 + (a as f32 + 0.5) / 8.0) / w as f32,
                        (j as f32 + (b as f32 + 0.5) / 8.0) / hgt as f32,
                    );
                }
            }
            sum / 64.0
        })
        .collect();
    let got: Vec<f64> = film.pixels.iter().map(|p| p[0]).collect();
    let (sg, se): (f64, f64) = (got.iter().sum(), expected.iter().sum());
    eprintln!("image mean ratio {:.5}", sg / se);
    assert!((sg / se - 1.0).abs() < 0.005, "image mean ratio {}", sg / se);
    // 8×8-pixel blocks (≈ 30k connections each → ~0.6% noise): the falloff must match everywhere.
    for by in 0..hgt / 8 {
        for bx in 0..w / 8 {
            let idx = |p: &dyn Fn(usize) -> f64| {
                (0..64).map(|k| p((by * 8 + k / 8) * w + bx * 8 + k % 8)).sum::<f64>()
            };
            let r = idx(&|p| got[p]) / idx(&|p| expected[p]);
            assert!((r - 1.0).abs() < 0.03, "block ({bx},{by}) ratio {r}");
        }
    }
}

/// A Lambertian emitter seen directly: pixels it covers read exactly its radiance L (which is
/// Φ/(π·A)); pixels beside it read zero; seen from behind (one-sided) it is black.
#[test]
fn lambertian_emitter_reads_its_radiance() {
    let l = Rgb::new(3.0, 2.0, 0.5);
    let scene = Scene::build(&emitting_panel(l)).unwrap();
    let area = 1.0f32;
    assert!((scene.lights[0].power() - std::f32::consts::PI * l * area).abs().max_element() < 1e-5);
    let view = |eye: Vec3| {
        Pinhole::new(&CameraDesc {
            eye,
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_x_degrees: 40.0,
            width: 32,
            height: 32,
        })
        .unwrap()
    };
    let front = view(Vec3::new(0.3, 0.2, 2.0));
    let film = trace_and_render(&scene, &front, 2_000_000, 9);
    let (mut inside, mut n_inside) = (glam::DVec3::ZERO, 0);
    for (p, v) in film.pixels.iter().enumerate() {
        let (i, j) = (p % 32, p / 32);
        // Classify the pixel by its four corners' rays hitting the panel.
        let hits = corners_on_panel(&front, p);
        if hits == 4 {
            inside += glam::DVec3::from_array(*v);
            n_inside += 1;
        } else if hits == 0 {
            assert_eq!(*v, [0.0; 3], "pixel ({i},{j}) off the panel must be black");
        }
    }
    let mean = inside / n_inside as f64;
    eprintln!("{n_inside} pixels on the panel: mean {mean:?}, expected {l:?}");
    assert!(n_inside > 100);
    for c in 0..3 {
        assert!((mean[c] / l[c] as f64 - 1.0).abs() < 0.01, "channel {c}: {} vs {}", mean[c], l[c]);
    }
    let back = trace_and_render(&scene, &view(Vec3::new(0.3, 0.2, -2.0)), 200_000, 9);
    assert!(back.pixels.iter().all(|p| *p == [0.0; 3]), "a one-sided emitter is black from behind");
}
