//! The direct light of environment lights (the sky) at a meter target, by a visibility-guided,
//! unbiased sampler — why: through a window or a roof opening a meter point sees the sky in a
//! small solid angle, and directions drawn from the sky's own luminance over the whole sphere
//! rarely pass (with 256 of them a point's standard error was 0–104 % in CIE 171's cases
//! 5.9–5.12). The sampler learns, per target, where the sky is seen, and spends its directions
//! there, and decides itself how many it needs.
//!
//! **Target.** E_T = (1/A_T)∫_T ∫_{H²} f(p, ω) dω dA_p with f = Σ_k L'_k(ω)·cos θ_p·τ(p, ω), the
//! environments' relit radiance, the cosine to the meter's normal and the shadow ray's
//! transmittance (0 if blocked; through thin panes, `Scene::shadow_transmittance`). A point is a
//! target of one point (no dA_p).
//!
//! **1. Pilot (a guide, discarded).** The hemisphere above the target's normal is the image of
//! the unit square under the concentric cosine map (Shirley–Chiu disk, lifted by Malley's
//! method), cut into [`SIDE`]² equal bins: a uniform point of the square maps to a direction of
//! solid-angle density cos θ/π, so each bin holds 1/[`BINS`] of it. The pilot traces
//! [`PILOT_PER_BIN`] jittered directions in every bin of a pilot grid (from a uniform point of
//! the cell for a cell) and gives pilot bin b the weight w_b = mean of luminance(L'·τ) there (∝
//! the bin's share of ∫f, since each bin has the same ∫cos θ/π), then at least [`SPREAD`] times
//! its largest neighbour's ([`dilate`]: a bin the opening covers in part may be missed by its few
//! pilot directions); each guide bin takes its pilot bin's weight. The pilot grid is the guide's
//! ([`SIDE`]², at most 8192 directions a target in its second pass) unless the meter has many
//! targets: over a whole meter the pilot traces at most [`PILOT_BUDGET`] directions, the grid's
//! side halving (32, 16, then the floor [`MIN_PILOT_SIDE`]) until its targets fit ([`pilot_side`]; with
//! [`super::MAX_TARGETS`] targets at the floor, exactly the budget). A 100 × 100-cell plane's
//! pilot is 16² bins (at most 8² + 16² pairs, 640 directions a cell, 6.4 M in all, not 82 M); its guide is coarser,
//! which costs variance, never bias (below). The pilot grid is traced in two passes: first a
//! grid [`REFINE`] times coarser along each side ([`coarse_side`]), then the pilot grid only in
//! the coarse bins that saw the sky or lie within two bins of one (a sliver of sky the coarse
//! pass's few directions missed is then still found); the bins the second pass skips keep
//! weight 0. Through an opening, where a point sees the sky in a few per cent of its
//! hemisphere, that is about a third of one pass's directions for the same guide (most of a
//! sky case's `measure` time before it draws a fresh direction, at 8 points); where the sky is
//! seen everywhere, 1¼ times ([`pilot_most`], which the budget counts). The guide draws bin b with P(b) = w_b/Σw and a
//! uniform square point in it, so its solid-angle density is
//!
//! ```text
//! p_guide(ω) = P(b(ω)) · BINS · cos θ/π        (0 below the horizon of the meter)
//! ```
//!
//! **2. Defensive mixture.** The fresh directions are drawn from
//! p(ω) = α·p_env(ω) + (1 − α)·p_guide(ω): with probability α from the environments' own
//! sampling (p_env, the mean of their densities, each picked with probability 1/K), else from the
//! guide; whichever drew ω, both densities are evaluated at it. α = [`ALPHA`], or 1 when the
//! pilot saw no sky (no guide). Each fresh sample is f(p, ω)/p(ω).
//!
//! **Stratified in pairs, with an honest error.** Which component draws ω, and where the guide
//! draws it, are one coordinate s ∈ [0, 1): below α the environments' sampling (its own random
//! numbers), above it the guide's bin CDF at (s − α)/(1 − α), the bins in the square's row
//! order. s is stratified: N/2 equal strata of [0, 1), two independent samples in each
//! (`budget::PairedStrata`: the mean of the pairs, and the variance from each pair's
//! difference, unbiased with N/2 degrees of freedom). So each component gets its share α, 1 − α
//! of the samples and the guide's bins their weights' share, up to a stratum, instead of
//! binomial counts; what is left is the variation within a bin (an opening's edge crossing
//! it). Measured on CIE 171's roof case (8 points, overcast sky, `--direct-samples 8192`): a
//! point's standard error fell from 0.68–0.96 % to 0.25–0.45 % (a fifth of the variance; the
//! time to CIE 171's 2 % fell by half, `docs/performance.md`); Radiance's ambient sampling is
//! stratified over its hemisphere for the same reason.
//!
//! **Why it is unbiased.** p_env > 0 wherever an environment's radiance is (its sampling is
//! positive wherever L is), so p > 0 wherever f ≠ 0 whatever the guide is: E[f/p] = ∫f. The
//! guide and N depend on the pilot alone, whose samples are not in the estimate, so conditioned
//! on the pilot each stratum's pair is an independent draw of that estimator restricted to
//! the stratum, and the strata together cover s's whole range with their exact shares: the
//! reading is unbiased, conditionally and so unconditionally. A guide that misses part of the sky only costs variance there
//! (bounded by 1/α times the environment sampling's), never bias; the standard error is the
//! fresh pairs' own spread, so it reports what the guide and the strata achieved.
//!
//! **3. How many (default).** Drawn stratified from cos θ/π (q), the pilot also estimates the
//! mixture's one-sample variance, V = E_q[f²/(p·q)] − (E_q[f/q])² (from the second pass's
//! directions, each standing for 1/(PILOT_PER_BIN·side²) of q: the bins it skipped add 0), and N is the count whose
//! standard error would be 0.5 % of the value from independent draws (the strata only lower it,
//! so the count overshoots, as the area lights' does), between 256 and a cap (2^20 a target, and 2^24
//! over the whole meter: the bounds `budget.rs` keeps for every sampled direct term). An explicit count
//! (`direct_samples`) fixes N instead. Random numbers come from streams named by (seed, target),
//! so a reading does not depend on the thread count.

use super::budget::{self, channels};
use super::connect::DIRECT_STOP_DRAWS;
use super::layout::{MeterDraw, MeterLayout};
use crate::light::Light;
use crate::math::{Frame, Rgb, Vec2, Vec3, luminance};
use crate::sampling::RandomStream;
use crate::sampling::warp::square_to_cosine_hemisphere;
use crate::scene::Scene;
use crate::sensor::bidirectional::{RenderLights, shadow_ray};
use std::f64::consts::{FRAC_1_PI, PI};

/// Bins along each side of the square (the hemisphere has SIDE² of them).
pub(super) const SIDE: usize = 64;
/// Bins of the guide.
pub(super) const BINS: usize = SIDE * SIDE;
/// Pilot directions per bin (of the pilot grid, [`pilot_side`]).
pub(super) const PILOT_PER_BIN: usize = 2;
/// Most pilot directions of a whole meter (unless every target is at [`MIN_PILOT_SIDE`]).
pub(super) const PILOT_BUDGET: u64 = 1 << 23;
/// The coarse pass's bins are this many times wider along each side than the pilot grid's.
pub(super) const REFINE: usize = 2;
/// Fewest pilot bins along each side of the square: a coarser guide would barely aim.
pub(super) const MIN_PILOT_SIDE: usize = 8;
/// The share of its largest neighbour's weight a bin takes at least ([`dilate`]).
pub(super) const SPREAD: f64 = 0.5;
/// The defensive mixture's weight of the environments' own sampling.
pub(super) const ALPHA: f64 = 0.15;

/// Stream keys of the pilot and of the estimate.
const PILOT_STREAM: u64 = 0x6d65_7465_7270_696c;
const SKY_STREAM: u64 = 0x6d65_7465_7273_6b79;

/// The square point (in [0, 1]²) of a direction of the upper hemisphere (local frame, z up):
/// the inverse of [`square_to_cosine_hemisphere`] (drop z, invert the concentric map).
pub(super) fn square_of_local(v: Vec3) -> Vec2 {
    let (x, y) = (v.x as f64, v.y as f64);
    let r = (x * x + y * y).sqrt();
    if r == 0.0 {
        return Vec2::splat(0.5);
    }
    // φ in [−π/4, 7π/4): the four wedges of the concentric map.
    let mut phi = y.atan2(x);
    if phi < -PI / 4.0 {
        phi += 2.0 * PI;
    }
    let k = 4.0 / PI;
    let (a, b) = if phi < PI / 4.0 {
        (r, r * phi * k)
    } else if phi < 3.0 * PI / 4.0 {
        (r * (PI / 2.0 - phi) * k, r)
    } else if phi < 5.0 * PI / 4.0 {
        (-r, -r * (phi - PI) * k)
    } else {
        (-r * (3.0 * PI / 2.0 - phi) * k, -r)
    };
    let s = |o: f64| ((o.clamp(-1.0, 1.0) + 1.0) * 0.5) as f32;
    Vec2::new(s(a), s(b))
}

/// The bin of a square point.
#[inline]
fn bin_of_square(u: Vec2) -> usize {
    let i = ((u.x * SIDE as f32) as usize).min(SIDE - 1);
    let j = ((u.y * SIDE as f32) as usize).min(SIDE - 1);
    j * SIDE + i
}

/// The learned distribution over the hemisphere above a normal (module docs, 1).
#[derive(Clone, Debug)]
pub(super) struct Guide {
    frame: Frame,
    prob: Vec<f64>,
    cdf: Vec<f64>,
}

impl Guide {
    /// The guide of bin weights `weights` (BINS of them, ≥ 0) around `normal`; `None` when they
    /// are all 0.
    pub(super) fn new(normal: Vec3, weights: &[f64]) -> Option<Guide> {
        debug_assert_eq!(weights.len(), BINS);
        let total: f64 = weights.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let prob: Vec<f64> = weights.iter().map(|w| w / total).collect();
        let mut acc = 0.0;
        let mut cdf: Vec<f64> = prob
            .iter()
            .map(|p| {
                acc += p;
                acc
            })
            .collect();
        *cdf.last_mut().expect("bins") = 1.0;
        Some(Guide { frame: Frame::from_normal(normal), prob, cdf })
    }

    /// A unit world direction and its solid-angle density, from a uniform `u_bin` ∈ [0, 1) picking
    /// the bin and `v` ∈ [0, 1) the point's row in it; its column is where `u_bin` falls within
    /// the bin's share of the CDF (uniform in [0, 1) given the bin when `u_bin` is uniform, so
    /// the density is the same, and a stratified `u_bin` stratifies the columns too).
    pub(super) fn sample(&self, u_bin: f64, v: f32) -> (Vec3, f64) {
        let b = self.cdf.partition_point(|&c| c <= u_bin).min(BINS - 1);
        let lo = if b == 0 { 0.0 } else { self.cdf[b - 1] };
        let x = ((u_bin - lo) / (self.cdf[b] - lo)) as f32;
        let u = Vec2::new(if x.is_finite() { x.clamp(0.0, BELOW_ONE_F32) } else { 0.5 }, v);
        let cell = Vec2::new((b % SIDE) as f32, (b / SIDE) as f32);
        let local = square_to_cosine_hemisphere((cell + u) / SIDE as f32);
        // The density of the bin drawn (not re-derived from ω, which rounding may move).
        (self.frame.to_world(local).normalize(), self.prob[b] * BINS as f64 * local.z as f64 * FRAC_1_PI)
    }

    /// The solid-angle density of drawing the unit world direction `omega`.
    pub(super) fn pdf(&self, omega: Vec3) -> f64 {
        let local = self.frame.to_local(omega);
        if !(local.z > 0.0) {
            return 0.0;
        }
        self.prob[bin_of_square(square_of_local(local))] * BINS as f64 * local.z as f64 * FRAC_1_PI
    }
}

/// The pilot's bin weights grown by one bin all round: each bin takes at least [`SPREAD`] times
/// the largest of its 8 neighbours' (the concentric map is continuous, so neighbouring bins are
/// neighbouring directions). A bin the sky covers only in part may see it in none of its pilot
/// directions; its neighbour inside the opening did, and so it is still drawn often enough —
/// left to the defensive component alone, such a sliver costs far more variance than the
/// ring of bins the spread adds.
fn dilate(weights: &[f64], side: usize) -> Vec<f64> {
    let at = |i: isize, j: isize| {
        if (0..side as isize).contains(&i) && (0..side as isize).contains(&j) {
            weights[j as usize * side + i as usize]
        } else {
            0.0
        }
    };
    (0..side * side)
        .map(|b| {
            let (i, j) = ((b % side) as isize, (b / side) as isize);
            let mut most = 0.0f64;
            for (di, dj) in [(-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
                most = most.max(at(i + di, j + dj));
            }
            weights[b].max(SPREAD * most)
        })
        .collect()
}

/// The pilot grid's side for a meter of `targets` targets: [`SIDE`] halved until the meter's
/// pilot, PILOT_PER_BIN·side² directions a target, fits [`PILOT_BUDGET`], at least
/// [`MIN_PILOT_SIDE`] (module docs, 1).
pub(super) fn pilot_side(targets: usize) -> usize {
    let mut side = SIDE;
    while side > MIN_PILOT_SIDE && pilot_most(side) * targets as u64 > PILOT_BUDGET {
        side /= 2;
    }
    side
}

/// The coarse pass's grid side for a pilot grid of `side`: side/[`REFINE`], at least
/// [`MIN_PILOT_SIDE`] (at most `side`: then the pilot is one pass).
pub(super) fn coarse_side(side: usize) -> usize {
    (side / REFINE).max(MIN_PILOT_SIDE).min(side)
}

/// The most directions a target's pilot on a grid of `side` traces: both passes in full (the
/// sky seen everywhere).
pub(super) fn pilot_most(side: usize) -> u64 {
    let coarse = coarse_side(side);
    (PILOT_PER_BIN * (side * side + if coarse < side { coarse * coarse } else { 0 })) as u64
}

/// Guide bin weights (SIDE², row-major) from a pilot grid's (`side`², SIDE a multiple of it):
/// each guide bin takes the weight of the pilot bin it lies in.
fn refine(weights: &[f64], side: usize) -> Vec<f64> {
    let k = SIDE / side;
    (0..BINS).map(|b| weights[(b / SIDE / k) * side + (b % SIDE) / k]).collect()
}

/// The environments that are on, as the meter's direct term sees them.
pub(super) struct Sky<'a> {
    scene: &'a Scene,
    lights: &'a RenderLights,
    /// Indices into `lights.lights()` of the environment lights.
    envs: Vec<usize>,
}

/// How a target's fresh samples are drawn, from its pilot.
struct Mixture {
    guide: Option<Guide>,
    alpha: f64,
}

impl<'a> Sky<'a> {
    /// The environment lights among `lights`; `None` if there are none.
    pub(super) fn new(scene: &'a Scene, lights: &'a RenderLights) -> Option<Self> {
        let envs: Vec<usize> = (0..lights.lights().len())
            .filter(|&i| matches!(scene.lights[lights.lights()[i].scene_index], Light::Environment(_)))
            .collect();
        (!envs.is_empty()).then_some(Sky { scene, lights, envs })
    }

    fn env(&self, k: usize) -> &crate::light::EnvironmentLight {
        match &self.scene.lights[self.lights.lights()[self.envs[k]].scene_index] {
            Light::Environment(e) => e,
            _ => unreachable!("Sky::new keeps environments only"),
        }
    }

    /// Σ L'_k(ω)·τ(p, ω) arriving at `d` from the unit direction `omega`, and cos θ_p (0 from
    /// behind the meter, then nothing arrives).
    fn incoming(&self, d: &MeterDraw, omega: Vec3) -> (Rgb, f32) {
        let cos = d.normal.dot(omega);
        if !(cos > 0.0) {
            return (Rgb::ZERO, 0.0);
        }
        // The shadow ray before the sky's radiance: through an opening most directions are
        // blocked, and a ray on a small scene costs less than looking the direction up in the
        // environments' maps (callgrind: the pilot's directions of CIE 171's roof cases).
        let ray = shadow_ray(d.position, d.normal, omega, f32::INFINITY, None);
        let Some(tau) = ray.and_then(|ray| self.scene.shadow_transmittance(&ray)) else {
            return (Rgb::ZERO, cos);
        };
        // `radiance` is L'/(pdf·pick): with pdf 1, times pick, the relit radiance itself.
        let l = self.envs.iter().fold(Rgb::ZERO, |l, &i| {
            l + self
                .lights
                .environment_radiance(self.scene, i, omega, 1.0)
                .map_or(Rgb::ZERO, |(radiance, pick)| radiance * pick)
        });
        (l * tau, cos)
    }

    /// p_env(ω): the mean of the environments' own densities.
    fn env_pdf(&self, omega: Vec3) -> f64 {
        let k = self.envs.len();
        (0..k).map(|j| self.env(j).direction_pdf(omega) as f64).sum::<f64>() / k as f64
    }

    /// A direction from p_env and p_env there.
    fn sample_env(&self, rng: &mut RandomStream) -> (Vec3, f64) {
        let k = self.envs.len();
        let pick = if k == 1 { 0 } else { ((rng.next_f32() * k as f32) as usize).min(k - 1) };
        let (omega, own) = self.env(pick).sample_direction(rng.next_2d());
        let others: f64 =
            (0..k).filter(|&j| j != pick).map(|j| self.env(j).direction_pdf(omega) as f64).sum();
        (omega, (own as f64 + others) / k as f64)
    }

    /// The pilot of target `t` on a pilot grid of `side`² bins (module docs, 1 and 3), first
    /// traced on the grid of `coarse`² bins (a divisor of `side`; `side` itself: one pass) and
    /// then on `side`² only where that saw the sky: the mixture, the predicted number of samples
    /// for the target relative SE and the directions the pilot traced; `None` once `stop` said
    /// so.
    fn pilot(
        &self,
        layout: &MeterLayout,
        t: usize,
        (coarse, side): (usize, usize),
        seed: u64,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Option<(Mixture, f64, u32)> {
        debug_assert!(side <= SIDE && SIDE.is_multiple_of(side) && side.is_multiple_of(coarse));
        let mut rng = RandomStream::new(seed, &[PILOT_STREAM, t as u64]);
        let normal = layout.draw_in(t, Vec2::splat(0.5)).normal;
        let frame = Frame::from_normal(normal);
        // (guide bin, ω, luminance(L'τ), cos θ) of the fine pass's directions that saw the sky.
        let mut seen: Vec<(usize, Vec3, f64, f64)> = Vec::new();
        let mut drawn = 0u32;
        // PILOT_PER_BIN jittered directions in bin b of the grid of n² bins: Σ luminance(L'τ),
        // the directions that saw the sky kept in `seen` when `keep`.
        let mut trace = |b: usize, n: usize, keep: bool, seen: &mut Vec<(usize, Vec3, f64, f64)>| {
            let cell = Vec2::new((b % n) as f32, (b / n) as f32);
            let mut sum = 0.0;
            for _ in 0..PILOT_PER_BIN {
                if drawn.is_multiple_of(DIRECT_STOP_DRAWS) && stop() {
                    return None;
                }
                drawn += 1;
                let d = layout.draw_in(t, rng.next_2d());
                let u = (cell + rng.next_2d()) / n as f32;
                let local = square_to_cosine_hemisphere(u);
                let omega = frame.to_world(local).normalize();
                let (l, cos) = self.incoming(&d, omega);
                let g = luminance(l) as f64;
                if g > 0.0 {
                    sum += g;
                    if keep {
                        let fine = if n == SIDE { b } else { bin_of_square(u) };
                        seen.push((fine, omega, g, cos as f64));
                    }
                }
            }
            Some(sum)
        };
        // The coarse pass: which coarse bins (dilated: a sliver its few directions missed) the
        // fine pass traces; all of them for one pass.
        let region = if coarse == side {
            vec![1.0; side * side]
        } else {
            let mut found = vec![0.0f64; coarse * coarse];
            for (b, w) in found.iter_mut().enumerate() {
                *w = trace(b, coarse, false, &mut seen)?;
            }
            dilate(&dilate(&found, coarse), coarse)
        };
        let k = side / coarse;
        let mut weights = vec![0.0f64; side * side];
        for (b, weight) in weights.iter_mut().enumerate() {
            if region[(b / side / k) * coarse + (b % side) / k] > 0.0 {
                *weight = trace(b, side, true, &mut seen)?;
            }
        }
        let dilated = dilate(&weights, side);
        let guide = Guide::new(normal, &if side == SIDE { dilated } else { refine(&dilated, side) });
        let alpha = if guide.is_some() { ALPHA } else { 1.0 };
        // The fine pass's directions as a stratified sample of q over the whole grid: the bins it
        // skipped saw no sky in the coarse pass, and add 0.
        let n = (PILOT_PER_BIN * side * side) as f64;
        // With q = cos θ/π: f/q = g·π and f²/(p·q) = g²·cos θ·π/p.
        let (mut first, mut second) = (0.0, 0.0);
        for &(b, omega, g, cos) in &seen {
            let p_guide = guide.as_ref().map_or(0.0, |gd| gd.prob[b] * BINS as f64 * cos * FRAC_1_PI);
            let p = alpha * self.env_pdf(omega) + (1.0 - alpha) * p_guide;
            first += g * PI;
            if p > 0.0 {
                second += g * g * cos * PI / p;
            }
        }
        let (mean, second) = (first / n, second / n);
        let wanted = budget::wanted(second - mean * mean, mean);
        Some((Mixture { guide, alpha }, wanted, drawn))
    }

    /// Target `t`'s direct sky light: its mean per channel and in lux and their standard errors
    /// (module docs). `fixed` is an explicit sample count, else the pilot's within its bounds
    /// and `cap` ([`budget::count`]). `None` once `stop` said so (asked every DIRECT_STOP_DRAWS
    /// draws).
    pub(super) fn target(
        &self,
        layout: &MeterLayout,
        t: usize,
        fixed: Option<u32>,
        cap: u32,
        seed: u64,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Option<([f64; 4], [f64; 4])> {
        let side = pilot_side(layout.len());
        let (mix, wanted, _) = self.pilot(layout, t, (coarse_side(side), side), seed, stop)?;
        let n = budget::count(fixed, wanted, cap);
        self.estimate(layout, t, &mix, n, seed, stop)
    }

    /// Target `t`'s estimate from about n fresh samples drawn from the mixture `mix`, stratified
    /// in pairs (module docs, 2): its mean per channel and in lux and their standard errors.
    fn estimate(
        &self,
        layout: &MeterLayout,
        t: usize,
        mix: &Mixture,
        n: u32,
        seed: u64,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Option<([f64; 4], [f64; 4])> {
        let mut rng = RandomStream::new(seed, &[SKY_STREAM, t as u64]);
        let strata = (n / 2).max(1);
        let w = 1.0 / strata as f64;
        budget::in_pairs((0..strata).map(|h| (h, w)), stop, |&h| {
            let d = layout.draw_in(t, rng.next_2d());
            // The mixture's coordinate s, uniform in stratum h: below α the environments' own
            // sampling, above it the guide's bin CDF at (s − α)/(1 − α).
            let s = ((h as f64 + rng.next_f64()) * w).min(BELOW_ONE);
            channels(self.fresh(&d, mix, s, &mut rng), &self.scene.photometry)
        })
    }

    /// One fresh sample f(p, ω)/p(ω) at the meter point `d`, its direction drawn by the
    /// mixture's coordinate `s` (and `rng` for the rest).
    #[inline]
    fn fresh(&self, d: &MeterDraw, mix: &Mixture, s: f64, rng: &mut RandomStream) -> Rgb {
        // The direction and the density its sampler gave; the other sampler's density at it
        // is looked up only if light arrives (most directions through an opening are blocked,
        // and a zero contributes zero whatever the mixture's density).
        let (omega, guided, own) = match &mix.guide {
            Some(g) if s >= mix.alpha => {
                let u_bin = ((s - mix.alpha) / (1.0 - mix.alpha)).min(BELOW_ONE);
                let (omega, p_guide) = g.sample(u_bin, rng.next_f32());
                (omega, true, p_guide)
            }
            _ => {
                let (omega, p_env) = self.sample_env(rng);
                (omega, false, p_env)
            }
        };
        let (l, cos) = self.incoming(d, omega);
        if l == Rgb::ZERO {
            return Rgb::ZERO;
        }
        let p = match (&mix.guide, guided) {
            (_, true) => mix.alpha * self.env_pdf(omega) + (1.0 - mix.alpha) * own,
            (guide, false) => {
                mix.alpha * own + (1.0 - mix.alpha) * guide.as_ref().map_or(0.0, |g| g.pdf(omega))
            }
        };
        if p > 0.0 { l * (cos as f64 / p) as f32 } else { Rgb::ZERO }
    }
}

/// The largest f64 below 1.
const BELOW_ONE: f64 = 1.0 - f64::EPSILON / 2.0;
/// The largest f32 below 1.
const BELOW_ONE_F32: f32 = 1.0 - f32::EPSILON / 2.0;

#[cfg(test)]
mod tests;
