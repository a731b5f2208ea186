//! Tracing options shared by `trace`, `refine`, `add-light` and `bench`: the thesis's improvements (§6.2) as switches,
//! so their effect can be measured (`docs/convergence.md`). Defaults follow the thesis (energy
//! roulette, importance sampling) and start roulette at depth 5 as Mitsuba does; roulette from
//! depth 1 measured 1.1-1.2x more efficient on the Cornell box, at a little more noise per path.

use clap::{Args, ValueEnum};
use opticks_core::dataset::{Directions, Heuristic, Roulette, Selection, StrategyChoice, TraceSettings};

/// Russian roulette rule.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum RouletteArg {
    /// Survival probability from the path's energy: min(0.95, 2·max β).
    Energy,
    /// Fixed survival probability 0.95.
    Fixed,
}

/// Continuation direction sampling.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum DirectionsArg {
    /// Importance sampling of the BSDF.
    Importance,
    /// Uniform over the hemisphere.
    Uniform,
}

/// Vertex selection for extension.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum SelectionArg {
    /// One continuation per vertex.
    Single,
    /// High-energy vertices get proportionally more continuations (unbiased splitting).
    Priority,
}

/// The MIS records stored with each sample for the bidirectional estimator.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum MisRecordsArg {
    /// Records for the power heuristic (β = 2).
    Power,
    /// Records for the balance heuristic (β = 1).
    Balance,
    /// No records: a third smaller dataset that only the light estimator can render.
    None,
}

/// How paths continue. Every option is optional: `trace` and `bench` fill in the defaults
/// below, `refine` and `add-light` the strategy of the dataset's last pass (so refining a
/// dataset traced with, say, `--roulette fixed` continues it with the same estimator).
#[derive(Args, Debug, Clone)]
pub struct StrategyArgs {
    /// Path depth from which Russian roulette may end paths [default: 5].
    #[arg(long)]
    pub rr_depth: Option<u32>,
    /// Russian roulette rule [default: energy].
    #[arg(long, value_enum)]
    pub roulette: Option<RouletteArg>,
    /// Direction sampling [default: importance].
    #[arg(long, value_enum)]
    pub directions: Option<DirectionsArg>,
    /// Vertex selection [default: single].
    #[arg(long, value_enum)]
    pub selection: Option<SelectionArg>,
    /// MIS records for the bidirectional estimator, 16 bytes per sample (docs/bidirectional.md) [default: power].
    #[arg(long, value_enum)]
    pub mis_records: Option<MisRecordsArg>,
}

/// The command-line spelling of a roulette rule (what `info` shows).
pub fn roulette_name(r: Roulette) -> &'static str {
    match r {
        Roulette::Energy => "energy",
        Roulette::Fixed => "fixed",
    }
}

/// The command-line spelling of a direction sampling.
pub fn directions_name(d: Directions) -> &'static str {
    match d {
        Directions::Importance => "importance",
        Directions::Uniform => "uniform",
    }
}

/// The command-line spelling of a vertex selection.
pub fn selection_name(s: Selection) -> &'static str {
    match s {
        Selection::Single => "single",
        Selection::Priority => "priority",
    }
}

/// The command-line spelling of a pass's MIS records (`--mis-records`).
pub fn mis_records_name(m: Option<Heuristic>) -> &'static str {
    match m {
        Some(Heuristic::Power) => "power",
        Some(Heuristic::Balance) => "balance",
        None => "none",
    }
}

impl StrategyArgs {
    /// Trace settings with these options over the defaults.
    pub fn settings(&self, paths: u64, seed: u64) -> TraceSettings {
        self.choice().over(TraceSettings { paths, seed, ..Default::default() })
    }

    /// The options given on the command line (each replaces the strategy it is applied to).
    pub fn choice(&self) -> StrategyChoice {
        StrategyChoice {
            rr_depth: self.rr_depth,
            roulette: self.roulette.map(|r| match r {
                RouletteArg::Energy => Roulette::Energy,
                RouletteArg::Fixed => Roulette::Fixed,
            }),
            directions: self.directions.map(|d| match d {
                DirectionsArg::Importance => Directions::Importance,
                DirectionsArg::Uniform => Directions::Uniform,
            }),
            selection: self.selection.map(|s| match s {
                SelectionArg::Single => Selection::Single,
                SelectionArg::Priority => Selection::Priority,
            }),
            mis: self.mis_records.map(|m| match m {
                MisRecordsArg::Power => Some(Heuristic::Power),
                MisRecordsArg::Balance => Some(Heuristic::Balance),
                MisRecordsArg::None => None,
            }),
        }
    }
}
