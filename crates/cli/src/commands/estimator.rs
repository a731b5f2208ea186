//! `--estimator light|bidirectional` and its options, shared by `render` and `walk`, and the
//! bidirectional render as the command line runs it: the dataset's chunks as the core's light
//! vertex cache (`opticks_io::light_cache`), one splat pass, then camera passes — a fixed
//! number of camera paths per pixel (`--spp`), or passes until `--time` is up with a progress
//! bar and the running error estimate of `opticks_core::sensor::bidirectional::Progressive`.

use crate::progress;
use anyhow::{Result, anyhow, bail};
use clap::ValueEnum;
use opticks_core::dataset::MisUnavailable;
use opticks_core::sensor::Sensor;
use opticks_core::sensor::bidirectional::MAX_CONNECTIONS;
use opticks_core::sensor::bidirectional::run::{Coverage, Run, RunEvent, RunPlan};
use opticks_io::opened::{BidirectionalError, LitDataset};
use std::time::{Duration, Instant};

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

/// The estimator options. The bidirectional estimator's own options are `Option`s so that one
/// given with the light estimator, where it would do nothing, is refused rather than ignored.
#[derive(clap::Args, Debug, Clone)]
pub struct EstimatorArgs {
    /// The estimator: `light` (the thesis's, the default) or `bidirectional` (needs a dataset
    /// with MIS records, written by this version's `trace`).
    #[arg(long, value_enum, default_value_t = Estimator::Light)]
    pub estimator: Estimator,
    /// Bidirectional: camera paths per pixel (default 16); e.g. 64, 1k, 1e6.
    #[arg(long, allow_hyphen_values = true, value_parser = opticks_io::count_text::parse_spp)]
    spp: Option<u32>,
    /// Bidirectional: dataset vertices each camera vertex connects to (n_c; default 1, at most
    /// 1024).
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..=MAX_CONNECTIONS as i64))]
    connections: Option<u32>,
    /// Bidirectional: seed of the camera paths' random streams (default 0).
    #[arg(long = "camera-seed")]
    seed: Option<u64>,
    /// Bidirectional: which pixels get camera paths — `auto` (the default: those through which
    /// something other than a diffuse surface, or the sky, may be seen, and the image tiles where
    /// a short pilot finds them worth their time), `where-needed` (the former alone; the others
    /// are the light estimator's pixels, unbiased) or `everywhere`.
    #[arg(long, value_enum)]
    coverage: Option<CoverageArg>,
}

/// `--coverage`: which pixels get camera paths.
#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoverageArg {
    /// The pixels the splats cannot render alone, and where a pilot finds camera paths pay.
    Auto,
    /// Only the pixels the light-tracing splats cannot render alone.
    WhereNeeded,
    /// Every pixel.
    Everywhere,
}

impl EstimatorArgs {
    /// Camera paths per pixel.
    pub fn spp(&self) -> u32 {
        self.spp.unwrap_or(16)
    }

    /// n_c.
    pub fn connections(&self) -> u32 {
        self.connections.unwrap_or(1)
    }

    /// Checks the options that do not depend on the dataset: the bidirectional estimator's own
    /// options are refused with the light estimator, which has no use for them.
    pub fn check(&self) -> Result<()> {
        if self.estimator == Estimator::Light {
            let given: Vec<&str> = [
                (self.spp.is_some(), "--spp"),
                (self.connections.is_some(), "--connections"),
                (self.seed.is_some(), "--camera-seed"),
                (self.coverage.is_some(), "--coverage"),
            ]
            .into_iter()
            .filter_map(|(given, name)| given.then_some(name))
            .collect();
            if !given.is_empty() {
                bail!(
                    "{} applies to --estimator bidirectional; the light estimator has no camera paths",
                    given.join(", ")
                );
            }
        }
        if self.spp == Some(0) {
            bail!("--spp must be at least 1");
        }
        Ok(())
    }

    /// Renders `data` through `camera` bidirectionally (`opticks_core::sensor::bidirectional::run`):
    /// `self.spp()` camera paths per pixel in one pass, or, with `time`, passes of that many until
    /// `time` seconds have passed since the start. `pass` names the first pass's random streams
    /// (a walkthrough's frame number).
    pub fn render(
        &self,
        data: &LitDataset,
        camera: &Sensor,
        time: Option<Duration>,
        pass: u64,
        bars: bool,
    ) -> Result<Run> {
        let start = Instant::now();
        let deadline = time.map(|t| start + t);
        let coverage = match self.coverage {
            Some(CoverageArg::Everywhere) => Coverage::Everywhere,
            Some(CoverageArg::WhereNeeded) => Coverage::WhereNeeded,
            Some(CoverageArg::Auto) | None => Coverage::Auto,
        };
        let plan = RunPlan { spp: self.spp(), deadline, first_pass: pass };
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
                Some(t) => progress::seconds_bar(t.as_secs_f64()),
            }),
            RunEvent::Splatted(n) | RunEvent::Pixels(n) => {
                bar.lock().unwrap_or_else(|e| e.into_inner()).inc(n as u64)
            }
            RunEvent::Pass { passes, spp, error } => {
                let b = bar.lock().unwrap_or_else(|e| e.into_inner());
                b.set_position(start.elapsed().min(time.unwrap_or_default()).as_secs());
                b.set_message(match error {
                    Some(e) => format!("{passes} passes, {spp} spp, rel. error ≈ {:.2}%", 100.0 * e),
                    None => format!("{passes} passes, {spp} spp"),
                });
            }
            _ => {}
        };
        let run = data.render_bidirectional(
            *camera,
            self.connections(),
            self.seed.unwrap_or(0),
            plan,
            coverage,
            event,
            crate::interrupt::requested,
        );
        show(indicatif::ProgressBar::hidden());
        run.map_err(|e| match &e {
            BidirectionalError::Mis { path, source } => {
                let path = path.display();
                match source {
                    MisUnavailable::NoRecords { .. } | MisUnavailable::Signature { .. } => anyhow!(
                        "{e} (`opticks upgrade {path}` does that; or render it with --estimator light)"
                    ),
                    _ => anyhow!("{e} (or render it with --estimator light)"),
                }
            }
            _ => e.into(),
        })
    }
}
