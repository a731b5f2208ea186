//! [`SharedFilm`]: one f64 film that many threads add splats to at once, with atomic
//! compare-and-swap additions on each channel's bits. Its memory is the film's (24 bytes a
//! pixel) whatever the thread count, which is what large renders need (a 4096×4096 render on
//! two threads took 3.1 GB with per-thread films). The order in which concurrent splats land
//! varies from run to run, so its sums may differ between runs in the last bits of f64.

use super::{Film, SplatTarget};
use crate::math::Rgb;
use std::sync::atomic::{AtomicU64, Ordering};

/// A film of f64 sums (as bits in `AtomicU64`s) that threads add to concurrently.
#[derive(Debug)]
pub struct SharedFilm {
    width: u32,
    height: u32,
    pixels: Vec<[AtomicU64; 3]>,
}

impl SharedFilm {
    /// A black film.
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        let pixels = std::iter::repeat_with(|| [AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0)])
            .take(n)
            .collect();
        SharedFilm { width, height, pixels }
    }

    /// Adds `v` to pixel `index` (from any thread).
    #[inline]
    pub fn add(&self, index: usize, v: Rgb) {
        let p = &self.pixels[index];
        for (cell, x) in p.iter().zip(v.to_array()) {
            if x == 0.0 {
                continue;
            }
            let mut current = cell.load(Ordering::Relaxed);
            loop {
                let sum = (f64::from_bits(current) + x as f64).to_bits();
                match cell.compare_exchange_weak(current, sum, Ordering::Relaxed, Ordering::Relaxed) {
                    Ok(_) => break,
                    Err(now) => current = now,
                }
            }
        }
    }

    /// The accumulated film (reusing the memory: no second copy).
    pub fn into_film(self) -> Film {
        let pixels = self.pixels.into_iter().map(|p| p.map(|c| f64::from_bits(c.into_inner()))).collect();
        Film { width: self.width, height: self.height, pixels }
    }
}

/// A thread's handle on a [`SharedFilm`], usable wherever a [`SplatTarget`] is.
impl SplatTarget for &SharedFilm {
    #[inline]
    fn splat(&mut self, index: usize, v: Rgb) {
        self.add(index, v);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;

    #[test]
    fn concurrent_splats_all_land() {
        let film = SharedFilm::new(3, 2);
        (0..60_000usize).into_par_iter().for_each(|i| {
            let mut target = &film;
            target.splat(i % 6, Rgb::new(1.0, 0.5, 0.0));
        });
        let f = film.into_film();
        assert_eq!((f.width, f.height), (3, 2));
        assert!(f.pixels.iter().all(|p| *p == [10_000.0, 5_000.0, 0.0]), "{:?}", f.pixels);
    }
}
