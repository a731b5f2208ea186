//! Tracing options shared by `trace`, `refine`, `add-light` and `bench`: the thesis's improvements (§6.2) as switches,
//! so their effect can be measured (`docs/convergence.md`). Defaults follow the thesis (energy
//! roulette, importance sampling) and start roulette at depth 5 as Mitsuba does; roulette from
//! depth 1 measured 1.1-1.2x more efficient on the Cornell box, at a little more noise per path.

use clap::Args;
use clap::builder::TypedValueParser;
use opticks_core::dataset::{
    Choice, Directions, Heuristic, Roulette, Selection, StrategyChoice, TraceSettings,
};

/// A clap parser for a [`Choice`]: its names, with their help, and nothing else.
pub fn choice<C: Choice + Clone>() -> impl clap::builder::TypedValueParser<Value = C> {
    let values = C::ALL.iter().map(|c| clap::builder::PossibleValue::new(c.name()).help(c.help()));
    // Only the names listed are accepted, so the lookup finds one.
    clap::builder::PossibleValuesParser::new(values).map(|name| C::from_name(&name).unwrap_or(C::ALL[0]))
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
    #[arg(long, value_parser = choice::<Roulette>())]
    pub roulette: Option<Roulette>,
    /// Direction sampling [default: importance].
    #[arg(long, value_parser = choice::<Directions>())]
    pub directions: Option<Directions>,
    /// Vertex selection [default: single].
    #[arg(long, value_parser = choice::<Selection>())]
    pub selection: Option<Selection>,
    /// MIS records for the bidirectional estimator, 16 bytes per sample (docs/bidirectional.md) [default: power].
    #[arg(long, value_parser = choice::<MisRecords>())]
    pub mis_records: Option<MisRecords>,
}

/// The value of `--mis-records` (`none` or a heuristic). An alias, because clap's derive reads
/// a literal `Option<Option<T>>` as a flag whose value may be left out.
pub type MisRecords = Option<Heuristic>;

impl StrategyArgs {
    /// Trace settings with these options over the defaults.
    pub fn settings(&self, paths: u64, seed: u64) -> TraceSettings {
        self.choice().over(TraceSettings { paths, seed, ..Default::default() })
    }

    /// The options given on the command line (each replaces the strategy it is applied to).
    pub fn choice(&self) -> StrategyChoice {
        StrategyChoice {
            rr_depth: self.rr_depth,
            roulette: self.roulette,
            directions: self.directions,
            selection: self.selection,
            mis: self.mis_records,
        }
    }
}
