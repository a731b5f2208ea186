//! Whether a dataset can be rendered with the bidirectional estimator's multiple importance
//! sampling (`docs/bidirectional.md` §6–7): its MIS records must exist for every pass and be
//! exact for the combination the dataset is. The records of a pass depend on the heuristic it
//! was traced for, the tracer's densities (its sampling signature) and the light tracer's
//! direction rule; they depend on nothing a law changes — not on Φ_k, N_k, the roulette,
//! the selection, the seed or the stream — so merged, refined, resumed, relit, extended and
//! previewed datasets keep exact records, **if** every pass agrees on those three. Passes that
//! disagree still merge (the light estimator needs no records), but the result is refused here,
//! with the reason and the fix.
//!
//! The records themselves live here too, because the tracer computes them and the dataset
//! stores them: `recursion.rs` holds the [`Heuristic`] and the per-vertex recursion both sides
//! of the bidirectional estimator carry, `record.rs` the light side — a light's emission
//! densities ([`Emitter`]), a light vertex's state ([`LightVertexMis`]) and its stored form
//! ([`MisRecord`]). The estimator's camera side, in the bidirectional sensor, uses them;
//! nothing here depends on it.

use super::{DatasetHeader, Directions};
use crate::trace::SAMPLING_SIGNATURE;

mod record;
mod recursion;

pub use record::{Emitter, LightKind, LightVertexMis, MisRecord, VcmClass};
pub use recursion::Heuristic;
pub(crate) use recursion::{Subpath, div, mul};

/// What the camera side needs to weight a dataset's strategies: the heuristic its records are
/// powered for, and the light tracer's direction rule (for
/// [`crate::trace::light_direction_pdf`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MisSettings {
    /// The heuristic of every pass's records.
    pub heuristic: Heuristic,
    /// The direction rule every pass traced with.
    pub directions: Directions,
}

/// Why a dataset cannot be rendered with MIS, and what to do about it. Passes are numbered from
/// 0 in the header's order.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MisUnavailable {
    /// No pass traced any path.
    #[error("the dataset has no traced paths")]
    NoPaths,
    /// A pass stored no records.
    #[error(
        "pass {pass} (seed {seed}, stream {stream}) was traced without MIS records (by an Opticks older \
         than dataset format 3, or with them switched off): re-trace the dataset with MIS records, or \
         upgrade it (its passes re-traced from their own seeds and streams), to render it with the \
         bidirectional estimator"
    )]
    NoRecords {
        /// The pass.
        pass: usize,
        /// Its seed.
        seed: u64,
        /// Its stream.
        stream: u64,
    },
    /// Two passes' records are powered for different heuristics.
    #[error(
        "pass {pass}'s MIS records are for the {other:?} heuristic, pass {first_pass}'s for the {first:?} \
         heuristic: a merged dataset needs one heuristic for all its records; re-trace (or refine into) \
         the dataset with one heuristic"
    )]
    Heuristics {
        /// The first pass with records.
        first_pass: usize,
        /// Its heuristic.
        first: Heuristic,
        /// The pass that differs.
        pass: usize,
        /// Its heuristic.
        other: Heuristic,
    },
    /// A pass's records were computed by a tracer whose densities differ from this build's.
    #[error(
        "pass {pass}'s MIS records were computed by a tracer of sampling signature {found}, this build's \
         is {supported}: the densities they hold are no longer the ones this build samples with; \
         re-trace the dataset (or upgrade it) to render it with the bidirectional estimator"
    )]
    Signature {
        /// The pass.
        pass: usize,
        /// Its signature.
        found: u32,
        /// This build's ([`SAMPLING_SIGNATURE`]).
        supported: u32,
    },
    /// Two passes traced with different direction rules: their paths come from different
    /// densities, a mixture no record describes.
    #[error(
        "pass {pass} traced with {other:?} directions, pass {first_pass} with {first:?}: the paths of a \
         dataset rendered with MIS must come from one light-tracer density; trace (or refine) every pass \
         with the same directions"
    )]
    Directions {
        /// The first pass.
        first_pass: usize,
        /// Its rule.
        first: Directions,
        /// The pass that differs.
        pass: usize,
        /// Its rule.
        other: Directions,
    },
}

/// Whether the dataset of `header` can be rendered with MIS by this build, and with what: every
/// pass that traced paths must carry records ([`super::TracePass::mis`]) of one heuristic, of
/// this build's [`SAMPLING_SIGNATURE`], traced with one direction rule. Passes without paths
/// (an interrupted run's pass saved before its first block) do not count.
pub fn mis_compatibility(header: &DatasetHeader) -> Result<MisSettings, MisUnavailable> {
    let mut first: Option<(usize, MisSettings)> = None;
    for (i, p) in header.trace.passes.iter().enumerate().filter(|(_, p)| p.paths > 0) {
        let Some(mis) = p.mis else {
            return Err(MisUnavailable::NoRecords { pass: i, seed: p.seed, stream: p.stream });
        };
        if mis.signature != SAMPLING_SIGNATURE {
            return Err(MisUnavailable::Signature {
                pass: i,
                found: mis.signature,
                supported: SAMPLING_SIGNATURE,
            });
        }
        let Some((first_pass, f)) = first else {
            first = Some((i, MisSettings { heuristic: mis.heuristic, directions: p.directions }));
            continue;
        };
        if mis.heuristic != f.heuristic {
            return Err(MisUnavailable::Heuristics {
                first_pass,
                first: f.heuristic,
                pass: i,
                other: mis.heuristic,
            });
        }
        if p.directions != f.directions {
            return Err(MisUnavailable::Directions {
                first_pass,
                first: f.directions,
                pass: i,
                other: p.directions,
            });
        }
    }
    first.map(|f| f.1).ok_or(MisUnavailable::NoPaths)
}

#[cfg(test)]
mod tests;
