//! Tests of the MIS weights against the explicit formula.
//!
//! Random paths of 1–10 segments, with random per-vertex light-tracer and camera-tracer pdfs,
//! random delta vertices, random light kinds (area, point, directional, environment) and camera kinds
//! (pinhole, thin lens, equirectangular, orthographic), random counts and light-pick probabilities and both
//! heuristics. For each path the light side is walked from the light as the tracer will (and
//! stored through a [`MisRecord`]), the camera side from the camera as the renderer will, and
//! every strategy the renderer evaluates is weighted through the public API. A brute force, in
//! f64, builds each strategy's density as the product of the area densities of its light and
//! camera prefixes, counting the Dirac deltas each one samples: a strategy whose density has
//! fewer deltas than the path's contribution cannot produce the path (a connection at a delta
//! vertex, an emitter hit on a delta light), so nothing about which strategies are possible is
//! written into it by hand. It then applies w_s = (c_s p_s)^β / Σ_j (c_j p_j)^β.
//!
//! Checked: (1) every weight equals the brute force's; (2) the weights of a path sum to 1;
//! (3) the strategies the brute force finds impossible are exactly those the renderer skips
//! (or that the API weights 0). The mutants at the end show the check fails when the
//! recursion is wrong: SmallVCM's 1:1 counts, a dropped term, a lost class bit, one merged vc
//! sum, or the light-pick probability ignored. (The round trip of a record and the
//! heuristic's header byte are tested with them, in the dataset.)

use super::*;

/// SplitMix64: the tests' own generator, so they depend on nothing else in the crate.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f32 {
        (lo + (hi - lo) * self.uniform()) as f32
    }

    fn log_uniform(&mut self, lo: f64, hi: f64) -> f32 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.uniform()).exp() as f32
    }

    fn chance(&mut self, p: f64) -> bool {
        self.uniform() < p
    }

    fn below(&mut self, n: usize) -> usize {
        (self.uniform() * n as f64) as usize
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum CameraKind {
    Pinhole,
    ThinLens,
    Equirect,
    /// A delta direction whose rays start on the film with an area density (`cam_pdf_w` is
    /// then that area density).
    Orthographic,
}

const CAMERAS: [CameraKind; 4] =
    [CameraKind::Pinhole, CameraKind::ThinLens, CameraKind::Equirect, CameraKind::Orthographic];

/// Segment i joins x_i and x_{i+1}: squared length, |cos| at x_i and at x_{i+1}.
#[derive(Clone, Copy, Debug)]
struct Segment {
    dist2: f32,
    cos_a: f32,
    cos_b: f32,
}

/// A path x₀ (light) … x_k (camera) and every density any strategy needs.
#[derive(Clone, Debug)]
struct Path {
    light: LightKind,
    camera: CameraKind,
    /// Area light: area density of x₀; directional and environment: disk density; point: unused.
    pos_pdf: f32,
    /// Area and point lights: the emission direction's density toward x₁; environment: the
    /// solid-angle density of its direction x₀ (segment 0's length and cosine at x₀ unused).
    dir_pdf: f32,
    seg: Vec<Segment>,
    /// Per vertex (x₀ … x_k): a delta surface (only x₁ … x_{k−1} can be).
    delta: Vec<bool>,
    /// Per surface vertex x_i: the light tracer's density of x_i → x_{i+1} (arriving from x_{i−1}).
    l_fwd: Vec<f32>,
    /// Per surface vertex x_i: the camera tracer's density of x_i → x_{i−1} (arriving from x_{i+1}).
    c_fwd: Vec<f32>,
    /// The camera's image-wide density of the direction x_k → x_{k−1} (orthographic: of the
    /// ray's origin on the film, per unit area).
    cam_pdf_w: f32,
    /// The thin lens's area density of x_k.
    lens_pdf: f32,
}

impl Path {
    fn k(&self) -> usize {
        self.seg.len()
    }

    fn camera_pdf(&self) -> CameraPdf {
        match self.camera {
            CameraKind::Orthographic => CameraPdf::Area(self.cam_pdf_w),
            _ => CameraPdf::Solid(self.cam_pdf_w),
        }
    }

    fn emitter(&self) -> Emitter {
        match self.light {
            LightKind::Area => Emitter::area(self.pos_pdf, self.dir_pdf),
            LightKind::Point => Emitter::point(self.dir_pdf),
            LightKind::Directional => Emitter::directional(self.pos_pdf),
            LightKind::Environment => Emitter::environment(self.dir_pdf, self.pos_pdf),
        }
    }
}

/// The ranges densities, squared distances and cosines are drawn from (log-uniform for the
/// first two).
#[derive(Clone, Copy)]
struct Ranges {
    pdf: (f64, f64),
    dist2: (f64, f64),
    cos: (f64, f64),
}

const ORDINARY: Ranges = Ranges { pdf: (1e-2, 1e2), dist2: (1e-2, 1e2), cos: (0.02, 1.0) };
const EXTREME: Ranges = Ranges { pdf: (1e-5, 1e5), dist2: (1e-5, 1e5), cos: (1e-4, 1.0) };

fn random_path(rng: &mut Rng, r: Ranges) -> Path {
    let k = 1 + rng.below(10);
    let light =
        [LightKind::Area, LightKind::Point, LightKind::Directional, LightKind::Environment][rng.below(4)];
    let camera = CAMERAS[rng.below(CAMERAS.len())];
    let delta_rate = [0.0, 0.3, 0.7][rng.below(3)];
    let mut p = Path {
        light,
        camera,
        pos_pdf: rng.log_uniform(r.pdf.0, r.pdf.1),
        dir_pdf: rng.log_uniform(r.pdf.0, r.pdf.1),
        seg: Vec::new(),
        delta: vec![false; k + 1],
        l_fwd: vec![0.0; k + 1],
        c_fwd: vec![0.0; k + 1],
        cam_pdf_w: rng.log_uniform(r.pdf.0, r.pdf.1),
        lens_pdf: rng.log_uniform(r.pdf.0, r.pdf.1),
    };
    for _ in 0..k {
        let dist2 = rng.log_uniform(r.dist2.0, r.dist2.1);
        p.seg.push(Segment { dist2, cos_a: rng.range(r.cos.0, r.cos.1), cos_b: rng.range(r.cos.0, r.cos.1) });
    }
    for i in 1..k {
        p.delta[i] = rng.chance(delta_rate);
        if p.delta[i] {
            // A lobe's discrete probabilities; often (not always) the same both ways.
            p.l_fwd[i] = rng.range(0.1, 1.0);
            p.c_fwd[i] = if rng.chance(0.5) { p.l_fwd[i] } else { rng.range(0.1, 1.0) };
        } else {
            p.l_fwd[i] = rng.log_uniform(r.pdf.0, r.pdf.1);
            p.c_fwd[i] = rng.log_uniform(r.pdf.0, r.pdf.1);
        }
    }
    p
}

/// The render-time settings a path is weighted under.
#[derive(Clone, Copy, Debug)]
struct Render {
    heuristic: Heuristic,
    counts: Counts,
    pick: f32,
}

fn random_render(rng: &mut Rng, heuristic: Heuristic) -> Render {
    let counts =
        Counts { conn: rng.log_uniform(1e-2, 1e2) as f64, light_trace: rng.log_uniform(1e-3, 10.0) as f64 };
    Render { heuristic, counts, pick: rng.range(0.02, 1.0) }
}

/// What the brute force says of strategy s.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Truth {
    /// The estimator has no such strategy (the splat of a point or directional light's y₀).
    NotAStrategy,
    /// A strategy, but it cannot produce this path.
    Impossible,
    /// Its weight.
    Weight(f64),
}

/// A density and the number of Dirac deltas it carries.
#[derive(Clone, Copy, Debug)]
struct Density {
    value: f64,
    deltas: u32,
}

impl std::ops::Mul for Density {
    type Output = Density;
    fn mul(self, o: Density) -> Density {
        Density { value: self.value * o.value, deltas: self.deltas + o.deltas }
    }
}

const ONE: Density = Density { value: 1.0, deltas: 0 };

/// w_s = (c_s p_s)^β / Σ_j (c_j p_j)^β with p_j the product of the area densities of strategy
/// j's light prefix (light pick included) and camera prefix.
fn brute_force(path: &Path, render: Render) -> Vec<Truth> {
    let k = path.k();
    let (light, p) = (path.light, render.pick as f64);
    let seg = |i: usize| {
        let s = path.seg[i];
        (s.dist2 as f64, s.cos_a as f64, s.cos_b as f64)
    };
    let dens = |value: f64, delta: bool| Density { value, deltas: u32::from(delta) };
    // The light side's density of x_i (i < k), drawn from x_{i−1}.
    let fwd = |i: usize| match i {
        0 => match light {
            LightKind::Area => dens(p * path.pos_pdf as f64, false),
            LightKind::Point | LightKind::Directional => dens(p, true), // δ position or direction
            LightKind::Environment => dens(p * path.dir_pdf as f64, false), // solid angle
        },
        1 => {
            let (d2, _, cos1) = seg(0);
            match light {
                LightKind::Directional | LightKind::Environment => dens(path.pos_pdf as f64 * cos1, false),
                _ => dens(path.dir_pdf as f64 * cos1 / d2, false),
            }
        }
        i => {
            let (d2, _, cos) = seg(i - 1);
            dens(path.l_fwd[i - 1] as f64 * cos / d2, path.delta[i - 1])
        }
    };
    // The camera side's density of x_i, drawn from x_{i+1} (x_k: the lens).
    let rev = |i: usize| {
        if i == k {
            return match path.camera {
                CameraKind::ThinLens => dens(path.lens_pdf as f64, false),
                CameraKind::Pinhole | CameraKind::Equirect => dens(1.0, true), // δ position
                CameraKind::Orthographic => dens(1.0, true),                   // δ direction
            };
        }
        if i == 0 && light == LightKind::Environment {
            // A camera ray leaving the scene: its solid-angle density, no conversion.
            return if k == 1 {
                dens(path.cam_pdf_w as f64, false)
            } else {
                dens(path.c_fwd[1] as f64, path.delta[1])
            };
        }
        if i == 0 && light != LightKind::Area {
            return dens(0.0, false); // a direction or a point a camera ray never finds
        }
        let (d2, cos, _) = seg(i);
        if i == k - 1 && path.camera == CameraKind::Orthographic {
            return dens(path.cam_pdf_w as f64 * cos, false); // the film's area density, projected
        }
        let (pdf, delta) = if i == k - 1 {
            (path.cam_pdf_w as f64, false)
        } else {
            (path.c_fwd[i + 1] as f64, path.delta[i + 1])
        };
        dens(pdf * cos / d2, delta)
    };
    let product =
        |range: std::ops::Range<usize>, f: &dyn Fn(usize) -> Density| range.fold(ONE, |a, i| a * f(i));
    let (c_conn, c_lt) = (render.counts.conn, render.counts.light_trace);
    let strategies: Vec<Option<(f64, Density)>> = (0..=k)
        .map(|s| match s {
            0 => Some((1.0, product(0..k + 1, &rev))),
            1 if k >= 2 => Some((1.0, fwd(0) * product(1..k + 1, &rev))), // NEE draws x₀ as the light
            1 => (light == LightKind::Area).then(|| (c_lt, fwd(0) * rev(1))),
            s if s < k => Some((c_conn, product(0..s, &fwd) * product(s..k + 1, &rev))),
            _ => Some((c_lt, product(0..k, &fwd) * rev(k))),
        })
        .collect();
    let deltas = path.delta.iter().filter(|d| **d).count() as u32
        + u32::from(matches!(light, LightKind::Point | LightKind::Directional))
        + u32::from(path.camera != CameraKind::ThinLens);
    let beta = render.heuristic.exponent() as i32;
    let term = |c: f64, d: Density| (d.deltas == deltas && d.value > 0.0).then(|| (c * d.value).powi(beta));
    let total: f64 = strategies.iter().flatten().filter_map(|&(c, d)| term(c, d)).sum();
    strategies
        .iter()
        .map(|st| match *st {
            None => Truth::NotAStrategy,
            Some((c, d)) => term(c, d).map_or(Truth::Impossible, |t| Truth::Weight(t / total)),
        })
        .collect()
}

/// Ways of getting the recursion wrong, to show the check fails on them.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mutant {
    None,
    /// SmallVCM's pairing: one light path per camera path, so c_conn = c_LT = 1.
    SmallVcmCounts,
    /// The light-pick probability taken as 1.
    IgnorePick,
    /// The stored emitter-hit sum lost.
    DropHitTerm,
    /// The record's class bits lost (every vcm a connection's).
    NoClassBit,
    /// SmallVCM's single dVC: the three sums stored as one (weighted as connections).
    SingleVc,
    /// The orthographic camera's film density taken as a pinhole's solid-angle one (a 1/d²
    /// too many at the first camera hit).
    OrthographicAsPoint,
}

/// The trace-time record of a light vertex, as it comes back from the dataset.
fn stored(state: LightVertexMis, heuristic: Heuristic, mutant: Mutant) -> LightVertexMis {
    // The record's four f32 in their stored order (`MisRecord` is `repr(C)`), the class bits in
    // the signs of the first two.
    let [mut vcm, mut vc_hit, mut vc_nee, mut vc_conn]: [f32; 4] = bytemuck::cast(state.record());
    const SIGN: u32 = 1 << 31;
    let keep_sign = |x: f32| f32::from_bits(x.to_bits() & SIGN);
    let magnitude = |x: f32| f32::from_bits(x.to_bits() & !SIGN);
    match mutant {
        Mutant::DropHitTerm => vc_hit = keep_sign(vc_hit),
        Mutant::NoClassBit => (vcm, vc_hit) = (magnitude(vcm), magnitude(vc_hit)),
        Mutant::SingleVc => {
            // Records hold roots: power the three, sum them, store the root.
            let h = heuristic;
            let sum = h.mis(magnitude(vc_hit) as f64) + h.mis(vc_nee as f64) + h.mis(vc_conn as f64);
            vc_conn = h.root(sum) as f32;
            (vc_hit, vc_nee) = (keep_sign(vc_hit), 0.0);
        }
        Mutant::None | Mutant::SmallVcmCounts | Mutant::IgnorePick | Mutant::OrthographicAsPoint => {}
    }
    LightVertexMis::from_record(bytemuck::cast([vcm, vc_hit, vc_nee, vc_conn]), heuristic)
}

/// Every strategy's weight through the API, walking the light side from the light (the
/// tracer) and the camera side from the camera (the renderer); `None` where the renderer
/// evaluates nothing (no stored vertex, a delta camera vertex, no y₀).
fn recursive(path: &Path, render: Render, mutant: Mutant) -> Vec<Option<f32>> {
    let (k, h, e, seg) = (path.k(), render.heuristic, path.emitter(), &path.seg);
    let camera_pdf = match mutant {
        Mutant::OrthographicAsPoint => CameraPdf::Solid(path.cam_pdf_w),
        _ => path.camera_pdf(),
    };
    let (counts, pick) = match mutant {
        Mutant::SmallVcmCounts => (Counts { conn: 1.0, light_trace: 1.0 }, render.pick),
        Mutant::IgnorePick => (render.counts, 1.0),
        _ => (render.counts, render.pick),
    };
    // The tracer: a record at y₀ (area lights) and at every non-delta hit.
    let mut light: Vec<Option<LightVertexMis>> = vec![None; k];
    if path.light == LightKind::Area {
        light[0] = Some(stored(LightVertexMis::emission_vertex(e, h), h, mutant));
    }
    let mut l = LightVertexMis::at_emission(e, seg[0].cos_a, h);
    for i in 1..k {
        l = l.after_hit(seg[i - 1].dist2, seg[i - 1].cos_b);
        if !path.delta[i] {
            light[i] = Some(stored(l, h, mutant));
        }
        l = l.after_scatter(seg[i].cos_a, path.l_fwd[i], path.c_fwd[i], path.delta[i]);
    }
    // The camera path, x_{k−1} down to x₀.
    let mut camera = vec![CameraVertexMis::at_camera(CameraPdf::Solid(1.0), h); k];
    let mut c = CameraVertexMis::at_camera(camera_pdf, h);
    for i in (0..k).rev() {
        // An environment's x₀ is found by leaving the scene: the segment's state, unconverted.
        if i > 0 || path.light != LightKind::Environment {
            c = c.after_hit(seg[i].dist2, seg[i].cos_a);
        }
        camera[i] = c;
        if i > 0 {
            c = c.after_scatter(seg[i - 1].cos_b, path.c_fwd[i], path.l_fwd[i], path.delta[i]);
        }
    }
    let mut w = vec![None; k + 1];
    w[0] = Some(weight_emitter_hit(&camera[0], e, pick, counts)); // 0 for delta lights
    let splat = |y: &LightVertexMis, i: usize, rev: f32| {
        let end = ConnectionEnd { cos: seg[i].cos_a, pdf_fwd_w: 0.0, pdf_rev_w: rev };
        weight_light_trace(y, end, camera_pdf, seg[i].dist2, pick, counts)
    };
    if k == 1 {
        w[1] = light[0].map(|y0| splat(&y0, 0, 0.0));
        return w;
    }
    if !path.delta[1] {
        let end = ConnectionEnd { cos: seg[0].cos_b, pdf_fwd_w: path.c_fwd[1], pdf_rev_w: path.l_fwd[1] };
        w[1] = Some(weight_nee(&camera[1], end, e, seg[0].cos_a, seg[0].dist2, pick, counts));
    }
    for s in 2..k {
        if let (Some(y), false) = (light[s - 1], path.delta[s]) {
            let at_camera =
                ConnectionEnd { cos: seg[s - 1].cos_b, pdf_fwd_w: path.c_fwd[s], pdf_rev_w: path.l_fwd[s] };
            let at_light = ConnectionEnd {
                cos: seg[s - 1].cos_a,
                pdf_fwd_w: path.l_fwd[s - 1],
                pdf_rev_w: path.c_fwd[s - 1],
            };
            w[s] =
                Some(weight_connection(&camera[s], at_camera, &y, at_light, seg[s - 1].dist2, pick, counts));
        }
    }
    w[k] = light[k - 1].map(|y| splat(&y, k - 1, path.c_fwd[k - 1]));
    w
}

/// The worst disagreements over a set of paths.
#[derive(Clone, Copy, Debug, Default)]
struct Report {
    paths: usize,
    strategies: usize,
    /// max |w_api − w_exact| / max(w_exact, 10⁻⁶): relative, absolute for weights below 10⁻⁶.
    weight_error: f64,
    /// max |Σ_s w_s − 1|.
    sum_error: f64,
    /// Impossible strategies the API weighted non-zero, or possible ones it skipped.
    wrong_set: usize,
    /// Weights outside [0, 1] or NaN.
    out_of_range: usize,
}

fn check(path: &Path, render: Render, mutant: Mutant, report: &mut Report) {
    let exact = brute_force(path, render);
    let api = recursive(path, render, mutant);
    report.paths += 1;
    let mut sum = 0.0f64;
    let mut any = false;
    for (truth, got) in exact.iter().zip(&api) {
        if let Some(w) = got
            && !(0.0..=1.0).contains(w)
        {
            report.out_of_range += 1;
        }
        match (*truth, *got) {
            (Truth::Weight(w), Some(g)) => {
                report.strategies += 1;
                let err = (g as f64 - w).abs() / w.max(1e-6);
                report.weight_error = report.weight_error.max(err);
                sum += g as f64;
                any = true;
            }
            (Truth::Impossible, None | Some(0.0)) | (Truth::NotAStrategy, None) => {}
            _ => report.wrong_set += 1,
        }
    }
    if any {
        report.sum_error = report.sum_error.max((sum - 1.0).abs());
    }
}

fn run(seed: u64, paths: usize, ranges: Ranges, mutant: Mutant) -> Report {
    let mut rng = Rng(seed);
    let mut report = Report::default();
    for _ in 0..paths {
        let mut path = random_path(&mut rng, ranges);
        for heuristic in [Heuristic::Balance, Heuristic::Power] {
            // One trace-time record set, three renders (counts, light pick, camera kind).
            for _ in 0..3 {
                path.camera = CAMERAS[rng.below(CAMERAS.len())];
                check(&path, random_render(&mut rng, heuristic), mutant, &mut report);
            }
        }
    }
    report
}

#[test]
fn recursive_weights_equal_the_explicit_formula_and_sum_to_one() {
    let r = run(1, 20_000, ORDINARY, Mutant::None);
    eprintln!("ordinary ranges: {r:?}");
    assert!(r.strategies > 200_000, "{r:?}");
    // f64 recursion, f32 inputs, records and weights: a few f32 roundings (measured 1.6e-7).
    assert!(r.weight_error < 1e-6, "recursive weight ≠ explicit formula: {r:?}");
    assert!(r.sum_error < 1e-6, "weights do not sum to 1: {r:?}");
    assert_eq!(r.wrong_set, 0, "impossible strategies weighted, or possible ones skipped: {r:?}");
    assert_eq!(r.out_of_range, 0, "{r:?}");
}

#[test]
fn extreme_densities_give_no_nan_and_still_sum_to_one() {
    // Densities over ten decades and grazing cosines: the powered products leave f32's range
    // (an f32 recursion failed this test with weight errors of 1.0), f64's they do not, and the
    // records' roots fit f32.
    let r = run(2, 20_000, EXTREME, Mutant::None);
    eprintln!("extreme ranges: {r:?}");
    assert_eq!(r.out_of_range, 0, "{r:?}");
    assert_eq!(r.wrong_set, 0, "{r:?}");
    assert!(r.sum_error < 1e-5, "{r:?}");
    assert!(r.weight_error < 1e-5, "{r:?}");
}

#[test]
fn the_check_fails_on_wrong_recursions() {
    for mutant in [
        Mutant::SmallVcmCounts,
        Mutant::IgnorePick,
        Mutant::DropHitTerm,
        Mutant::NoClassBit,
        Mutant::SingleVc,
        Mutant::OrthographicAsPoint,
    ] {
        let r = run(3, 2_000, ORDINARY, mutant);
        eprintln!("{mutant:?}: {r:?}");
        assert!(r.weight_error > 1e-2, "{mutant:?} not detected: {r:?}");
        // Wrong counts still give a partition of unity (any consistent constants do): only the
        // comparison with the formula sees them. A wrong record breaks the sum too.
        // So does a consistent wrong camera density.
        let sums_break =
            !matches!(mutant, Mutant::SmallVcmCounts | Mutant::IgnorePick | Mutant::OrthographicAsPoint);
        assert_eq!(r.sum_error > 1e-2, sums_break, "{mutant:?}: {r:?}");
    }
}

#[test]
fn counts_follow_the_render() {
    // 4 connections per vertex, 10⁶ light paths that stored 2.5·10⁶ vertices, 320×240×16 camera paths.
    let c = Counts::new(4, 1_000_000, 2_500_000, 320 * 240 * 16);
    assert!((c.conn - 1.6).abs() < 1e-12);
    assert!((c.light_trace - 1e6 / 1_228_800.0).abs() < 1e-12);
    assert_eq!(Counts::new(4, 10, 0, 1).conn, 0.0);
}

#[test]
fn a_light_seen_directly_splits_between_hit_and_splat() {
    // k = 1: the camera sees an area light. Emitter hit: density of x₀ p_cam·cos/d² (count 1);
    // splat of y₀: P·p_pos (count c_LT). Balance heuristic by hand.
    let (pos_pdf, dir_pdf, cam_pdf_w, cos, d2, pick) = (0.5f32, 0.3f32, 2.0f32, 0.8f32, 4.0f32, 0.25f32);
    let counts = Counts { conn: 3.0, light_trace: 0.1 };
    let h = Heuristic::Balance;
    let hit_density = (cam_pdf_w * cos / d2) as f64;
    let splat_density = counts.light_trace * (pick * pos_pdf) as f64;
    let camera = CameraVertexMis::at_camera(CameraPdf::Solid(cam_pdf_w), h).after_hit(d2, cos);
    let w_hit = weight_emitter_hit(&camera, Emitter::area(pos_pdf, dir_pdf), pick, counts) as f64;
    let y0 = LightVertexMis::emission_vertex(Emitter::area(pos_pdf, dir_pdf), h);
    let end = ConnectionEnd { cos, pdf_fwd_w: 0.0, pdf_rev_w: 0.0 };
    let w_splat = weight_light_trace(&y0, end, CameraPdf::Solid(cam_pdf_w), d2, pick, counts) as f64;
    assert!((w_hit - hit_density / (hit_density + splat_density)).abs() < 1e-6);
    assert!((w_splat - splat_density / (hit_density + splat_density)).abs() < 1e-6);
    // A point light is never hit.
    assert_eq!(weight_emitter_hit(&camera, Emitter::point(dir_pdf), pick, counts), 0.0);
    // An orthographic camera (film area density p_A) finds x₀ with density p_A·cos: no 1/d².
    let p_film = 0.7f32;
    let hit_density = (p_film * cos) as f64;
    let camera = CameraVertexMis::at_camera(CameraPdf::Area(p_film), h).after_hit(d2, cos);
    let w_hit = weight_emitter_hit(&camera, Emitter::area(pos_pdf, dir_pdf), pick, counts) as f64;
    let w_splat = weight_light_trace(&y0, end, CameraPdf::Area(p_film), d2, pick, counts) as f64;
    assert!((w_hit - hit_density / (hit_density + splat_density)).abs() < 1e-6);
    assert!((w_splat - splat_density / (hit_density + splat_density)).abs() < 1e-6);
}
