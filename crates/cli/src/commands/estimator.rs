//! `--estimator light|bidirectional` and its options, shared by `render` and `walk`, and the
//! bidirectional render as the command line runs it: the dataset's chunks as the core's light
//! vertex cache (`opticks_io::light_cache`), one splat pass, then camera passes — a fixed
//! number of camera paths per pixel (`--spp`), or passes until `--time` is up with a progress
//! bar and the running error estimate of `opticks_core::sensor::bidirectional::Progressive`.

use crate::progress;
use anyhow::{Result, anyhow, bail};
use clap::ValueEnum;
use opticks_core::dataset::{Directions, Heuristic, MisUnavailable, mis_compatibility};
use opticks_core::sensor::Sensor;
use opticks_core::sensor::bidirectional::Settings;
use opticks_core::sensor::bidirectional::run::{self, Run, RunEvent, RunPlan};
use opticks_io::opened::LitDataset;
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

impl EstimatorArgs {
    /// Checks the options that do not depend on the dataset.
    pub fn check(&self) -> Result<()> {
        if self.estimator == Estimator::Bidirectional && self.spp == 0 {
            bail!("--spp must be at least 1");
        }
        Ok(())
    }

    /// Renders `data` through `camera` bidirectionally (`opticks_core::sensor::bidirectional::run`):
    /// `self.spp` camera paths per pixel in one pass, or, with `time`, passes of that many until
    /// `time` seconds have passed since the start. `pass` names the first pass's random streams
    /// (a walkthrough's frame number).
    pub fn render(
        &self,
        data: &LitDataset,
        camera: &Sensor,
        time: Option<f64>,
        pass: u64,
        bars: bool,
    ) -> Result<Run> {
        let start = Instant::now();
        let (heuristic, directions) = mis_settings(data)?;
        let chunks = data.cache_chunks()?;
        if !chunks.iter().all(|c| c.records.len() == c.samples.len()) {
            bail!("{}: a chunk of a pass with MIS records has none", data.reader().path().display());
        }
        let settings = Settings { connections: self.connections, seed: self.seed, heuristic, directions };
        let deadline = time.map(|t| start + std::time::Duration::from_secs_f64(t));
        let plan = RunPlan { spp: self.spp, deadline, first_pass: pass };
        let bar = std::sync::Mutex::new(indicatif::ProgressBar::hidden());
        let show = |new: indicatif::ProgressBar| {
            let mut b = bar.lock().unwrap_or_else(|e| e.into_inner());
            b.finish_and_clear();
            *b = new;
        };
        let event = |e: RunEvent| match e {
            RunEvent::SplatStart(samples) if bars => show(progress::bar(samples, "splatting", "samples")),
            RunEvent::CameraStart(pixels) if bars => show(match time {
                None => progress::bar(pixels, "camera", "pixels"),
                Some(t) => progress::seconds_bar(t),
            }),
            RunEvent::Splatted(n) | RunEvent::Pixels(n) => {
                bar.lock().unwrap_or_else(|e| e.into_inner()).inc(n as u64)
            }
            RunEvent::Pass { passes, spp, error } => {
                let b = bar.lock().unwrap_or_else(|e| e.into_inner());
                b.set_position(start.elapsed().as_secs_f64().min(time.unwrap_or(0.0)) as u64);
                b.set_message(match error {
                    Some(e) => format!("{passes} passes, {spp} spp, rel. error ≈ {:.2}%", 100.0 * e),
                    None => format!("{passes} passes, {spp} spp"),
                });
            }
            _ => {}
        };
        let names = data.light_names();
        let stop = crate::interrupt::requested;
        let run = run::render(
            data.scene(),
            *camera,
            chunks,
            &names,
            data.flux_per_path(),
            settings,
            plan,
            event,
            stop,
        );
        show(indicatif::ProgressBar::hidden());
        run.ok_or_else(|| anyhow!("interrupted: stopped, nothing written"))
    }
}

/// The heuristic and direction strategy the dataset's records were traced with
/// (`opticks_core::dataset::mis_compatibility`, which words why a dataset cannot be rendered
/// with MIS); the command line adds the other way out.
fn mis_settings(data: &LitDataset) -> Result<(Heuristic, Directions)> {
    let s = mis_compatibility(data.reader().header()).map_err(|e| {
        let path = data.reader().path().display();
        match e {
            MisUnavailable::NoRecords { .. } | MisUnavailable::Signature { .. } => anyhow!(
                "{path}: {e} (`opticks upgrade {path}` does that; or render it with --estimator light)"
            ),
            _ => anyhow!("{path}: {e} (or render it with --estimator light)"),
        }
    })?;
    Ok((s.heuristic, s.directions))
}
