//! The film: a grid of accumulated pixel values (radiance, or irradiance for meters), summed in
//! f64 so that millions of small splats lose nothing.

use crate::math::Rgb;

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
    pub fn splat(&mut self, index: usize, v: Rgb) {
        let p = &mut self.pixels[index];
        p[0] += v.x as f64;
        p[1] += v.y as f64;
        p[2] += v.z as f64;
    }

    /// Adds another film of the same size (reduction of per-thread films).
    pub fn add(&mut self, other: &Film) {
        debug_assert_eq!((self.width, self.height), (other.width, other.height));
        for (a, b) in self.pixels.iter_mut().zip(&other.pixels) {
            a[0] += b[0];
            a[1] += b[1];
            a[2] += b[2];
        }
    }

    /// Pixel values as interleaved f32 RGB (what image writers take).
    pub fn to_rgb_f32(&self) -> Vec<f32> {
        self.pixels.iter().flat_map(|p| p.map(|x| x as f32)).collect()
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
