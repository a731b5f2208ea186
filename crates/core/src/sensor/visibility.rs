//! The visibility buffer: which stored samples a pinhole camera sees, answered for most of
//! them without a shadow ray (issue 25, design change 4: every splat's shadow ray ends at the
//! same point, the eye, so their answers can be shared).
//!
//! **What it holds.** Per pixel of the camera's image, the one triangle T that alone is seen
//! through that pixel, or nothing. T qualifies for pixel p when
//! 1. T's projection covers p's square grown by a margin m on every side (the *footprint*);
//! 2. every other triangle whose projection meets the footprint lies strictly behind T along
//!    every ray of the footprint (its plane's inverse depth, an affine function of the image
//!    point, is below T's at every corner, by a relative 10⁻⁴ and by twice the largest push of a
//!    shadow ray's origin in depth);
//! 3. T is not masked (stochastic opacity, `Scene::meets`), and is at least `z_near` in front of
//!    the eye over the footprint.
//!
//! **Why the answer is the shadow ray's.** A sample x on triangle U projects to a point of some
//! pixel p; the segment from the eye to x projects to that one point. If p holds T: when U = T,
//! everything else that the segment could cross lies behind T, so nothing blocks it — visible;
//! when U ≠ T, U meets the footprint (x is on it), so U lies behind T, and the segment crosses T
//! (which covers the footprint with margin) before x — hidden. The shadow ray starts not at x but
//! at x pushed off its surface (`offset_ray_origin`, at most a few hundred float steps); the
//! margin m is chosen so that this push stays inside the footprint for every T at least `z_near`
//! away (module constant [`MARGIN_PX`]), and the relative depth gap of condition 2 keeps the
//! pushed origin on the same side of every plane. Pixels without such a T (silhouettes, small
//! triangles, masks, anything near the eye) answer "unknown", and the caller traces the shadow
//! ray as before. The tests check that every known answer equals the shadow ray's (the Cornell
//! box, and random cameras in a cloud of triangles, half the points within a hair of an edge)
//! and that renders with and without the buffer are the same bit for bit; they fail without the
//! occluder check of condition 2. They find no case that the margins decide: those follow from
//! the argument above, not from a failing test.
//!
//! **Cost.** Building it rasterises every triangle once per pass (two passes, row by row over a
//! convex polygon's exact row span, in f64); a lookup is a projection and one 4-byte read. Only
//! pinhole cameras have one (a lens or a 360° camera has no single eye; the orthographic camera
//! could, but is rare).

use super::Pinhole;
use crate::math::Vec3;
use crate::scene::Scene;

/// How much a pixel's square is grown on every side, in pixels (module docs).
const MARGIN_PX: f64 = 0.25;

/// The relative gap in inverse depth by which another triangle must lie behind T.
const DEPTH_GAP: f64 = 1e-4;

/// No triangle alone is seen through the pixel.
const NONE: u32 = u32::MAX;

/// What the buffer says about a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Seen {
    /// The eye sees it: no shadow ray is needed.
    Visible,
    /// Something is in front of it.
    Hidden,
    /// The buffer does not know: trace the shadow ray.
    Unknown,
}

/// Per pixel, the triangle seen alone through it (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct VisibilityBuffer {
    camera: Pinhole,
    front: Vec<u32>,
}

impl VisibilityBuffer {
    /// The buffer of `camera` in `scene`, or `None` when it could not know anything (the eye
    /// inside the scene's geometry's reach of float error).
    pub fn build(scene: &Scene, camera: &Pinhole) -> Option<VisibilityBuffer> {
        let raster = Projection::new(scene, camera)?;
        let (w, h) = (raster.size[0], raster.size[1]);
        let mut front = vec![NONE; w * h];
        let mut front_inv_z = vec![0.0f64; w * h];
        // Pass 1: per pixel the nearest unmasked triangle covering its footprint.
        for (t, tri) in scene.triangles.iter().enumerate() {
            if scene.is_masked(t as u32) {
                continue;
            }
            let Some(poly) = raster.polygon(tri.v0, tri.v0 + tri.e1, tri.v0 + tri.e2)? else { continue };
            let Some(plane) = poly.plane else { continue };
            if poly.hi[0] - poly.lo[0] < 1.0 + 2.0 * MARGIN_PX
                || poly.hi[1] - poly.lo[1] < 1.0 + 2.0 * MARGIN_PX
            {
                continue; // too small to cover a footprint
            }
            raster.rows(&poly, |j, _, covered| {
                for i in covered {
                    let p = j * w + i;
                    let (lo, hi) = raster.inv_z_range(&plane, i, j);
                    // In front of the eye by z_near at every corner, and nearer than the best so far.
                    if lo > 0.0 && hi < raster.inv_z_near && lo > front_inv_z[p] {
                        front[p] = t as u32;
                        front_inv_z[p] = lo;
                    }
                }
            })?;
        }
        // Pass 2: every other triangle meeting a footprint must lie strictly behind its T.
        for (t, tri) in scene.triangles.iter().enumerate() {
            let t = t as u32;
            let Some(poly) = raster.polygon(tri.v0, tri.v0 + tri.e1, tri.v0 + tri.e2)? else { continue };
            raster.rows(&poly, |j, meets, _| {
                for i in meets {
                    let p = j * w + i;
                    if front[p] == NONE || front[p] == t {
                        continue;
                    }
                    let behind = match &poly.plane {
                        Some(plane) => raster.inv_z_range(plane, i, j).1 < raster.behind(front_inv_z[p]),
                        None => false, // seen edge-on: its depth is unknown here
                    };
                    if !behind {
                        front[p] = NONE;
                    }
                }
            })?;
        }
        Some(VisibilityBuffer { camera: *camera, front })
    }

    /// Whether the eye sees point `x` of triangle `prim` (a stored sample's position and
    /// triangle).
    #[inline]
    pub fn seen(&self, x: Vec3, prim: u32) -> Seen {
        match self.pixel(x - self.camera.eye) {
            Some(p) => self.seen_at(p, prim),
            None => Seen::Unknown,
        }
    }

    /// [`VisibilityBuffer::seen`] for a point already projected to full-film coordinates
    /// (s_x, s_y) (as the pinhole's filtered connection gives them, `Sensor::film_hit`).
    #[inline]
    pub fn seen_on_film(&self, (sx, sy): (f32, f32), prim: u32) -> Seen {
        match self.film_pixel(sx, sy) {
            Some(p) => self.seen_at(p, prim),
            None => Seen::Unknown,
        }
    }

    /// [`VisibilityBuffer::seen`] for a point already projected to image pixel `pixel`
    /// (row-major in the image, as the pinhole's box connection gives it).
    #[inline]
    pub fn seen_at(&self, pixel: usize, prim: u32) -> Seen {
        match self.front.get(pixel) {
            Some(&t) if t == prim => Seen::Visible,
            Some(&t) if t != NONE => Seen::Hidden,
            _ => Seen::Unknown,
        }
    }

    /// Hints that [`seen_at`](Self::seen_at) will soon be asked about `pixel` (no effect on any
    /// answer).
    #[inline(always)]
    pub fn prefetch(&self, pixel: usize) {
        if let Some(t) = self.front.get(pixel) {
            crate::math::prefetch(t);
        }
    }

    /// The triangle a ray from `origin` along `dir` hits first, if the buffer knows it: `origin`
    /// must be the eye itself (a camera path's first ray), and the ray's pixel must hold a front
    /// triangle (everything else along it lies behind).
    #[inline]
    pub fn front(&self, origin: Vec3, dir: Vec3) -> Option<u32> {
        if origin != self.camera.eye {
            return None;
        }
        let t = self.front[self.pixel(dir)?];
        (t != NONE).then_some(t)
    }

    /// The image pixel that offset `v` from the eye (a point's, or a direction) projects to,
    /// by the pinhole's own arithmetic; `None` behind the eye or outside the image.
    #[inline]
    fn pixel(&self, v: Vec3) -> Option<usize> {
        let c = &self.camera;
        let z = v.dot(c.forward);
        if !(z > 0.0) {
            return None;
        }
        let sx = 0.5 * (v.dot(c.right) / (z * c.tan_x) + 1.0);
        let sy = 0.5 * (1.0 - v.dot(c.up) / (z * c.tan_y));
        self.film_pixel(sx, sy)
    }

    /// The image pixel of full-film coordinates (s_x, s_y); `None` outside the image.
    #[inline]
    fn film_pixel(&self, sx: f32, sy: f32) -> Option<usize> {
        let c = &self.camera;
        let window = c.raster.window;
        let px = sx * c.width as f32 - window.x as f32;
        let py = sy * c.height as f32 - window.y as f32;
        if !(px >= 0.0 && py >= 0.0 && px < window.width as f32 && py < window.height as f32) {
            return None;
        }
        Some(py as usize * window.width as usize + px as usize)
    }

    /// Per image pixel, whether a camera ray through its square grown by `grow` whole pixels
    /// (and the buffer's margin) may first meet a triangle `t` with `flagged(t)` — conservatively:
    /// every such triangle flags every pixel whose footprint its projection meets, whether or not
    /// something hides it — or, when `escapes`, whether it may leave the scene (no triangle known
    /// to cover the footprint). So an unflagged pixel's camera rays all first hit triangles that
    /// are not flagged (`bidirectional::allocation`). `None` when the buffer cannot tell (a
    /// flagged triangle between the eye and its clipping depth).
    pub fn pixels_meeting(
        &self,
        scene: &Scene,
        flagged: impl Fn(u32) -> bool,
        grow: usize,
        escapes: bool,
    ) -> Option<Vec<bool>> {
        let raster = Projection::new(scene, &self.camera)?;
        let (w, h) = (raster.size[0], raster.size[1]);
        let mut flags: Vec<bool> = self.front.iter().map(|&t| escapes && t == NONE).collect();
        for (t, tri) in scene.triangles.iter().enumerate() {
            if !flagged(t as u32) {
                continue;
            }
            let Some(poly) = raster.polygon(tri.v0, tri.v0 + tri.e1, tri.v0 + tri.e2)? else { continue };
            raster.rows(&poly, |j, meets, _| {
                for i in meets {
                    flags[j * w + i] = true;
                }
            })?;
        }
        if grow > 0 {
            // Dilate by `grow` pixels: rows, then columns (a square's maximum is separable).
            let mut rows = vec![false; w * h];
            for j in 0..h {
                for i in 0..w {
                    rows[j * w + i] = flags[j * w + i.saturating_sub(grow)..j * w + (i + grow + 1).min(w)]
                        .iter()
                        .any(|&f| f);
                }
            }
            for j in 0..h {
                for i in 0..w {
                    flags[j * w + i] =
                        (j.saturating_sub(grow)..(j + grow + 1).min(h)).any(|k| rows[k * w + i]);
                }
            }
        }
        Some(flags)
    }

    /// The share of pixels whose answers are known (for reports and tests).
    pub fn known_fraction(&self) -> f64 {
        self.front.iter().filter(|&&t| t != NONE).count() as f64 / self.front.len().max(1) as f64
    }
}

/// A triangle in camera space, clipped in front of the eye and projected to pixel coordinates.
struct Polygon {
    /// Vertices in pixel coordinates (x right, y down), convex, in order: the first `n` of 4.
    corners: [[f64; 2]; 4],
    n: usize,
    /// Its bounding box: x from `lo[0]` to `hi[0]`, y from `lo[1]` to `hi[1]`.
    lo: [f64; 2],
    hi: [f64; 2],
    /// The inverse depth 1/z as an affine function of the pixel point (a, b, c: a·x + b·y + c),
    /// or `None` when the triangle's plane passes through the eye (seen edge-on).
    plane: Option<[f64; 3]>,
}

/// The camera's projection onto the image's pixels in f64, with the margins of the module
/// docs (not `crate::sensor::Raster`, the film's window and filter).
struct Projection {
    eye: [f64; 3],
    axes: [[f64; 3]; 3], // right, up, forward
    /// Pixels per unit of x/z and of y/z.
    scale: [f64; 2],
    /// Where the view axis meets the image, in the image's pixel coordinates (the full film's
    /// centre, moved by the crop window's corner).
    center: [f64; 2],
    /// The image (the crop window): the buffer's pixels are the image's.
    size: [usize; 2],
    /// Triangles are clipped at this depth; one wholly in front of it (but in front of the eye)
    /// makes the buffer give up.
    z_clip: f64,
    /// The largest distance a shadow ray's origin is pushed off its surface.
    push: f64,
    /// 1 / z_near: a T must be farther than z_near over its footprint.
    inv_z_near: f64,
}

impl Projection {
    fn new(scene: &Scene, c: &Pinhole) -> Option<Projection> {
        let f = |v: Vec3| [v.x as f64, v.y as f64, v.z as f64];
        let eye = f(c.eye);
        let axes = [f(c.right), f(c.up), f(c.forward)];
        let scale = [c.width as f64 / (2.0 * c.tan_x as f64), c.height as f64 / (2.0 * c.tan_y as f64)];
        // The largest push of a shadow ray's origin off its surface (`offset_ray_origin`): 256
        // float steps of the largest coordinate per axis, or 2^-16 near zero; twice that, seen
        // from z_near, must stay within the margin.
        let mut largest = c.eye.abs().max_element() as f64;
        for t in &scene.triangles {
            for v in [t.v0, t.v0 + t.e1, t.v0 + t.e2] {
                largest = largest.max(v.abs().max_element() as f64);
            }
        }
        if !largest.is_finite() {
            return None;
        }
        let push = 3f64.sqrt() * (256.0 * largest * f32::EPSILON as f64).max(1.0 / 65536.0);
        // A push moves the projection by at most push·scale·(1 + |x/z| + |y/z|)/z pixels.
        let spread = 1.0 + c.tan_x as f64 + c.tan_y as f64;
        let z_near = 2.0 * push * scale[0].max(scale[1]) * spread / MARGIN_PX;
        let window = c.raster.window;
        Some(Projection {
            eye,
            axes,
            scale,
            center: [0.5 * c.width as f64 - window.x as f64, 0.5 * c.height as f64 - window.y as f64],
            size: [window.width as usize, window.height as usize],
            z_clip: z_near * 1e-3,
            push,
            inv_z_near: 1.0 / z_near,
        })
    }

    /// The inverse depth another triangle must stay below, over a footprint whose T has least
    /// inverse depth `front`: behind T by a relative [`DEPTH_GAP`] and by twice the push in
    /// depth (so a pushed origin of a sample behind T stays behind it, and one on T in front
    /// of everything else).
    #[inline]
    fn behind(&self, front: f64) -> f64 {
        (front * (1.0 - DEPTH_GAP)).min(1.0 / (1.0 / front + 2.0 * self.push))
    }

    /// The triangle (a, b, c) in pixel coordinates, clipped to z ≥ z_clip: `Some(None)` if
    /// nothing of it is in front of the eye, `None` if it lies wholly between the eye and
    /// z_clip (the buffer then gives up).
    fn polygon(&self, a: Vec3, b: Vec3, c: Vec3) -> Option<Option<Polygon>> {
        let cam = |v: Vec3| {
            let d = [v.x as f64 - self.eye[0], v.y as f64 - self.eye[1], v.z as f64 - self.eye[2]];
            self.axes.map(|ax| ax[0] * d[0] + ax[1] * d[1] + ax[2] * d[2])
        };
        let (a, b, c) = (cam(a), cam(b), cam(c));
        // Clip against z ≥ z_clip (Sutherland–Hodgman, one plane).
        let (mut clipped, mut count) = ([[0.0f64; 3]; 4], 0);
        let tri = [a, b, c];
        for k in 0..3 {
            let (p, q) = (tri[k], tri[(k + 1) % 3]);
            let (pin, qin) = (p[2] >= self.z_clip, q[2] >= self.z_clip);
            if pin {
                clipped[count] = p;
                count += 1;
            }
            if pin != qin {
                let s = (self.z_clip - p[2]) / (q[2] - p[2]);
                clipped[count] = [p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]), self.z_clip];
                count += 1;
            }
        }
        if count < 3 {
            let in_front = a[2] > 0.0 || b[2] > 0.0 || c[2] > 0.0;
            return if in_front { None } else { Some(None) };
        }
        let (mut corners, mut lo, mut hi) = ([[0.0f64; 2]; 4], [f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for k in 0..count {
            let p = clipped[k];
            let q =
                [self.center[0] + p[0] / p[2] * self.scale[0], self.center[1] - p[1] / p[2] * self.scale[1]];
            corners[k] = q;
            for a in 0..2 {
                lo[a] = lo[a].min(q[a]);
                hi[a] = hi[a].max(q[a]);
            }
        }
        // Nothing of it near the image: no footprint can meet it.
        let reach = MARGIN_PX + 1.0;
        if hi[0] < -reach
            || hi[1] < -reach
            || lo[0] > self.size[0] as f64 + reach
            || lo[1] > self.size[1] as f64 + reach
        {
            return Some(None);
        }
        // The plane n·P = d in camera space; along the ray through pixel point (x, y),
        // P = z·((x − c_x)/sx, (c_y − y)/sy, 1) (c the centre), so 1/z = n·that / d, affine in
        // (x, y).
        let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
        let d = n[0] * a[0] + n[1] * a[1] + n[2] * a[2];
        let scale_n = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let reach =
            [a, b, c].iter().map(|p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()).fold(0.0, f64::max);
        let plane = (d.abs() > 1e-9 * scale_n * reach).then(|| {
            let (ax, ay) = (n[0] / (self.scale[0] * d), -n[1] / (self.scale[1] * d));
            let c0 = n[2] / d - ax * self.center[0] - ay * self.center[1];
            [ax, ay, c0]
        });
        Some(Some(Polygon { corners, n: count, lo, hi, plane }))
    }

    /// The least and greatest inverse depth of `plane` over pixel (i, j)'s footprint (an affine
    /// function's extremes over a square are at its corners).
    #[inline]
    fn inv_z_range(&self, plane: &[f64; 3], i: usize, j: usize) -> (f64, f64) {
        let (cx, cy) = (i as f64 + 0.5, j as f64 + 0.5);
        let mid = plane[0] * cx + plane[1] * cy + plane[2];
        let spread = (plane[0].abs() + plane[1].abs()) * (0.5 + MARGIN_PX);
        (mid - spread, mid + spread)
    }

    /// For every image row j the polygon's footprints reach: the pixels whose footprint it
    /// meets and those whose footprint it covers (each a range of column indices, possibly
    /// empty). `None` (and the caller gives up the buffer) never happens for finite input; the
    /// `Option` lets the closure's `?` stay out of the hot loop.
    fn rows(
        &self,
        poly: &Polygon,
        mut each: impl FnMut(usize, std::ops::Range<usize>, std::ops::Range<usize>),
    ) -> Option<()> {
        let m = MARGIN_PX;
        let (w, h) = (self.size[0] as f64, self.size[1] as f64);
        let (y_lo, y_hi) = (poly.lo[1], poly.hi[1]);
        if !(y_lo.is_finite() && y_hi.is_finite() && poly.lo[0].is_finite() && poly.hi[0].is_finite()) {
            return None;
        }
        let points = &poly.corners[..poly.n];
        let col = |x: f64| x.clamp(0.0, w) as usize;
        let row = |y: f64| y.clamp(0.0, h) as usize;
        if poly.hi[0] - poly.lo[0] < 1.0 + 2.0 * m && poly.hi[1] - poly.lo[1] < 1.0 + 2.0 * m {
            // Smaller than a footprint (most triangles of a fine mesh): it covers none, and the
            // footprints its bounding box meets stand for those it meets.
            let meets = col((poly.lo[0] - 1.0 - m).ceil())..col((poly.hi[0] + m).floor() + 1.0);
            for j in row((y_lo - 1.0 - m).ceil())..row((y_hi + m).floor() + 1.0) {
                each(j, meets.clone(), 0..0);
            }
            return Some(());
        }
        let j0 = (y_lo - m - 1.0).floor().clamp(0.0, h) as usize;
        let j1 = (y_hi + m + 1.0).floor().clamp(0.0, h) as usize; // exclusive after clamping
        for j in j0..j1.min(self.size[1]) {
            let (top, bottom) = (j as f64 - m, j as f64 + 1.0 + m);
            // Columns whose grown square meets the polygon: its x extent within the band.
            let Some((x_lo, x_hi)) = band_extent(points, top, bottom) else { continue };
            let meets = col((x_lo - 1.0 - m).ceil())..col((x_hi + m).floor() + 1.0);
            // Columns whose grown square lies inside: both of the band's edges' chords contain it.
            let covered = match (chord(points, top), chord(points, bottom)) {
                (Some((l0, r0)), Some((l1, r1))) => {
                    let (l, r) = (l0.max(l1), r0.min(r1));
                    let tol = 1e-9 * (w + h);
                    col((l + m + tol).ceil())
                        ..col((r - 1.0 - m - tol).floor() + 1.0).max(col((l + m + tol).ceil()))
                }
                _ => 0..0,
            };
            each(j, meets, covered);
        }
        Some(())
    }
}

/// The x extent of a convex polygon's part between the lines y = top and y = bottom.
fn band_extent(points: &[[f64; 2]], top: f64, bottom: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let n = points.len();
    for k in 0..n {
        let (p, q) = (points[k], points[(k + 1) % n]);
        if p[1] >= top && p[1] <= bottom {
            lo = lo.min(p[0]);
            hi = hi.max(p[0]);
        }
        for y in [top, bottom] {
            if (p[1] - y) * (q[1] - y) < 0.0 {
                let x = p[0] + (y - p[1]) / (q[1] - p[1]) * (q[0] - p[0]);
                lo = lo.min(x);
                hi = hi.max(x);
            }
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// Where the line y = `y` crosses a convex polygon: its [left, right] chord, if it does.
fn chord(points: &[[f64; 2]], y: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let n = points.len();
    for k in 0..n {
        let (p, q) = (points[k], points[(k + 1) % n]);
        if p[1] == y {
            lo = lo.min(p[0]);
            hi = hi.max(p[0]);
        }
        if (p[1] - y) * (q[1] - y) < 0.0 {
            let x = p[0] + (y - p[1]) / (q[1] - p[1]) * (q[0] - p[0]);
            lo = lo.min(x);
            hi = hi.max(x);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::{Bsdf, Lambert, Material};
    use crate::film::Film;
    use crate::math::Rgb;
    use crate::sampling::RandomStream;
    use crate::scene::{CameraDesc, CameraKind, MeshDesc, PointLightDesc, SceneDescription, cornell_box};
    use crate::sensor::{SampleBatch, Sensor, sees, splat};

    /// Every answer the buffer knows for `points` random points on the scene's triangles is the
    /// shadow ray's; returns the share it knew.
    fn agrees_with_shadow_rays(scene: &Scene, camera: &Pinhole, points: usize, seed: u64) -> f64 {
        let Some(buffer) = VisibilityBuffer::build(scene, camera) else { return 0.0 };
        let mut rng = RandomStream::new(seed, &[0x0076_6973]);
        let (mut known, mut tried) = (0usize, 0usize);
        for _ in 0..points {
            let t = ((rng.next_f32() * scene.triangles.len() as f32) as usize).min(scene.triangles.len() - 1);
            let tri = &scene.triangles[t];
            let (mut u, mut v) = (rng.next_f32(), rng.next_f32());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            // Half the points within a hair of an edge, where silhouettes and contacts are.
            if rng.next_f32() < 0.5 {
                u *= 1e-4;
            }
            let x = tri.snap(tri.v0 + u * tri.e1 + v * tri.e2);
            let answer = buffer.seen(x, t as u32);
            if answer == Seen::Unknown || camera.project(x).is_none() {
                continue;
            }
            tried += 1;
            let wc = (camera.eye - x).normalize();
            let traced = sees(scene, x, scene.normal(t as u32), wc, camera.eye);
            assert_eq!(
                answer == Seen::Visible,
                traced,
                "triangle {t} at {x:?}: buffer {answer:?}, shadow ray {traced}"
            );
            known += 1;
        }
        assert!(tried > 0 || known == 0);
        known as f64 / points as f64
    }

    fn quad(m: &mut MeshDesc, p: [Vec3; 4]) {
        let i = m.positions.len() as u32;
        m.positions.extend(p);
        m.triangles.extend([[i, i + 1, i + 2], [i, i + 2, i + 3]]);
    }

    /// A floor, two walls and a cloud of 400 small triangles in front of them: silhouettes,
    /// overlaps and triangles crossing the camera's plane everywhere.
    fn clutter() -> Scene {
        let mut walls = MeshDesc { name: "walls".into(), ..Default::default() };
        let v = Vec3::new;
        quad(&mut walls, [v(-4., 0., 4.), v(4., 0., 4.), v(4., 0., -4.), v(-4., 0., -4.)]);
        quad(&mut walls, [v(-4., 0., -4.), v(4., 0., -4.), v(4., 3., -4.), v(-4., 3., -4.)]);
        quad(&mut walls, [v(-4., 0., 4.), v(-4., 0., -4.), v(-4., 3., -4.), v(-4., 3., 4.)]);
        let mut cloud = MeshDesc { name: "cloud".into(), ..Default::default() };
        let mut rng = RandomStream::new(7, &[1]);
        for _ in 0..400 {
            let c = v(rng.next_f32() * 7.0 - 3.5, rng.next_f32() * 2.8 + 0.1, rng.next_f32() * 7.0 - 3.5);
            let i = cloud.positions.len() as u32;
            for _ in 0..3 {
                let r = v(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5);
                cloud.positions.push(c + 0.6 * r);
            }
            cloud.triangles.push([i, i + 1, i + 2]);
        }
        let grey = Material {
            name: "grey".into(),
            bsdf: Bsdf::Lambert(Lambert::new(Rgb::splat(0.5)).unwrap()),
            two_sided: true,
        };
        let bulb = PointLightDesc {
            name: "bulb".into(),
            position: v(0., 2.5, 0.),
            intensity: Rgb::ONE,
            ..Default::default()
        };
        let desc = SceneDescription {
            materials: vec![grey],
            meshes: vec![walls, cloud],
            point_lights: vec![bulb],
            ..Default::default()
        };
        Scene::build(&desc).unwrap()
    }

    fn camera(eye: Vec3, target: Vec3, fov: f32, width: u32, height: u32) -> Pinhole {
        let d = CameraDesc {
            eye,
            target,
            up: Vec3::Y,
            fov_x_degrees: fov,
            width,
            height,
            kind: CameraKind::Perspective,
            film: Default::default(),
        };
        Pinhole::new(&d).unwrap()
    }

    /// The Cornell box through its own camera: most of the image is known, and every known
    /// answer is the shadow ray's.
    #[test]
    fn the_cornell_box_is_mostly_known_and_always_right() {
        let desc = cornell_box();
        let scene = Scene::build(&desc).unwrap();
        let cam = Pinhole::new(&desc.camera.unwrap()).unwrap();
        let buffer = VisibilityBuffer::build(&scene, &cam).unwrap();
        assert!(buffer.known_fraction() > 0.8, "known {}", buffer.known_fraction());
        let known = agrees_with_shadow_rays(&scene, &cam, 200_000, 1);
        assert!(known > 0.3, "known for {known} of the points");
    }

    /// Random cameras in a cluttered room — inside the cloud, close to walls, wide and narrow
    /// fields of view: never a wrong answer.
    #[test]
    fn random_cameras_in_clutter_never_disagree_with_shadow_rays() {
        let scene = clutter();
        let mut rng = RandomStream::new(11, &[2]);
        let mut known = 0.0;
        for k in 0..24 {
            let eye =
                Vec3::new(rng.next_f32() * 7.6 - 3.8, rng.next_f32() * 2.8 + 0.1, rng.next_f32() * 7.6 - 3.8);
            let target =
                Vec3::new(rng.next_f32() * 8.0 - 4.0, rng.next_f32() * 3.0, rng.next_f32() * 8.0 - 4.0);
            let fov = [20.0, 60.0, 100.0, 150.0][k % 4];
            let cam = camera(eye, target, fov, 48 + k as u32, 40);
            known += agrees_with_shadow_rays(&scene, &cam, 20_000, k as u64);
        }
        assert!(known / 24.0 > 0.02, "the buffer knew {} of the points on average", known / 24.0);
    }

    /// The light estimator's image with the buffer is the one without it, bit for bit, on the
    /// whole film and in a crop window (the buffer's pixels are the window's), box-filtered (the
    /// pixel the connection found) and gaussian-filtered (the buffer's own projection).
    #[test]
    fn splats_with_the_buffer_are_the_same_image() {
        use crate::sensor::{Crop, FilmSpec, Filter};
        let desc = cornell_box();
        let scene = Scene::build(&desc).unwrap();
        let traced = crate::dataset::testing::trace_into(&scene, 20_000, 5);
        let crop = Some(Crop { x: 37, y: 90, width: 150, height: 101 });
        let films = [
            FilmSpec::default(),
            FilmSpec { crop, ..Default::default() },
            FilmSpec { crop, filter: Filter::Gaussian { stddev: 0.5 } },
        ];
        for film in films {
            let camera = CameraDesc { film, ..desc.camera.unwrap() };
            let sensor: Sensor = Pinhole::new(&camera).unwrap().into();
            let buffer = sensor.visibility(&scene).unwrap();
            let (w, h) = (sensor.width(), sensor.height());
            let (mut with, mut without) = (Film::new(w, h), Film::new(w, h));
            for c in &traced.chunks {
                let batch = SampleBatch { flux_per_path: Rgb::ONE, samples: &c.samples };
                splat(&scene, &sensor, Some(&buffer), batch, &mut with);
                splat(&scene, &sensor, None, batch, &mut without);
            }
            assert!(with.mean()[0] > 0.0, "{film:?}");
            assert_eq!(with.pixels, without.pixels, "{film:?}");
        }
    }
}
