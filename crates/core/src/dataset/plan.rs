//! The trace plan: what a pass of light sampling sets out to do, before any path is traced.
//! [`TraceSettings`] (seed, stream, the §6.2 strategy), the split of a pass's paths over the
//! lights ([`path_quotas`], [`LightPlan`]) and the order its blocks are traced in
//! ([`block_order`]). The tracer (`crate::trace`) carries a plan out; the dataset records it in
//! each pass ([`super::TracePass`]), which is what lets a refinement continue a dataset with the
//! same estimator and an interrupted pass be resumed block for block.
//!
//! Determinism: each light's quota N_k is cut into blocks of [`BLOCK_PATHS`] paths; block b of
//! light k draws from its own random stream named by (seed, stream, k, b). Blocks of different
//! lights are interleaved in proportion to their quotas, so a trace stopped early is still
//! balanced, and the order is fixed by the plan alone, so a stopped run's blocks are a known
//! prefix ([`blocks_done`]).

use super::{Heuristic, LightRecord, LightTable};
use crate::math::Rgb;
use crate::scene::Scene;

/// Paths per block (one block = one chunk = one random stream).
pub const BLOCK_PATHS: u64 = 4096;

/// How a light path continues at a vertex: the thesis's improvements (§6.2), each an option
/// whose effect is measured (`docs/convergence.md`) and none of which biases the estimator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Roulette {
    /// Survival driven by the path's energy (§6.2.1): q = min(0.95, 2·max β).
    #[default]
    Energy,
    /// Survival with a fixed probability q = 0.95, whatever the path carries.
    Fixed,
}

/// How continuation directions are drawn (§6.2.2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Directions {
    /// Importance sampling of the BSDF (Lafortune & Willems for Modified Phong).
    #[default]
    Importance,
    /// Uniform over the hemisphere (the baseline the thesis improves on).
    Uniform,
}

/// Which vertices are extended how often (§6.2.3, priority sample selection, in unbiased form).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Selection {
    /// Every vertex is extended once (then roulette).
    #[default]
    Single,
    /// A vertex carrying energy β is extended c = max β / [`crate::trace::PRIORITY_TARGET`]
    /// times on average (at most [`crate::trace::MAX_SPLIT`]): ⌊c⌋ or ⌈c⌉ children, each with
    /// weight divided by c, so high-energy samples get more descendants and the expectation is
    /// unchanged. Below c = 1, roulette.
    Priority,
}

/// What to trace.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceSettings {
    /// Total light paths over all lights (split ∝ power).
    pub paths: u64,
    /// Seed of all random streams.
    pub seed: u64,
    /// Which independent stream family to use (0 for a first trace; refinement passes use others).
    pub stream: u64,
    /// Path depth from which Russian roulette may end a path.
    pub rr_depth: u32,
    /// Russian roulette rule.
    pub roulette: Roulette,
    /// Continuation direction sampling.
    pub directions: Directions,
    /// Vertex selection for extension.
    pub selection: Selection,
    /// The MIS heuristic the bidirectional estimator's per-sample records are computed for
    /// (`docs/bidirectional.md` §5; the tracer stores one [`MisRecord`](super::MisRecord)
    /// per sample), or `None` for no records (the light estimator needs none). Records never
    /// change the samples: the random numbers drawn are the same either way.
    pub mis: Option<Heuristic>,
}

impl Default for TraceSettings {
    fn default() -> Self {
        TraceSettings {
            paths: 1 << 20,
            seed: 0,
            stream: 0,
            rr_depth: 5,
            roulette: Roulette::default(),
            directions: Directions::default(),
            selection: Selection::default(),
            mis: Some(Heuristic::Power),
        }
    }
}

/// Strategy options chosen for a pass; each `None` keeps the strategy of the settings it is
/// applied to ([`StrategyChoice::over`]): the defaults for a new trace, the dataset's last pass
/// for a continuation ([`super::continued_settings`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StrategyChoice {
    /// Path depth from which Russian roulette may end paths.
    pub rr_depth: Option<u32>,
    /// Russian roulette rule.
    pub roulette: Option<Roulette>,
    /// Continuation direction sampling.
    pub directions: Option<Directions>,
    /// Vertex selection for extension.
    pub selection: Option<Selection>,
    /// MIS records: `Some(None)` for none, `Some(Some(h))` for records of heuristic h.
    pub mis: Option<Option<Heuristic>>,
}

impl StrategyChoice {
    /// `base` with the chosen options replacing its strategy.
    pub fn over(&self, base: TraceSettings) -> TraceSettings {
        TraceSettings {
            rr_depth: self.rr_depth.unwrap_or(base.rr_depth),
            roulette: self.roulette.unwrap_or(base.roulette),
            directions: self.directions.unwrap_or(base.directions),
            selection: self.selection.unwrap_or(base.selection),
            mis: self.mis.unwrap_or(base.mis),
            ..base
        }
    }
}

/// A light's weight when paths are shared out by power: the sum of its power's channels.
#[inline]
pub fn quota_weight(power: Rgb) -> f32 {
    power.x + power.y + power.z
}

/// Splits `total` paths over lights in proportion to their power ([`quota_weight`]), by largest
/// remainder; every light with non-zero power gets at least one path.
pub fn path_quotas(powers: &[Rgb], total: u64) -> Vec<u64> {
    let weights: Vec<f64> = powers.iter().map(|&p| quota_weight(p).max(0.0) as f64).collect();
    let sum: f64 = weights.iter().sum();
    if sum <= 0.0 || total == 0 {
        return vec![0; powers.len()];
    }
    let ideal: Vec<f64> = weights.iter().map(|w| w / sum * total as f64).collect();
    let mut quotas: Vec<u64> = ideal.iter().map(|x| x.floor() as u64).collect();
    // Rounding in f64 may make the floors sum to a little more than `total` (only for totals
    // beyond 2^53, which [`check_path_budget`] refuses): take the excess from the largest quotas,
    // so the sum never exceeds the total and nothing wraps.
    let mut sum: u128 = quotas.iter().map(|&q| q as u128).sum();
    while sum > total as u128 {
        let largest = (0..quotas.len()).max_by_key(|&i| quotas[i]).unwrap_or(0);
        let cut = (sum - total as u128).min(quotas[largest] as u128);
        quotas[largest] -= cut as u64;
        sum -= cut;
    }
    let mut left = total - sum as u64;
    let mut order: Vec<usize> = (0..powers.len()).collect();
    order.sort_by(|&a, &b| (ideal[b] - ideal[b].floor()).total_cmp(&(ideal[a] - ideal[a].floor())));
    for &i in order.iter().cycle().take(powers.len() * 2) {
        if left == 0 {
            break;
        }
        if weights[i] > 0.0 {
            quotas[i] += 1;
            left -= 1;
        }
    }
    if left > 0 {
        // Only for totals beyond 2^53, where f64 floors can be short by more than one per light.
        let heaviest = (0..weights.len()).max_by(|&a, &b| weights[a].total_cmp(&weights[b])).unwrap_or(0);
        quotas[heaviest] += left;
    }
    for (q, w) in quotas.iter_mut().zip(&weights) {
        if *w > 0.0 && *q == 0 && total >= powers.len() as u64 {
            *q = 1;
        }
    }
    quotas
}

/// One light's share of a trace: which scene light, under which index of the dataset's light
/// table its chunks are filed (and its random streams named), and how many paths.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightPlan {
    /// Index into `Scene::lights`.
    pub scene_light: usize,
    /// Index into the dataset's light table (`Chunk::light`).
    pub table_index: u32,
    /// Paths to trace.
    pub paths: u64,
}

/// A pass to trace: its settings, its lights' plan, and how many of the plan's blocks (in
/// [`block_order`]) the dataset holds already — zero, except when an interrupted pass is resumed.
#[derive(Clone, Debug, PartialEq)]
pub struct PassPlan {
    /// Seed, stream and strategy.
    pub settings: TraceSettings,
    /// Which lights, filed under which table index, how many paths.
    pub lights: Vec<LightPlan>,
    /// Blocks of the plan already traced.
    pub first_block: usize,
}

impl PassPlan {
    /// "light 'ceiling' 4000000 paths, …": what the pass traces, named from `table`.
    pub fn describe(&self, table: &LightTable) -> String {
        let name = |i: u32| table.lights.get(i as usize).map_or("?", |l| l.name.as_str());
        let parts: Vec<String> = self
            .lights
            .iter()
            .map(|p| format!("light '{}' {} paths", name(p.table_index), p.paths))
            .collect();
        parts.join(", ")
    }
}

/// The plan that shares `paths` out over `scene_lights` (scene indices) by their current power
/// ([`path_quotas`]), filing light i of the list under table index i.
pub fn plan_lights(scene: &Scene, scene_lights: &[usize], paths: u64) -> Vec<LightPlan> {
    let powers: Vec<Rgb> = scene_lights.iter().map(|&i| scene.lights[i].power()).collect();
    path_quotas(&powers, paths)
        .into_iter()
        .zip(scene_lights)
        .enumerate()
        .map(|(k, (paths, &scene_light))| LightPlan { scene_light, table_index: k as u32, paths })
        .collect()
}

/// A plan that traces nothing: no light of it emits (each has zero power, so none gets a path).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("no light emits: every light has zero power, so there is nothing to trace")]
pub struct NoEmission;

/// Refuses a plan of no paths ([`NoEmission`]): tracing it would write an empty dataset.
pub fn check_emission(plan: &[LightPlan]) -> Result<(), NoEmission> {
    if plan.iter().any(|p| p.paths > 0) { Ok(()) } else { Err(NoEmission) }
}

/// The plan for a fresh trace: every scene light, table index = scene index, quotas ∝ power.
pub fn plan_all(scene: &Scene, paths: u64) -> Vec<LightPlan> {
    plan_lights(scene, &(0..scene.lights.len()).collect::<Vec<_>>(), paths)
}

/// Scene light `i`'s row for a dataset's light table: its name, shape and current power, with
/// `paths` paths.
pub fn light_record(scene: &Scene, i: usize, paths: u64) -> LightRecord {
    let l = &scene.lights[i];
    LightRecord { name: l.name().to_string(), shape: scene.light_shapes[i], power: l.power(), paths }
}

/// The light table of a fresh trace of `paths` paths: each light's name, shape, power Φ_k and
/// quota N_k. Known before tracing, so a dataset header can be written first.
pub fn planned_table(scene: &Scene, paths: u64) -> LightTable {
    LightTable {
        lights: plan_all(scene, paths).iter().map(|p| light_record(scene, p.scene_light, p.paths)).collect(),
    }
}

/// One block of a plan: `paths` (≤ [`BLOCK_PATHS`]) paths of `light`, the `index`-th block of
/// that light (which, with the seed, the stream and the table index, names its random stream).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Block {
    /// The plan entry the block belongs to.
    pub light: LightPlan,
    /// Block number within the light.
    pub index: u64,
    /// Paths in the block.
    pub paths: u64,
}

/// The most light paths a dataset may hold, over all its lights and passes: 2⁵³ (about
/// 9·10¹⁵; at 3 M paths/s, 95 years of tracing). Below it every path count is exact in the f64
/// arithmetic of the quotas ([`path_quotas`]) and no sum of N_k can wrap; every plan is checked
/// against it before anything is traced ([`check_path_budget`]).
pub const MAX_PATHS: u64 = 1 << 53;

/// A pass would take a dataset beyond [`MAX_PATHS`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{adding} more paths on top of the {existing} the dataset holds exceed the maximum of {} paths per \
     dataset (2^53)",
    MAX_PATHS
)]
pub struct TooManyPaths {
    /// Paths the dataset holds already.
    pub existing: u64,
    /// Paths the pass plans (saturated at `u64::MAX`).
    pub adding: u64,
}

/// Checks that tracing `pass` into a dataset whose light table is `table` keeps it within
/// [`MAX_PATHS`]. The pass's first blocks already traced (when resuming) are among `table`'s
/// paths, so only the rest counts.
pub fn check_path_budget(table: &LightTable, pass: &PassPlan) -> Result<(), TooManyPaths> {
    let existing = table.lights.iter().fold(0u64, |a, l| a.saturating_add(l.paths));
    let planned = pass.lights.iter().fold(0u64, |a, p| a.saturating_add(p.paths));
    let done = block_order(&pass.lights).take(pass.first_block).fold(0u64, |a, b| a.saturating_add(b.paths));
    let adding = planned - done.min(planned);
    match existing.checked_add(adding) {
        Some(total) if total <= MAX_PATHS && existing <= MAX_PATHS => Ok(()),
        _ => Err(TooManyPaths { existing, adding }),
    }
}

/// The blocks of a plan in the order they are traced, produced lazily (memory independent of the
/// path count): interleaved across lights in proportion to their quotas (block b of a light with
/// B blocks comes at "time" (b + ½)/B, ties by table index, then plan order), so that a trace
/// stopped early has traced every light about equally far.
pub fn block_order(plan: &[LightPlan]) -> BlockOrder<'_> {
    BlockOrder { plan, next: vec![0; plan.len()] }
}

/// The iterator of [`block_order`]: a merge of the lights' block sequences, each already in
/// order, by their times. One step costs O(lights).
#[derive(Clone, Debug)]
pub struct BlockOrder<'a> {
    plan: &'a [LightPlan],
    /// The next block of each plan entry.
    next: Vec<u64>,
}

impl BlockOrder<'_> {
    /// Time of block `b` of a light with `n` blocks.
    fn time(b: u64, n: u64) -> f64 {
        (b as f64 + 0.5) / n as f64
    }
}

impl Iterator for BlockOrder<'_> {
    type Item = Block;

    fn next(&mut self) -> Option<Block> {
        let mut best: Option<(f64, u32, usize)> = None;
        for (i, p) in self.plan.iter().enumerate() {
            let n = p.paths.div_ceil(BLOCK_PATHS);
            if self.next[i] >= n {
                continue;
            }
            let key = (Self::time(self.next[i], n), p.table_index, i);
            let earlier = best.is_none_or(|b| key.0.total_cmp(&b.0).then(key.1.cmp(&b.1)).is_lt());
            if earlier {
                best = Some(key);
            }
        }
        let (_, _, i) = best?;
        let (p, b) = (self.plan[i], self.next[i]);
        self.next[i] += 1;
        Some(Block { light: p, index: b, paths: BLOCK_PATHS.min(p.paths - b * BLOCK_PATHS) })
    }
}

/// How many blocks of `plan`, in [`block_order`], hold exactly `paths` paths: the blocks an
/// interrupted run of the plan completed (it stops between blocks, in order). `None` if no
/// prefix of blocks holds that many. Takes time ∝ `paths` / [`BLOCK_PATHS`], no memory.
pub fn blocks_done(plan: &[LightPlan], paths: u64) -> Option<usize> {
    let mut sum = 0u64;
    let mut count = 0;
    for b in block_order(plan) {
        if sum >= paths {
            break;
        }
        sum += b.paths;
        count += 1;
    }
    (sum == paths).then_some(count)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quotas_follow_power_and_sum_to_total() {
        let p = [Rgb::splat(1.0), Rgb::splat(3.0), Rgb::ZERO];
        let q = path_quotas(&p, 1000);
        assert_eq!(q, vec![250, 750, 0]);
        let q = path_quotas(&[Rgb::splat(1.0), Rgb::splat(1e-9)], 10);
        assert_eq!(q.iter().sum::<u64>(), 11, "a dim light still gets a path");
        assert!(q[1] >= 1);
        assert_eq!(path_quotas(&[Rgb::splat(2.0); 3], 7).iter().sum::<u64>(), 7);
    }

    #[test]
    fn blocks_done_finds_the_prefix_an_interrupted_run_traced() {
        let plan = [
            LightPlan { scene_light: 0, table_index: 0, paths: 3 * BLOCK_PATHS },
            LightPlan { scene_light: 1, table_index: 1, paths: BLOCK_PATHS + 7 },
        ];
        let order: Vec<Block> = block_order(&plan).collect();
        let mut sum = 0;
        for (i, b) in order.iter().enumerate() {
            assert_eq!(blocks_done(&plan, sum), Some(i));
            assert_eq!(blocks_done(&plan, sum + 1), None, "not a block boundary");
            sum += b.paths;
        }
        assert_eq!(blocks_done(&plan, sum), Some(order.len()));
        assert_eq!(blocks_done(&plan, sum + 1), None);
    }

    #[test]
    fn blocks_interleave_lights_by_quota_and_cover_the_plan_once() {
        let plan = [
            LightPlan { scene_light: 0, table_index: 0, paths: 4 * BLOCK_PATHS },
            LightPlan { scene_light: 1, table_index: 1, paths: BLOCK_PATHS + 7 },
        ];
        let order: Vec<(u32, u64, u64)> =
            block_order(&plan).map(|b| (b.light.table_index, b.index, b.paths)).collect();
        let b = BLOCK_PATHS;
        // Light 0's blocks at 1/8, 3/8, 5/8, 7/8; light 1's at 1/4, 3/4.
        assert_eq!(order, [(0, 0, b), (1, 0, b), (0, 1, b), (0, 2, b), (1, 1, 7), (0, 3, b)]);
    }

    /// The order the plan had when it was a sorted list (before it became lazy): the lazy merge
    /// must give exactly the same blocks, or resumed datasets would differ.
    fn sorted_block_order(plan: &[LightPlan]) -> Vec<Block> {
        let mut blocks: Vec<(f64, Block)> = plan
            .iter()
            .flat_map(|&p| {
                let n = p.paths.div_ceil(BLOCK_PATHS);
                (0..n).map(move |b| {
                    let block =
                        Block { light: p, index: b, paths: BLOCK_PATHS.min(p.paths - b * BLOCK_PATHS) };
                    ((b as f64 + 0.5) / n as f64, block)
                })
            })
            .collect();
        blocks.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.light.table_index.cmp(&b.1.light.table_index)));
        blocks.into_iter().map(|(_, b)| b).collect()
    }

    #[test]
    fn the_lazy_block_order_is_the_sorted_one() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        for case in 0..200 {
            let lights = 1 + case % 5;
            let plan: Vec<LightPlan> = (0..lights)
                .map(|k| {
                    x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                    let paths = (x >> 33) % (40 * BLOCK_PATHS);
                    // Table indices out of plan order, as an added light's are.
                    LightPlan { scene_light: k, table_index: ((k * 3 + case) % lights) as u32, paths }
                })
                .collect();
            assert_eq!(block_order(&plan).collect::<Vec<_>>(), sorted_block_order(&plan), "plan {plan:?}");
        }
    }

    #[test]
    fn a_plan_of_any_size_costs_no_memory_and_sums_never_wrap() {
        // Before the plan was lazy, this plan (u64::MAX paths) allocated 2·10¹⁷ bytes.
        let plan = [
            LightPlan { scene_light: 0, table_index: 0, paths: u64::MAX / 2 },
            LightPlan { scene_light: 1, table_index: 1, paths: u64::MAX / 2 + 1 },
        ];
        let first: Vec<Block> = block_order(&plan).take(3).collect();
        assert_eq!(
            first.iter().map(|b| (b.light.table_index, b.index)).collect::<Vec<_>>(),
            [(0, 0), (1, 0), (0, 1)]
        );
        // A total beyond the bound is refused, and so is one whose sum would wrap.
        let table = |n: &[u64]| LightTable {
            lights: n
                .iter()
                .map(|&paths| LightRecord { name: String::new(), shape: [0; 16], power: Rgb::ONE, paths })
                .collect(),
        };
        let pass = |lights: &[LightPlan], first_block| PassPlan {
            settings: TraceSettings::default(),
            lights: lights.to_vec(),
            first_block,
        };
        assert!(check_path_budget(&table(&[0, 0]), &pass(&plan, 0)).is_err());
        let fits = [LightPlan { scene_light: 0, table_index: 0, paths: MAX_PATHS - 10 }];
        assert_eq!(check_path_budget(&table(&[10]), &pass(&fits, 0)), Ok(()));
        assert!(check_path_budget(&table(&[11]), &pass(&fits, 0)).is_err());
        // Resuming: the blocks done are in the table already and count once.
        assert_eq!(check_path_budget(&table(&[10 + BLOCK_PATHS]), &pass(&fits, 1)), Ok(()));
        assert!(check_path_budget(&table(&[u64::MAX, 2]), &pass(&[], 0)).is_err(), "a wrapping table total");
        // Quotas of the largest totals still sum exactly to the total.
        for total in [MAX_PATHS, u64::MAX] {
            let q = path_quotas(&[Rgb::splat(1.0), Rgb::splat(2.0), Rgb::splat(3.0)], total);
            assert_eq!(q.iter().fold(0u128, |a, &b| a + b as u128), total as u128, "{total}");
        }
    }

    #[test]
    fn a_strategy_choice_replaces_only_what_it_names() {
        let base = TraceSettings { paths: 9, seed: 4, stream: 2, rr_depth: 3, ..Default::default() };
        assert_eq!(StrategyChoice::default().over(base), base);
        let choice =
            StrategyChoice { roulette: Some(Roulette::Fixed), rr_depth: Some(1), ..Default::default() };
        assert_eq!(choice.over(base), TraceSettings { roulette: Roulette::Fixed, rr_depth: 1, ..base });
    }

    #[test]
    fn a_scene_without_emitting_lights_plans_nothing_and_is_refused() {
        let mut d = crate::scene::cornell_box();
        assert_eq!(check_emission(&plan_all(&Scene::build(&d).unwrap(), 1000)), Ok(()));
        d.meshes.iter_mut().filter_map(|m| m.emission.as_mut()).for_each(|e| e.radiance = Rgb::ZERO);
        let dark = Scene::build(&d).unwrap();
        let plan = plan_all(&dark, 1000);
        assert_eq!(plan.iter().map(|p| p.paths).sum::<u64>(), 0);
        assert_eq!(check_emission(&plan), Err(NoEmission));
    }
}
