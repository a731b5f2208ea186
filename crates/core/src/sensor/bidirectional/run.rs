//! A whole bidirectional render as a front end asks for one: one splat pass over the light
//! vertex cache, then camera passes — a fixed number of camera paths per pixel, or passes until
//! a deadline — accumulated with the running error estimate of [`Progressive`]. Progress and
//! interruption go through callbacks, so the command line's bars, a binding's callback and a
//! server's status all drive the same loop.
//!
//! With a deadline, M (the camera paths the render will take, which the MIS weights of the
//! light-tracing strategy need before the first pass) is planned from a pilot pass of one path
//! per pixel; any constant M is unbiased (`docs/bidirectional.md` §10.2), so the plan only
//! balances the strategies, and the render stops at the first pass ending past the deadline.

use super::{Allocation, CacheChunk, Progressive, Renderer, Settings};
use crate::film::Film;
use crate::math::Rgb;
use crate::scene::Scene;
use crate::sensor::Sensor;
use std::time::Instant;

/// How many camera paths a render takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunPlan {
    /// Camera paths per pixel in each pass (at least 1).
    pub spp: u32,
    /// `None`: one pass. `Some(t)`: passes until `t` (at least one).
    pub deadline: Option<Instant>,
    /// The first pass's number, which names its random streams (a walkthrough's frame).
    pub first_pass: u64,
}

/// What a render reports while it runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RunEvent {
    /// The splat pass will go over this many stored samples.
    SplatStart(u64),
    /// The splat pass finished this many more samples.
    Splatted(usize),
    /// The splat pass is done; the camera passes start (over this many pixels each).
    CameraStart(u64),
    /// The single camera pass (no deadline) finished this many more pixels.
    Pixels(usize),
    /// A camera pass (with a deadline) finished: the passes and camera paths per pixel so far,
    /// and the running relative error estimate (from the second pass on).
    Pass {
        /// Passes so far.
        passes: u64,
        /// Camera paths per pixel so far.
        spp: u64,
        /// [`Progressive::relative_error`].
        error: Option<f64>,
    },
}

/// What a bidirectional render did.
pub struct Run {
    /// The image.
    pub film: Film,
    /// Camera passes.
    pub passes: u64,
    /// Camera paths per pixel in all.
    pub spp: u64,
    /// The running estimate of the relative error (after two passes).
    pub error: Option<f64>,
    /// `stop` ended the render before its plan was done: the image is that of the passes
    /// completed (an unbiased estimate, as any number of passes is; §10.2).
    pub interrupted: bool,
}

/// Renders the light vertex cache `chunks` (lights `names`, their flux per path
/// `flux_per_path`) of `scene` through `camera` as `plan` says. Once `stop` returns true, the
/// passes completed make the image ([`Run::interrupted`]), or, before the first is complete,
/// there is none (`None`).
#[allow(clippy::too_many_arguments)]
pub fn render(
    scene: &Scene,
    camera: Sensor,
    chunks: Vec<CacheChunk<'_>>,
    names: &[&str],
    flux_per_path: &[Rgb],
    settings: Settings,
    plan: RunPlan,
    progress: impl Fn(RunEvent) + Sync,
    stop: impl Fn() -> bool + Sync,
) -> Option<Run> {
    let (w, h) = (camera.width(), camera.height());
    let per_pass = w as u64 * h as u64 * plan.spp as u64;
    let planned = match plan.deadline {
        None => per_pass,
        Some(deadline) => {
            let pilot =
                Renderer::new(scene, camera, chunks.clone(), names, flux_per_path, settings, per_pass);
            let t0 = Instant::now();
            pilot.camera_pass(u64::MAX, &Allocation::Uniform(1), |_| {}, &stop)?;
            let per_spp = t0.elapsed().as_secs_f64().max(1e-6);
            let left = deadline.saturating_duration_since(Instant::now()).as_secs_f64();
            let passes = (left / (per_spp * plan.spp as f64)).floor().max(1.0);
            per_pass * passes as u64
        }
    };
    let renderer = Renderer::new(scene, camera, chunks, names, flux_per_path, settings, planned);
    progress(RunEvent::SplatStart(renderer.cache().chunks().iter().map(|c| c.samples.len() as u64).sum()));
    let splat = renderer.splat_pass(|n| progress(RunEvent::Splatted(n)), &stop)?;
    progress(RunEvent::CameraStart(w as u64 * h as u64));
    let spp = Allocation::Uniform(plan.spp);
    let mut acc = Progressive::new(w, h, spp.clone());
    let mut interrupted = false;
    match plan.deadline {
        None => {
            let film =
                renderer.camera_pass(plan.first_pass, &spp, |n| progress(RunEvent::Pixels(n)), &stop)?;
            acc.add(&film);
        }
        Some(deadline) => {
            let mut pass = plan.first_pass;
            loop {
                let Some(film) = renderer.camera_pass(pass, &spp, |_| {}, &stop) else {
                    // The passes done stand on their own; with none there is no image.
                    if acc.passes() == 0 {
                        return None;
                    }
                    interrupted = true;
                    break;
                };
                acc.add(&film);
                pass += 1;
                progress(RunEvent::Pass {
                    passes: acc.passes(),
                    spp: acc.spp(),
                    error: acc.relative_error(),
                });
                if Instant::now() >= deadline {
                    break;
                }
            }
        }
    }
    let (passes, spp, error) = (acc.passes(), acc.spp(), acc.relative_error());
    Some(Run { film: acc.image(&splat), passes, spp, error, interrupted })
}
