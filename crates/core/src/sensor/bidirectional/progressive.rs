//! Progressive rendering: camera passes over the same dataset and splat film accumulate into
//! one image, with a running estimate of its error. Each pass is an independent estimate of
//! the camera strategies' share of every pixel, so the spread of the passes' pixel values
//! gives the standard error of their mean without a reference: the reported figure is the
//! relative RMS standard error of the image's luminance, √(mean over pixels of s²/P) / (mean
//! luminance), s² the pixels' sample variance over the P passes. It leaves out the splat
//! pass's noise (one estimate, no spread to measure), so it is a lower bound of the error.

use super::allocation::Allocation;
use super::render::combine;
use crate::film::Film;
use crate::math::{Rgb, luminance};

/// The sum of the camera passes so far, and what their error estimate needs.
#[derive(Clone, Debug, PartialEq)]
pub struct Progressive {
    sum: Film,
    /// Per pixel: Σ over passes of (the pass's per-camera-path mean luminance)².
    squares: Vec<f64>,
    /// Per pixel: Σ over passes of that mean.
    means: Vec<f64>,
    passes: u64,
    /// Camera paths per pixel in each pass.
    allocation: Allocation,
}

impl Progressive {
    /// Nothing rendered yet, for a `width`×`height` image whose passes each take
    /// `allocation`'s camera paths per pixel.
    pub fn new(width: u32, height: u32, allocation: Allocation) -> Self {
        let n = width as usize * height as usize;
        Progressive {
            sum: Film::new(width, height),
            squares: vec![0.0; n],
            means: vec![0.0; n],
            passes: 0,
            allocation,
        }
    }

    /// Adds a camera pass: per pixel the sum of its allocated camera paths' estimates.
    pub fn add(&mut self, pass: &Film) {
        self.sum.add(pass);
        for (i, p) in pass.pixels.iter().enumerate() {
            let inv = 1.0 / self.allocation.at(i).max(1) as f64;
            let l = luminance(Rgb::new(p[0] as f32, p[1] as f32, p[2] as f32)) as f64 * inv;
            self.means[i] += l;
            self.squares[i] += l * l;
        }
        self.passes += 1;
    }

    /// Camera passes added.
    pub fn passes(&self) -> u64 {
        self.passes
    }

    /// Camera paths per pixel so far (their mean over the pixels, rounded, if allocated pixel
    /// by pixel).
    pub fn spp(&self) -> u64 {
        let pixels = self.means.len().max(1) as u64;
        (self.allocation.total(self.means.len()) * self.passes + pixels / 2) / pixels
    }

    /// The relative RMS standard error of the camera passes' mean (module docs); `None` before
    /// two passes or on a black image.
    pub fn relative_error(&self) -> Option<f64> {
        if self.passes < 2 {
            return None;
        }
        let p = self.passes as f64;
        let (mut var, mut mean) = (0.0, 0.0);
        for (m, s) in self.means.iter().zip(&self.squares) {
            let mu = m / p;
            var += ((s / p - mu * mu) * p / (p - 1.0)).max(0.0) / p;
            mean += mu;
        }
        let n = self.means.len().max(1) as f64;
        (mean > 0.0).then(|| (var / n).sqrt() / (mean / n))
    }

    /// The image: `splat` plus the camera passes' mean.
    pub fn image(&self, splat: &Film) -> Film {
        combine(splat, &self.sum, &self.allocation, self.passes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Passes of known spread: the estimate is the standard error of the mean.
    #[test]
    fn the_error_estimate_is_the_standard_error_of_the_passes_mean() {
        let mut p = Progressive::new(2, 1, Allocation::Uniform(2));
        assert_eq!(p.relative_error(), None);
        // Luminance of grey g is g; pixel values per pass (sums over 2 paths): means 1 ± 0.5.
        for v in [1.0, 3.0, 1.0, 3.0] {
            let mut f = Film::new(2, 1);
            f.pixels = vec![[v; 3], [v; 3]];
            p.add(&f);
        }
        assert_eq!((p.passes(), p.spp()), (4, 8));
        // Sample variance of (0.5, 1.5, 0.5, 1.5) = 1/3; standard error² = 1/12; mean 1.
        let e = p.relative_error().unwrap();
        assert!((e - (1.0f64 / 12.0).sqrt()).abs() < 1e-5, "{e}");
        let image = p.image(&Film::new(2, 1));
        assert!((image.pixels[0][0] - 1.0).abs() < 1e-12);
    }
}
