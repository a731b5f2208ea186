//! Ray queries over the scene's triangles: closest hit and occlusion.
//!
//! The hierarchy is obvhs's compressed wide BVH (CWBVH, 8-wide, PLOC build with reinsertion
//! optimisation): a maintained crate with SIMD CPU traversal, so we do not write our own.
//! Triangles are stored in BVH leaf order for cache locality; `order` maps back to scene indices.

use crate::geometry::Ray;
use crate::math::{Vec3, Vec3A};
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray as BvhRay, RayHit};
use obvhs::rt_triangle::RtTriangle;
use obvhs::triangle::Triangle as BvhTriangle;
use obvhs::{BvhBuildParams, cwbvh::builder::build_cwbvh_from_tris};
use std::time::Duration;

/// A BVH over a fixed set of triangles.
pub struct Accel {
    bvh: CwBvh,
    /// Triangles in BVH order, in the layout obvhs intersects fastest.
    tris: Vec<RtTriangle>,
    /// BVH slot → scene triangle index.
    order: Vec<u32>,
}

impl std::fmt::Debug for Accel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Accel").field("triangles", &self.tris.len()).finish()
    }
}

impl Accel {
    /// Builds the BVH over triangles given as vertex triples (scene order). Needs at least one.
    pub fn build(triangles: &[[Vec3; 3]]) -> Self {
        let input: Vec<BvhTriangle> = triangles
            .iter()
            .map(|t| BvhTriangle { v0: t[0].into(), v1: t[1].into(), v2: t[2].into() })
            .collect();
        let bvh = build_cwbvh_from_tris(&input, BvhBuildParams::medium_build(), &mut Duration::default());
        let order = bvh.primitive_indices.clone();
        let tris = order.iter().map(|&i| RtTriangle::from(&input[i as usize])).collect();
        Accel { bvh, tris, order }
    }

    /// Closest hit along `ray` within [0, t_max]: distance and scene triangle index.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<(f32, u32)> {
        let r = bvh_ray(ray);
        let mut hit = RayHit::none();
        let tris = &self.tris;
        if self.bvh.ray_traverse(r, &mut hit, |r, id| tris[id].intersect(r)) {
            Some((hit.t, self.order[hit.primitive_id as usize]))
        } else {
            None
        }
    }

    /// Whether anything blocks the open segment (0, t_max) of `ray`.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let r = bvh_ray(ray);
        let tris = &self.tris;
        !self.bvh.ray_traverse_miss(r, |r, id| tris[id].intersect(r))
    }
}

/// The obvhs ray for `ray`. Negative zeros in the direction become positive zeros: obvhs picks
/// the slab order from `dir < 0` but inverts -0.0 to a huge *negative* number, and the mismatch
/// makes axis-aligned rays such as `-Vec3::Y` miss everything (regression test below).
#[inline]
fn bvh_ray(ray: &Ray) -> BvhRay {
    BvhRay::new(Vec3A::from(ray.origin), Vec3A::from(ray.dir) + Vec3A::ZERO, 0.0, ray.t_max)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(y: f32) -> [[Vec3; 3]; 2] {
        let (a, b, c, d) = (
            Vec3::new(-1.0, y, -1.0),
            Vec3::new(1.0, y, -1.0),
            Vec3::new(1.0, y, 1.0),
            Vec3::new(-1.0, y, 1.0),
        );
        [[a, b, c], [a, c, d]]
    }

    #[test]
    fn closest_hit_and_occlusion() {
        let mut tris = Vec::new();
        tris.extend(quad(0.0));
        tris.extend(quad(2.0));
        let accel = Accel::build(&tris);
        // -Vec3::Y is (-0, -1, -0): the negative zeros used to make obvhs miss.
        let down = Ray { origin: Vec3::new(0.1, 5.0, 0.2), dir: -Vec3::Y, t_max: f32::INFINITY };
        let (t, prim) = accel.intersect(&down).unwrap();
        assert!((t - 3.0).abs() < 1e-5 && prim >= 2, "t={t} prim={prim}");
        let between = Ray { origin: Vec3::new(0.1, 1.0, 0.2), dir: -Vec3::Y, t_max: 0.5 };
        assert!(!accel.occluded(&between));
        assert!(accel.occluded(&Ray { t_max: 1.5, ..between }));
        let miss = Ray { origin: Vec3::new(3.0, 1.0, 0.0), dir: -Vec3::Y, t_max: f32::INFINITY };
        assert!(accel.intersect(&miss).is_none());
    }
}
