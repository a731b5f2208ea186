//! Analytic cases: scenes whose answer is known in closed form, so a wrong weight, a missing
//! cosine or a biased roulette shows up as a number that does not match.
//!
//! Tolerances are statistical: each check compares against the standard error it measures
//! (4σ) or against a noise level estimated from the path count, stated next to it.

use opticks_testkit as common;

use common::*;
use opticks_core::bsdf::{Bsdf, Material, ModifiedPhong};
use opticks_core::math::{Rgb, Vec3};
use opticks_core::sampling::RandomStream;
use opticks_core::scene::{CameraDesc, CameraKind, Scene, SceneDescription};
use opticks_core::sensor::Pinhole;
use opticks_core::trace::{PathScratch, TraceSettings, trace_path};
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
    let mut stack = PathScratch::default();
    let settings = TraceSettings::default();
    let mut totals = Vec::with_capacity(paths);
    let mut first_on_floor = Vec::with_capacity(paths);
    for _ in 0..paths {
        out.clear();
        trace_path(&scene, 0, &settings, &mut rng, &mut out, &mut Vec::new(), &mut stack);
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

/// The emissive furnace with the bidirectional estimator (every strategy, n_c = 2).
#[test]
fn emissive_furnace_is_uniform_bidirectional() {
    let (le, rho) = (1.0f32, 0.8f32);
    let desc = emissive_furnace(le, rho, Some(furnace_view(100.0, 32, 32)));
    let scene = Scene::build(&desc).unwrap();
    let (table, chunks) = trace_chunks(&scene, 200_000, 3);
    let film = render_bidirectional(&scene, camera(&scene).into(), &table, &chunks, true, 256, 2, 3);
    assert_uniform("mean radiance (bidirectional)", &film, (le / (1.0 - rho)) as f64);
}

/// Radiance of a Lambertian plane lit by a point light of intensity I at height h:
/// L = ρ·I·cosθ/(π·d²) with cosθ = h/d (inverse-square law and Lambert's cosine law).
#[test]
fn point_light_over_lambertian_plane() {
    let rho = 0.6;
    let material = lambert("plane", rho as f32, false);
    point_light_over_plane(material, &|_, _| rho / PI, false);
}

/// The same plane with the bidirectional estimator (NEE, connections, splats under MIS).
#[test]
fn point_light_over_lambertian_plane_bidirectional() {
    let rho = 0.6;
    let material = lambert("plane", rho as f32, false);
    point_light_over_plane(material, &|_, _| rho / PI, true);
}

/// The same plane with the Modified Phong BRDF (a glossy highlight in view): every pixel reads
/// L = f_r(ω_light, ω_camera)·I·cosθ/d², with f_r = kd/π + ks·(n+2)/(2π)·cosⁿα written out here
/// independently of the renderer's BSDF code. Checks the sensor's BRDF evaluation end to end.
#[test]
fn point_light_over_phong_plane() {
    let (kd, ks, n) = (0.25, 0.6, 30.0);
    let phong = ModifiedPhong::new(Rgb::splat(kd as f32), Rgb::splat(ks as f32), n as f32).unwrap();
    let material = Material { name: "plane".into(), bsdf: Bsdf::ModifiedPhong(phong), two_sided: false };
    point_light_over_plane(
        material,
        &|to_light, to_camera| phong_brdf(kd, ks, n, to_light, to_camera),
        false,
    );
}

/// The Phong plane with the bidirectional estimator: its glossy highlight is where NEE, the
/// connections and the splats differ most, so their weights must sum to one there.
#[test]
fn point_light_over_phong_plane_bidirectional() {
    let (kd, ks, n) = (0.25, 0.6, 30.0);
    let phong = ModifiedPhong::new(Rgb::splat(kd as f32), Rgb::splat(ks as f32), n as f32).unwrap();
    let material = Material { name: "plane".into(), bsdf: Bsdf::ModifiedPhong(phong), two_sided: false };
    point_light_over_plane(material, &|to_light, to_camera| phong_brdf(kd, ks, n, to_light, to_camera), true);
}

/// f_r of the Modified Phong BRDF on the plane y = 0 (normal +y), for unit directions towards
/// the light and towards the viewer.
fn phong_brdf(kd: f64, ks: f64, n: f64, to_light: [f64; 3], to_viewer: [f64; 3]) -> f64 {
    let mirror = [-to_light[0], to_light[1], -to_light[2]];
    let cos_alpha = mirror[0] * to_viewer[0] + mirror[1] * to_viewer[1] + mirror[2] * to_viewer[2];
    kd / PI + ks * (n + 2.0) / (2.0 * PI) * cos_alpha.max(0.0).powf(n)
}

/// A point light of intensity I at height h over the plane y = 0 made of `material`, seen by a
/// camera: pixel values must equal the radiance f_r·I·cosθ/d² averaged over each pixel's film
/// square (8×8 points), as a whole and in every 8×8-pixel block. `brdf(to_light, to_camera)`.
/// `bidirectional`: rendered by the bidirectional estimator (500 k paths, 64 camera paths per
/// pixel) instead of the light estimator (4 M paths).
fn point_light_over_plane(material: Material, brdf: &dyn Fn([f64; 3], [f64; 3]) -> f64, bidirectional: bool) {
    let (intensity, h) = (2.0f32, 1.0f32);
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
        kind: CameraKind::Perspective,
        film: Default::default(),
    };
    let desc = SceneDescription {
        materials: vec![material],
        meshes: vec![plane],
        point_lights: vec![point_light("bulb", light_pos, Rgb::splat(intensity))],
        camera: Some(cam_desc),
        ..Default::default()
    };
    let scene = Scene::build(&desc).unwrap();
    let cam = Pinhole::new(&cam_desc).unwrap();
    let film = if bidirectional {
        // Measured image mean ratio over 12 seeds: 0.99922 ± 0.0014 (σ of one seed), NEE
        // alone 0.99986; worst 8×8 block 1.5–2.8%.
        let (table, chunks) = trace_chunks(&scene, 500_000, 5);
        render_bidirectional(&scene, cam.into(), &table, &chunks, true, 64, 1, 5)
    } else {
        trace_and_render(&scene, &cam, 4_000_000, 5)
    };

    let unit = |v: Vec3| {
        let v = v.as_dvec3().normalize();
        [v.x, v.y, v.z]
    };
    let radiance = |sx: f32, sy: f32| {
        let d = cam.direction(sx, sy);
        let t = -cam.eye.y / d.y;
        let x = cam.eye + t * d;
        let to_light = light_pos - x;
        let dist2 = to_light.length_squared() as f64;
        let cos_theta = h as f64 / dist2.sqrt();
        brdf(unit(to_light), unit(cam.eye - x)) * intensity as f64 * cos_theta / dist2
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
    let mut worst = 0.0f64;
    for by in 0..hgt / 8 {
        for bx in 0..w / 8 {
            let idx = |p: &dyn Fn(usize) -> f64| {
                (0..64).map(|k| p((by * 8 + k / 8) * w + bx * 8 + k % 8)).sum::<f64>()
            };
            let r = idx(&|p| got[p]) / idx(&|p| expected[p]);
            worst = worst.max((r - 1.0).abs());
            assert!((r - 1.0).abs() < 0.03, "block ({bx},{by}) ratio {r}");
        }
    }
    eprintln!("worst 8×8 block deviation {worst:.4}");
}

/// A point light in a closed box whose walls are black and whose floor is Modified Phong: the
/// flux incident on all surfaces is Φ (first hits) plus the flux the floor reflects, which is
/// ∫ E(x)·a(θ(x)) dA with a(θ) the BRDF's directional albedo. Both integrals are evaluated here by
/// quadrature of the closed-form BRDF; the tracer gets the second term only through its sampled
/// weights f·cosθ/pdf, so a sampling density that disagreed with the BRDF would show.
#[test]
fn phong_floor_reflects_its_directional_albedo() {
    let (kd, ks, n) = (0.2, 0.7, 12.0);
    let phong = ModifiedPhong::new(Rgb::splat(kd as f32), Rgb::splat(ks as f32), n as f32).unwrap();
    let mut meshes = inward_box(Vec3::splat(-1.0), Vec3::splat(1.0), 1, None);
    meshes[0].material = 0; // the floor, y = −1
    let light = Vec3::new(0.2, -0.4, 0.1);
    let intensity = 1.5f32;
    let desc = SceneDescription {
        materials: vec![
            Material { name: "phong".into(), bsdf: Bsdf::ModifiedPhong(phong), two_sided: false },
            lambert("black", 0.0, false),
        ],
        meshes,
        point_lights: vec![point_light("bulb", light, Rgb::splat(intensity))],
        ..Default::default()
    };
    let scene = Scene::build(&desc).unwrap();
    let phi = scene.lights[0].power().x as f64;

    // Directional albedo a(cosθ) by midpoint quadrature over the hemisphere (cosθ_o, φ_o).
    let albedo = |cos_i: f64| {
        let to_light = [(1.0 - cos_i * cos_i).sqrt(), cos_i, 0.0];
        let (m, k) = (400, 400);
        let mut sum = 0.0;
        for a in 0..m {
            let cos_o = (a as f64 + 0.5) / m as f64;
            let sin_o = (1.0 - cos_o * cos_o).sqrt();
            for b in 0..k {
                let phi_o = 2.0 * PI * (b as f64 + 0.5) / k as f64;
                let wo = [sin_o * phi_o.cos(), cos_o, sin_o * phi_o.sin()];
                sum += phong_brdf(kd, ks, n, to_light, wo) * cos_o;
            }
        }
        sum * 2.0 * PI / (m * k) as f64
    };
    let table: Vec<f64> = (0..=64).map(|i| albedo(i as f64 / 64.0)).collect();
    let albedo_at = |c: f64| {
        let x = c.clamp(0.0, 1.0) * 64.0;
        let i = (x as usize).min(63);
        table[i] + (x - i as f64) * (table[i + 1] - table[i])
    };
    // Flux the floor reflects: ∫ I·cosθ/d² · a(θ) dA over [−1, 1]², midpoint rule.
    let (g, hgt) = (600, (light.y + 1.0) as f64);
    let mut reflected = 0.0;
    for i in 0..g {
        for j in 0..g {
            let x = -1.0 + 2.0 * (i as f64 + 0.5) / g as f64 - light.x as f64;
            let z = -1.0 + 2.0 * (j as f64 + 0.5) / g as f64 - light.z as f64;
            let d2 = x * x + z * z + hgt * hgt;
            let cos = hgt / d2.sqrt();
            reflected += intensity as f64 * cos / d2 * albedo_at(cos);
        }
    }
    reflected *= 4.0 / (g * g) as f64;
    let expected = phi + reflected;

    let paths = 2_000_000;
    let mut rng = RandomStream::new(17, &[]);
    let (mut out, mut stack) = (Vec::new(), PathScratch::default());
    let settings = TraceSettings::default();
    let totals: Vec<f64> = (0..paths)
        .map(|_| {
            out.clear();
            trace_path(&scene, 0, &settings, &mut rng, &mut out, &mut Vec::new(), &mut stack);
            out.iter().map(|s| phi * s.beta[0] as f64).sum::<f64>()
        })
        .collect();
    // Measured: 4M paths, seeds 1–3: −0.2σ, −0.8σ, −1.3σ; 16M paths: +1.7σ (σ = 0.0016 W).
    let (total, err) = mean_and_error(&totals);
    eprintln!(
        "incident flux {total:.5} ± {err:.5} W, expected {expected:.5} (Φ = {phi:.5}, reflected {reflected:.5})"
    );
    assert!((total - expected).abs() < 4.0 * err, "incident flux {total} ± {err}, expected {expected}");
    // The reflected part alone, to 1%: a Lambertian floor of the same kd + ks would differ by ~10%.
    assert!(((total - phi) / reflected - 1.0).abs() < 0.01, "reflected {} vs {reflected}", total - phi);
}

/// A Lambertian emitter seen directly: pixels it covers read exactly its radiance L (which is
/// Φ/(π·A)); pixels beside it read zero; seen from behind (one-sided) it is black.
#[test]
fn lambertian_emitter_reads_its_radiance() {
    let l = Rgb::new(3.0, 2.0, 0.5);
    let scene = Scene::build(&emitting_panel(l)).unwrap();
    let area = 1.0f32;
    assert!((scene.lights[0].power() - std::f32::consts::PI * l * area).abs().max_element() < 1e-5);
    let view = panel_view;
    let front = view(Vec3::new(0.3, 0.2, 2.0));
    let film = trace_and_render(&scene, &front, 2_000_000, 9);
    emitter_reads(&film, &front, l);
    let back = trace_and_render(&scene, &view(Vec3::new(0.3, 0.2, -2.0)), 200_000, 9);
    assert!(back.pixels.iter().all(|p| *p == [0.0; 3]), "a one-sided emitter is black from behind");
}

/// The emitter seen directly with the bidirectional estimator: emitter hits and the splats of
/// y₀ under MIS (and nothing from behind).
#[test]
fn lambertian_emitter_reads_its_radiance_bidirectional() {
    let l = Rgb::new(3.0, 2.0, 0.5);
    let scene = Scene::build(&emitting_panel(l)).unwrap();
    let view = panel_view;
    let (table, chunks) = trace_chunks(&scene, 200_000, 9);
    let front = view(Vec3::new(0.3, 0.2, 2.0));
    let film = render_bidirectional(&scene, front.into(), &table, &chunks, true, 16, 1, 9);
    emitter_reads(&film, &front, l);
    let back =
        render_bidirectional(&scene, view(Vec3::new(0.3, 0.2, -2.0)).into(), &table, &chunks, true, 4, 1, 9);
    assert!(back.pixels.iter().all(|p| *p == [0.0; 3]), "a one-sided emitter is black from behind");
}

/// A 32×32 camera at `eye` looking at the emitting panel.
pub(crate) fn panel_view(eye: Vec3) -> Pinhole {
    let desc = CameraDesc {
        eye,
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_x_degrees: 40.0,
        width: 32,
        height: 32,
        kind: CameraKind::Perspective,
        film: Default::default(),
    };
    Pinhole::new(&desc).unwrap()
}

/// Pixels of `film` (through `front`) that the panel of radiance `l` covers read `l` within 1%;
/// pixels beside it are black.
fn emitter_reads(film: &opticks_core::film::Film, front: &Pinhole, l: Rgb) {
    let (mut inside, mut n_inside) = (glam::DVec3::ZERO, 0);
    for (p, v) in film.pixels.iter().enumerate() {
        let (i, j) = (p % 32, p / 32);
        // Classify the pixel by its four corners' rays hitting the panel.
        let hits = corners_on_panel(front, p);
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
}
