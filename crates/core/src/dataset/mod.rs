//! The dataset: what light sampling produces and every sensor consumes. A light table
//! (Φ_k, N_k per light) and chunks of compact [`Sample`] records, each chunk from one light.
//!
//! The estimator contract (docs/estimator.md §2): a sample of light k with weight β stands for the
//! incident flux Φ_k·β/N_k. Each light's energy is split only among its own N_k paths, so
//! relighting (scaling Φ_k) and merging (summing N_k) are exact laws, not approximations.
//!
//! Every law and operation of the dataset is a function here; the file format
//! (`opticks_io::dataset_file`) only encodes and decodes, and the command line only parses and
//! prints:
//!
//! * the model — [`Sample`], [`Chunk`], [`LightTable`] (`sample.rs`, `table.rs`) and the
//!   header: fingerprint, label, passes ([`DatasetHeader`], `header.rs`);
//! * the trace plan — [`TraceSettings`] and the strategy, quotas ∝ power, the block order
//!   (`plan.rs`), carried out by `crate::trace`;
//! * the passes a dataset gains — a first trace, a refinement, an added light (`extend.rs`),
//!   the rest of an interrupted pass (`resume.rs`) — and their bookkeeping
//!   ([`DatasetHeader::record_traced`]); a pass traced by many hands, its chunks put back in
//!   block order ([`PassDispatch`], `dispatch.rs`);
//! * the laws of using one — relighting (`relight.rs`), merging (`merge.rs`), a preview from a
//!   subset of chunks (`subset.rs`) — and the dataset-versus-scene check (`scene_check.rs`);
//! * the MIS records (one per sample, [`Chunk::records`]) and whether they serve the
//!   bidirectional estimator ([`mis_compatibility`], `mis/mod.rs`): every law keeps them exact
//!   as long as all passes agree on heuristic, sampling signature and direction rule; a dataset
//!   without them gains them by re-tracing its passes block for block ([`upgrade_plan`],
//!   `upgrade.rs`). The records themselves — the [`Heuristic`] and the recursion both sides of
//!   the estimator share (`mis/recursion.rs`), the light side the tracer walks and stores
//!   ([`Emitter`], [`LightVertexMis`], [`MisRecord`], `mis/record.rs`) — are the dataset's too,
//!   so the sensors use what the dataset stores and the dataset and the tracer never use a
//!   sensor.

mod choice;
mod dispatch;
mod extend;
mod header;
mod merge;
pub(crate) mod mis;
mod plan;
mod relight;
mod resume;
mod sample;
mod scene_check;
mod subset;
mod table;
#[cfg(test)]
pub(crate) mod testing;
mod upgrade;

pub use choice::Choice;
pub use dispatch::{NumberedBlock, PassDispatch};
pub use extend::{AddLightError, add_light, continued_settings, fair_share, new_trace, refine};
pub use header::{DatasetHeader, NoPassRecord, PassMis, TraceInfo, TracePass};
pub use merge::{MergeError, merge_header, merge_tables};
pub use mis::{
    Emitter, Heuristic, LightKind, LightVertexMis, MisRecord, MisSettings, MisUnavailable, VcmClass,
    mis_compatibility,
};
pub use plan::{BLOCK_PATHS, Block, Directions, LightPlan, PassPlan, Roulette, Selection, StrategyChoice};
pub use plan::{BlockOrder, MAX_PATHS, TooManyPaths, check_path_budget, planned_table, quota_weight};
pub use plan::{NoEmission, check_emission};
pub use plan::{TraceSettings, block_order, blocks_done, light_record, path_quotas, plan_all, plan_lights};
pub use relight::{LightScale, Lighting, LightingError, lighting};
pub use resume::{EndPassError, ResumeError, TargetChanged, Unfinished, check_finished, check_resume_target};
pub use resume::{end_pass_here, resume_plan, salvage_counts};
pub use sample::{EMISSION_FLAG, Sample};
pub use scene_check::{
    ChangesText, LightMismatch, SceneMismatch, check_scene, differing_objects, scene_lights,
};
pub use subset::{BadFraction, Subset, subset};
pub use table::{Chunk, LightRecord, LightTable};
pub use upgrade::{RetraceBlock, UpgradeError, reproduces, upgrade_plan};
