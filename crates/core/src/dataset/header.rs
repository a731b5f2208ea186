//! The dataset's header model: everything a dataset says about itself besides its samples —
//! the scene fingerprint, a label, the trace passes that made it and the light table — and the
//! bookkeeping of passes (a pass is planned, then the paths it traced are added to N_k).
//! The file format (`opticks_io::dataset_file`) encodes exactly this; `docs/dataset-format.md`
//! gives the bytes.

use super::{Directions, Heuristic, Roulette, Selection};
use super::{LightPlan, LightTable, TraceSettings};
use crate::scene::{Fingerprint, ObjectHash};

/// The MIS records a pass stored with its samples (dataset format 3, `docs/bidirectional.md`
/// §5, §7): the heuristic they are powered for and the sampling signature of the tracer that
/// computed them (`crate::trace::SAMPLING_SIGNATURE`; never 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PassMis {
    /// The heuristic of the records.
    pub heuristic: Heuristic,
    /// The sampling signature of the tracer that wrote them.
    pub signature: u32,
}

/// One run of light sampling that contributed paths to the dataset: a trace, a refinement, an
/// added light, or a dataset merged in. Kept so that refinements pick a fresh random stream and
/// reuse the strategy, merges refuse datasets that share a stream (their paths would be
/// identical, not independent), an interrupted pass can be resumed (its plan says which blocks
/// are missing), and a summary can say how the dataset was made.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TracePass {
    /// Seed of the random streams.
    pub seed: u64,
    /// Stream family within the seed (0 for a first trace, then 1, 2, … for refinements).
    pub stream: u64,
    /// Light paths this pass traced, over all its lights.
    pub paths: u64,
    /// Path depth from which Russian roulette started.
    pub rr_depth: u32,
    /// Wall-clock seconds the pass took.
    pub seconds: f32,
    /// Russian roulette rule.
    pub roulette: Roulette,
    /// Continuation direction sampling.
    pub directions: Directions,
    /// Vertex selection for extension.
    pub selection: Selection,
    /// What the pass set out to trace: (light table index, planned paths) per light, in plan
    /// order. The pass is complete when `paths` reaches their sum; empty = unknown (format
    /// version 1), taken as complete.
    pub planned: Vec<(u32, u64)>,
    /// The MIS records its chunks carry, `None` if they carry none (traced without them, or
    /// by an Opticks older than format 3).
    pub mis: Option<PassMis>,
}

impl TracePass {
    /// A new pass of `settings` planning `plan` (its paths and time are filled in when it ends).
    pub fn new(settings: &TraceSettings, plan: &[LightPlan]) -> Self {
        let TraceSettings { paths: _, seed, stream, rr_depth, roulette, directions, selection, mis } =
            *settings;
        TracePass {
            seed,
            stream,
            paths: 0,
            rr_depth,
            seconds: 0.0,
            roulette,
            directions,
            selection,
            planned: plan.iter().map(|p| (p.table_index, p.paths)).collect(),
            mis: mis.map(|heuristic| PassMis { heuristic, signature: crate::trace::SAMPLING_SIGNATURE }),
        }
    }

    /// Paths the pass planned (= `paths` when the plan is unknown).
    pub fn planned_paths(&self) -> u64 {
        if self.planned.is_empty() {
            self.paths
        } else {
            self.planned.iter().fold(0u64, |a, p| a.saturating_add(p.1))
        }
    }

    /// Whether the pass traced everything it planned (false for an interrupted run).
    pub fn is_complete(&self) -> bool {
        self.paths >= self.planned_paths()
    }

    /// The settings the pass traced with (`paths` = the planned total).
    pub fn settings(&self) -> TraceSettings {
        TraceSettings {
            paths: self.planned_paths(),
            seed: self.seed,
            stream: self.stream,
            rr_depth: self.rr_depth,
            roulette: self.roulette,
            directions: self.directions,
            selection: self.selection,
            mis: self.mis.map(|m| m.heuristic),
        }
    }
}

/// How the dataset was traced: its passes, oldest first.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TraceInfo {
    /// The passes.
    pub passes: Vec<TracePass>,
}

impl TraceInfo {
    /// The first stream number not used yet with `seed`.
    pub fn next_stream(&self, seed: u64) -> u64 {
        self.passes.iter().filter(|p| p.seed == seed).map(|p| p.stream + 1).max().unwrap_or(0)
    }

    /// Total tracing time over all passes, seconds.
    pub fn seconds(&self) -> f64 {
        self.passes.iter().map(|p| p.seconds as f64).sum()
    }
}

/// Everything in the file before the chunks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DatasetHeader {
    /// Content hashes of the scene the dataset was traced in.
    pub fingerprint: Fingerprint,
    /// The hash of each of its meshes and materials ([`crate::scene::ObjectHash`]), so that a
    /// refusal can name what changed; empty in datasets older than format 4.
    pub objects: Vec<ObjectHash>,
    /// Free-form UTF-8 label, e.g. the scene file's path.
    pub label: String,
    /// Trace settings.
    pub trace: TraceInfo,
    /// The light table: Φ_k and N_k. In a finished file N_k equals the sum of the paths of the
    /// light's chunks.
    pub table: LightTable,
}

/// [`DatasetHeader::record_traced`] was asked to book paths to a header without passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("a new pass needs a pass record")]
pub struct NoPassRecord;

impl DatasetHeader {
    /// Books what the header's last pass traced: `traced[i]` paths for `plan[i]` (added to its
    /// light's N_k and to the pass's paths) in `seconds`. Returns whether the pass is now
    /// complete (false for an interrupted run, whose remaining blocks a resumption traces).
    pub fn record_traced(
        &mut self,
        plan: &[LightPlan],
        traced: &[u64],
        seconds: f64,
    ) -> Result<bool, NoPassRecord> {
        for (p, n) in plan.iter().zip(traced) {
            self.table.lights[p.table_index as usize].paths += n;
        }
        let pass = self.trace.passes.last_mut().ok_or(NoPassRecord)?;
        pass.paths += traced.iter().sum::<u64>();
        pass.seconds += seconds as f32;
        Ok(pass.is_complete())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::LightRecord;
    use crate::math::Rgb;

    fn header(lights: usize) -> DatasetHeader {
        let record =
            |k: usize| LightRecord { name: format!("l{k}"), shape: [0; 16], power: Rgb::ONE, paths: 10 };
        DatasetHeader {
            table: LightTable { lights: (0..lights).map(record).collect() },
            ..Default::default()
        }
    }

    #[test]
    fn a_pass_records_its_settings_and_plan_and_gives_them_back() {
        let settings = TraceSettings {
            paths: 100,
            seed: 7,
            stream: 2,
            rr_depth: 3,
            roulette: Roulette::Fixed,
            directions: Directions::Uniform,
            selection: Selection::Priority,
            mis: TraceSettings::default().mis,
        };
        let plan = [
            LightPlan { scene_light: 4, table_index: 1, paths: 60 },
            LightPlan { scene_light: 0, table_index: 0, paths: 41 },
        ];
        let pass = TracePass::new(&settings, &plan);
        assert_eq!(pass.planned, [(1, 60), (0, 41)]);
        assert_eq!((pass.paths, pass.seconds), (0, 0.0));
        assert_eq!(pass.settings(), TraceSettings { paths: 101, ..settings }, "paths = the plan's total");
        assert!(!pass.is_complete());
        let v1 = TracePass { paths: 5, planned: vec![], ..pass };
        assert!(v1.is_complete() && v1.planned_paths() == 5, "an unknown plan is complete");
    }

    #[test]
    fn streams_are_numbered_per_seed() {
        let pass = |seed, stream| TracePass { seed, stream, ..Default::default() };
        let info = TraceInfo { passes: vec![pass(1, 0), pass(2, 0), pass(1, 1)] };
        assert_eq!((info.next_stream(1), info.next_stream(2), info.next_stream(3)), (2, 1, 0));
    }

    #[test]
    fn booking_a_pass_adds_its_paths_to_n_k_and_says_whether_it_is_complete() {
        let mut h = header(2);
        assert_eq!(h.record_traced(&[], &[], 1.0), Err(NoPassRecord));
        let plan = [
            LightPlan { scene_light: 0, table_index: 1, paths: 30 },
            LightPlan { scene_light: 1, table_index: 0, paths: 20 },
        ];
        h.trace.passes.push(TracePass::new(&TraceSettings::default(), &plan));
        assert_eq!(h.record_traced(&plan, &[30, 5], 0.5), Ok(false), "interrupted");
        assert_eq!((h.table.lights[0].paths, h.table.lights[1].paths), (15, 40));
        assert_eq!(h.record_traced(&plan, &[0, 15], 0.25), Ok(true), "resumed");
        let pass = &h.trace.passes[0];
        assert_eq!((pass.paths, pass.seconds, h.table.total_paths()), (50, 0.75, 70));
    }
}
