//! The film a camera's image is read from: which pixels of the projected film are written (a crop
//! window, Mitsuba's `hdrfilm` `crop_*`) and how a pixel weighs the image plane around it (the
//! reconstruction filter, Mitsuba's `box`, `tent` and `gaussian` `<rfilter>`). Kept apart from the
//! cameras because it is the same for every projection: a camera maps a point to a position on
//! its full film, the [`Raster`] turns that position into pixels of the image written.
//!
//! **Crop.** The camera's projection is always that of the full `W`×`H` film; the image is the
//! window of `width`×`height` pixels whose top-left pixel is (`x`, `y`) of the full film. Pixel
//! (i, j) of the image is pixel (x + i, y + j) of the film.
//!
//! **Filters.** Pixel p (centre c_p, film coordinates in pixels) measures
//!
//! ```text
//! I_p = ∫ f̂(s − c_p) L(s) ds,   f̂(d) = f(d_x)·f(d_y) / (∫f)²
//! ```
//!
//! over the image plane (beyond the film's edge too: the projection extends there), with f the
//! 1-D filter truncated at its radius r: box 1 on |d| ≤ ½; tent 1 − |d|/r (r = 1 by default);
//! gaussian exp(−d²/2σ²) − exp(−r²/2σ²), r = 4σ (σ = ½ by default) — Mitsuba 3's definitions.
//! The light tracer estimates I_p by giving a splat at s the weight f̂(s − c_p) in every pixel
//! within the radius ([`Raster::footprint`]); a camera path of pixel p draws s − c_p from f̂
//! itself ([`Filter::sample`], the exact inverse CDF of each axis), so its throughput stays 1 and
//! its density carries the factor f̂ ([`Raster::weight`]) that the MIS weights of every strategy
//! share. Both estimate the same I_p without the bias of a weighted average. The splat weights of
//! one point sum to one for the box and the tent; for the gaussian they sum to one on average over
//! the point's position (exactly: ∫ Σ_p f̂ = 1), within about 1.5 % at any one point — Mitsuba's
//! particle tracer renormalises them to one, its path tracer does not; I_p is the latter's limit.
//!
//! The box filter is the fast path: one pixel, the half-open pixel square, exactly as before
//! filters existed ([`Raster::box_pixel`]).

use super::CameraError;
use crate::math::Vec2;

/// A crop window in pixels of the full film (Mitsuba's `crop_offset_x`, `crop_offset_y`,
/// `crop_width`, `crop_height`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Crop {
    /// Column of the window's left pixel.
    pub x: u32,
    /// Row of the window's top pixel.
    pub y: u32,
    /// Width of the window (of the image written), pixels.
    pub width: u32,
    /// Height of the window, pixels.
    pub height: u32,
}

/// A reconstruction filter, separable, in pixel units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Filter {
    /// 1 on [−½, ½): each pixel averages its own square.
    #[default]
    Box,
    /// 1 − |d|/radius on [−radius, radius] (Mitsuba's `tent`, radius 1 by default).
    Tent {
        /// Radius, pixels.
        radius: f32,
    },
    /// exp(−d²/2σ²) − exp(−8) on [−4σ, 4σ] (Mitsuba's `gaussian`, σ = ½ by default).
    Gaussian {
        /// Standard deviation σ, pixels.
        stddev: f32,
    },
}

/// The widest filter radius, in pixels: a splat's footprint is at most
/// (2·radius + 1)² pixels, its weights held on the stack.
pub const MAX_FILTER_RADIUS: f32 = 16.0;

/// Pixels of a footprint's side (the splat's stack arrays).
const MAX_SIDE: usize = 2 * MAX_FILTER_RADIUS as usize + 2;

/// What a scene file states about its film besides its size: the crop window (none: the whole
/// film) and the reconstruction filter.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FilmSpec {
    /// The crop window, if any.
    pub crop: Option<Crop>,
    /// The reconstruction filter.
    pub filter: Filter,
}

impl Filter {
    /// The filter's radius, pixels.
    pub fn radius(&self) -> f32 {
        match *self {
            Filter::Box => 0.5,
            Filter::Tent { radius } => radius,
            Filter::Gaussian { stddev } => 4.0 * stddev,
        }
    }

    /// A filter Opticks can use: a finite radius in (0, [`MAX_FILTER_RADIUS`]].
    pub fn check(&self) -> Result<(), CameraError> {
        let r = self.radius();
        let (name, value) = match *self {
            Filter::Box => return Ok(()),
            Filter::Tent { radius } => ("tent radius", radius),
            Filter::Gaussian { stddev } => ("gaussian stddev", stddev),
        };
        if r.is_finite() && r > 0.0 && r <= MAX_FILTER_RADIUS {
            Ok(())
        } else {
            Err(CameraError::Filter(format!(
                "{name} {value} must be a finite number > 0 with a radius of at most {MAX_FILTER_RADIUS} pixels"
            )))
        }
    }

    /// The unnormalised 1-D filter f(d).
    #[inline]
    fn eval(&self, d: f32) -> f32 {
        match *self {
            Filter::Box => (-0.5..0.5).contains(&d) as u32 as f32,
            Filter::Tent { radius } => (1.0 - d.abs() / radius).max(0.0),
            Filter::Gaussian { stddev } => {
                // At the radius 4σ the gaussian is exp(−8): Mitsuba's bias.
                let a = -0.5 / (stddev * stddev);
                ((a * d * d).exp() - GAUSSIAN_BIAS).max(0.0)
            }
        }
    }

    /// ∫ f over [−r, r] (f64: the gaussian's closed form).
    fn integral(&self) -> f64 {
        match *self {
            Filter::Box => 1.0,
            Filter::Tent { radius } => radius as f64,
            Filter::Gaussian { stddev } => gaussian_cdf_unnormalised(stddev as f64, 4.0 * stddev as f64),
        }
    }

    /// An offset from the pixel centre, drawn from f̂ by the inverse CDF of each axis
    /// (`u` ∈ [0,1)²).
    #[inline]
    pub fn sample(&self, u: Vec2) -> Vec2 {
        Vec2::new(self.sample_1d(u.x), self.sample_1d(u.y))
    }

    /// The inverse CDF of the normalised 1-D filter at `u` ∈ [0, 1).
    fn sample_1d(&self, u: f32) -> f32 {
        match *self {
            Filter::Box => u - 0.5,
            Filter::Tent { radius } => {
                if u < 0.5 {
                    radius * ((2.0 * u).sqrt() - 1.0)
                } else {
                    radius * (1.0 - (2.0 - 2.0 * u).sqrt())
                }
            }
            Filter::Gaussian { stddev } => gaussian_inverse_cdf(stddev as f64, u as f64) as f32,
        }
    }
}

/// exp(−8): the truncated gaussian's value at its radius 4σ, subtracted so that it ends at 0.
const GAUSSIAN_BIAS: f32 = 3.354_626_3e-4;

/// erf(z) by its Taylor series: exact to f64 rounding (about 1e−13) for |z| ≤ 3, where the
/// gaussian filter uses it (z ≤ 4σ/(σ√2) = 2√2).
fn erf(z: f64) -> f64 {
    let (z2, mut term, mut sum) = (z * z, z, z);
    for n in 1..80 {
        term *= -z2 / n as f64;
        let t = term / (2 * n + 1) as f64;
        sum += t;
        if t.abs() < 1e-17 * sum.abs() {
            break;
        }
    }
    sum * std::f64::consts::FRAC_2_SQRT_PI
}

/// ∫ from −r to x of the truncated gaussian exp(−d²/2σ²) − exp(−r²/2σ²), r = 4σ, x ∈ [−r, r].
fn gaussian_cdf_unnormalised(stddev: f64, x: f64) -> f64 {
    let r = 4.0 * stddev;
    let k = stddev * std::f64::consts::SQRT_2;
    let bias = GAUSSIAN_BIAS as f64;
    stddev * (std::f64::consts::PI / 2.0).sqrt() * (erf(x / k) + erf(r / k)) - bias * (x + r)
}

/// The offset x ∈ (−4σ, 4σ) at which the truncated gaussian's normalised CDF is `u`: Newton's
/// method on the closed-form CDF, kept inside a shrinking bracket (the CDF is increasing).
fn gaussian_inverse_cdf(stddev: f64, u: f64) -> f64 {
    let r = 4.0 * stddev;
    let total = gaussian_cdf_unnormalised(stddev, r);
    let target = u.clamp(0.0, 1.0) * total;
    let density = |x: f64| (-0.5 * x * x / (stddev * stddev)).exp() - GAUSSIAN_BIAS as f64;
    let (mut lo, mut hi, mut x) = (-r, r, 0.0);
    for _ in 0..100 {
        let g = gaussian_cdf_unnormalised(stddev, x) - target;
        if g.abs() <= 1e-15 * total || hi - lo <= 1e-13 * r {
            break;
        }
        if g < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let next = x - g / density(x);
        x = if next.is_finite() && next > lo && next < hi { next } else { 0.5 * (lo + hi) };
    }
    x.clamp(-r, r)
}

/// The pixels of the image written and the filter: the full film's size (the projection's),
/// the crop window, the filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Raster {
    /// The full film's width, pixels (the projection's).
    pub full_width: u32,
    /// The full film's height, pixels.
    pub full_height: u32,
    /// The window written (the whole film without a crop).
    pub window: Crop,
    /// The reconstruction filter.
    pub filter: Filter,
    /// 1/∫f, normalising the 1-D filter.
    inv_integral: f32,
}

/// The pixel of a point that does not project into the image ([`Raster::box_pixel_index`]).
pub const NO_PIXEL: u32 = u32::MAX;

/// The pixels a filtered splat reaches and their weights (on the stack).
#[derive(Clone, Copy, Debug)]
pub struct Footprint {
    /// Image column and row of the first pixel.
    first: (u32, u32),
    /// Columns and rows reached.
    count: (usize, usize),
    /// Image width (the row stride).
    stride: usize,
    /// f̂'s factor of each column and row.
    wx: [f32; MAX_SIDE],
    wy: [f32; MAX_SIDE],
}

impl Footprint {
    /// Calls `add(pixel, weight)` for each pixel reached, row-major.
    #[inline]
    pub fn for_each(&self, mut add: impl FnMut(usize, f32)) {
        for (row, &wy) in self.wy[..self.count.1].iter().enumerate() {
            let base = (self.first.1 as usize + row) * self.stride + self.first.0 as usize;
            for (col, &wx) in self.wx[..self.count.0].iter().enumerate() {
                add(base + col, wx * wy);
            }
        }
    }
}

impl Raster {
    /// The raster of a `width`×`height` film with `spec`'s crop and filter; refuses a crop that
    /// leaves the film or is empty, and a filter [`Filter::check`] refuses.
    pub fn new(width: u32, height: u32, spec: FilmSpec) -> Result<Self, CameraError> {
        spec.filter.check()?;
        let window = match spec.crop {
            None => Crop { x: 0, y: 0, width, height },
            Some(c) => {
                let fits = |o: u32, s: u32, full: u32| s >= 1 && o.checked_add(s).is_some_and(|e| e <= full);
                if !(fits(c.x, c.width, width) && fits(c.y, c.height, height)) {
                    return Err(CameraError::Crop { crop: c, width, height });
                }
                c
            }
        };
        let inv_integral = (1.0 / spec.filter.integral()) as f32;
        Ok(Raster { full_width: width, full_height: height, window, filter: spec.filter, inv_integral })
    }

    /// The normalised 1-D filter f(d)/∫f.
    #[inline]
    pub fn weight_1d(&self, d: f32) -> f32 {
        self.filter.eval(d) * self.inv_integral
    }

    /// The normalised 2-D filter f̂(d) = f(d_x)·f(d_y)/(∫f)²: the density [`Filter::sample`]
    /// draws offsets with (1 inside the pixel for the box).
    #[inline]
    pub fn weight(&self, d: Vec2) -> f32 {
        self.weight_1d(d.x) * self.weight_1d(d.y)
    }

    /// The image's width (the window's).
    #[inline]
    pub fn width(&self) -> u32 {
        self.window.width
    }

    /// The image's height (the window's).
    #[inline]
    pub fn height(&self) -> u32 {
        self.window.height
    }

    /// Whether the filter is the box (one pixel per splat).
    #[inline]
    pub fn is_box(&self) -> bool {
        self.filter == Filter::Box
    }

    /// The image pixel (row-major in the window) of full-film point (s_x, s_y) ∈ \[0,1)²
    /// under the box filter; `None` outside the film or the window.
    #[inline]
    pub fn box_pixel(&self, sx: f32, sy: f32) -> Option<usize> {
        let pixel = self.box_pixel_index(sx, sy);
        (pixel != NO_PIXEL).then_some(pixel as usize)
    }

    /// [`Raster::box_pixel`] without a branch, [`NO_PIXEL`] for `None` (what a block of points
    /// is projected with: `Pinhole::connect_block`). The column and row are clamped to the film
    /// before the truncation, which gives the same integers for points on it.
    #[inline(always)]
    pub fn box_pixel_index(&self, sx: f32, sy: f32) -> u32 {
        let (w, fw, fh) = (&self.window, self.full_width, self.full_height);
        let on_film = (0.0..1.0).contains(&sx) && (0.0..1.0).contains(&sy);
        let i = ((sx * fw as f32).min((fw - 1) as f32).max(0.0) as u32).wrapping_sub(w.x);
        let j = ((sy * fh as f32).min((fh - 1) as f32).max(0.0) as u32).wrapping_sub(w.y);
        if on_film && i < w.width && j < w.height { j * w.width + i } else { NO_PIXEL }
    }

    /// The image pixel of full-film pixel (`i`, `j`), if the window holds it.
    #[inline]
    pub fn window_pixel(&self, i: u32, j: u32) -> Option<usize> {
        let w = self.window;
        let (i, j) = (i.checked_sub(w.x)?, j.checked_sub(w.y)?);
        (i < w.width && j < w.height).then(|| j as usize * w.width as usize + i as usize)
    }

    /// Full-film coordinates (s_x, s_y) of offset `d` (pixels) from the centre of image pixel
    /// (`i`, `j`).
    #[inline]
    pub fn film_point(&self, i: u32, j: u32, d: Vec2) -> (f32, f32) {
        let (x, y) = (self.window.x + i, self.window.y + j);
        ((x as f32 + 0.5 + d.x) / self.full_width as f32, (y as f32 + 0.5 + d.y) / self.full_height as f32)
    }

    /// The pixels within the filter's radius of full-film point (s_x, s_y) (any real
    /// coordinates) that the window holds, with their weights f̂(s − c_p); `None` when there
    /// are none.
    #[inline]
    pub fn footprint(&self, sx: f32, sy: f32) -> Option<Footprint> {
        let r = self.filter.radius();
        let w = self.window;
        let axis = |s: f32, full: u32, first: u32, size: u32, out: &mut [f32; MAX_SIDE]| {
            let x = s * full as f32 - 0.5; // relative to pixel centres
            if !x.is_finite() {
                return None;
            }
            // Pixels with |x − c| < r; the box's half-open square: the one pixel holding s.
            let (lo, hi) = match self.filter {
                Filter::Box => ((x + 0.5).floor(), (x + 0.5).floor()),
                _ => ((x - r).floor() + 1.0, (x + r).ceil() - 1.0),
            };
            let (lo, hi) = (lo.max(first as f32), hi.min((first + size - 1) as f32));
            if !(lo <= hi) {
                return None;
            }
            let (lo, n) = (lo as u32, ((hi - lo) as usize + 1).min(MAX_SIDE));
            for (k, o) in out[..n].iter_mut().enumerate() {
                *o = self.weight_1d(x - (lo as f32 + k as f32));
            }
            Some((lo - first, n))
        };
        let (mut wx, mut wy) = ([0.0; MAX_SIDE], [0.0; MAX_SIDE]);
        let (x0, nx) = axis(sx, self.full_width, w.x, w.width, &mut wx)?;
        let (y0, ny) = axis(sy, self.full_height, w.y, w.height, &mut wy)?;
        Some(Footprint { first: (x0, y0), count: (nx, ny), stride: w.width as usize, wx, wy })
    }
}

#[cfg(test)]
mod tests;
