//! `opticks info`: what a dataset holds, readably (or as JSON with `--json`), after verifying
//! every checksum in it. The scene is shown as the dataset records it — relative to the
//! dataset's own folder and absolute (`opticks_io::scene_ref`) — with which of them is found.

use crate::output;
use anyhow::Result;
use opticks_core::dataset::{Choice, DatasetHeader};
use opticks_io::dataset_file::DatasetReader;
use opticks_io::output_paths::check_input_file;
use opticks_io::scene_ref;
use serde_json::json;
use std::path::PathBuf;

/// Arguments of `opticks info`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Dataset file.
    dataset: PathBuf,
    /// Print one JSON object instead of the readable summary.
    #[arg(long)]
    json: bool,
}

/// Prints the summary.
pub fn run(a: Args) -> Result<()> {
    check_input_file(&a.dataset, "a dataset")?;
    let mut reader = DatasetReader::open(&a.dataset)?;
    // Samples are range-checked against the scene's triangles when the scene loads (as `render`
    // checks them); the checksums and values are checked in any case.
    let checked = match super::open_with_scene(&a.dataset, None, &Default::default()) {
        Ok(opened) => {
            let triangles = opened.scene.triangles.len();
            reader.check_triangles(triangles);
            format!("every sample checked against its scene's {triangles} triangles")
        }
        Err(e) => format!("samples not checked against the scene: {e:#}"),
    };
    reader.verify()?; // every chunk's checksum: `info` is also the integrity check
    if a.json {
        output::data(&as_json(&a, &reader, &checked).to_string());
    } else {
        for line in readable(&a, &reader, &checked) {
            output::data(&line);
        }
    }
    Ok(())
}

/// `--roulette energy --rr-depth 5 …`: the options that would repeat pass `i`.
fn strategy(h: &DatasetHeader, i: usize) -> String {
    let p = &h.trace.passes[i];
    format!(
        "--roulette {} --rr-depth {} --directions {} --selection {} --mis-records {}{}",
        p.roulette.name(),
        p.rr_depth,
        p.directions.name(),
        p.selection.name(),
        p.mis.map(|m| m.heuristic).name(),
        p.mis.map_or(String::new(), |m| format!(" (sampling signature {})", m.signature))
    )
}

/// What is to be said of pass `i` if it is unfinished: only the last one can be resumed.
fn state(h: &DatasetHeader, i: usize) -> Option<String> {
    let p = &h.trace.passes[i];
    match (p.is_complete(), i + 1 == h.trace.passes.len()) {
        (true, _) => None,
        (false, true) => Some(format!(
            "interrupted: {} of {} planned paths (`opticks resume` finishes it)",
            p.paths,
            p.planned_paths()
        )),
        (false, false) => Some(format!(
            "interrupted: {} of {} planned paths (passes were added after it, so it cannot be resumed)",
            p.paths,
            p.planned_paths()
        )),
    }
}

fn readable(a: &Args, reader: &DatasetReader, checked: &str) -> Vec<String> {
    let h = reader.header();
    let samples = reader.total_samples();
    let paths = h.table.total_paths();
    let mut out = vec![format!("dataset   {}", a.dataset.display())];
    for (i, line) in scene_ref::describe(&h.label, &a.dataset).into_iter().enumerate() {
        out.push(format!("{}{line}", if i == 0 { "scene     " } else { "          " }));
    }
    out.push(format!("checked   {checked}"));
    out.push(format!("geometry  {}", h.fingerprint.geometry_hex()));
    out.push(format!("lights    {}", h.fingerprint.lights_hex()));
    out.push(format!("objects   {}", objects_summary(&h.objects)));
    for (i, p) in h.trace.passes.iter().enumerate() {
        let state = state(h, i).map(|s| format!(" — {s}")).unwrap_or_default();
        out.push(format!(
            "pass      seed {}, stream {}: {} paths in {:.2} s; {}{state}",
            p.seed,
            p.stream,
            p.paths,
            p.seconds,
            strategy(h, i)
        ));
    }
    out.push(match opticks_core::dataset::mis_compatibility(h) {
        Ok(m) => format!(
            "mis       the bidirectional estimator can weight it ({} heuristic)",
            Some(m.heuristic).name()
        ),
        Err(e) => format!("mis       not usable by the bidirectional estimator: {e}"),
    });
    out.push(format!("paths     {paths}"));
    out.push(format!("samples   {samples} ({:.2} per path)", samples as f64 / paths.max(1) as f64));
    out.push(format!("chunks    {}", reader.chunk_count()));
    out.push(format!(
        "size      {} ({} bytes, {:.1} bytes/sample)",
        output::bytes(reader.file_len()),
        reader.file_len(),
        reader.file_len() as f64 / samples.max(1) as f64
    ));
    out.push(format!("{:>5}  {:<24} {:>14}  power Φ (W, RGB)", "light", "name", "paths N_k"));
    for (k, l) in h.table.lights.iter().enumerate() {
        out.push(format!(
            "{k:>5}  {:<24} {:>14}  {:.6} {:.6} {:.6}",
            l.name, l.paths, l.power.x, l.power.y, l.power.z
        ));
    }
    out
}

fn as_json(a: &Args, reader: &DatasetReader, checked: &str) -> serde_json::Value {
    let h = reader.header();
    let n = h.trace.passes.len();
    let scene = match scene_ref::parse(&h.label) {
        scene_ref::RecordedScene::Builtin(name) => json!({ "builtin": name }),
        scene_ref::RecordedScene::File { relative, absolute } => {
            json!({ "relative": relative, "absolute": absolute })
        }
        scene_ref::RecordedScene::Legacy(path) => json!({ "recorded": path }),
    };
    let found = scene_ref::resolve(&h.label, &a.dataset).ok();
    let passes: Vec<_> = h
        .trace
        .passes
        .iter()
        .enumerate()
        .map(|(i, p)| {
            json!({
                "seed": p.seed,
                "stream": p.stream,
                "paths": p.paths,
                "planned_paths": p.planned_paths(),
                "complete": p.is_complete(),
                "resumable": !p.is_complete() && i + 1 == n,
                "seconds": p.seconds,
                "roulette": p.roulette.name(),
                "rr_depth": p.rr_depth,
                "directions": p.directions.name(),
                "selection": p.selection.name(),
                "mis_records": p.mis.map(|m| m.heuristic).name(),
                "sampling_signature": p.mis.map(|m| m.signature),
            })
        })
        .collect();
    let lights: Vec<_> = h
        .table
        .lights
        .iter()
        .map(|l| json!({ "name": l.name, "paths": l.paths, "power_w": l.power.to_array() }))
        .collect();
    json!({
        "dataset": a.dataset,
        "checked": checked,
        "scene": scene,
        "scene_found": found,
        "geometry_fingerprint": h.fingerprint.geometry_hex(),
        "lights_fingerprint": h.fingerprint.lights_hex(),
        "objects": h.objects.iter().map(|o| json!({ "kind": o.kind.word(), "name": o.name })).collect::<Vec<_>>(),
        "passes": passes,
        "bidirectional": opticks_core::dataset::mis_compatibility(h).is_ok(),
        "paths": h.table.total_paths(),
        "samples": reader.total_samples(),
        "chunks": reader.chunk_count(),
        "bytes": reader.file_len(),
        "lights": lights,
    })
}

/// `12 meshes and 6 materials hashed (a refusal names which changed)`, or that an older
/// dataset records none.
fn objects_summary(objects: &[opticks_core::scene::ObjectHash]) -> String {
    use opticks_core::scene::ObjectKind;
    if objects.is_empty() {
        return "not recorded (dataset format < 4: a refusal cannot name which mesh or material changed)"
            .into();
    }
    let meshes = objects.iter().filter(|o| o.kind == ObjectKind::Mesh).count();
    let count = |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    format!(
        "{} and {} hashed (a refusal names which changed)",
        count(meshes, "mesh", "meshes"),
        count(objects.len() - meshes, "material", "materials")
    )
}
