//! Merging: independent datasets of the same scene become one (the thesis's master/worker
//! merge, §6.2.4). Exact, because each light's energy is split only among its own paths: a
//! light in several inputs has its N_k summed, and the samples of all of them then share
//! Φ_k/(N_k¹ + N_k² + …); a light only some inputs have (one gained it by adding a light) keeps
//! those inputs' paths. Refused: inputs traced from different geometry, a light whose shape
//! differs, and inputs that share a random stream (their paths would be copies, not new
//! samples).

use super::{ChangesText, DatasetHeader, LightTable, MAX_PATHS, TooManyPaths, differing_objects};
use crate::scene::{Fingerprint, ObjectChanges};

/// Why two datasets cannot be merged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MergeError {
    /// The geometry/material fingerprints differ.
    #[error(
        "the datasets were traced from different scenes: {} (geometry fingerprints {} and {})",
        ChangesText(changes.as_ref()),
        first.geometry_hex(),
        other.geometry_hex()
    )]
    DifferentScenes {
        /// The fingerprint of the datasets merged so far.
        first: Fingerprint,
        /// The fingerprint of the dataset merged in.
        other: Fingerprint,
        /// The meshes and materials of the dataset merged in that differ, if both record them.
        changes: Option<ObjectChanges>,
    },
    /// A light has the same name but another shape.
    #[error("light '{0}' differs in shape between the datasets: they were traced from different scenes")]
    ShapeChanged(String),
    /// A pass of the dataset merged in used a (seed, stream) some earlier pass used.
    #[error(
        "the dataset repeats the random stream (seed {seed}, stream {stream}) of an earlier one: its paths \
         are copies, not independent samples"
    )]
    RepeatedStream {
        /// The seed.
        seed: u64,
        /// The stream family.
        stream: u64,
    },
    /// The merged dataset would hold more than [`MAX_PATHS`] paths.
    #[error(transparent)]
    TooManyPaths(#[from] TooManyPaths),
}

/// The light table of the union of two independent datasets of the same scene, and where each
/// of `b`'s lights went in it. Lights are matched by name (and must have the same shape): a
/// light in both has N_k summed; a light in only one keeps its N_k (e.g. `b` is a copy of `a`
/// that gained a light) — exact too, since each light's energy is split only among its own
/// paths. `a`'s lights keep their indices; `b`'s new lights follow in `b`'s order.
/// Powers are taken from `a` (samples do not depend on power; a difference is relighting).
pub fn merge_tables(a: &LightTable, b: &LightTable) -> Result<(LightTable, Vec<u32>), MergeError> {
    let mut out = a.clone();
    let mut b_index = Vec::with_capacity(b.lights.len());
    for y in &b.lights {
        match out.lights.iter().position(|x| x.name == y.name) {
            Some(k) if out.lights[k].shape != y.shape => {
                return Err(MergeError::ShapeChanged(y.name.clone()));
            }
            Some(k) => {
                // Cannot wrap below the checked total; saturating keeps it so if a table is
                // beyond the bound (then refused below).
                out.lights[k].paths = out.lights[k].paths.saturating_add(y.paths);
                b_index.push(k as u32);
            }
            None => {
                b_index.push(out.lights.len() as u32);
                out.lights.push(y.clone());
            }
        }
    }
    let (existing, adding) = (a.total_paths(), b.total_paths());
    if existing.checked_add(adding).is_none_or(|total| total > MAX_PATHS) {
        return Err(TooManyPaths { existing, adding }.into());
    }
    Ok((out, b_index))
}

/// Merges the header of dataset `b` into `merged` (the header of the datasets merged so far,
/// starting with the first one's), and returns where each of `b`'s lights went in the merged
/// table ([`merge_tables`]): its chunks are copied under those indices. `b`'s passes are
/// appended with their plans remapped to the merged table. The lights hash and the label (the
/// scene file) are `b`'s once `b` has every light of the union. On an error `merged` is left as it was.
pub fn merge_header(merged: &mut DatasetHeader, b: &DatasetHeader) -> Result<Vec<u32>, MergeError> {
    if b.fingerprint.geometry != merged.fingerprint.geometry {
        let changes = differing_objects(&merged.objects, &b.objects);
        return Err(MergeError::DifferentScenes { first: merged.fingerprint, other: b.fingerprint, changes });
    }
    let (table, lights) = merge_tables(&merged.table, &b.table)?;
    let mut out = merged.clone();
    if table.lights.len() == b.table.lights.len() {
        // This input has every light: its scene is the one the merged dataset belongs to.
        out.fingerprint.lights = b.fingerprint.lights;
        out.label = b.label.clone();
    }
    if out.objects.is_empty() {
        // Same geometry: an input of format 4 on knows its objects for all of them.
        out.objects = b.objects.clone();
    }
    out.table = table;
    for p in &b.trace.passes {
        if out.trace.passes.iter().any(|q| q.seed == p.seed && q.stream == p.stream) {
            return Err(MergeError::RepeatedStream { seed: p.seed, stream: p.stream });
        }
        let mut p = p.clone();
        p.planned.iter_mut().for_each(|(light, _)| *light = lights[*light as usize]);
        out.trace.passes.push(p);
    }
    *merged = out;
    Ok(lights)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::testing::{Traced, cornell_with_bulb, trace_into};
    use crate::dataset::{LightRecord, TraceInfo, TracePass};
    use crate::math::Rgb;
    use crate::scene::{Change, ObjectHash, ObjectKind, Scene};

    fn table(lights: &[(&str, u8, u64)]) -> LightTable {
        LightTable {
            lights: lights
                .iter()
                .map(|&(name, shape, paths)| LightRecord {
                    name: name.into(),
                    shape: [shape; 16],
                    power: Rgb::ONE,
                    paths,
                })
                .collect(),
        }
    }

    #[test]
    fn merging_unites_light_tables_by_name_and_sums_their_paths() {
        let a = table(&[("sun", 1, 10), ("lamp", 2, 20)]);
        let b = table(&[("bulb", 3, 5), ("lamp", 2, 7), ("sun", 1, 1)]);
        let (m, map) = merge_tables(&a, &b).unwrap();
        assert_eq!(m, table(&[("sun", 1, 11), ("lamp", 2, 27), ("bulb", 3, 5)]));
        assert_eq!(map, [2, 1, 0]);
        let (m, map) = merge_tables(&b, &a).unwrap();
        assert_eq!(m, table(&[("bulb", 3, 5), ("lamp", 2, 27), ("sun", 1, 11)]));
        assert_eq!(map, [2, 1]);
        let moved = table(&[("lamp", 9, 1)]);
        assert_eq!(merge_tables(&a, &moved), Err(MergeError::ShapeChanged("lamp".into())));
    }

    /// A pass: seed, stream, plan (light, paths).
    type Pass<'a> = (u64, u64, &'a [(u32, u64)]);

    fn header(geometry: u8, lights: &[(&str, u8, u64)], passes: &[Pass<'_>]) -> DatasetHeader {
        DatasetHeader {
            fingerprint: Fingerprint { geometry: [geometry; 16], lights: [lights.len() as u8; 16] },
            objects: vec![ObjectHash { kind: ObjectKind::Mesh, name: "box".into(), hash: [geometry; 16] }],
            label: format!("scene {geometry}"),
            trace: TraceInfo {
                passes: passes
                    .iter()
                    .map(|&(seed, stream, planned)| TracePass {
                        seed,
                        stream,
                        paths: planned.iter().map(|p| p.1).sum(),
                        planned: planned.to_vec(),
                        ..Default::default()
                    })
                    .collect(),
            },
            table: table(lights),
        }
    }

    #[test]
    fn merged_headers_sum_n_k_remap_the_passes_and_take_the_fuller_lights_hash() {
        let a = header(1, &[("light", 1, 10)], &[(1, 0, &[(0, 10)])]);
        // b traced the box, then gained a bulb (another pass, planned for b's light 0).
        let mut b = header(1, &[("bulb", 2, 5), ("light", 1, 20)], &[(2, 0, &[(1, 20)]), (2, 1, &[(0, 5)])]);
        b.label = "scene-with-bulb.xml".into();
        let mut m = a.clone();
        assert_eq!(merge_header(&mut m, &b), Ok(vec![1, 0]));
        assert_eq!(m.table, table(&[("light", 1, 30), ("bulb", 2, 5)]));
        assert_eq!(m.label, b.label, "the scene with every light names the merged dataset's scene");
        assert_eq!(m.fingerprint.lights, b.fingerprint.lights, "b has every light of the union");
        let plans: Vec<_> = m.trace.passes.iter().map(|p| (p.seed, p.stream, p.planned.clone())).collect();
        assert_eq!(plans, [(1, 0, vec![(0, 10)]), (2, 0, vec![(0, 20)]), (2, 1, vec![(1, 5)])]);
        // Merging a third input with fewer lights keeps the fuller hash.
        let c = header(1, &[("light", 1, 4)], &[(3, 0, &[(0, 4)])]);
        merge_header(&mut m, &c).unwrap();
        assert_eq!((m.fingerprint.lights, m.table.total_paths()), (b.fingerprint.lights, 39));
        assert_eq!(m.label, b.label, "an input with fewer lights does not name the scene");
    }

    #[test]
    fn path_counts_beyond_the_bound_are_refused_not_wrapped() {
        // Issue 10: lights of 2^63+18 and 2^63+32 paths wrapped to "paths 50".
        let a = table(&[("a", 1, (1 << 63) + 18)]);
        let b = table(&[("b", 2, (1 << 63) + 32)]);
        assert!(matches!(merge_tables(&a, &b), Err(MergeError::TooManyPaths(_))));
        let c = table(&[("a", 1, MAX_PATHS / 2)]);
        assert!(merge_tables(&c, &c).is_ok());
        assert!(matches!(
            merge_tables(&c, &table(&[("a", 1, MAX_PATHS / 2 + 1)])),
            Err(MergeError::TooManyPaths(_))
        ));
    }

    #[test]
    fn other_geometry_a_moved_light_or_a_repeated_stream_is_refused_and_changes_nothing() {
        let a = header(1, &[("light", 1, 10)], &[(1, 0, &[(0, 10)])]);
        let refused = |b: &DatasetHeader| {
            let mut m = a.clone();
            let e = merge_header(&mut m, b).unwrap_err();
            assert_eq!(m, a, "a refused merge leaves the header as it was");
            e
        };
        let other = header(2, &[("light", 1, 10)], &[(2, 0, &[(0, 10)])]);
        let e = refused(&other);
        let changes =
            Some(ObjectChanges { changes: vec![(ObjectKind::Mesh, "box".into(), Change::Changed)] });
        assert_eq!(
            e,
            MergeError::DifferentScenes { first: a.fingerprint, other: other.fingerprint, changes }
        );
        assert!(e.to_string().contains("mesh 'box' changed"), "{e}");
        let moved = header(1, &[("light", 9, 10)], &[(2, 0, &[(0, 10)])]);
        assert_eq!(refused(&moved), MergeError::ShapeChanged("light".into()));
        // The second pass repeats the first input's stream: a copy of its paths.
        let again = header(1, &[("light", 1, 20)], &[(2, 0, &[(0, 10)]), (1, 0, &[(0, 10)])]);
        assert_eq!(refused(&again), MergeError::RepeatedStream { seed: 1, stream: 0 });
        let e = refused(&again).to_string();
        assert!(e.contains("seed 1") && e.contains("copies"), "{e}");
    }

    /// A merge of traces of other seeds is a dataset of all their paths: every chunk is one of
    /// an input's (independent streams), N_k is the sum, so each sample stands for
    /// Φ_k/(N_k¹ + N_k²) — and its flux estimate agrees with one trace of all the paths.
    #[test]
    fn a_merge_of_two_traces_estimates_like_one_trace_of_all_the_paths() {
        let scene = Scene::build(&cornell_with_bulb()).unwrap();
        let (one, two) = (trace_into(&scene, 20_000, 1), trace_into(&scene, 20_000, 2));
        let mut header = one.header.clone();
        let lights = merge_header(&mut header, &two.header).unwrap();
        assert_eq!(lights, [0, 1]);
        for (k, l) in header.table.lights.iter().enumerate() {
            assert_eq!(l.paths, one.header.table.lights[k].paths + two.header.table.lights[k].paths);
        }
        let merged = Traced { header, chunks: [one.chunks.clone(), two.chunks.clone()].concat() };
        assert_eq!(merged.header.trace.passes.len(), 2);
        merged.assert_estimates_like(&trace_into(&scene, 40_000, 3), "merged 2 × 20k");
    }
}
