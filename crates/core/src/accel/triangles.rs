//! The triangle test, one triangle at a time ([`Tri`]) and four at a time ([`Tri4`]).
//!
//! # Why packets of four
//!
//! A leaf holds up to four triangles ([`super::build::MAX_LEAF`]). Tested one by one, each
//! costs a Möller–Trumbore of ~30 instructions plus the loop's loads and branches; laid out lane
//! by lane (structure of arrays, as Embree's `Triangle4`), one SSE pass tests all four in about
//! the time of one. The packet computes **every lane exactly as [`Tri::intersect`] computes its
//! triangle**: the same operations in the same order — glam's `Vec3A` cross product is
//! `a.y·b.z − a.z·b.y` per component and its dot product `(x·x′ + y·y′) + z·z′`, without fused
//! multiply-adds on the default target, and IEEE lane arithmetic rounds exactly as scalar
//! arithmetic — so distances are bit-identical to the one-at-a-time test, which the brute-force
//! comparisons in `tests.rs` check. Unused lanes hold NaN, which no comparison accepts.

use crate::math::{Vec3, Vec3A, Vec4};

/// A triangle laid out for the intersection test (obvhs's `RtTriangle`): `v0`, `e1 = v0 − v1`,
/// `e2 = v2 − v0`, `ng = e1 × e2`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Tri {
    v0: Vec3A,
    e1: Vec3A,
    e2: Vec3A,
    ng: Vec3A,
}

impl Tri {
    pub(super) fn new(t: &[Vec3; 3]) -> Tri {
        let (v0, v1, v2) = (Vec3A::from(t[0]), Vec3A::from(t[1]), Vec3A::from(t[2]));
        let (e1, e2) = (v0 - v1, v2 - v0);
        Tri { v0, e1, e2, ng: e1.cross(e2) }
    }

    /// Distance to the hit in [0, t_max], or infinity: Möller–Trumbore as obvhs 0.4's
    /// `RtTriangle::intersect` computes it, but with a zero barycentric of either sign inside
    /// (obvhs tests the sign bit, so a `-0.0` counted as outside: a ray meeting the back of two
    /// triangles exactly on their shared edge, where both compute −0, passed between them — a
    /// leak CIE 171's case 5.5 found along a square's diagonal).
    #[inline(always)]
    pub(super) fn intersect(&self, o: Vec3A, d: Vec3A, t_max: f32) -> f32 {
        let c = self.v0 - o;
        let r = d.cross(c);
        let inv_det = 1.0 / self.ng.dot(d);
        let u = r.dot(self.e2) * inv_det;
        let v = r.dot(self.e1) * inv_det;
        let w = 1.0 - u - v;
        if inv_det != 0.0 && u >= 0.0 && v >= 0.0 && w >= 0.0 {
            let t = self.ng.dot(c) * inv_det;
            if t >= 0.0 && t <= t_max {
                return t;
            }
        }
        f32::INFINITY
    }
}

/// Up to four [`Tri`]s, each quantity as three vectors (x, y, z) of one lane per triangle.
#[derive(Clone, Copy, Debug)]
#[repr(align(64))]
pub(super) struct Tri4 {
    v0: [Vec4; 3],
    e1: [Vec4; 3],
    e2: [Vec4; 3],
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
        Tri4 { v0: lanes(&|t| t.v0), e1: lanes(&|t| t.e1), e2: lanes(&|t| t.e2), ng: lanes(&|t| t.ng) }
    }

    /// The triangle in `lane`, for the one-at-a-time queries.
    pub(super) fn lane(&self, lane: usize) -> Tri {
        let v = |a: &[Vec4; 3]| Vec3A::new(a[0][lane], a[1][lane], a[2][lane]);
        Tri { v0: v(&self.v0), e1: v(&self.e1), e2: v(&self.e2), ng: v(&self.ng) }
    }

    /// Per lane, what [`Tri::intersect`] returns for that lane's triangle (infinity in unused
    /// lanes); `o` and `d` are the ray's origin and direction splat per axis.
    #[inline(always)]
    pub(super) fn intersect(&self, o: &[Vec4; 3], d: &[Vec4; 3], t_max: f32) -> Vec4 {
        let c = [self.v0[0] - o[0], self.v0[1] - o[1], self.v0[2] - o[2]];
        let r = [d[1] * c[2] - d[2] * c[1], d[2] * c[0] - d[0] * c[2], d[0] * c[1] - d[1] * c[0]];
        let inv_det = Vec4::ONE / dot(&self.ng, d);
        let u = dot(&r, &self.e2) * inv_det;
        let v = dot(&r, &self.e1) * inv_det;
        let w = Vec4::ONE - u - v;
        let t = dot(&self.ng, &c) * inv_det;
        let inside = inv_det.cmpne(Vec4::ZERO)
            & u.cmpge(Vec4::ZERO)
            & v.cmpge(Vec4::ZERO)
            & w.cmpge(Vec4::ZERO)
            & t.cmpge(Vec4::ZERO)
            & t.cmple(Vec4::splat(t_max));
        Vec4::select(inside, t, Vec4::INFINITY)
    }
}
