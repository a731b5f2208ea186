//! The preview-subset law: rendering from a subset of a dataset's chunks is still unbiased if
//! the subset's samples stand for Φ_k/N'_k each, N'_k being the paths of light k the subset
//! holds (instead of Φ_k/N_k) — a cheaper, noisier estimate from fewer paths. Exact for the
//! same reason as merging: each light's energy is split only among its own paths, and every
//! chunk holds whole, independent paths.

/// Which chunks a preview keeps, and how much more flux each of their samples carries.
#[derive(Clone, Debug, PartialEq)]
pub struct Subset {
    /// Indices of the kept chunks, ascending.
    pub chunks: Vec<usize>,
    /// Per light: N_k/N'_k, the factor on its flux per path (1 for a light without paths).
    pub flux_scale: Vec<f32>,
}

/// The fraction asked for is not in (0, 1].
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error("the fraction {0} must be in (0, 1]")]
pub struct BadFraction(pub f64);

/// Keeps about `fraction` of each light's chunks, evenly spread: chunk j of a light is kept
/// when ⌊(j+1)·f⌋ > ⌊j·f⌋. A light with too few chunks to thin keeps all of them rather than be
/// lost. `chunks` gives each chunk's (light, paths), every light below `lights`.
pub fn subset(chunks: &[(u32, u64)], lights: usize, fraction: f64) -> Result<Subset, BadFraction> {
    if !(fraction > 0.0 && fraction <= 1.0) {
        return Err(BadFraction(fraction));
    }
    let (mut seen, mut kept_paths, mut all_paths) =
        (vec![0u64; lights], vec![0u64; lights], vec![0u64; lights]);
    let mut kept = Vec::new();
    for (i, &(light, paths)) in chunks.iter().enumerate() {
        let k = light as usize;
        let j = seen[k] as f64;
        seen[k] += 1;
        all_paths[k] += paths;
        if ((j + 1.0) * fraction).floor() > (j * fraction).floor() {
            kept.push(i);
            kept_paths[k] += paths;
        }
    }
    let mut flux_scale = vec![1.0f32; lights];
    for k in 0..lights {
        if kept_paths[k] == 0 && all_paths[k] > 0 {
            kept.extend((0..chunks.len()).filter(|&i| chunks[i].0 as usize == k));
            kept_paths[k] = all_paths[k];
        }
        if kept_paths[k] > 0 {
            flux_scale[k] = all_paths[k] as f32 / kept_paths[k] as f32;
        }
    }
    kept.sort_unstable();
    Ok(Subset { chunks: kept, flux_scale })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::testing::{cornell_with_bulb, trace_into};
    use crate::scene::Scene;

    #[test]
    fn a_subset_spreads_evenly_over_each_light_and_renormalises_by_its_paths() {
        // Light 0: five chunks of 10 paths; light 1: two chunks (7 and 3 paths); light 2: none.
        let chunks = [(0, 10), (1, 7), (0, 10), (0, 10), (1, 3), (0, 10), (0, 10)];
        let s = subset(&chunks, 3, 0.5).unwrap();
        // Light 0 keeps its chunks j = 1, 3 (where ⌊(j+1)/2⌋ steps); light 1 its chunk j = 1.
        assert_eq!(s.chunks, [2, 4, 5]);
        assert_eq!(s.flux_scale, [50.0 / 20.0, 10.0 / 3.0, 1.0]);
        let all = subset(&chunks, 3, 1.0).unwrap();
        assert_eq!((all.chunks, all.flux_scale), ((0..7).collect(), vec![1.0; 3]));
        // Light 1 has too few chunks to keep a tenth of: it keeps them all rather than vanish.
        let chunks: Vec<(u32, u64)> = [(0, 10); 10].into_iter().chain([(1, 5)]).collect();
        let s = subset(&chunks, 2, 0.1).unwrap();
        assert_eq!((s.chunks, s.flux_scale), (vec![9, 10], vec![10.0, 1.0]));
        for bad in [0.0, -0.5, 1.5, f64::NAN] {
            assert!(subset(&chunks, 3, bad).is_err(), "{bad}");
        }
        assert_eq!(BadFraction(0.0).to_string(), "the fraction 0 must be in (0, 1]");
    }

    /// Renormalised, a quarter of the chunks estimates what all of them do, from fewer paths.
    #[test]
    fn a_quarter_of_the_chunks_estimates_like_all_of_them() {
        let scene = Scene::build(&cornell_with_bulb()).unwrap();
        let data = trace_into(&scene, 120_000, 7);
        let summary: Vec<(u32, u64)> = data.chunks.iter().map(|c| (c.light, c.paths)).collect();
        let s = subset(&summary, 2, 0.25).unwrap();
        let mut preview = data.clone();
        preview.chunks = s.chunks.iter().map(|&i| data.chunks[i].clone()).collect();
        for (k, l) in preview.header.table.lights.iter_mut().enumerate() {
            let kept: u64 = preview.chunks.iter().filter(|c| c.light as usize == k).map(|c| c.paths).sum();
            assert_eq!(l.paths as f32 / kept as f32, s.flux_scale[k], "N_k/N'_k");
            l.paths = kept; // Φ_k/N'_k per path
        }
        assert!(preview.chunks.len() < data.chunks.len() / 3);
        preview.assert_estimates_like(&data, "a quarter of the chunks");
    }
}
