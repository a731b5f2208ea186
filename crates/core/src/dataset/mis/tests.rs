//! The dataset laws keep the MIS records exact, and [`mis_compatibility`] refuses exactly the
//! combinations whose records would not be: a fresh trace, a merge, a refinement, an added
//! light and a resumed run carry one record per sample and stay compatible; records depend
//! neither on the lights' power (relighting) nor on the roulette rule, so passes that differ in
//! those merge with exact records; mixed heuristics, record-less passes, another sampling
//! signature or mixed direction rules are refused with the pass and the fix.

use super::*;
use crate::dataset::testing::{Traced, cornell_with_bulb, trace_into};
use crate::dataset::{
    PassMis, Roulette, StrategyChoice, TracePass, TraceSettings, add_light, merge_header, new_trace, refine,
};
use crate::sampling::RandomStream;
use crate::scene::{Scene, cornell_box};
use crate::trace::{PathScratch, trace_path};

/// A fresh trace of `settings` into memory.
fn traced(scene: &Scene, settings: TraceSettings) -> Traced {
    let (header, pass) = new_trace(scene, "test", settings);
    let mut t = Traced { header, chunks: Vec::new() };
    t.run(scene, &pass);
    t
}

/// Every chunk carries one record per sample (or none, when the pass has no MIS).
#[track_caller]
fn assert_records(t: &Traced, want: bool) {
    for c in &t.chunks {
        assert_eq!(c.records.len(), if want { c.samples.len() } else { 0 });
    }
}

fn merged(a: &Traced, b: &Traced) -> Traced {
    let mut header = a.header.clone();
    merge_header(&mut header, &b.header).unwrap();
    Traced { header, chunks: [a.chunks.clone(), b.chunks.clone()].concat() }
}

const POWER_IMPORTANCE: MisSettings =
    MisSettings { heuristic: Heuristic::Power, directions: Directions::Importance };

#[test]
fn a_trace_and_its_merges_refinements_and_added_lights_stay_compatible() {
    let (one, two) = (Scene::build(&cornell_box()).unwrap(), Scene::build(&cornell_with_bulb()).unwrap());
    let a = trace_into(&one, 9_000, 1);
    assert_records(&a, true);
    assert_eq!(
        a.header.trace.passes[0].mis,
        Some(PassMis { heuristic: Heuristic::Power, signature: SAMPLING_SIGNATURE })
    );
    assert_eq!(mis_compatibility(&a.header), Ok(POWER_IMPORTANCE));
    let m = merged(&a, &trace_into(&one, 9_000, 2));
    assert_eq!(mis_compatibility(&m.header), Ok(POWER_IMPORTANCE));

    // A refinement and an added light continue with the dataset's records.
    let none = StrategyChoice::default();
    let mut r = m.clone();
    let (header, pass) = refine(&r.header, &one, 5_000, None, &none).unwrap();
    assert_eq!(pass.settings.mis, Some(Heuristic::Power));
    r.header = header;
    r.run(&one, &pass);
    assert_records(&r, true);
    let (header, pass) = add_light(&r.header, &two, "bulb", Some(5_000), None, &none).unwrap();
    r.header = header;
    r.run(&two, &pass);
    assert_records(&r, true);
    assert_eq!(r.header.trace.passes.len(), 4);
    assert_eq!(mis_compatibility(&r.header), Ok(POWER_IMPORTANCE));

    // A balance-heuristic dataset is refined with balance records.
    let b = traced(
        &one,
        TraceSettings { paths: 4_000, seed: 5, mis: Some(Heuristic::Balance), ..Default::default() },
    );
    let (_, pass) = refine(&b.header, &one, 4_000, None, &none).unwrap();
    assert_eq!(pass.settings.mis, Some(Heuristic::Balance));
    assert_eq!(mis_compatibility(&b.header).map(|s| s.heuristic), Ok(Heuristic::Balance));
}

#[test]
fn mixed_or_missing_records_merge_but_are_refused_for_mis_with_the_reason() {
    let one = Scene::build(&cornell_box()).unwrap();
    let a = trace_into(&one, 4_000, 1);
    let s =
        |seed, mis, directions| TraceSettings { paths: 4_000, seed, mis, directions, ..Default::default() };
    let balance = traced(&one, s(2, Some(Heuristic::Balance), Directions::Importance));
    let without = traced(&one, s(3, None, Directions::Importance));
    assert_records(&without, false);
    let uniform = traced(&one, s(4, Some(Heuristic::Power), Directions::Uniform));

    let e = mis_compatibility(&merged(&a, &balance).header).unwrap_err();
    assert_eq!(
        e,
        MisUnavailable::Heuristics {
            first_pass: 0,
            first: Heuristic::Power,
            pass: 1,
            other: Heuristic::Balance
        }
    );
    assert!(e.to_string().contains("one heuristic"), "{e}");
    let e = mis_compatibility(&merged(&a, &without).header).unwrap_err();
    assert_eq!(e, MisUnavailable::NoRecords { pass: 1, seed: 3, stream: 0 });
    let text = e.to_string();
    assert!(text.starts_with("pass 1 (seed 3, stream 0) was traced without MIS records"), "{text}");
    assert!(text.contains("re-trace the dataset") && text.contains("bidirectional estimator"), "{text}");
    assert_eq!(
        mis_compatibility(&without.header),
        Err(MisUnavailable::NoRecords { pass: 0, seed: 3, stream: 0 })
    );
    let e = mis_compatibility(&merged(&a, &uniform).header).unwrap_err();
    assert!(matches!(e, MisUnavailable::Directions { pass: 1, other: Directions::Uniform, .. }), "{e}");

    // Records of another tracer, and a dataset with no paths at all.
    let mut old = a.header.clone();
    old.trace.passes[0].mis =
        Some(PassMis { heuristic: Heuristic::Power, signature: SAMPLING_SIGNATURE + 1 });
    let e = mis_compatibility(&old).unwrap_err();
    assert_eq!(
        e,
        MisUnavailable::Signature { pass: 0, found: SAMPLING_SIGNATURE + 1, supported: SAMPLING_SIGNATURE }
    );
    assert!(e.to_string().contains("re-trace"), "{e}");
    assert_eq!(
        mis_compatibility(&new_trace(&one, "empty", TraceSettings::default()).0),
        Err(MisUnavailable::NoPaths)
    );
    // A pass that traced nothing (saved before its first block) does not count.
    let mut h = a.header.clone();
    h.trace.passes.push(TracePass { paths: 0, ..Default::default() });
    assert_eq!(mis_compatibility(&h), Ok(POWER_IMPORTANCE));
}

/// The paths of light `k` of `scene` under `settings`, each from its own stream: samples and
/// records per path.
fn paths(scene: &Scene, k: usize, settings: &TraceSettings, n: u64) -> Vec<(Vec<Sample>, Vec<MisRecord>)> {
    let mut stack = PathScratch::default();
    (0..n)
        .map(|i| {
            let mut rng = RandomStream::new(settings.seed, &[99, i]);
            let (mut out, mut records) = (Vec::new(), Vec::new());
            trace_path(scene, k, settings, &mut rng, &mut out, &mut records, &mut stack);
            (out, records)
        })
        .collect()
}

use crate::dataset::Sample;

/// Records are functions of the path and the heuristic only: the same random numbers give the
/// same records whatever the light's power (relighting a light, or its power changed in the
/// scene, needs no new records) and whatever the roulette rule (which changes β and where
/// paths end, not the densities of what is stored before).
#[test]
fn records_depend_neither_on_power_nor_on_roulette() {
    let scene = Scene::build(&cornell_with_bulb()).unwrap();
    let mut bright = cornell_with_bulb();
    bright.point_lights[0].intensity *= 7.0;
    let bright = Scene::build(&bright).unwrap();
    let base = TraceSettings { seed: 8, rr_depth: 1, ..Default::default() };
    let fixed = TraceSettings { roulette: Roulette::Fixed, ..base };
    let (mut compared, mut differing_beta) = (0, 0);
    for k in 0..scene.lights.len() {
        let a = paths(&scene, k, &base, 400);
        assert_eq!(
            a,
            paths(&bright, k, &base, 400),
            "light {k}: a brighter light traces the same samples and records"
        );
        for ((sa, ra), (sb, rb)) in a.iter().zip(paths(&scene, k, &fixed, 400)) {
            // The same random numbers: the same vertices until roulette ends one of the paths.
            let n = sa.len().min(sb.len());
            for j in 0..n {
                assert_eq!(sa[j].position, sb[j].position);
                assert_eq!(ra[j], rb[j], "light {k}: records under energy and fixed roulette");
                differing_beta += usize::from(sa[j].beta != sb[j].beta);
            }
            compared += n;
        }
    }
    assert!(
        compared > 1000 && differing_beta > 100,
        "{compared} vertices compared, {differing_beta} with other β"
    );
}
