//! Shading normals end to end: the light tracer with the adjoint BSDF (docs/estimator.md §4, Veach §5.3)
//! must converge to what a camera-side evaluation with shading normals computes, and vertex
//! normals equal to the geometric ones must change nothing.

// Only the core-only helpers: this is a test of the core (`crates/core/Cargo.toml`).
use opticks_testkit as common;

use common::*;
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::{CameraDesc, CameraKind, MeshDesc, PointLightDesc, Scene, SceneDescription};
use opticks_core::sensor::Pinhole;
use std::f64::consts::PI;

const S: f32 = 3.0;
/// The plane's shading normal field n(x, z) ∝ (A·x, 1, B·z): linear, so barycentric
/// interpolation of its values at the quad's corners reproduces it exactly.
const A: f32 = 0.25;
const B: f32 = -0.2;

fn bent_plane(with_normals: bool) -> MeshDesc {
    let mut m = quad(
        "plane",
        [Vec3::new(-S, 0.0, -S), Vec3::new(-S, 0.0, S), Vec3::new(S, 0.0, S), Vec3::new(S, 0.0, -S)],
        0,
        None,
    );
    if with_normals {
        m.normals = m.positions.iter().map(|p| Vec3::new(A * p.x, 1.0, B * p.z)).collect();
    }
    m
}

fn scene(mesh: MeshDesc, light: Vec3, camera: CameraDesc) -> SceneDescription {
    SceneDescription {
        materials: vec![lambert("plane", 0.6, false)],
        meshes: vec![mesh],
        point_lights: vec![PointLightDesc {
            name: "bulb".into(),
            position: light,
            intensity: Rgb::splat(2.0),
            ..Default::default()
        }],
        camera: Some(camera),
        ..Default::default()
    }
}

/// A Lambertian plane with bent shading normals under a point light, light-traced, against the
/// camera-side radiance L = ρ/π·max(0, n_s·ω_l)·I/d² (zero where n_s·ω_c ≤ 0) at each pixel's
/// visible point. With the plane alone there is no interreflection, so this is exact per pixel;
/// it checks the sensor's connection (f_eff and the geometric |cos θ_x|).
#[test]
fn bent_normals_match_the_camera_side_radiance() {
    let (rho, intensity) = (0.6f64, 2.0f64);
    let light = Vec3::new(0.1, 1.0, -0.2);
    let cam_desc = CameraDesc {
        eye: Vec3::new(0.4, 2.5, 0.6),
        target: Vec3::ZERO,
        up: Vec3::new(0.0, 0.0, -1.0),
        fov_x_degrees: 70.0,
        width: 48,
        height: 40,
        kind: CameraKind::Perspective,
        film: Default::default(),
    };
    let scene_ = Scene::build(&scene(bent_plane(true), light, cam_desc)).unwrap();
    assert!(scene_.has_shading_normals());
    let cam = Pinhole::new(&cam_desc).unwrap();
    let film = trace_and_render(&scene_, &cam, 4_000_000, 11);

    // shading = false: the faceted plane's radiance, to show how far apart the two are.
    let radiance = |sx: f32, sy: f32, shading: bool| {
        let d = cam.direction(sx, sy);
        let x = cam.eye + (-cam.eye.y / d.y) * d;
        let ns = if shading { Vec3::new(A * x.x, 1.0, B * x.z).normalize() } else { Vec3::Y };
        let to_light = light - x;
        let d2 = to_light.length_squared() as f64;
        let (wl, wc) = (to_light.normalize(), (cam.eye - x).normalize());
        if ns.dot(wc) <= 0.0 {
            return 0.0;
        }
        rho / PI * (ns.dot(wl).max(0.0) as f64) * intensity / d2
    };
    let (w, h) = (cam.width as usize, cam.height as usize);
    let expected = |shading: bool| -> Vec<f64> {
        (0..w * h)
            .map(|p| {
                let (i, j) = (p % w, p / w);
                let mut sum = 0.0;
                for a in 0..8 {
                    for b in 0..8 {
                        let sx = (i as f32 + (a as f32 + 0.5) / 8.0) / w as f32;
                        let sy = (j as f32 + (b as f32 + 0.5) / 8.0) / h as f32;
                        sum += radiance(sx, sy, shading);
                    }
                }
                sum / 64.0
            })
            .collect()
    };
    let (want, flat) = (expected(true), expected(false));
    let got: Vec<f64> = film.pixels.iter().map(|p| p[0]).collect();
    let block = |v: &[f64], bx: usize, by: usize| {
        (0..64).map(|k| v[(by * 8 + k / 8) * w + bx * 8 + k % 8]).sum::<f64>()
    };
    let (mut worst, mut worst_flat) = (0.0f64, 0.0f64);
    for by in 0..h / 8 {
        for bx in 0..w / 8 {
            let r = block(&got, bx, by) / block(&want, bx, by);
            worst = worst.max((r - 1.0).abs());
            worst_flat = worst_flat.max((block(&flat, bx, by) / block(&want, bx, by) - 1.0).abs());
        }
    }
    let mean = got.iter().sum::<f64>() / want.iter().sum::<f64>();
    eprintln!(
        "mean ratio {mean:.5}, worst 8×8 block {worst:.4} (faceted plane would be {worst_flat:.3} off)"
    );
    // Measured (seed 11): mean 1.00000, blocks within 0.5 % where bright and 2.1 % in the two
    // dimmest corner blocks (30× darker, so ~5× the relative noise).
    assert!((mean - 1.0).abs() < 0.005, "image mean ratio {mean}");
    assert!(worst < 0.04, "worst block off by {worst}");
    assert!(worst_flat > 0.1, "the test must tell shading normals from none ({worst_flat})");
}

/// Vertex normals equal to the geometric normals leave the dataset and the fingerprint as they
/// are without normals: bit for bit.
#[test]
fn geometric_vertex_normals_change_nothing() {
    let cam = furnace_view(60.0, 8, 8);
    let light = Vec3::new(0.3, 1.5, 0.2);
    let mut flat_normals = bent_plane(false);
    flat_normals.normals = vec![Vec3::new(0.0, 2.0, 0.0); 4]; // any length: normalised
    let sphere = icosphere("ball", Vec3::new(0.0, 0.6, 0.0), 0.5, 2, 0);
    // The icosphere again, split per triangle so each corner can carry its face's normal.
    let mut split = MeshDesc { name: "split".into(), positions: vec![], triangles: vec![], ..sphere.clone() };
    for t in &sphere.triangles {
        let [a, b, c] = t.map(|i| sphere.positions[i as usize] + Vec3::new(1.2, 0.0, 0.0));
        let n = (b - a).cross(c - a).normalize();
        let k = split.positions.len() as u32;
        split.positions.extend([a, b, c]);
        split.normals.extend([n, n, n]);
        split.triangles.push([k, k + 1, k + 2]);
    }
    let mut plain = scene(bent_plane(false), light, cam);
    plain.meshes.extend([sphere.clone(), MeshDesc { normals: vec![], ..split.clone() }]);
    let mut with = scene(flat_normals, light, cam);
    with.meshes.extend([sphere, split]);
    let (a, b) = (Scene::build(&plain).unwrap(), Scene::build(&with).unwrap());
    assert!(!b.has_shading_normals());
    assert_eq!(a.fingerprint, b.fingerprint);
    let (ta, ca) = trace_chunks(&a, 50_000, 3);
    let (tb, cb) = trace_chunks(&b, 50_000, 3);
    assert_eq!(ta, tb);
    assert_eq!(ca, cb);
}

/// Bad vertex normals are errors naming the mesh; normals pointing against the winding turn the
/// triangle's front to their side (as pbrt and Mitsuba orient the geometric normal).
#[test]
fn vertex_normals_are_checked_and_orient_the_front() {
    let cam = furnace_view(60.0, 8, 8);
    let light = Vec3::new(0.0, 1.0, 0.0);
    let with = |normals: Vec<Vec3>| {
        let mut m = bent_plane(false);
        m.normals = normals;
        Scene::build(&scene(m, light, cam))
    };
    let e = with(vec![Vec3::Y; 3]).unwrap_err().to_string();
    assert!(e.contains("mesh 'plane': 3 vertex normals for 4 vertices"), "{e}");
    let e = with(vec![Vec3::Y, Vec3::ZERO, Vec3::Y, Vec3::Y]).unwrap_err().to_string();
    assert!(e.contains("vertex normal 1"), "{e}");
    let e = with(vec![Vec3::Y, Vec3::Y, Vec3::new(f32::NAN, 1.0, 0.0), Vec3::Y]).unwrap_err().to_string();
    assert!(e.contains("vertex normal 2"), "{e}");
    let down = with(vec![Vec3::new(0.1, -1.0, 0.0); 4]).unwrap();
    let n = down.normals_at(0, Vec3::ZERO);
    assert_eq!(n.geometric, -Vec3::Y);
    assert!(n.shading.dot(n.geometric) > 0.99);
}

/// The trace's β update with shading normals (the second bounce): the bent plane, lit by a
/// point light that shines only downward, reflects onto a black ceiling whose illuminance meter
/// must read ∫ L(x→y)·cos θ_y·cos θ_x/r² dA_x with the camera-side L of the test above. A
/// tracer without the adjoint correction would converge to L·|ω_l·n_g|·|ω·n_s|/(|ω_l·n_s|·|ω·n_g|)
/// instead; the test checks that it can tell the two apart.
#[test]
fn second_bounce_matches_the_camera_side_radiance() {
    use opticks_core::light::EmissionProfile;
    use opticks_core::math::Frame;
    use opticks_core::sensor::{IlluminanceMeter, measure};
    let (rho, intensity, height) = (0.6f64, 2.0f64, 1.5f32);
    let light = Vec3::new(0.1, 0.5, -0.2);
    let cam = furnace_view(60.0, 8, 8);
    let mut desc = scene(bent_plane(true), light, cam);
    desc.point_lights[0].profile = Some(EmissionProfile::Spot {
        cutoff_angle: std::f32::consts::FRAC_PI_2,
        beam_width: std::f32::consts::FRAC_PI_2,
    });
    desc.point_lights[0].orientation = Some(Frame::from_normal(-Vec3::Y));
    desc.materials.push(lambert("black", 0.0, false));
    desc.meshes.push(quad(
        "ceiling",
        [
            Vec3::new(-S, height, -S),
            Vec3::new(S, height, -S),
            Vec3::new(S, height, S),
            Vec3::new(-S, height, S),
        ],
        1,
        None,
    ));
    let scene_ = Scene::build(&desc).unwrap();
    assert_eq!(scene_.normals_at(2, Vec3::new(0.0, height, 0.0)).geometric, -Vec3::Y);
    let (nx, ny) = (4u32, 4u32);
    let meter = IlluminanceMeter::new(
        Vec3::new(-1.0, height, -1.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 2.0),
        nx,
        ny,
    )
    .unwrap();
    let (table, chunks) = trace_chunks(&scene_, 4_000_000, 21);
    let got = measure(&meter, &scene_, chunks.len(), |i| batch(&table, &chunks, i), |_| {}).unwrap();

    // Irradiance at y from the plane, by the midpoint rule on a 240×240 grid.
    let irradiance = |y: Vec3, adjoint: bool| {
        let m = 240;
        let h = 2.0 * S / m as f32;
        let mut sum = 0.0f64;
        for a in 0..m {
            for b in 0..m {
                let x = Vec3::new(-S + (a as f32 + 0.5) * h, 0.0, -S + (b as f32 + 0.5) * h);
                let ns = Vec3::new(A * x.x, 1.0, B * x.z).normalize();
                let to_light = light - x;
                let d2 = to_light.length_squared() as f64;
                let wl = to_light.normalize();
                let r = y - x;
                let w = r.normalize();
                let (cl, co) = (ns.dot(wl), ns.dot(w));
                if cl <= 0.0 || co <= 0.0 {
                    continue;
                }
                let l = if adjoint { cl as f64 } else { (wl.y * co / w.y) as f64 };
                let radiance = rho / PI * l * intensity / d2;
                sum += radiance * (w.y as f64) * (w.y as f64) / r.length_squared() as f64;
            }
        }
        sum * (h * h) as f64
    };
    let cell = |i: u32, j: u32, adjoint: bool| {
        let mut s = 0.0;
        for (a, b) in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)] {
            let p = Vec3::new(
                -1.0 + 2.0 * (i as f32 + a) / nx as f32,
                height,
                -1.0 + 2.0 * (j as f32 + b) / ny as f32,
            );
            s += irradiance(p, adjoint);
        }
        s / 4.0
    };
    let (mut worst, mut worst_wrong, mut sum_got, mut sum_want) = (0.0f64, 0.0f64, 0.0, 0.0);
    for j in 0..ny {
        for i in 0..nx {
            let (want, wrong) = (cell(i, j, true), cell(i, j, false));
            let g = got.pixels[(j * nx + i) as usize][0];
            worst = worst.max((g / want - 1.0).abs());
            worst_wrong = worst_wrong.max((wrong / want - 1.0).abs());
            sum_got += g;
            sum_want += want;
        }
    }
    let mean = sum_got / sum_want;
    eprintln!("mean ratio {mean:.5}, worst cell {worst:.4}; without the adjoint correction {worst_wrong:.4}");
    // Measured (seed 21): mean 0.9968, worst cell 1.0 % (~0.7 % noise per cell); the plain BSDF
    // would put some cells 4.9 % off.
    assert!((mean - 1.0).abs() < 0.01, "mean ratio {mean}");
    assert!(worst < 0.02, "worst cell off by {worst}");
    assert!(worst_wrong > 2.0 * 0.02, "the test must tell the adjoint from the plain BSDF ({worst_wrong})");
}
