//! The bidirectional renderer: the light vertex cache, the lights that are on, the render's
//! [`Counts`] and the two kinds of pass that make an image —
//!
//! * one **splat pass** ([`Renderer::splat_pass`]): every stored sample's MIS-weighted
//!   light-tracing splat (t = 1), and
//! * any number of **camera passes** ([`Renderer::camera_pass`]), each tracing `spp` camera
//!   paths per pixel with the camera strategies (emitter hits, NEE, cache connections).
//!
//! The image is the splat film plus the camera films' sum divided by the total spp
//! ([`combine`]). The counts are constants of the render, fixed when the renderer is made from
//! the total camera paths M the render is planned to take (`docs/bidirectional.md` §2, §10.2:
//! any constants keep the estimator unbiased; the planned ones make it the heuristic of the
//! actual sample numbers). A cache without records renders the camera strategies only
//! (emitter hits and NEE with their MIS, no connections, no splats: a path tracer); the command
//! line refuses such datasets for `--estimator bidirectional`, the core's tests use it for the
//! camera half alone.
//!
//! Interruption: `stop` is asked before every band and, inside a band, after every
//! [`STOP_WORK`] camera paths' worth of work (a path counted with its connections), so an
//! interrupt is seen after a bounded amount of work whatever `spp` and the image size are;
//! n_c itself is bounded by [`MAX_CONNECTIONS`].
//!
//! Determinism: a camera path draws from its own random stream, named by (seed, pass, pixel),
//! and adds only to its own pixel; rows of the image are rendered in parallel bands. The splat
//! pass cuts the chunks into a fixed number of runs and adds their films in run order. So an
//! image depends on the seed, never on the thread count.

use super::Counts;
use super::allocation::Allocation;
use super::cache::{CacheChunk, ConnectionSet, LightCache};
use super::lights::RenderLights;
use super::path::camera_path;
use super::splat::splat_chunk;
use super::vertex::Context;
use crate::dataset::{Directions, Heuristic};
use crate::film::{Accumulator, Film};
use crate::math::Rgb;
use crate::sampling::RandomStream;
use crate::scene::Scene;
use crate::sensor::{Sensor, VisibilityBuffer};
use rayon::prelude::*;

/// The options of a bidirectional render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// n_c: cache vertices each non-delta camera vertex connects to.
    pub connections: u32,
    /// Names the camera paths' random streams.
    pub seed: u64,
    /// The dataset's MIS heuristic (its records are powered for it).
    pub heuristic: Heuristic,
    /// The dataset's direction strategy (the light tracer's densities).
    pub directions: Directions,
}

/// First key word of every camera path's random stream (distinct from the tracer's streams).
const CAMERA_STREAM: u64 = 0x6361_6d65_7261; // "camera"

/// Image rows per parallel band of a camera pass.
const BAND_ROWS: usize = 2;

/// First key word of the random stream that fills a band's connection set.
const SET_STREAM: u64 = 0x7365_7473; // "sets"

/// Most vertices in a band's connection set (52 bytes each: 416 KiB, within a core's L2 beside
/// the scene's hot data; `docs/performance.md`).
const SET_MAX: usize = 1 << 13;

/// Work between two questions to `stop` inside a camera pass's band, in camera paths of one
/// vertex each making one connection (module docs): a few milliseconds of one core.
pub const STOP_WORK: u64 = 1 << 12;

/// Most cache vertices a camera vertex may connect to (n_c): more than the light-tracing splat
/// gains anything from at a vertex (each connection costs a shadow ray), and what keeps a single
/// camera path's work, the unit [`STOP_WORK`] is counted in, bounded.
pub const MAX_CONNECTIONS: u32 = 1 << 10;

/// Camera paths between two questions to `stop` inside a band, for n_c = `connections`.
fn stop_interval(connections: u32) -> u64 {
    (STOP_WORK / (1 + connections as u64)).max(1)
}

/// Runs the splat pass's chunks are cut into, whatever the thread count.
const SPLAT_RUNS: usize = 64;

/// Runs of the splat pass rendered at once (each with its own film), then added in order.
const SPLAT_GROUP: usize = 4;

/// A bidirectional render of one dataset through one sensor (module docs).
#[derive(Debug)]
pub struct Renderer<'a> {
    scene: &'a Scene,
    sensor: Sensor,
    cache: LightCache<'a>,
    lights: RenderLights,
    flux_per_path: Vec<Rgb>,
    counts: Counts,
    /// Per pixel c_LT(p) when the render's camera paths are allocated pixel by pixel
    /// ([`Allocation`]); `None`: `counts.light_trace` everywhere.
    pixel_light_trace: Option<Vec<f64>>,
    settings: Settings,
    /// The sensor's visibility buffer (the splats' shadow rays, the camera paths' first hits).
    visibility: Option<VisibilityBuffer>,
}

impl<'a> Renderer<'a> {
    /// A render of `chunks` (the dataset's, or a preview's subset) whose table has the light
    /// `names`, each light's samples standing for `flux_per_path[k]` = Φ'_k/N_k (relit, over
    /// these chunks' N_k), planned to take `camera_paths` camera paths in all (M = W·H·spp).
    pub fn new(
        scene: &'a Scene,
        sensor: Sensor,
        chunks: Vec<CacheChunk<'a>>,
        names: &[&str],
        flux_per_path: &[Rgb],
        settings: Settings,
        camera_paths: u64,
    ) -> Self {
        let visibility = sensor.visibility(scene);
        Self::with_visibility(scene, sensor, visibility, chunks, names, flux_per_path, settings, camera_paths)
    }

    /// [`Renderer::new`] with the sensor's visibility buffer already built
    /// (`sensor.visibility(scene)`, which a caller choosing the pixels that need camera paths
    /// has made anyway: building it again was a serial pass over every triangle).
    #[allow(clippy::too_many_arguments)]
    pub fn with_visibility(
        scene: &'a Scene,
        sensor: Sensor,
        visibility: Option<VisibilityBuffer>,
        chunks: Vec<CacheChunk<'a>>,
        names: &[&str],
        flux_per_path: &[Rgb],
        settings: Settings,
        camera_paths: u64,
    ) -> Self {
        let mut paths = vec![0u64; names.len()];
        for c in &chunks {
            if let Some(p) = paths.get_mut(c.light as usize) {
                *p += c.paths;
            }
        }
        let lights = RenderLights::new(scene, names, flux_per_path, &paths);
        let on: Vec<bool> = (0..names.len()).map(|k| lights.of_table(k).is_some()).collect();
        let cache = LightCache::new(chunks, names.len(), &on);
        let counts = if cache.has_records() {
            Counts::new(settings.connections, lights.total_paths(), cache.vertices(), camera_paths.max(1))
        } else {
            Counts { conn: 0.0, light_trace: 0.0 }
        };
        Renderer {
            scene,
            visibility,
            sensor,
            cache,
            lights,
            flux_per_path: flux_per_path.to_vec(),
            counts,
            pixel_light_trace: None,
            settings,
        }
    }

    /// [`Renderer::new`] for a render of `passes` camera passes of `allocation`'s camera paths
    /// per pixel: with a per-pixel allocation, each pixel's light-tracing count is its own
    /// (`allocation` module docs).
    #[allow(clippy::too_many_arguments)]
    pub fn allocated(
        scene: &'a Scene,
        sensor: Sensor,
        chunks: Vec<CacheChunk<'a>>,
        names: &[&str],
        flux_per_path: &[Rgb],
        settings: Settings,
        allocation: &Allocation,
        passes: u64,
    ) -> Self {
        let mut r = Renderer::new(scene, sensor, chunks, names, flux_per_path, settings, 1);
        r.plan(allocation, passes);
        r
    }

    /// Plans the render to take `passes` camera passes of `allocation`'s camera paths per pixel
    /// (before any pass: the counts are constants of the render, module docs).
    pub fn plan(&mut self, allocation: &Allocation, passes: u64) {
        let pixels = self.sensor.width() as usize * self.sensor.height() as usize;
        let planned = allocation.total(pixels) * passes.max(1);
        if self.cache.has_records() {
            self.counts = Counts::new(
                self.settings.connections,
                self.lights.total_paths(),
                self.cache.vertices(),
                planned.max(1),
            );
            self.pixel_light_trace = allocation.light_trace_counts(self.lights.total_paths(), pixels, passes);
        }
    }

    /// The render's counts (c_conn = n_c·N/|Y|, c_LT = N/M).
    pub fn counts(&self) -> Counts {
        self.counts
    }

    /// The light vertex cache.
    pub fn cache(&self) -> &LightCache<'a> {
        &self.cache
    }

    /// The lights that are on.
    pub fn lights(&self) -> &RenderLights {
        &self.lights
    }

    /// The context camera vertices gather with.
    pub fn context(&self) -> Context<'_> {
        Context {
            scene: self.scene,
            visibility: self.visibility.as_ref(),
            lights: &self.lights,
            cache: &self.cache,
            set: None,
            flux_per_path: &self.flux_per_path,
            counts: self.counts,
            pixel_light_trace: self.pixel_light_trace.as_deref(),
            heuristic: self.settings.heuristic,
            directions: self.settings.directions,
            connections: self.settings.connections,
        }
    }

    /// The MIS-weighted light-tracing splats of every sample (black without records);
    /// `progress(samples)` after each chunk; `None` if `stop()` said so between chunks.
    pub fn splat_pass(
        &self,
        progress: impl Fn(usize) + Sync,
        stop: impl Fn() -> bool + Sync,
    ) -> Option<Film> {
        let (w, h) = (self.sensor.width(), self.sensor.height());
        let mut total = Film::new(w, h);
        if !self.cache.has_records() || self.counts.light_trace == 0.0 {
            return Some(total);
        }
        let ctx = self.context();
        let chunks = self.cache.chunks();
        let run_len = chunks.len().div_ceil(SPLAT_RUNS).max(1);
        let runs: Vec<usize> = (0..chunks.len().div_ceil(run_len)).collect();
        // One accumulator per run of a group, reused group after group: a run's film is the
        // same as a fresh one's, without allocating, faulting in and freeing 64 films.
        let mut accs: Vec<Accumulator> =
            (0..SPLAT_GROUP.min(runs.len())).map(|_| Accumulator::new(w, h)).collect();
        for group in runs.chunks(SPLAT_GROUP) {
            let done = accs[..group.len()].par_iter_mut().zip(group).all(|(acc, &r)| {
                for c in &chunks[r * run_len..((r + 1) * run_len).min(chunks.len())] {
                    if stop() {
                        return false;
                    }
                    splat_chunk(&ctx, &self.sensor, ctx.visibility, c, acc);
                    progress(c.samples.len());
                }
                acc.film();
                true
            });
            if !done {
                return None;
            }
            for acc in &mut accs[..group.len()] {
                total.add(acc.film());
                acc.clear();
            }
        }
        Some(total)
    }

    /// Pass number `pass` of `spp` camera paths per pixel (the same everywhere, or per pixel:
    /// [`Allocation`]): per pixel the **sum** of their estimates; `progress(pixels)` after each
    /// band of rows; `None` if `stop()` said so (asked before each band and after every bounded
    /// amount of work within it: module docs).
    pub fn camera_pass(
        &self,
        pass: u64,
        spp: &Allocation,
        progress: impl Fn(usize) + Sync,
        stop: impl Fn() -> bool + Sync,
    ) -> Option<Film> {
        let (w, h) = (self.sensor.width(), self.sensor.height());
        let mut film = Film::new(w, h);
        let ctx = self.context();
        let band = w as usize * BAND_ROWS;
        // Each band connects through its own set of cache vertices, as many as its camera paths
        // make connections from their first vertex (each is then reused about once per further
        // vertex), at most SET_MAX; filled from the band's own stream, so the image does not
        // depend on the thread count.
        let connects = self.counts.conn > 0.0 && self.settings.connections > 0;
        let set_size =
            (band as u64 * spp.max() as u64 * self.settings.connections as u64).min(SET_MAX as u64) as usize;
        let init = || ConnectionSet::with_capacity(if connects { set_size } else { 0 });
        let every = stop_interval(self.settings.connections);
        let stopped = film.pixels.par_chunks_mut(band).enumerate().map_init(init, |set, (b, pixels)| {
            if stop() {
                return true;
            }
            let mut ctx = ctx;
            if connects {
                let mut rng = RandomStream::new(self.settings.seed, &[SET_STREAM, pass, b as u64]);
                self.cache.fill_set(set, set_size, &mut rng);
                ctx.set = Some(set);
            }
            let ctx = &ctx;
            let mut since_stop = 0u64;
            for (k, px) in pixels.iter_mut().enumerate() {
                let p = b * band + k;
                let (i, j) = ((p % w as usize) as u32, (p / w as usize) as u32);
                let mut rng = RandomStream::new(self.settings.seed, &[CAMERA_STREAM, pass, p as u64]);
                let mut sum = [0.0f64; 3];
                let ctx = &Context { counts: ctx.counts_at(p), ..*ctx };
                for _ in 0..spp.at(p) {
                    since_stop += 1;
                    if since_stop == every {
                        since_stop = 0;
                        if stop() {
                            return true;
                        }
                    }
                    let l = camera_path(ctx, &self.sensor, i, j, &mut rng);
                    for c in 0..3 {
                        sum[c] += l[c] as f64;
                    }
                }
                *px = sum;
            }
            progress(pixels.len());
            false
        });
        (!stopped.any(|s| s)).then_some(film)
    }
}

/// The image: the splat film plus the camera films' sum over `passes` passes of `spp` camera
/// paths per pixel.
pub fn combine(splat: &Film, camera_sum: &Film, spp: &Allocation, passes: u64) -> Film {
    let mut image = splat.clone();
    for (p, (a, b)) in image.pixels.iter_mut().zip(&camera_sum.pixels).enumerate() {
        let inv = 1.0 / (spp.at(p) as u64 * passes).max(1) as f64;
        for c in 0..3 {
            a[c] += b[c] * inv;
        }
    }
    image
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::cornell_box;
    use crate::sensor::Pinhole;
    use std::sync::atomic::{AtomicU64, Ordering};

    /// A stop asked for once a band has begun ends the pass within the band (after at most
    /// `stop_interval` camera paths), not after the band's 2^16 paths per pixel: `stop` is
    /// asked once before the band and once inside it, and the pass returns `None`.
    #[test]
    fn a_camera_pass_sees_a_stop_inside_a_band() {
        let mut desc = cornell_box();
        let camera = desc.camera.as_mut().unwrap();
        (camera.width, camera.height) = (2, BAND_ROWS as u32); // one band
        let scene = Scene::build(&desc).unwrap();
        let sensor = Sensor::from(Pinhole::new(scene.camera.as_ref().unwrap()).unwrap());
        let settings = Settings {
            connections: 1,
            seed: 0,
            heuristic: Heuristic::Power,
            directions: Directions::Importance,
        };
        let renderer = Renderer::new(&scene, sensor, Vec::new(), &[], &[], settings, 1);
        let asked = AtomicU64::new(0);
        let stop = || asked.fetch_add(1, Ordering::Relaxed) >= 1; // false before the band only
        assert!(renderer.camera_pass(0, &Allocation::Uniform(1 << 16), |_| {}, stop).is_none());
        assert_eq!(asked.load(Ordering::Relaxed), 2);
    }

    /// The work between two questions to `stop` is at most STOP_WORK paths' worth, up to the
    /// largest n_c, and never zero paths.
    #[test]
    fn the_stop_interval_bounds_the_work_between_questions() {
        for n_c in [0, 1, 7, 100, MAX_CONNECTIONS] {
            let every = stop_interval(n_c);
            assert!(every >= 1);
            assert!(every * (1 + n_c as u64) <= STOP_WORK.max(1 + n_c as u64), "{n_c}");
        }
    }
}
