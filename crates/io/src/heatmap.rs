//! Heat-map PNGs of meter readings: the cells in a perceptual colour map (a viridis
//! approximation), with numbered axes in metres along the meter's edges and a numbered colour
//! bar.
//!
//! Text is drawn with a built-in 5×7 bitmap font covering only what the plots need (digits,
//! `. - + e ( ) /`, space and the letters `E W l m u v x`; other characters draw as blanks).
//! That is ~30 lines of data; the alternative, a glyph rasteriser such as `ab_glyph`, would need
//! a font file shipped in the repository or fetched from a crate, for a handful of tick labels.
//!
//! Layout: cell (i, j) of an nx × ny meter is drawn with i growing to the right (along u) and j
//! growing *upward* (along v), like a plot with the origin at the bottom left; the map keeps the
//! meter's aspect ratio |u| : |v|. The colour scale runs from 0 to the largest value.

use image::{ImageEncoder, codecs::png::PngEncoder};
use std::path::{Path, PathBuf};

/// Why a heat map cannot be drawn or written.
#[derive(Debug, thiserror::Error)]
pub enum HeatmapError {
    /// The value count does not match nx × ny, or a size is zero.
    #[error("heat map of {nx}x{ny} cells given {len} values")]
    Size {
        /// Cells along u.
        nx: u32,
        /// Cells along v.
        ny: u32,
        /// Values given.
        len: usize,
    },
    /// A value or an edge length is NaN or infinite.
    #[error("heat map values and edge lengths must be finite")]
    NotFinite,
    /// Writing failed.
    #[error("cannot write {}: {source}", .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// PNG encoding failed.
    #[error("cannot encode {}: {source}", .path.display())]
    Encode {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: image::ImageError,
    },
}

/// An RGB8 raster.
#[derive(Clone, Debug, PartialEq)]
pub struct Raster {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Interleaved RGB, row 0 at the top.
    pub rgb: Vec<u8>,
}

impl Raster {
    fn new(width: u32, height: u32, bg: [u8; 3]) -> Self {
        Raster { width, height, rgb: bg.repeat(width as usize * height as usize) }
    }

    fn set(&mut self, x: i64, y: i64, c: [u8; 3]) {
        if x >= 0 && y >= 0 && x < self.width as i64 && y < self.height as i64 {
            let k = 3 * (y as usize * self.width as usize + x as usize);
            self.rgb[k..k + 3].copy_from_slice(&c);
        }
    }

    fn fill(&mut self, x0: i64, y0: i64, x1: i64, y1: i64, c: [u8; 3]) {
        for y in y0..y1 {
            for x in x0..x1 {
                self.set(x, y, c);
            }
        }
    }

    /// Draws `text` with its top-left corner at (x, y), glyphs scaled by `scale`.
    fn text(&mut self, x: i64, y: i64, text: &str, scale: i64, c: [u8; 3]) {
        for (k, ch) in text.chars().enumerate() {
            let rows = glyph(ch);
            let gx = x + k as i64 * 6 * scale;
            for (r, bits) in rows.iter().enumerate() {
                for col in 0..5 {
                    if bits & (0x10 >> col) != 0 {
                        self.fill(
                            gx + col * scale,
                            y + r as i64 * scale,
                            gx + (col + 1) * scale,
                            y + (r as i64 + 1) * scale,
                            c,
                        );
                    }
                }
            }
        }
    }
}

/// Width of `text` in pixels at `scale`.
fn text_width(text: &str, scale: i64) -> i64 {
    (text.chars().count() as i64 * 6 - 1).max(0) * scale
}

/// The 5×7 bitmap of a character (bit 4 is the leftmost column).
fn glyph(c: char) -> [u8; 7] {
    match c {
        '0' => [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E],
        '1' => [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
        '2' => [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
        '3' => [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E],
        '4' => [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
        '5' => [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
        '6' => [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
        '7' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E],
        '9' => [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C],
        '.' => [0, 0, 0, 0, 0, 0x0C, 0x0C],
        '-' => [0, 0, 0, 0x1F, 0, 0, 0],
        '+' => [0, 0x04, 0x04, 0x1F, 0x04, 0x04, 0],
        'e' => [0, 0, 0x0E, 0x11, 0x1F, 0x10, 0x0E],
        '(' => [0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02],
        ')' => [0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08],
        '/' => [0, 0x01, 0x02, 0x04, 0x08, 0x10, 0],
        'u' => [0, 0, 0x11, 0x11, 0x11, 0x13, 0x0D],
        'v' => [0, 0, 0x11, 0x11, 0x11, 0x0A, 0x04],
        'm' => [0, 0, 0x1A, 0x15, 0x15, 0x11, 0x11],
        'l' => [0x0C, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E],
        'x' => [0, 0, 0x11, 0x0A, 0x04, 0x0A, 0x11],
        'E' => [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F],
        'W' => [0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A],
        _ => [0; 7],
    }
}

/// The colour of t ∈ [0, 1] (piecewise-linear approximation of matplotlib's viridis).
pub fn colour(t: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 5] = [
        [68.0, 1.0, 84.0],
        [59.0, 82.0, 139.0],
        [33.0, 145.0, 140.0],
        [94.0, 201.0, 98.0],
        [253.0, 231.0, 37.0],
    ];
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 } * 4.0;
    let k = (t as usize).min(3);
    let f = t - k as f64;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    [0, 1, 2].map(|c| (a[c] + f * (b[c] - a[c])).round() as u8)
}

/// A tick label with about three significant digits.
pub fn format_number(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (0.01..1e5).contains(&a) {
        let decimals = (2 - a.log10().floor() as i32).clamp(0, 4) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
    } else {
        format!("{v:.1e}")
    }
}

/// Tick positions in [0, max]: multiples of a 1-2-5 step giving about `count` intervals.
fn ticks(max: f64, count: f64) -> Vec<f64> {
    if max.is_nan() || max <= 0.0 {
        return vec![0.0];
    }
    let raw = max / count;
    let p = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0].into_iter().map(|m| m * p).find(|s| *s >= raw).unwrap_or(10.0 * p);
    (0..).map(|k| k as f64 * step).take_while(|t| *t <= max * (1.0 + 1e-9)).collect()
}

/// Draws the heat map of `values` (nx × ny cells, entry `j * nx + i`, j along v) for a meter
/// whose edges are `u_len` × `v_len` metres, titled `title`.
pub fn draw(
    values: &[f64],
    nx: u32,
    ny: u32,
    u_len: f64,
    v_len: f64,
    title: &str,
) -> Result<Raster, HeatmapError> {
    if nx == 0 || ny == 0 || values.len() != nx as usize * ny as usize {
        return Err(HeatmapError::Size { nx, ny, len: values.len() });
    }
    let edges_ok = u_len.is_finite() && v_len.is_finite() && u_len > 0.0 && v_len > 0.0;
    if !edges_ok || !values.iter().all(|v| v.is_finite()) {
        return Err(HeatmapError::NotFinite);
    }
    const SIDE: f64 = 480.0;
    let (mw, mh) = if u_len >= v_len {
        (SIDE, (SIDE * v_len / u_len).max(40.0))
    } else {
        ((SIDE * u_len / v_len).max(40.0), SIDE)
    };
    let (mw, mh) = (mw.round() as i64, mh.round() as i64);
    let (left, top, bottom, right) = (90i64, 40i64, 60i64, 150i64);
    let (w, h) = (left + mw + right, top + mh + bottom);
    let (white, black) = ([255u8; 3], [0u8; 3]);
    let mut r = Raster::new(w as u32, h as u32, white);
    let vmax = values.iter().copied().fold(0.0f64, f64::max);
    // Cells.
    for py in 0..mh {
        let j = (((mh - 1 - py) as f64 + 0.5) / mh as f64 * ny as f64) as usize;
        for px in 0..mw {
            let i = ((px as f64 + 0.5) / mw as f64 * nx as f64) as usize;
            let v = values[j.min(ny as usize - 1) * nx as usize + i.min(nx as usize - 1)];
            r.set(left + px, top + py, colour(if vmax > 0.0 { v / vmax } else { 0.0 }));
        }
    }
    // Frame, axes and ticks.
    r.fill(left - 1, top - 1, left + mw + 1, top, black);
    r.fill(left - 1, top + mh, left + mw + 1, top + mh + 1, black);
    r.fill(left - 1, top - 1, left, top + mh + 1, black);
    r.fill(left + mw, top - 1, left + mw + 1, top + mh + 1, black);
    for t in ticks(u_len, 5.0) {
        let x = left + (t / u_len * mw as f64).round() as i64;
        r.fill(x, top + mh, x + 1, top + mh + 6, black);
        let s = format_number(t);
        r.text(x - text_width(&s, 2) / 2, top + mh + 10, &s, 2, black);
    }
    for t in ticks(v_len, 5.0) {
        let y = top + mh - (t / v_len * mh as f64).round() as i64;
        r.fill(left - 6, y, left, y + 1, black);
        let s = format_number(t);
        r.text(left - 10 - text_width(&s, 2), y - 7, &s, 2, black);
    }
    r.text(left + mw / 2 - text_width("u (m)", 2) / 2, top + mh + 34, "u (m)", 2, black);
    r.text(4, top - 30, "v (m)", 2, black);
    r.text(left + mw / 2 - text_width(title, 2) / 2, 8, title, 2, black);
    // Colour bar.
    let (bx, bw) = (left + mw + 20, 20);
    for py in 0..mh {
        let c = colour((mh - 1 - py) as f64 / (mh - 1).max(1) as f64);
        r.fill(bx, top + py, bx + bw, top + py + 1, c);
    }
    r.fill(bx - 1, top - 1, bx + bw + 1, top, black);
    r.fill(bx - 1, top + mh, bx + bw + 1, top + mh + 1, black);
    r.fill(bx - 1, top - 1, bx, top + mh + 1, black);
    r.fill(bx + bw, top - 1, bx + bw + 1, top + mh + 1, black);
    for t in ticks(vmax, 5.0) {
        let y = top + mh - if vmax > 0.0 { (t / vmax * mh as f64).round() as i64 } else { 0 };
        r.fill(bx + bw, y, bx + bw + 6, y + 1, black);
        r.text(bx + bw + 10, y - 7, &format_number(t), 2, black);
    }
    Ok(r)
}

/// The PNG bytes of the heat map (see [`draw`]); `path` only names it in errors. Written with
/// the command's other outputs, all or none (`crate::image_file::write_files_atomically`).
pub fn encode_heatmap(
    path: &Path,
    values: &[f64],
    nx: u32,
    ny: u32,
    u_len: f64,
    v_len: f64,
    title: &str,
) -> Result<Vec<u8>, HeatmapError> {
    let r = draw(values, nx, ny, u_len, v_len, title)?;
    let mut png = Vec::new();
    PngEncoder::new(&mut png)
        .write_image(&r.rgb, r.width, r.height, image::ExtendedColorType::Rgb8)
        .map_err(|source| HeatmapError::Encode { path: path.to_path_buf(), source })?;
    Ok(png)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_ticks_read_well() {
        assert_eq!(format_number(0.0), "0");
        assert_eq!(format_number(1234.0), "1234");
        assert_eq!(format_number(12.34), "12.3");
        assert_eq!(format_number(0.5), "0.5");
        assert_eq!(format_number(0.0123), "0.0123");
        assert_eq!(format_number(2.0e-5), "2.0e-5");
        assert_eq!(ticks(1.0, 5.0), vec![0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0]);
        assert_eq!(ticks(0.0, 5.0), vec![0.0]);
        assert_eq!(colour(0.0), [68, 1, 84]);
        assert_eq!(colour(1.0), [253, 231, 37]);
        assert_eq!(colour(f64::NAN), [68, 1, 84]);
    }

    #[test]
    fn draws_cells_bottom_up_and_refuses_bad_input() {
        let r = draw(&[0.0, 1.0, 2.0, 4.0], 2, 2, 2.0, 1.0, "E (lux)").unwrap();
        assert_eq!((r.width, r.height), (90 + 480 + 150, 40 + 240 + 60));
        let at = |x: u32, y: u32| {
            let k = 3 * (y * r.width + x) as usize;
            [r.rgb[k], r.rgb[k + 1], r.rgb[k + 2]]
        };
        assert_eq!(at(90 + 10, 40 + 230), colour(0.0)); // cell (0, 0) bottom left
        assert_eq!(at(90 + 470, 40 + 10), colour(1.0)); // cell (1, 1) top right
        assert!(matches!(draw(&[1.0], 2, 2, 1.0, 1.0, ""), Err(HeatmapError::Size { .. })));
        assert!(matches!(draw(&[f64::NAN], 1, 1, 1.0, 1.0, ""), Err(HeatmapError::NotFinite)));
        assert!(matches!(draw(&[1.0], 1, 1, 0.0, 1.0, ""), Err(HeatmapError::NotFinite)));
    }
}
