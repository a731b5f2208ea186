//! `--estimator light|bidirectional` and its options, shared by `render` and `walk`, and the
//! bidirectional render as the command line runs it: the dataset's chunks as the core's light
//! vertex cache (`opticks_io::light_cache`), one splat pass, then camera passes — a fixed
//! number of camera paths per pixel (`--spp`), or passes until `--time` is up with a progress
//! bar and the running error estimate of `opticks_core::sensor::bidirectional::Progressive`.

use super::LitDataset;
use crate::progress;
use anyhow::{Result, anyhow, bail};
use clap::ValueEnum;
use opticks_core::dataset::{Directions, MisUnavailable, mis_compatibility};
use opticks_core::film::Film;
use opticks_core::sensor::Sensor;
use opticks_core::sensor::bidirectional::{Heuristic, Progressive, Renderer, Settings};
use std::time::Instant;

/// Which estimator renders the image.
#[derive(ValueEnum, Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Estimator {
    /// The thesis's light tracer: every stored sample connected to the camera.
    #[default]
    Light,
    /// Camera paths with NEE, connections to the dataset and emitter hits, plus the light
    /// tracer's splats, combined by MIS: sees mirrors, glass and what lies behind them.
    Bidirectional,
}

/// The estimator options.
#[derive(clap::Args, Debug, Clone)]
pub struct EstimatorArgs {
    /// The estimator: `light` (the thesis's, the default) or `bidirectional` (needs a dataset
    /// with MIS records, written by this version's `trace`).
    #[arg(long, value_enum, default_value_t = Estimator::Light)]
    pub estimator: Estimator,
    /// Bidirectional: camera paths per pixel.
    #[arg(long, default_value_t = 16)]
    pub spp: u32,
    /// Bidirectional: dataset vertices each camera vertex connects to (n_c).
    #[arg(long, default_value_t = 1)]
    pub connections: u32,
    /// Bidirectional: seed of the camera paths' random streams.
    #[arg(long = "camera-seed", default_value_t = 0)]
    pub seed: u64,
}

/// What a bidirectional render did.
pub struct BidirectionalRun {
    /// The image.
    pub film: Film,
    /// Camera passes and camera paths per pixel.
    pub passes: u64,
    /// Camera paths per pixel in all.
    pub spp: u64,
    /// The running estimate of the relative error (after two passes).
    pub error: Option<f64>,
}

impl EstimatorArgs {
    /// Checks the options that do not depend on the dataset.
    pub fn check(&self) -> Result<()> {
        if self.estimator == Estimator::Bidirectional && self.spp == 0 {
            bail!("--spp must be at least 1");
        }
        Ok(())
    }

    /// Renders `data` through `camera` bidirectionally: `self.spp` camera paths per pixel in one
    /// pass, or, with `time`, passes of that many until `time` seconds have passed since the
    /// start. `pass` names the first pass's random streams (a walkthrough's frame number).
    pub fn render(
        &self,
        data: &LitDataset,
        camera: &Sensor,
        time: Option<f64>,
        pass: u64,
        bars: bool,
    ) -> Result<BidirectionalRun> {
        let start = Instant::now();
        let (heuristic, directions) = mis_settings(data)?;
        let chunks = data.cache_chunks()?;
        if !chunks.iter().all(|c| c.records.len() == c.samples.len()) {
            bail!("{}: a chunk of a pass with MIS records has none", data.reader.path().display());
        }
        let names = data.light_names();
        let settings = Settings { connections: self.connections, seed: self.seed, heuristic, directions };
        let (w, h) = (camera.width(), camera.height());
        let per_pass = w as u64 * h as u64 * self.spp as u64;
        let stop = crate::interrupt::requested;
        let interrupted = || anyhow!("interrupted: stopped, nothing written");
        // M, the camera paths the render will take: known for --spp; for --time planned from a
        // one-path-per-pixel pilot (any constant is unbiased, docs/bidirectional.md §10.2).
        let planned = match time {
            None => per_pass,
            Some(t) => {
                let pilot = Renderer::new(
                    &data.scene,
                    *camera,
                    chunks.clone(),
                    &names,
                    data.flux_per_path(),
                    settings,
                    per_pass,
                );
                let t0 = Instant::now();
                pilot.camera_pass(u64::MAX, 1, |_| {}, stop).ok_or_else(interrupted)?;
                let per_spp = t0.elapsed().as_secs_f64().max(1e-6);
                let left = (t - start.elapsed().as_secs_f64()).max(0.0);
                let passes = (left / (per_spp * self.spp as f64)).floor().max(1.0);
                per_pass * passes as u64
            }
        };
        let renderer =
            Renderer::new(&data.scene, *camera, chunks, &names, data.flux_per_path(), settings, planned);
        let samples: u64 = renderer.cache().chunks().iter().map(|c| c.samples.len() as u64).sum();
        let pb = if bars {
            progress::bar(samples, "splatting", "samples")
        } else {
            indicatif::ProgressBar::hidden()
        };
        let splat = renderer.splat_pass(|n| pb.inc(n as u64), stop).ok_or_else(interrupted)?;
        pb.finish_and_clear();
        let mut acc = Progressive::new(w, h);
        match time {
            None => {
                let pb = if bars {
                    progress::bar(w as u64 * h as u64, "camera", "pixels")
                } else {
                    indicatif::ProgressBar::hidden()
                };
                let film = renderer
                    .camera_pass(pass, self.spp, |n| pb.inc(n as u64), stop)
                    .ok_or_else(interrupted)?;
                pb.finish_and_clear();
                acc.add(&film, self.spp);
            }
            Some(t) => {
                let pb = if bars { progress::seconds_bar(t) } else { indicatif::ProgressBar::hidden() };
                let mut p = pass;
                loop {
                    let film = renderer.camera_pass(p, self.spp, |_| {}, stop).ok_or_else(interrupted)?;
                    acc.add(&film, self.spp);
                    p += 1;
                    let elapsed = start.elapsed().as_secs_f64();
                    pb.set_position(elapsed.min(t) as u64);
                    pb.set_message(match acc.relative_error() {
                        Some(e) => format!(
                            "{} passes, {} spp, rel. error ≈ {:.2}%",
                            acc.passes(),
                            acc.spp(),
                            100.0 * e
                        ),
                        None => format!("{} passes, {} spp", acc.passes(), acc.spp()),
                    });
                    if elapsed >= t {
                        break;
                    }
                }
                pb.finish_and_clear();
            }
        }
        Ok(BidirectionalRun {
            film: acc.image(&splat),
            passes: acc.passes(),
            spp: acc.spp(),
            error: acc.relative_error(),
        })
    }
}

/// The heuristic and direction strategy the dataset's records were traced with
/// (`opticks_core::dataset::mis_compatibility`, which words why a dataset cannot be rendered
/// with MIS); the command line adds the other way out.
fn mis_settings(data: &LitDataset) -> Result<(Heuristic, Directions)> {
    let s = mis_compatibility(data.reader.header()).map_err(|e| {
        let path = data.reader.path().display();
        match e {
            MisUnavailable::NoRecords { .. } | MisUnavailable::Signature { .. } => anyhow!(
                "{path}: {e} (`opticks upgrade {path}` does that; or render it with --estimator light)"
            ),
            _ => anyhow!("{path}: {e} (or render it with --estimator light)"),
        }
    })?;
    Ok((s.heuristic, s.directions))
}
