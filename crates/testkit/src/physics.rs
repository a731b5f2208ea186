//! Helpers shared by the end-to-end tests that need only the core (the core's own physics
//! tests use them too): trace-and-render in memory,
//! the small scenes and statistics the analytic tests build on (grey Lambertian materials, quads
//! and boxes, the emissive furnace, the emitting panel, mean and standard error).

use opticks_core::bsdf::{Bsdf, Lambert, Material};
use opticks_core::dataset::{Chunk, Directions, Heuristic, LightTable};
use opticks_core::film::Film;
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::{
    AreaEmission, CameraDesc, CameraKind, MeshDesc, PointLightDesc, Scene, SceneDescription,
};
use opticks_core::sensor::bidirectional::{Allocation, CacheChunk, Renderer, Settings, combine};
use opticks_core::sensor::{Pinhole, SampleBatch, Sensor, render};
use opticks_core::trace::{TraceSettings, trace};

/// The scene's own camera.
pub fn camera(scene: &Scene) -> Pinhole {
    Pinhole::new(scene.camera.as_ref().expect("scene has a camera")).unwrap()
}

/// Traces `paths` light paths with `seed` into memory.
pub fn trace_chunks(scene: &Scene, paths: u64, seed: u64) -> (LightTable, Vec<Chunk>) {
    trace_chunks_with(scene, &TraceSettings { paths, seed, ..Default::default() })
}

/// Traces with any settings into memory.
pub fn trace_chunks_with(scene: &Scene, settings: &TraceSettings) -> (LightTable, Vec<Chunk>) {
    let mut chunks: Vec<Chunk> = Vec::new();
    let table = trace(
        scene,
        settings,
        |c| {
            chunks.push(c);
            Ok::<(), ()>(())
        },
        |_| {},
    )
    .unwrap();
    (table, chunks)
}

/// Renders in-memory chunks through a sensor.
pub fn render_chunks(scene: &Scene, sensor: &Sensor, table: &LightTable, chunks: &[Chunk]) -> Film {
    render(scene, sensor, chunks.len(), |i| batch(table, chunks, i), |_| {}).unwrap()
}

/// In-memory chunk `i` as the sample batch a sensor reads.
pub fn batch<'a>(table: &LightTable, chunks: &'a [Chunk], i: usize) -> Result<SampleBatch<'a>, ()> {
    Ok(SampleBatch {
        flux_per_path: table.flux_per_path(chunks[i].light as usize),
        samples: &chunks[i].samples,
    })
}

/// Traces `paths` light paths with `seed` and renders them through `cam`, in memory.
pub fn trace_and_render(scene: &Scene, cam: &Pinhole, paths: u64, seed: u64) -> Film {
    trace_and_render_with(scene, cam, &TraceSettings { paths, seed, ..Default::default() })
}

/// Traces with any settings and renders through `cam`, in memory.
pub fn trace_and_render_with(scene: &Scene, cam: &Pinhole, settings: &TraceSettings) -> Film {
    let (table, chunks) = trace_chunks_with(scene, settings);
    render_chunks(scene, &Sensor::from(*cam), &table, &chunks)
}

/// Renders in-memory chunks with the bidirectional estimator through `sensor`: `spp` camera
/// paths per pixel, n_c = `connections`, the chunks' MIS records if `records` (else the camera
/// strategies alone: emitter hits and NEE), the power heuristic the tracer's default records use.
#[allow(clippy::too_many_arguments)]
pub fn render_bidirectional(
    scene: &Scene,
    sensor: Sensor,
    table: &LightTable,
    chunks: &[Chunk],
    records: bool,
    spp: u32,
    connections: u32,
    seed: u64,
) -> Film {
    render_bidirectional_allocated(
        scene,
        sensor,
        table,
        chunks,
        records,
        &Allocation::Uniform(spp),
        connections,
        seed,
    )
}

/// [`render_bidirectional`] with one camera pass of `allocation`'s camera paths per pixel (the
/// same everywhere, or pixel by pixel).
#[allow(clippy::too_many_arguments)]
pub fn render_bidirectional_allocated(
    scene: &Scene,
    sensor: Sensor,
    table: &LightTable,
    chunks: &[Chunk],
    records: bool,
    allocation: &Allocation,
    connections: u32,
    seed: u64,
) -> Film {
    let views = chunks
        .iter()
        .map(|c| {
            CacheChunk::new(c.light, c.paths, &c.samples, if records { &c.records } else { &[] }).unwrap()
        })
        .collect();
    let names: Vec<&str> = table.lights.iter().map(|l| l.name.as_str()).collect();
    let flux: Vec<Rgb> = (0..names.len()).map(|k| table.flux_per_path(k)).collect();
    let settings =
        Settings { connections, seed, heuristic: Heuristic::Power, directions: Directions::Importance };
    let r = Renderer::allocated(scene, sensor, views, &names, &flux, settings, allocation, 1);
    let splat = r.splat_pass(|_| {}, || false).unwrap();
    let cam = r.camera_pass(0, allocation, |_| {}, || false).unwrap();
    combine(&splat, &cam, allocation, 1)
}

/// A Lambertian BSDF of grey albedo.
pub fn lambert_bsdf(albedo: f32) -> Bsdf {
    Bsdf::Lambert(Lambert::new(Rgb::splat(albedo)).unwrap())
}

/// A grey Lambertian material.
pub fn lambert(name: &str, albedo: f32, two_sided: bool) -> Material {
    Material { name: name.into(), bsdf: lambert_bsdf(albedo), two_sided }
}

/// A quad a-b-c-d as a mesh (counter-clockwise seen from its front).
pub fn quad(name: &str, q: [Vec3; 4], material: usize, emission: Option<Rgb>) -> MeshDesc {
    MeshDesc {
        name: name.into(),
        positions: q.to_vec(),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material,
        emission: emission.map(AreaEmission::lambertian),
        ..Default::default()
    }
}

/// The six inward-facing faces of the box [lo, hi]: floor (y = lo.y), ceiling, x0, x1, z0, z1.
pub fn inward_box(lo: Vec3, hi: Vec3, material: usize, emission: Option<Rgb>) -> Vec<MeshDesc> {
    let c = |x: bool, y: bool, z: bool| {
        Vec3::new(if x { hi.x } else { lo.x }, if y { hi.y } else { lo.y }, if z { hi.z } else { lo.z })
    };
    let (f, t) = (false, true);
    vec![
        quad("floor", [c(f, f, f), c(f, f, t), c(t, f, t), c(t, f, f)], material, emission),
        quad("ceiling", [c(f, t, f), c(t, t, f), c(t, t, t), c(f, t, t)], material, emission),
        quad("x0", [c(f, f, f), c(f, t, f), c(f, t, t), c(f, f, t)], material, emission),
        quad("x1", [c(t, f, f), c(t, f, t), c(t, t, t), c(t, t, f)], material, emission),
        quad("z0", [c(f, f, f), c(t, f, f), c(t, t, f), c(f, t, f)], material, emission),
        quad("z1", [c(f, f, t), c(f, t, t), c(t, t, t), c(t, f, t)], material, emission),
    ]
}

/// The emissive furnace: the closed box [−1, 1]³ whose every face emits `le` inward and reflects
/// with two-sided grey albedo `rho`, so the radiance everywhere inside is `le / (1 − rho)`.
pub fn emissive_furnace(le: f32, rho: f32, camera: Option<CameraDesc>) -> SceneDescription {
    SceneDescription {
        materials: vec![lambert("grey", rho, true)],
        meshes: inward_box(Vec3::splat(-1.0), Vec3::splat(1.0), 0, Some(Rgb::splat(le))),
        point_lights: vec![],
        camera,
        ..Default::default()
    }
}

/// A camera inside the [`emissive_furnace`], looking obliquely into a corner.
pub fn furnace_view(fov_x_degrees: f32, width: u32, height: u32) -> CameraDesc {
    CameraDesc {
        eye: Vec3::new(0.2, -0.3, 0.1),
        target: Vec3::new(1.0, 0.2, -0.4),
        up: Vec3::Y,
        fov_x_degrees,
        width,
        height,
        kind: CameraKind::Perspective,
        film: Default::default(),
    }
}

/// Asserts that the image of a uniform scene reads `expected` in every channel's mean (within
/// 0.5 %) and in every 8×8 block (see [`assert_blocks_uniform`]); `what` labels the printout.
pub fn assert_uniform(what: &str, film: &Film, expected: f64) {
    let m = film.mean();
    eprintln!("{what} {m:?}, expected {expected}");
    for c in m {
        assert!((c / expected - 1.0).abs() < 0.005, "mean {c} vs {expected}");
    }
    // Every 8×8 block of pixels, not only the mean.
    assert_blocks_uniform(film, expected);
}

/// Asserts that every 8×8 block of pixels (green channel) reads `expected` within 3 %.
pub fn assert_blocks_uniform(film: &Film, expected: f64) {
    let w = film.width as usize;
    for by in 0..film.height as usize / 8 {
        for bx in 0..w / 8 {
            let s: f64 = (0..64).map(|k| film.pixels[(by * 8 + k / 8) * w + bx * 8 + k % 8][1]).sum();
            assert!(
                (s / 64.0 / expected - 1.0).abs() < 0.03,
                "block ({bx},{by}): {} vs {expected}",
                s / 64.0
            );
        }
    }
}

/// The panel [−½, ½]² in the plane z = 0, facing +z, emitting radiance `l` from a black one-sided
/// material, alone in the scene.
pub fn emitting_panel(l: Rgb) -> SceneDescription {
    let panel = quad(
        "panel",
        [
            Vec3::new(-0.5, -0.5, 0.0),
            Vec3::new(0.5, -0.5, 0.0),
            Vec3::new(0.5, 0.5, 0.0),
            Vec3::new(-0.5, 0.5, 0.0),
        ],
        0,
        Some(l),
    );
    SceneDescription {
        materials: vec![lambert("black", 0.0, false)],
        meshes: vec![panel],
        point_lights: vec![],
        camera: None,
        ..Default::default()
    }
}

/// How many of the four corner rays of pixel `p` of `cam` hit the [`emitting_panel`] (4: the pixel
/// sees only the panel; 0: it does not see it).
pub fn corners_on_panel(cam: &Pinhole, p: usize) -> usize {
    let (i, j) = (p % cam.width as usize, p / cam.width as usize);
    [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
        .iter()
        .filter(|(a, b)| {
            let d = cam.direction((i as f32 + a) / cam.width as f32, (j as f32 + b) / cam.height as f32);
            let x = cam.eye + (-cam.eye.z / d.z) * d;
            x.x.abs() < 0.5 && x.y.abs() < 0.5
        })
        .count()
}

/// Mean and standard error of the mean.
pub fn mean_and_error(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// An icosphere (icosahedron subdivided `levels` times), outward normals.
pub fn icosphere(name: &str, centre: Vec3, radius: f32, levels: u32, material: usize) -> MeshDesc {
    let p = (1.0 + 5f32.sqrt()) / 2.0;
    let mut v: Vec<Vec3> = [
        (-1.0, p, 0.0),
        (1.0, p, 0.0),
        (-1.0, -p, 0.0),
        (1.0, -p, 0.0),
        (0.0, -1.0, p),
        (0.0, 1.0, p),
        (0.0, -1.0, -p),
        (0.0, 1.0, -p),
        (p, 0.0, -1.0),
        (p, 0.0, 1.0),
        (-p, 0.0, -1.0),
        (-p, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut t: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, v: &mut Vec<Vec3>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(((v[a as usize] + v[b as usize]) * 0.5).normalize());
                v.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(t.len() * 4);
        for [a, b, c] in t {
            let (ab, bc, ca) = (midpoint(a, b, &mut v), midpoint(b, c, &mut v), midpoint(c, a, &mut v));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        t = next;
    }
    // Make every triangle wind counter-clockwise seen from outside.
    for tri in &mut t {
        let [a, b, c] = tri.map(|i| v[i as usize]);
        if (b - a).cross(c - a).dot(a + b + c) < 0.0 {
            tri.swap(1, 2);
        }
    }
    MeshDesc {
        name: name.into(),
        positions: v.iter().map(|&x| centre + radius * x).collect(),
        triangles: t,
        material,
        emission: None,
        ..Default::default()
    }
}

/// `mesh` with every triangle's winding reversed: its front faces the other way (an icosphere
/// whose normals point to its centre, for closed measuring spheres).
pub fn turned_inside_out(mut mesh: MeshDesc) -> MeshDesc {
    mesh.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    mesh
}

/// An isotropic point light named `name` at `position`, of intensity `intensity` (W/sr).
pub fn point_light(name: &str, position: Vec3, intensity: Rgb) -> PointLightDesc {
    PointLightDesc { name: name.into(), position, intensity, ..Default::default() }
}

/// A square Lambertian emitter of radiance `l` (half-size `half`, at height `h`, facing −y)
/// over a black floor y = 0 of half-size 50: the meter tests' parallel-rectangle scene
/// ([`panel_irradiance`] is its closed form).
pub fn panel_over_black_floor(l: f32, h: f32, half: f32) -> SceneDescription {
    let (s, y) = (50.0, 0.0);
    let floor = quad(
        "floor",
        [Vec3::new(-s, y, -s), Vec3::new(-s, y, s), Vec3::new(s, y, s), Vec3::new(s, y, -s)],
        0,
        None,
    );
    let panel = quad(
        "panel",
        [
            Vec3::new(-half, h, -half),
            Vec3::new(half, h, -half),
            Vec3::new(half, h, half),
            Vec3::new(-half, h, half),
        ],
        0,
        Some(Rgb::splat(l)),
    );
    SceneDescription {
        materials: vec![lambert("black", 0.0, false)],
        meshes: vec![floor, panel],
        ..Default::default()
    }
}

/// The irradiance on a plane facing the square emitter of [`panel_over_black_floor`] (radiance
/// `l`, half-size `half`), at distance `d` below it and at (x, z): four superposed corners of
/// E = (L/2)·[A/√(1+A²)·atan(B/√(1+A²)) + B/√(1+B²)·atan(A/√(1+B²))], A = a/d, B = b/d (= π·L·F
/// with F the corner view factor).
pub fn panel_irradiance(l: f64, d: f64, half: f64, x: f64, z: f64) -> f64 {
    let corner = |a: f64, b: f64| {
        let (sa, sb) = (a.signum(), b.signum());
        let (a, b) = (a.abs() / d, b.abs() / d);
        let (ra, rb) = ((1.0 + a * a).sqrt(), (1.0 + b * b).sqrt());
        sa * sb * 0.5 * l * (a / ra * (b / ra).atan() + b / rb * (a / rb).atan())
    };
    corner(half - x, half - z) - corner(-half - x, half - z) - corner(half - x, -half - z)
        + corner(-half - x, -half - z)
}
