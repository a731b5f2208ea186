//! Tracing options shared by `trace` and `bench`: the thesis's improvements (§6.2) as switches,
//! so their effect can be measured (`docs/convergence.md`). Defaults follow the thesis (energy
//! roulette, importance sampling) and start roulette at depth 5 as Mitsuba does; roulette from
//! depth 1 measured 1.1-1.2x more efficient on the Cornell box, at a little more noise per path.

use clap::{Args, ValueEnum};
use opticks_core::trace::{Directions, Roulette, Selection, TraceSettings};

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

/// How paths continue.
#[derive(Args, Debug, Clone)]
pub struct StrategyArgs {
    /// Path depth from which Russian roulette may end paths.
    #[arg(long, default_value_t = 5)]
    pub rr_depth: u32,
    /// Russian roulette rule (thesis §6.2.1).
    #[arg(long, value_enum, default_value = "energy")]
    pub roulette: RouletteArg,
    /// Direction sampling (thesis §6.2.2).
    #[arg(long, value_enum, default_value = "importance")]
    pub directions: DirectionsArg,
    /// Priority sample selection (thesis §6.2.3).
    #[arg(long, value_enum, default_value = "single")]
    pub selection: SelectionArg,
}

impl StrategyArgs {
    /// Trace settings with these options.
    pub fn settings(&self, paths: u64, seed: u64) -> TraceSettings {
        TraceSettings {
            paths,
            seed,
            stream: 0,
            rr_depth: self.rr_depth,
            roulette: match self.roulette {
                RouletteArg::Energy => Roulette::Energy,
                RouletteArg::Fixed => Roulette::Fixed,
            },
            directions: match self.directions {
                DirectionsArg::Importance => Directions::Importance,
                DirectionsArg::Uniform => Directions::Uniform,
            },
            selection: match self.selection {
                SelectionArg::Single => Selection::Single,
                SelectionArg::Priority => Selection::Priority,
            },
        }
    }
}
