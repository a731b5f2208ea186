//! The dataset as a product (issue #4), through the `opticks` binary: one smoke test per verb
//! that makes or uses a dataset (render's relighting, refine, merge, add-light, resume, walk,
//! measure), each checking that the verb does its job and says so the command line's way.
//!
//! The laws themselves — relighting, merging, refining and adding a light are exact, so each
//! result estimates what a fresh trace of the same thing does; a preview from a subset of chunks
//! is renormalised; a resumed pass is bit for bit the uninterrupted one — are unit tests of the
//! core functions that implement them (`crates/core/src/dataset/`), and writing, interrupting
//! and resuming a dataset file is tested with the job that does it
//! (`crates/io/src/dataset_job/`). Small path counts: these tests check behaviour, not noise.

use crate::cli_run;
use opticks_testkit as common;

use cli_run::*;
use common::*;
use opticks_core::dataset::{Chunk, DatasetHeader};
use opticks_io::dataset_file::{DatasetReader, read_all};
use opticks_io::image_file::read_exr_rgb;
use std::path::Path;
use std::process::Command;

/// Runs opticks as if Ctrl-C were pressed once `paths` paths are traced (at the end of the
/// first batch of 64 blocks); returns its stderr.
fn interrupted(args: &[&str], dir: &Path, paths: u64) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_opticks"))
        .args(args)
        .current_dir(dir)
        .env("OPTICKS_INTERRUPT_AFTER_PATHS", paths.to_string())
        .output()
        .unwrap();
    let se = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success() && se.contains("interrupted") && se.contains("opticks resume"), "{se}");
    se
}

fn image(dir: &Path, name: &str) -> Vec<f32> {
    read_exr_rgb(&dir.join(name)).unwrap().2
}

/// Header (without wall-clock times) and chunks: what must be identical between two runs.
fn contents(path: &Path) -> (DatasetHeader, Vec<Chunk>) {
    let (mut h, chunks) = read_all(path).unwrap();
    h.trace.passes.iter_mut().for_each(|p| p.seconds = 0.0);
    (h, chunks)
}

/// N_k of light `name` in the light table `opticks info` prints.
fn paths_of(info: &str, name: &str) -> u64 {
    let row =
        info.lines().map(|l| l.split_whitespace().collect::<Vec<_>>()).find(|w| w.get(1) == Some(&name));
    row.and_then(|w| w.get(2)?.parse().ok()).unwrap_or_else(|| panic!("no light {name} in {info}"))
}

/// The flux arriving at the scene's surfaces, summed over all bounces: Σ β·Φ_k/N_k over the
/// stored reflection vertices — an unbiased estimate, as every sensor's is.
fn flux(dataset: &Path) -> [f64; 3] {
    let (header, chunks) = read_all(dataset).unwrap();
    let mut sum = [0.0; 3];
    for c in &chunks {
        let per_path = header.table.flux_per_path(c.light as usize).to_array();
        for s in c.samples.iter().filter(|s| !s.is_emission()) {
            (0..3).for_each(|k| sum[k] += (s.beta[k] * per_path[k]) as f64);
        }
    }
    sum
}

/// The Cornell box with `edit` applied to its scene file (mesh paths made absolute).
fn edited_cornell(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> String {
    let xml = std::fs::read_to_string(scene_file("cornell", "scene.xml")).unwrap();
    let meshes = scene_file("cornell", "meshes");
    let xml = edit(xml.replace("meshes/", &format!("{}/", meshes.display())));
    let path = dir.join(name);
    std::fs::write(&path, xml).unwrap();
    path.to_str().unwrap().to_string()
}

/// Point emitters for a Mitsuba scene file.
fn point_lights(lights: &[(&str, [f32; 3], &str)]) -> String {
    lights
        .iter()
        .map(|(id, [x, y, z], rgb)| {
            format!(
                "<emitter type=\"point\" id=\"{id}\"><point name=\"position\" x=\"{x}\" y=\"{y}\" z=\"{z}\"/>\
                 <rgb name=\"intensity\" value=\"{rgb}\"/></emitter>\n"
            )
        })
        .collect()
}

/// The Cornell box with a second light: a point light in front of the large box.
fn two_light_scene(dir: &Path) -> String {
    let bulb = point_lights(&[("bulb", [0.3, -0.2, 0.6], "0.2, 0.3, 0.5")]);
    edited_cornell(dir, "two.xml", |x| x.replace("</scene>", &format!("{bulb}</scene>")))
}

/// The Cornell box with 80 dim lamps besides its light: a plan of 82 blocks from 20 000 paths,
/// so a run stopped after its first batch of 64 blocks stops inside the plan.
fn many_light_scene(dir: &Path) -> String {
    let names: Vec<String> = (0..80).map(|i| format!("lamp{i}")).collect();
    let lamps: Vec<(&str, [f32; 3], &str)> = names
        .iter()
        .enumerate()
        .map(|(i, n)| {
            (n.as_str(), [i as f32 / 50.0 - 0.8, 0.5, (i % 7) as f32 / 10.0 - 0.3], "0.01, 0.01, 0.01")
        })
        .collect();
    let lamps = point_lights(&lamps);
    edited_cornell(dir, "lamps.xml", |x| x.replace("</scene>", &format!("{lamps}</scene>")))
}

/// `render --light`: relighting is exact — by name or index, per channel, linear — and the
/// scene file may change a power (with a note), not a light's shape; unknown and untraced lights
/// are refused in the command line's words.
#[test]
fn render_relights_exactly_and_refuses_lights_it_cannot_light() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let two = two_light_scene(d);
    ok(&["trace", &two, "--paths", "30000", "-o", "two.opds", "--seed", "1"], d);
    let render = |out: &str, lights: &[&str]| {
        let mut args = vec!["render", "two.opds", "-o", out, "--size", "64x64"];
        lights.iter().for_each(|l| args.extend(["--light", l]));
        ok(&args, d);
        image(d, out)
    };
    // Switch the bulb off by name, and by index: the same thing.
    let off = render("off.exr", &["bulb=0"]);
    assert!(off == render("off1.exr", &["1=0"]));
    // Scaling a light scales its share exactly: I(s) = I(0) + s·(I(1) − I(0)), per channel.
    let one = render("one.exr", &[]);
    let tinted = render("tinted.exr", &["bulb=3,0.5,0", "light=2"]);
    let ceiling2 = render("ceiling2.exr", &["bulb=0", "light=2"]);
    let s = [3.0f32, 0.5, 0.0];
    let mut worst = 0.0f32;
    for i in 0..off.len() {
        let expected = ceiling2[i] + s[i % 3] * (one[i] - off[i]);
        worst = worst.max((tinted[i] - expected).abs() / (expected.abs() + 1e-3));
    }
    assert!(worst < 1e-4, "relighting is not linear: worst relative deviation {worst}");
    assert!(one.iter().zip(&off).map(|(a, b)| a - b).sum::<f32>() > 0.0, "the bulb adds light");
    // The scene file may change a light's power: that is relighting too.
    let brighter = std::fs::read_to_string(&two).unwrap().replace("0.2, 0.3, 0.5", "0.6, 0.9, 1.5");
    std::fs::write(d.join("brighter.xml"), brighter).unwrap();
    let note = ok(&["render", "two.opds", "--scene", "brighter.xml", "-o", "br.exr", "--size", "64x64"], d);
    assert!(note.contains("note: light 'bulb': power changed since the trace"), "{note}");
    let (b3, br) = (render("bulb3.exr", &["bulb=3"]), image(d, "br.exr"));
    assert!(b3.iter().zip(&br).all(|(a, b)| (a - b).abs() <= 1e-5 * a.abs().max(1e-3)));
    // A light the dataset does not know, a moved light, a light without paths: refused.
    let e = fails(&["render", "two.opds", "-o", "x.exr", "--light", "sun=2"], d);
    assert!(e.contains("no light 'sun'") && e.contains("bulb"), "{e}");
    let moved = std::fs::read_to_string(&two).unwrap().replace("x=\"0.3\"", "x=\"0.2\"");
    std::fs::write(d.join("moved.xml"), moved).unwrap();
    let e = fails(&["render", "two.opds", "--scene", "moved.xml", "-o", "x.exr"], d);
    assert!(
        e.contains("light 'bulb' has moved or changed shape since the trace: its samples no longer apply (re-trace the scene)"),
        "{e}"
    );
    let cornell = scene_file("cornell", "scene.xml");
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "5000", "-o", "box.opds"], d);
    let e = fails(&["render", "box.opds", "--scene", &two, "-o", "x.exr"], d);
    assert!(
        e.contains(
            "light 'bulb' of the scene has no paths in the dataset: add it with `opticks add-light`, or \
             switch it off with --light 'bulb=0'"
        ),
        "{e}"
    );
    ok(&["render", "box.opds", "--scene", &two, "-o", "x.exr", "--light", "bulb=0", "--size", "8x8"], d);
}

/// `refine`: a pass from stream 1 of the dataset's seed, with the dataset's strategy, appended
/// after the dataset's own chunks; a scene that moved a light is refused.
#[test]
fn refine_appends_a_pass_from_a_fresh_stream_with_the_datasets_strategy() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let two = two_light_scene(d);
    let trace = ["trace", &two, "--paths", "20000", "--seed", "4", "--roulette", "fixed", "--rr-depth", "2"];
    ok(&[&trace[..], &["-o", "data.opds"]].concat(), d);
    let (_, before) = read_all(&d.join("data.opds")).unwrap();
    let out = ok(&["refine", "data.opds", "--paths", "10000", "-o", "refined.opds"], d);
    assert!(out.starts_with("refined data.opds: 20000 + 10000 paths = 30000 paths, "), "{out}");
    let info = ok(&["info", "refined.opds"], d);
    assert!(info.contains("seed 4, stream 1: 10000 paths") && info.contains("paths     30000"), "{info}");
    assert_eq!(info.matches("--roulette fixed --rr-depth 2").count(), 2, "{info}");
    let (header, chunks) = read_all(&d.join("refined.opds")).unwrap();
    assert_eq!(chunks[..before.len()], before[..], "the dataset's chunks come first, untouched");
    assert_eq!(header.table.total_paths(), 30000);
    // A strategy option overrides the last pass's; the default output replaces the dataset.
    ok(&["refine", "refined.opds", "--paths", "5000", "--selection", "priority"], d);
    let info = ok(&["info", "refined.opds"], d);
    assert!(
        info.contains("stream 2: 5000 paths")
            && info.contains("--rr-depth 2 --directions importance --selection priority"),
        "{info}"
    );
    let moved = std::fs::read_to_string(&two).unwrap().replace("x=\"0.3\"", "x=\"-0.3\"");
    std::fs::write(d.join("moved.xml"), moved).unwrap();
    let e = fails(&["refine", "data.opds", "--paths", "10", "--scene", "moved.xml"], d);
    assert!(
        e.contains("light 'bulb' has moved or changed shape since the trace: refine needs the same scene"),
        "{e}"
    );
}

/// `merge`: N_k summed, a light only one input has kept; other scenes, copied streams, damaged
/// inputs and moved lights are refused, and a refused merge leaves the output as it was.
#[test]
fn merge_unites_datasets_and_refuses_what_would_not_be_independent_samples() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let two = two_light_scene(d);
    let cornell = scene_file("cornell", "scene.xml");
    let (cornell, furnace) = (cornell.to_str().unwrap(), scene_file("furnace", "scene.xml"));
    // Worker 1 traced the box; worker 2 too, and then added the bulb.
    ok(&["trace", cornell, "--paths", "20000", "-o", "w1.opds", "--seed", "1"], d);
    ok(&["trace", cornell, "--paths", "20000", "-o", "w2.opds", "--seed", "2"], d);
    ok(&["add-light", "w2.opds", "bulb", "--scene", &two, "--paths", "10000"], d);
    let out = ok(&["merge", "w1.opds", "w2.opds", "-o", "m.opds"], d);
    assert!(out.starts_with("merged 2 datasets: 50000 paths, 2 lights, "), "{out}");
    let info = ok(&["info", "m.opds"], d);
    assert_eq!((paths_of(&info, "light"), paths_of(&info, "bulb")), (40000, 10000), "{info}");
    let ((_, w1), (_, w2), (_, m)) = (
        read_all(&d.join("w1.opds")).unwrap(),
        read_all(&d.join("w2.opds")).unwrap(),
        read_all(&d.join("m.opds")).unwrap(),
    );
    assert!(m == [w1, w2].concat(), "every input's chunks, in input order, under the merged lights");
    ok(&["render", "m.opds", "--scene", &two, "-o", "m.exr", "--size", "8x8"], d);

    ok(&["trace", cornell, "--paths", "5000", "-o", "c1again.opds", "--seed", "1"], d);
    ok(&["trace", furnace.to_str().unwrap(), "--paths", "5000", "-o", "f.opds", "--seed", "2"], d);
    let e = fails(&["merge", "w1.opds", "f.opds", "-o", "x.opds"], d);
    assert!(e.contains("w1.opds and f.opds were traced from different scenes: mesh '"), "{e}");
    assert!(e.contains("(geometry fingerprints"), "{e}");
    let e = fails(&["merge", "w1.opds", "c1again.opds", "-o", "x.opds"], d);
    assert!(
        e.contains(
            "c1again.opds repeats the random stream (seed 1, stream 0) of an earlier input: its paths are \
             copies, not independent samples (trace workers with different --seed)"
        ),
        "{e}"
    );
    let moved = std::fs::read_to_string(&two).unwrap().replace("x=\"0.3\"", "x=\"-0.3\"");
    std::fs::write(d.join("moved.xml"), moved).unwrap();
    ok(&["trace", "moved.xml", "--paths", "5000", "-o", "moved.opds", "--seed", "5"], d);
    let e = fails(&["merge", "m.opds", "moved.opds", "-o", "x.opds"], d);
    assert!(e.contains("cannot merge moved.opds into m.opds: light 'bulb' differs in shape"), "{e}");
    assert!(!d.join("x.opds").exists());
    // A damaged input is reported by name; the output is left as it was.
    let mut b = std::fs::read(d.join("c1again.opds")).unwrap();
    let n = b.len();
    b[n - 100] ^= 0x40;
    std::fs::write(d.join("flipped.opds"), &b).unwrap();
    let before = std::fs::read(d.join("m.opds")).unwrap();
    let e = fails(&["merge", "w2.opds", "flipped.opds", "-o", "m.opds", "--overwrite"], d);
    assert!(e.contains("flipped.opds"), "{e}");
    assert!(std::fs::read(d.join("m.opds")).unwrap() == before, "a failed merge leaves the output as it was");
    let e = fails(&["merge", "w1.opds", "-o", "m2.opds"], d);
    assert!(e.contains("2") || e.contains("required"), "{e}");
}

/// `add-light`: only the new light is traced, the old chunks kept; a surface that becomes a
/// light is added (same geometry), a repainted one refused; a light already there is refused.
#[test]
fn add_light_traces_only_the_new_light_and_refuses_what_it_cannot_add() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let two = two_light_scene(d);
    let cornell = scene_file("cornell", "scene.xml");
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "20000", "-o", "grow.opds", "--seed", "5"], d);
    let (_, before) = read_all(&d.join("grow.opds")).unwrap();
    let out = ok(&["add-light", "grow.opds", "bulb", "--scene", &two, "--paths", "9000"], d);
    assert!(
        out.starts_with("added light 'bulb' with 9000 paths (") && out.contains("→ grow.opds (2 lights, "),
        "{out}"
    );
    let (header, chunks) = read_all(&d.join("grow.opds")).unwrap();
    assert_eq!(chunks[..before.len()], before[..]);
    assert!(chunks[before.len()..].iter().all(|c| c.light == 1) && header.table.lights[1].paths == 9000);
    ok(&["render", "grow.opds", "--scene", &two, "-o", "grow.exr", "--size", "8x8"], d);
    // The dataset now belongs to the scene with the bulb: a plain render lights it, no --scene.
    let plain = opticks(&["render", "grow.opds", "-o", "plain.exr", "--size", "8x8"], d);
    let err = String::from_utf8_lossy(&plain.stderr);
    assert!(plain.status.success() && !err.contains("bulb"), "{err}");
    assert_eq!(read_exr_rgb(&d.join("plain.exr")).unwrap(), read_exr_rgb(&d.join("grow.exr")).unwrap());
    let info = ok(&["info", "grow.opds"], d);
    let two_name = Path::new(&two).file_name().unwrap().to_str().unwrap();
    assert!(info.lines().nth(1).unwrap().contains(two_name), "{info}");
    let e = fails(&["add-light", "grow.opds", "bulb", "--scene", &two], d);
    assert!(e.contains("light 'bulb' is already in grow.opds: use `opticks refine` for more paths"), "{e}");
    let e = fails(&["add-light", "grow.opds", "sun", "--scene", &two], d);
    assert!(e.contains("the scene has no light 'sun' (its lights: light, bulb)"), "{e}");

    // The green wall becomes a light: same triangles, same BSDFs — accepted, with its fair
    // share of paths by default. Another reflectance: the stored paths were reflected
    // differently — refused.
    let green = "<ref id=\"green\"/>";
    let glow = edited_cornell(d, "glow.xml", |x| {
        let emitter = "<emitter type=\"area\"><rgb name=\"radiance\" value=\"0.3, 0.8, 0.3\"/></emitter>";
        x.replace(green, &format!("{green}{emitter}"))
    });
    let repainted =
        edited_cornell(d, "repainted.xml", |x| x.replace("0.570068, 0.0430135", "0.470068, 0.0430135"));
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "20000", "-o", "box.opds", "--seed", "5"], d);
    let e = fails(&["add-light", "box.opds", "green_wall", "--scene", &repainted], d);
    assert!(e.contains("box.opds was traced from a different scene than"), "{e}");
    let out = ok(&["add-light", "box.opds", "green_wall", "--scene", &glow, "-o", "glow.opds"], d);
    let paths: u64 = out.split_whitespace().nth(4).unwrap().parse().unwrap();
    let glow_table = read_all(&d.join("glow.opds")).unwrap().0.table;
    assert_eq!(glow_table.lights[1].paths, paths);
    let (phi_new, phi_old) =
        (glow_table.lights[1].power.element_sum(), glow_table.lights[0].power.element_sum());
    assert!((paths as f32 / (20000.0 * phi_new / phi_old) - 1.0).abs() < 1e-3, "fair share: {out}");
    ok(&["render", "glow.opds", "--scene", &glow, "-o", "glow.exr", "--size", "8x8"], d);
    // The box traced, plus the glowing wall added, estimates what a trace of both lights does
    // (within 3 %: over four standard errors at these path counts).
    let total = (20000 + paths).to_string();
    ok(&["trace", &glow, "--paths", &total, "-o", "fresh.opds", "--seed", "6"], d);
    let (added, fresh) = (flux(&d.join("glow.opds")), flux(&d.join("fresh.opds")));
    eprintln!("flux of traced + added surface light {added:?}, of a fresh trace {fresh:?}");
    for c in 0..3 {
        assert!(
            (added[c] / fresh[c] - 1.0).abs() < 0.03,
            "traced + added surface light: {added:?} vs {fresh:?}"
        );
    }
}

/// `resume`: an interrupted trace or refine, finished from its `NAME.partial.opds`, is bit for
/// bit the uninterrupted dataset (a non-default strategy kept throughout); the interrupted
/// refine left its dataset as it was, and a complete dataset has nothing to resume.
#[test]
fn resume_finishes_an_interrupted_trace_or_refine_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lamps = many_light_scene(d);
    let trace =
        ["trace", &lamps, "--paths", "20000", "--seed", "3", "--roulette", "fixed", "--rr-depth", "2"];
    ok(&[&trace[..], &["-o", "whole.opds"]].concat(), d);
    interrupted(&[&trace[..], &["-o", "cut.opds"]].concat(), d, 1);
    assert!(!d.join("cut.opds").exists());
    let partial = DatasetReader::open(&d.join("cut.partial.opds")).unwrap();
    let pass = &partial.header().trace.passes[0];
    let (done, planned) = (pass.paths, pass.planned_paths());
    assert!(partial.chunk_count() == 64 && done < planned && planned == 20000, "{done} of {planned}");
    let info = ok(&["info", "cut.partial.opds"], d);
    assert!(
        info.contains(&format!(
            "interrupted: {done} of {planned} planned paths (`opticks resume` finishes it)"
        )),
        "{info}"
    );
    drop(partial);
    let out = ok(&["resume", "cut.partial.opds"], d);
    assert!(
        out.starts_with(&format!(
            "resumed cut.partial.opds: {done} + {} paths = {planned} planned (",
            planned - done
        )),
        "{out}"
    );
    assert!(!d.join("cut.partial.opds").exists(), "the partial file is used up");
    assert!(contents(&d.join("cut.opds")) == contents(&d.join("whole.opds")), "resumed trace ≠ trace");
    let e = fails(&["resume", "cut.opds"], d);
    assert!(e.contains("cut.opds: nothing to resume, its last trace pass is complete"), "{e}");

    // Refine reuses the dataset's strategy; an interrupted refine leaves the dataset as it was.
    ok(&["refine", "whole.opds", "--paths", "20000"], d);
    let before = std::fs::read(d.join("cut.opds")).unwrap();
    interrupted(&["refine", "cut.opds", "--paths", "20000"], d, 1);
    assert!(std::fs::read(d.join("cut.opds")).unwrap() == before, "the dataset is intact");
    ok(&["resume", "cut.partial.opds"], d);
    assert!(contents(&d.join("cut.opds")) == contents(&d.join("whole.opds")), "resumed refine ≠ refine");
    assert_eq!(files(d), ["cut.opds", "lamps.xml", "whole.opds"], "no temporary or partial file is left");
}

/// A trace killed outright keeps its work (issue 25's test for `panic = "abort"`; SIGKILL, the
/// out-of-memory killer and a power cut leave the same file). A test hook aborts the process
/// once its writer has handed N chunks to the system: no destructor runs, its temporary file
/// stays. The next run on the same target saves that file's whole blocks as the partial
/// dataset and stops, saying so; `resume` then finishes it bit for bit. A chunk cut short is
/// dropped; a run killed after its last block keeps all but that block, so that it resumes.
#[cfg(unix)]
#[test]
fn a_killed_trace_keeps_its_written_blocks() {
    use std::os::unix::process::ExitStatusExt;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cornell = scene_file("cornell", "scene.xml");
    let trace = ["trace", cornell.to_str().unwrap(), "--paths", "40000", "--seed", "3"];
    ok(&[&trace[..], &["-o", "whole.opds"]].concat(), d);
    let blocks = 40000u64.div_ceil(4096);
    // (chunks in the file when killed, bytes then cut off its end, paths saved)
    for (chunks, cut, saved) in
        [(4u64, 0u64, 4 * 4096u64), (4, 100, 3 * 4096), (blocks, 0, (blocks - 1) * 4096)]
    {
        let out = opticks_env(
            &[&trace[..], &["-o", "cut.opds"]].concat(),
            d,
            &[("OPTICKS_ABORT_AFTER_CHUNKS", &chunks.to_string())],
        );
        assert_eq!(out.status.signal(), Some(6), "aborted (SIGABRT): {out:?}");
        let stale: Vec<_> = files(d).into_iter().filter(|f| f.starts_with(".cut.opds.tmp-")).collect();
        assert_eq!(stale.len(), 1, "{stale:?}");
        let tmp = d.join(&stale[0]);
        if cut > 0 {
            let len = std::fs::metadata(&tmp).unwrap().len();
            std::fs::OpenOptions::new().write(true).open(&tmp).unwrap().set_len(len - cut).unwrap();
        }
        let e = fails(&[&trace[..], &["-o", "cut.opds"]].concat(), d);
        assert!(
            e.contains(&format!(
                "a run writing cut.opds was killed before it finished; the {saved} light paths it had written are \
                 saved in cut.partial.opds: finish them with `opticks resume cut.partial.opds`"
            )),
            "{e}"
        );
        assert!(!tmp.exists() && !d.join("cut.opds").exists());
        ok(&["resume", "cut.partial.opds"], d);
        assert!(contents(&d.join("cut.opds")) == contents(&d.join("whole.opds")), "resumed ≠ uninterrupted");
        assert_eq!(files(d), ["cut.opds", "whole.opds"], "no temporary or partial file is left");
        std::fs::remove_file(d.join("cut.opds")).unwrap();
    }
    // A resumption killed outright: its file starts with the partial dataset's chunks, so the
    // next resumption adds its new blocks to the partial file before it goes on.
    let killed = |chunks: &str, args: &[&str]| {
        let out = opticks_env(args, d, &[("OPTICKS_ABORT_AFTER_CHUNKS", chunks)]);
        assert_eq!(out.status.signal(), Some(6), "aborted (SIGABRT): {out:?}");
    };
    killed("3", &[&trace[..], &["-o", "cut.opds"]].concat());
    fails(&[&trace[..], &["-o", "cut.opds"]].concat(), d);
    killed("7", &["resume", "cut.partial.opds"]);
    let out = ok(&["resume", "cut.partial.opds"], d);
    assert!(
        out.contains(&format!(
            "an earlier resumption of cut.partial.opds was killed; the blocks it had written were added to it \
             ({} paths now)",
            7 * 4096
        )),
        "{out}"
    );
    assert!(out.contains(&format!("resumed cut.partial.opds: {} + ", 7 * 4096)), "{out}");
    assert!(
        contents(&d.join("cut.opds")) == contents(&d.join("whole.opds")),
        "resumed twice ≠ uninterrupted"
    );
    assert_eq!(files(d), ["cut.opds", "whole.opds"]);
    std::fs::remove_file(d.join("cut.opds")).unwrap();

    // A file with no whole chunk of the run holds nothing to save: removed, as before.
    let out =
        opticks_env(&[&trace[..], &["-o", "cut.opds"]].concat(), d, &[("OPTICKS_ABORT_AFTER_CHUNKS", "1")]);
    assert_eq!(out.status.signal(), Some(6));
    let stale = files(d).into_iter().find(|f| f.starts_with(".cut.opds.tmp-")).unwrap();
    let len = std::fs::metadata(d.join(&stale)).unwrap().len();
    std::fs::OpenOptions::new().write(true).open(d.join(&stale)).unwrap().set_len(len - 40).unwrap();
    let out = ok(&[&trace[..], &["-o", "cut.opds"]].concat(), d);
    assert!(out.contains(&stale) && out.contains("killed"), "{out}");
    assert!(contents(&d.join("cut.opds")) == contents(&d.join("whole.opds")));
    assert_eq!(files(d), ["cut.opds", "whole.opds"]);
}

/// `trace --time` (and `refine --time`, `resume --time`): a run with a time limit is complete by
/// definition (issue 26: a `.partial.opds` that `merge`, `refine` and `add-light` refuse and
/// `resume` would trace for ever was all `trace --paths 1e12 --time 1` left). When the time is
/// up the trace ends at a block boundary, and the dataset is exactly a trace planning the paths
/// it traced. An interrupted run is accepted as it is by `resume --finish-now`.
/// 300 000 paths are 74 blocks, more than the first batch of 64, and a millisecond is less than
/// any machine takes to trace that batch: the run is cut, after 0 or 64 blocks (after none, the
/// light has no path yet, and the run is saved to be resumed).
#[test]
fn a_time_limited_trace_is_complete_with_what_it_traced() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let trace = ["trace", "builtin:cornell", "--seed", "8"];
    let out = ok(&[&trace[..], &["--paths", "300000", "-o", "cut.opds", "--time", "0.001"]].concat(), d);
    if d.join("cut.partial.opds").exists() {
        assert!(out.contains("before every light had a path"), "{out}");
        ok(&["resume", "cut.partial.opds"], d);
    } else {
        let cut = DatasetReader::open(&d.join("cut.opds")).unwrap();
        let pass = &cut.header().trace.passes[0];
        assert!(pass.is_complete() && pass.paths == 64 * 4096, "{:?}", pass);
        let paths = pass.paths.to_string();
        ok(&[&trace[..], &["--paths", &paths, "-o", "planned.opds"]].concat(), d);
        assert!(contents(&d.join("cut.opds")) == contents(&d.join("planned.opds")), "cut ≠ planned");
    }
    // It can be refined (a partial dataset could not), with a time limit too.
    let out = ok(&["refine", "cut.opds", "--paths", "1e9", "--time", "0.001"], d);
    assert!(!d.join("cut.partial.opds").exists(), "{out}");
    DatasetReader::open(&d.join("cut.opds")).unwrap().verify().unwrap();

    // An interrupted run (another seed, to merge with the first), accepted as it is.
    let trace = ["trace", "builtin:cornell", "--seed", "9"];
    interrupted(&[&trace[..], &["--paths", "300000", "-o", "int.opds"]].concat(), d, 1);
    let partial = DatasetReader::open(&d.join("int.partial.opds")).unwrap();
    let done = partial.header().trace.passes[0].paths;
    drop(partial);
    let out = ok(&["resume", "int.partial.opds", "--finish-now"], d);
    assert!(out.starts_with(&format!("finished int.partial.opds as it is: {done} of the 300000")), "{out}");
    assert!(!d.join("int.partial.opds").exists());
    ok(&[&trace[..], &["--paths", &done.to_string(), "-o", "int-planned.opds"]].concat(), d);
    assert!(contents(&d.join("int.opds")) == contents(&d.join("int-planned.opds")), "finished ≠ planned");
    ok(&["merge", "int.opds", "cut.opds", "-o", "both.opds"], d);
    let e = fails(&["resume", "int.opds", "--finish-now"], d);
    assert!(e.contains("complete"), "{e}");

    for bad in ["0", "-1", "soon", "inf"] {
        let e = fails(&["trace", "builtin:cornell", "-o", "x.opds", &format!("--time={bad}")], d);
        assert!(e.contains("is not a positive number of seconds"), "{e}");
    }
}

/// Ctrl-C during `refine` or `add-light` (simulated; the real signal is tested on `trace` in
/// crates/cli/tests/it/cli.rs, through the same job) saves the completed paths as a valid
/// `data.partial.opds` and leaves the dataset intact, with no temporary file.
#[test]
fn an_interrupted_refine_or_add_light_leaves_the_dataset_intact() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lamps = many_light_scene(d);
    let two = two_light_scene(d);
    let cornell = scene_file("cornell", "scene.xml");
    ok(&["trace", &lamps, "--paths", "10000", "-o", "data.opds"], d);
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "10000", "-o", "box.opds"], d);
    for (data, args) in [
        ("data", vec!["refine", "data.opds", "--paths", "20000"]),
        ("box", vec!["add-light", "box.opds", "bulb", "--scene", &two, "--paths", "270000"]),
    ] {
        let before = std::fs::read(d.join(format!("{data}.opds"))).unwrap();
        let err = interrupted(&args, d, 1);
        assert!(
            err.contains(&format!("{data}.opds was left as it was"))
                && err.contains(&format!("{data}.partial.opds")),
            "{args:?}: {err}"
        );
        assert!(
            std::fs::read(d.join(format!("{data}.opds"))).unwrap() == before,
            "{args:?} changed the dataset"
        );
        let partial = DatasetReader::open(&d.join(format!("{data}.partial.opds"))).unwrap();
        partial.verify().unwrap();
        assert!(partial.header().table.total_paths() > 10000);
        assert!(!partial.header().trace.passes.last().unwrap().is_complete());
        drop(partial);
        std::fs::remove_file(d.join(format!("{data}.partial.opds"))).unwrap();
    }
    assert_eq!(files(d), ["box.opds", "data.opds", "lamps.xml", "two.xml"], "no temporary file is left");
}

/// `walk`: frames from one dataset — frame 0 is what `render` gives from keyframe 0, the camera
/// moves; `--fraction` previews from a renormalised subset of chunks; bad input is refused.
#[test]
fn walkthrough_frames_come_from_one_dataset() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cornell = scene_file("cornell", "scene.xml");
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "100000", "-o", "w.opds"], d);
    std::fs::write(
        d.join("cam.json"),
        r#"{"fps": 2, "size": [64, 48], "keyframes": [
            {"time": 0, "eye": [0, 0, 3.9], "target": [0, 0, 0], "fov": 40},
            {"time": 1, "eye": [0.6, 0.3, 3.0], "target": [0, -0.3, 0]},
            {"time": 1.5, "eye": [-0.5, -0.2, 2.5], "target": [0.2, -0.5, 0], "fov": 50}]}"#,
    )
    .unwrap();
    let out = ok(&["walk", "w.opds", "--path", "cam.json", "-o", "frames", "--format", "exr"], d);
    assert!(out.contains("per frame") && out.contains("the trace took"), "{out}");
    let frames: Vec<_> = std::fs::read_dir(d.join("frames")).unwrap().filter_map(|e| e.ok()).collect();
    assert_eq!(frames.iter().filter(|e| e.file_name().to_string_lossy().ends_with(".exr")).count(), 4);
    // Frame 0 is keyframe 0: the same image `render` gives from that camera.
    ok(
        &[
            "render", "w.opds", "-o", "k0.exr", "--eye", "0,0,3.9", "--target", "0,0,0", "--fov", "40",
            "--size", "64x48",
        ],
        d,
    );
    let (a, b) = (image(d, "frames/frame_00000.exr"), image(d, "k0.exr"));
    assert!(a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= 1e-4 * x.abs().max(1e-3)));
    let last = image(d, "frames/frame_00003.exr");
    assert!(last != a, "the camera moved");
    // A preview from a quarter of the chunks: renormalised, so the same image up to noise.
    ok(
        &["walk", "w.opds", "--path", "cam.json", "-o", "preview", "--format", "exr", "--fraction", "0.25"],
        d,
    );
    let preview = image(d, "preview/frame_00000.exr");
    let (m_full, m_preview) = (a.iter().sum::<f32>(), preview.iter().sum::<f32>());
    assert!(preview != a && (m_preview / m_full - 1.0).abs() < 0.05, "{m_preview} vs {m_full}");
    let e = fails(&["walk", "w.opds", "--path", "cam.json", "-o", "f3", "--fraction", "0"], d);
    assert!(e.contains("the fraction 0 must be in (0, 1]"), "{e}");
    // Bad camera paths are clear errors naming the file.
    std::fs::write(d.join("bad.json"), "{\"keyframes\": [{\"time\": 0, \"eye\": [0,0]}]}").unwrap();
    let e = fails(&["walk", "w.opds", "--path", "bad.json", "-o", "f2"], d);
    assert!(e.contains("bad.json") && e.contains("line"), "{e}");
    let e = fails(&["walk", "w.opds", "--path", "missing.json", "-o", "f2"], d);
    assert!(e.contains("missing.json"), "{e}");
}

#[cfg(unix)]
#[test]
fn walk_hands_ffmpeg_exactly_this_runs_frames_and_moves_the_video_into_place() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A fake ffmpeg first on the PATH: it logs its arguments and writes its output file.
    let bin = d.join("bin");
    std::fs::create_dir(&bin).unwrap();
    let fake = bin.join("ffmpeg");
    std::fs::write(
        &fake,
        "#!/bin/sh\n[ \"$1\" = -version ] && exit 0\necho \"$@\" >> \"$FAKE_FFMPEG_LOG\"\n\
         for last; do :; done\necho video > \"$last\"\n",
    )
    .unwrap();
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let walk = |format: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_opticks"))
            .args(["walk", "w.opds", "--path", "cam.json", "-o", "frames", "--format", format])
            .current_dir(d)
            .env("PATH", &path)
            .env("FAKE_FFMPEG_LOG", d.join("ffmpeg.log"))
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let cornell = scene_file("cornell", "scene.xml");
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "20000", "-o", "w.opds"], d);
    std::fs::write(
        d.join("cam.json"),
        r#"{"fps": 2, "size": [32, 24], "keyframes": [
            {"time": 0, "eye": [0, 0, 3.9], "target": [0, 0, 0]},
            {"time": 1.5, "eye": [0.6, 0.3, 3.0], "target": [0, -0.3, 0]}]}"#,
    )
    .unwrap();
    std::fs::create_dir(d.join("frames")).unwrap();
    std::fs::write(d.join("frames/frame_00009.png"), b"stale frame of an earlier run").unwrap();
    let out = walk("png");
    assert!(out.contains("video →"), "{out}");
    let log = std::fs::read_to_string(d.join("ffmpeg.log")).unwrap();
    assert!(log.contains("-start_number 0") && log.contains("-frames:v 4"), "{log}");
    assert_eq!(std::fs::read_to_string(d.join("frames/walk.mp4")).unwrap(), "video\n");
    let names = files(&d.join("frames"));
    let expected = [
        "frame_00000.png",
        "frame_00001.png",
        "frame_00002.png",
        "frame_00003.png",
        "frame_00009.png",
        "walk.mp4",
    ];
    assert_eq!(names, expected, "no temporary video is left");
    let out = walk("exr");
    assert!(out.contains("no video"), "{out}");
    assert_eq!(
        std::fs::read_to_string(d.join("ffmpeg.log")).unwrap(),
        log,
        "ffmpeg is not run for EXR frames"
    );
    // A bad keyframe is refused before the output folder exists.
    std::fs::write(d.join("same.json"), r#"{"keyframes": [{"time": 0, "eye": [1,1,1], "target": [1,1,1]}]}"#)
        .unwrap();
    let e = fails(&["walk", "w.opds", "--path", "same.json", "-o", "never"], d);
    assert!(
        e.contains("same.json") && e.contains("keyframe 0") && e.matches("same point").count() == 1,
        "{e}"
    );
    assert!(!d.join("never").exists());
}

/// `measure` reads the dataset the way `render` does: relit exactly (the ceiling light at twice
/// its power, the bulb off, reads twice the ceiling light's share) and against its scene.
#[test]
fn measure_relights_like_render() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let two = two_light_scene(d);
    ok(&["trace", &two, "--paths", "20000", "-o", "two.opds", "--seed", "2"], d);
    let measure = |csv: &str, lights: &[&str]| -> Vec<f64> {
        let mut args = vec!["measure", "two.opds", "--surface", "red_wall", "--cells", "3x2", "-o", csv];
        lights.iter().for_each(|l| args.extend(["--light", l]));
        let out = ok(&args, d);
        assert!(out.contains("3x2 cells on") && out.contains(csv), "{out}");
        let text = std::fs::read_to_string(d.join(csv)).unwrap();
        assert_eq!(text.lines().count(), 7, "{text}");
        text.lines()
            .skip(1)
            .flat_map(|l| l.split(',').skip(5).map(|x| x.parse::<f64>().unwrap()).collect::<Vec<_>>())
            .collect()
    };
    let (all, ceiling, doubled) = (
        measure("all.csv", &[]),
        measure("ceiling.csv", &["bulb=0"]),
        measure("doubled.csv", &["bulb=0", "light=2"]),
    );
    for i in 0..all.len() {
        assert!(
            (doubled[i] - 2.0 * ceiling[i]).abs() <= 1e-5 * doubled[i].abs().max(1e-9),
            "{i}: {} vs 2 × {}",
            doubled[i],
            ceiling[i]
        );
        assert!(all[i] > ceiling[i], "the bulb lights the red wall");
    }
    let e = fails(
        &[
            "measure",
            "two.opds",
            "--scene",
            scene_file("furnace", "scene.xml").to_str().unwrap(),
            "--surface",
            "x",
            "-o",
            "x.csv",
        ],
        d,
    );
    assert!(e.contains("two.opds was traced from a different scene than"), "{e}");
}
