//! Sensors against closed forms: the illuminance meter under a point light (E = I·cosθ/d²) and
//! under a Lambertian rectangle (the parallel-rectangle corner formula), its lux under a lamp
//! given in lumens (E_v = Φ_v/4π·cosθ/d²), the meter against the
//! camera on a Lambertian floor (L = ρE/π), the thin lens (r → 0 is the pinhole; in focus is
//! sharp; a uniform scene is unchanged) and the equirectangular camera in the emissive furnace.
//!
//! Tolerances come from measured noise: each meter cell's standard error is computed from its
//! own samples (each path puts at most one sample on the black receiver), and the 1 % bounds
//! are asserted only where that error is below 0.25 % (so 1 % is 4σ); every cell must be within
//! 4σ regardless.

use opticks_testkit as common;

use common::*;
use opticks_core::dataset::{Chunk, LightTable};
use opticks_core::film::Film;
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::{
    CameraDesc, CameraKind, MeshDesc, PointLightDesc, Scene, SceneDescription, cornell_box,
};
use opticks_core::sensor::{
    Equirectangular, IlluminanceMeter, Orthographic, Pinhole, SampleBatch, Sensor, ThinLens, measure,
};
use std::f64::consts::PI;

/// The floor y = 0, facing +y, half-size s.
fn floor(s: f32, material: usize) -> MeshDesc {
    quad(
        "floor",
        [Vec3::new(-s, 0.0, -s), Vec3::new(-s, 0.0, s), Vec3::new(s, 0.0, s), Vec3::new(s, 0.0, -s)],
        material,
        None,
    )
}

/// The meter on the floor square [−1,1]² (facing +y), n×n cells; cell (i, j) spans
/// x ∈ [−1 + 2i/n, …], z ∈ [1 − 2j/n − 2/n, 1 − 2j/n].
fn floor_meter(n: u32) -> IlluminanceMeter {
    IlluminanceMeter::new(
        Vec3::new(-1.0, 0.0, 1.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -2.0),
        n,
        n,
    )
    .unwrap()
}

/// Mean of `e(x, z)` over cell (i, j) of [`floor_meter`] (midpoint rule, 40×40 points).
fn cell_mean(n: u32, i: u32, j: u32, e: &dyn Fn(f64, f64) -> f64) -> f64 {
    let w = 2.0 / n as f64;
    let (x0, z1) = (-1.0 + w * i as f64, 1.0 - w * j as f64);
    let k = 40;
    let mut s = 0.0;
    for a in 0..k {
        for b in 0..k {
            s += e(x0 + w * (a as f64 + 0.5) / k as f64, z1 - w * (b as f64 + 0.5) / k as f64);
        }
    }
    s / (k * k) as f64
}

/// Measures, and the standard error of each cell (red channel) from the sum of squared
/// contributions (paths are independent and each puts at most one sample in a cell here).
fn measure_with_error(
    meter: &IlluminanceMeter,
    scene: &Scene,
    table: &LightTable,
    chunks: &[Chunk],
) -> (Film, Vec<f64>) {
    let film = measure(meter, scene, chunks.len(), |i| batch(table, chunks, i), |_| {}).unwrap();
    let mut sq = vec![0.0f64; film.pixels.len()];
    let mut one = Film::new(meter.nx, meter.ny);
    for c in chunks {
        let flux = table.flux_per_path(c.light as usize);
        for s in &c.samples {
            one.pixels.iter_mut().for_each(|p| *p = [0.0; 3]);
            meter.splat_on(
                scene,
                SampleBatch { flux_per_path: flux, samples: std::slice::from_ref(s) },
                &mut one,
            );
            for (q, p) in sq.iter_mut().zip(&one.pixels) {
                *q += p[0] * p[0];
            }
        }
    }
    (film, sq.into_iter().map(f64::sqrt).collect())
}

/// Checks measured cells against expected ones: all within 4σ, well-measured ones within 1 %.
fn check_cells(what: &str, got: &Film, err: &[f64], expected: &[f64], min_strict: usize) {
    let mut strict = 0;
    let mut worst = 0.0f64;
    for (k, (g, e)) in got.pixels.iter().zip(expected).enumerate() {
        let (g, sigma) = (g[0], err[k] / e);
        let r = g / e - 1.0;
        eprintln!("{what} cell {k}: {g:.5} vs {e:.5} ({:+.3} %, σ {:.3} %)", 100.0 * r, 100.0 * sigma);
        assert!(r.abs() < 4.0 * sigma, "{what} cell {k}: {g} vs {e} ({r:+.4}, σ {sigma:.4})");
        if sigma < 0.0025 {
            assert!(r.abs() < 0.01, "{what} cell {k}: {g} vs {e}");
            strict += 1;
            worst = worst.max(r.abs());
        }
    }
    eprintln!("{what}: {strict} cells with σ < 0.25 %, worst of them {:.3} %", 100.0 * worst);
    assert!(strict >= min_strict, "{what}: too few well-measured cells ({strict}) for the 1 % check");
}

/// E = I·cosθ/d² under an isotropic point light, over a 4×4 grid on a black floor.
#[test]
fn meter_matches_point_light_inverse_square_law() {
    let (intensity, light) = (2.0f32, Vec3::new(0.2, 0.5, -0.1));
    let desc = SceneDescription {
        materials: vec![lambert("black", 0.0, false)],
        meshes: vec![floor(50.0, 0)],
        point_lights: vec![point_light("bulb", light, Rgb::splat(intensity))],
        camera: None,
        ..Default::default()
    };
    let scene = Scene::build(&desc).unwrap();
    let (table, chunks) = trace_chunks(&scene, 4_000_000, 21);
    let meter = floor_meter(4);
    let (film, err) = measure_with_error(&meter, &scene, &table, &chunks);
    let e = |x: f64, z: f64| {
        let d2 = (x - light.x as f64).powi(2) + (light.y as f64).powi(2) + (z - light.z as f64).powi(2);
        intensity as f64 * light.y as f64 / (d2 * d2.sqrt())
    };
    let expected: Vec<f64> = (0..16).map(|k| cell_mean(4, k % 4, k / 4, &e)).collect();
    check_cells("point light 4x4", &film, &err, &expected, 2);
    // Larger cells, same paths: every one is measured to better than 0.25 %.
    let meter = floor_meter(2);
    let (film, err) = measure_with_error(&meter, &scene, &table, &chunks);
    let expected: Vec<f64> = (0..4).map(|k| cell_mean(2, k % 2, k / 2, &e)).collect();
    check_cells("point light 2x2", &film, &err, &expected, 4);
}

/// A Lambertian square emitter over a parallel black floor, against the closed form.
#[test]
fn meter_matches_parallel_rectangle_emitter() {
    let (l, h, half) = (1.5f32, 0.5f32, 0.5f32);
    let scene = Scene::build(&panel_over_black_floor(l, h, half)).unwrap();
    let (l, h, half) = (l as f64, h as f64, half as f64);
    let e = |x: f64, z: f64| panel_irradiance(l, h, half, x, z);
    // The formula itself, against brute-force quadrature of L·h²/r⁴ over the panel.
    for (px, pz) in [(0.0, 0.0), (0.3, -0.7), (0.9, 0.95)] {
        let k = 400;
        let mut s = 0.0;
        for a in 0..k {
            for b in 0..k {
                let (x, z) = (-half + (a as f64 + 0.5) / k as f64, -half + (b as f64 + 0.5) / k as f64);
                let r2 = (x - px).powi(2) + (z - pz).powi(2) + h * h;
                s += l * h * h / (r2 * r2) / (k * k) as f64;
            }
        }
        assert!((e(px, pz) / s - 1.0).abs() < 1e-4, "closed form {} vs quadrature {s}", e(px, pz));
    }
    let (table, chunks) = trace_chunks(&scene, 3_000_000, 22);
    let meter = floor_meter(4);
    let (film, err) = measure_with_error(&meter, &scene, &table, &chunks);
    let expected: Vec<f64> = (0..16).map(|k| cell_mean(4, k % 4, k / 4, &e)).collect();
    check_cells("rectangle", &film, &err, &expected, 4);
}

/// A pinhole looking straight down at a Lambertian floor sees L = ρE/π: each meter cell's ρE/π
/// equals the mean of the pixels that tile it (the image covers the meter exactly, 16×16 pixels
/// per cell, all with the same footprint because the floor is parallel to the image plane).
#[test]
fn meter_agrees_with_the_camera_on_a_lambertian_floor() {
    let rho = 0.5f32;
    let cam_desc = CameraDesc {
        eye: Vec3::new(0.0, 2.0, 0.0),
        target: Vec3::ZERO,
        up: Vec3::NEG_Z,
        fov_x_degrees: 2.0 * 0.5f32.atan().to_degrees(),
        width: 64,
        height: 64,
        kind: CameraKind::Perspective,
        film: Default::default(),
    };
    let desc = SceneDescription {
        materials: vec![lambert("grey", rho, false)],
        meshes: vec![floor(50.0, 0)],
        point_lights: vec![PointLightDesc {
            name: "bulb".into(),
            source: Default::default(),
            position: Vec3::new(0.3, 1.0, 0.2),
            intensity: Rgb::splat(1.0),
            ..Default::default()
        }],
        camera: Some(cam_desc),
        ..Default::default()
    };
    let scene = Scene::build(&desc).unwrap();
    let cam = Pinhole::new(&cam_desc).unwrap();
    let (table, chunks) = trace_chunks(&scene, 2_000_000, 23);
    let meter = floor_meter(4);
    let e = measure(&meter, &scene, chunks.len(), |i| batch(&table, &chunks, i), |_| {}).unwrap();
    let film = render_chunks(&scene, &Sensor::from(cam), &table, &chunks);
    let mut sums = [0.0f64; 16];
    let mut counts = vec![0usize; 16];
    for (p, v) in film.pixels.iter().enumerate() {
        let d = cam.direction(((p % 64) as f32 + 0.5) / 64.0, ((p / 64) as f32 + 0.5) / 64.0);
        let x = cam.eye + (-cam.eye.y / d.y) * d;
        let cell = meter.locate(x).expect("the image covers the meter");
        sums[cell] += v[0];
        counts[cell] += 1;
    }
    assert!(counts.iter().all(|&c| c == 256), "{counts:?}");
    let mut worst = 0.0f64;
    for (k, sum) in sums.iter().enumerate() {
        let from_camera = sum / 256.0;
        let from_meter = rho as f64 * e.pixels[k][0] / PI;
        let r = from_camera / from_meter - 1.0;
        eprintln!("cell {k}: camera {from_camera:.5}, ρE/π {from_meter:.5} ({:+.3} %)", 100.0 * r);
        worst = worst.max(r.abs());
    }
    eprintln!("worst cell {:.3} %", 100.0 * worst);
    assert!(worst < 0.01, "camera and meter disagree by {:.3} %", 100.0 * worst);
}

/// Squared error of `a` against `b`, relative to b's energy: Σ(a−b)²/Σb².
fn rel_mse(a: &Film, b: &Film) -> f64 {
    let (mut e, mut n) = (0.0, 0.0);
    for (x, y) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            e += (x[c] - y[c]).powi(2);
            n += y[c] * y[c];
        }
    }
    e / n
}

/// A thin lens with a vanishing aperture renders the pinhole's image: its difference from the
/// pinhole image of the same dataset is far below the noise between two datasets.
#[test]
fn thin_lens_with_zero_radius_is_the_pinhole() {
    let scene = Scene::build(&cornell_box()).unwrap();
    let cam = camera(&scene);
    let focus = (scene.camera.unwrap().target - cam.eye).length();
    let (table, chunks) = trace_chunks(&scene, 400_000, 31);
    let pinhole = render_chunks(&scene, &Sensor::from(cam), &table, &chunks);
    let tiny = render_chunks(&scene, &ThinLens::new(cam, 1e-6, focus).unwrap().into(), &table, &chunks);
    let exact = render_chunks(&scene, &ThinLens::new(cam, 0.0, focus).unwrap().into(), &table, &chunks);
    assert_eq!(exact, pinhole, "r = 0 is exactly the pinhole");
    let (table2, chunks2) = trace_chunks(&scene, 400_000, 32);
    let other = render_chunks(&scene, &Sensor::from(cam), &table2, &chunks2);
    let (m, mp) = (tiny.mean(), pinhole.mean());
    let (noise, diff) = (rel_mse(&other, &pinhole), rel_mse(&tiny, &pinhole));
    eprintln!("mean {m:?} vs {mp:?}; relMSE tiny lens {diff:.3e}, between seeds {noise:.3e}");
    for c in 0..3 {
        assert!((m[c] / mp[c] - 1.0).abs() < 1e-3);
    }
    assert!(diff < 0.01 * noise, "relMSE {diff} vs noise {noise}");
}

/// In the emissive furnace (radiance L_e/(1−ρ) everywhere) a wide-open, defocused lens still
/// reads the uniform radiance in every 8×8 block: depth of field moves light, never adds any.
#[test]
fn thin_lens_leaves_a_uniform_scene_unchanged() {
    let (le, rho) = (1.0f32, 0.8f32);
    let cam_desc = furnace_view(100.0, 32, 32);
    let desc = emissive_furnace(le, rho, Some(cam_desc));
    let scene = Scene::build(&desc).unwrap();
    let lens = ThinLens::new(Pinhole::new(&cam_desc).unwrap(), 0.3, 0.4).unwrap();
    let (table, chunks) = trace_chunks(&scene, 1_500_000, 33);
    let film = render_chunks(&scene, &lens.into(), &table, &chunks);
    let expected = (le / (1.0 - rho)) as f64;
    assert_uniform("thin lens mean", &film, expected);
}

/// A Lambertian panel on the plane of focus is as sharp as through a pinhole (pixels that do not
/// see it are exactly black, pixels that do read its radiance); focused nearer, its edge blurs
/// into the neighbouring pixels while the image's total stays the same.
#[test]
fn thin_lens_focus_is_sharp_and_defocus_blurs() {
    let l = Rgb::new(3.0, 2.0, 0.5);
    let scene = Scene::build(&emitting_panel(l)).unwrap();
    let cam = crate::analytic::panel_view(Vec3::new(0.0, 0.0, 2.0));
    let (table, chunks) = trace_chunks(&scene, 2_000_000, 34);
    let sharp = render_chunks(&scene, &ThinLens::new(cam, 0.1, 2.0).unwrap().into(), &table, &chunks);
    let blurred = render_chunks(&scene, &ThinLens::new(cam, 0.1, 1.0).unwrap().into(), &table, &chunks);
    let (mut inside, mut n_inside, mut blurred_off) = (0.0, 0, 0);
    for p in 0..32 * 32 {
        match corners_on_panel(&cam, p) {
            4 => {
                inside += sharp.pixels[p][0];
                n_inside += 1;
            }
            0 => {
                assert_eq!(sharp.pixels[p], [0.0; 3], "in focus, pixel {p} off the panel must be black");
                if blurred.pixels[p][0] > 0.0 {
                    blurred_off += 1;
                }
            }
            _ => {}
        }
    }
    let mean = inside / n_inside as f64;
    eprintln!(
        "in focus: {n_inside} pixels on the panel read {mean:.4} (L = {}); defocused: {blurred_off} pixels off the panel lit",
        l.x
    );
    assert!((mean / l.x as f64 - 1.0).abs() < 0.01);
    assert!(blurred_off > 40, "defocus must spread light past the panel's edge ({blurred_off} pixels)");
    let (a, b) = (sharp.mean()[0], blurred.mean()[0]);
    assert!((a / b - 1.0).abs() < 0.01, "total light {a} (sharp) vs {b} (blurred)");
}

/// The orthographic camera inside the emissive furnace reads L_e/(1−ρ) in every block, through
/// its light-tracing connection (W = 1/a, no 1/d²), through its camera rays (the bidirectional
/// estimator's camera half alone, a dataset without records) and with every strategy combined
/// (the MIS weights of its camera vertex, a direction).
#[test]
fn orthographic_reads_the_emissive_furnace_with_both_estimators() {
    let (le, rho) = (1.0f32, 0.8f32);
    let cam_desc = furnace_view(45.0, 32, 24);
    let desc = emissive_furnace(le, rho, Some(cam_desc));
    let scene = Scene::build(&desc).unwrap();
    let ortho = Orthographic::new(&cam_desc, 0.4, 0.3).unwrap();
    let (table, chunks) = trace_chunks(&scene, 1_500_000, 36);
    let expected = (le / (1.0 - rho)) as f64;
    let film = render_chunks(&scene, &ortho.into(), &table, &chunks);
    assert_uniform("orthographic, light estimator", &film, expected);
    let (table, chunks) = trace_chunks(&scene, 100_000, 37);
    let film = render_bidirectional(&scene, ortho.into(), &table, &chunks, false, 256, 0, 1);
    assert_uniform("orthographic, camera half", &film, expected);
    let film = render_bidirectional(&scene, ortho.into(), &table, &chunks, true, 64, 1, 2);
    assert_uniform("orthographic, bidirectional", &film, expected);
}

/// The equirectangular camera inside the emissive furnace: every region of the panorama, poles
/// included, reads L_e/(1−ρ).
#[test]
fn equirect_reads_the_emissive_furnace_everywhere() {
    let (le, rho) = (1.0f32, 0.8f32);
    let cam_desc = furnace_view(90.0, 64, 32);
    let desc = emissive_furnace(le, rho, Some(cam_desc));
    let scene = Scene::build(&desc).unwrap();
    let pano = Equirectangular::new(&cam_desc).unwrap();
    let (table, chunks) = trace_chunks(&scene, 1_500_000, 35);
    let film = render_chunks(&scene, &pano.into(), &table, &chunks);
    let expected = (le / (1.0 - rho)) as f64;
    // Solid-angle-weighted mean: the total radiance over the sphere.
    let mut total = 0.0;
    for (p, v) in film.pixels.iter().enumerate() {
        total += v[1] * pano.pixel_solid_angle((p / 64) as u32) as f64;
    }
    let sphere_mean = total / (4.0 * PI);
    eprintln!("panorama: sphere mean {sphere_mean:.4}, pixel mean {:?}, expected {expected}", film.mean());
    assert!((sphere_mean / expected - 1.0).abs() < 0.005);
    assert_blocks_uniform(&film, expected);
}

/// Runs the `opticks` binary in `dir`.
fn opticks(args: &[&str], dir: &std::path::Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_opticks")).args(args).current_dir(dir).output().unwrap()
}

/// `opticks measure` end to end on the Cornell box: a named wall and the same rectangle given
/// as --plane read the same, the CSV and the heat map are written, bad input is refused with a
/// clear message; `render` takes the thin lens and the panorama options.
#[test]
fn measure_and_sensor_options_on_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = scene_file("cornell", "scene.xml");
    let ok = |o: std::process::Output| {
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    ok(opticks(&["trace", scene.to_str().unwrap(), "--paths", "200000", "-o", "c.opds"], d));
    ok(opticks(
        &["measure", "c.opds", "--surface", "red_wall", "--cells", "4x3", "-o", "a.csv", "--png", "a.png"],
        d,
    ));
    let csv = std::fs::read_to_string(d.join("a.csv")).unwrap();
    let rows: Vec<Vec<f64>> =
        csv.lines().skip(1).map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect()).collect();
    assert_eq!(csv.lines().next().unwrap(), "i,j,x,y,z,E_R,E_G,E_B,E_v_lux,SE_R,SE_G,SE_B,SE_v_lux");
    assert_eq!(rows.len(), 12);
    for r in &rows {
        assert!((r[2] + 1.0).abs() < 1e-3, "the red wall is x = −1: {r:?}");
        assert!(r[5] > 0.0 && r[5] > r[6], "red wall lit, reflecting red: {r:?}");
        let lux = 683.0 * (0.2126 * r[5] + 0.7152 * r[6] + 0.0722 * r[7]);
        assert!((r[8] / lux - 1.0).abs() < 1e-6);
        assert!(r[12] > 0.0 && r[12] < 0.2 * r[8], "a standard error, and a small one: {r:?}");
    }
    let png = image::open(d.join("a.png")).unwrap();
    assert!(png.width() > 300 && png.height() > 200);
    // The same rectangle as a plane: x = −1, y and z ∈ [−1, 1], u = −z (to the right), v = +y;
    // a plane counts the samples on it when asked to (`--surface` does by default).
    let plane = ["measure", "c.opds", "--plane", "-1,-1,1,0,0,-2,0,2,0", "--cells", "4x3"];
    ok(opticks(&[&plane[..], &["--estimator", "samples", "-o", "b.csv"]].concat(), d));
    let b = std::fs::read_to_string(d.join("b.csv")).unwrap();
    assert_eq!(b.lines().skip(1).count(), 12);
    let total = |s: &str| -> f64 {
        s.lines().skip(1).map(|l| l.split(',').nth(8).unwrap().parse::<f64>().unwrap()).sum()
    };
    // Both count only the samples of surfaces parallel to them: the floor, ceiling and back
    // wall, whose samples near the shared edges lie inside the plane's band, are not the
    // wall's (counted, they made the plane read 1e-4 more than the surface).
    assert!((total(&csv) / total(&b) - 1.0).abs() < 1e-9, "surface and plane meters disagree");
    // Issue 26: a plane in the air has no samples to count — it read ~1e-4 of the light with
    // exit 0 — so it is refused; one reaching beyond the wall is warned of.
    let air = opticks(
        &[
            "measure",
            "c.opds",
            "--plane",
            "-1,-1,0.95,2,0,0,0,2,0",
            "--estimator",
            "samples",
            "-o",
            "air.csv",
        ],
        d,
    );
    let err = String::from_utf8_lossy(&air.stderr);
    assert!(!air.status.success() && err.contains("lies on no scene surface"), "{err}");
    let beyond =
        ["--plane", "-1,-1,1,0,0,-2,0,4,0", "--cells", "4x4", "--estimator", "samples", "-o", "h.csv"];
    let half = opticks(&[&["measure", "c.opds"][..], &beyond[..]].concat(), d);
    let err = String::from_utf8_lossy(&half.stderr);
    assert!(half.status.success() && err.contains("8 of the 16 cells"), "{err}");
    // By default a plane connects the samples to itself: the same wall within the errors.
    ok(opticks(&[&plane[..], &["-o", "c.csv"]].concat(), d));
    let c = std::fs::read_to_string(d.join("c.csv")).unwrap();
    for (r, q) in rows.iter().zip(c.lines().skip(1)) {
        let q: Vec<f64> = q.split(',').map(|x| x.parse().unwrap()).collect();
        assert!((r[8] - q[8]).abs() < 4.0 * r[12].hypot(q[12]), "samples {r:?} vs connections {q:?}");
    }
    for (args, msg) in [
        (vec!["--surface", "nope"], "no mesh named 'nope'"),
        (vec!["--surface", "white_geometry"], "not planar"),
        (vec!["--plane", "1,2,3"], "nine comma-separated numbers"),
        (vec!["--plane", "0,0,0,1,0,0,2,0,0"], "degenerate"),
        (vec!["--surface", "red_wall", "--cells", "0x3"], "between 1 and 65536"),
    ] {
        let mut a = vec!["measure", "c.opds", "-o", "x.csv"];
        a.extend(args);
        let o = opticks(&a, d);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(msg), "{a:?}: {err}");
    }
    ok(opticks(&["render", "c.opds", "-o", "pano.exr", "--projection", "equirect", "--size", "64x32"], d));
    ok(opticks(
        &["render", "c.opds", "-o", "dof.exr", "--lens-radius", "0.05", "--focus-distance", "3.9"],
        d,
    ));
    ok(opticks(&["render", "c.opds", "-o", "ortho.exr", "--ortho-width", "1.5", "--size", "48x32"], d));
    assert!(d.join("ortho.exr").exists());
    let o = opticks(&["render", "c.opds", "-o", "x.exr", "--projection", "orthographic"], d);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("--ortho-width"));
    let o = opticks(&["render", "c.opds", "-o", "x.exr", "--lens-radius", "-1"], d);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("lens radius"));
}

/// Photometry end to end: an isotropic IES lamp given in lumens (Mitsuba `lumens`, white) over
/// a black floor. Its luminous intensity is I_v = Φ_v/4π, so the illuminance is
/// E_v = I_v·cosθ/d²; the meter's lux, 683·(0.2126 E_R + 0.7152 E_G + 0.0722 E_B), must match
/// it within the measured noise (the same 4σ / 1 % rule as the radiometric checks).
#[test]
fn meter_lux_matches_a_lamp_given_in_lumens() {
    let dir = tempfile::tempdir().unwrap();
    let ies = "IESNA:LM-63-2002\n[TEST] isotropic\nTILT=NONE\n1 1000 1.0 2 1 1 2 0.0 0.0 0.0\n1.0 1.0 60\n0 180\n0\n100 100\n";
    std::fs::write(dir.path().join("iso.ies"), ies).unwrap();
    let (lumens, light) = (2000.0f64, Vec3::new(0.2, 0.5, -0.1));
    let xml = format!(
        r#"<scene version="3.0.0"><emitter type="ies" id="lamp"><string name="filename" value="iso.ies"/>
  <transform name="to_world"><translate x="{}" y="{}" z="{}"/></transform><float name="lumens" value="{lumens}"/></emitter></scene>"#,
        light.x, light.y, light.z
    );
    std::fs::write(dir.path().join("scene.xml"), xml).unwrap();
    let mut desc = opticks_io::load_scene(&dir.path().join("scene.xml")).unwrap().description;
    desc.materials.push(lambert("black", 0.0, false));
    desc.meshes.push(floor(50.0, desc.materials.len() - 1));
    let scene = Scene::build(&desc).unwrap();
    let (table, chunks) = trace_chunks(&scene, 4_000_000, 22);
    let meter = floor_meter(2);
    let (film, err) = measure_with_error(&meter, &scene, &table, &chunks);
    let lux: Vec<f64> =
        film.pixels.iter().map(|e| 683.0 * (0.2126 * e[0] + 0.7152 * e[1] + 0.0722 * e[2])).collect();
    let e_v = |x: f64, z: f64| {
        let d2 = (x - light.x as f64).powi(2) + (light.y as f64).powi(2) + (z - light.z as f64).powi(2);
        lumens / (4.0 * PI) * light.y as f64 / (d2 * d2.sqrt())
    };
    let expected: Vec<f64> = (0..4).map(|k| cell_mean(2, k % 2, k / 2, &e_v)).collect();
    for (k, (l, e)) in lux.iter().zip(&expected).enumerate() {
        eprintln!("lux cell {k}: {l:.2} lx vs E_v = {e:.2} lx");
        let p = film.pixels[k];
        assert!(
            (p[0] - p[1]).abs() <= 1e-6 * p[0] && (p[0] - p[2]).abs() <= 1e-6 * p[0],
            "white light: {p:?}"
        );
    }
    // White light: lux = 683·E_R, so checking E_R against E_v/683 checks the lux, with its noise.
    let expected_w: Vec<f64> = expected.iter().map(|e| e / 683.0).collect();
    check_cells("lamp in lumens 2x2", &film, &err, &expected_w, 4);
}
