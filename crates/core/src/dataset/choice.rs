//! The names of a trace's options — roulette rule, direction sampling, vertex selection, MIS
//! records — as every front end spells them (`--roulette energy`, `info`'s summary, a binding's
//! keyword): one table per option, here with the options, so no front end keeps its own copy.

use super::{Directions, Heuristic, Roulette, Selection};

/// An option with a fixed set of named values.
pub trait Choice: Copy + PartialEq + Send + Sync + 'static {
    /// Every value, the default first.
    const ALL: &'static [Self];
    /// Its name (lower case, as typed).
    fn name(self) -> &'static str;
    /// One line on what it does.
    fn help(self) -> &'static str;
    /// The value named `name`, if any.
    fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|c| c.name() == name)
    }
}

impl Choice for Roulette {
    const ALL: &'static [Self] = &[Roulette::Energy, Roulette::Fixed];
    fn name(self) -> &'static str {
        match self {
            Roulette::Energy => "energy",
            Roulette::Fixed => "fixed",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Roulette::Energy => "Survival probability from the path's energy: min(0.95, 2·max β)",
            Roulette::Fixed => "Fixed survival probability 0.95",
        }
    }
}

impl Choice for Directions {
    const ALL: &'static [Self] = &[Directions::Importance, Directions::Uniform];
    fn name(self) -> &'static str {
        match self {
            Directions::Importance => "importance",
            Directions::Uniform => "uniform",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Directions::Importance => "Importance sampling of the BSDF",
            Directions::Uniform => "Uniform over the hemisphere",
        }
    }
}

impl Choice for Selection {
    const ALL: &'static [Self] = &[Selection::Single, Selection::Priority];
    fn name(self) -> &'static str {
        match self {
            Selection::Single => "single",
            Selection::Priority => "priority",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Selection::Single => "One continuation per vertex",
            Selection::Priority => {
                "High-energy vertices get proportionally more continuations (unbiased splitting)"
            }
        }
    }
}

/// The MIS records a pass stores: for a heuristic, or none.
impl Choice for Option<Heuristic> {
    const ALL: &'static [Self] = &[Some(Heuristic::Power), Some(Heuristic::Balance), None];
    fn name(self) -> &'static str {
        match self {
            Some(Heuristic::Power) => "power",
            Some(Heuristic::Balance) => "balance",
            None => "none",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Some(Heuristic::Power) => "Records for the power heuristic (β = 2)",
            Some(Heuristic::Balance) => "Records for the balance heuristic (β = 1)",
            None => "No records: a third smaller dataset that only the light estimator can render",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trips<C: Choice + std::fmt::Debug>() {
        for &c in C::ALL {
            assert_eq!(C::from_name(c.name()), Some(c), "{c:?}");
            assert!(!c.help().is_empty());
        }
        assert_eq!(C::from_name("no such value"), None);
    }

    #[test]
    fn every_name_is_unique_and_parses_back() {
        round_trips::<Roulette>();
        round_trips::<Directions>();
        round_trips::<Selection>();
        round_trips::<Option<Heuristic>>();
        assert_eq!(Roulette::ALL[0], Roulette::default());
        assert_eq!(Directions::ALL[0], Directions::default());
        assert_eq!(Selection::ALL[0], Selection::default());
    }
}
