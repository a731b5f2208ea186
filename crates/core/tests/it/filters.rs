//! Reconstruction filters and crop windows (`opticks_core::sensor::raster`) through both
//! estimators: the light estimator's filtered splats and the bidirectional estimator's camera
//! paths (which draw their film offsets from the filter, every MIS density carrying the
//! pixel's f̂) must estimate the same filtered pixels. The Cornell box through a cropped film,
//! tent and gaussian, compared in the image mean and an 8 × 8 grid of regions: each estimate's
//! standard errors measured from 16 disjoint batches of its trace (the bidirectional batches
//! each with its own camera seed), the difference within 5.5σ (195 comparisons, ~30 degrees of
//! freedom: a false alarm below 1 %).

use opticks_testkit as common;

use common::regions::{self, Estimate};
use common::*;
use opticks_core::dataset::Chunk;
use opticks_core::scene::{Scene, cornell_box};
use opticks_core::sensor::{Crop, FilmSpec, Filter, Sensor};
use opticks_core::trace::TraceSettings;

const K: usize = 16;
const GRID: usize = 8;
const Z: f64 = 5.5;

/// The bidirectional estimate from `k` disjoint batches of one trace, each rendered with its own
/// camera seed (`spp` camera paths per pixel, one connection), with the standard errors of the
/// image and region means from their spread.
fn bidirectional_estimate(scene: &Scene, sensor: Sensor, paths: u64, spp: u32) -> Estimate {
    let (table, chunks) = trace_chunks(scene, paths, 77);
    let group = regions::deal(&table, &chunks, K);
    regions::from_renders(K, GRID, sensor.width() as usize, |g| {
        let members: Vec<Chunk> =
            (0..chunks.len()).filter(|&i| group[i] == g).map(|i| chunks[i].clone()).collect();
        let mut lit = table.clone();
        for (k, l) in lit.lights.iter_mut().enumerate() {
            // Φ_k/N'_k for the batch's N'_k paths of light k.
            let in_batch: u64 = members.iter().filter(|c| c.light as usize == k).map(|c| c.paths).sum();
            l.power *= (l.paths as f64 / in_batch as f64) as f32;
        }
        render_bidirectional(scene, sensor, &lit, &members, true, spp, 1, 1000 + g as u64).to_rgb_f32()
    })
}

#[test]
fn light_and_bidirectional_estimators_agree_through_tent_and_gaussian_filters() {
    let mut desc = cornell_box();
    for filter in [Filter::Tent { radius: 1.0 }, Filter::Gaussian { stddev: 0.5 }] {
        let cam = desc.camera.as_mut().unwrap();
        (cam.width, cam.height) = (40, 30);
        cam.film = FilmSpec { crop: Some(Crop { x: 4, y: 3, width: 32, height: 24 }), filter };
        let scene = Scene::build(&desc).unwrap();
        let sensor = Sensor::new(scene.camera.as_ref().unwrap()).unwrap();
        assert_eq!((sensor.width(), sensor.height()), (32, 24));
        let settings = TraceSettings { paths: 1_600_000, seed: 3, ..Default::default() };
        let light = regions::estimate(&scene, sensor, &settings, K, GRID);
        let bidirectional = bidirectional_estimate(&scene, sensor, 400_000, 16);
        regions::assert_same_expectation(&format!("{filter:?}"), &bidirectional, &light, Z);
    }
}
