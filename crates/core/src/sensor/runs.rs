//! How a render is cut into work and summed, fixed by the film and the dataset alone: the
//! batches (chunks) are taken in *runs* of [`batches_per_run`] consecutive batches, each run is
//! splatted into its own film through an f32-staged [`Accumulator`], and the run films are added
//! in run order ([`RunFold`]). No step depends on the thread count or on which process rendered
//! which run, so an image is the same bit for bit on 1 or 64 threads, and in one process or
//! split over the ranks of a cluster job (the CLI's `cluster` module sends each run's film to
//! the master, which adds them in the same order).
//!
//! Memory: a *wave* of runs is rendered at once, at most one per thread and never more than
//! `crate::film::PRIVATE_FILMS_BUDGET` allows beside the fold's film
//! ([`crate::film::wave_width`]); only the wave's width, never the result, depends on the
//! threads and the budget. Films too large for even two run films and the fold within the
//! budget ([`crate::film::private_films`] is false) are accumulated into one shared atomic film
//! instead (`super::accumulate`), equal to the run-order sum within float rounding but not bit
//! for bit.

use super::{AsBatch, Scene, Sensor, SensorSplat, Splatter, VisibilityBuffer, accumulate};
use crate::film::{Accumulator, Film, wave_width};
use rayon::prelude::*;

/// Batches per run for a `width`×`height` film: about one batch per 4096 pixels, between 4
/// and 64. A run's film costs a clear and an addition of every pixel, so a run should carry
/// more samples than the film has pixels (a batch is ~20 000 samples); more runs than threads
/// keep the threads busy.
pub fn batches_per_run(width: u32, height: u32) -> usize {
    (width as usize * height as usize / 4096).clamp(4, 64)
}

/// Runs of `count` batches for a `width`×`height` film.
pub fn run_count(count: usize, width: u32, height: u32) -> usize {
    count.div_ceil(batches_per_run(width, height))
}

/// The film of run `run`: its batches in order, each handed to `splatter` with one accumulator.
fn render_run<B: AsBatch, E>(
    (width, height): (u32, u32),
    count: usize,
    run: usize,
    batch: &(impl Fn(usize) -> Result<B, E> + Sync),
    progress: &(impl Fn(usize) + Sync),
    splatter: &impl Splatter,
) -> Result<Film, E> {
    let len = batches_per_run(width, height);
    let mut acc = Accumulator::new(width, height);
    for i in (run * len)..((run + 1) * len).min(count) {
        let b = batch(i)?;
        let b = b.as_batch();
        splatter.splat_batch(b, &mut acc);
        progress(b.samples.len());
    }
    Ok(acc.into_film())
}

/// Renders the runs `runs` (in increasing order) on all cores, a wave ([`wave_width`]) at a
/// time, and hands each run's film to `done` in that order.
pub(crate) fn splat_runs<B: AsBatch, E: Send>(
    size: (u32, u32),
    count: usize,
    runs: &[usize],
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
    splatter: &impl Splatter,
    mut done: impl FnMut(usize, Film) -> Result<(), E>,
) -> Result<(), E> {
    let wave = wave_width(size.0, size.1, rayon::current_num_threads());
    for wave in runs.chunks(wave) {
        let films: Vec<Film> = wave
            .par_iter()
            .map(|&r| render_run(size, count, r, &batch, &progress, splatter))
            .collect::<Result<_, E>>()?;
        for (&r, film) in wave.iter().zip(films) {
            done(r, film)?;
        }
    }
    Ok(())
}

/// Renders `count` batches (fetched by index, from memory or read from a file) through
/// `sensor` on all cores, in memory bounded by [`crate::film::accumulation_bytes`].
pub fn render<B: AsBatch, E: Send>(
    scene: &Scene,
    sensor: &Sensor,
    count: usize,
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
) -> Result<Film, E> {
    render_with_buffer(scene, sensor, sensor.visibility(scene), count, batch, progress)
}

/// [`render`] with `sensor`'s visibility buffer already built ([`Sensor::visibility`]): for a
/// caller that made it anyway (the bidirectional estimator, choosing which pixels need camera
/// paths), so that it is not built twice.
pub fn render_with_buffer<B: AsBatch, E: Send>(
    scene: &Scene,
    sensor: &Sensor,
    visibility: Option<VisibilityBuffer>,
    count: usize,
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
) -> Result<Film, E> {
    let splat = SensorSplat::with_buffer(scene, sensor, visibility);
    accumulate((sensor.width(), sensor.height()), count, batch, progress, &splat)
}

/// The runs `runs` of `count` batches seen through `sensor`, each run's film handed to `done`
/// in the order of `runs`: what a cluster worker renders of its share (the master adds the
/// films with a [`RunFold`]). Meant for films with [`crate::film::private_films`].
pub fn render_runs<B: AsBatch, E: Send>(
    scene: &Scene,
    sensor: &Sensor,
    count: usize,
    runs: &[usize],
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
    done: impl FnMut(usize, Film) -> Result<(), E>,
) -> Result<(), E> {
    let size = (sensor.width(), sensor.height());
    splat_runs(size, count, runs, batch, progress, &SensorSplat::new(scene, sensor), done)
}

/// The sum of run films, added strictly in run order (f64 addition is not associative, so the
/// order is what makes the image independent of who rendered which run).
#[derive(Debug)]
pub struct RunFold {
    film: Film,
    next: usize,
}

impl RunFold {
    /// A black `width`×`height` film, expecting run 0 first.
    pub fn new(width: u32, height: u32) -> Self {
        RunFold { film: Film::new(width, height), next: 0 }
    }

    /// Adds run `run`'s film; runs must come in order.
    pub fn add(&mut self, run: usize, film: &Film) {
        assert_eq!(run, self.next, "run films are added in run order");
        self.film.add(film);
        self.next += 1;
    }

    /// The image.
    pub fn into_film(self) -> Film {
        self.film
    }
}

/// Every run of `count` batches, summed in order: how `super::accumulate` renders a film with
/// [`crate::film::private_films`].
pub(crate) fn accumulate_runs<B: AsBatch, E: Send>(
    (width, height): (u32, u32),
    count: usize,
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
    splatter: &impl Splatter,
) -> Result<Film, E> {
    let runs: Vec<usize> = (0..run_count(count, width, height)).collect();
    let mut fold = RunFold::new(width, height);
    splat_runs((width, height), count, &runs, batch, progress, splatter, |r, film| {
        fold.add(r, &film);
        Ok(())
    })?;
    Ok(fold.into_film())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::Sample;
    use crate::film::SplatTarget;
    use crate::math::{Rgb, Vec3};
    use crate::sensor::SampleBatch;

    /// A stand-in splat: each sample adds β to pixel (prim mod pixels), values whose sums round
    /// differently in different orders.
    struct ByPrim;

    impl Splatter for ByPrim {
        fn splat_batch<T: SplatTarget>(&self, batch: SampleBatch<'_>, film: &mut T) {
            for s in batch.samples {
                film.splat(s.prim as usize % 64, s.beta());
            }
        }
    }

    fn batch<'a>(batches: &'a [Vec<Sample>]) -> impl Fn(usize) -> Result<SampleBatch<'a>, ()> + Sync + 'a {
        move |i| Ok(SampleBatch { flux_per_path: Rgb::ONE, samples: &batches[i] })
    }

    fn render_on(threads: usize, batches: &[Vec<Sample>]) -> Film {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| accumulate_runs((8, 8), batches.len(), batch(batches), |_| {}, &ByPrim).unwrap())
    }

    #[test]
    fn a_render_is_the_same_bit_for_bit_on_any_number_of_threads() {
        let batches: Vec<Vec<Sample>> = (0..37)
            .map(|b| {
                (0..500)
                    .map(|i| {
                        let v = 1.1f32.powi((b * 7 + i) % 200) * 1e-3;
                        Sample::scattered(
                            Vec3::ZERO,
                            Vec3::Z,
                            (b * 31 + i * 17) as u32,
                            Rgb::new(v, 2.0 * v, 0.5),
                        )
                    })
                    .collect()
            })
            .collect();
        let one = render_on(1, &batches);
        for threads in [2, 3, 5] {
            assert!(render_on(threads, &batches) == one, "{threads} threads");
        }
        // And it is the in-order sum of the run films, whoever rendered them.
        let mut fold = RunFold::new(8, 8);
        let runs: Vec<usize> = (0..run_count(batches.len(), 8, 8)).rev().collect();
        let mut films = vec![None; runs.len()];
        splat_runs(
            (8, 8),
            batches.len(),
            &runs,
            batch(&batches),
            |_| {},
            &ByPrim,
            |r, f| {
                films[r] = Some(f);
                Ok(())
            },
        )
        .unwrap();
        for (r, f) in films.into_iter().enumerate() {
            fold.add(r, &f.unwrap());
        }
        assert!(fold.into_film() == one);
        assert_eq!(run_count(37, 8, 8), 10, "4 batches per run at least");
    }

    #[test]
    fn runs_are_chosen_by_the_film_size_alone_and_a_wave_stays_in_the_budget() {
        use crate::film::{ACCUMULATOR_BYTES_PER_PIXEL, PRIVATE_FILMS_BUDGET, private_films};
        assert!(private_films(1024, 1024) && private_films(1576, 1576));
        assert!(!private_films(1600, 1600) && !private_films(4096, 4096));
        for threads in [1, 2, 64, 1024] {
            for (w, h) in [(64, 64), (1024, 1024), (1576, 1576)] {
                let wave = wave_width(w, h, threads) as u64;
                assert!(wave >= 1 && wave <= threads as u64);
                let run_bytes = w as u64 * h as u64 * ACCUMULATOR_BYTES_PER_PIXEL;
                assert!((wave + 1) * run_bytes <= PRIVATE_FILMS_BUDGET, "{w}x{h}, {threads}");
            }
        }
        assert_eq!(wave_width(64, 64, 64), 64);
        assert_eq!(wave_width(1576, 1576, 64), 2, "two run films and the fold");
    }
}
