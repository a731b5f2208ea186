//! The passes a dataset gains: its first trace, a refinement (more paths for every light, from
//! a fresh random stream) and an added light (a light the scene gained, traced alone). Each
//! returns the header to write — its light table with N_k = the paths already in the dataset,
//! its last pass the new one — and the [`PassPlan`] to trace; booking the traced paths is
//! [`DatasetHeader::record_traced`].
//!
//! Refinements and added lights continue a dataset ([`continued_settings`]): a stream no pass
//! of the seed has used (so the new paths are independent of the old), and the strategy of the
//! dataset's last pass unless another is chosen (so they are drawn by the same estimator). A
//! refinement shares its paths out by the lights' current power, as a trace does; an added
//! light gets its fair share by default: the paths it would have had at the dataset's path
//! density, N·w_new/Σw with the weights a trace's quotas use ([`quota_weight`]).
//!
//! The scene must have passed [`super::check_scene`] against the header.

use super::{DatasetHeader, LightMismatch, LightPlan, LightTable, PassPlan, StrategyChoice, TraceInfo};
use super::{TracePass, TraceSettings, light_record, plan_all, plan_lights, quota_weight, scene_lights};
use crate::math::Rgb;
use crate::scene::Scene;

/// A fresh dataset of `scene` labelled `label`: every scene light with N_k = 0 (the header is
/// written before the paths), one pass of `settings` planning `settings.paths` ∝ power.
pub fn new_trace(scene: &Scene, label: &str, settings: TraceSettings) -> (DatasetHeader, PassPlan) {
    let lights = plan_all(scene, settings.paths);
    let header = DatasetHeader {
        fingerprint: scene.fingerprint,
        objects: scene.objects.clone(),
        label: label.to_string(),
        trace: TraceInfo { passes: vec![TracePass::new(&settings, &lights)] },
        table: LightTable { lights: (0..scene.lights.len()).map(|i| light_record(scene, i, 0)).collect() },
    };
    (header, PassPlan { settings, lights, first_block: 0 })
}

/// The settings of a pass of `paths` paths that continues a dataset: `seed` or the dataset's
/// first, a stream no pass of that seed has used, and the strategy of the dataset's last pass
/// unless `strategy` chooses another — so that the new paths are drawn by the same estimator
/// as the old ones. Roulette starts at depth 1 at the earliest.
pub fn continued_settings(
    header: &DatasetHeader,
    paths: u64,
    seed: Option<u64>,
    strategy: &StrategyChoice,
) -> TraceSettings {
    let seed = seed.unwrap_or(header.trace.passes.first().map_or(0, |p| p.seed));
    let last = header.trace.passes.last().map(|p| p.settings()).unwrap_or_default();
    let base = TraceSettings { paths, seed, stream: header.trace.next_stream(seed), ..last };
    let s = strategy.over(base);
    TraceSettings { rr_depth: s.rr_depth.max(1), ..s }
}

/// A refinement: `paths` more paths over all of the dataset's lights (split by their current
/// power in `scene`), as a new pass continuing the dataset. The header records the scene's
/// current geometry hash (it matched, perhaps as a version-1 hash) and object hashes.
pub fn refine(
    header: &DatasetHeader,
    scene: &Scene,
    paths: u64,
    seed: Option<u64>,
    strategy: &StrategyChoice,
) -> Result<(DatasetHeader, PassPlan), LightMismatch> {
    let mut header = header.clone();
    let scene_lights = scene_lights(&header.table, scene)?;
    header.fingerprint.geometry = scene.fingerprint.geometry;
    header.objects = scene.objects.clone();
    let lights = plan_lights(scene, &scene_lights, paths);
    let settings = continued_settings(&header, paths, seed, strategy);
    header.trace.passes.push(TracePass::new(&settings, &lights));
    Ok((header, PassPlan { settings, lights, first_block: 0 }))
}

/// Why a light cannot be added to a dataset.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AddLightError {
    /// The scene has no light of that name.
    #[error("the scene has no light '{name}' (its lights: {})", lights.join(", "))]
    NoSuchLight {
        /// The name asked for.
        name: String,
        /// The scene's light names.
        lights: Vec<String>,
    },
    /// The dataset has paths of the light already (a refinement adds more).
    #[error("light '{0}' is already in the dataset")]
    AlreadyTraced(String),
    /// No path count was given and the dataset's lights have no power to compare with.
    #[error("no path count given, and the dataset's lights have no power to compare with")]
    NoPowerToCompare,
    /// A path count of zero was given.
    #[error("the path count must be at least 1")]
    NoPaths,
}

/// The paths a light of power `power` gets by default when it is added to a dataset: its share
/// at the dataset's path density, ⌈N·w/Σw⌉ with N the dataset's paths and w the
/// [`quota_weight`]s, at least 1. `None` if the dataset's lights carry no power.
pub fn fair_share(table: &LightTable, power: Rgb) -> Option<u64> {
    let traced: f32 = table.lights.iter().map(|l| quota_weight(l.power)).sum();
    (traced > 0.0)
        .then(|| ((table.total_paths() as f64 * (quota_weight(power) / traced) as f64).ceil() as u64).max(1))
}

/// Adds scene light `name` to the dataset: a new light record (N_k = 0 until traced) and a new
/// pass continuing the dataset that traces `paths` paths of it (default: its [`fair_share`]).
/// The other lights' samples stay valid — the geometry is unchanged — so the header records
/// the scene's current fingerprint, lights hash included.
pub fn add_light(
    header: &DatasetHeader,
    scene: &Scene,
    name: &str,
    paths: Option<u64>,
    seed: Option<u64>,
    strategy: &StrategyChoice,
) -> Result<(DatasetHeader, PassPlan), AddLightError> {
    let Some(scene_light) = scene.light_index(name) else {
        let lights = scene.lights.iter().map(|l| l.name().to_string()).collect();
        return Err(AddLightError::NoSuchLight { name: name.to_string(), lights });
    };
    if header.table.lights.iter().any(|l| l.name == name) {
        return Err(AddLightError::AlreadyTraced(name.to_string()));
    }
    let paths = match paths {
        Some(n) => n,
        None => fair_share(&header.table, scene.lights[scene_light].power())
            .ok_or(AddLightError::NoPowerToCompare)?,
    };
    if paths == 0 {
        return Err(AddLightError::NoPaths);
    }
    let mut header = header.clone();
    let table_index = header.table.lights.len() as u32;
    header.table.lights.push(light_record(scene, scene_light, 0));
    header.fingerprint = scene.fingerprint;
    header.objects = scene.objects.clone();
    let settings = continued_settings(&header, paths, seed, strategy);
    let lights = vec![LightPlan { scene_light, table_index, paths }];
    header.trace.passes.push(TracePass::new(&settings, &lights));
    Ok((header, PassPlan { settings, lights, first_block: 0 }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::testing::{Traced, cornell_with_bulb, trace_into};
    use crate::dataset::{BLOCK_PATHS, LightRecord, Roulette, Selection, path_quotas};
    use crate::scene::cornell_box;

    #[test]
    fn a_new_trace_plans_every_light_by_power_with_n_k_still_zero() {
        let scene = Scene::build(&cornell_with_bulb()).unwrap();
        let settings = TraceSettings { paths: 1000, seed: 3, ..Default::default() };
        let (h, pass) = new_trace(&scene, "two.xml", settings);
        assert_eq!((h.label.as_str(), h.fingerprint), ("two.xml", scene.fingerprint));
        let names: Vec<_> = h.table.lights.iter().map(|l| (l.name.as_str(), l.paths)).collect();
        assert_eq!(names, [("light", 0), ("bulb", 0)]);
        let quotas = path_quotas(&scene.light_powers(), 1000);
        let plan: Vec<_> = pass.lights.iter().map(|p| (p.scene_light, p.table_index, p.paths)).collect();
        assert_eq!(plan, [(0, 0, quotas[0]), (1, 1, quotas[1])]);
        assert_eq!((pass.settings, pass.first_block), (settings, 0));
        assert_eq!(h.trace.passes, [TracePass::new(&settings, &pass.lights)]);
    }

    #[test]
    fn a_continuation_takes_a_fresh_stream_and_the_last_passes_strategy() {
        let scene = Scene::build(&cornell_box()).unwrap();
        let strategy =
            TraceSettings { roulette: Roulette::Fixed, rr_depth: 2, seed: 9, ..Default::default() };
        let (mut h, _) = new_trace(&scene, "box", strategy);
        let s = continued_settings(&h, 50, None, &StrategyChoice::default());
        assert_eq!(s, TraceSettings { paths: 50, stream: 1, ..strategy }, "seed 9, stream 1, fixed, depth 2");
        h.trace.passes.push(TracePass::new(&s, &[]));
        assert_eq!(continued_settings(&h, 50, None, &StrategyChoice::default()).stream, 2);
        assert_eq!(continued_settings(&h, 50, Some(4), &StrategyChoice::default()).stream, 0, "a new seed");
        let choice =
            StrategyChoice { selection: Some(Selection::Priority), rr_depth: Some(0), ..Default::default() };
        let s = continued_settings(&h, 50, None, &choice);
        assert_eq!((s.selection, s.roulette, s.rr_depth), (Selection::Priority, Roulette::Fixed, 1));
        let empty = DatasetHeader::default();
        let s = continued_settings(&empty, 50, None, &StrategyChoice::default());
        assert_eq!(s, TraceSettings { paths: 50, ..Default::default() });
    }

    /// A refinement is a trace of its paths from stream 1, appended: the result has the N_k of
    /// both and estimates like one trace of all the paths.
    #[test]
    fn a_refined_dataset_estimates_like_one_trace_of_all_the_paths() {
        let scene = Scene::build(&cornell_with_bulb()).unwrap();
        let mut data = trace_into(&scene, 20_000, 4);
        let before = data.header.clone();
        let (header, pass) = refine(&data.header, &scene, 20_000, None, &StrategyChoice::default()).unwrap();
        assert_eq!(pass.settings, TraceSettings { paths: 20_000, seed: 4, stream: 1, ..Default::default() });
        let quotas: Vec<u64> = pass.lights.iter().map(|p| p.paths).collect();
        assert_eq!(quotas, path_quotas(&scene.light_powers(), 20_000));
        assert_eq!(header.trace.passes[..1], before.trace.passes[..]);
        assert_eq!(header.table, before.table, "N_k grows only as paths are traced");
        data.header = header;
        data.run(&scene, &pass);
        assert_eq!(data.header.table.total_paths(), 40_000);
        assert!(data.header.trace.passes.iter().all(TracePass::is_complete));
        data.assert_estimates_like(&trace_into(&scene, 40_000, 5), "refined 20k + 20k");
        // A light that moved since the trace cannot be refined.
        let mut moved = cornell_with_bulb();
        moved.point_lights[0].position.x = -0.3;
        let moved = Scene::build(&moved).unwrap();
        let e = refine(&before, &moved, 10, None, &StrategyChoice::default()).unwrap_err();
        assert_eq!(e, LightMismatch::Moved("bulb".into()));
    }

    #[test]
    fn an_added_light_gets_its_fair_share_by_the_weights_of_the_quotas() {
        let record = |power: Rgb, paths| LightRecord { name: "a".into(), shape: [0; 16], power, paths };
        let table = LightTable { lights: vec![record(Rgb::splat(1.0), 600), record(Rgb::splat(3.0), 400)] };
        assert_eq!(fair_share(&table, Rgb::new(0.5, 0.5, 1.0)), Some(167), "⌈1000 · 2/12⌉");
        assert_eq!(fair_share(&table, Rgb::new(0.0, 0.0, 0.1)), Some(9), "⌈8.33…⌉");
        assert_eq!(fair_share(&table, Rgb::ZERO), Some(1), "at least one path");
        let dark = LightTable { lights: vec![record(Rgb::ZERO, 600)] };
        assert_eq!(fair_share(&dark, Rgb::ONE), None);
    }

    /// Adding the bulb to a dataset of the box gives what tracing both lights gives: the box's
    /// chunks untouched, the bulb's from a stream of its own, and the same flux estimate.
    #[test]
    fn adding_a_light_equals_tracing_both_lights() {
        let (one, two) = (Scene::build(&cornell_box()).unwrap(), Scene::build(&cornell_with_bulb()).unwrap());
        let mut data = trace_into(&one, 30_000, 5);
        let (box_chunks, box_pass) = (data.chunks.clone(), data.header.trace.passes[0].clone());
        let none = StrategyChoice::default();
        let (header, pass) = add_light(&data.header, &two, "bulb", Some(12_000), None, &none).unwrap();
        assert_eq!(header.fingerprint, two.fingerprint, "the lights hash now has the bulb");
        assert_eq!(header.table.lights[1], light_record(&two, 1, 0));
        assert_eq!(pass.lights, [LightPlan { scene_light: 1, table_index: 1, paths: 12_000 }]);
        assert_eq!((pass.settings.seed, pass.settings.stream), (5, 1));
        assert_eq!(header.trace.passes, [box_pass, TracePass::new(&pass.settings, &pass.lights)]);
        data.header = header;
        data.run(&two, &pass);
        assert_eq!(data.chunks[..box_chunks.len()], box_chunks[..]);
        assert!(data.chunks[box_chunks.len()..].iter().all(|c| c.light == 1));
        assert_eq!(data.chunks.len() - box_chunks.len(), 12_000usize.div_ceil(BLOCK_PATHS as usize));
        let both = trace_into(&two, 42_000, 6);
        data.assert_estimates_like(&both, "traced box + added bulb");

        // Its fair share by default; refused: a light the scene lacks, one already there, 0 paths.
        let (_, by_default) =
            add_light(&trace_into(&one, 30_000, 5).header, &two, "bulb", None, None, &none).unwrap();
        let share = fair_share(&trace_into(&one, 30_000, 5).header.table, two.lights[1].power()).unwrap();
        assert_eq!(by_default.lights[0].paths, share);
        assert_eq!(
            add_light(&data.header, &two, "sun", None, None, &none),
            Err(AddLightError::NoSuchLight {
                name: "sun".into(),
                lights: vec!["light".into(), "bulb".into()]
            })
        );
        assert_eq!(
            add_light(&data.header, &two, "bulb", None, None, &none),
            Err(AddLightError::AlreadyTraced("bulb".into()))
        );
        let empty = Traced { header: new_trace(&one, "box", Default::default()).0, chunks: vec![] };
        let mut dark = empty.header.clone();
        dark.table.lights[0].power = Rgb::ZERO;
        assert_eq!(add_light(&dark, &two, "bulb", None, None, &none), Err(AddLightError::NoPowerToCompare));
        assert_eq!(add_light(&dark, &two, "bulb", Some(0), None, &none), Err(AddLightError::NoPaths));
    }
}
