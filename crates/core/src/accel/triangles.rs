//! The triangle test, one triangle at a time ([`Tri`]) and four at a time ([`Tri4`]).
//!
//! # Why watertight
//!
//! The test is Woop, Benthin and Wald's watertight ray–triangle intersection ("Watertight
//! Ray/Triangle Intersection", JCGT 2013; pbrt-v4 and Embree's robust mode use it): the
//! vertices are translated to the ray's origin and sheared so that the ray runs along +z
//! ([`Shear`], once per ray), and the 2D edge functions of the projected triangle decide
//! inside. An edge shared by two triangles gets the same edge function, up to sign, from both
//! — the same products of the same sheared coordinates — so a ray meeting it is inside one of
//! them at least (an edge function that rounds to zero is recomputed in f64, where the products
//! of f32 values are exact). Möller–Trumbore, used before, rounds its barycentrics per
//! triangle: rays aimed at a closed room's edges escaped through them (2.8 % of rays aimed at
//! edges and corners, `accel::tests`); CIE 171's façade case found it as a meter direction that
//! left a closed black room through its corner and read the sky, a sample 250 times the mean.
//!
//! The **distance** is still the plane's, as Möller–Trumbore computed it, `ng·(v0 − o) /
//! ng·d` with `ng = (v0 − v1) × (v2 − v0)`, operation for operation: the hierarchy's box test
//! was proven against that rounding (its slack), the sheared distance of the paper rounds worse
//! for triangles far from the origin (the brute-force tests found hits tens of units off beside
//! coordinates of 2³⁰), and every hit both tests accept is where it was, bit for bit (datasets
//! of the Cornell box are byte-identical to the old test's). The price, counted: +12 % of the
//! instructions of `opticks bench` on the Cornell box (the ray queries +31 %), a trace
//! 5–13 % slower (`docs/performance.md`).
//!
//! # Why packets of four
//!
//! A leaf holds up to four triangles ([`super::build::MAX_LEAF`]). Laid out lane by lane
//! (structure of arrays, as Embree's `Triangle4`), one SSE pass tests all four in about the
//! time of one. The packet computes **every lane exactly as [`Tri::intersect`] computes its
//! triangle**: the same operations in the same order, without fused multiply-adds on the
//! default target, and IEEE lane arithmetic rounds exactly as scalar arithmetic — so distances
//! are bit-identical to the one-at-a-time test, which the brute-force comparisons in `tests.rs`
//! check. Unused lanes hold NaN, which no comparison accepts.

use crate::math::{Vec3, Vec3A, Vec4};

/// A ray prepared for the watertight test: z is the axis of the direction's largest
/// component, x and y the other two (in cyclic order: either orientation of the projected
/// triangles is accepted, so no swap keeps their winding), the origin in that order, and the
/// shear (S_x, S_y) = (d_x/d_z, d_y/d_z) that maps the direction to the z axis.
#[derive(Clone, Copy, Debug)]
pub(super) struct Shear {
    /// The world axes of the sheared x, y and z.
    k: [usize; 3],
    /// The origin in that order and (S_x, S_y), each in every lane (the one-at-a-time test
    /// reads lane 0).
    o4: [Vec4; 3],
    s4: [Vec4; 2],
}

impl Shear {
    pub(super) fn new(o: Vec3A, d: Vec3A) -> Shear {
        let a = d.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let k = [(kz + 1) % 3, (kz + 2) % 3, kz];
        let r = 1.0 / d[kz];
        Shear { k, o4: k.map(|i| Vec4::splat(o[i])), s4: [d[k[0]] * r, d[k[1]] * r].map(Vec4::splat) }
    }
}

/// A triangle's vertices and its unnormalised normal `ng = (v0 − v1) × (v2 − v0)`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Tri {
    v: [Vec3A; 3],
    ng: Vec3A,
}

/// Edge functions that rounded to zero, again from the same f32 sheared coordinates in f64,
/// where their products are exact and the difference rounds once: the sign a shared edge
/// gets is then the same from both of its triangles.
#[inline(never)]
#[cold]
fn edges_f64(x: [f32; 3], y: [f32; 3]) -> [f32; 3] {
    let (x, y) = (x.map(f64::from), y.map(f64::from));
    [
        (x[1] * y[2] - y[1] * x[2]) as f32,
        (x[2] * y[0] - y[2] * x[0]) as f32,
        (x[0] * y[1] - y[0] * x[1]) as f32,
    ]
}

impl Tri {
    pub(super) fn new(t: &[Vec3; 3]) -> Tri {
        let v = t.map(Vec3A::from);
        Tri { v, ng: (v[0] - v[1]).cross(v[2] - v[0]) }
    }

    /// Distance to the hit in [0, t_max], or infinity, for the ray from `o` along `d` prepared
    /// as `sh` (module docs: inside by the watertight edge functions, an edge function of zero
    /// of either sign inside; the distance the plane's). Both faces count.
    #[inline(always)]
    pub(super) fn intersect(&self, o: Vec3A, d: Vec3A, sh: &Shear, t_max: f32) -> f32 {
        let [kx, ky, kz] = sh.k;
        let ([ox, oy, oz], [sx, sy]) = (sh.o4.map(|v| v.x), sh.s4.map(|v| v.x));
        let xy = |v: Vec3A| {
            let z = v[kz] - oz;
            ((v[kx] - ox) - sx * z, (v[ky] - oy) - sy * z)
        };
        let [(x0, y0), (x1, y1), (x2, y2)] = self.v.map(xy);
        let (x, y) = ([x0, x1, x2], [y0, y1, y2]);
        let mut e = [x[1] * y[2] - y[1] * x[2], x[2] * y[0] - y[2] * x[0], x[0] * y[1] - y[0] * x[1]];
        if e[0] == 0.0 || e[1] == 0.0 || e[2] == 0.0 {
            e = edges_f64(x, y);
        }
        let negative = e[0] < 0.0 || e[1] < 0.0 || e[2] < 0.0;
        let positive = e[0] > 0.0 || e[1] > 0.0 || e[2] > 0.0;
        let det = (e[0] + e[1]) + e[2];
        let inv = 1.0 / self.ng.dot(d);
        if !(negative && positive) && det != 0.0 && inv != 0.0 {
            let t = self.ng.dot(self.v[0] - o) * inv;
            if t >= 0.0 && t <= t_max {
                return t;
            }
        }
        f32::INFINITY
    }
}

/// Up to four [`Tri`]s: per vertex and for the normal, its x, y and z of one lane per
/// triangle.
#[derive(Clone, Copy, Debug)]
#[repr(align(64))]
pub(super) struct Tri4 {
    v: [[Vec4; 3]; 3],
    ng: [Vec4; 3],
}

/// The dot product of two lane-wise vectors, in `Vec3A::dot`'s order.
#[inline(always)]
fn dot(a: &[Vec4; 3], b: &[Vec4; 3]) -> Vec4 {
    (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2]
}

impl Tri4 {
    /// The packet of `tris` (one to four), its unused lanes NaN.
    pub(super) fn new(tris: &[Tri]) -> Tri4 {
        debug_assert!(!tris.is_empty() && tris.len() <= 4);
        let lanes = |f: &dyn Fn(&Tri) -> Vec3A| -> [Vec4; 3] {
            let mut a = [[f32::NAN; 4]; 3];
            for (l, t) in tris.iter().enumerate() {
                let v = f(t);
                (a[0][l], a[1][l], a[2][l]) = (v.x, v.y, v.z);
            }
            a.map(Vec4::from_array)
        };
        Tri4 { v: [lanes(&|t| t.v[0]), lanes(&|t| t.v[1]), lanes(&|t| t.v[2])], ng: lanes(&|t| t.ng) }
    }

    /// The triangle in `lane`, for the one-at-a-time queries.
    pub(super) fn lane(&self, lane: usize) -> Tri {
        let v = |a: &[Vec4; 3]| Vec3A::new(a[0][lane], a[1][lane], a[2][lane]);
        Tri { v: self.v.each_ref().map(v), ng: v(&self.ng) }
    }

    /// Per lane, what [`Tri::intersect`] returns for that lane's triangle (infinity in unused
    /// lanes); `d` is the ray's direction splat per axis, its origin is in `sh`.
    #[inline(always)]
    pub(super) fn intersect(&self, d: &[Vec4; 3], sh: &Shear, t_max: f32) -> Vec4 {
        // The axes as constants: no index arithmetic in the packet's arithmetic.
        match sh.k[2] {
            0 => self.intersect_along::<1, 2, 0>(d, sh, t_max),
            1 => self.intersect_along::<2, 0, 1>(d, sh, t_max),
            _ => self.intersect_along::<0, 1, 2>(d, sh, t_max),
        }
    }

    /// [`Tri4::intersect`] for a ray sheared along axis `KZ` (`KX`, `KY` the other two).
    #[inline(always)]
    fn intersect_along<const KX: usize, const KY: usize, const KZ: usize>(
        &self,
        d: &[Vec4; 3],
        sh: &Shear,
        t_max: f32,
    ) -> Vec4 {
        // Each vertex relative to the origin (v − o per axis, as the plane's distance needs it
        // for v0), then sheared.
        let rel = |v: &[Vec4; 3]| [v[KX] - sh.o4[0], v[KY] - sh.o4[1], v[KZ] - sh.o4[2]];
        let xy = |r: [Vec4; 3]| (r[0] - sh.s4[0] * r[2], r[1] - sh.s4[1] * r[2]);
        let r0 = rel(&self.v[0]);
        let [(x0, y0), (x1, y1), (x2, y2)] = [xy(r0), xy(rel(&self.v[1])), xy(rel(&self.v[2]))];
        let (x, y) = ([x0, x1, x2], [y0, y1, y2]);
        let mut e = [x[1] * y[2] - y[1] * x[2], x[2] * y[0] - y[2] * x[0], x[0] * y[1] - y[0] * x[1]];
        let zero = e[0].cmpeq(Vec4::ZERO) | e[1].cmpeq(Vec4::ZERO) | e[2].cmpeq(Vec4::ZERO);
        if zero.any() {
            let mut lanes = e.map(|v| v.to_array());
            let (xs, ys) = (x.map(|v| v.to_array()), y.map(|v| v.to_array()));
            let mut m = zero.bitmask();
            while m != 0 {
                let l = m.trailing_zeros() as usize;
                m &= m - 1;
                let f = edges_f64([xs[0][l], xs[1][l], xs[2][l]], [ys[0][l], ys[1][l], ys[2][l]]);
                (lanes[0][l], lanes[1][l], lanes[2][l]) = (f[0], f[1], f[2]);
            }
            e = lanes.map(Vec4::from_array);
        }
        // All three of one sign (zeros of either sign count as both); NaN lanes fail below.
        let same_sign =
            e[0].min(e[1]).min(e[2]).cmpge(Vec4::ZERO) | e[0].max(e[1]).max(e[2]).cmple(Vec4::ZERO);
        let det = (e[0] + e[1]) + e[2];
        let crossed = same_sign & det.cmpne(Vec4::ZERO);
        if !crossed.any() {
            return Vec4::INFINITY; // the plane's distance unneeded
        }
        let inv = Vec4::ONE / dot(&self.ng, d);
        // v0 − o in world axis order (the same subtractions as the one-at-a-time test's).
        let mut c = [Vec4::ZERO; 3];
        (c[KX], c[KY], c[KZ]) = (r0[0], r0[1], r0[2]);
        let t = dot(&self.ng, &c) * inv;
        let inside = crossed & inv.cmpne(Vec4::ZERO) & t.cmpge(Vec4::ZERO) & t.cmple(Vec4::splat(t_max));
        Vec4::select(inside, t, Vec4::INFINITY)
    }
}
