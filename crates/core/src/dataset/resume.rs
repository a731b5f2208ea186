//! Resuming an interrupted pass. A run stopped early saves the complete blocks it traced, and
//! its last pass records what it planned (paths per light, seed, stream, strategy). Blocks are
//! traced in a fixed order ([`super::block_order`]), each from its own random stream, so the
//! blocks saved are a known prefix and tracing only the rest gives exactly the samples of an
//! uninterrupted run.
//!
//! Or the pass ends where it stopped ([`end_pass_here`]): a time-limited run is complete by
//! definition, and an interrupted one may be accepted as it is. Its plan becomes what it
//! traced; since every block's random stream is named by its light and number alone, the
//! dataset is then exactly what a run planning those paths would have traced.

use super::{
    DatasetHeader, LightMismatch, LightPlan, PassPlan, TracePass, block_order, blocks_done, scene_lights,
};
use crate::scene::Scene;

/// Why a dataset's last pass cannot be resumed.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ResumeError {
    /// The last pass traced all it planned (or there is no pass).
    #[error("nothing to resume, its last trace pass is complete")]
    Complete,
    /// A light of the dataset is not in the scene as it was traced.
    #[error(transparent)]
    Light(#[from] LightMismatch),
    /// The paths traced are not a whole number of the plan's first blocks.
    #[error(
        "its last pass traced {paths} paths, which is no whole number of its blocks: not a dataset saved by \
         an interrupted run"
    )]
    NotBlockAligned {
        /// Paths the pass traced.
        paths: u64,
    },
}

/// The rest of the dataset's interrupted last pass: its settings and plan (light table indices
/// mapped to `scene`'s lights by name), and the blocks already traced. The scene must have
/// passed [`super::check_scene`]. Tracing it and booking the paths
/// ([`DatasetHeader::record_traced`]) completes the pass.
pub fn resume_plan(header: &DatasetHeader, scene: &Scene) -> Result<PassPlan, ResumeError> {
    let Some(pass) = header.trace.passes.last().filter(|p| !p.is_complete()) else {
        return Err(ResumeError::Complete);
    };
    let scene_lights = scene_lights(&header.table, scene)?;
    let (lights, done) = traced_plan(pass, |t| scene_lights[t as usize]);
    let first_block = done.ok_or(ResumeError::NotBlockAligned { paths: pass.paths })?;
    Ok(PassPlan { settings: pass.settings(), lights, first_block })
}

/// The plan of `pass` with its light table indices mapped to scene lights by `scene_light`
/// (from [`scene_lights`]), and how many of its blocks (in [`super::block_order`]) it traced
/// (`None` if its paths are no whole number of them).
pub(super) fn traced_plan(
    pass: &TracePass,
    scene_light: impl Fn(u32) -> usize,
) -> (Vec<LightPlan>, Option<usize>) {
    let lights: Vec<LightPlan> = pass
        .planned
        .iter()
        .map(|&(table_index, paths)| LightPlan { scene_light: scene_light(table_index), table_index, paths })
        .collect();
    let done = blocks_done(&lights, pass.paths);
    (lights, done)
}

/// Why an unfinished pass cannot end where it stopped.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum EndPassError {
    /// The last pass traced all it planned (or there is no pass).
    #[error("nothing to end, its last trace pass is complete")]
    Complete,
    /// The paths traced are not a whole number of the plan's first blocks.
    #[error("its last pass traced {paths} paths, which is no whole number of its blocks")]
    NotBlockAligned {
        /// Paths the pass traced.
        paths: u64,
    },
    /// A light the pass was to trace has no paths in the dataset yet: ended here, the dataset
    /// would not see that light at all.
    #[error("light '{name}' has no paths yet, so the dataset would not see it: trace longer")]
    Unlit {
        /// The light.
        name: String,
    },
}

/// Ends the dataset's unfinished last pass where it stopped: its plan becomes, per light, the
/// paths of the blocks it traced (a prefix of its [`super::block_order`]), so the pass is
/// complete, the dataset can be refined, merged or given a light, and it holds exactly the
/// chunks a pass planning those paths traces (in another order across lights; each light's
/// own blocks in the same order). N_k and the samples are unchanged. Refused if a light the
/// pass was to trace would be left without any path.
pub fn end_pass_here(header: &mut DatasetHeader) -> Result<(), EndPassError> {
    let Some(pass) = header.trace.passes.last().filter(|p| !p.is_complete()) else {
        return Err(EndPassError::Complete);
    };
    // No scene here: the block order depends on the table indices and counts alone.
    let (plan, blocks) = traced_plan(pass, |_| 0);
    let blocks = blocks.ok_or(EndPassError::NotBlockAligned { paths: pass.paths })?;
    let mut traced: Vec<(u32, u64)> = pass.planned.iter().map(|&(t, _)| (t, 0)).collect();
    for b in block_order(&plan).take(blocks) {
        if let Some(entry) = traced.iter_mut().find(|e| e.0 == b.light.table_index) {
            entry.1 += b.paths;
        }
    }
    for &(t, planned) in &pass.planned {
        if let Some(light) = header.table.lights.get(t as usize).filter(|l| planned > 0 && l.paths == 0) {
            return Err(EndPassError::Unlit { name: light.name.clone() });
        }
    }
    if let Some(pass) = header.trace.passes.last_mut() {
        pass.planned = traced;
    }
    Ok(())
}

/// A dataset whose last pass was interrupted: only resuming it keeps it resumable. A pass
/// appended after it (a refinement, an added light, a merge) would leave the interrupted pass
/// in the middle, where no resumption can reach it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("its last trace pass was interrupted ({done} of {planned} planned paths) and must be finished first")]
pub struct Unfinished {
    /// Paths the pass traced.
    pub done: u64,
    /// Paths it planned.
    pub planned: u64,
}

/// Whether a pass may be added to the dataset of `header` (see [`Unfinished`]).
pub fn check_finished(header: &DatasetHeader) -> Result<(), Unfinished> {
    match header.trace.passes.last() {
        Some(p) if !p.is_complete() => Err(Unfinished { done: p.paths, planned: p.planned_paths() }),
        _ => Ok(()),
    }
}

/// The dataset a resumption would replace is no longer the one the interrupted run started
/// from: replacing it would discard what was done to it since (e.g. a later refinement).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "it has changed since the interrupted run started from it ({target_passes} trace passes; the run \
     started from {started_from}), so finishing the run there would discard that work"
)]
pub struct TargetChanged {
    /// Passes of the existing target.
    pub target_passes: usize,
    /// Passes of the dataset the interrupted run extended.
    pub started_from: usize,
}

/// Whether finishing the interrupted run of `partial` may replace the existing dataset
/// `target`: only if `target` is what the run started from — the partial's passes but its
/// last, with the same geometry (an interrupted refinement or added light, whose target is
/// still as it was).
pub fn check_resume_target(partial: &DatasetHeader, target: &DatasetHeader) -> Result<(), TargetChanged> {
    let before = &partial.trace.passes[..partial.trace.passes.len().saturating_sub(1)];
    let same = target.fingerprint.geometry == partial.fingerprint.geometry
        && !before.is_empty()
        && target.trace.passes == before;
    if same {
        Ok(())
    } else {
        Err(TargetChanged { target_passes: target.trace.passes.len(), started_from: before.len() })
    }
}

/// Books the chunks found in the file of a run that was killed before it finished (no end
/// record: a SIGKILL, a power cut, a panic under `panic = "abort"`): `header` is the one the run
/// wrote first (its table's N_k and its last pass's paths as they were before the run), `kept`
/// the paths per light of the whole chunks found in the file, in order. The chunks beyond
/// `header`'s counts must be the first blocks, in [`super::block_order`], of the last pass's
/// remaining plan — as a run writes them — for the file to be a valid interrupted run; then N_k
/// and the pass's paths are booked and the new paths returned, so [`resume_plan`] finishes it.
/// `None` when they are not (a copy that did not finish, a foreign file): nothing to save.
pub fn salvage_counts(header: &mut DatasetHeader, kept: &[u64]) -> Option<u64> {
    let lights = &header.table.lights;
    if kept.len() != lights.len() {
        return None;
    }
    let extra: Vec<u64> =
        kept.iter().zip(lights).map(|(k, l)| k.checked_sub(l.paths)).collect::<Option<_>>()?;
    let total: u64 = extra.iter().sum();
    let pass = header.trace.passes.last_mut()?;
    let (plan, done) = traced_plan(pass, |_| 0);
    let mut found = vec![0u64; extra.len()];
    let mut sum = 0u64;
    for b in block_order(&plan).skip(done?) {
        if sum >= total {
            break;
        }
        found[b.light.table_index as usize] += b.paths;
        sum += b.paths;
    }
    if found != extra {
        return None;
    }
    pass.paths += total;
    for (l, k) in header.table.lights.iter_mut().zip(kept) {
        l.paths = *k;
    }
    Some(total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::testing::{Traced, cornell_with_bulb};
    use crate::dataset::{Roulette, StrategyChoice, TraceSettings, new_trace, refine};
    use crate::scene::cornell_box;

    /// `data` as a run stopped after its first `blocks` chunks of the last pass would have
    /// saved it: the chunks before, and the pass's paths and N_k booked for those blocks only.
    fn cut(before: &Traced, pass: &PassPlan, done: &Traced, blocks: usize) -> Traced {
        let mut cut = before.clone();
        let new = &done.chunks[before.chunks.len()..before.chunks.len() + blocks];
        let traced: Vec<u64> = pass
            .lights
            .iter()
            .map(|p| new.iter().filter(|c| c.light == p.table_index).map(|c| c.paths).sum())
            .collect();
        assert_eq!(cut.header.record_traced(&pass.lights, &traced, 0.1), Ok(false));
        cut.chunks.extend_from_slice(new);
        cut
    }

    /// Without wall-clock times: what must be identical between two runs.
    fn contents(t: &Traced) -> Traced {
        let mut t = t.clone();
        t.header.trace.passes.iter_mut().for_each(|p| p.seconds = 0.0);
        t
    }

    #[test]
    fn an_interrupted_trace_or_refinement_resumes_to_exactly_the_uninterrupted_dataset() {
        let scene = Scene::build(&cornell_with_bulb()).unwrap();
        // A non-default strategy, which the resumed part must keep using.
        let settings = TraceSettings {
            paths: 30_000,
            seed: 3,
            rr_depth: 2,
            roulette: Roulette::Fixed,
            ..Default::default()
        };
        let (header, pass) = new_trace(&scene, "two", settings);
        let empty = Traced { header, chunks: vec![] };
        let mut whole = empty.clone();
        whole.run(&scene, &pass);
        for blocks in [0, 1, 4, 7] {
            let mut cut = cut(&empty, &pass, &whole, blocks);
            let rest = resume_plan(&cut.header, &scene).unwrap();
            assert_eq!(rest, PassPlan { first_block: blocks, ..pass.clone() });
            cut.run(&scene, &rest);
            assert_eq!(contents(&cut), contents(&whole), "trace resumed after {blocks} blocks");
        }
        assert_eq!(resume_plan(&whole.header, &scene), Err(ResumeError::Complete));

        let (header, pass) = refine(&whole.header, &scene, 20_000, None, &StrategyChoice::default()).unwrap();
        assert_eq!(pass.settings, TraceSettings { paths: 20_000, stream: 1, ..settings });
        let before = Traced { header, chunks: whole.chunks.clone() };
        let mut refined = before.clone();
        refined.run(&scene, &pass);
        let mut cut = cut(&before, &pass, &refined, 3);
        let rest = resume_plan(&cut.header, &scene).unwrap();
        assert_eq!((rest.first_block, rest.settings), (3, pass.settings));
        cut.run(&scene, &rest);
        assert_eq!(contents(&cut), contents(&refined), "refinement resumed");
    }

    /// A killed run's file: whatever prefix of its blocks reached the disk is booked as the
    /// interrupted run that `cut` saves (so it resumes to the uninterrupted dataset); a file
    /// whose chunks are not such a prefix (a copy cut short, a block skipped) is refused.
    #[test]
    fn the_chunks_of_a_killed_run_are_booked_as_its_interrupted_pass() {
        let scene = Scene::build(&cornell_with_bulb()).unwrap();
        let settings = TraceSettings { paths: 30_000, seed: 5, ..Default::default() };
        let (header, pass) = new_trace(&scene, "two", settings);
        let empty = Traced { header, chunks: vec![] };
        let mut whole = empty.clone();
        whole.run(&scene, &pass);
        let kept = |chunks: &[crate::dataset::Chunk]| -> Vec<u64> {
            (0..2u32).map(|k| chunks.iter().filter(|c| c.light == k).map(|c| c.paths).sum()).collect()
        };
        for blocks in [0, 1, 3, 7] {
            let mut salvaged = empty.header.clone();
            let paths = salvage_counts(&mut salvaged, &kept(&whole.chunks[..blocks]));
            let expected = cut(&empty, &pass, &whole, blocks);
            assert_eq!(paths, Some(expected.header.trace.passes[0].paths), "{blocks} blocks");
            assert_eq!(
                contents(&Traced { header: salvaged, chunks: vec![] }).header,
                contents(&expected).header
            );
        }
        // Not a prefix of the blocks: a path more than three blocks hold, or a fourth block of
        // the light whose turn it is not.
        let mut odd = kept(&whole.chunks[..3]);
        odd[0] += 1;
        assert_eq!(salvage_counts(&mut empty.header.clone(), &odd), None);
        let next = whole.chunks[3].light as usize;
        let mut skipped = kept(&whole.chunks[..3]);
        skipped[1 - next] += whole.chunks[3].paths;
        assert_eq!(salvage_counts(&mut empty.header.clone(), &skipped), None);
        assert_eq!(salvage_counts(&mut empty.header.clone(), &[0]), None, "the table's length");

        // A refinement killed while it copied the earlier chunks: fewer than the header's N_k.
        let (header, pass) = refine(&whole.header, &scene, 20_000, None, &StrategyChoice::default()).unwrap();
        let copied = kept(&whole.chunks[..5]);
        assert_eq!(salvage_counts(&mut header.clone(), &copied), None);
        // …and killed after its copy and two new blocks.
        let before = Traced { header: header.clone(), chunks: whole.chunks.clone() };
        let mut refined = before.clone();
        refined.run(&scene, &pass);
        let n = whole.chunks.len() + 2;
        let mut salvaged = header.clone();
        assert!(salvage_counts(&mut salvaged, &kept(&refined.chunks[..n])).is_some());
        assert_eq!(
            contents(&Traced { header: salvaged, chunks: vec![] }).header,
            contents(&cut(&before, &pass, &refined, 2)).header
        );
    }

    /// The chunks of each light, in order: what two passes tracing the same blocks share.
    fn per_light(t: &Traced, lights: u32) -> Vec<Vec<&crate::dataset::Chunk>> {
        (0..lights).map(|k| t.chunks.iter().filter(|c| c.light == k).collect()).collect()
    }

    #[test]
    fn a_pass_ended_where_it_stopped_is_complete_and_is_the_trace_of_what_it_traced() {
        let scene = Scene::build(&cornell_with_bulb()).unwrap();
        let settings = TraceSettings { paths: 60_000, seed: 5, ..Default::default() };
        let (header, pass) = new_trace(&scene, "two", settings);
        let empty = Traced { header, chunks: vec![] };
        let mut whole = empty.clone();
        whole.run(&scene, &pass);
        assert!(pass.lights.iter().all(|l| l.paths > 0) && pass.lights.len() == 2);

        let nothing = cut(&empty, &pass, &whole, 0);
        let mut unlit = nothing.header.clone();
        assert!(matches!(end_pass_here(&mut unlit), Err(EndPassError::Unlit { .. })), "no path at all");
        let mut ended = cut(&empty, &pass, &whole, 5);
        let table = ended.header.table.clone();
        end_pass_here(&mut ended.header).unwrap();
        let p = ended.header.trace.passes.last().unwrap();
        assert!(p.is_complete() && check_finished(&ended.header).is_ok());
        assert_eq!(ended.header.table, table, "N_k unchanged");
        for &(t, planned) in &p.planned {
            assert_eq!(planned, table.lights[t as usize].paths, "light {t}: the plan is what it traced");
        }
        assert_eq!(end_pass_here(&mut ended.header), Err(EndPassError::Complete));

        // A pass planning those paths traces the same blocks.
        let lights: Vec<LightPlan> = pass
            .lights
            .iter()
            .map(|l| LightPlan { paths: table.lights[l.table_index as usize].paths, ..*l })
            .collect();
        let mut short = empty.clone();
        short.run(&scene, &PassPlan { lights, ..pass.clone() });
        assert_eq!(per_light(&short, 2), per_light(&ended, 2));
        // And the dataset can be refined.
        refine(&ended.header, &scene, 10_000, None, &StrategyChoice::default()).unwrap();
    }

    #[test]
    fn only_a_prefix_of_blocks_of_an_unfinished_pass_against_its_lights_resumes() {
        let scene = Scene::build(&cornell_with_bulb()).unwrap();
        let (mut header, pass) =
            new_trace(&scene, "two", TraceSettings { paths: 10_000, ..Default::default() });
        header.trace.passes[0].paths = 4097;
        assert_eq!(resume_plan(&header, &scene), Err(ResumeError::NotBlockAligned { paths: 4097 }));
        header.trace.passes[0].paths = 0;
        assert_eq!(resume_plan(&header, &scene).map(|p| p.lights), Ok(pass.lights));
        let gone = Scene::build(&cornell_box()).unwrap();
        assert_eq!(resume_plan(&header, &gone), Err(ResumeError::Light(LightMismatch::Gone("bulb".into()))));
        header.trace.passes.clear();
        assert_eq!(resume_plan(&header, &scene), Err(ResumeError::Complete));
    }

    #[test]
    fn a_resumption_replaces_only_the_dataset_its_run_started_from() {
        let scene = Scene::build(&cornell_with_bulb()).unwrap();
        let (header, pass) = new_trace(&scene, "two", TraceSettings { paths: 10_000, ..Default::default() });
        let mut done = Traced { header, chunks: vec![] };
        done.run(&scene, &pass);
        assert_eq!(check_finished(&done.header), Ok(()));
        let (mut partial, _) = refine(&done.header, &scene, 9000, None, &StrategyChoice::default()).unwrap();
        assert_eq!(check_finished(&partial), Err(Unfinished { done: 0, planned: 9000 }));
        assert_eq!(check_resume_target(&partial, &done.header), Ok(()), "an interrupted refinement");
        let (later, _) = refine(&done.header, &scene, 5000, None, &StrategyChoice::default()).unwrap();
        assert_eq!(
            check_resume_target(&partial, &later),
            Err(TargetChanged { target_passes: 2, started_from: 1 }),
            "refined since"
        );
        partial.trace.passes.remove(0); // an interrupted first trace: any existing target is another's
        assert!(check_resume_target(&partial, &done.header).is_err());
    }
}
