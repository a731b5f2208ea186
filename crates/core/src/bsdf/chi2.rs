//! Test-only statistical harness for BSDF sampling (compiled under `#[cfg(test)]`).
//!
//! A sampling routine and its claimed density must agree; a mismatch silently biases every
//! render. [`Chi2Test`] checks it the way Mitsuba and PBRT do: draw many samples, bin them over a
//! grid covering the whole sphere, integrate the claimed pdf over each cell to get the expected
//! counts, pool sparse cells and run Pearson's χ² goodness-of-fit test. It also checks that every
//! sample lands where the pdf is positive, that the pdf the sampler reports equals the pdf
//! function, and that the pdf integrates to the fraction of calls that returned a sample.
//!
//! Narrow lobes (Phong exponents up to 10⁵, lobes a few milliradians wide) and lobes cut by the
//! horizon (grazing incidence) make both binning and integration hard. Hence:
//! * [`SphereGrid`] is a (θ, φ) grid about a chosen axis (the lobe axis). Its θ edges are
//!   quantiles of the angle to the axis in an independent *pilot* batch of samples, merged with
//!   uniform edges: the cells follow the lobe whatever its width, and since the pilot is
//!   independent of the tested samples the χ² statistic stays valid.
//! * Cell integrals use 5×5 Gauss–Legendre quadrature (in θ, φ with the sin θ Jacobian) refined
//!   adaptively (quad-tree subdivision until parent and children agree to a relative 10⁻⁴; the
//!   expected counts of a χ² test only to a small fraction of each cell's Poisson noise). The
//!   horizon, where a BSDF's pdf jumps to zero and which cuts through cells of a grid tilted
//!   towards a grazing reflection direction, is handled exactly instead: for each φ node the θ
//!   interval is split where the horizon crosses it, so no cell integrates across a jump.
//!
//! The p-value comes from the regularised upper incomplete gamma function Q(k/2, χ²/2)
//! ([`chi2_survival`]), written here (series + Lentz continued fraction, Lanczos ln Γ). A test
//! fails when p < 0.01 / [`CHI2_FAMILY`] (Bonferroni over all χ² tests of the crate).
//!
//! The same grid and integrator also give accurate directional albedos ([`directional_albedo`]).
//! [`incident`] and [`reflect`] are the test directions the BSDF tests share.

use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::RandomStream;
use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// Upper bound on the number of χ² tests run by the crate's test suite; the Bonferroni
/// correction divides the 1 % family-wise significance by it.
pub(crate) const CHI2_FAMILY: usize = 96;

/// Per-test significance level (Bonferroni-corrected).
pub(crate) const ALPHA: f64 = 0.01 / CHI2_FAMILY as f64;

/// Gauss–Legendre nodes and weights, 5 points on [−1, 1].
const GL_X: [f64; 5] =
    [-0.906_179_845_938_664, -0.538_469_310_105_683_1, 0.0, 0.538_469_310_105_683_1, 0.906_179_845_938_664];
const GL_W: [f64; 5] = [
    0.236_926_885_056_189_1,
    0.478_628_670_499_366_5,
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_5,
    0.236_926_885_056_189_1,
];

/// Relative tolerance of a cell integral, and the absolute floor (in probability).
const REL_TOL: f64 = 1e-4;
const ABS_TOL: f64 = 1e-10;
/// Quad-tree depth limits of the adaptive integration.
const MIN_DEPTH: u32 = 1;
const MAX_DEPTH: u32 = 10;

/// A grid of cells [θ_k, θ_{k+1}] × [φ_j, φ_{j+1}] covering the sphere, in spherical coordinates
/// about `axis` (θ = angle to the axis, φ measured in a fixed frame around it), with an optional
/// plane across which integrands may be discontinuous (see [`SphereGrid::with_discontinuity`]).
pub(crate) struct SphereGrid {
    s: DVec3,
    t: DVec3,
    a: DVec3,
    theta_edges: Vec<f64>,
    phi_bins: usize,
    discontinuity: Option<DVec3>,
}

impl SphereGrid {
    /// A grid with explicit θ edges (must start at 0, end at π, increase) and `phi_bins` uniform
    /// φ bins.
    pub(crate) fn new(axis: Vec3, theta_edges: Vec<f64>, phi_bins: usize) -> Self {
        assert!(theta_edges.len() >= 2 && theta_edges[0] == 0.0 && *theta_edges.last().unwrap() == PI);
        assert!(theta_edges.windows(2).all(|w| w[0] < w[1]) && phi_bins > 0);
        let a = axis.as_dvec3().normalize();
        // Duff et al. 2017 orthonormal basis, in f64.
        let sign = 1.0f64.copysign(a.z);
        let p = -1.0 / (sign + a.z);
        let b = a.x * a.y * p;
        let s = DVec3::new(1.0 + sign * a.x * a.x * p, sign * b, -sign * a.x);
        let t = DVec3::new(b, sign + a.y * a.y * p, -a.y);
        SphereGrid { s, t, a, theta_edges, phi_bins, discontinuity: Some(DVec3::Z) }
    }

    /// A grid adapted to a distribution: θ edges at the `theta_bins` quantiles of the angle to
    /// `axis` among `pilot` directions, plus uniform edges every π/16 (so broad regions are
    /// resolved too). `pilot` must be independent of the samples later binned on this grid.
    pub(crate) fn adapted(axis: Vec3, pilot: &[Vec3], theta_bins: usize, phi_bins: usize) -> Self {
        let mut grid = SphereGrid::new(axis, vec![0.0, PI], phi_bins);
        let mut angles: Vec<f64> = pilot.iter().map(|&v| grid.angles(v).0).collect();
        angles.sort_by(f64::total_cmp);
        let mut edges: Vec<f64> = (0..=16).map(|k| PI * k as f64 / 16.0).collect();
        if !angles.is_empty() {
            edges.extend((1..theta_bins).map(|k| angles[k * angles.len() / theta_bins]));
        }
        edges.sort_by(f64::total_cmp);
        edges.dedup_by(|b, a| *b - *a < 1e-7);
        *edges.last_mut().unwrap() = PI;
        grid.theta_edges = edges;
        grid
    }

    /// Declares the plane (through the origin, given by its normal) across which the integrand
    /// may jump; `None` if it is smooth. Defaults to the surface, normal z, where every
    /// reflection-only BSDF drops to zero.
    pub(crate) fn with_discontinuity(mut self, normal: Option<Vec3>) -> Self {
        self.discontinuity = normal.map(|n| n.as_dvec3().normalize());
        self
    }

    /// Number of cells.
    pub(crate) fn cells(&self) -> usize {
        (self.theta_edges.len() - 1) * self.phi_bins
    }

    /// (θ, φ) of a direction, θ ∈ [0, π], φ ∈ [0, 2π).
    fn angles(&self, v: Vec3) -> (f64, f64) {
        let v = v.as_dvec3().normalize();
        let theta = v.cross(self.a).length().atan2(v.dot(self.a));
        let phi = v.dot(self.t).atan2(v.dot(self.s)).rem_euclid(TAU);
        (theta, phi)
    }

    /// The cell containing direction `v`.
    pub(crate) fn cell_of(&self, v: Vec3) -> usize {
        let (theta, phi) = self.angles(v);
        let k = self.theta_edges.partition_point(|&e| e <= theta).clamp(1, self.theta_edges.len() - 1) - 1;
        let j = ((phi / TAU * self.phi_bins as f64) as usize).min(self.phi_bins - 1);
        k * self.phi_bins + j
    }

    /// Unit direction at (θ, φ), given (sin θ, cos θ, sin φ, cos φ).
    fn dir_from(&self, st: f64, ct: f64, sp: f64, cp: f64) -> Vec3 {
        (self.s * (st * cp) + self.t * (st * sp) + self.a * ct).as_vec3()
    }

    /// 5×5 Gauss–Legendre estimate of ∫∫ f sin θ dθ dφ over one rectangle. For each φ node the
    /// θ interval is split where the great circle of the discontinuity plane crosses it, so an
    /// integrand that jumps there (a BSDF at the horizon) is integrated as two smooth pieces.
    /// The sines and cosines of the nodes are computed once per node, not once per point.
    fn gauss(&self, f: &impl Fn(Vec3) -> DVec3, th: (f64, f64), ph: (f64, f64)) -> DVec3 {
        let (hph, cph) = (0.5 * (ph.1 - ph.0), 0.5 * (ph.1 + ph.0));
        // θ nodes of an interval: (sin θ, cos θ) and the weight w·h·sin θ.
        let nodes = |a: f64, b: f64| -> [(f64, f64, f64); 5] {
            let (hth, cth) = (0.5 * (b - a), 0.5 * (b + a));
            std::array::from_fn(|i| {
                let (st, ct) = (cth + hth * GL_X[i]).sin_cos();
                (st, ct, GL_W[i] * hth * st)
            })
        };
        let uncut = nodes(th.0, th.1);
        let mut sum = DVec3::ZERO;
        for (xj, wj) in GL_X.iter().zip(GL_W) {
            let phi = cph + hph * xj;
            let (sp, cp) = phi.sin_cos();
            let mut cuts = [th.0, th.1, th.1, th.1];
            let mut pieces = 1;
            if let Some(c) = self.discontinuity {
                // v(θ)·c = A cos θ + B sin θ = R cos(θ − δ) vanishes at θ = δ + π/2 + kπ.
                let delta = (self.s * cp + self.t * sp).dot(c).atan2(self.a.dot(c));
                for k in -2..=1 {
                    let x = delta + 0.5 * PI + k as f64 * PI;
                    if x > th.0 && x < th.1 && pieces < 3 {
                        cuts[pieces] = x;
                        pieces += 1;
                    }
                }
                cuts[..=pieces].sort_by(f64::total_cmp);
                cuts[pieces] = th.1;
            }
            let mut col = DVec3::ZERO;
            for piece in cuts[..=pieces].windows(2) {
                let cut;
                let piece_nodes = if pieces == 1 {
                    &uncut
                } else {
                    cut = nodes(piece[0], piece[1]);
                    &cut
                };
                for &(st, ct, w) in piece_nodes {
                    col += f(self.dir_from(st, ct, sp, cp)) * w;
                }
            }
            sum += col * wj;
        }
        sum * hph
    }

    /// Adaptive quad-tree refinement of a rectangle whose coarse estimate is `whole`.
    fn adaptive(
        &self,
        f: &impl Fn(Vec3) -> DVec3,
        th: (f64, f64),
        ph: (f64, f64),
        whole: DVec3,
        tol: f64,
        depth: u32,
    ) -> DVec3 {
        let (tm, pm) = (0.5 * (th.0 + th.1), 0.5 * (ph.0 + ph.1));
        let quads = [
            ((th.0, tm), (ph.0, pm)),
            ((th.0, tm), (pm, ph.1)),
            ((tm, th.1), (ph.0, pm)),
            ((tm, th.1), (pm, ph.1)),
        ];
        let parts = quads.map(|(t, p)| self.gauss(f, t, p));
        let sum: DVec3 = parts.iter().sum();
        let converged = (sum - whole).abs().max_element() <= tol;
        if depth >= MAX_DEPTH || (depth >= MIN_DEPTH && converged) {
            return sum;
        }
        quads
            .iter()
            .zip(parts)
            .map(|(&(t, p), part)| self.adaptive(f, t, p, part, 0.5 * tol, depth + 1))
            .sum()
    }

    /// ∫ f dω over every cell (same order as [`Self::cell_of`]), each to a relative accuracy of
    /// about 10⁻⁵. Cells are integrated in parallel; each one's result does not depend on the
    /// others or on the thread count.
    pub(crate) fn integrate_cells(&self, f: impl Fn(Vec3) -> DVec3 + Sync) -> Vec<DVec3> {
        self.integrate_cells_within(f, |_| 0.0)
    }

    /// [`Self::integrate_cells`], each cell also allowed an absolute error of `tol(v)`, v the
    /// coarse estimate of its integral's largest channel.
    fn integrate_cells_within(
        &self,
        f: impl Fn(Vec3) -> DVec3 + Sync,
        tol: impl Fn(f64) -> f64 + Sync,
    ) -> Vec<DVec3> {
        let dphi = TAU / self.phi_bins as f64;
        (0..self.cells())
            .into_par_iter()
            .map(|cell| {
                let (k, j) = (cell / self.phi_bins, cell % self.phi_bins);
                let th = (self.theta_edges[k], self.theta_edges[k + 1]);
                let ph = (j as f64 * dphi, (j + 1) as f64 * dphi);
                let whole = self.gauss(&f, th, ph);
                let v = whole.abs().max_element();
                let tol = (REL_TOL * v).max(ABS_TOL).max(tol(v));
                self.adaptive(&f, th, ph, whole, tol, 0)
            })
            .collect()
    }

    /// ∫ f dω over the whole sphere.
    pub(crate) fn integrate(&self, f: impl Fn(Vec3) -> DVec3 + Sync) -> DVec3 {
        self.integrate_cells(f).iter().sum()
    }
}

/// Incident direction at polar angle `deg` from the normal, azimuth 0.3 rad.
pub(crate) fn incident(deg: f32) -> Vec3 {
    let (st, ct) = deg.to_radians().sin_cos();
    Vec3::new(st * 0.3f32.cos(), st * 0.3f32.sin(), ct)
}

/// The direction at polar angle θ and azimuth φ (degrees): how the Mitsuba value tables
/// (`tools/mitsuba/*_values.py`) name directions.
pub(crate) fn direction((theta, phi): (f32, f32)) -> Vec3 {
    let (st, ct) = theta.to_radians().sin_cos();
    let (sp, cp) = phi.to_radians().sin_cos();
    Vec3::new(st * cp, st * sp, ct)
}

/// χ² of each of `cases`' samples against its `pdf` at normal, oblique and grazing incidence
/// (0°, 50°, 85°), the tests' seeds counted from `seed`, a failure named `name`, case, angle.
pub(crate) fn chi2_at_three_incidences(cases: &[super::Bsdf], seed: u64, name: &str) {
    let items: Vec<(usize, f32)> =
        (0..cases.len()).flat_map(|b| [0.0, 50.0, 85.0].map(move |d| (b, d))).collect();
    items.into_par_iter().enumerate().for_each(|(i, (k, deg))| {
        let b = &cases[k];
        let wi = incident(deg);
        let mode = super::TransportMode::Radiance;
        Chi2Test::new(Vec3::Z, seed + i as u64)
            .run(|ul, u| b.sample(wi, ul, u, mode).map(|s| (s.wo, s.pdf)), |wo| b.pdf(wi, wo))
            .assert_ok(&format!("{name} {k} θi={deg}°"));
    });
}

/// Whether `ours` is Mitsuba's `theirs` within 2·10⁻⁴ relative (+10⁻⁶): f32 rounding.
pub(crate) fn close_to_mitsuba(ours: f32, theirs: f32) -> bool {
    (ours - theirs).abs() <= 2e-4 * theirs.abs() + 1e-6
}

/// Asserts every channel of `ours` [`close_to_mitsuba`] to Mitsuba's `theirs`; `what` names the
/// value (case, directions, which f) in a failure.
pub(crate) fn assert_rgb_close_to_mitsuba(ours: Rgb, theirs: [f32; 3], what: &str) {
    for c in 0..3 {
        assert!(
            close_to_mitsuba(ours[c], theirs[c]),
            "{what} ch {c}: {} vs Mitsuba's {}",
            ours[c],
            theirs[c]
        );
    }
}

/// χ² of each of `cases`' samples (importance mode) against its `pdf` over the sphere, from
/// each of `wis` (either face), axis −wi, case k and direction j drawing stream seed + 10k + j.
pub(crate) fn chi2_from_directions(cases: &[super::Bsdf], wis: &[Vec3], seed: u64, name: &str) {
    let runs: Vec<(usize, usize)> =
        (0..cases.len()).flat_map(|k| (0..wis.len()).map(move |j| (k, j))).collect();
    runs.into_par_iter().for_each(|(k, j)| {
        let (b, wi) = (&cases[k], wis[j]);
        let mode = super::TransportMode::Importance;
        Chi2Test::new(-wi, seed + 10 * k as u64 + j as u64)
            .run(|ul, u| b.sample(wi, ul, u, mode).map(|s| (s.wo, s.pdf)), |wo| b.pdf(wi, wo))
            .assert_ok(&format!("{name} {k} wi={wi}"));
    });
}

/// For one-sided, reflecting, non-delta `cases` whose f is symmetric in its two directions
/// (so that the adjoint is f itself): reciprocity f(wi → wo) = f(wo → wi) within 10⁻⁴, every
/// sample's weight eval·cos/pdf within 10⁻⁵, its pdf the one `pdf` gives, nothing sampled
/// below the surface or from below it (5000 direction pairs a case, stream `seed`).
pub(crate) fn assert_reciprocal_and_consistent(cases: &[super::Bsdf], seed: u64) {
    let mode = super::TransportMode::Radiance;
    let mut rng = RandomStream::new(seed, &[]);
    for b in cases {
        for _ in 0..5_000 {
            let wi = crate::sampling::warp::square_to_uniform_hemisphere(rng.next_2d());
            let wo = crate::sampling::warp::square_to_uniform_hemisphere(rng.next_2d());
            let (f, g) = (b.eval(wi, wo), b.eval(wo, wi));
            assert!((f - g).abs().max_element() <= 1e-4 * f.max_element().max(1e-6), "{f} {g}");
            let Some(s) = b.sample(wi, rng.next_f32(), rng.next_2d(), mode) else { continue };
            let w = b.eval(wi, s.wo) * s.wo.z / s.pdf;
            assert!((s.weight - w).abs().max_element() <= 1e-5 * w.max_element() + 1e-30, "{s:?} {w}");
            assert!(!s.delta && s.wo.z > 0.0);
            assert_eq!(b.pdf(wi, s.wo), s.pdf);
        }
        assert!(b.sample(-Vec3::Z, 0.5, Vec2::splat(0.5), mode).is_none(), "one-sided");
    }
}

/// The mirror direction of `wi` about the shading normal (+z).
pub(crate) fn reflect(wi: Vec3) -> Vec3 {
    Vec3::new(-wi.x, -wi.y, wi.z)
}

/// Directions from `count` calls of a sampler, `None`s skipped (for [`SphereGrid::adapted`]).
pub(crate) fn pilot(
    mut sample: impl FnMut(f32, Vec2) -> Option<(Vec3, f32)>,
    count: usize,
    seed: u64,
) -> Vec<Vec3> {
    let mut rng = RandomStream::new(seed, &[0x9117]);
    (0..count).filter_map(|_| sample(rng.next_f32(), rng.next_2d()).map(|(v, _)| v)).collect()
}

/// Directional albedo ∫ f(wo)·max(0, cos θ_o) dω_o per channel, by adaptive quadrature on `grid`
/// (local frame, z = normal).
/// The mean of `m` sample weights (a failed sample weighs 0) with its standard error per
/// channel: the Monte Carlo estimate of a BSDF's directional albedo that its sampling gives, to
/// compare with [`directional_albedo`] of its evaluation.
pub(crate) fn mean_sample_weight(m: usize, mut weight: impl FnMut() -> Option<Rgb>) -> (DVec3, DVec3) {
    let (mut sum, mut sum2) = (DVec3::ZERO, DVec3::ZERO);
    for _ in 0..m {
        if let Some(w) = weight() {
            let w = w.as_dvec3();
            sum += w;
            sum2 += w * w;
        }
    }
    let mean = sum / m as f64;
    let se = ((sum2 / m as f64 - mean * mean).max(DVec3::ZERO) / m as f64).powf(0.5);
    (mean, se)
}

pub(crate) fn directional_albedo(grid: &SphereGrid, f: impl Fn(Vec3) -> Rgb + Sync) -> DVec3 {
    grid.integrate(|wo| f(wo).as_dvec3() * wo.z.max(0.0) as f64)
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, n = 9; relative error ~1e-15).
pub(crate) fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x)Γ(1−x) = π / sin(πx).
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let a = C[0] + (1..9).map(|i| C[i] / (x + i as f64)).sum::<f64>();
    let t = x + 7.5;
    0.5 * TAU.ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Regularised upper incomplete gamma Q(a, x) = Γ(a, x)/Γ(a), for a > 0, x ≥ 0 (Numerical
/// Recipes: power series for x < a + 1, Lentz's continued fraction otherwise).
pub(crate) fn gamma_q(a: f64, x: f64) -> f64 {
    assert!(a > 0.0 && x >= 0.0, "gamma_q({a}, {x})");
    if x == 0.0 {
        return 1.0;
    }
    let prefactor = (-x + a * x.ln() - ln_gamma(a)).exp();
    if x < a + 1.0 {
        // P(a, x) = e^{−x} x^a / Γ(a) · Σ x^k / (a (a+1) … (a+k)).
        let (mut ap, mut term) = (a, 1.0 / a);
        let mut sum = term;
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * prefactor).clamp(0.0, 1.0)
    } else {
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + an / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (prefactor * h).clamp(0.0, 1.0)
    }
}

/// P(X ≥ `statistic`) for X ~ χ² with `dof` degrees of freedom.
pub(crate) fn chi2_survival(statistic: f64, dof: usize) -> f64 {
    gamma_q(0.5 * dof as f64, 0.5 * statistic.max(0.0))
}

/// Configuration of one χ² goodness-of-fit test.
#[derive(Clone, Debug)]
pub(crate) struct Chi2Test {
    /// Pole of the grid: put it on the lobe axis (reflection direction, or the normal).
    pub axis: Vec3,
    /// Number of tested samples.
    pub samples: usize,
    /// Size of the independent pilot batch that places the θ edges.
    pub pilot: usize,
    /// Quantile θ bands (merged with 16 uniform ones).
    pub theta_bins: usize,
    /// Uniform φ bins.
    pub phi_bins: usize,
    /// Seed of the random streams.
    pub seed: u64,
    /// Cells with fewer expected samples are pooled.
    pub min_expected: f64,
}

impl Chi2Test {
    /// Defaults: 10⁶ samples, 5·10⁴ pilot samples, 16 quantile bands × 24 φ bins.
    pub(crate) fn new(axis: Vec3, seed: u64) -> Self {
        Chi2Test {
            axis,
            samples: 1_000_000,
            pilot: 50_000,
            theta_bins: 16,
            phi_bins: 24,
            seed,
            min_expected: 5.0,
        }
    }

    /// Runs the test: `sample(u_lobe, u)` returns a direction and the pdf it claims; `pdf(wo)`
    /// is the density to test against. The samples are drawn (in order, from one stream) while
    /// the expected counts are integrated on the other threads.
    pub(crate) fn run(
        &self,
        mut sample: impl FnMut(f32, Vec2) -> Option<(Vec3, f32)> + Send,
        pdf: impl Fn(Vec3) -> f32 + Sync,
    ) -> Chi2Report {
        let grid = SphereGrid::adapted(
            self.axis,
            &pilot(&mut sample, self.pilot, self.seed ^ 0xa5a5),
            self.theta_bins,
            self.phi_bins,
        );
        let n = self.samples as f64;
        // Each cell's expected count needs to be exact only to a small fraction of its Poisson
        // standard deviation √(n·p): a cell of probability p may be off by c·√(p/n), c at most
        // 1 %, which moves the expected χ² by Σ c² ≤ 10⁻⁴ per cell. c is also small enough that
        // the errors of all cells add up to at most 10⁻⁴ of ∫pdf (Σ √(p/n) ≤ √(cells/n)), half
        // of what `integral_mismatch` allows the quadrature.
        let c = 0.01f64.min(1e-4 * (n / grid.cells() as f64).sqrt());
        let (counts, expected) = rayon::join(
            || self.draw(&grid, sample, &pdf),
            || -> Vec<f64> {
                grid.integrate_cells_within(|v| DVec3::splat(pdf(v) as f64), |p| c * (p / n).sqrt())
                    .iter()
                    .map(|cell| cell.x * n)
                    .collect()
            },
        );
        let Counts { observed, accepted, zero_pdf, pdf_mismatch, bad_dir } = counts;
        let integral = expected.iter().sum::<f64>() / n;

        // Pool sparse cells (in increasing order of expectation) until each pool expects ≥ min.
        let mut order: Vec<usize> = (0..expected.len()).collect();
        order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
        let mut bins: Vec<(f64, f64)> = Vec::new();
        let (mut pool_e, mut pool_o) = (0.0, 0.0);
        for &i in &order {
            let (e, o) = (expected[i], observed[i] as f64);
            if e >= self.min_expected && pool_e == 0.0 && pool_o == 0.0 {
                bins.push((e, o));
                continue;
            }
            pool_e += e;
            pool_o += o;
            if pool_e >= self.min_expected {
                bins.push((pool_e, pool_o));
                (pool_e, pool_o) = (0.0, 0.0);
            }
        }
        if pool_e > 0.0 || pool_o > 0.0 {
            match bins.first_mut() {
                Some(b) => *b = (b.0 + pool_e, b.1 + pool_o),
                None => bins.push((pool_e, pool_o)),
            }
        }
        let statistic: f64 = bins
            .iter()
            .map(|&(e, o)| {
                if e > 0.0 {
                    (o - e) * (o - e) / e
                } else if o > 0.0 {
                    f64::INFINITY
                } else {
                    0.0
                }
            })
            .sum();
        let dof = bins.len().saturating_sub(1).max(1);
        let p_value = if statistic.is_finite() { chi2_survival(statistic, dof) } else { 0.0 };
        Chi2Report {
            statistic,
            dof,
            p_value,
            accepted_fraction: accepted as f64 / n,
            integral,
            samples: self.samples,
            zero_pdf,
            pdf_mismatch,
            bad_dir,
        }
    }
}

/// What [`Chi2Test::draw`] counted.
struct Counts {
    observed: Vec<u64>,
    accepted: usize,
    zero_pdf: usize,
    pdf_mismatch: usize,
    bad_dir: usize,
}

impl Chi2Test {
    /// Draws the tested samples and bins them on `grid`, checking each against `pdf`.
    fn draw(
        &self,
        grid: &SphereGrid,
        mut sample: impl FnMut(f32, Vec2) -> Option<(Vec3, f32)>,
        pdf: &impl Fn(Vec3) -> f32,
    ) -> Counts {
        let mut c = Counts {
            observed: vec![0u64; grid.cells()],
            accepted: 0,
            zero_pdf: 0,
            pdf_mismatch: 0,
            bad_dir: 0,
        };
        let mut rng = RandomStream::new(self.seed, &[0xc412]);
        for _ in 0..self.samples {
            let Some((wo, p)) = sample(rng.next_f32(), rng.next_2d()) else { continue };
            c.accepted += 1;
            if !wo.is_finite() || (wo.length() - 1.0).abs() > 1e-4 {
                c.bad_dir += 1;
                continue;
            }
            let q = pdf(wo);
            if q.is_nan() || q <= 0.0 {
                c.zero_pdf += 1;
            }
            let agrees = (p - q).abs() <= 1e-4 * q.abs().max(p.abs());
            if !agrees {
                c.pdf_mismatch += 1;
            }
            c.observed[grid.cell_of(wo)] += 1;
        }
        c
    }
}

/// Outcome of a [`Chi2Test`].
#[derive(Clone, Debug)]
pub(crate) struct Chi2Report {
    /// Pearson's statistic over the pooled bins.
    pub statistic: f64,
    /// Degrees of freedom (pooled bins − 1).
    pub dof: usize,
    /// P(χ²_dof ≥ statistic).
    pub p_value: f64,
    /// Fraction of sampler calls that returned a direction.
    pub accepted_fraction: f64,
    /// ∫ pdf over the sphere (numerical).
    pub integral: f64,
    /// Number of sampler calls.
    pub samples: usize,
    /// Samples where the pdf function is not positive.
    pub zero_pdf: usize,
    /// Samples whose reported pdf differs from the pdf function (relative 10⁻⁴).
    pub pdf_mismatch: usize,
    /// Samples whose direction is not a finite unit vector.
    pub bad_dir: usize,
}

impl Chi2Report {
    /// Whether the χ² test rejects the hypothesis "samples follow the pdf" at [`ALPHA`].
    pub(crate) fn chi2_rejects(&self) -> bool {
        self.p_value.is_nan() || self.p_value < ALPHA
    }

    /// Whether ∫ pdf differs from the accepted fraction by more than sampling noise (5σ of the
    /// binomial acceptance) plus quadrature error, or exceeds 1.
    pub(crate) fn integral_mismatch(&self) -> bool {
        let f = self.accepted_fraction;
        let sigma = (f * (1.0 - f) / self.samples as f64).sqrt();
        let ok = (self.integral - f).abs() <= 5.0 * sigma + 2e-4 && self.integral <= 1.0 + 2e-4;
        !ok
    }

    /// Every failed check, as messages (empty if the sampler and pdf agree).
    pub(crate) fn failures(&self) -> Vec<String> {
        let mut out = Vec::new();
        if self.chi2_rejects() {
            out.push(format!(
                "χ² = {:.1} with {} dof: p = {:.3e} < {ALPHA:.1e}",
                self.statistic, self.dof, self.p_value
            ));
        }
        if self.integral_mismatch() {
            out.push(format!(
                "∫pdf = {:.6} but {:.6} of the samples were accepted",
                self.integral, self.accepted_fraction
            ));
        }
        if self.zero_pdf > 0 {
            out.push(format!("{} samples where pdf = 0", self.zero_pdf));
        }
        if self.pdf_mismatch > 0 {
            out.push(format!("{} samples whose reported pdf differs from pdf()", self.pdf_mismatch));
        }
        if self.bad_dir > 0 {
            out.push(format!("{} samples are not finite unit vectors", self.bad_dir));
        }
        out
    }

    /// Panics with every failure and `context` if any check failed.
    #[track_caller]
    pub(crate) fn assert_ok(&self, context: &str) {
        let failures = self.failures();
        if std::env::var_os("CHI2_VERBOSE").is_some() {
            eprintln!(
                "{context}: p = {:.4}, χ² = {:.1}/{} dof, ∫pdf = {:.6}, accepted {:.6}",
                self.p_value, self.statistic, self.dof, self.integral, self.accepted_fraction
            );
        }
        assert!(failures.is_empty(), "{context}: {}\n{self:?}", failures.join("; "));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::warp;

    #[test]
    fn special_functions_match_known_values() {
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
        assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-12);
        assert!((ln_gamma(0.1) - 2.252_712_651_734_206).abs() < 1e-10);
        assert!((ln_gamma(100.0) - 359.134_205_369_575_4).abs() < 1e-9);
        for x in [0.01, 0.5, 1.0, 3.0, 20.0, 200.0] {
            assert!((gamma_q(1.0, x) - (-x).exp()).abs() < 1e-12, "Q(1, {x})");
        }
        // Tabulated 5 % and 1 % critical values of χ².
        for (stat, dof, p) in [
            (3.841_458_8, 1, 0.05),
            (18.307_038, 10, 0.05),
            (124.342_113, 100, 0.05),
            (6.634_897, 1, 0.01),
            (1_106.969_2, 1_000, 0.01),
        ] {
            let q = chi2_survival(stat, dof);
            assert!((q - p).abs() < 1e-6 * p.max(1e-3) * 100.0, "χ²({stat}, {dof}) → {q}, want {p}");
        }
        assert_eq!(chi2_survival(0.0, 5), 1.0);
        assert!(chi2_survival(1e5, 10) < 1e-300);
    }

    #[test]
    fn quadrature_resolves_narrow_lobes_and_the_horizon() {
        // A 10⁵ Phong lobe integrates to 1 on a grid adapted from its own samples…
        let n = 1e5;
        let axis = Vec3::Z;
        let dirs = pilot(|_, u| Some((warp::square_to_phong_lobe(u, n), 0.0)), 20_000, 1);
        let grid = SphereGrid::adapted(axis, &dirs, 16, 12);
        let total = grid.integrate(|v| {
            DVec3::splat(warp::phong_lobe_pdf_from_versine(0.5 * (v - Vec3::Z).length_squared(), n) as f64)
        });
        assert!((total.x - 1.0).abs() < 1e-4, "{total}");
        // … and a hemisphere cut diagonally through a tilted grid has exactly half the sphere.
        let grid = SphereGrid::adapted(Vec3::new(1.0, 0.3, 0.2), &[], 1, 24);
        assert!(grid.discontinuity == Some(DVec3::Z));
        let half = grid.integrate(|v| DVec3::splat(if v.z > 0.0 { 1.0 } else { 0.0 }));
        assert!((half.x - TAU).abs() < 1e-4 * TAU, "{half}");
        // A jump across an arbitrary declared plane is integrated exactly too.
        let plane = Vec3::new(0.3, -0.8, 0.5).normalize();
        let grid = SphereGrid::adapted(Vec3::Z, &[], 1, 8).with_discontinuity(Some(plane));
        let half = grid.integrate(|v| DVec3::splat(if v.dot(plane) > 0.0 { 1.0 } else { 0.0 }));
        assert!((half.x - TAU).abs() < 1e-4 * TAU, "{half}");
        // Every direction maps to a valid cell.
        for v in [Vec3::X, -Vec3::X, Vec3::Z, -Vec3::Z, Vec3::new(1.0, 0.3, 0.2).normalize()] {
            assert!(grid.cell_of(v) < grid.cells());
        }
    }

    #[test]
    fn accepts_a_correct_sampler() {
        let report = Chi2Test::new(Vec3::new(0.2, -0.4, 0.9), 11).run(
            |_, u| Some((warp::square_to_uniform_sphere(u), warp::UNIFORM_SPHERE_PDF)),
            |_| warp::UNIFORM_SPHERE_PDF,
        );
        report.assert_ok("uniform sphere");
        assert!((report.integral - 1.0).abs() < 1e-5);
    }

    /// The harness must be able to fail: a Phong pdf with the wrong exponent (still normalised,
    /// so only χ² can notice) and a sampler with the classic off-by-one exponent are rejected.
    #[test]
    fn rejects_mismatched_pdfs() {
        let t = Chi2Test { samples: 300_000, ..Chi2Test::new(Vec3::Z, 12) };
        let wrong_exponent = t.run(
            |_, u| Some((warp::square_to_phong_lobe(u, 100.0), 0.0)),
            |v| warp::phong_lobe_pdf(v.z, 110.0),
        );
        assert!(wrong_exponent.chi2_rejects(), "{wrong_exponent:?}");
        assert!(!wrong_exponent.integral_mismatch(), "{wrong_exponent:?}");

        // cos α = u^(1/n) instead of u^(1/(n+1)), with the pdf claimed for n.
        let off_by_one = t.run(
            |_, u| {
                let v = warp::square_to_phong_lobe(u, 9.0);
                Some((v, warp::phong_lobe_pdf(v.z, 10.0)))
            },
            |v| warp::phong_lobe_pdf(v.z, 10.0),
        );
        assert!(off_by_one.chi2_rejects(), "{off_by_one:?}");

        // A pdf that integrates to 1.02 and a pdf that misses half the samples' support.
        let scaled =
            t.run(|_, u| Some((warp::square_to_uniform_sphere(u), 0.0)), |_| 1.02 * warp::UNIFORM_SPHERE_PDF);
        assert!(scaled.integral_mismatch(), "{scaled:?}");
        let half = t.run(
            |_, u| Some((warp::square_to_uniform_sphere(u), 0.0)),
            |v| if v.z > 0.0 { 2.0 * warp::UNIFORM_SPHERE_PDF } else { 0.0 },
        );
        assert!(half.zero_pdf > 0 && half.chi2_rejects(), "{half:?}");
        assert!(!half.failures().is_empty());
    }
}
