//! Tests of [`Accel`]: hand-made queries, and a brute-force comparison on hostile geometry
//! (huge and tiny coordinates, degenerate, identical, coplanar and deeply nested triangles)
//! that proves on every ray that the hierarchy loses no hit.

use super::*;
use crate::sampling::RandomStream;

fn quad(y: f32) -> [[Vec3; 3]; 2] {
    let (a, b, c, d) =
        (Vec3::new(-1.0, y, -1.0), Vec3::new(1.0, y, -1.0), Vec3::new(1.0, y, 1.0), Vec3::new(-1.0, y, 1.0));
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

/// Rays with zero direction components lying in a box's face plane (where the slab test
/// computes 0·∞ = NaN), and rays starting on a surface: occlusion is over the open segment.
#[test]
fn rays_in_face_planes_and_from_surfaces() {
    let mut tris = quad(0.0).to_vec();
    // A wall at x = 2 standing on the quad's plane.
    tris.push([Vec3::new(2.0, -1.0, -1.0), Vec3::new(2.0, 1.0, -1.0), Vec3::new(2.0, 0.0, 1.0)]);
    let accel = Accel::build(&tris);
    // In the quad's plane (its box is flat in y), on its box's faces x = -1 and x = 1.
    for origin in [Vec3::new(0.0, 0.0, 0.0), Vec3::new(-1.0, 0.0, 0.3), Vec3::new(1.0, 0.0, -0.5)] {
        let along = Ray { origin, dir: Vec3::X, t_max: f32::INFINITY };
        let (t, prim) = accel.intersect(&along).unwrap();
        assert!(prim == 2 && (t - (2.0 - origin.x)).abs() < 1e-6, "{origin}: t={t} prim={prim}");
        assert!(accel.occluded(&Ray { t_max: 5.0, ..along }));
    }
    // From a point of the quad, leaving it: the quad is at t = 0, outside (0, t_max).
    let up = Ray { origin: Vec3::new(0.3, 0.0, 0.4), dir: Vec3::new(0.6, 0.8, 0.0), t_max: 1.0 };
    assert!(!accel.occluded(&up));
}

/// A scene to test: its triangles, the ones rays are aimed at, and how far from its target a
/// ray starts (log-uniform in the range, relative to the target triangle's size).
struct Case {
    name: String,
    tris: Vec<[Vec3; 3]>,
    targets: Vec<u32>,
    distance: (f32, f32),
}

struct Rng(RandomStream);

impl Rng {
    fn new(key: u64) -> Self {
        Rng(RandomStream::new(0xacce1, &[key]))
    }
    fn f(&mut self) -> f32 {
        self.0.next_f32()
    }
    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f()
    }
    /// Log-uniform in [lo, hi).
    fn log_range(&mut self, lo: f32, hi: f32) -> f32 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.f()).exp()
    }
    fn index(&mut self, n: usize) -> usize {
        (self.0.next_u64() % n as u64) as usize
    }
    fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }
    /// A direction that is axis-aligned (exact zeros), in an axis plane (one zero) or general.
    fn direction(&mut self) -> Vec3 {
        let mut d = self.unit();
        match self.index(8) {
            0 => {
                let axis = self.index(3);
                d = Vec3::ZERO;
                d[axis] = if self.f() < 0.5 { -1.0 } else { 1.0 };
            }
            1 => {
                d[self.index(3)] = 0.0;
                d = d.normalize();
            }
            _ => {}
        }
        d
    }
    /// A uniform point in the box [lo, hi)³.
    fn point(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        Vec3::new(self.range(lo.x, hi.x), self.range(lo.y, hi.y), self.range(lo.z, hi.z))
    }
    /// A triangle of size `size` around `c`, randomly oriented.
    fn triangle(&mut self, c: Vec3, size: f32) -> [Vec3; 3] {
        [c + self.unit() * size, c + self.unit() * size, c + self.unit() * size]
    }
}

fn size_of(t: &[Vec3; 3]) -> f32 {
    (t[1] - t[0]).length().max((t[2] - t[0]).length()).max((t[2] - t[1]).length())
}

/// The brute-force answers with the same triangle test as [`Accel`] on every triangle: the
/// closest hit in [0, t_max], and whether a hit lies in the open segment (0, t_max).
fn brute_force(tris: &[Tri], ray: &Ray) -> (f32, bool) {
    let q = Query::new(ray);
    let ts = tris.iter().map(|t| t.intersect(q.o, q.d, &q.sh, ray.t_max));
    ts.fold((f32::INFINITY, false), |(min, blocked), t| (min.min(t), blocked || (t > 0.0 && t < ray.t_max)))
}

/// Fires `rays` rays at the case's targets and returns a description of every ray on which the
/// BVH disagrees with brute force: a closest hit farther than the brute-force one (or none), or
/// an occlusion answer that differs.
fn disagreements(accel: &Accel, case: &Case, rays: usize, rng: &mut Rng) -> Vec<String> {
    let rt: Vec<Tri> = case.tris.iter().map(Tri::new).collect();
    let mut bad = Vec::new();
    for _ in 0..rays {
        let target = case.tris[case.targets[rng.index(case.targets.len())] as usize];
        let (u, v) = (rng.f(), rng.f());
        let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (u, v) };
        let p = target[0] + u * (target[1] - target[0]) + v * (target[2] - target[0]);
        let size = size_of(&target).max(f32::MIN_POSITIVE);
        let distance = size * rng.log_range(case.distance.0, case.distance.1);
        let dir = rng.direction();
        let origin = p - dir * distance;
        let ray = Ray { origin, dir, t_max: f32::INFINITY };
        let expect = brute_force(&rt, &ray).0;
        let got = accel.intersect(&ray);
        let got_t = got.map_or(f32::INFINITY, |h| h.0);
        if got_t != expect {
            bad.push(format!("closest: {ray:?}: brute force t={expect}, BVH {got:?}"));
        }
        let t_max = (p - origin).length() * rng.range(0.5, 1.5);
        let shadow = Ray { t_max, ..ray };
        let blocked = brute_force(&rt, &shadow).1;
        if accel.occluded(&shadow) != blocked {
            bad.push(format!("occluded: {shadow:?}: brute force {blocked}"));
        }
    }
    bad
}

/// The reproducer: a unit quad seen by the rays, and off to the side a sliver with one
/// vertex at y = -2^k. The quantised child boxes lost the quad (mean radiance 0.0003, not 0.0396).
fn sliver_cases() -> Vec<Case> {
    (24..=30)
        .step_by(2)
        .map(|k| {
            let mut tris = quad(0.0).to_vec();
            let far = -(2.0f32).powi(k);
            tris.push([Vec3::new(3.0, 0.0, 3.0), Vec3::new(3.01, 0.0, 3.0), Vec3::new(3.0, far, 3.0)]);
            Case {
                name: format!("quad + sliver to y=-2^{k}"),
                tris,
                targets: vec![0, 1],
                distance: (0.5, 50.0),
            }
        })
        .collect()
}

/// Unit triangles near the origin next to triangles with coordinates of ±2^24…2^30.
fn huge_case(rng: &mut Rng) -> Case {
    let mut tris: Vec<[Vec3; 3]> = (0..300)
        .map(|_| {
            let c = rng.point(Vec3::splat(-10.0), Vec3::splat(10.0));
            rng.triangle(c, 1.0)
        })
        .collect();
    let targets = (0..tris.len() as u32).collect();
    for k in 24..=30 {
        let h = (2.0f32).powi(k);
        let c = rng.triangle(Vec3::ZERO, 10.0)[0];
        tris.push([c, c + Vec3::X * 0.1, Vec3::new(c.x, c.y, -h)]); // sliver to -2^k
        tris.push([Vec3::splat(h), Vec3::new(h, h + 1.0, h), Vec3::new(h + 1.0, h, h)]); // far away
        tris.push([Vec3::new(-h, -h, 50.0), Vec3::new(h, -h, 50.0), Vec3::new(0.0, h, 50.0)]); // huge, behind
        tris.push([Vec3::new(-h, 0.0, -h), Vec3::new(-h + 1.0, 0.0, -h), Vec3::new(-h, 1.0, -h)]);
    }
    Case { name: "unit triangles beside ±2^24…2^30".into(), tris, targets, distance: (0.5, 100.0) }
}

/// A whole scene 10 µm across, seen from up to 1 mm: every hit is closer than 1e-4.
fn tiny_case(rng: &mut Rng) -> Case {
    let tris: Vec<[Vec3; 3]> = (0..300)
        .map(|_| {
            let c = rng.point(Vec3::splat(-1e-5), Vec3::splat(1e-5));
            let size = rng.log_range(1e-8, 1e-6);
            rng.triangle(c, size)
        })
        .collect();
    let targets = (0..tris.len() as u32).collect();
    Case { name: "tiny triangles".into(), tris, targets, distance: (0.5, 1000.0) }
}

/// Zero-area triangles (repeated and collinear vertices) and needles among ordinary ones.
fn degenerate_case(rng: &mut Rng) -> Case {
    let mut tris = Vec::new();
    let mut targets = Vec::new();
    for i in 0..600 {
        let c = rng.point(Vec3::splat(-5.0), Vec3::splat(5.0));
        let [a, b, d] = rng.triangle(c, 1.0);
        match i % 4 {
            0 => tris.push([a, a, a]),
            1 => tris.push([a, b, a + 2.0 * (b - a)]),
            2 => tris.push([a, b, b + (d - b) * 1e-6]),
            _ => {
                targets.push(tris.len() as u32);
                tris.push([a, b, d]);
            }
        }
    }
    Case { name: "degenerate triangles".into(), tris, targets, distance: (0.5, 20.0) }
}

/// Thousands of copies of one triangle (the build used to take quadratic time on them).
fn identical_case(rng: &mut Rng) -> Case {
    let one = rng.triangle(Vec3::ZERO, 1.0);
    let mut tris = vec![one; 3000];
    for _ in 0..100 {
        let c = rng.point(Vec3::new(-3.0, 0.0, -3.0), Vec3::new(3.0, 0.0, 3.0));
        tris.push(rng.triangle(c, 0.5));
    }
    Case {
        name: "3000 identical triangles".into(),
        targets: vec![0, 1500, 2999, 3000, 3050],
        tris,
        distance: (0.5, 20.0),
    }
}

/// Overlapping triangles in common planes (axis-aligned and not), duplicates of either winding.
fn coplanar_case(rng: &mut Rng) -> Case {
    let mut tris = Vec::new();
    let tilt = Vec3::new(0.3, 1.0, -0.2).normalize();
    let (e1, e2) = (tilt.cross(Vec3::X).normalize(), tilt.cross(Vec3::X).normalize().cross(tilt));
    for _ in 0..400 {
        let p = |rng: &mut Rng| Vec3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), 0.5);
        let t = [p(rng), p(rng), p(rng)];
        tris.push(t);
        tris.push([t[0], t[2], t[1]]);
        let q = |rng: &mut Rng| 2.0 * tilt + rng.range(-1.0, 1.0) * e1 + rng.range(-1.0, 1.0) * e2;
        tris.push([q(rng), q(rng), q(rng)]);
        let r = |rng: &mut Rng| Vec3::new(0.0, rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        tris.push([r(rng), r(rng), r(rng)]);
    }
    let targets = (0..tris.len() as u32).collect();
    Case { name: "coplanar overlapping triangles".into(), tris, targets, distance: (0.1, 10.0) }
}

/// A geometric series of nested triangles, each 0.8 times the previous one, down to 1e-9 (below
/// that, f32 Möller–Trumbore underflows): SAH peels them off one by one, so the tree is as
/// deep as the build allows (obvhs's traversal stack held 32 entries).
fn nested_case() -> Case {
    let base = [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    let tris: Vec<[Vec3; 3]> = (0..90)
        .map(|i| {
            let s = 0.8f32.powi(i);
            base.map(|v| v * s + Vec3::new(0.0, 0.0, 0.01 * s * (i % 3) as f32))
        })
        .collect();
    let targets = (0..tris.len() as u32).collect();
    Case { name: "90 nested triangles".into(), tris, targets, distance: (0.5, 20.0) }
}

/// Along each axis, triangles 8 times smaller and 8 times closer to the origin than the last,
/// from 10¹² down to 10⁻¹¹: each centroid bin split peels off one triangle, so the tree gets
/// as deep as the build's depth bound allows (obvhs's traversal stack held 32 entries).
fn scale_series_case() -> Case {
    let mut tris = Vec::new();
    for i in 0..=26 {
        for axis in 0..3 {
            let s = 1e12 * 0.125f32.powi(i);
            let mut c = Vec3::ZERO;
            c[axis] = s;
            tris.push([c, c + s * Vec3::new(0.05, 0.01, 0.0), c + s * Vec3::new(0.0, 0.03, 0.05)]);
        }
    }
    let targets = (0..tris.len() as u32).collect();
    Case { name: "sizes 1e12…1e-11".into(), tris, targets, distance: (0.5, 20.0) }
}

/// 30,000 copies of a triangle (and of a point): the build halves them by index, so the tree
/// is log₂ n deep and the work linear-logarithmic (obvhs's PLOC: 38 s, quadratic). Any input:
/// no node deeper than `MAX_DEPTH`, at most 4 triangle visits per triangle and level.
#[test]
fn build_depth_and_work_are_bounded() {
    let one = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    let n = 30_000;
    for tris in [vec![one; n], vec![[Vec3::ONE; 3]; n]] {
        let accel = Accel::build(&tris);
        assert!(accel.depth <= build::ceil_log2(n), "depth {}", accel.depth);
        assert!(accel.build_work <= (n * (accel.depth + 1)) as u64, "work {}", accel.build_work);
    }
    for case in [nested_case(), scale_series_case(), identical_case(&mut Rng::new(2))] {
        let accel = Accel::build(&case.tris);
        let n = case.tris.len();
        assert!(accel.depth <= build::MAX_DEPTH, "{}: depth {}", case.name, accel.depth);
        assert!(
            accel.build_work <= 4 * (n * (accel.depth + 1)) as u64,
            "{}: work {}",
            case.name,
            accel.build_work
        );
    }
}

/// Build time of 30,000 identical triangles (`cargo test --release -p opticks-core --lib
/// accel::tests::time_identical_build -- --ignored --nocapture`).
#[test]
#[ignore]
fn time_identical_build() {
    let one = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    for n in [30_000, 100_000] {
        let start = std::time::Instant::now();
        let accel = Accel::build(&vec![one; n]);
        eprintln!("{n} identical triangles: {:.4} s, depth {}", start.elapsed().as_secs_f64(), accel.depth);
    }
}

#[test]
fn bvh_agrees_with_brute_force_on_hostile_geometry() {
    let mut rng = Rng::new(1);
    let mut cases = sliver_cases();
    cases.push(huge_case(&mut rng));
    cases.push(tiny_case(&mut rng));
    cases.push(degenerate_case(&mut rng));
    cases.push(identical_case(&mut rng));
    cases.push(coplanar_case(&mut rng));
    cases.push(nested_case());
    cases.push(scale_series_case());
    let mut report = String::new();
    for case in &cases {
        // Also with SAH cut off at depth 3, so that most of the tree comes from median splits.
        for max_depth in [MAX_DEPTH, 3] {
            let accel = Accel::build_limited(&case.tris, max_depth);
            // The release-mode check passes (the queries did not fall back to brute force).
            let boxes: Vec<Aabb> = case.tris.iter().map(Aabb::of).collect();
            let built = build::build(&boxes, max_depth);
            let leaf_boxes: Vec<Aabb> = built.order.iter().map(|&i| boxes[i as usize]).collect();
            if let Err(e) = build::validate(&built.nodes, &leaf_boxes) {
                report += &format!("{} (SAH to depth {max_depth}): invalid tree: {e}\n", case.name);
            }
            let bound = max_depth.max(build::ceil_log2(case.tris.len()));
            if accel.depth > bound {
                report +=
                    &format!("{} (SAH to depth {max_depth}): depth {} > {bound}\n", case.name, accel.depth);
            }
            let bad = disagreements(&accel, case, 1500, &mut rng);
            if !bad.is_empty() {
                report += &format!(
                    "{} (SAH to depth {max_depth}): {} of 3000 queries wrong, e.g.\n",
                    case.name,
                    bad.len()
                );
                for b in bad.iter().take(3) {
                    report += &format!("    {b}\n");
                }
            }
        }
    }
    assert!(report.is_empty(), "BVH disagrees with brute force:\n{report}");
}

/// The release-mode check catches a box that misses a triangle and a triangle in two leaves.
#[test]
fn validation_catches_broken_trees() {
    let case = degenerate_case(&mut Rng::new(3));
    let boxes: Vec<Aabb> = case.tris.iter().map(Aabb::of).collect();
    let built = build::build(&boxes, MAX_DEPTH);
    let leaf_boxes: Vec<Aabb> = built.order.iter().map(|&i| boxes[i as usize]).collect();
    assert_eq!(build::validate(&built.nodes, &leaf_boxes), Ok(()));
    let leaf = built.nodes.iter().position(|n| n.count[0] > 1).unwrap();
    let mut shrunk = built.nodes.clone();
    let mut b = shrunk[leaf].bounds(0);
    b.hi = b.lo;
    let (first, count) = (shrunk[leaf].first[0], shrunk[leaf].count[0]);
    shrunk[leaf].set(0, &b, first, count);
    assert!(matches!(build::validate(&shrunk, &leaf_boxes), Err(build::Invalid::SlotOutsideLeaf { .. })));
    let mut twice = built.nodes.clone();
    twice[leaf].first[0] += 1;
    assert!(build::validate(&twice, &leaf_boxes).is_err());
}

/// Queries that overflow the small stack a query starts with and start again with a stack
/// sized for the tree give exactly the answer of one traversal with the full [`STACK`] from
/// the start: the same distance *and the same triangle* (ties between equal distances, as among
/// identical triangles, resolve alike), the same occlusion. With the [`SMALL_STACK`] of the
/// queries, overflows are rare (3 of these 8,000 rays), so this also runs the traversal with
/// small stacks of 1 to 4 entries, which overflow often (the test checks that they did).
#[test]
fn queries_that_outgrow_the_small_stack_answer_as_with_the_full_stack() {
    fn answers<const SMALL: usize>(accel: &Accel, ray: &Ray, shadow: &Ray) -> (Option<(u32, u32)>, bool) {
        let (q, qs) = (Query::new(ray), Query::new(shadow));
        let hit = accel.closest::<true, SMALL>(&q, ray.t_max).map(|(t, slot)| (t.to_bits(), slot));
        (hit, accel.any_hit::<true, SMALL>(&qs, shadow.t_max))
    }
    fn overflows<const SMALL: usize>(accel: &Accel, ray: &Ray) -> bool {
        let mut t_max = ray.t_max;
        accel.traverse_with::<true, true, SMALL>(&Query::new(ray), &mut t_max, &mut |_, _, _| false).is_none()
    }
    let mut rng = Rng::new(7);
    let mut overflowed = 0;
    for case in [identical_case(&mut rng), nested_case(), scale_series_case(), coplanar_case(&mut rng)] {
        for max_depth in [MAX_DEPTH, 3] {
            let accel = Accel::build_limited(&case.tris, max_depth);
            for _ in 0..1000 {
                let target = case.tris[case.targets[rng.index(case.targets.len())] as usize];
                let p = (target[0] + target[1] + target[2]) / 3.0;
                let dir = rng.direction();
                let distance = size_of(&target).max(f32::MIN_POSITIVE) * rng.log_range(0.5, 20.0);
                let ray = Ray { origin: p - dir * distance, dir, t_max: f32::INFINITY };
                let shadow = Ray { t_max: distance * rng.range(0.5, 1.5), ..ray };
                let full = answers::<STACK>(&accel, &ray, &shadow);
                assert_eq!(answers::<SMALL_STACK>(&accel, &ray, &shadow), full, "{}: {ray:?}", case.name);
                assert_eq!(answers::<1>(&accel, &ray, &shadow), full, "{}: {ray:?}", case.name);
                assert_eq!(answers::<2>(&accel, &ray, &shadow), full, "{}: {ray:?}", case.name);
                assert_eq!(answers::<4>(&accel, &ray, &shadow), full, "{}: {ray:?}", case.name);
                overflowed += usize::from(overflows::<2>(&accel, &ray));
            }
        }
    }
    assert!(overflowed > 500, "only {overflowed} queries outgrew a 2-entry stack: the test shows nothing");
}

/// A build that splits its nodes over threads makes the tree one thread makes, node for node
/// (subtrees are built in arenas of their own and appended: only the binary numbering differs,
/// and the 4-wide tree is laid out depth first from it).
#[test]
fn a_parallel_build_is_the_single_threaded_tree() {
    let mut rng = Rng::new(11);
    let mut tris: Vec<[Vec3; 3]> = (0..20_000)
        .map(|_| {
            let c = rng.point(Vec3::splat(-10.0), Vec3::splat(10.0));
            rng.triangle(c, 0.2)
        })
        .collect();
    tris.extend(identical_case(&mut rng).tris);
    let boxes: Vec<build::Aabb> = tris.iter().map(build::Aabb::of).collect();
    let one = build::build_with(&boxes, MAX_DEPTH, usize::MAX);
    let many = build::build_with(&boxes, MAX_DEPTH, 16);
    assert!(one.nodes.len() > 1000);
    assert_eq!(format!("{:?}", one.nodes), format!("{:?}", many.nodes));
    assert_eq!((one.order, one.depth, one.work), (many.order, many.depth, many.work));
}

/// A filtered query (a masked surface the ray passes through) answers as brute force over the
/// accepted triangles only: the traversal goes on behind a rejected hit, and a rejected
/// blocker does not block. Here every other triangle of a random soup is rejected.
#[test]
fn filtered_queries_skip_exactly_the_rejected_hits() {
    let mut rng = Rng::new(77);
    let mut corner = || Vec3::new(rng.f(), rng.f(), rng.f()) * 10.0;
    let soup: Vec<[Vec3; 3]> = (0..600)
        .map(|_| {
            let a = corner();
            [a, a + (corner() - Vec3::splat(5.0)) * 0.3, a + (corner() - Vec3::splat(5.0)) * 0.3]
        })
        .collect();
    let accel = Accel::build(&soup);
    let accepted: Vec<Tri> = soup.iter().step_by(2).map(Tri::new).collect();
    let accept = |prim: u32, _t: f32| prim.is_multiple_of(2);
    let mut rng = Rng::new(78);
    let (mut hits, mut skipped) = (0, 0);
    for _ in 0..4000 {
        let origin = Vec3::new(rng.f(), rng.f(), rng.f()) * 12.0 - Vec3::splat(1.0);
        let ray = Ray { origin, dir: rng.direction(), t_max: 4.0 + 20.0 * rng.f() };
        let (want_t, want_blocked) = brute_force(&accepted, &ray);
        let got = accel.intersect_where(&ray, accept);
        match got {
            Some((t, prim)) => {
                assert_eq!(t.to_bits(), want_t.to_bits(), "{ray:?}");
                assert!(prim.is_multiple_of(2));
                hits += 1;
            }
            None => assert!(!(want_t < ray.t_max), "{ray:?}: missed {want_t}"),
        }
        assert_eq!(accel.occluded_where(&ray, accept), want_blocked, "{ray:?}");
        if accel.intersect(&ray).is_some_and(|(_, p)| p % 2 == 1) {
            skipped += 1;
        }
    }
    assert!(hits > 500 && skipped > 500, "the test must see both: {hits} hits, {skipped} skipped");
}

/// `intersect_one` on the closest hit's triangle gives the closest hit's distance, bit for bit
/// (the visibility buffer's first hits rely on it), and misses a triangle the ray misses.
#[test]
fn one_triangle_test_gives_the_traversals_distance() {
    let mut rng = Rng::new(77);
    let tris: Vec<[Vec3; 3]> = (0..2000)
        .map(|_| {
            let c = rng.point(Vec3::splat(-5.0), Vec3::splat(5.0));
            rng.triangle(c, 0.8)
        })
        .collect();
    let accel = Accel::build(&tris);
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..20_000 {
        let ray = Ray {
            origin: rng.point(Vec3::splat(-6.0), Vec3::splat(6.0)),
            dir: rng.unit(),
            t_max: f32::INFINITY,
        };
        if let Some((t, prim)) = accel.intersect(&ray) {
            assert_eq!(accel.intersect_one(&ray, prim), Some(t));
            hits += 1;
        }
        let other = rng.index(tris.len()) as u32;
        if accel.intersect_one(&ray, other).is_none() {
            misses += 1;
        }
    }
    assert!(hits > 1000 && misses > 1000, "hits {hits}, misses {misses}");
    assert_eq!(
        accel.intersect_one(&Ray { origin: Vec3::ZERO, dir: Vec3::X, t_max: 1.0 }, tris.len() as u32),
        None
    );
}

/// No light leaks through the edge two triangles share: rays straight through a square's
/// diagonal, from either side, hit it (obvhs's sign-bit test let the back side's −0 pass).
#[test]
fn rays_through_a_shared_edge_hit_from_both_sides() {
    let accel = Accel::build(&quad(0.0));
    for k in 0..=20 {
        let s = -1.0 + 0.1 * k as f32;
        for (y, dir) in [(1.0f32, -Vec3::Y), (-1.0, Vec3::Y)] {
            let ray = Ray { origin: Vec3::new(s, y, s), dir, t_max: f32::INFINITY };
            let hit = accel.intersect(&ray);
            assert!(
                hit.is_some_and(|(t, _)| (t - 1.0).abs() < 1e-6),
                "through ({s}, {s}) from y = {y}: {hit:?}"
            );
            assert!(accel.occluded(&Ray { t_max: 2.0, ..ray }));
        }
    }
}

/// A closed room of two-triangle walls, each wall's corners in any order and either diagonal:
/// no ray from inside escapes, however exactly it meets an edge or a corner between walls or
/// triangles. The first ray is the one that escaped through the corner of CIE 171's façade room
/// before the test was watertight (Möller–Trumbore's edge tests round differently on the two
/// triangles of an edge, and both rejected it); the others are aimed at points on the edges,
/// at the corners, and at the diagonals, computed in f32 as a user's vertices would be.
#[test]
fn no_ray_leaves_a_closed_room_through_its_edges() {
    let corner = |i: usize| Vec3::new([-3.0, 3.0][i & 1], [-3.0, 3.0][i >> 1 & 1], [0.0, 3.0][i >> 2 & 1]);
    // The six walls as quads of corner indices (x, y, z bits), each in cyclic order.
    let walls: [[usize; 4]; 6] =
        [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]];
    let mut rng = Rng(RandomStream::new(5, &[1]));
    let exact = Ray {
        origin: Vec3::from_array([0u32, 3221225472, 931135488].map(f32::from_bits)),
        dir: Vec3::from_array([3210545452u32, 3197328244, 1054090064].map(f32::from_bits)),
        t_max: f32::INFINITY,
    };
    let mut escaped = Vec::new();
    for layout in 0..64 {
        // Each wall starts its quad at a random corner, cut along either diagonal, and each
        // triangle starts at a random vertex: the rounding differs with all three.
        let mut tris = Vec::new();
        let mut edges = Vec::new();
        for w in walls {
            let s = rng.index(4);
            let [a, b, c, d] = [0, 1, 2, 3].map(|i| corner(w[(s + i) % 4]));
            for t in [[a, b, c], [a, c, d]] {
                let r = rng.index(3);
                tris.push([t[r], t[(r + 1) % 3], t[(r + 2) % 3]]);
            }
            edges.extend([(a, b), (b, c), (c, d), (d, a), (a, c)]);
        }
        let accel = Accel::build(&tris);
        let mut rays = vec![exact];
        for _ in 0..2000 {
            let origin = rng.point(Vec3::new(-2.9, -2.9, 0.1), Vec3::new(2.9, 2.9, 2.9));
            let (a, b) = edges[rng.index(edges.len())];
            let target = match rng.index(4) {
                0 => a,
                _ => a + (b - a) * rng.f(),
            };
            rays.push(Ray { origin, dir: (target - origin).normalize(), t_max: f32::INFINITY });
        }
        for ray in rays {
            if accel.intersect(&ray).is_none() || !accel.occluded(&Ray { t_max: 100.0, ..ray }) {
                escaped.push(format!("layout {layout}: {ray:?}"));
            }
        }
    }
    assert!(
        escaped.is_empty(),
        "{} rays escaped, e.g. {:?}",
        escaped.len(),
        &escaped[..escaped.len().min(4)]
    );
}
