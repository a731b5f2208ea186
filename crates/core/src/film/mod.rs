//! The film: a grid of accumulated pixel values (radiance, or irradiance for meters), summed in
//! f64 so that millions of small splats lose nothing.
//!
//! Splatting is a random read-modify-write per stored sample, so the film's size in cache
//! decides much of the render time. An [`Accumulator`] stages splats in an f32 copy (half the
//! bytes: a 256×256 image fits a core's L2) and folds them into the f64 film every
//! [`FLUSH_SPLATS`] splats, long before f32 could lose precision. A render splats each run of
//! batches into its own accumulator, a few runs at a time, while two of them and the summed film
//! fit in [`PRIVATE_FILMS_BUDGET`] ([`private_films`], [`wave_width`]; `crate::sensor`'s
//! `runs.rs`); larger images are accumulated into one [`SharedFilm`] that every thread adds to
//! atomically (`shared.rs`), so a render's memory never grows as threads × pixels
//! ([`accumulation_bytes`]).

mod shared;

pub use shared::SharedFilm;

use crate::math::Rgb;
use rayon::prelude::*;

/// Pixels per task when [`Film::add`] runs on all cores (below two of these, one thread adds).
const ADD_GRAIN: usize = 1 << 15;

/// Bytes the [`Accumulator`]s of a render may take together with the film they are summed
/// into; beyond it, one [`SharedFilm`] is used. 256 MiB: private accumulators up to about
/// 1576×1576 (two of them and the sum; they are faster while they fit in cache), a shared film
/// above.
pub const PRIVATE_FILMS_BUDGET: u64 = 256 << 20;

/// Bytes of one [`Accumulator`] per pixel: the f64 film and its f32 staging copy.
pub const ACCUMULATOR_BYTES_PER_PIXEL: u64 = 36;

/// Bytes of a [`Film`] (and of a [`SharedFilm`]) per pixel.
pub const FILM_BYTES_PER_PIXEL: u64 = 24;

/// Bytes of one accumulator of a `width`×`height` film (the summed film is counted at the same
/// rate, an upper bound).
fn accumulator_bytes(width: u32, height: u32) -> u64 {
    (width as u64 * height as u64).saturating_mul(ACCUMULATOR_BYTES_PER_PIXEL).max(1)
}

/// Whether a `width`×`height` render accumulates into private accumulators (one per run of
/// batches, summed in order: bit for bit the same on any number of threads), else into one
/// [`SharedFilm`]: whether two accumulators and the summed film fit in
/// [`PRIVATE_FILMS_BUDGET`] — up to about 2.5 million pixels. The size alone decides.
pub fn private_films(width: u32, height: u32) -> bool {
    accumulator_bytes(width, height).saturating_mul(3) <= PRIVATE_FILMS_BUDGET
}

/// Private accumulators a render on `threads` threads holds at once: one per thread, as many as
/// fit in [`PRIVATE_FILMS_BUDGET`] beside the summed film (at least one).
pub fn wave_width(width: u32, height: u32, threads: usize) -> usize {
    let fit = (PRIVATE_FILMS_BUDGET / accumulator_bytes(width, height)).saturating_sub(1);
    threads.min(usize::try_from(fit).unwrap_or(usize::MAX)).max(1)
}

/// The most memory accumulating a `width`×`height` film on `threads` threads takes, in bytes:
/// at most [`PRIVATE_FILMS_BUDGET`] for images with [`private_films`], one shared film
/// (24 bytes a pixel) for larger ones — never threads × pixels. What a caller checks against
/// the memory it has before any work.
pub fn accumulation_bytes(width: u32, height: u32, threads: usize) -> u64 {
    let film = width as u64 * height as u64 * FILM_BYTES_PER_PIXEL;
    match private_films(width, height) {
        true => (wave_width(width, height, threads) as u64 + 1) * accumulator_bytes(width, height),
        false => film,
    }
}

/// Anything splats can be added to.
pub trait SplatTarget {
    /// Adds `v` to pixel (or cell) `index`.
    fn splat(&mut self, index: usize, v: Rgb);

    /// Hints that pixel `index` will soon be added to (a splat loop that knows its next pixels
    /// ahead starts their loads, `crate::sensor::splat`); no effect on any value.
    #[inline(always)]
    fn prefetch(&self, _index: usize) {}
}

/// Splats staged in f32 and folded into an f64 [`Film`] every [`FLUSH_SPLATS`] splats.
#[derive(Clone, Debug)]
pub struct Accumulator {
    film: Film,
    staging: Vec<[f32; 3]>,
    staged: usize,
}

/// Splats staged in f32 before they are folded into f64. With at most 2²⁰ splats spread over
/// a film, a pixel's f32 sum carries a rounding error far below the image's noise.
pub const FLUSH_SPLATS: usize = 1 << 20;

impl Accumulator {
    /// A black accumulator.
    pub fn new(width: u32, height: u32) -> Self {
        let film = Film::new(width, height);
        let staging = vec![[0.0; 3]; film.pixels.len()];
        Accumulator { film, staging, staged: 0 }
    }

    fn flush(&mut self) {
        for (a, b) in self.film.pixels.iter_mut().zip(self.staging.iter_mut()) {
            for c in 0..3 {
                a[c] += b[c] as f64;
            }
            *b = [0.0; 3];
        }
        self.staged = 0;
    }

    /// The accumulated film.
    pub fn into_film(mut self) -> Film {
        self.flush();
        self.film
    }

    /// The accumulated film, in place (the staged splats folded in): what
    /// [`Accumulator::into_film`] would return, for a caller that reuses the accumulator.
    pub fn film(&mut self) -> &Film {
        if self.staged > 0 {
            self.flush();
        }
        &self.film
    }

    /// Black again, keeping its memory: the same as a new accumulator of its size. (The
    /// staging is all zeros unless something was staged since the last flush; folding it in
    /// first, as this did, was a pass over every pixel for nothing.)
    pub fn clear(&mut self) {
        if self.staged > 0 {
            self.staging.fill([0.0; 3]);
            self.staged = 0;
        }
        self.film.pixels.fill([0.0; 3]);
    }
}

impl SplatTarget for Accumulator {
    #[inline]
    fn splat(&mut self, index: usize, v: Rgb) {
        let p = &mut self.staging[index];
        p[0] += v.x;
        p[1] += v.y;
        p[2] += v.z;
        self.staged += 1;
        if self.staged >= FLUSH_SPLATS {
            self.flush();
        }
    }

    #[inline(always)]
    fn prefetch(&self, index: usize) {
        if let Some(p) = self.staging.get(index) {
            crate::math::prefetch(p);
        }
    }
}

impl SplatTarget for Film {
    #[inline]
    fn splat(&mut self, index: usize, v: Rgb) {
        Film::splat(self, index, v);
    }
}

/// Accumulated RGB values, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Per-pixel sums, `width * height` entries.
    pub pixels: Vec<[f64; 3]>,
}

impl Film {
    /// A black film.
    pub fn new(width: u32, height: u32) -> Self {
        Film { width, height, pixels: vec![[0.0; 3]; width as usize * height as usize] }
    }

    /// Adds `v` to pixel `index`.
    #[inline]
    fn splat(&mut self, index: usize, v: Rgb) {
        let p = &mut self.pixels[index];
        p[0] += v.x as f64;
        p[1] += v.y as f64;
        p[2] += v.z as f64;
    }

    /// Adds another film of the same size (reduction of per-thread films). Large films are
    /// added on all cores, a band of pixels per task: each pixel's sum is one addition, so the
    /// result is the same bit for bit (renders fold one film per run of batches, in run order,
    /// and that fold was a serial pass over every pixel per run).
    pub fn add(&mut self, other: &Film) {
        debug_assert_eq!((self.width, self.height), (other.width, other.height));
        let add = |a: &mut [[f64; 3]], b: &[[f64; 3]]| {
            for (a, b) in a.iter_mut().zip(b) {
                a[0] += b[0];
                a[1] += b[1];
                a[2] += b[2];
            }
        };
        if self.pixels.len() < 2 * ADD_GRAIN {
            add(&mut self.pixels, &other.pixels);
        } else {
            self.pixels
                .par_chunks_mut(ADD_GRAIN)
                .zip(other.pixels.par_chunks(ADD_GRAIN))
                .for_each(|(a, b)| add(a, b));
        }
    }

    /// Pixel values as interleaved f32 RGB (what image writers take).
    pub fn to_rgb_f32(&self) -> Vec<f32> {
        self.pixels.iter().flat_map(|p| p.map(|x| x as f32)).collect()
    }

    /// Whether every pixel is zero: nothing reached the sensor.
    pub fn is_black(&self) -> bool {
        self.pixels.iter().all(|p| p.iter().all(|&v| v == 0.0))
    }

    /// Mean value per channel.
    pub fn mean(&self) -> [f64; 3] {
        let n = self.pixels.len().max(1) as f64;
        let mut m = [0.0; 3];
        for p in &self.pixels {
            for c in 0..3 {
                m[c] += p[c];
            }
        }
        m.map(|x| x / n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cleared accumulator is a new one: reused, it gives the film a fresh one gives, and
    /// `film` (in place) is `into_film`.
    #[test]
    fn a_cleared_accumulator_is_a_new_one() {
        let splats = |acc: &mut Accumulator, k: f32| {
            for i in 0..50 {
                acc.splat(i % 6, Rgb::new(k * i as f32, 0.5, 1e-3 * k));
            }
        };
        let mut reused = Accumulator::new(3, 2);
        splats(&mut reused, 7.0);
        reused.clear();
        assert_eq!(reused.film(), &Film::new(3, 2));
        splats(&mut reused, 0.25);
        let mut fresh = Accumulator::new(3, 2);
        splats(&mut fresh, 0.25);
        assert_eq!(reused.film(), &fresh.clone().into_film());
        assert_ne!(fresh.into_film(), Film::new(3, 2));
        // Cleared after its splats were folded in (nothing staged): black again too.
        reused.clear();
        assert_eq!(reused.film(), &Film::new(3, 2));
        splats(&mut reused, 0.25);
        assert_ne!(reused.film(), &Film::new(3, 2));
    }

    /// Adding a large film (on all cores, by bands) gives every pixel the one addition a
    /// serial loop gives, bit for bit, at band edges and in the last, short band.
    #[test]
    fn adding_a_large_film_is_the_pixelwise_sum() {
        let (w, h) = (331, 211); // > 2 bands, not a multiple of one
        let film = |k: f64| Film {
            width: w,
            height: h,
            pixels: (0..w * h)
                .map(|i| [k * i as f64 / 7.0, 1.0 / (i as f64 + k), (i % 13) as f64 * 0.1])
                .collect(),
        };
        let (a, b) = (film(3.0), film(0.1));
        let mut sum = a.clone();
        sum.add(&b);
        assert!(a.pixels.len() >= 2 * ADD_GRAIN);
        for ((s, x), y) in sum.pixels.iter().zip(&a.pixels).zip(&b.pixels) {
            for c in 0..3 {
                assert_eq!(s[c].to_bits(), (x[c] + y[c]).to_bits());
            }
        }
    }
}
