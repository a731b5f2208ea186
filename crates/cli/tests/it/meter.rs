//! The illuminance meter anywhere (the connected estimator, `opticks_core::sensor::meter`):
//! planes in the air under a point light (E = I·cosθ/d², the direct term) and under a
//! Lambertian rectangle (the parallel-rectangle corner formula, carried by the area light's
//! direct term, sampled at the meter), a plane in the air inside the closed furnace room against a Mitsuba 3
//! `irradiancemeter` reference (`testdata/mitsuba/meter-furnace`), and `opticks measure
//! --points` end to end, bad points files included.
//!
//! Thresholds are the meter's own stated standard errors: every cell within 4σ, and the mean
//! of z² over many cells between bounds that a correct error (mean z² ≈ 1, its spread
//! √(2/cells)) passes and an error stated 2× too small or 2× too large fails.

use opticks_testkit as common;

use common::*;
use opticks_core::dataset::{Chunk, LightTable};
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::{MeshDesc, Scene, SceneDescription};
use opticks_core::sensor::IlluminanceMeter;
use opticks_core::sensor::bidirectional::RenderLights;
use opticks_core::sensor::meter::{
    ConnectedSettings, Group, MeterLayout, MeterPoint, Reading, read_connected,
};

/// A black floor y = 0, half-size 50.
fn black_floor() -> MeshDesc {
    let s = 50.0;
    quad(
        "floor",
        [Vec3::new(-s, 0.0, -s), Vec3::new(-s, 0.0, s), Vec3::new(s, 0.0, s), Vec3::new(s, 0.0, -s)],
        0,
        None,
    )
}

/// Reads `layout` from in-memory chunks with the table's own powers.
fn read(scene: &Scene, table: &LightTable, chunks: &[Chunk], layout: &MeterLayout) -> Reading {
    let names: Vec<&str> = table.lights.iter().map(|l| l.name.as_str()).collect();
    let flux: Vec<Rgb> = (0..names.len()).map(|k| table.flux_per_path(k)).collect();
    let paths: Vec<u64> = table.lights.iter().map(|l| l.paths).collect();
    let lights = RenderLights::new(scene, &names, &flux, &paths);
    let groups: Vec<Group> = chunks.iter().map(|c| Group { light: c.light, paths: c.paths }).collect();
    read_connected(
        scene,
        &lights,
        layout,
        ConnectedSettings::default(),
        &groups,
        |i| batch(table, chunks, i),
        |_| {},
        || false,
    )
    .unwrap()
    .unwrap()
}

/// The horizontal plane y = `y` over x, z ∈ [−1, 1], `n`×`n` cells, facing up (+y: u = +z,
/// v = +x) or down (u = +x, v = +z). Cell (i, j) spans x ∈ [−1 + 2j/n, …], z ∈ [−1 + 2i/n, …]
/// facing up, the other way round facing down.
fn plane(y: f32, n: u32, up: bool) -> IlluminanceMeter {
    let (a, b) = (Vec3::new(0.0, 0.0, 2.0), Vec3::new(2.0, 0.0, 0.0));
    let (u, v) = if up { (a, b) } else { (b, a) };
    IlluminanceMeter::new(Vec3::new(-1.0, y, -1.0), u, v, n, n).unwrap()
}

/// Mean of `e(x, z)` over target `t` of the up-facing [`plane`] with n×n cells (midpoint rule).
fn cell_mean(n: u32, t: usize, e: &dyn Fn(f64, f64) -> f64) -> f64 {
    let w = 2.0 / n as f64;
    let (z0, x0) = (-1.0 + w * (t % n as usize) as f64, -1.0 + w * (t / n as usize) as f64);
    let k = 40;
    let mut s = 0.0;
    for a in 0..k {
        for b in 0..k {
            s += e(x0 + w * (a as f64 + 0.5) / k as f64, z0 + w * (b as f64 + 0.5) / k as f64);
        }
    }
    s / (k * k) as f64
}

/// Every target within 4 of its stated σ (`other_se`: a reference's own error, in quadrature)
/// and the mean z² in [0.45, 1.9] — what an honest error gives over ≥ 30 targets (mean 1,
/// spread ≤ 0.26), and not an error off by 2× either way (mean z² 4 or 0.25).
fn check(what: &str, got: &Reading, expected: &[f64], other_se: &[f64]) {
    let mut z2 = 0.0;
    for (t, &e) in expected.iter().enumerate() {
        let (v, se) = (got.value[t][0], got.std_error[t][0].hypot(other_se[t]));
        let z = (v - e) / se;
        eprintln!("{what} {t}: {v:.6} ± {se:.6} vs {e:.6} (z {z:+.2})");
        assert!(se > 0.0 && z.abs() < 4.0, "{what} target {t}: {v} ± {se} vs {e}");
        z2 += z * z;
    }
    let m = z2 / expected.len() as f64;
    eprintln!("{what}: mean z² {m:.3} over {} targets", expected.len());
    assert!((0.45..1.9).contains(&m), "{what}: mean z² {m} — the stated errors are not the measured noise");
}

/// A plane in the air 0.8 m under a point light (the floor black): each cell reads the mean
/// of I·cosθ/d² over it; the same plane facing down, away from the light, reads 0.
#[test]
fn plane_in_the_air_under_a_point_light() {
    let (intensity, light) = (2.0f32, Vec3::new(0.2, 1.5, -0.1));
    let desc = SceneDescription {
        materials: vec![lambert("black", 0.0, false)],
        meshes: vec![black_floor()],
        point_lights: vec![point_light("bulb", light, Rgb::splat(intensity))],
        ..Default::default()
    };
    let scene = Scene::build(&desc).unwrap();
    let (table, chunks) = trace_chunks(&scene, 100_000, 3);
    let y = 0.7;
    let up = read(&scene, &table, &chunks, &MeterLayout::Grid(plane(y, 8, true)));
    let h = (light.y - y) as f64;
    let e = |x: f64, z: f64| {
        let d2 = (x - light.x as f64).powi(2) + h * h + (z - light.z as f64).powi(2);
        intensity as f64 * h / (d2 * d2.sqrt())
    };
    let expected: Vec<f64> = (0..64).map(|t| cell_mean(8, t, &e)).collect();
    check("point light", &up, &expected, &[0.0; 64]);
    let down = read(&scene, &table, &chunks, &MeterLayout::Grid(plane(y, 8, false)));
    assert!(down.value.iter().all(|v| v[0] == 0.0), "light from behind the measured side");
}

/// A plane in the air 0.3 m over a black floor under a constant sky L (and nothing else): each
/// cell reads E = π·L (the upper hemisphere, cosine-weighted) within its stated error — the
/// environment's direct light, drawn at the meter with its own sampling; facing down, toward
/// the black floor, about 0 (below).
#[test]
fn plane_in_the_air_under_a_constant_sky() {
    let l = 0.8f32;
    let desc = SceneDescription {
        materials: vec![lambert("black", 0.0, false)],
        meshes: vec![black_floor()],
        environment_lights: vec![opticks_core::scene::EnvironmentLightDesc {
            name: "sky".into(),
            source: Default::default(),
            radiance: opticks_core::scene::EnvironmentRadiance::Constant(Rgb::splat(l)),
            to_world: opticks_core::math::Mat3::IDENTITY,
            sky: None,
        }],
        ..Default::default()
    };
    let scene = Scene::build(&desc).unwrap();
    let (table, chunks) = trace_chunks(&scene, 20_000, 5);
    let up = read(&scene, &table, &chunks, &MeterLayout::Grid(plane(0.3, 10, true)));
    let e = std::f64::consts::PI * l as f64;
    check("constant sky", &up, &[e; 100], &[0.0; 100]);
    // Facing down only the sky beyond the floor's edge (50 m away, 0.3 m below: elevations
    // down to −0.34°) reaches the meter: E ≈ π·L·α² ≈ 9·10⁻⁵.
    let down = read(&scene, &table, &chunks, &MeterLayout::Grid(plane(0.3, 6, false)));
    assert!(down.value.iter().all(|v| v[0] < 5e-4), "{:?}", down.value);
}

/// A plane in the air 0.4 m under a Lambertian square emitter (no point light, a black floor):
/// the light reaches it only as the area light's direct term, sampled from each cell; each cell
/// reads the closed form (`panel_irradiance`) within its stated error.
#[test]
fn plane_in_the_air_under_an_area_light() {
    let (l, h, half) = (1.5f32, 0.6f32, 0.5f32);
    let scene = Scene::build(&panel_over_black_floor(l, h, half)).unwrap();
    let (table, chunks) = trace_chunks(&scene, 1_000_000, 4);
    let y = 0.2;
    let got = read(&scene, &table, &chunks, &MeterLayout::Grid(plane(y, 6, true)));
    let e = |x: f64, z: f64| panel_irradiance(l as f64, (h - y) as f64, half as f64, x, z);
    let expected: Vec<f64> = (0..36).map(|t| cell_mean(6, t, &e)).collect();
    check("area light", &got, &expected, &[0.0; 36]);
}

/// Points under a Lambertian square emitter, from a small dataset (4096 paths, one chunk): under
/// its centre, a corner, an edge and off its side, each within max(1 %, 4 SE) of the closed form
/// with default settings — the direct term sampled at the points carries the light, and the
/// stored emission points are not connected too (that would read twice the light).
#[test]
fn points_under_an_area_light_from_a_small_dataset() {
    let (l, h, half) = (1.5f32, 2.0f32, 0.5f32);
    let scene = Scene::build(&panel_over_black_floor(l, h, half)).unwrap();
    let (table, chunks) = trace_chunks(&scene, 4096, 8);
    let at = [(0.0f32, 0.0f32), (0.5, 0.5), (0.5, 0.0), (1.5, 0.3), (3.0, 2.0)];
    let points: Vec<MeterPoint> =
        at.iter().map(|&(x, z)| MeterPoint::new(Vec3::new(x, 0.0, z), Vec3::Y).unwrap()).collect();
    let got = read(&scene, &table, &chunks, &MeterLayout::points(points).unwrap());
    for (k, &(x, z)) in at.iter().enumerate() {
        let e = panel_irradiance(l as f64, h as f64, half as f64, x as f64, z as f64);
        let (v, se) = (got.value[k][0], got.std_error[k][0]);
        eprintln!("({x}, {z}): {v} ± {se} vs {e}");
        assert!(se.is_finite() && se <= 0.01 * e, "({x}, {z}): {v} ± {se}");
        assert!((v - e).abs() <= (4.0 * se).max(0.01 * e), "({x}, {z}): {v} ± {se} vs {e}");
    }
}

/// The area light of `plane_in_the_air_under_an_area_light` 2 m up, seen through a horizontal
/// pane at 1 m (the floor black: only the area light's direct term carries light): a tinted
/// filter (a thin sheet of index 1: no reflection, T = its tint at every angle, per channel)
/// reads the closed form times the tint within its stated error, its channels in the tint's
/// ratios; clear glass (n = 1.52) over points under a small panel (every connection within 6°
/// of the normal, where T stays within 10⁻⁴ of T(0) = (1 − r)/(1 + r)) reads the closed form
/// times T(0). Shadow rays that stopped at the pane read 0.
#[test]
fn stored_samples_reach_the_meter_through_a_pane() {
    use opticks_core::bsdf::{Bsdf, Material, ThinDielectric};
    let with_pane = |half: f32, pane: ThinDielectric| {
        let mut desc = panel_over_black_floor(1.5, 2.0, half);
        desc.materials.push(Material {
            name: "pane".into(),
            bsdf: Bsdf::ThinDielectric(pane),
            two_sided: false,
        });
        let s = 3.0;
        let q = [Vec3::new(-s, 1.0, -s), Vec3::new(-s, 1.0, s), Vec3::new(s, 1.0, s), Vec3::new(s, 1.0, -s)];
        desc.meshes.push(quad("pane", q, 1, None));
        Scene::build(&desc).unwrap()
    };
    let tint = Rgb::new(0.8, 0.5, 0.2);
    let scene = with_pane(0.5, ThinDielectric::new(1.0, 1.0, Rgb::ONE, tint).unwrap());
    let (table, chunks) = trace_chunks(&scene, 1_000_000, 6);
    let y = 0.2;
    let got = read(&scene, &table, &chunks, &MeterLayout::Grid(plane(y, 6, true)));
    let e = |x: f64, z: f64| tint.x as f64 * panel_irradiance(1.5, (2.0 - y) as f64, 0.5, x, z);
    let expected: Vec<f64> = (0..36).map(|t| cell_mean(6, t, &e)).collect();
    check("tinted filter", &got, &expected, &[0.0; 36]);
    for v in &got.value {
        for (c, t) in [(1, tint.y), (2, tint.z)] {
            assert!((v[c] / v[0] - (t / tint.x) as f64).abs() < 1e-4, "channels in the tint's ratios: {v:?}");
        }
    }

    let (n, half) = (1.52f64, 0.1f32);
    let clear = with_pane(half, ThinDielectric::new(n as f32, 1.0, Rgb::ONE, Rgb::ONE).unwrap());
    let (table, chunks) = trace_chunks(&clear, 1_000_000, 7);
    let points: Vec<MeterPoint> = (0..36)
        .map(|k| Vec3::new(-0.05 + 0.02 * (k % 6) as f32, y, -0.05 + 0.02 * (k / 6) as f32 + 0.003))
        .map(|p| MeterPoint::new(p, Vec3::Y).unwrap())
        .collect();
    let got = read(&clear, &table, &chunks, &MeterLayout::points(points.clone()).unwrap());
    let r = ((n - 1.0) / (n + 1.0)).powi(2);
    let t0 = (1.0 - r) / (1.0 + r);
    let expected: Vec<f64> = points
        .iter()
        .map(|p| {
            t0 * panel_irradiance(
                1.5,
                (2.0 - y) as f64,
                half as f64,
                p.position.x as f64,
                p.position.z as f64,
            )
        })
        .collect();
    check("clear glass", &got, &expected, &[0.0; 36]);
}

/// Inside the closed furnace room, planes in the air at y = 0.5 facing the light and facing the
/// floor match Mitsuba 3's `irradiancemeter` (`volpath`, 16.8 M samples per cell) within the
/// two estimates' combined error.
#[test]
fn plane_in_the_air_in_a_closed_room_matches_mitsuba() {
    let path = repo().join("testdata/mitsuba/meter-furnace/reference.json");
    let reference: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let scene = load("furnace");
    let (table, chunks) = trace_chunks(&scene, 1_000_000, 5);
    let (mut got, mut expected, mut ref_se) = (Reading::zero(0), Vec::new(), Vec::new());
    for grid in ["up", "down"] {
        let g = &reference["grids"][grid];
        let v3 = |k: &str| {
            let a: Vec<f32> = g[k].as_array().unwrap().iter().map(|x| x.as_f64().unwrap() as f32).collect();
            Vec3::new(a[0], a[1], a[2])
        };
        let meter = IlluminanceMeter::new(v3("origin"), v3("u"), v3("v"), 4, 4).unwrap();
        let r = read(&scene, &table, &chunks, &MeterLayout::Grid(meter));
        let mut cells = vec![(0.0, 0.0); 16];
        for c in reference["cells"].as_array().unwrap().iter().filter(|c| c["grid"] == grid) {
            let (i, j) = (c["i"].as_u64().unwrap() as usize, c["j"].as_u64().unwrap() as usize);
            cells[j * 4 + i] = (c["E"].as_f64().unwrap(), c["se"].as_f64().unwrap());
        }
        expected.extend(cells.iter().map(|c| c.0));
        ref_se.extend(cells.iter().map(|c| c.1));
        got.value.extend(r.value);
        got.std_error.extend(r.std_error);
    }
    check("furnace", &got, &expected, &ref_se);
}

fn opticks(args: &[&str], dir: &std::path::Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_opticks")).args(args).current_dir(dir).output().unwrap()
}

/// The rows of a measure CSV after its header, as numbers.
fn rows(csv: &str) -> Vec<Vec<f64>> {
    csv.lines().skip(1).map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect()).collect()
}

/// `opticks measure --points` in the furnace room: the CSV has one row per point in file
/// order (normals normalised) and each point agrees, within the errors, with a 2 mm cell
/// around it measured by `--plane` in the air; bad points files and options are refused,
/// naming the file and line, and nothing is written.
#[test]
fn measure_at_points_from_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = scene_file("furnace", "scene.xml");
    let ok = |o: std::process::Output| {
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    ok(opticks(&["trace", scene.to_str().unwrap(), "--paths", "300000", "-o", "f.opds"], d));
    let points: [([f64; 3], [f64; 3]); 3] = [
        ([0.5, 0.5, 0.5], [0.0, 1.0, 0.0]),
        ([0.3, 0.2, 0.7], [0.0, -2.0, 0.0]),
        ([0.5, 0.9, 0.5], [1.0, 0.0, 0.0]),
    ];
    let mut file = String::from("# x y z nx ny nz\nx,y,z,nx,ny,nz\n");
    for (p, n) in &points {
        file += &format!("{} {} {}, {},{},{}\n", p[0], p[1], p[2], n[0], n[1], n[2]);
    }
    std::fs::write(d.join("pts.csv"), file).unwrap();
    let out = ok(opticks(&["measure", "f.opds", "--points", "pts.csv", "-o", "p.csv"], d));
    assert!(out.contains("3 points") && out.contains("relative standard error"), "{out}");
    let text = std::fs::read_to_string(d.join("p.csv")).unwrap();
    assert_eq!(
        text.lines().next().unwrap(),
        "point,x,y,z,nx,ny,nz,E_R,E_G,E_B,E_v_lux,SE_R,SE_G,SE_B,SE_v_lux"
    );
    let got = rows(&text);
    assert_eq!(got.len(), 3);
    let s = 0.002f32;
    for (k, ((p, n), row)) in points.iter().zip(&got).enumerate() {
        assert_eq!(row[0], k as f64);
        assert!(row[1..4].iter().zip(p).all(|(a, b)| (a - b).abs() < 1e-6), "{row:?}");
        let len = n.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!(row[4..7].iter().zip(n).all(|(a, b)| (a - b / len).abs() < 1e-6), "normalised: {row:?}");
        // The 2 mm cell facing the same way: u × v = n.
        let (u, v) = match k {
            0 => (Vec3::Z * s, Vec3::X * s),
            1 => (Vec3::X * s, Vec3::Z * s),
            _ => (Vec3::Y * s, Vec3::Z * s),
        };
        let o = Vec3::from(p.map(|x| x as f32)) - 0.5 * (u + v);
        let plane = format!("{},{},{},{},{},{},{},{},{}", o.x, o.y, o.z, u.x, u.y, u.z, v.x, v.y, v.z);
        ok(opticks(
            &["measure", "f.opds", "--plane", &plane, "--cells", "1x1", "-o", "c.csv", "--seed", "9"],
            d,
        ));
        let cell = rows(&std::fs::read_to_string(d.join("c.csv")).unwrap()).remove(0);
        let (a, b) = ((row[7], row[11]), (cell[5], cell[9]));
        assert!(a.0 > 0.0 && a.1 > 0.0 && b.1 > 0.0, "{a:?} {b:?}");
        assert!((a.0 - b.0).abs() < 4.0 * a.1.hypot(b.1), "point {k}: {a:?} vs the cell around it {b:?}");
    }
    for (file, args, msg) in [
        ("0,0,0,0,1,0\n\n1,2,3,0,1\n", vec![], "bad.csv:3: expected 6 numbers"),
        ("0.5,0.5,0.5,0,1,zero\n", vec![], "bad.csv:1: 'zero' is not a number"),
        ("0.5,0.5,0.5,0,0,0\n", vec![], "bad.csv:1: the normal"),
        ("# only a comment\n", vec![], "bad.csv: 0 points"),
        ("0.5,0.5,0.5,0,1,0\n", vec!["--png", "x.png"], "--png"),
        ("0.5,0.5,0.5,0,1,0\n", vec!["--cells", "2x2"], "--cells is for planes"),
        ("0.5,0.5,0.5,0,1,0\n", vec!["--estimator", "samples"], "cannot read points"),
    ] {
        std::fs::write(d.join("bad.csv"), file).unwrap();
        let mut a = vec!["measure", "f.opds", "--points", "bad.csv", "-o", "never.csv"];
        a.extend(args);
        let o = opticks(&a, d);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(msg), "{a:?} on {file:?}: {err}");
        assert!(!d.join("never.csv").exists() && !d.join("x.png").exists());
    }
    let o = opticks(&["measure", "f.opds", "--points", "f.opds", "-o", "never.csv"], d);
    assert!(!o.status.success(), "a dataset is not a points file");
    let o = opticks(&["measure", "f.opds", "--points", "pts.csv", "-o", "pts.csv"], d);
    assert!(!o.status.success(), "the output may not replace the points file");
}
