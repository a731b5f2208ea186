//! Which of the pixels that could do without camera paths should still get them (issue 25,
//! design change 3, `--coverage auto`): a short pilot measures, per image tile, how noisy the
//! light tracer's splats are there and how much a camera path would remove, and the tiles where
//! camera paths buy the most error per unit of work get them.
//!
//! **Only efficiency is at stake.** The pixels that need camera paths for the image to be
//! unbiased (a mirror, glass, a glossy metal, the sky: [`super::cameras_needed`]) always get
//! them, decided from geometry; the pilot only chooses among the others, which the splats alone
//! render unbiased, whether camera paths would make them cheaper to the same error. Any choice
//! fixed before the render's passes keeps the estimator unbiased (`allocation` module docs), so
//! the pilot's noise costs efficiency, never correctness — and unlike the pilots measured before
//! (`docs/performance.md`), a rare bright camera path it fails to see (a caustic through glass)
//! can no longer leave a mirror or a glass pixel without camera paths.
//!
//! **What is measured.** The light half: a deterministic subset of each light's chunks (at least
//! [`LIGHT_SHARE`] of its paths) splatted as the light estimator splats them; per tile, over
//! its candidate pixels, the splats' luminance c summed, and c² scaled to the whole dataset —
//! the light estimator's variance of a pixel is about the sum of its splats' squares (the paths
//! are independent). The camera half: one camera path in one pixel of four (candidates and
//! fixed pixels alike), a path tracer's (NEE and emitter hits, no dataset: it needs no light
//! vertex cache, so a render that ends up without camera paths never reads one), its luminance
//! and its rays. A tile is [`TILE`]×[`TILE`] pixels.
//!
//! **The model.** Per tile, the light estimator's mean squared error per pixel a (its variance,
//! plus the square of what the camera path sees beyond the splats: light the pilot's subset
//! missed) and a camera path's variance b; with m camera paths per pixel the two combine to
//! about 1/(1/a + m/b) (inverse-variance weighting, which MIS matches or beats). Each pixel's
//! error is weighted 1/(μ² + 0.01), μ its tile's mean luminance — the relative MSE the project
//! measures efficiency with (`opticks_io::compare`: the mean of (t − r)²/(r² + 0.01)). The fixed pixels' error with their
//! camera paths counts too (at least a candidate's without them: their rare bright paths are
//! what the pilot's few paths miss). Work is counted in rays (a camera
//! path's, scaled from the pilot's n_c = 0 to the render's n_c; a splat [`SPLAT_WORK`], a
//! dataset sample read into the cache [`CACHE_WORK`]). The tiles are sorted by error removed per
//! work, and the prefix of that order that gives the least error × work gets `spp` camera paths
//! per pixel. Nothing reads a clock: the same seed gives the same choice on any machine.
//!
//! **Where no pixel needs camera paths** (a diffuse view), the render is the light estimator's
//! image unless the pilot finds tiles worth camera paths, so [`light_first`] renders that image
//! first and takes the light half from it: the spread of each pixel over the pass's runs
//! (independent sets of paths) estimates its variance from every sample, where [`choose`]
//! splats a subset a second time. Measured (callgrind, one thread, 1 M paths): the
//! bidirectional frame's cost over the light estimator's fell from 8.4 % to 6.2 % on the
//! Cornell box and from 9.1 % to 5.5 % on `bunny-box` (what is left is the camera half).

use super::cache::LightCache;
use super::lights::RenderLights;
use super::path::camera_path_rays;
use super::vertex::Context;
use super::{Counts, Settings};
use crate::film::{Film, SplatTarget, private_films};
use crate::math::{Rgb, luminance};
use crate::sampling::RandomStream;
use crate::scene::Scene;
use crate::sensor::meter::Group;
use crate::sensor::runs::{RunFold, run_count, splat_runs};
use crate::sensor::{AsBatch, Sensor, SensorSplat, VisibilityBuffer, render, splat};
use rayon::prelude::*;

/// Tile side in pixels: a tile shares one decision.
pub const TILE: u32 = 8;

/// Least share of each light's paths the pilot splats.
pub const LIGHT_SHARE: f64 = 1.0 / 16.0;

/// Work of one sample's MIS-weighted splat, in rays of a camera path (its projection, BSDF, MIS
/// weight and shadow ray against a path's closest hits, shadow rays and shading). Measured on
/// the Cornell box (1 M paths, one thread's CPU time, 2026-12-07, after the splat loop became a
/// batch kernel): a camera path ~1.5 µs for ~7.5 rays, ~0.2 µs a ray; a plain splat ~0.05 µs;
/// the cache and the weighted splat pass ~0.08 µs a sample (it was 0.55, 0.5 and 0.15 before
/// the kernel, which made camera paths look cheap beside the splats).
pub const SPLAT_WORK: f64 = 0.3;

/// Work of one sample of the plain splat pass the render is without camera paths, in rays.
pub const PLAIN_SPLAT_WORK: f64 = 0.25;

/// Work of reading one sample and its record into the light vertex cache, in rays (the render
/// pays it once any pixel gets camera paths).
pub const CACHE_WORK: f64 = 0.1;

/// First key word of the pilot's camera streams (distinct from the render's).
const PILOT_STREAM: u64 = 0x0070_696c_6f74; // "pilot"

/// One tile's sums over its candidate pixels (or its fixed ones).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct TileSums {
    /// The pixels.
    pixels: f64,
    /// Σ over splats of the light estimator's c, and of c² (scaled to the whole dataset).
    light: f64,
    light_sq: f64,
    /// The pilot's camera paths among them ([`piloted`] pixels), and Σ of their L, L² and rays.
    paths: f64,
    camera: f64,
    camera_sq: f64,
    rays: f64,
}

/// Whether pixel (i, j) gets a pilot camera path: one pixel in four, spread evenly (each row
/// every fourth pixel, shifted by two from row to row).
#[inline]
fn piloted(i: u32, j: u32) -> bool {
    (i + 2 * j).is_multiple_of(4)
}

/// A splat target summing luminance and its square per tile, over candidate pixels only.
struct TileMoments<'a> {
    width: u32,
    tiles_x: u32,
    candidate: &'a [bool],
    sums: &'a mut [TileSums],
    /// The batch's share of its light's paths (the splats come scaled by 1/share; their squares
    /// are scaled by share again, to the whole dataset's sum of squares).
    share: f64,
}

impl SplatTarget for TileMoments<'_> {
    #[inline]
    fn splat(&mut self, index: usize, v: Rgb) {
        if !self.candidate[index] {
            return;
        }
        let (x, y) = ((index % self.width as usize) as u32, (index / self.width as usize) as u32);
        let t = &mut self.sums[((y / TILE) * self.tiles_x + x / TILE) as usize];
        let c = luminance(v) as f64;
        t.light += c;
        t.light_sq += c * c * self.share;
    }
}

/// What the render is planned to be, for the pilot's work model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plan {
    /// Camera paths per pixel of the pixels that get them.
    pub spp: u32,
    /// n_c of the render.
    pub connections: u32,
    /// Samples in the dataset (every one is splatted).
    pub samples: u64,
}

/// The pixels of `sensor`'s image that get camera paths (module docs): those `needed` marks,
/// and the tiles of the others where the pilot finds them worth their work (`visibility`: the
/// sensor's buffer, which `needed` came from). The pilot reads the
/// chunks `groups` lists (light and paths of each) through `batch`, a subset of each light's; the
/// camera paths use the lights `names`, each standing for `flux_per_path[k]` per path of its
/// `paths[k]`. `None` if `stop()` said so.
#[allow(clippy::too_many_arguments)]
pub fn choose<B: AsBatch, E: Send>(
    scene: &Scene,
    sensor: &Sensor,
    visibility: Option<&VisibilityBuffer>,
    needed: &[bool],
    groups: &[Group],
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    names: &[&str],
    flux_per_path: &[Rgb],
    settings: Settings,
    plan: Plan,
    stop: impl Fn() -> bool + Sync,
) -> Result<Option<Vec<bool>>, E> {
    let (width, height) = (sensor.width(), sensor.height());
    let tiles_x = width.div_ceil(TILE);
    let tile_count = tiles_x as usize * height.div_ceil(TILE) as usize;
    let candidate: Vec<bool> = needed.iter().map(|&n| !n).collect();
    let paths = Group::paths_per_light(groups, names.len());
    let lights = RenderLights::new(scene, names, flux_per_path, &paths);
    // The light half: per light, its first chunks up to LIGHT_SHARE of its paths.
    let mut taken = vec![0u64; names.len()];
    let subset: Vec<usize> = (0..groups.len())
        .filter(|&i| {
            let k = groups[i].light as usize;
            let take = lights.of_table(k).is_some() && (taken[k] as f64) < LIGHT_SHARE * paths[k] as f64;
            if take {
                taken[k] += groups[i].paths;
            }
            take
        })
        .collect();
    let runs = subset
        .par_chunks(subset.len().div_ceil(16).max(1))
        .map(|run| {
            let mut sums = vec![TileSums::default(); tile_count];
            for &i in run {
                if stop() {
                    return Ok(None);
                }
                let k = groups[i].light as usize;
                let share = taken[k] as f64 / paths[k].max(1) as f64;
                let owned = batch(i)?;
                let mut b = owned.as_batch();
                b.flux_per_path *= (1.0 / share) as f32;
                let mut target =
                    TileMoments { width, tiles_x, candidate: &candidate, sums: &mut sums, share };
                splat(scene, sensor, visibility, b, &mut target);
            }
            Ok(Some(sums))
        })
        .collect::<Result<Option<Vec<_>>, E>>()?;
    let Some(runs) = runs else { return Ok(None) };
    let mut tiles = vec![TileSums::default(); tile_count];
    for run in runs {
        for (t, r) in tiles.iter_mut().zip(run) {
            t.light += r.light;
            t.light_sq += r.light_sq;
        }
    }
    let half = CameraHalf { lights: &lights, flux_per_path, settings, plan };
    Ok(half.choose(scene, sensor, visibility, needed, &candidate, tiles, &stop))
}

/// What [`light_first`] found.
#[derive(Debug)]
pub enum LightFirst {
    /// No tile pays for camera paths: the light estimator's image, bit for bit what
    /// [`crate::sensor::render`] makes of the same batches.
    Image(Film),
    /// The pixels that get camera paths (some do).
    Cameras(Vec<bool>),
}

/// Fewest runs of the light estimator's pass ([`crate::sensor::run_count`]) from whose spread
/// [`light_first`] estimates a pixel's variance (fewer: [`choose`]'s subset instead).
pub const LIGHT_FIRST_RUNS: usize = 8;

/// [`choose`] for a view in which no pixel needs camera paths (`cameras_needed` all false),
/// starting with the light estimator's image. Its pass over **every** batch (`batch(i)` for each
/// of `groups`, `progress` after each) is summed run by run in run order, as
/// [`crate::sensor::render`] sums it; the runs are independent estimates (disjoint sets of
/// paths), so the spread of a pixel's luminance over them estimates its variance — the pilot's
/// light half, from every sample, at the cost of a luminance per pixel and run, where
/// [`choose`] reads a subset ([`LIGHT_SHARE`]) again and splats it a second time. When the
/// pilot then gives no tile camera paths, that image is the render (its light half cost
/// nothing); when it does, the image is discarded for the bidirectional render. With fewer
/// than [`LIGHT_FIRST_RUNS`] runs, or films too large for private run films
/// ([`crate::film::private_films`]), [`choose`]'s subset is used. `None` if `stop()` said so.
#[allow(clippy::too_many_arguments)]
pub fn light_first<B: AsBatch, E: Send>(
    scene: &Scene,
    sensor: &Sensor,
    visibility: Option<&VisibilityBuffer>,
    groups: &[Group],
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
    names: &[&str],
    flux_per_path: &[Rgb],
    settings: Settings,
    plan: Plan,
    stop: impl Fn() -> bool + Sync,
) -> Result<Option<LightFirst>, E> {
    let (width, height) = (sensor.width(), sensor.height());
    let none = vec![false; width as usize * height as usize];
    let runs = run_count(groups.len(), width, height);
    if runs < LIGHT_FIRST_RUNS || !private_films(width, height) {
        let chosen = choose(
            scene,
            sensor,
            visibility,
            &none,
            groups,
            &batch,
            names,
            flux_per_path,
            settings,
            plan,
            &stop,
        )?;
        let Some(c) = chosen else { return Ok(None) };
        if c.contains(&true) {
            return Ok(Some(LightFirst::Cameras(c)));
        }
        return render(scene, sensor, groups.len(), batch, progress).map(|f| Some(LightFirst::Image(f)));
    }
    // Per pixel, Σ over runs of the run film's luminance and of its square.
    let mut moments = vec![[0.0f64; 2]; none.len()];
    let mut fold = RunFold::new(width, height);
    let splatter = SensorSplat::with_buffer(scene, sensor, visibility.cloned());
    let all_runs: Vec<usize> = (0..runs).collect();
    splat_runs((width, height), groups.len(), &all_runs, batch, progress, &splatter, |r, film| {
        for (m, p) in moments.iter_mut().zip(&film.pixels) {
            let c = luminance(Rgb::new(p[0] as f32, p[1] as f32, p[2] as f32)) as f64;
            m[0] += c;
            m[1] += c * c;
        }
        fold.add(r, &film);
        Ok(())
    })?;
    if stop() {
        return Ok(None);
    }
    let tiles = tiles_from_runs(&moments, runs, width, height);
    let paths = Group::paths_per_light(groups, names.len());
    let lights = RenderLights::new(scene, names, flux_per_path, &paths);
    let half = CameraHalf { lights: &lights, flux_per_path, settings, plan };
    let all = vec![true; none.len()];
    Ok(half.choose(scene, sensor, visibility, &none, &all, tiles, &stop).map(|c| match c.contains(&true) {
        true => LightFirst::Cameras(c),
        false => LightFirst::Image(fold.into_film()),
    }))
}

/// The light half of [`light_first`]'s tiles from `moments` (per pixel of a `width`-wide image,
/// Σ over `runs` run films of the pixel's luminance and of its square): a tile's Σ luminance,
/// and Σ over its pixels of the variance of their sum over the runs, R·s² (s² the runs' sample
/// variance) — what [`choose`] sums from the splats as Σ c².
fn tiles_from_runs(moments: &[[f64; 2]], runs: usize, width: u32, height: u32) -> Vec<TileSums> {
    let tiles_x = width.div_ceil(TILE);
    let mut tiles = vec![TileSums::default(); tiles_x as usize * height.div_ceil(TILE) as usize];
    let r = runs as f64;
    for (p, &[s1, s2]) in moments.iter().enumerate() {
        let (x, y) = (p as u32 % width, p as u32 / width);
        let t = &mut tiles[((y / TILE) * tiles_x + x / TILE) as usize];
        t.light += s1;
        t.light_sq += (r / (r - 1.0) * (s2 - s1 * s1 / r)).max(0.0);
    }
    tiles
}

/// The pilot's camera half and the choice: what [`choose`] and [`light_first`] share.
struct CameraHalf<'a> {
    lights: &'a RenderLights,
    flux_per_path: &'a [Rgb],
    settings: Settings,
    plan: Plan,
}

impl CameraHalf<'_> {
    /// Per pixel whether it gets camera paths: the `needed` ones, and the candidates' tiles the
    /// model chooses given their light-half sums `tiles` (a path tracer's path in each
    /// [`piloted`] pixel, rows in parallel). `None` if `stop()` said so.
    #[allow(clippy::too_many_arguments)]
    fn choose(
        &self,
        scene: &Scene,
        sensor: &Sensor,
        visibility: Option<&VisibilityBuffer>,
        needed: &[bool],
        candidate: &[bool],
        mut tiles: Vec<TileSums>,
        stop: &(impl Fn() -> bool + Sync),
    ) -> Option<Vec<bool>> {
        let (width, height) = (sensor.width(), sensor.height());
        let tiles_x = width.div_ceil(TILE);
        let tile_count = tiles.len();
        let (lights, flux_per_path, settings, plan) =
            (self.lights, self.flux_per_path, self.settings, self.plan);
        // The camera half: a path tracer's path per candidate pixel, rows in parallel.
        let cache = LightCache::new(Vec::new(), flux_per_path.len(), &vec![true; flux_per_path.len()]);
        let ctx = Context {
            scene,
            visibility,
            lights,
            cache: &cache,
            set: None,
            flux_per_path,
            counts: Counts { conn: 0.0, light_trace: 0.0 },
            pixel_light_trace: None,
            heuristic: settings.heuristic,
            directions: settings.directions,
            connections: 0,
        };
        let rows: Option<Vec<Vec<(f64, u32)>>> = (0..height)
            .into_par_iter()
            .map(|j| {
                if stop() {
                    return None;
                }
                let row = (0..width)
                    .map(|i| {
                        let p = j as u64 * width as u64 + i as u64;
                        if !piloted(i, j) {
                            return (0.0, 0);
                        }
                        let mut rng = RandomStream::new(settings.seed, &[PILOT_STREAM, p]);
                        let (l, rays) = camera_path_rays(&ctx, sensor, i, j, &mut rng);
                        (luminance(l) as f64, rays)
                    })
                    .collect();
                Some(row)
            })
            .collect();
        let rows = rows?;
        // Per tile, the candidates' camera moments, and the fixed pixels' (their error with `spp`
        // camera paths is part of the image's, against which the choice is weighed).
        let mut fixed = vec![TileSums::default(); tile_count];
        for (p, &c) in candidate.iter().enumerate() {
            let (x, y) = ((p % width as usize) as u32, (p / width as usize) as u32);
            let tile = ((y / TILE) * tiles_x + x / TILE) as usize;
            if c { &mut tiles[tile] } else { &mut fixed[tile] }.pixels += 1.0;
        }
        for (j, row) in rows.into_iter().enumerate() {
            for (i, (l, rays)) in row.into_iter().enumerate() {
                if !piloted(i as u32, j as u32) {
                    continue;
                }
                let tile = (j as u32 / TILE * tiles_x + i as u32 / TILE) as usize;
                let t = if candidate[j * width as usize + i] { &mut tiles[tile] } else { &mut fixed[tile] };
                t.paths += 1.0;
                t.camera += l;
                t.camera_sq += l * l;
                t.rays += rays as f64;
            }
        }
        let chosen = decide(&tiles, &fixed, plan);
        let mut cameras = needed.to_vec();
        for (p, c) in cameras.iter_mut().enumerate() {
            let (x, y) = ((p % width as usize) as u32, (p / width as usize) as u32);
            *c |= chosen[((y / TILE) * tiles_x + x / TILE) as usize];
        }
        Some(cameras)
    }
}

/// One tile as the model sees it: its candidate pixels' weighted error per pixel without camera
/// paths (`alone`) and with `spp` (`with`), and the work of giving them camera paths.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Choice {
    alone: f64,
    with: f64,
    work: f64,
}

/// Rays per camera path at the pilot's n_c = 0 scaled to the render's n_c: a path of k segments
/// asks k closest hits and k NEE rays at n_c = 0 (2k), and k more per connection.
fn rays_at(pilot_rays: f64, connections: u32) -> f64 {
    pilot_rays * (2.0 + connections as f64) / 2.0
}

/// A tile's mean luminance and its pixels' error weight 1/(μ² + 0.01) (module docs); its
/// camera paths' variance b, and rays per path at the render's n_c.
fn camera_side(t: &TileSums, connections: u32) -> (f64, f64, f64, f64) {
    let n = t.paths.max(1.0);
    let cam_mean = t.camera / n;
    let b = (t.camera_sq / n - cam_mean * cam_mean).max(0.0) * n / (n - 1.0).max(1.0);
    let mu = (t.light / t.pixels.max(1.0)).max(cam_mean);
    (cam_mean, b, 1.0 / (mu * mu + 0.01), rays_at(t.rays / n, connections))
}

/// Per tile, whether its candidate pixels get camera paths (module docs): the prefix of the
/// tiles sorted by error removed per work that gives the least error × work, with the `fixed`
/// pixels' camera paths (their error and work) and the splat pass included.
fn decide(tiles: &[TileSums], fixed: &[TileSums], plan: Plan) -> Vec<bool> {
    let spp = plan.spp.max(1) as f64;
    let choices: Vec<Choice> = tiles
        .iter()
        .map(|t| {
            let p = t.pixels.max(1.0);
            let light_mean = t.light / p;
            let (cam_mean, b, w, rays) = camera_side(t, plan.connections);
            let missed = (cam_mean - light_mean).max(0.0);
            let a = t.light_sq / p + (missed * missed - b / t.paths.max(1.0)).max(0.0);
            let with = if a > 0.0 && b > 0.0 { 1.0 / (1.0 / a + spp / b) } else { a.min(b / spp) };
            Choice {
                alone: t.pixels * w * a,
                with: t.pixels * w * with,
                work: t.pixels * spp * rays.max(1.0),
            }
        })
        .collect();
    // The fixed pixels: their camera paths' error and work, whatever is chosen.
    let (mut fixed_error, mut fixed_work) = (0.0, 0.0);
    for t in fixed.iter().filter(|t| t.pixels > 0.0) {
        let (_, b, w, rays) = camera_side(t, plan.connections);
        fixed_error += t.pixels * w * b / spp;
        fixed_work += t.pixels * spp * rays.max(1.0);
    }
    // A fixed pixel's camera paths see what the pilot's few paths cannot (rare, bright paths
    // through glass): count its error at least as a candidate's without camera paths.
    let (alone, pixels) =
        choices.iter().zip(tiles).fold((0.0, 0.0), |(e, n), (c, t)| (e + c.alone, n + t.pixels));
    let fixed_pixels: f64 = fixed.iter().map(|t| t.pixels).sum();
    if pixels > 0.0 {
        fixed_error = fixed_error.max(fixed_pixels * alone / pixels);
    }
    let samples = plan.samples as f64;
    let bidirectional = samples * (SPLAT_WORK + CACHE_WORK) + fixed_work;
    let mut order: Vec<usize> = (0..choices.len()).filter(|&i| choices[i].alone > choices[i].with).collect();
    let gain = |i: usize| (choices[i].alone - choices[i].with) / choices[i].work.max(1e-30);
    order.sort_by(|&a, &b| gain(b).total_cmp(&gain(a)).then(a.cmp(&b)));
    let mut error: f64 = fixed_error + choices.iter().map(|c| c.alone).sum::<f64>();
    let mut work = if fixed_work > 0.0 { bidirectional } else { samples * PLAIN_SPLAT_WORK };
    let (mut best, mut best_k) = (error * work, 0);
    work = work.max(bidirectional);
    for (k, &i) in order.iter().enumerate() {
        error -= choices[i].alone - choices[i].with;
        work += choices[i].work;
        if error * work < best {
            (best, best_k) = (error * work, k + 1);
        }
    }
    let mut chosen = vec![false; tiles.len()];
    for &i in &order[..best_k] {
        chosen[i] = true;
    }
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tile of 64 candidate pixels whose splats have variance `light_var` per pixel around
    /// `mean`, whose camera paths have variance `camera_var` around it, with `rays` rays each.
    fn tile(light_var: f64, camera_var: f64, mean: f64, rays: f64) -> TileSums {
        let p = 64.0;
        TileSums {
            pixels: p,
            light: mean * p,
            light_sq: light_var * p,
            paths: p,
            camera: mean * p,
            camera_sq: (camera_var + mean * mean) * p,
            rays: rays * p,
        }
    }

    fn plan(samples: u64) -> Plan {
        Plan { spp: 16, connections: 1, samples }
    }

    /// Where the splats are good and camera paths noisy, no tile gets camera paths (the light
    /// estimator's image); where the splats are far noisier than 16 camera paths, every tile
    /// does; of a mix, the noisy tiles first.
    #[test]
    fn camera_paths_go_where_the_splats_are_weak() {
        let quiet = tile(1e-4, 1.0, 1.0, 4.0);
        let noisy = tile(1.0, 0.1, 1.0, 4.0);
        assert_eq!(decide(&[quiet; 4], &[], plan(100_000)), vec![false; 4]);
        assert_eq!(decide(&[noisy; 4], &[], plan(100_000)), vec![true; 4]);
        assert_eq!(decide(&[quiet, noisy, quiet, noisy], &[], plan(100_000)), vec![false, true, false, true]);
    }

    /// Light the pilot's splats missed but its camera paths saw counts as the splats' error.
    #[test]
    fn light_the_splats_missed_buys_camera_paths() {
        let mut blind = tile(0.0, 0.01, 1.0, 4.0);
        blind.light = 0.0;
        assert_eq!(decide(&[blind], &[], plan(1_000)), vec![true]);
    }

    /// The runs' spread is each pixel's variance: a pixel whose run films read 1, 2, 3 and 4 sums
    /// to 10 with variance 4 · 5/3 (four runs, sample variance 5/3); runs that agree, none.
    #[test]
    fn the_runs_spread_is_each_pixels_variance() {
        let runs = [1.0, 2.0, 3.0, 4.0];
        let spread = [runs.iter().sum::<f64>(), runs.iter().map(|x| x * x).sum()];
        // A 16×8 image: two tiles; the spread pixel in the second, the rest agreeing runs of 0.5.
        let mut moments = vec![[2.0, 1.0]; 16 * 8];
        moments[8 + 3 * 16] = spread;
        let tiles = tiles_from_runs(&moments, 4, 16, 8);
        assert_eq!(tiles.len(), 2);
        assert_eq!((tiles[0].light, tiles[0].light_sq), (2.0 * 64.0, 0.0));
        assert_eq!(tiles[1].light, 2.0 * 63.0 + 10.0);
        assert!((tiles[1].light_sq - 4.0 * 5.0 / 3.0).abs() < 1e-12, "{}", tiles[1].light_sq);
    }

    /// On the diffuse Cornell box (no pixel needs camera paths) the pilot started from the light
    /// estimator's image gives no tile camera paths, and that image is the light estimator's, bit
    /// for bit; the pilot's choice is the same with the subset-based light half.
    #[test]
    fn the_light_first_pilot_keeps_the_light_image_of_a_diffuse_box() {
        use crate::dataset::testing::trace_into;
        use crate::dataset::{Directions, Heuristic};
        use crate::scene::cornell_box;
        use crate::sensor::{Pinhole, SampleBatch};
        let scene = Scene::build(&cornell_box()).unwrap();
        let mut cam = scene.camera.unwrap();
        (cam.width, cam.height) = (64, 64);
        let sensor = Sensor::from(Pinhole::new(&cam).unwrap());
        let buffer = sensor.visibility(&scene).unwrap();
        let traced = trace_into(&scene, 40 * 4096, 3);
        let chunks = &traced.chunks;
        let table = &traced.header.table;
        assert!(run_count(chunks.len(), 64, 64) >= LIGHT_FIRST_RUNS);
        let groups: Vec<Group> = chunks.iter().map(|c| Group { light: c.light, paths: c.paths }).collect();
        let names: Vec<&str> = table.lights.iter().map(|l| l.name.as_str()).collect();
        let flux: Vec<Rgb> = (0..names.len()).map(|k| table.flux_per_path(k)).collect();
        let batch = |i: usize| {
            Ok::<_, ()>(SampleBatch {
                flux_per_path: flux[chunks[i].light as usize],
                samples: &chunks[i].samples,
            })
        };
        let settings = Settings {
            connections: 1,
            seed: 5,
            heuristic: Heuristic::Power,
            directions: Directions::Importance,
        };
        let samples = chunks.iter().map(|c| c.samples.len() as u64).sum();
        let plan = Plan { spp: 16, connections: 1, samples };
        let first = light_first(
            &scene,
            &sensor,
            Some(&buffer),
            &groups,
            batch,
            |_| (),
            &names,
            &flux,
            settings,
            plan,
            || false,
        );
        let Ok(Some(LightFirst::Image(film))) = first else { panic!("camera paths chosen: {first:?}") };
        let light = render(&scene, &sensor, chunks.len(), batch, |_| ()).unwrap();
        assert!(film.pixels == light.pixels, "the light estimator's image, bit for bit");
        let none = vec![false; 64 * 64];
        let subset = choose(
            &scene,
            &sensor,
            Some(&buffer),
            &none,
            &groups,
            batch,
            &names,
            &flux,
            settings,
            plan,
            || false,
        );
        assert_eq!(subset, Ok(Some(none)), "the subset's light half chooses the same");
    }

    /// A costlier splat pass makes camera paths relatively cheaper: more tiles take them.
    #[test]
    fn a_costlier_splat_pass_buys_more_camera_paths() {
        let tiles: Vec<TileSums> = (0..8).map(|k| tile(0.01 * (1 << k) as f64, 1.0, 1.0, 4.0)).collect();
        let count = |samples| decide(&tiles, &[], plan(samples)).iter().filter(|&&c| c).count();
        assert!(count(100_000_000) > count(1_000), "{} vs {}", count(100_000_000), count(1_000));
    }
}
