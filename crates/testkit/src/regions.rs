//! Region statistics of light-traced images: the image mean and the means of a coarse grid of
//! regions, each with its standard error measured from the spread of disjoint batches of one
//! trace, and the check that two estimates (another strategy's, or Mitsuba's reference) agree
//! in all of them within a number of standard errors — so a bias confined to part of the image
//! is caught, not averaged away. Used by `strategies.rs` and `mitsuba_scenes.rs`.

use super::physics::{batch, trace_chunks_with};
use opticks_core::dataset::{Chunk, LightTable};
use opticks_core::scene::Scene;
use opticks_core::sensor::{SampleBatch, Sensor, render};
use opticks_core::trace::TraceSettings;

/// Per-channel means of the whole image (entry 0) and of the GRID × GRID regions (entries
/// 1..), with their standard errors; and the full image as interleaved RGB.
pub struct Estimate {
    /// Per-channel means: the image (entry 0), then the regions row by row.
    pub mean: Vec<[f64; 3]>,
    /// Their standard errors.
    pub err: Vec<[f64; 3]>,
    /// The whole image, interleaved RGB.
    pub image: Vec<f32>,
    /// Regions per side.
    pub grid: usize,
}

/// Traces with `settings`, renders `k` disjoint batches of chunks and measures the estimate of
/// the image and of every region of a `grid` × `grid` grid, with standard errors from their
/// spread.
pub fn estimate(
    scene: &Scene,
    sensor: impl Into<Sensor>,
    settings: &TraceSettings,
    k: usize,
    grid: usize,
) -> Estimate {
    let (table, chunks) = trace_chunks_with(scene, settings);
    let sensor: Sensor = sensor.into();
    let group = deal(&table, &chunks, k);
    from_renders(k, grid, sensor.width() as usize, |g| {
        let members: Vec<usize> = (0..chunks.len()).filter(|&i| group[i] == g).collect();
        let film =
            render(scene, &sensor, members.len(), |i| scaled_batch(&table, &chunks, &members, i), |_| {})
                .unwrap();
        film.pixels.iter().flat_map(|p| p.map(|x| x as f32)).collect()
    })
}

/// Per chunk, which of `k` disjoint batches it goes to: each light's chunks dealt round robin,
/// so that every batch holds every light (a batch without some light's chunks would miss its
/// light). Panics if a light has fewer than `k` chunks.
pub fn deal(table: &LightTable, chunks: &[Chunk], k: usize) -> Vec<usize> {
    let mut rank = vec![0usize; table.lights.len()];
    let group: Vec<usize> = chunks
        .iter()
        .map(|c| {
            let r = &mut rank[c.light as usize];
            *r += 1;
            (*r - 1) % k
        })
        .collect();
    assert!(
        rank.iter().all(|&n| n == 0 || n >= k),
        "every light needs at least {k} chunks for the error estimate: {rank:?} (trace more paths)"
    );
    group
}

/// The estimate of `k` independent renders (`render(g)`, interleaved RGB images `width` pixels
/// wide): their mean image, and the image's and every region's mean of a `grid` × `grid` grid
/// with standard errors from their spread.
pub fn from_renders(
    k: usize,
    grid: usize,
    width: usize,
    mut render: impl FnMut(usize) -> Vec<f32>,
) -> Estimate {
    let regions = 1 + grid * grid;
    let mut sums = vec![[0.0f64; 3]; regions];
    let mut squares = vec![[0.0f64; 3]; regions];
    let mut image: Vec<f32> = Vec::new();
    for g in 0..k {
        let rgb = render(g);
        image.resize(rgb.len(), 0.0);
        for (o, p) in image.iter_mut().zip(&rgb) {
            *o += p / k as f32;
        }
        for (r, m) in region_means(&rgb, width, grid).into_iter().enumerate() {
            for c in 0..3 {
                sums[r][c] += m[c];
                squares[r][c] += m[c] * m[c];
            }
        }
    }
    let k = k as f64;
    let mean: Vec<[f64; 3]> = sums.iter().map(|s| s.map(|x| x / k)).collect();
    let err = squares
        .iter()
        .zip(&mean)
        .map(|(q, m)| std::array::from_fn(|c| ((q[c] / k - m[c] * m[c]).max(0.0) / (k - 1.0)).sqrt()))
        .collect();
    Estimate { mean, err, image, grid }
}

/// Chunk `members[i]` as a batch that stands for the whole trace: its light's Φ/N_k scaled by
/// N_k over the paths of that light in the batch.
pub fn scaled_batch<'a>(
    table: &LightTable,
    chunks: &'a [Chunk],
    members: &[usize],
    i: usize,
) -> Result<SampleBatch<'a>, ()> {
    let mut b = batch(table, chunks, members[i])?;
    let light = chunks[members[i]].light;
    let in_batch: u64 =
        members.iter().map(|&j| &chunks[j]).filter(|c| c.light == light).map(|c| c.paths).sum();
    b.flux_per_path *= (table.lights[light as usize].paths as f64 / in_batch as f64) as f32;
    Ok(b)
}

/// The whole image's mean and the `grid` × `grid` region means, per channel, of an
/// interleaved RGB image `width` pixels wide.
pub fn region_means(rgb: &[f32], width: usize, grid: usize) -> Vec<[f64; 3]> {
    let (w, h) = (width, rgb.len() / 3 / width);
    let mut out = vec![[0.0f64; 3]; 1 + grid * grid];
    let mut counts = vec![0usize; 1 + grid * grid];
    for (i, p) in rgb.chunks(3).enumerate() {
        let (x, y) = (i % w, i / w);
        let r = 1 + (y * grid / h) * grid + x * grid / w;
        for idx in [0, r] {
            counts[idx] += 1;
            for c in 0..3 {
                out[idx][c] += p[c] as f64;
            }
        }
    }
    out.iter().zip(&counts).map(|(s, &n)| s.map(|x| x / n as f64)).collect()
}

/// Asserts that `v` agrees with `base` in the image mean and every region, within `z` standard
/// errors of their difference.
pub fn assert_same_expectation(name: &str, v: &Estimate, base: &Estimate, z_max: f64) {
    let mut worst = (0.0f64, 0usize, 0usize);
    for r in 0..v.mean.len() {
        for c in 0..3 {
            let sigma = v.err[r][c].hypot(base.err[r][c]);
            let d = v.mean[r][c] - base.mean[r][c];
            if sigma == 0.0 {
                assert_eq!(d, 0.0, "{name}: region {r} channel {c}");
                continue;
            }
            let z = d.abs() / sigma;
            if z > worst.0 {
                worst = (z, r, c);
            }
            let what = if r == 0 { "image mean".to_string() } else { format!("region {}", r - 1) };
            assert!(
                z < z_max,
                "{name}: {what}, channel {c}: {} vs default {} (difference {z:.1}σ, σ = {sigma:.3e})",
                v.mean[r][c],
                base.mean[r][c]
            );
        }
    }
    let rel = |e: &Estimate| e.err[0][1] / e.mean[0][1];
    eprintln!(
        "{name}: mean ratio {:.5} (standard error {:.3}%), worst of {} comparisons {:.2}σ (region {}, channel {})",
        v.mean[0][1] / base.mean[0][1],
        100.0 * rel(v).hypot(rel(base)),
        v.mean.len(),
        worst.0,
        worst.1 as i64 - 1,
        worst.2
    );
}
