//! Building the hierarchy: a binned-SAH top-down build whose depth and work are bounded for
//! any input, and the release-mode check that the built tree is complete.
//!
//! * **Split choice.** Each node bins its triangles' centroids into [`BINS`] bins on every axis
//!   the centroids span and takes the split of least surface-area cost. Areas are summed in
//!   `f64`, so boxes with coordinates near `f32::MAX` neither overflow nor turn into NaN.
//! * **Bounded depth.** Where the centroids all coincide (identical or concentric triangles)
//!   there is no plane to split at, and the node is halved by index. Where SAH would go on
//!   peeling one triangle at a time off a node (a geometric series of nested triangles), a node
//!   at depth `d` holding `m` triangles switches to median splits once `d + ⌈log₂ m⌉` reaches
//!   [`MAX_DEPTH`]: median splits keep that sum from growing, so no leaf is deeper than
//!   `MAX_DEPTH` and the traversal's fixed stack cannot overflow.
//! * **Bounded work.** Every level of the tree touches each triangle a bounded number of times,
//!   so the build does at most `(MAX_DEPTH + 1) · n` triangle visits
//!   ([`Built::work`] counts them), whatever the input: 30,000 identical triangles used to cost
//!   obvhs's PLOC builder 38 s (quadratic), here a few milliseconds.
//! * **Parallel, same tree.** A node of at least [`PARALLEL_FROM`] triangles builds its two
//!   subtrees on two threads (`rayon::join`), each into an arena of its own that is then
//!   appended to its parent's. Split decisions depend on a node's triangles alone and the
//!   4-wide tree is laid out depth first from the binary one, so the result is the tree a
//!   single thread builds, node for node, whatever the thread count (a test holds it).
//! * **Validation** ([`validate`]) runs in release builds: every triangle in exactly one leaf,
//!   every child box inside its parent's and every triangle inside its leaf's box (exact `f32`
//!   comparisons), no node reached twice, no leaf deeper than the stack.

use super::{EMPTY, Node, WIDTH};
use crate::math::{Vec3, Vec4};

/// Centroid bins per axis and node.
const BINS: usize = 16;
/// Triangles in one leaf, at most (more only in the brute-force fallback).
pub(super) const MAX_LEAF: usize = 4;
/// The deepest a node can be (the root is at depth 0); the traversal stack holds this many.
pub(super) const MAX_DEPTH: usize = 64;
/// Nodes with at least this many triangles build their two subtrees in parallel (below it,
/// a task costs more than it saves).
pub(super) const PARALLEL_FROM: usize = 4096;

/// A built hierarchy, before its triangles are reordered.
pub(super) struct Built {
    /// The 4-wide nodes the traversal reads; the root is node 0.
    pub nodes: Vec<Node>,
    /// Leaf slot → input triangle index.
    pub order: Vec<u32>,
    /// Depth of the deepest node of the binary tree (the 4-wide one is no deeper).
    pub depth: usize,
    /// Triangle visits made by the build (binning and partitioning).
    pub work: u64,
}

/// An axis-aligned box in `f32`; `EMPTY_BOX` contains nothing and no ray meets it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Aabb {
    pub lo: Vec3,
    pub hi: Vec3,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb { lo: Vec3::INFINITY, hi: Vec3::NEG_INFINITY };

    pub fn of(t: &[Vec3; 3]) -> Aabb {
        Aabb { lo: t[0].min(t[1]).min(t[2]), hi: t[0].max(t[1]).max(t[2]) }
    }
    fn union(self, o: Aabb) -> Aabb {
        Aabb { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi) }
    }
    pub fn contains(&self, o: &Aabb) -> bool {
        self.lo.cmple(o.lo).all() && self.hi.cmpge(o.hi).all()
    }
    /// Half the surface area, in `f64` so that huge boxes neither overflow nor become NaN.
    fn half_area(&self) -> f64 {
        if self.lo.cmpgt(self.hi).any() {
            return 0.0;
        }
        let d = self.hi.as_dvec3() - self.lo.as_dvec3();
        d.x * d.y + d.y * d.z + d.z * d.x
    }
}

/// A child slot: its box and what it points at (a leaf of `count` triangles from slot
/// `first`, an interior node `first` if `count == 0`, nothing if `first == EMPTY`).
#[derive(Clone, Copy)]
struct Child {
    bounds: Aabb,
    first: u32,
    count: u32,
}

/// A node of the binary tree the build makes (then collapsed into 4-wide nodes).
#[derive(Clone, Copy)]
struct Node2([Child; 2]);

struct Builder<'a> {
    boxes: &'a [Aabb],
    /// Centroids, as `lo/2 + hi/2` (cannot overflow).
    centroids: &'a [Vec3],
    /// This builder's arena of binary nodes (a subtree built in parallel has its own).
    nodes: Vec<Node2>,
    depth: usize,
    work: u64,
    max_depth: usize,
    /// Nodes of at least this many triangles split their work over two threads.
    parallel_from: usize,
}

/// Builds the hierarchy over triangles given by their boxes, switching to median splits where
/// SAH could take a node deeper than `max_depth` (so no node is deeper than
/// `max(max_depth, ⌈log₂ n⌉)`).
pub(super) fn build(boxes: &[Aabb], max_depth: usize) -> Built {
    build_with(boxes, max_depth, PARALLEL_FROM)
}

/// [`build`], splitting nodes of at least `parallel_from` triangles over two threads.
pub(super) fn build_with(boxes: &[Aabb], max_depth: usize, parallel_from: usize) -> Built {
    use rayon::prelude::*;
    let centroid = |b: &Aabb| b.lo * 0.5 + b.hi * 0.5;
    // Below `parallel_from` triangles nothing is parallel, and a small scene's build does not
    // start rayon's pool (its threads: ~0.3 ms of a small case's 3 ms trace).
    let centroids: Vec<Vec3> = if boxes.len() >= parallel_from {
        boxes.par_iter().map(centroid).collect()
    } else {
        boxes.iter().map(centroid).collect()
    };
    let mut b = Builder {
        boxes,
        centroids: &centroids,
        nodes: Vec::new(),
        depth: 0,
        work: 0,
        max_depth,
        parallel_from: parallel_from.max(2 * MAX_LEAF),
    };
    let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
    b.nodes.push(Node2([empty_child(); 2]));
    if order.len() <= MAX_LEAF {
        // Too few to split: the root holds one leaf and an empty slot.
        b.nodes[0].0[0] = b.leaf(&order, 0);
    } else {
        b.interior(&mut order, 0, 0, 0);
    }
    let mut nodes = Vec::with_capacity(b.nodes.len() / 2 + 1);
    collapse(&b.nodes, 0, &mut nodes);
    Built { nodes, order, depth: b.depth, work: b.work }
}

fn empty_child() -> Child {
    Child { bounds: Aabb::EMPTY, first: EMPTY, count: 0 }
}

/// Appends the 4-wide node for binary node `i` and its subtree to `out`; returns its index.
/// Each binary interior child of largest area is replaced by its two children while there is
/// room, so the wide tree is no deeper than the binary one.
fn collapse(bin: &[Node2], i: usize, out: &mut Vec<Node>) -> u32 {
    let mut kids = [empty_child(); WIDTH];
    let mut k = 0;
    for c in bin[i].0 {
        if c.first != EMPTY {
            kids[k] = c;
            k += 1;
        }
    }
    while k < WIDTH {
        let inner = (0..k)
            .filter(|&j| kids[j].count == 0)
            .max_by(|&a, &b| kids[a].bounds.half_area().total_cmp(&kids[b].bounds.half_area()));
        let Some(j) = inner else { break };
        let [a, b] = bin[kids[j].first as usize].0;
        (kids[j], kids[k]) = (a, b);
        k += 1;
    }
    let slot = out.len();
    out.push(Node::EMPTY);
    let mut node = Node::EMPTY;
    for (lane, kid) in kids[..k].iter().enumerate() {
        let first = if kid.count == 0 { collapse(bin, kid.first as usize, out) } else { kid.first };
        node.set(lane, &kid.bounds, first, kid.count);
    }
    out[slot] = node;
    slot as u32
}

/// ⌈log₂ m⌉ for m ≥ 1.
pub(super) fn ceil_log2(m: usize) -> usize {
    (usize::BITS - (m.max(1) - 1).leading_zeros()) as usize
}

impl<'a> Builder<'a> {
    fn bounds(&self, prims: &[u32]) -> Aabb {
        prims.iter().fold(Aabb::EMPTY, |acc, &i| acc.union(self.boxes[i as usize]))
    }

    fn leaf(&self, prims: &[u32], first: usize) -> Child {
        if prims.is_empty() {
            return empty_child();
        }
        Child { bounds: self.bounds(prims), first: first as u32, count: prims.len() as u32 }
    }

    /// Builds the subtree over `prims` (which sit at `first..` in the leaf order) into node
    /// slot `slot`, which is at depth `depth`.
    fn interior(&mut self, prims: &mut [u32], first: usize, slot: usize, depth: usize) {
        self.depth = self.depth.max(depth);
        self.work += prims.len() as u64;
        let mid = self.split(prims, depth);
        let parallel = prims.len() >= self.parallel_from;
        let (left, right) = prims.split_at_mut(mid);
        let (a, b) = if parallel {
            let (mut l, mut r) = (self.fork(), self.fork());
            let (a, b) =
                rayon::join(|| l.child(left, first, depth + 1), || r.child(right, first + mid, depth + 1));
            (self.adopt(l, a), self.adopt(r, b))
        } else {
            let a = self.child(left, first, depth + 1);
            (a, self.child(right, first + mid, depth + 1))
        };
        self.nodes[slot] = Node2([a, b]);
    }

    /// A builder for a subtree built on another thread: same inputs, an arena of its own.
    fn fork(&self) -> Builder<'a> {
        Builder { nodes: Vec::new(), depth: 0, work: 0, ..*self }
    }

    /// Appends the arena of `sub` (which built `child`) to this one, renumbering its interior
    /// nodes; returns `child` renumbered.
    fn adopt(&mut self, sub: Builder<'_>, child: Child) -> Child {
        let offset = self.nodes.len() as u32;
        let renumber = |mut c: Child| {
            if c.count == 0 && c.first != EMPTY {
                c.first += offset;
            }
            c
        };
        self.nodes.extend(sub.nodes.into_iter().map(|Node2(kids)| Node2(kids.map(renumber))));
        self.depth = self.depth.max(sub.depth);
        self.work += sub.work;
        renumber(child)
    }

    /// The child slot over `prims`: a leaf, or a new interior node at depth `depth`.
    fn child(&mut self, prims: &mut [u32], first: usize, depth: usize) -> Child {
        if prims.len() <= MAX_LEAF && self.leaf_is_cheaper(prims) {
            return self.leaf(prims, first);
        }
        let slot = self.nodes.len();
        self.nodes.push(Node2([empty_child(); 2]));
        self.interior(prims, first, slot, depth);
        let [a, b] = self.nodes[slot].0;
        Child { bounds: a.bounds.union(b.bounds), first: slot as u32, count: 0 }
    }

    /// SAH for a small node: one leaf of `m` triangles against a split into two leaves (a
    /// node visit costs as much as a triangle test).
    fn leaf_is_cheaper(&self, prims: &[u32]) -> bool {
        if prims.len() <= 1 {
            return true;
        }
        let area = self.bounds(prims).half_area();
        let (l, r) = prims.split_at(prims.len() / 2);
        let split =
            area + self.bounds(l).half_area() * l.len() as f64 + self.bounds(r).half_area() * r.len() as f64;
        area * prims.len() as f64 <= split
    }

    /// Reorders `prims` into two non-empty halves and returns the size of the first.
    fn split(&mut self, prims: &mut [u32], depth: usize) -> usize {
        let (clo, chi) = prims.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &i| {
            let c = self.centroids[i as usize];
            (lo.min(c), hi.max(c))
        });
        let extent = chi.as_dvec3() - clo.as_dvec3();
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        if extent[axis] <= 0.0 {
            // All centroids coincide: no plane separates them, halve by index.
            return prims.len() / 2;
        }
        if depth + ceil_log2(prims.len()) < self.max_depth
            && let Some((axis, bin)) = self.best_binned_split(prims, clo, extent)
        {
            let scale = BINS as f64 / extent[axis];
            let lo = clo[axis] as f64;
            let c = &self.centroids;
            let left = partition(prims, |i| bin_of(c[i as usize][axis], lo, scale) < bin);
            if left > 0 && left < prims.len() {
                return left;
            }
        }
        // Median split on the widest axis: halves the count, so depth stays bounded.
        let mid = prims.len() / 2;
        let c = &self.centroids;
        prims.select_nth_unstable_by(mid, |&a, &b| c[a as usize][axis].total_cmp(&c[b as usize][axis]));
        mid
    }

    /// The (axis, first right bin) of least SAH cost over the axes the centroids span.
    fn best_binned_split(&mut self, prims: &[u32], clo: Vec3, extent: glam::DVec3) -> Option<(usize, usize)> {
        // All three axes are binned in one pass over the triangles (one fetch of each
        // triangle's centroid and box instead of three, which dominate a large node's build);
        // an axis the centroids do not span gets bins that are never read.
        let scale = [0, 1, 2].map(|axis| BINS as f64 / extent[axis]);
        let lo = [0, 1, 2].map(|axis| clo[axis] as f64);
        let mut all_bins = [[(0u32, Aabb::EMPTY); BINS]; 3];
        for &i in prims {
            let (c, bounds) = (self.centroids[i as usize], self.boxes[i as usize]);
            for (axis, bins) in all_bins.iter_mut().enumerate() {
                let b = &mut bins[bin_of(c[axis], lo[axis], scale[axis])];
                b.0 += 1;
                b.1 = b.1.union(bounds);
            }
        }
        let mut best: Option<(f64, usize, usize)> = None;
        for (axis, bins) in all_bins.iter().enumerate() {
            if extent[axis] <= 0.0 {
                continue;
            }
            self.work += prims.len() as u64;
            // right[k]: count and SAH cost of bins k.. (the right side of a split before bin k).
            let mut right = [(0u32, 0.0f64); BINS];
            let (mut n, mut acc) = (0u32, Aabb::EMPTY);
            for k in (1..BINS).rev() {
                n += bins[k].0;
                acc = acc.union(bins[k].1);
                right[k] = (n, acc.half_area() * n as f64);
            }
            let (mut n, mut acc) = (0u32, Aabb::EMPTY);
            for k in 1..BINS {
                n += bins[k - 1].0;
                acc = acc.union(bins[k - 1].1);
                let cost = acc.half_area() * n as f64 + right[k].1;
                if n > 0 && right[k].0 > 0 && best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, axis, k));
                }
            }
        }
        best.map(|(_, axis, bin)| (axis, bin))
    }
}

/// The centroid bin of coordinate `c` ≥ `lo`, for bins of `1/scale` from `lo`.
/// Clamping before the conversion (`x ≥ 0` truncates to the same bin either way) spares the
/// saturating float-to-integer conversion its range checks, the inner loop's largest cost.
fn bin_of(c: f32, lo: f64, scale: f64) -> usize {
    ((c as f64 - lo) * scale).min((BINS - 1) as f64) as u32 as usize
}

/// Moves the elements for which `left` holds to the front; returns how many there are.
fn partition(prims: &mut [u32], left: impl Fn(u32) -> bool) -> usize {
    let mut k = 0;
    for j in 0..prims.len() {
        if left(prims[j]) {
            prims.swap(k, j);
            k += 1;
        }
    }
    k
}

/// The first way a built tree breaks the invariants [`validate`] checks.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub(super) enum Invalid {
    /// A node lies deeper than the traversal's stack allows.
    #[error("node {node} at depth {depth} > {MAX_DEPTH}")]
    TooDeep { node: usize, depth: usize },
    /// A node is the child of two lanes.
    #[error("node {node} reached twice")]
    NodeTwice { node: usize },
    /// A leaf's triangle range runs past the triangles.
    #[error("node {node}: leaf {first}+{count} out of range")]
    LeafOutOfRange { node: usize, first: usize, count: usize },
    /// A triangle slot belongs to two leaves.
    #[error("triangle slot {slot} in two leaves")]
    SlotTwice { slot: usize },
    /// A triangle's box pokes out of its leaf's box.
    #[error("node {node}: triangle slot {slot} outside its leaf's box")]
    SlotOutsideLeaf { node: usize, slot: usize },
    /// A child index points backwards or past the nodes (children follow their parents).
    #[error("node {node}: child {child} out of order")]
    ChildOutOfOrder { node: usize, child: usize },
    /// A child's boxes are not inside the box its parent keeps for it.
    #[error("node {node}: child {child}'s boxes outside its box")]
    ChildOutsideParent { node: usize, child: usize },
    /// A triangle slot belongs to no leaf.
    #[error("triangle slot {slot} in no leaf")]
    SlotInNoLeaf { slot: usize },
}

/// Checks the built tree completely (release builds too): every triangle slot in exactly one
/// leaf, every node reached once, every child box inside its parent's, every triangle inside
/// its leaf's box, no node deeper than [`MAX_DEPTH`]. `boxes` are the triangles' boxes in leaf
/// order. Returns the first violation found.
pub(super) fn validate(nodes: &[Node], boxes: &[Aabb]) -> Result<(), Invalid> {
    let mut seen_slot = vec![false; boxes.len()];
    let mut seen_node = vec![false; nodes.len()];
    let mut stack = vec![(0usize, 0usize)];
    while let Some((i, depth)) = stack.pop() {
        if depth > MAX_DEPTH {
            return Err(Invalid::TooDeep { node: i, depth });
        }
        if std::mem::replace(&mut seen_node[i], true) {
            return Err(Invalid::NodeTwice { node: i });
        }
        let n = &nodes[i];
        for lane in 0..WIDTH {
            let bounds = n.bounds(lane);
            let (first, count) = (n.first[lane] as usize, n.count[lane] as usize);
            if count > 0 {
                let Some(slots) = boxes.get(first..first + count) else {
                    return Err(Invalid::LeafOutOfRange { node: i, first, count });
                };
                for (s, b) in slots.iter().enumerate() {
                    if std::mem::replace(&mut seen_slot[first + s], true) {
                        return Err(Invalid::SlotTwice { slot: first + s });
                    }
                    if !bounds.contains(b) {
                        return Err(Invalid::SlotOutsideLeaf { node: i, slot: first + s });
                    }
                }
            } else if n.first[lane] != EMPTY {
                if first <= i || first >= nodes.len() {
                    return Err(Invalid::ChildOutOfOrder { node: i, child: first });
                }
                let c = &nodes[first];
                if !(0..WIDTH).all(|l| bounds.contains(&c.bounds(l))) {
                    return Err(Invalid::ChildOutsideParent { node: i, child: first });
                }
                stack.push((first, depth + 1));
            }
        }
    }
    match seen_slot.iter().position(|s| !s) {
        Some(slot) => Err(Invalid::SlotInNoLeaf { slot }),
        None => Ok(()),
    }
}

impl Node {
    /// Lane `lane`'s box.
    pub(super) fn bounds(&self, lane: usize) -> Aabb {
        let p = |k: usize| self.planes[k].to_array()[lane];
        Aabb { lo: Vec3::new(p(0), p(2), p(4)), hi: Vec3::new(p(1), p(3), p(5)) }
    }

    /// Sets lane `lane` to a child with box `b`.
    pub(super) fn set(&mut self, lane: usize, b: &Aabb, first: u32, count: u32) {
        for (k, v) in [b.lo.x, b.hi.x, b.lo.y, b.hi.y, b.lo.z, b.hi.z].into_iter().enumerate() {
            let mut a = self.planes[k].to_array();
            a[lane] = v;
            self.planes[k] = Vec4::from_array(a);
        }
        (self.first[lane], self.count[lane]) = (first, count);
    }
}
