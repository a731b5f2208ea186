//! The efficiency-driven allocation of camera paths (issue 25, design change 3): a short pilot
//! measures, tile by tile, how well each half of the estimator does alone, and the render then
//! spends its camera paths where they buy the most error.
//!
//! The light-tracing splats are nearly free where light tracing is strong (diffuse surfaces,
//! caustics seen directly); camera paths pay where it is weak (glossy and specular first hits,
//! anything seen through glass or in a mirror, which the splats cannot reach at all). The
//! pilot measures, per 8×8-pixel tile, from
//!
//! * one **camera-only pass** of one path per pixel (the camera strategies weighted as if there
//!   were no splats: c_LT ≈ 0): the tile's mean I_c and the per-path variance σ²_c, the latter
//!   from neighbouring pixels' differences (½(x_a − x_b)², which leaves out the image's own
//!   structure better than the tile's spread would), and
//! * the **unweighted splats of a subset of the cache** (the light estimator, c_LT = ∞): the
//!   tile's mean I_L and the variance of the whole splat film V_L, from the squared splats
//!   scaled to the whole cache (each light path adds to a pixel a few independent splats, so the
//!   sum of their squares estimates the variance of their sum). Where the splats miss light the
//!   camera paths see (I_c clearly above I_L: a mirror, glass), the missing part counts as error
//!   of the splats: V_L + (I_c − I_L)².
//!
//! Treating the two as independent estimates of the tile's value I, combined at their
//! precisions, a tile with n camera paths per pixel has relative variance
//! 1/(I²/V_L + n·I²/σ²_c); minimising its sum over the tiles for a given number of camera paths
//! gives n = k·σ_c/I − σ²_c/V_L (the Lagrange condition), at least 1 (every pixel keeps a camera
//! path: the allocation module's rule) and at most [`MAX_FACTOR`] times the mean, k found by
//! bisection so that the paths add up to the budget. I is regularised by a tenth of the image's
//! mean (dark tiles would otherwise ask for everything), and fractional counts are dithered
//! pixel by pixel with a fixed hash, so the mean is kept and the allocation is deterministic.
//! The MIS weights are not this model — it only decides where the paths go; any allocation
//! decided before the render's passes keeps it unbiased (`allocation` module docs), which is why
//! the pilot's own paths are not part of the image.

use super::Counts;
use super::allocation::Allocation;
use super::render::Renderer;
use super::splat::splat_chunk;
use super::vertex::Context;
use crate::film::SplatTarget;
use crate::math::{Rgb, luminance};
use rayon::prelude::*;

/// Tile side, in pixels.
const TILE: usize = 8;

/// The most camera paths per pixel a tile may get, as a multiple of the mean.
pub const MAX_FACTOR: f64 = 4.0;

/// Share of the cache whose splats the pilot measures (every `SPLAT_STRIDE`-th chunk, at least
/// one).
const SPLAT_STRIDE: usize = 8;

/// The pass number of the pilot's camera paths (never an image pass's).
const PILOT_PASS: u64 = u64::MAX - 1;

/// What the pilot measured (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct PilotMeasure {
    width: usize,
    height: usize,
    /// Per pixel, one camera-only path's luminance.
    camera: Vec<f64>,
    /// Per pixel, the splat subset's sum and sum of squares (luminance), already scaled to the
    /// whole cache.
    splat_sum: Vec<f64>,
    splat_squares: Vec<f64>,
    /// Seconds of wall time per camera path of the pilot's pass, and of the whole splat pass
    /// (the subset's, scaled to the cache).
    pub path_seconds: f64,
    /// See `path_seconds`.
    pub splat_seconds: f64,
}

/// Per-pixel sums and sums of squares of splats' luminance.
struct Moments {
    sum: Vec<f64>,
    squares: Vec<f64>,
}

impl SplatTarget for Moments {
    #[inline]
    fn splat(&mut self, index: usize, v: Rgb) {
        let l = luminance(v) as f64;
        self.sum[index] += l;
        self.squares[index] += l * l;
    }
}

impl PilotMeasure {
    /// Runs the pilot over `renderer`'s cache and sensor (its counts are replaced by the
    /// pilot's own); `None` if `stop` said so.
    pub fn run(renderer: &Renderer<'_>, stop: impl Fn() -> bool + Sync) -> Option<PilotMeasure> {
        let (width, height) = (renderer.sensor().width() as usize, renderer.sensor().height() as usize);
        let pixels = width * height;
        let base = renderer.context();
        // Camera strategies alone: c_LT ≈ 0 (no splats to share the paths with).
        let camera_ctx =
            Context { counts: Counts { light_trace: 0.0, ..base.counts }, pixel_light_trace: None, ..base };
        let t0 = std::time::Instant::now();
        let film =
            renderer.camera_pass_in(&camera_ctx, PILOT_PASS, &Allocation::Uniform(1), |_| {}, &stop)?;
        let path_seconds = t0.elapsed().as_secs_f64() / pixels.max(1) as f64;
        let t0 = std::time::Instant::now();
        let camera = film
            .pixels
            .iter()
            .map(|p| luminance(Rgb::new(p[0] as f32, p[1] as f32, p[2] as f32)) as f64)
            .collect();
        // The light estimator's splats (c_LT = ∞: the splat takes every path it can make).
        let splat_ctx =
            Context { counts: Counts { light_trace: 1e30, ..base.counts }, pixel_light_trace: None, ..base };
        let chunks = renderer.cache().chunks();
        let subset: Vec<_> = chunks.iter().step_by(SPLAT_STRIDE).collect();
        let (all, some): (u64, u64) =
            (chunks.iter().map(|c| c.paths).sum(), subset.iter().map(|c| c.paths).sum());
        let moments = subset
            .par_iter()
            .fold(
                || Some(Moments { sum: vec![0.0; pixels], squares: vec![0.0; pixels] }),
                |m, c| {
                    let mut m = m?;
                    if stop() {
                        return None;
                    }
                    splat_chunk(&splat_ctx, renderer.sensor(), c, &mut m);
                    Some(m)
                },
            )
            .reduce(
                || Some(Moments { sum: vec![0.0; pixels], squares: vec![0.0; pixels] }),
                |a, b| {
                    let (mut a, b) = (a?, b?);
                    for i in 0..pixels {
                        a.sum[i] += b.sum[i];
                        a.squares[i] += b.squares[i];
                    }
                    Some(a)
                },
            )?;
        // The subset's splats carry the whole cache's flux per path: scaled by all/some, their
        // sum estimates the whole film's, and so does the sum of their squares its variance.
        let f = if some == 0 { 0.0 } else { all as f64 / some as f64 };
        Some(PilotMeasure {
            path_seconds,
            splat_seconds: t0.elapsed().as_secs_f64() * f,
            width,
            height,
            camera,
            splat_sum: moments.sum.iter().map(|s| s * f).collect(),
            splat_squares: moments.squares.iter().map(|s| s * f).collect(),
        })
    }

    /// The allocation of `mean` camera paths per pixel on average (module docs).
    pub fn allocate(&self, mean: u32) -> Allocation {
        let model = self.model();
        let budget = mean as f64 * (self.width * self.height) as f64;
        let hi = (MAX_FACTOR * mean as f64).max(1.0);
        // spent(k) grows with k from (at least) the pixels to (at most) hi per pixel.
        let (mut k0, mut k1) = (0.0, 1.0);
        while model.spent(k1, hi) < budget && k1 < 1e30 {
            k1 *= 2.0;
        }
        for _ in 0..100 {
            let k = 0.5 * (k0 + k1);
            if model.spent(k, hi) < budget {
                k0 = k;
            } else {
                k1 = k;
            }
        }
        self.dithered(&model, k1, hi)
    }

    /// The allocation, of at most `max_mean` camera paths per pixel on average, that the model
    /// expects to give the most efficient frame (1/(relative error × time)), a camera path
    /// costing `path_cost` and the splats `splat_cost` (both in the same unit, e.g. seconds):
    /// where the splats are strong everywhere, few camera paths; where they are weak, more.
    pub fn allocate_for_efficiency(&self, max_mean: u32, path_cost: f64, splat_cost: f64) -> Allocation {
        let model = self.model();
        let pixels = (self.width * self.height) as f64;
        let hi = (MAX_FACTOR * max_mean as f64).max(1.0);
        let budget = max_mean as f64 * pixels;
        // k from the one that gives every tile its minimum to the one that spends the most.
        let (mut best, mut best_k) = (f64::INFINITY, 0.0);
        let mut k = 1e-6;
        while k < 1e30 {
            let spent = model.spent(k, hi);
            if spent > budget {
                break;
            }
            let cost = (splat_cost + path_cost * spent).max(f64::MIN_POSITIVE);
            let score = model.error(k, hi) * cost;
            if score < best {
                (best, best_k) = (score, k);
            }
            k *= 1.25;
        }
        self.dithered(&model, best_k, hi)
    }

    /// The per-tile quantities of the model (module docs).
    fn model(&self) -> Model {
        let (w, h) = (self.width, self.height);
        let (tw, th) = (w.div_ceil(TILE), h.div_ceil(TILE));
        let mut tiles = Vec::with_capacity(tw * th);
        for ty in 0..th {
            for tx in 0..tw {
                let (x0, y0) = (tx * TILE, ty * TILE);
                let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
                let n = ((x1 - x0) * (y1 - y0)) as f64;
                let (mut ic, mut il, mut vl, mut diff2, mut pairs) = (0.0, 0.0, 0.0, 0.0, 0.0);
                for y in y0..y1 {
                    for x in x0..x1 {
                        let p = y * w + x;
                        ic += self.camera[p];
                        il += self.splat_sum[p];
                        vl += self.splat_squares[p];
                        if x + 1 < x1 && (x - x0) % 2 == 0 {
                            diff2 += 0.5 * (self.camera[p] - self.camera[p + 1]).powi(2);
                            pairs += 1.0;
                        }
                    }
                }
                let (ic, il, vl) = (ic / n, il / n, vl / n);
                let var_c = if pairs > 0.0 { diff2 / pairs } else { ic * ic };
                // Light the splats miss, beyond two standard errors of the camera's mean.
                let missed = (ic - il - 2.0 * (var_c / n).sqrt()).max(0.0);
                tiles.push(Tile {
                    pixels: n,
                    value: ic.max(il),
                    var_camera: var_c,
                    var_splat: vl + missed * missed,
                });
            }
        }
        let image_mean = tiles.iter().map(|t| t.pixels * t.value).sum::<f64>() / (w * h).max(1) as f64;
        let eps = (0.1 * image_mean).powi(2).max(f64::MIN_POSITIVE);
        Model { tiles, eps, tiles_x: tw, lo: 1.0 }
    }

    /// Per pixel, the tile's count at `k`, its fraction dithered.
    fn dithered(&self, model: &Model, k: f64, hi: f64) -> Allocation {
        let w = self.width;
        let per_tile: Vec<f64> = model.tiles.iter().map(|t| model.count(t, k, hi)).collect();
        Allocation::PerPixel(
            (0..w * self.height)
                .map(|p| {
                    let (x, y) = (p % w, p / w);
                    let n = per_tile[(y / TILE) * model.tiles_x + x / TILE];
                    let frac = n - n.floor();
                    (n.floor() as u32).max(1) + (dither(p as u64) < frac) as u32
                })
                .collect(),
        )
    }
}

/// A tile of the model: its pixels, value I, a camera path's variance σ²_c and the splat film's
/// variance V_L (with the light it misses).
struct Tile {
    pixels: f64,
    value: f64,
    var_camera: f64,
    var_splat: f64,
}

/// The pilot's tiles and the regularisation ε of I².
struct Model {
    tiles: Vec<Tile>,
    eps: f64,
    tiles_x: usize,
    lo: f64,
}

impl Model {
    /// Camera paths per pixel of tile `t` at multiplier `k`, within [1, `hi`].
    fn count(&self, t: &Tile, k: f64, hi: f64) -> f64 {
        let want = k * t.var_camera.sqrt() / (t.value * t.value + self.eps).sqrt()
            - if t.var_splat > 0.0 { t.var_camera / t.var_splat } else { 0.0 };
        want.clamp(self.lo, hi)
    }

    /// Camera paths of one pass at `k`.
    fn spent(&self, k: f64, hi: f64) -> f64 {
        self.tiles.iter().map(|t| t.pixels * self.count(t, k, hi)).sum()
    }

    /// The expected relative variance summed over the pixels at `k` (the combination at the
    /// two halves' precisions).
    fn error(&self, k: f64, hi: f64) -> f64 {
        self.tiles
            .iter()
            .map(|t| {
                let i2 = t.value * t.value + self.eps;
                let a = if t.var_splat > 0.0 { i2 / t.var_splat } else { f64::INFINITY };
                let b = if t.var_camera > 0.0 { i2 / t.var_camera } else { f64::INFINITY };
                t.pixels / (a + self.count(t, k, hi) * b)
            })
            .sum()
    }
}

/// A fixed, well-spread number in [0, 1) per pixel (SplitMix64's finaliser).
fn dither(p: u64) -> f64 {
    let mut z = p.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 16×8 image of two tiles: `left` and `right` give (camera path values alternating
    /// ±spread around a mean, splat mean, splat squares) per pixel.
    fn measure(left: (f64, f64, f64, f64), right: (f64, f64, f64, f64)) -> PilotMeasure {
        let (w, h) = (16, 8);
        let mut m = PilotMeasure {
            width: w,
            height: h,
            camera: vec![0.0; w * h],
            splat_sum: vec![0.0; w * h],
            splat_squares: vec![0.0; w * h],
            path_seconds: 0.0,
            splat_seconds: 0.0,
        };
        for p in 0..w * h {
            let (mean, spread, il, vl) = if p % w < 8 { left } else { right };
            m.camera[p] = mean + if p % 2 == 0 { spread } else { -spread };
            m.splat_sum[p] = il;
            m.splat_squares[p] = vl;
        }
        m
    }

    fn tile_mean(a: &Allocation, left: bool) -> f64 {
        let v: Vec<u32> = (0..128).filter(|p| (p % 16 < 8) == left).map(|p| a.at(p)).collect();
        v.iter().map(|&n| n as f64).sum::<f64>() / v.len() as f64
    }

    /// The budget is kept (to the dithering's rounding), every pixel keeps a path, and the
    /// paths go where the splats are weak: a tile whose splats are exact gets the minimum.
    #[test]
    fn paths_go_where_the_splats_are_weak_and_the_budget_is_kept() {
        // Left: splats noiseless and right; right: splats noisy (variance 4 per pixel).
        let a = measure((1.0, 0.5, 1.0, 1e-12), (1.0, 0.5, 1.0, 4.0)).allocate(8);
        assert_eq!(tile_mean(&a, true), 1.0);
        let total = a.total(128) as f64;
        assert!((total - 8.0 * 128.0).abs() <= 0.05 * 8.0 * 128.0, "{total}");
        assert!(tile_mean(&a, false) > 14.0);
        assert!((0..128).all(|p| a.at(p) >= 1 && a.at(p) as f64 <= MAX_FACTOR * 8.0 + 1.0));
    }

    /// A tile whose splats miss the light camera paths see (a mirror: splats black and
    /// noiseless) is not mistaken for an exact one.
    #[test]
    fn light_the_splats_miss_counts_as_their_error() {
        let a = measure((1.0, 0.5, 0.0, 0.0), (1.0, 0.5, 1.0, 1e-12)).allocate(4);
        assert!(tile_mean(&a, true) > 6.0, "{}", tile_mean(&a, true));
        assert_eq!(tile_mean(&a, false), 1.0);
    }

    /// Equal tiles get equal shares: the allocation is uniform up to the dithering.
    #[test]
    fn equal_tiles_share_equally() {
        let a = measure((1.0, 0.5, 1.0, 0.1), (1.0, 0.5, 1.0, 0.1)).allocate(5);
        assert!((tile_mean(&a, true) - 5.0).abs() < 0.5 && (tile_mean(&a, false) - 5.0).abs() < 0.5);
    }
}
