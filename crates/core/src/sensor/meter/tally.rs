//! A meter's reading and its standard error, from independent groups of light paths.
//!
//! Every chunk of a dataset is one block of paths of one light, traced from its own random
//! stream (`crate::dataset::plan`), so the chunks are independent; within one light its paths
//! are identically distributed. A meter estimator adds each chunk's contribution X_c (per
//! target and channel) to a scratch row; the [`Tally`] keeps, per light k and target,
//! S₁ = Σ X_c, S₂ = Σ X_c² and S_n = Σ n_c·X_c, and per light N = Σ n_c and Q = Σ n_c² over its
//! chunks of n_c paths. The reading is Σ_k S₁ and, with μ = S₁/N the mean per path,
//!
//! ```text
//! Var_k = (S₂ − 2μ·S_n + μ²·Q) / (1 − Q/N²)
//! ```
//!
//! is unbiased for the variance of light k's sum: each X_c is a sum of n_c i.i.d. path
//! contributions of variance σ², so E[(X_c − n_c·μ)²] = n_c·σ²·(1 − n_c/N), whose sum over c
//! is σ²·(N − Q/N), and Var(Σ X_c) = N·σ². With equal chunks (m of n paths) this is m times the
//! chunks' sample variance. A light with a single chunk gives no variance estimate: its targets
//! that it lit get NaN. The channels are R, G, B and E_v in lux, by the scene's photometric rule
//! ([`Photometry`]), applied to each path's contribution as it is tallied, so that E_v's
//! standard error is that of the lux themselves. The chunks are cut into a
//! fixed number of runs whose tallies are summed in order, so a reading is the same bit for bit
//! whatever the thread count.

use crate::dataset::Sample;
use crate::film::SplatTarget;
use crate::math::Rgb;
use crate::scene::Photometry;
use rayon::prelude::*;

/// One independent group of paths: a chunk, its light (table index) and its path count n_c.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Group {
    /// The light's index in the dataset's table.
    pub light: u32,
    /// Paths in the group.
    pub paths: u64,
}

impl Group {
    /// Per table light (`lights` of them), the paths of `groups` that are its N_k; a group
    /// naming no table light counts for none.
    pub fn paths_per_light(groups: &[Group], lights: usize) -> Vec<u64> {
        let mut paths = vec![0u64; lights];
        for g in groups {
            if let Some(p) = paths.get_mut(g.light as usize) {
                *p += g.paths;
            }
        }
        paths
    }
}

/// What a meter read: per target (cell or point) the value and its standard error, channels
/// R, G, B (W/m²) and E_v (lux).
#[derive(Clone, Debug, PartialEq)]
pub struct Reading {
    /// The estimate per target.
    pub value: Vec<[f64; 4]>,
    /// Its standard error (NaN where it could not be estimated: a light with one chunk).
    pub std_error: Vec<[f64; 4]>,
}

impl Reading {
    /// A reading of `n` targets, all zero.
    pub fn zero(n: usize) -> Self {
        Reading { value: vec![[0.0; 4]; n], std_error: vec![[0.0; 4]; n] }
    }

    /// Adds an independent estimate (its value, and its error in quadrature).
    pub fn add_independent(&mut self, other: &Reading) {
        for (t, (v, e)) in self.value.iter_mut().zip(&mut self.std_error).enumerate() {
            for c in 0..4 {
                v[c] += other.value[t][c];
                e[c] = e[c].hypot(other.std_error[t][c]);
            }
        }
    }

    /// The reading cut into consecutive parts of `lens` targets each (several meters read in
    /// one pass, their targets one after the other), the values and errors as they are.
    pub fn split(self, lens: &[usize]) -> Vec<Reading> {
        let (mut value, mut std_error) = (self.value.into_iter(), self.std_error.into_iter());
        lens.iter()
            .map(|&n| Reading {
                value: value.by_ref().take(n).collect(),
                std_error: std_error.by_ref().take(n).collect(),
            })
            .collect()
    }

    /// The relative standard error of E_v over the targets that read more than 0: (largest,
    /// mean, how many such targets). NaN if any error is unknown; (0, 0, 0) if none is lit.
    pub fn relative_error(&self) -> (f64, f64, usize) {
        let rel: Vec<f64> = self
            .value
            .iter()
            .zip(&self.std_error)
            .filter(|(v, _)| v[3] > 0.0)
            .map(|(v, e)| e[3] / v[3])
            .collect();
        if rel.is_empty() {
            return (0.0, 0.0, 0);
        }
        let max = rel.iter().fold(0.0f64, |a, &b| if b.is_nan() || a.is_nan() { f64::NAN } else { a.max(b) });
        (max, rel.iter().sum::<f64>() / rel.len() as f64, rel.len())
    }
}

/// One chunk's contributions, row by target; only the touched targets are folded and cleared.
#[derive(Clone, Debug)]
pub struct Scratch {
    photometry: Photometry,
    cells: Vec<[f64; 4]>,
    touched: Vec<u32>,
    marked: Vec<bool>,
}

impl Scratch {
    fn new(n: usize, photometry: Photometry) -> Self {
        Scratch { photometry, cells: vec![[0.0; 4]; n], touched: Vec::new(), marked: vec![false; n] }
    }
}

impl SplatTarget for Scratch {
    #[inline]
    fn splat(&mut self, index: usize, v: Rgb) {
        if !self.marked[index] {
            self.marked[index] = true;
            self.touched.push(index as u32);
        }
        let rgb = [v.x as f64, v.y as f64, v.z as f64];
        let c = &mut self.cells[index];
        for k in 0..3 {
            c[k] += rgb[k];
        }
        c[3] += self.photometry.lux(rgb);
    }
}

/// One meter's view of a row shared by several meters read in one pass: its target `t` is the
/// row's `offset + t`.
pub(crate) struct Offset<'a, T> {
    /// The shared row.
    pub(crate) row: &'a mut T,
    /// Where the meter's targets start in it.
    pub(crate) offset: usize,
}

impl<T: SplatTarget> SplatTarget for Offset<'_, T> {
    #[inline]
    fn splat(&mut self, index: usize, v: Rgb) {
        self.row.splat(self.offset + index, v)
    }
}

/// Where each of meters of `lens` targets starts in their shared row, and the row's length.
pub(crate) fn offsets(lens: &[usize]) -> (Vec<usize>, usize) {
    let mut total = 0;
    let offsets = lens
        .iter()
        .map(|&n| {
            total += n;
            total - n
        })
        .collect();
    (offsets, total)
}

/// Per light: S₁, S₂, S_n per target and channel, N and Q.
#[derive(Clone, Debug)]
struct LightMoments {
    s1: Vec<[f64; 4]>,
    s2: Vec<[f64; 4]>,
    sn: Vec<[f64; 4]>,
    n: f64,
    q: f64,
    groups: u64,
}

impl LightMoments {
    fn new(targets: usize) -> Self {
        let z = vec![[0.0; 4]; targets];
        LightMoments { s1: z.clone(), s2: z.clone(), sn: z, n: 0.0, q: 0.0, groups: 0 }
    }

    fn add(&mut self, o: &LightMoments) {
        for (a, b) in [(&mut self.s1, &o.s1), (&mut self.s2, &o.s2), (&mut self.sn, &o.sn)] {
            for (x, y) in a.iter_mut().zip(b) {
                for c in 0..4 {
                    x[c] += y[c];
                }
            }
        }
        self.n += o.n;
        self.q += o.q;
        self.groups += o.groups;
    }
}

/// The moments of every light over the groups seen so far.
#[derive(Clone, Debug)]
struct Tally {
    targets: usize,
    lights: Vec<Option<LightMoments>>,
}

impl Tally {
    fn new(targets: usize, lights: usize) -> Self {
        Tally { targets, lights: vec![None; lights] }
    }

    /// Folds one group's scratch row in (and clears it).
    fn fold(&mut self, group: Group, scratch: &mut Scratch) {
        let n = group.paths as f64;
        let m = self.lights[group.light as usize].get_or_insert_with(|| LightMoments::new(self.targets));
        m.n += n;
        m.q += n * n;
        m.groups += 1;
        for &t in &scratch.touched {
            let t = t as usize;
            let x = std::mem::replace(&mut scratch.cells[t], [0.0; 4]);
            scratch.marked[t] = false;
            for (c, x) in x.into_iter().enumerate() {
                m.s1[t][c] += x;
                m.s2[t][c] += x * x;
                m.sn[t][c] += n * x;
            }
        }
        scratch.touched.clear();
    }

    fn add(mut self, o: Tally) -> Tally {
        for (a, b) in self.lights.iter_mut().zip(o.lights) {
            match (a.as_mut(), b) {
                (Some(a), Some(b)) => a.add(&b),
                (None, b) => *a = b,
                (_, None) => {}
            }
        }
        self
    }

    fn reading(&self) -> Reading {
        let mut r = Reading::zero(self.targets);
        let mut var = vec![[0.0f64; 4]; self.targets];
        for m in self.lights.iter().flatten() {
            let spread = 1.0 - m.q / (m.n * m.n);
            for (t, (value, var)) in r.value.iter_mut().zip(&mut var).enumerate() {
                for (c, (value, var)) in value.iter_mut().zip(var).enumerate() {
                    let (s1, s2, sn) = (m.s1[t][c], m.s2[t][c], m.sn[t][c]);
                    *value += s1;
                    if s2 == 0.0 {
                        continue;
                    }
                    let mu = s1 / m.n;
                    *var += if m.groups < 2 || !(spread > 0.0) {
                        f64::NAN
                    } else {
                        ((s2 - 2.0 * mu * sn + mu * mu * m.q) / spread).max(0.0)
                    };
                }
            }
        }
        for (e, v) in r.std_error.iter_mut().zip(var) {
            *e = v.map(f64::sqrt);
        }
        r
    }
}

/// Runs the groups are cut into, whatever the thread count.
const RUNS: usize = 32;

/// Reads `groups.len()` batches (batch i is group i: one chunk, fetched from memory or a file)
/// on all cores: `add(i, samples, flux per path, scratch)` puts batch i's contribution to every
/// target into the scratch row, and the result is the sum with its standard error. `targets`
/// is the number of cells or points, `photometry` the rule of the E_v channel.
pub(crate) fn tally_groups<B: super::super::AsBatch, E: Send>(
    targets: usize,
    photometry: Photometry,
    groups: &[Group],
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
    add: impl Fn(usize, &[Sample], Rgb, &mut Scratch) + Sync,
) -> Result<Reading, E> {
    let lights = groups.iter().map(|g| g.light as usize + 1).max().unwrap_or(0);
    let count = groups.len();
    // A fixed cut into runs, and their tallies folded in run order: the sums do not depend on
    // the thread count. Runs go in waves of one per thread, so only that many tallies live.
    let runs = RUNS.clamp(1, count.max(1));
    let run_len = count.div_ceil(runs).max(1);
    let wave = rayon::current_num_threads().max(1);
    let mut tally = Tally::new(targets, lights);
    for first_run in (0..runs).step_by(wave) {
        let done: Vec<Tally> = (first_run..(first_run + wave).min(runs))
            .into_par_iter()
            .map(|r| {
                let mut tally = Tally::new(targets, lights);
                let mut scratch = Scratch::new(targets, photometry);
                let first = (r * run_len).min(count);
                for (i, &group) in groups.iter().enumerate().take(((r + 1) * run_len).min(count)).skip(first)
                {
                    let b = batch(i)?;
                    let b = b.as_batch();
                    if group.paths > 0 {
                        add(i, b.samples, b.flux_per_path, &mut scratch);
                        tally.fold(group, &mut scratch);
                    }
                    progress(b.samples.len());
                }
                Ok(tally)
            })
            .collect::<Result<_, E>>()?;
        for t in done {
            tally = tally.add(t);
        }
    }
    Ok(tally.reading())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::RandomStream;

    /// The variance formula against the spread of many independent repetitions: groups of
    /// unequal size (two lights, one with a last short chunk) of i.i.d. path contributions.
    #[test]
    fn the_standard_error_matches_the_spread_of_repeated_readings() {
        let groups: Vec<Group> = [(0, 40), (0, 40), (0, 40), (0, 13), (1, 25), (1, 25), (1, 25), (1, 25)]
            .map(|(light, paths)| Group { light, paths })
            .to_vec();
        let (reps, mut values, mut var_est) = (4000, Vec::new(), 0.0);
        for rep in 0..reps {
            let r = tally_groups(
                2,
                Photometry::default(),
                &groups,
                |_| Ok::<_, ()>(crate::sensor::OwnedBatch::default()),
                |_| {},
                |i, _, _, s| {
                    let mut rng = RandomStream::new(rep, &[i as u64]);
                    for _ in 0..groups[i].paths {
                        // Light 0: exponential-ish contributions to target 0; light 1: to both.
                        let x = -rng.next_f32().max(1e-9).ln();
                        if groups[i].light == 0 {
                            s.splat(0, Rgb::splat(x));
                        } else {
                            s.splat(0, Rgb::splat(0.5 * x));
                            s.splat(1, Rgb::new(x * x, 0.0, 1.0));
                        }
                    }
                },
            )
            .unwrap();
            values.push(r.value[0][0]);
            var_est += r.std_error[0][0].powi(2) / reps as f64;
            assert_eq!(r.std_error[1][2], 0.0, "a constant has no error");
        }
        let mean = values.iter().sum::<f64>() / reps as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (reps - 1) as f64;
        // Expected: light 0 has 133 paths of Var 1, light 1 100 paths of Var 0.25 → 158.
        assert!((var / 158.0 - 1.0).abs() < 0.1, "spread {var} vs 158");
        // The mean of the estimated variances is unbiased: within its own noise (~2%).
        assert!((var_est / 158.0 - 1.0).abs() < 0.05, "estimated variance {var_est} vs 158");
    }

    /// The same reading, bit for bit, on one thread and on three.
    #[test]
    fn readings_do_not_depend_on_the_thread_count() {
        let groups: Vec<Group> = (0..100).map(|i| Group { light: i % 3, paths: 7 + i as u64 % 5 }).collect();
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                tally_groups(
                    4,
                    Photometry::default(),
                    &groups,
                    |_| Ok::<_, ()>(crate::sensor::OwnedBatch::default()),
                    |_| {},
                    |i, _, _, s| {
                        let mut rng = RandomStream::new(9, &[i as u64]);
                        for _ in 0..groups[i].paths {
                            s.splat((rng.next_f32() * 4.0) as usize, Rgb::splat(rng.next_f32() * 1e3));
                        }
                    },
                )
                .unwrap()
            })
        };
        assert_eq!(run(1), run(3));
    }

    #[test]
    fn one_chunk_of_a_light_leaves_its_error_unknown() {
        let groups = [Group { light: 0, paths: 10 }];
        let r = tally_groups(
            2,
            Photometry::default(),
            &groups,
            |_| Ok::<_, ()>(crate::sensor::OwnedBatch::default()),
            |_| {},
            |_, _, _, s| s.splat(1, Rgb::ONE),
        )
        .unwrap();
        assert_eq!(r.std_error[0], [0.0; 4]);
        assert!(r.std_error[1][0].is_nan());
        assert!(r.relative_error().0.is_nan());
        assert_eq!(r.value[1][3], Photometry::default().lux([1.0; 3]));
    }

    /// E_v follows the rule it is given: a white irradiance E reads 683·E lux by default and
    /// 179·E by Radiance's; a coloured one the rule's weights; R, G, B are untouched.
    #[test]
    fn the_lux_channel_uses_the_scenes_rule() {
        let groups = [Group { light: 0, paths: 10 }, Group { light: 0, paths: 10 }];
        let read = |photometry: Photometry, e: Rgb| {
            tally_groups(
                1,
                photometry,
                &groups,
                |_| Ok::<_, ()>(crate::sensor::OwnedBatch::default()),
                |_| {},
                |i, _, _, s| s.splat(0, e * (i + 1) as f32),
            )
            .unwrap()
        };
        let white = Rgb::splat(2.0);
        let (ours, radiance) = (read(Photometry::REC709_683, white), read(Photometry::RADIANCE, white));
        assert!((ours.value[0][3] / (683.0 * 6.0) - 1.0).abs() < 1e-12, "{:?}", ours.value);
        assert!((radiance.value[0][3] / (179.0 * 6.0) - 1.0).abs() < 1e-8, "{:?}", radiance.value);
        assert_eq!(ours.value[0][..3], radiance.value[0][..3]);
        // The standard error of E_v scales with the rule: chunk values 179·2 and 179·4 lux.
        assert!((radiance.std_error[0][3] / ours.std_error[0][3] - 179.0 / 683.0).abs() < 1e-8);
        let red = Rgb::new(1.0, 0.0, 0.0);
        assert!(
            (read(Photometry::RADIANCE, red).value[0][3] - 179.0 * 0.2651058201058201 * 3.0).abs() < 1e-9
        );
        assert_eq!(read(Photometry::REC709_683, red).value[0][3], 683.0 * 0.2126 + 683.0 * 0.2126 * 2.0);
    }
}
