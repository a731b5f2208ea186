use opticks_core::dataset::Chunk;
use opticks_core::scene::{Pinhole, Scene, cornell_box};
use opticks_core::sensor::{SampleBatch, render_pinhole};
use opticks_core::trace::{TraceSettings, trace};
use std::time::Instant;

#[test]
fn quick_mean() {
    let scene = Scene::build(&cornell_box()).unwrap();
    let rr: u32 = std::env::var("RR").map(|s| s.parse().unwrap()).unwrap_or(5);
    let settings = TraceSettings { paths: 1 << 22, seed: 1, rr_depth: rr, ..Default::default() };
    let t0 = Instant::now();
    let mut chunks: Vec<Chunk> = Vec::new();
    let table = trace(&scene, &settings, |c| { chunks.push(c); Ok::<(), ()>(()) }, |_| {}).unwrap();
    let t1 = Instant::now();
    let n: usize = chunks.iter().map(|c| c.samples.len()).sum();
    let cam = Pinhole::new(scene.camera.as_ref().unwrap()).unwrap();
    let film = render_pinhole(&scene, &cam, chunks.len(), |i| Ok::<_, ()>(SampleBatch { flux_per_path: table.flux_per_path(chunks[i].light as usize), samples: &chunks[i].samples }), |_| {}).unwrap();
    let t2 = Instant::now();
    eprintln!("samples {n} ({:.2}/path) trace {:?} render {:?} mean {:?} (ref 0.244475 0.141444 0.060009)", n as f64 / settings.paths as f64, t1 - t0, t2 - t1, film.mean());
    let raw: Vec<u8> = film.to_rgb_f32().iter().flat_map(|x| x.to_le_bytes()).collect();
    std::fs::write("/tmp/quick.f32", raw).unwrap();
}
