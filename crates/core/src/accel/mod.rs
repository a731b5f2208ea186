//! Ray queries over the scene's triangles: closest hit and occlusion, through a bounding
//! volume hierarchy that provably loses no hit.
//!
//! # Why our own hierarchy
//!
//! Opticks used obvhs 0.4's compressed wide BVH (CWBVH). Fuzzing found that it silently drops
//! geometry, and obvhs checks its trees only with debug assertions on, so release builds
//! rendered wrong images with exit code 0. The causes, all in obvhs:
//!
//! * its node test clamps the ray's start to `t = 1e-4` (`cwbvh::node::EPSILON`), so every hit
//!   nearer than 1e-4 is lost (a scene modelled at millimetre scale, a path in a corner);
//! * child boxes are stored as 8-bit offsets `q` on a grid `e` from the parent's corner `p`
//!   and tested as `(p − o)·(1/d) + q·(e/d)`: with a vertex at y = −2²⁴ in the scene, `p` is
//!   2²⁴ below the ray origin, `p − o` carries an error of an ulp of 2²⁴ (2 units), and the two
//!   terms cancel, so the slab of a flat, unit-sized child lands units away from where the ray
//!   meets it — the quad vanished and 69 % of fuzzed rays missed (the quantisation
//!   itself also rounds `child − p` before taking its floor, which need not be conservative);
//! * `safe_inverse` replaces a direction component below 2⁻²³ by ±2⁻²³, which shrinks slabs;
//! * the traversal stack holds 32 entries and silently overwrites its top when a tree is
//!   deeper (`StackStack::push` clamps its index);
//! * PLOC pairs each node with its cheapest neighbour and breaks ties toward the farthest one,
//!   so identical triangles merge a pair or so per pass: quadratic time (30,000 triangles:
//!   38 s) and a chain-shaped tree that overflows both that stack and the converter's recursion.
//!
//! None of these can be fixed from outside the crate (the node test, the stack and PLOC are
//! its internals), and 0.4 is its newest release. The hierarchy here is small enough to prove
//! complete, and on the reference meshes faster: per single-threaded query, 0.8–0.9× obvhs's
//! time on the 36-triangle Cornell box and 0.5–0.8× on the 6,000–8,000-triangle test meshes.
//!
//! # Why no hit is lost
//!
//! * **Exact boxes.** `build.rs` makes a binary tree (binned SAH; depth ≤ `MAX_DEPTH` = 64;
//!   work ≤ 4·(depth + 1)·n) and collapses it into 4-wide nodes, one child box per SIMD lane,
//!   in plain `f32`: every box is the exact min/max of its triangles' vertices (no
//!   quantisation, no offsets from a distant corner).
//! * **Checked in release.** `build::validate` checks every built tree: each triangle in
//!   exactly one leaf, each triangle inside its leaf's box, each child box inside its parent's,
//!   no node reached twice or deeper than `MAX_DEPTH`. Should that ever fail, the queries fall
//!   back to testing every triangle (slow, never wrong).
//! * **A robust slab test** after Ize, "Robust BVH Ray Traversal" (JCGT 2013): directions are
//!   inverted exactly (`1/±0 = ±∞`, no clamping), the near and far planes are picked by the
//!   sign of the inverse (so `−0` works), `0·∞` (a ray in a box's face plane) counts as inside,
//!   there is no minimum distance, and the far distance is scaled by `1 + 2⁻²⁰`. Ize's bound
//!   needs `1 + 2γ₃ ≈ 1 + 3.6e-7` for the computed interval to contain the exact one, so a box
//!   that the exact ray meets within [0, t_max] is always entered; the 2.6× margin above that
//!   also covers the triangle test's own rounding, which grows with the distance too.
//! * **A stack that cannot overflow**: a node pushes at most three siblings and the tree is at
//!   most `MAX_DEPTH` deep, so `STACK` entries always suffice.
//!
//! `tests.rs` checks that every closest-hit distance and every occlusion answer is
//! bit-identical to brute force, on hostile geometry: the quad-and-sliver reproducer,
//! coordinates up to ±2³⁰ beside unit triangles, a scene 10 µm across, zero-area and needle
//! triangles, 3,000 identical triangles, coplanar overlapping ones, nested series, sizes from
//! 10¹² to 10⁻¹¹, each also with SAH cut off early so that median splits build most of it.
//!
//! The triangle test is watertight (`triangles.rs`: Woop, Benthin and Wald's edge functions
//! decide inside, so no ray passes between two triangles sharing an edge); its distance is
//! obvhs's Möller–Trumbore's (`RtTriangle::intersect`), operation for operation. Closest hits
//! count in [0, t_max), occluders in the open segment (0, t_max) only, so a surface through a
//! shadow ray's origin (the other wall, for a sample lying in a corner) does not block it. Ordinary images change
//! only where obvhs lost a hit: the seeded Cornell trace and render are byte-identical, while
//! in `opticks bench`'s million paths 87 of ~4.6 M bounces, leaving a corner with the next hit
//! nearer than 1e-4, used to escape the closed room. Triangles are stored in leaf order for
//! cache locality, four to a packet tested in one SIMD pass (`triangles.rs`: each lane computes
//! what the one-at-a-time test computes, bit for bit); `prims` maps lanes back to scene
//! indices. The packets cut the Cornell trace's user time by 5–8 % (and `bunny-box`'s by
//! 5–10 %), though callgrind counts 7 % more instructions in the ray queries: half-empty
//! lanes cost instructions, not time.

mod build;
#[cfg(test)]
mod tests;
mod triangles;

use crate::geometry::Ray;
use crate::math::{Vec3, Vec3A, Vec4};
use build::{Aabb, MAX_DEPTH};
use triangles::{Shear, Tri, Tri4};

/// A child slot that holds nothing (and a box no ray meets).
const EMPTY: u32 = u32::MAX;

/// Children per node.
const WIDTH: usize = 4;

/// Traversal stack entries: a node pushes at most `WIDTH − 1` siblings, the tree is at most
/// `MAX_DEPTH` deep.
const STACK: usize = (WIDTH - 1) * MAX_DEPTH + 1;

/// Entries of the traversal stack every query starts with ([`Accel::traverse`]).
const SMALL_STACK: usize = 16;

/// The far-distance factor of the robust slab test: more than Ize's 1 + 2γ₃ ≈ 1 + 3.6e-7.
const SLACK: f32 = 1.0 + 1.0 / 1_048_576.0;

/// A node: the boxes of up to four children, one per SIMD lane, and for each either a leaf
/// (`count > 0` triangles in the packets from `first`, four to a packet; built as leaf slots
/// `first..first + count` and renumbered by [`Accel::build`]), a node (`count == 0`, node index `first`), or
/// nothing (`first == EMPTY`, box empty).
#[derive(Clone, Copy, Debug)]
struct Node {
    /// Per lane: `[lo.x, hi.x, lo.y, hi.y, lo.z, hi.z]`.
    planes: [Vec4; 6],
    first: [u32; WIDTH],
    count: [u32; WIDTH],
}

impl Node {
    const EMPTY: Node = Node {
        planes: [
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
        ],
        first: [EMPTY; WIDTH],
        count: [0; WIDTH],
    };
}

/// A ray prepared for slab tests.
struct Query {
    o: Vec3A,
    d: Vec3A,
    /// `1/d`, exactly rounded; `±∞` for zero components.
    inv: Vec3A,
    /// Per axis, the origin, the direction and `1/d` in every lane.
    o4: [Vec4; 3],
    d4: [Vec4; 3],
    inv4: [Vec4; 3],
    /// The ray prepared for the triangle test.
    sh: Shear,
    /// Per axis, the index in [`Node::planes`] of the near and the far plane: the max where
    /// `1/d < 0` (including `−∞`), the min elsewhere.
    near: [usize; 3],
    far: [usize; 3],
}

impl Query {
    fn new(ray: &Ray) -> Query {
        let o = Vec3A::from(ray.origin);
        // `+ 0` turns `-0.0` components into `+0.0`, as the triangle test always saw them.
        let d = Vec3A::from(ray.dir) + Vec3A::ZERO;
        let inv = Vec3A::from(ray.dir).recip();
        let neg = |a: usize| (inv[a] < 0.0) as usize;
        Query {
            o,
            d,
            inv,
            o4: [Vec4::splat(o.x), Vec4::splat(o.y), Vec4::splat(o.z)],
            d4: [Vec4::splat(d.x), Vec4::splat(d.y), Vec4::splat(d.z)],
            inv4: [Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z)],
            near: [neg(0), 2 + neg(1), 4 + neg(2)],
            far: [1 - neg(0), 3 - neg(1), 5 - neg(2)],
            sh: Shear::new(o, d),
        }
    }

    /// Whether some `1/d` is infinite, so that `(plane − o)·(1/d)` can be `0·∞ = NaN`.
    fn has_infinite_inverse(&self) -> bool {
        !self.inv.is_finite()
    }

    /// Robust slab test of a node's child boxes against [0, t_max]: the lanes the ray may
    /// enter (bit mask) and their entry distances. With `NAN_SAFE`, `0·∞` lanes (the ray lies
    /// in a face's plane) count as inside; without, they cannot occur.
    #[inline(always)]
    fn enters<const NAN_SAFE: bool>(&self, n: &Node, t_max: f32) -> (u32, Vec4) {
        let mut t0 = Vec4::ZERO;
        let mut t1 = Vec4::splat(t_max);
        for a in 0..3 {
            let mut tn = (n.planes[self.near[a]] - self.o4[a]) * self.inv4[a];
            let mut tf = (n.planes[self.far[a]] - self.o4[a]) * self.inv4[a];
            if NAN_SAFE {
                tn = Vec4::select(tn.is_nan_mask(), Vec4::NEG_INFINITY, tn);
                tf = Vec4::select(tf.is_nan_mask(), Vec4::INFINITY, tf);
            }
            t0 = t0.max(tn);
            t1 = t1.min(tf);
        }
        (t0.cmple(t1 * SLACK).bitmask(), t0)
    }
}

/// A BVH over a fixed set of triangles.
pub struct Accel {
    nodes: Vec<Node>,
    /// Triangles in leaf order, four to a packet (each leaf starts a packet).
    packs: Vec<Tri4>,
    /// Packet lane → scene triangle index (`EMPTY` in unused lanes).
    prims: Vec<[u32; 4]>,
    /// Scene triangle index → its lane, `4·packet + lane`.
    lane_of: Vec<u32>,
    /// Depth of the deepest node (the root is at 0).
    depth: usize,
    /// Triangle visits the build made.
    #[cfg_attr(not(test), allow(dead_code))]
    build_work: u64,
}

impl std::fmt::Debug for Accel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Accel").field("triangles", &self.lane_of.len()).field("depth", &self.depth).finish()
    }
}

impl Accel {
    /// Builds the BVH over triangles given as vertex triples (scene order).
    pub fn build(triangles: &[[Vec3; 3]]) -> Self {
        Self::build_limited(triangles, MAX_DEPTH)
    }

    /// [`Accel::build`] with SAH splits only down to `max_depth` (tests use a small one to
    /// exercise the median splits that bound the depth).
    fn build_limited(triangles: &[[Vec3; 3]], max_depth: usize) -> Self {
        let boxes: Vec<Aabb> = triangles.iter().map(Aabb::of).collect();
        let built = build::build(&boxes, max_depth.min(MAX_DEPTH));
        let leaf_boxes: Vec<Aabb> = built.order.iter().map(|&i| boxes[i as usize]).collect();
        let (nodes, depth) = match build::validate(&built.nodes, &leaf_boxes) {
            Ok(()) => (built.nodes, built.depth),
            Err(e) => {
                // Cannot happen by construction; if it ever did, test every triangle rather
                // than lose any.
                debug_assert!(false, "invalid BVH: {e}");
                let all = leaf_boxes
                    .iter()
                    .fold(Aabb::EMPTY, |a, b| Aabb { lo: a.lo.min(b.lo), hi: a.hi.max(b.hi) });
                let mut root = Node::EMPTY;
                if !triangles.is_empty() {
                    root.set(0, &all, 0, triangles.len() as u32);
                }
                (vec![root], 0)
            }
        };
        let mut nodes = nodes;
        let (packs, prims, lane_of) = pack_leaves(&mut nodes, &built.order, triangles);
        Accel { nodes, packs, prims, lane_of, depth, build_work: built.work }
    }

    /// Closest hit along `ray` within [0, t_max): distance and scene triangle index.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<(f32, u32)> {
        let q = Query::new(ray);
        let hit = if q.has_infinite_inverse() {
            self.closest::<true, SMALL_STACK>(&q, ray.t_max)
        } else {
            self.closest::<false, SMALL_STACK>(&q, ray.t_max)
        };
        hit.map(|(t, lane)| (t, self.prim(lane)))
    }

    /// The scene triangle in lane `4·packet + lane`.
    #[inline(always)]
    fn prim(&self, lane: u32) -> u32 {
        self.prims[(lane / 4) as usize][(lane % 4) as usize]
    }

    /// The triangle in lane `4·packet + lane`, for the one-at-a-time tests.
    fn tri(&self, lane: u32) -> Tri {
        self.packs[(lane / 4) as usize].lane((lane % 4) as usize)
    }

    /// The distance along `ray` to scene triangle `prim` alone, within [0, t_max), by the same
    /// test as [`Accel::intersect`]: when `prim` is the closest hit, the same distance.
    #[inline]
    pub fn intersect_one(&self, ray: &Ray, prim: u32) -> Option<f32> {
        let lane = *self.lane_of.get(prim as usize).filter(|&&l| l != EMPTY)?;
        let (o, d) = (Vec3A::from(ray.origin), Vec3A::from(ray.dir) + Vec3A::ZERO);
        let t = self.tri(lane).intersect(o, d, &Shear::new(o, d), ray.t_max);
        (t < ray.t_max).then_some(t)
    }

    /// Whether anything blocks the open segment (0, t_max) of `ray`.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let q = Query::new(ray);
        if q.has_infinite_inverse() {
            self.any_hit::<true, SMALL_STACK>(&q, ray.t_max)
        } else {
            self.any_hit::<false, SMALL_STACK>(&q, ray.t_max)
        }
    }

    /// [`Accel::intersect`] counting only the hits `accept(triangle, t)` accepts (a masked
    /// surface the ray passes through is not a hit; the traversal goes on behind it). `accept`
    /// must answer the same for the same triangle and distance: a query may visit a leaf twice.
    /// (A query of its own, not [`Accel::intersect`] with an accept-all filter: sharing the
    /// leaf loop cost unfiltered queries 5 % more instructions, their leaf test no longer
    /// inlined.)
    pub fn intersect_where(&self, ray: &Ray, accept: impl Fn(u32, f32) -> bool) -> Option<(f32, u32)> {
        let q = Query::new(ray);
        let mut best: Option<(f32, u32)> = None;
        let mut t_max = ray.t_max;
        self.traverse::<true, true, SMALL_STACK>(&q, &mut t_max, |first, count, t_max| {
            for lane in 4 * first..4 * first + count {
                let t = self.tri(lane).intersect(q.o, q.d, &q.sh, *t_max);
                if t < *t_max && accept(self.prim(lane), t) {
                    *t_max = t;
                    best = Some((t, lane));
                }
            }
            false
        });
        best.map(|(t, lane)| (t, self.prim(lane)))
    }

    /// [`Accel::occluded`] counting only the blockers `accept(triangle, t)` accepts (as
    /// [`Accel::intersect_where`]).
    pub fn occluded_where(&self, ray: &Ray, accept: impl Fn(u32, f32) -> bool) -> bool {
        let q = Query::new(ray);
        let mut t = ray.t_max;
        self.traverse::<true, false, SMALL_STACK>(&q, &mut t, |first, count, t_max| {
            (4 * first..4 * first + count).any(|lane| {
                let t = self.tri(lane).intersect(q.o, q.d, &q.sh, *t_max);
                t > 0.0 && t < *t_max && accept(self.prim(lane), t)
            })
        })
    }

    /// The closest hit (distance, leaf slot), the traversal starting with `SMALL` stack entries.
    fn closest<const NAN_SAFE: bool, const SMALL: usize>(&self, q: &Query, t_max: f32) -> Option<(f32, u32)> {
        let mut best: Option<(f32, u32)> = None;
        let mut t_max = t_max;
        self.traverse::<NAN_SAFE, true, SMALL>(
            q,
            &mut t_max,
            #[inline(always)]
            |first, count, t_max| {
                for p in first..first + count.div_ceil(4) {
                    let t = self.packs[p as usize].intersect(&q.d4, &q.sh, *t_max);
                    let mut mask = t.cmplt(Vec4::splat(*t_max)).bitmask();
                    if mask != 0 {
                        // Lane by lane, as the one-at-a-time test visits them: the first of equal
                        // distances wins.
                        let t = t.to_array();
                        while mask != 0 {
                            let l = mask.trailing_zeros();
                            mask &= mask - 1;
                            if t[l as usize] < *t_max {
                                *t_max = t[l as usize];
                                best = Some((*t_max, 4 * p + l));
                            }
                        }
                    }
                }
                false
            },
        );
        best
    }

    /// Whether anything blocks the open segment, the traversal starting with `SMALL` entries.
    fn any_hit<const NAN_SAFE: bool, const SMALL: usize>(&self, q: &Query, t_max: f32) -> bool {
        let mut t = t_max;
        self.traverse::<NAN_SAFE, false, SMALL>(
            q,
            &mut t,
            #[inline(always)]
            |first, count, t_max| {
                (first..first + count.div_ceil(4)).any(|p| {
                    // The segment is open at both ends: a surface through the origin (t = ±0, e.g.
                    // the other wall at a corner a sample lies in) does not block it.
                    let t = self.packs[p as usize].intersect(&q.d4, &q.sh, *t_max);
                    (t.cmpgt(Vec4::ZERO) & t.cmplt(Vec4::splat(*t_max))).any()
                })
            },
        )
    }

    /// Visits every leaf whose box the ray may enter within [0, t_max]; with `NEAR_FIRST`, the
    /// inner children of a node in order of entry distance (closest hits shorten `t_max`
    /// sooner), else in lane order (occlusion stops at any hit, so sorting would be wasted).
    /// `leaf(first, count, t_max)` tests a leaf's `count` triangles (packets from `first`), may shorten `t_max`, and
    /// returns true to stop. Returns whether it stopped.
    ///
    /// The stack lives on the frame: a node pushes at most `WIDTH − 1` siblings, so
    /// `(WIDTH − 1)·depth + 1` entries always suffice, but zeroing them on every query costs
    /// (the worst-case [`STACK`] entries: ~8 % of a Cornell-box trace; 64 entries, a `memset`
    /// call per query: ~3 % of a bidirectional render, callgrind). So a query first runs with
    /// `SMALL` entries ([`SMALL_STACK`], zeroed inline), enough for almost every ray; one that would
    /// overflow them starts again from the root with a stack sized for the tree's depth,
    /// keeping the `t_max` it reached. The answer is the same: every leaf holding a hit nearer
    /// than `t_max` is still visited, in the same depth-first order (so ties between equal
    /// distances resolve as before), and an occlusion query that had found a hit was done.
    #[inline(always)]
    fn traverse<const NAN_SAFE: bool, const NEAR_FIRST: bool, const SMALL: usize>(
        &self,
        q: &Query,
        t_max: &mut f32,
        mut leaf: impl FnMut(u32, u32, &mut f32) -> bool,
    ) -> bool {
        const fn fits(entries: usize) -> usize {
            (entries - 1) / (WIDTH - 1)
        }
        if let Some(stopped) = self.traverse_with::<NAN_SAFE, NEAR_FIRST, SMALL>(q, t_max, &mut leaf) {
            stopped
        } else {
            self.traverse_deep::<NAN_SAFE, NEAR_FIRST>(q, t_max, leaf, self.depth <= fits(64))
        }
    }

    /// The traversal of a query that overflowed its small stack: from the root, with 64 entries
    /// if `fits_64` (the tree is at most 21 nodes deep), else [`STACK`].
    #[inline(never)]
    #[cold]
    fn traverse_deep<const NAN_SAFE: bool, const NEAR_FIRST: bool>(
        &self,
        q: &Query,
        t_max: &mut f32,
        mut leaf: impl FnMut(u32, u32, &mut f32) -> bool,
        fits_64: bool,
    ) -> bool {
        let done = if fits_64 {
            self.traverse_with::<NAN_SAFE, NEAR_FIRST, 64>(q, t_max, &mut leaf)
        } else {
            self.traverse_with::<NAN_SAFE, NEAR_FIRST, STACK>(q, t_max, &mut leaf)
        };
        done.expect("a stack sized for the tree's depth never overflows")
    }

    /// [`Accel::traverse`] with a stack of `S` entries: whether it stopped, or `None` if the
    /// stack would have overflowed (never when `S ≥ (WIDTH − 1)·depth + 1`).
    #[inline(always)]
    fn traverse_with<const NAN_SAFE: bool, const NEAR_FIRST: bool, const S: usize>(
        &self,
        q: &Query,
        t_max: &mut f32,
        leaf: &mut impl FnMut(u32, u32, &mut f32) -> bool,
    ) -> Option<bool> {
        let mut stack = [(0u32, 0.0f32); S];
        let mut sp = 0;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            let (mut mask, t0) = q.enters::<NAN_SAFE>(n, *t_max);
            let t0 = t0.to_array();
            let mut inner = [(0u32, 0.0f32); WIDTH];
            let mut k = 0;
            while mask != 0 {
                let c = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                if n.count[c] > 0 {
                    if leaf(n.first[c], n.count[c], t_max) {
                        return Some(true);
                    }
                } else {
                    inner[k] = (n.first[c], t0[c]);
                    k += 1;
                }
            }
            if k > 0 {
                // Farthest first onto the stack, continue with the nearest.
                if NEAR_FIRST {
                    sort_far_to_near(&mut inner[..k]);
                }
                if sp + k - 1 > S {
                    return None;
                }
                for &e in &inner[..k - 1] {
                    stack[sp] = e;
                    sp += 1;
                }
                node = inner[k - 1].0 as usize;
                continue;
            }
            loop {
                if sp == 0 {
                    return Some(false);
                }
                sp -= 1;
                let (next, t0) = stack[sp];
                // Skip what a closer hit found since has put out of reach.
                if t0 <= *t_max * SLACK {
                    node = next as usize;
                    break;
                }
            }
        }
    }
}

/// Lays the triangles out in packets ([`Tri4`]), each leaf's from a packet of its own, in leaf
/// order, and renumbers each leaf's `first` from its slot to its first packet. Returns the
/// packets, their lanes' scene triangles and each scene triangle's lane.
fn pack_leaves(
    nodes: &mut [Node],
    order: &[u32],
    triangles: &[[Vec3; 3]],
) -> (Vec<Tri4>, Vec<[u32; 4]>, Vec<u32>) {
    let mut leaves: Vec<(u32, usize, usize)> = Vec::new();
    for (i, n) in nodes.iter().enumerate() {
        for c in 0..WIDTH {
            if n.first[c] != EMPTY && n.count[c] > 0 {
                leaves.push((n.first[c], i, c));
            }
        }
    }
    leaves.sort_unstable();
    let mut packs = Vec::with_capacity(order.len().div_ceil(2));
    let mut prims = Vec::with_capacity(packs.capacity());
    let mut lane_of = vec![EMPTY; order.len()];
    for (slot, i, c) in leaves {
        let leaf = &order[slot as usize..][..nodes[i].count[c] as usize];
        nodes[i].first[c] = packs.len() as u32;
        for four in leaf.chunks(4) {
            let mut tris = [Tri::new(&triangles[four[0] as usize]); 4];
            let mut lanes = [EMPTY; 4];
            for (l, &t) in four.iter().enumerate() {
                tris[l] = Tri::new(&triangles[t as usize]);
                lanes[l] = t;
                lane_of[t as usize] = 4 * packs.len() as u32 + l as u32;
            }
            packs.push(Tri4::new(&tris[..four.len()]));
            prims.push(lanes);
        }
    }
    (packs, prims, lane_of)
}

/// Sorts up to [`WIDTH`] (node, entry distance) pairs by decreasing distance: an insertion
/// sort, which for four elements beats the general sort's call and dispatch.
#[inline(always)]
fn sort_far_to_near(v: &mut [(u32, f32)]) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && v[j - 1].1 < v[j].1 {
            v.swap(j - 1, j);
            j -= 1;
        }
    }
}
