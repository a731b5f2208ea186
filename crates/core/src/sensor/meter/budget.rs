//! How many samples a target's direct light takes, shared by the sampled direct terms (the sky's,
//! `sky.rs`, and the area lights', `area.rs`), and the sums that give a mean and its standard
//! error. Why one place: both terms aim at the same relative standard error by default and keep
//! the same bounds per target and per meter, so a huge grid stays bounded whatever light lights
//! it; an explicit `--direct-samples N` fixes the count for both.
//!
//! A term's discarded pilot estimates the variance σ² one sample of its estimator would have
//! (for a stratified estimator, the pilot's variance times its sample count: an upper bound of
//! what more strata give, since stratifying finer never adds variance per sample). The count
//! is then σ²/(r·μ)², r = [`TARGET_RELATIVE_SE`], within [[`MIN_SAMPLES`], cap], the cap
//! [`sample_cap`]: [`BUDGET`] over the whole meter, at most [`MAX_SAMPLES`] a target. Because
//! the count depends on the pilot alone, whose samples are not in the estimate, the estimate
//! given the count is an average of independent fresh samples: unbiased.

use super::connect::DIRECT_STOP_DRAWS;
use crate::math::Rgb;
use crate::scene::Photometry;

/// The relative standard error the default sample count aims at.
pub(super) const TARGET_RELATIVE_SE: f64 = 0.005;
/// Fewest fresh samples of a target by default (also when the pilot saw no light).
pub(super) const MIN_SAMPLES: u32 = 256;
/// Most fresh samples of a target.
pub(super) const MAX_SAMPLES: u32 = 1 << 20;
/// Most fresh samples of a whole meter by default, per term: a target's cap is BUDGET/targets,
/// within [MIN_SAMPLES, MAX_SAMPLES].
pub(super) const BUDGET: u64 = 1 << 24;

/// The default cap on a target's fresh samples for a meter of `targets` targets.
pub(super) fn sample_cap(targets: usize) -> u32 {
    (BUDGET / targets.max(1) as u64).clamp(MIN_SAMPLES as u64, MAX_SAMPLES as u64) as u32
}

/// The samples whose mean has a standard error of [`TARGET_RELATIVE_SE`] of `mean`, one sample
/// having variance `variance` (module docs); 0 when the mean is not positive (nothing seen).
pub(super) fn wanted(variance: f64, mean: f64) -> f64 {
    if mean > 0.0 { variance.max(0.0) / (TARGET_RELATIVE_SE * mean).powi(2) } else { 0.0 }
}

/// A target's sample count: `fixed` if given, else `wanted` (from its pilot) within
/// [[`MIN_SAMPLES`], `cap`].
pub(super) fn count(fixed: Option<u32>, wanted: f64, cap: u32) -> u32 {
    fixed.unwrap_or_else(|| wanted.ceil().clamp(MIN_SAMPLES as f64, cap.max(MIN_SAMPLES) as f64) as u32)
}

/// The channels of an irradiance sample: R, G, B (W/m²) and E_v (lux) by `photometry`.
#[inline]
pub(super) fn channels(e: Rgb, photometry: &Photometry) -> [f64; 4] {
    let e = [e.x as f64, e.y as f64, e.z as f64];
    [e[0], e[1], e[2], photometry.lux(e)]
}

/// Sums of a target's samples, per channel and in lux: their mean and its standard error.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Moments {
    sum: [f64; 4],
    sq: [f64; 4],
    n: u64,
}

impl Moments {
    /// Adds a sample of irradiance `e` (W/m²), its lux by `photometry`.
    #[inline]
    pub(super) fn add(&mut self, e: Rgb, photometry: &Photometry) {
        let x = channels(e, photometry);
        for ((sum, sq), x) in self.sum.iter_mut().zip(&mut self.sq).zip(x) {
            *sum += x;
            *sq += x * x;
        }
        self.n += 1;
    }

    /// The mean and its standard error per channel (0 for fewer than two samples).
    pub(super) fn finish(&self) -> ([f64; 4], [f64; 4]) {
        let m = self.n.max(1) as f64;
        let mean = self.sum.map(|s| s / m);
        let mut se = [0.0; 4];
        if self.n > 1 {
            for c in 0..4 {
                se[c] = ((self.sq[c] - m * mean[c] * mean[c]).max(0.0) / (m - 1.0) / m).sqrt();
            }
        }
        (mean, se)
    }
}

/// A stratified estimate in pairs ([`PairedStrata`]): two samples of `sample(stratum)` in each
/// of `strata` (a stratum and its share of the domain), in order; its mean per channel and
/// their standard errors, or `None` once `stop` said so (asked every [`DIRECT_STOP_DRAWS`]
/// draws). The area lights' and the sky's direct terms both estimate this way.
pub(super) fn in_pairs<S>(
    strata: impl IntoIterator<Item = (S, f64)>,
    stop: &(dyn Fn() -> bool + Sync),
    mut sample: impl FnMut(&S) -> [f64; 4],
) -> Option<([f64; 4], [f64; 4])> {
    let mut sums = PairedStrata::default();
    let mut drawn = 0u32;
    for (stratum, w) in strata {
        let mut pair = [[0.0f64; 4]; 2];
        for x in &mut pair {
            if drawn.is_multiple_of(DIRECT_STOP_DRAWS) && stop() {
                return None;
            }
            drawn += 1;
            *x = sample(&stratum);
        }
        sums.add(w, pair);
    }
    Some(sums.finish())
}

/// Sums of a stratified estimate whose strata hold two independent samples each: the estimate
/// Σ_h w_h·(x_h1 + x_h2)/2 (w_h the stratum's share of the domain) and the unbiased estimate of
/// its variance Σ_h w_h²·(x_h1 − x_h2)²/4, each stratum's pair being an i.i.d. pair of its
/// conditional distribution (one degree of freedom a stratum).
#[derive(Clone, Copy, Debug, Default)]
struct PairedStrata {
    mean: [f64; 4],
    var: [f64; 4],
}

impl PairedStrata {
    /// Adds stratum of share `w` with its two samples' channels ([`channels`]).
    #[inline]
    fn add(&mut self, w: f64, pair: [[f64; 4]; 2]) {
        let [a, b] = pair;
        for (((mean, var), a), b) in self.mean.iter_mut().zip(&mut self.var).zip(a).zip(b) {
            *mean += w * 0.5 * (a + b);
            *var += (w * 0.5 * (a - b)).powi(2);
        }
    }

    /// The estimate and its standard error per channel.
    fn finish(&self) -> ([f64; 4], [f64; 4]) {
        (self.mean, self.var.map(f64::sqrt))
    }
}
