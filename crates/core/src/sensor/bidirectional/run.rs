//! A whole bidirectional render as a front end asks for one: one splat pass over the light
//! vertex cache, then camera passes — a fixed number of camera paths per pixel, or passes until
//! a deadline — accumulated with the running error estimate of [`Progressive`]. Progress and
//! interruption go through callbacks, so the command line's bars, a binding's callback and a
//! server's status all drive the same loop.
//!
//! Which pixels get camera paths is the caller's ([`Coverage`]: by default those the splats
//! alone cannot render unbiased, `allocation` module docs, and those a pilot finds worth it,
//! `pilot`); with none, the render is its splat pass alone.
//!
//! With a deadline, M (the camera paths the render will take, which the MIS weights of the
//! light-tracing strategy need before the first pass) is planned from a pilot pass of one path
//! per pixel; any constant M is unbiased (`docs/bidirectional.md` §10.2), so the plan only
//! balances the strategies, and the render stops at the first pass ending past the deadline.

use super::{Allocation, CacheChunk, Progressive, Renderer, Settings};
use crate::film::Film;
use crate::math::Rgb;
use crate::scene::Scene;
use crate::sensor::{Sensor, VisibilityBuffer};
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

/// Which pixels a render gives camera paths (a front end decides, before [`render`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Coverage {
    /// Those of [`Coverage::WhereNeeded`], and the image tiles of the others where a pilot finds
    /// camera paths worth their work ([`super::pilot`]).
    #[default]
    Auto,
    /// Only those the light-tracing splats alone cannot render unbiased: any surface but a
    /// diffuse one, or the sky, may be seen through them ([`super::cameras_needed`]). The
    /// others are the light estimator's pixels.
    WhereNeeded,
    /// Every pixel.
    Everywhere,
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
    /// Camera paths in all per pixel that gets any ([`Run::camera_pixels`]).
    pub spp: u64,
    /// The running estimate of the relative error (after two passes).
    pub error: Option<f64>,
    /// `stop` ended the render before its plan was done: the image is that of the passes
    /// completed (an unbiased estimate, as any number of passes is; §10.2).
    pub interrupted: bool,
    /// Pixels given camera paths ([`Coverage`]); the others are the splats' alone.
    pub camera_pixels: u64,
}

impl Run {
    /// A render without camera paths: the light estimator's image, `film`.
    pub fn splats_alone(film: Film) -> Run {
        Run { film, passes: 0, spp: 0, error: None, interrupted: false, camera_pixels: 0 }
    }
}

/// Renders the light vertex cache `chunks` (lights `names`, their flux per path
/// `flux_per_path`) of `scene` through `camera` as `plan` says, camera paths in the pixels
/// `cameras` marks (`None`: in every pixel; with none marked, the splat pass alone).
/// `visibility` is the camera's visibility buffer, `camera.visibility(scene)`, built by the
/// caller (who chose `cameras` with it). Once `stop` returns true, the
/// passes completed make the image ([`Run::interrupted`]), or, before the first is complete,
/// there is none (`None`).
#[allow(clippy::too_many_arguments)]
pub fn render(
    scene: &Scene,
    camera: Sensor,
    visibility: Option<VisibilityBuffer>,
    chunks: Vec<CacheChunk<'_>>,
    names: &[&str],
    flux_per_path: &[Rgb],
    settings: Settings,
    plan: RunPlan,
    cameras: Option<&[bool]>,
    progress: impl Fn(RunEvent) + Sync,
    stop: impl Fn() -> bool + Sync,
) -> Option<Run> {
    let (w, h) = (camera.width(), camera.height());
    let mut renderer =
        Renderer::with_visibility(scene, camera, visibility, chunks, names, flux_per_path, settings, 1);
    let spp = Allocation::where_needed(cameras, plan.spp);
    let per_pass = spp.total(w as usize * h as usize);
    let passes = match plan.deadline {
        _ if per_pass == 0 => 0, // every pixel is the splats'
        None => 1,
        Some(deadline) => {
            // A pilot pass of one path per pixel that gets any, timed, plans the passes.
            let one = Allocation::where_needed(cameras, 1);
            renderer.plan(&one, 1);
            let t0 = Instant::now();
            renderer.camera_pass(u64::MAX, &one, |_| {}, &stop)?;
            let per_spp = t0.elapsed().as_secs_f64().max(1e-6);
            let left = deadline.saturating_duration_since(Instant::now()).as_secs_f64();
            (left / (per_spp * plan.spp as f64)).floor().max(1.0) as u64
        }
    };
    renderer.plan(&spp, passes);
    progress(RunEvent::SplatStart(renderer.cache().chunks().iter().map(|c| c.samples.len() as u64).sum()));
    let splat = renderer.splat_pass(|n| progress(RunEvent::Splatted(n)), &stop)?;
    if per_pass == 0 {
        return Some(Run {
            film: splat,
            passes: 0,
            spp: 0,
            error: None,
            interrupted: false,
            camera_pixels: 0,
        });
    }
    progress(RunEvent::CameraStart(w as u64 * h as u64));
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
                    spp: acc.passes() * plan.spp as u64,
                    error: acc.relative_error(),
                });
                if Instant::now() >= deadline {
                    break;
                }
            }
        }
    }
    let (passes, error) = (acc.passes(), acc.relative_error());
    let spp = passes * plan.spp as u64;
    let camera_pixels = cameras.map_or(w as u64 * h as u64, |n| n.iter().filter(|&&x| x).count() as u64);
    Some(Run { film: acc.image(&splat), passes, spp, error, interrupted, camera_pixels })
}
