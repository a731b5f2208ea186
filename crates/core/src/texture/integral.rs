//! The exact mean of a texture over a triangle of texture coordinates (what a textured area
//! light's power Φ = ∫ L(uv(y)) dA · ∫s dω is made of: [`crate::light::AreaLight`]).
//!
//! Every texture of (u, v) is piecewise polynomial of degree ≤ 2 on a grid of unit cells of
//! its own *cell space* q (an affine image of the UV after `to_uv`): a bilinear bitmap is
//! bilinear between four texel centres (q = (u·W − ½, v·H − ½)), a nearest bitmap constant
//! on each texel (q = (u·W, v·H)), a checkerboard constant on squares of side ½ (q = 2·uv).
//! The triangle's UV is affine in its barycentrics b, so is q(b); the mean over the triangle
//! (uniform in area, i.e. in b) is 2·∫ f(q(b)) db over the unit barycentric triangle, cut by
//! the cells' pre-images (half-planes in b, which also holds when the UV triangle is
//! degenerate): each piece is a convex polygon, fanned into triangles, on which the
//! three-edge-midpoint rule is exact for polynomials of degree 2. Cells wholly inside a
//! non-degenerate triangle take their closed form (the mean of the four corners, times the
//! cell's barycentric area 1/|det|). The work is bounded by [`MAX_CELLS`] cells per light.

use super::{Bitmap, Checkerboard, FilterType, Texture};
use crate::math::{Rgb, Vec2};
use glam::{DVec2, DVec3};

/// The most texture cells one light's triangles may cover (a 4096² bitmap over a quad covers
/// 2·4096² cells; a texture repeated more often than that over an emitter is refused).
pub const MAX_CELLS: u64 = 1 << 26;

/// Why a mean cannot be computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeanError {
    /// The triangles cover more than [`MAX_CELLS`] cells of the texture (or lie more than
    /// 10¹² cells from its origin).
    TooManyCells,
    /// A mesh attribute's values belong to the meshes, not to the texture.
    MeshAttribute,
}

/// The mean of `texture` over the triangle whose corners have texture coordinates `uv`
/// (uniform over its area), counting the cells visited into `cells` (an error once it passes
/// [`MAX_CELLS`]).
pub fn triangle_mean(texture: &Texture, uv: [Vec2; 3], cells: &mut u64) -> Result<Rgb, MeanError> {
    let to_uv_f64 = |t: &super::UvTransform, p: Vec2| {
        let [a, b] = t.0.map(|r| r.map(f64::from));
        let p = p.as_dvec2();
        DVec2::new(a[0] * p.x + a[1] * p.y + a[2], b[0] * p.x + b[1] * p.y + b[2])
    };
    let mean = match texture {
        Texture::Constant(v) => return Ok(Rgb::splat(*v)),
        Texture::MeshAttribute(_) => return Err(MeanError::MeshAttribute),
        Texture::Bitmap(bm) => {
            let (w, h) = (bm.width as f64, bm.height as f64);
            let half = if bm.filter == FilterType::Bilinear { 0.5 } else { 0.0 };
            let q = uv.map(|p| {
                let t = to_uv_f64(&bm.to_uv, p);
                DVec2::new(t.x * w - half, t.y * h - half)
            });
            integrate(q, cells, |i, j| bitmap_cell(bm, i, j))?
        }
        Texture::Checkerboard(c) => {
            let q = uv.map(|p| 2.0 * to_uv_f64(&c.to_uv, p));
            integrate(q, cells, |i, j| checker_cell(c, i, j))?
        }
    };
    Ok(mean.as_vec3())
}

/// The corner values (c00, c10, c01, c11) of a cell: the integrand there is their bilinear
/// interpolation in the cell's local coordinates.
type Corners = [DVec3; 4];

fn bitmap_cell(bm: &Bitmap, i: i64, j: i64) -> Corners {
    let t = |i, j| bm.texel(i, j).as_dvec3();
    match bm.filter {
        FilterType::Nearest => [t(i, j); 4],
        FilterType::Bilinear => [t(i, j), t(i + 1, j), t(i, j + 1), t(i + 1, j + 1)],
    }
}

fn checker_cell(c: &Checkerboard, i: i64, j: i64) -> Corners {
    // Cell (i, j) of q = 2·uv: u's fractional part is above ½ where i is odd.
    let colour = if (i.rem_euclid(2) == 1) == (j.rem_euclid(2) == 1) { c.color0 } else { c.color1 };
    [colour.as_dvec3(); 4]
}

/// A convex polygon of barycentric points (b1, b2).
type Polygon = Vec<DVec2>;

/// The part of `poly` where the affine g(b) = g0 + gb·b is ≥ 0 (Sutherland–Hodgman).
fn clip(poly: &[DVec2], g0: f64, gb: DVec2) -> Polygon {
    let g = |p: DVec2| g0 + gb.dot(p);
    let mut out = Vec::with_capacity(poly.len() + 1);
    for (k, &a) in poly.iter().enumerate() {
        let b = poly[(k + 1) % poly.len()];
        let (ga, gb_) = (g(a), g(b));
        if ga >= 0.0 {
            out.push(a);
        }
        if (ga >= 0.0) != (gb_ >= 0.0) {
            out.push(a + (b - a) * (ga / (ga - gb_)));
        }
    }
    out
}

/// 2·∫ f(q(b)) db over the unit barycentric triangle, where q(b) = q[0] + b1·(q[1] − q[0]) +
/// b2·(q[2] − q[0]) and f on cell (i, j) is the bilinear interpolation of `cell(i, j)` at
/// q − (i, j).
fn integrate(q: [DVec2; 3], cells: &mut u64, cell: impl Fn(i64, i64) -> Corners) -> Result<DVec3, MeanError> {
    if !q.iter().all(|p| p.is_finite()) {
        return Ok(cell(0, 0)[0]); // as `Bitmap::eval` treats a non-finite UV
    }
    let (d1, d2) = (q[1] - q[0], q[2] - q[0]);
    let det = d1.perp_dot(d2);
    let scale = d1.length() * d2.length();
    // qx(b) = q0.x + b·(d1.x, d2.x); qy likewise.
    let (gx, gy) = (DVec2::new(d1.x, d2.x), DVec2::new(d1.y, d2.y));
    let tri: Polygon = vec![DVec2::ZERO, DVec2::X, DVec2::Y];
    // Wholly-inside test for cells of a non-degenerate triangle: q's edge functions.
    let inside = |p: DVec2| {
        (0..3).all(|k| {
            let (a, b) = (q[k], q[(k + 1) % 3]);
            (b - a).perp_dot(p - a) * det.signum() >= 0.0
        })
    };
    let regular = det.abs() > 1e-9 * scale;
    let (lo, hi) = (q[0].min(q[1]).min(q[2]), q[0].max(q[1]).max(q[2]));
    // Far from the origin the cells' indices lose their meaning (and f32 lookups theirs).
    let (span, far) = (hi - lo, lo.abs().max(hi.abs()).max_element());
    if span.max_element() > MAX_CELLS as f64 || far > 1e12 {
        return Err(MeanError::TooManyCells);
    }
    let mut sum = DVec3::ZERO;
    for j in lo.y.floor() as i64..=(hi.y.ceil() as i64 - 1).max(lo.y.floor() as i64) {
        let jf = j as f64;
        *cells += 1;
        let row = clip(&clip(&tri, q[0].y - jf, gy), jf + 1.0 - q[0].y, -gy);
        if row.len() < 3 {
            continue;
        }
        let xs = row.iter().map(|b| q[0].x + gx.dot(*b));
        let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
        let (i0, i1) = (x0.floor() as i64, (x1.ceil() as i64 - 1).max(x0.floor() as i64));
        *cells += (i1 - i0) as u64;
        if *cells > MAX_CELLS {
            return Err(MeanError::TooManyCells);
        }
        for i in i0..=i1 {
            let (fi, c) = (i as f64, cell(i, j));
            let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
            if regular && corners.iter().all(|&(x, y)| inside(DVec2::new(fi + x, jf + y))) {
                sum += (c[0] + c[1] + c[2] + c[3]) * (0.25 / det.abs());
                continue;
            }
            let piece = clip(&clip(&row, q[0].x - fi, gx), fi + 1.0 - q[0].x, -gx);
            let f = |b: DVec2| {
                let (x, y) = (q[0].x + gx.dot(b) - fi, q[0].y + gy.dot(b) - jf);
                c[0] * ((1.0 - x) * (1.0 - y))
                    + c[1] * (x * (1.0 - y))
                    + c[2] * ((1.0 - x) * y)
                    + c[3] * (x * y)
            };
            for k in 1..piece.len().saturating_sub(1) {
                let (a, b, cc) = (piece[0], piece[k], piece[k + 1]);
                let area = 0.5 * (b - a).perp_dot(cc - a).abs();
                sum += (f(0.5 * (a + b)) + f(0.5 * (b + cc)) + f(0.5 * (cc + a))) * (area / 3.0);
            }
        }
    }
    Ok(2.0 * sum)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{UvTransform, WrapMode};

    fn mean(t: &Texture, uv: [Vec2; 3]) -> Rgb {
        triangle_mean(t, uv, &mut 0).unwrap()
    }

    /// The mean of `t` over the triangle by brute force: a stratified grid of barycentrics.
    fn brute(t: &Texture, uv: [Vec2; 3]) -> Rgb {
        let n = 600;
        let mut sum = DVec3::ZERO;
        let mut count = 0.0;
        for a in 0..n {
            for b in 0..n - a {
                let (b1, b2) = ((a as f32 + 1.0 / 3.0) / n as f32, (b as f32 + 1.0 / 3.0) / n as f32);
                let p = uv[0] + b1 * (uv[1] - uv[0]) + b2 * (uv[2] - uv[0]);
                sum += t.eval(p, Rgb::ZERO).as_dvec3();
                count += 1.0;
            }
        }
        (sum / count).as_vec3()
    }

    fn bitmap(filter: FilterType, wrap: WrapMode, to_uv: UvTransform) -> Texture {
        let texels = (0..12).map(|k| Rgb::new(k as f32, (k * k % 7) as f32, 1.0 + (k % 3) as f32)).collect();
        Texture::Bitmap(Bitmap::new(4, 3, texels, filter, wrap, to_uv).unwrap())
    }

    #[test]
    fn the_unit_square_mean_of_a_bitmap_is_its_texel_mean() {
        // Two triangles covering [0, 1]²: a repeated bilinear image and a nearest one both
        // average to the texels' mean (bilinear wraps around, weighting every texel alike).
        for filter in [FilterType::Bilinear, FilterType::Nearest] {
            let t = bitmap(filter, WrapMode::Repeat, UvTransform::IDENTITY);
            let (a, b, c, d) = (Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y);
            let m = (mean(&t, [a, b, c]) + mean(&t, [a, c, d])) * 0.5;
            let Texture::Bitmap(bm) = &t else { unreachable!() };
            let want = bm.texels().iter().fold(Rgb::ZERO, |s, x| s + *x) / 12.0;
            assert!((m - want).abs().max_element() < 1e-5, "{filter:?}: {m} vs {want}");
        }
    }

    #[test]
    fn a_checkerboard_of_two_colours_averages_them_on_whole_periods() {
        let c = Texture::Checkerboard(
            Checkerboard::new(Rgb::new(1.0, 0.0, 2.0), Rgb::new(0.0, 3.0, 0.0), UvTransform::IDENTITY)
                .unwrap(),
        );
        let (a, b, cc, d) = (Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y);
        let m = (mean(&c, [a, b, cc]) + mean(&c, [a, cc, d])) * 0.5;
        assert!((m - Rgb::new(0.5, 1.5, 1.0)).abs().max_element() < 1e-6, "{m}");
        // The lower-left triangle of one square [0, ½]²: color0 only.
        let m = mean(&c, [Vec2::ZERO, Vec2::new(0.5, 0.0), Vec2::new(0.0, 0.5)]);
        assert!((m - Rgb::new(1.0, 0.0, 2.0)).abs().max_element() < 1e-6, "{m}");
    }

    #[test]
    fn arbitrary_triangles_agree_with_a_brute_force_mean() {
        let to_uv = UvTransform([[1.3, 0.4, 0.1], [-0.2, 0.9, 0.3]]);
        let tris = [
            [Vec2::new(0.1, 0.2), Vec2::new(0.9, 0.35), Vec2::new(0.3, 0.95)],
            [Vec2::new(-0.7, 0.2), Vec2::new(1.6, -0.4), Vec2::new(0.2, 2.1)],
            [Vec2::new(0.4, 0.4), Vec2::new(0.45, 0.41), Vec2::new(0.42, 0.47)], // inside few cells
            [Vec2::new(0.1, 0.1), Vec2::new(0.5, 0.5), Vec2::new(0.9, 0.9)],     // degenerate: a segment
        ];
        let textures = [
            bitmap(FilterType::Bilinear, WrapMode::Repeat, to_uv),
            bitmap(FilterType::Bilinear, WrapMode::Mirror, UvTransform::IDENTITY),
            bitmap(FilterType::Nearest, WrapMode::Clamp, to_uv),
            Texture::Checkerboard(
                Checkerboard::new(Rgb::splat(4.0), Rgb::new(0.5, 1.0, 0.0), to_uv).unwrap(),
            ),
        ];
        for t in &textures {
            for uv in tris {
                let (m, b) = (mean(t, uv), brute(t, uv));
                // The brute force's own error: discontinuities and curvature over a 600-grid.
                assert!(
                    (m - b).abs().max_element() < 3e-3 * b.max_element().max(1.0),
                    "{t:?} {uv:?}: {m} vs {b}"
                );
            }
        }
    }

    #[test]
    fn a_texture_repeated_too_often_is_refused() {
        let t =
            bitmap(FilterType::Nearest, WrapMode::Repeat, UvTransform([[1e4, 0.0, 0.0], [0.0, 1e4, 0.0]]));
        let r = triangle_mean(&t, [Vec2::ZERO, Vec2::X, Vec2::Y], &mut 0);
        assert_eq!(r, Err(MeanError::TooManyCells));
    }
}
