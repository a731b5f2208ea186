//! The direct light of area lights at a meter target, by sampling the lights from the target —
//! why: connecting the dataset's stored emission points y₀ to the meter gives the same
//! estimate, but its error falls as 1/√(light paths), and 1 % at every point of CIE 171's
//! rectangle and disc sources took 2^19–2^20 traced paths; sampled from each target, with
//! stratified points on the lights, a few hundred shadow rays a point reach 0.5 %, whatever
//! the dataset's size.
//!
//! **Target.** E_T = (1/A_T)∫_T Σ_k ∫_{A_k} L'_k(y → p)·cos θ_y·cos θ_p/d²·τ(p, y) dA_y dA_p,
//! over the area lights k that are on: L'_k the relit emitted radiance (one-sided: 0 behind the
//! emitter), θ_y at the light, θ_p at the meter (0 from behind it), τ the shadow ray's
//! transmittance (0 if blocked; through thin panes, `Scene::shadow_transmittance`). A point is a
//! target of one point (no dA_p).
//!
//! **One sample.** u ∈ [0, 1)² picks light k with P_k = N_k/Σ_j N_j (its paths among the area
//! lights': independent of relighting, as NEE's pick) by u.x, which is then rescaled and, with
//! u.y, draws a point y uniform on the light's area (its own position sampling,
//! [`crate::light::AreaLight::sample_position`], density 1/A_k); the meter point p is uniform in
//! the target. The sample is L'_k·cos θ_y·cos θ_p·τ/d² · A_k/P_k, i.e. Φ'_k·(f_e/cos)·cos θ_y·
//! cos θ_p·τ/(d²·P_k) — what the light's NEE sends ([`RenderLights::toward`]) times cos θ_p —
//! so every sample is linear in each light's relit power: relighting and switching lights off
//! stay exact. Its expectation is E_T: the density P_k/A_k is positive wherever a light emits,
//! so nothing is missed, behind an obstruction or through a small opening alike (those cost
//! variance, never bias).
//!
//! **Stratified, with an honest error.** The unit square is cut into n strata of equal area
//! per row ([`Strata`]; rows of equal height, a row's columns of equal width) and each stratum
//! h, of area w_h, gets two independent samples x_h1, x_h2 uniform in it. The estimate
//! Σ_h w_h·(x_h1 + x_h2)/2 is unbiased, and Σ_h w_h²·(x_h1 − x_h2)²/4 is an unbiased estimate of
//! its variance (each stratum's pair is an i.i.d. pair of its conditional distribution), with n
//! degrees of freedom. Light k's share of u.x is an interval and its triangles' shares of that
//! are intervals, so strata stay compact on the lights: the smooth part of the integrand then
//! costs almost nothing and a shadow's edge crosses few strata. (Cells' points are not
//! stratified: their samples' p are i.i.d. uniform in the cell, which the pair estimate covers.)
//!
//! **How many.** By default a pilot of [`PILOT_STRATA`] strata (discarded) estimates the
//! variance, and the count is the shared budget's (`budget.rs`): as many as give a relative
//! standard error of 0.5 % assuming the variance falls as 1/n (stratification makes it fall
//! faster, so this overshoots), within the same bounds as the sky's (256 to 2^20 a target, 2^24
//! over the meter). `--direct-samples N` takes N samples (N/2 strata, rounded down to even). Random numbers come from
//! streams named by (seed, target), so a reading does not depend on the thread count.
//!
//! **Nothing counted twice.** The connected estimator no longer connects stored emission
//! vertices (`connect.rs`): the light of a path that reaches the meter straight from an area
//! light (its y₀ → p segment, through panes or not) is this term's alone, and every path that
//! scattered at least once is its scattered vertices' connections' alone. The two partition
//! the paths arriving at the meter by their length, each with weight 1.

use super::budget::{self, channels};
use super::layout::{MeterDraw, MeterLayout};
use crate::light::Light;
use crate::math::{Rgb, Vec2};
use crate::sampling::RandomStream;
use crate::scene::Scene;
use crate::sensor::bidirectional::{RenderLights, shadow_ray};

/// Strata of a target's pilot (two samples each).
pub(super) const PILOT_STRATA: u32 = 32;

/// Stream keys of the pilot and of the estimate.
const PILOT_STREAM: u64 = 0x6d65_7465_7261_706c;
const AREA_STREAM: u64 = 0x6d65_7465_7261_7265;

/// The largest f32 below 1 (a stratum's far edge, rounded, must not reach 1).
const BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;

/// The area lights that are on, as the meter's direct term sees them.
pub(super) struct AreaLights<'a> {
    scene: &'a Scene,
    lights: &'a RenderLights,
    /// Indices into `lights.lights()` of the area lights.
    members: Vec<usize>,
    /// Their cumulative pick probabilities P_k (last = 1).
    cumulative: Vec<f64>,
}

impl<'a> AreaLights<'a> {
    /// The area lights among `lights`; `None` if there are none.
    pub(super) fn new(scene: &'a Scene, lights: &'a RenderLights) -> Option<Self> {
        let all = lights.lights();
        let members: Vec<usize> =
            (0..all.len()).filter(|&i| matches!(scene.lights[all[i].scene_index], Light::Area(_))).collect();
        let total: u64 = members.iter().map(|&i| all[i].paths).sum();
        if members.is_empty() || total == 0 {
            return None;
        }
        let mut acc = 0u64;
        let mut cumulative: Vec<f64> = members
            .iter()
            .map(|&i| {
                acc += all[i].paths;
                acc as f64 / total as f64
            })
            .collect();
        *cumulative.last_mut().expect("members") = 1.0;
        Some(AreaLights { scene, lights, members, cumulative })
    }

    /// One sample at the meter point `d` from the light point `u` draws (module docs): the
    /// irradiance divided by the density of the light point.
    #[inline]
    fn sample(&self, d: &MeterDraw, u: Vec2) -> Rgb {
        let x = u.x as f64;
        let k = self.cumulative.partition_point(|&c| c <= x).min(self.members.len() - 1);
        let lo = if k == 0 { 0.0 } else { self.cumulative[k - 1] };
        let pick = self.cumulative[k] - lo;
        let ux = (((x - lo) / pick) as f32).clamp(0.0, BELOW_ONE);
        let i = self.members[k];
        let Light::Area(a) = &self.scene.lights[self.lights.lights()[i].scene_index] else {
            unreachable!("AreaLights::new keeps area lights only")
        };
        let (y, n_y, prim) = a.sample_position(&self.scene.triangles, Vec2::new(ux, u.y));
        let Some(lp) = self.lights.toward(self.scene, i, y, Some((n_y, prim)), d.position) else {
            return Rgb::ZERO;
        };
        let cos = d.normal.dot(lp.dir);
        if !(cos > 0.0) {
            return Rgb::ZERO;
        }
        let ray = shadow_ray(d.position, d.normal, lp.dir, lp.distance, Some((y, n_y)));
        let Some(tau) = ray.and_then(|ray| self.scene.shadow_transmittance(&ray)) else { return Rgb::ZERO };
        // `radiance` is divided by NEE's pick among all lights; here the area lights' own.
        lp.radiance * tau * (lp.pick * cos / pick as f32)
    }

    /// Target `t`'s stratified estimate with `strata` strata from the stream `key` (module
    /// docs): its mean per channel and in lux and their standard errors; `None` once `stop`
    /// said so (asked every DIRECT_STOP_DRAWS draws).
    fn stratified(
        &self,
        layout: &MeterLayout,
        t: usize,
        strata: u32,
        key: u64,
        seed: u64,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Option<([f64; 4], [f64; 4])> {
        let mut rng = RandomStream::new(seed, &[key, t as u64]);
        budget::in_pairs(Strata::new(strata).iter(), stop, |cell| {
            let d = layout.draw_in(t, rng.next_2d());
            let j = rng.next_2d();
            let u = Vec2::new(cell.0 + j.x * cell.2, cell.1 + j.y * cell.3).min(Vec2::splat(BELOW_ONE));
            channels(self.sample(&d, u), &self.scene.photometry)
        })
    }

    /// Target `t`'s direct light from the area lights: its mean per channel and in lux and
    /// their standard errors (module docs). `fixed` is an explicit sample count, else the
    /// pilot's within its bounds and `cap` ([`budget::count`]). `None` once `stop` said so.
    pub(super) fn target(
        &self,
        layout: &MeterLayout,
        t: usize,
        fixed: Option<u32>,
        cap: u32,
        seed: u64,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Option<([f64; 4], [f64; 4])> {
        let n = match fixed {
            Some(n) => n,
            None => {
                let (mean, se) = self.stratified(layout, t, PILOT_STRATA, PILOT_STREAM, seed, stop)?;
                // One sample's variance: the pilot mean's times its samples.
                let one = se[3] * se[3] * (2 * Strata::new(PILOT_STRATA).len()) as f64;
                budget::count(None, budget::wanted(one, mean[3]), cap)
            }
        };
        self.stratified(layout, t, (n / 2).max(1), AREA_STREAM, seed, stop)
    }
}

/// About n strata of the unit square (module docs): ⌊√n⌋ rows of equal height (at most n/2),
/// each of an even number of columns of equal width, n/2 pairs of columns dealt to the rows as
/// evenly as can be (n rounded down to even; n = 1 is the whole square). Why even: a quad
/// emitter is two triangles of equal area, split at u.x = ½, and a stratum straddling that
/// split holds two distant parts of the light — its pair's difference then dominated the error,
/// and made a pilot's estimate of it erratic.
#[derive(Clone, Copy, Debug)]
struct Strata {
    rows: u32,
    pairs: u32,
}

impl Strata {
    fn new(n: u32) -> Self {
        let pairs = n / 2;
        if pairs == 0 {
            return Strata { rows: 1, pairs: 0 };
        }
        Strata { rows: ((n as f64).sqrt() as u32).clamp(1, pairs), pairs }
    }

    /// The number of strata.
    fn len(self) -> u32 {
        (2 * self.pairs).max(1)
    }

    /// Each stratum's (x₀, y₀, width, height) and its area.
    fn iter(self) -> impl Iterator<Item = ((f32, f32, f32, f32), f64)> {
        let (base, extra) = (self.pairs / self.rows, self.pairs % self.rows);
        (0..self.rows).flat_map(move |r| {
            let cols = (2 * (base + u32::from(r < extra))).max(1);
            let (w, h) = (1.0 / cols as f32, 1.0 / self.rows as f32);
            let area = 1.0 / (cols as f64 * self.rows as f64);
            (0..cols).map(move |c| ((c as f32 * w, r as f32 * h, w, h), area))
        })
    }
}

#[cfg(test)]
pub(super) mod tests;
