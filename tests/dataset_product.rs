//! The dataset as a product (issue #4), through the `opticks` binary: relighting, adding a light,
//! refining and merging are exact laws, so each result must match a fresh trace of the same
//! thing — in its mean, and in its noise (relative MSE at the level two independent traces
//! show between themselves, measured in the same test).

mod common;

use common::*;
use opticks_io::compare::compare;
use opticks_io::image_file::read_exr_rgb;
use std::path::Path;
use std::process::{Command, Output};

fn opticks(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_opticks")).args(args).current_dir(dir).output().expect("runs opticks")
}

fn ok(args: &[&str], dir: &Path) -> String {
    let out = opticks(args, dir);
    let (so, se) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "opticks {args:?} failed:\nstdout: {so}\nstderr: {se}");
    format!("{so}{se}")
}

fn fails(args: &[&str], dir: &Path) -> String {
    let out = opticks(args, dir);
    let se = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "expected {args:?} to fail; stderr: {se}");
    assert!(se.starts_with("error: ") && !se.contains("panicked"), "{se}");
    se
}

fn image(dir: &Path, name: &str) -> Vec<f32> {
    read_exr_rgb(&dir.join(name)).unwrap().2
}

/// The Cornell box with a second light: a point light in front of the large box.
fn two_light_scene(dir: &Path) -> String {
    let xml = std::fs::read_to_string(scene_file("cornell", "scene.xml")).unwrap();
    let meshes = scene_file("cornell", "meshes");
    let xml = xml.replace("meshes/", &format!("{}/", meshes.display())).replace(
        "</scene>",
        "<emitter type=\"point\" id=\"bulb\"><point name=\"position\" x=\"0.3\" y=\"-0.2\" z=\"0.6\"/>\
         <rgb name=\"intensity\" value=\"0.2, 0.3, 0.5\"/></emitter>\n</scene>",
    );
    let path = dir.join("two.xml");
    std::fs::write(&path, xml).unwrap();
    path.to_str().unwrap().to_string()
}

/// Asserts that `image` (rendered in `d`) is a render of `scene` traced with `paths` paths: its
/// relMSE against a fresh trace is within 1.3× what two fresh traces (seeds 90, 91) show between
/// themselves, and its mean within 1 %.
fn assert_like_fresh_traces(d: &Path, image_name: &str, scene: &str, paths: &str, what: &str) {
    for seed in ["90", "91"] {
        ok(&["trace", scene, "--paths", paths, "-o", &format!("fresh{seed}.opds"), "--seed", seed], d);
        ok(&["render", &format!("fresh{seed}.opds"), "-o", &format!("fresh{seed}.exr")], d);
    }
    let noise = compare(&image(d, "fresh90.exr"), &image(d, "fresh91.exr")).relmse;
    let got = compare(&image(d, image_name), &image(d, "fresh90.exr"));
    eprintln!(
        "two fresh traces: relMSE {noise:.3e}; {what} vs a fresh trace: {:.3e}, mean ratios {:?}",
        got.relmse, got.mean_ratio
    );
    assert!(got.relmse < 1.3 * noise, "{what}: {} vs {noise}", got.relmse);
    for r in got.mean_ratio {
        assert!((r - 1.0).abs() < 0.01, "{what}: mean ratio {r}");
    }
}

#[test]
fn relighting_is_exact_and_switching_off_matches_a_trace_without_the_light() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let two = two_light_scene(d);
    let cornell = scene_file("cornell", "scene.xml");
    let cornell = cornell.to_str().unwrap();
    ok(&["trace", &two, "--paths", "1500000", "-o", "two.opds", "--seed", "1"], d);
    let info = ok(&["info", "two.opds"], d);
    // The ceiling light's share N_k of the two-light trace (table row "0  light  N_k ...").
    let n_ceiling: u64 = info
        .lines()
        .find(|l| l.trim_start().starts_with("0 ") && l.contains("light"))
        .and_then(|l| l.split_whitespace().nth(2))
        .and_then(|n| n.parse().ok())
        .expect("info lists light 0 with its N_k");
    let n = n_ceiling.to_string();
    ok(&["trace", cornell, "--paths", &n, "-o", "a.opds", "--seed", "2"], d);
    ok(&["trace", cornell, "--paths", &n, "-o", "b.opds", "--seed", "3"], d);
    ok(&["render", "a.opds", "-o", "a.exr"], d);
    ok(&["render", "b.opds", "-o", "b.exr"], d);
    // Switch the bulb off (by name) — and by index, the same thing.
    ok(&["render", "two.opds", "-o", "off.exr", "--light", "bulb=0"], d);
    ok(&["render", "two.opds", "-o", "off1.exr", "--light", "1=0"], d);
    assert!(image(d, "off.exr") == image(d, "off1.exr"));
    let noise = compare(&image(d, "a.exr"), &image(d, "b.exr")).relmse;
    let relit = compare(&image(d, "off.exr"), &image(d, "a.exr"));
    eprintln!(
        "two independent traces: relMSE {noise:.3e}; relit vs trace without the light: {:.3e}",
        relit.relmse
    );
    assert!(relit.relmse < 1.25 * noise && relit.relmse > 0.8 * noise, "{} vs {noise}", relit.relmse);
    for r in relit.mean_ratio {
        assert!((r - 1.0).abs() < 0.01, "mean ratio {r}");
    }

    // Scaling a light scales its share exactly: I(s) = I(0) + s·(I(1) − I(0)), per channel.
    ok(&["render", "two.opds", "-o", "one.exr"], d);
    ok(&["render", "two.opds", "-o", "tinted.exr", "--light", "bulb=3,0.5,0", "--light", "light=2"], d);
    ok(&["render", "two.opds", "-o", "ceiling2.exr", "--light", "bulb=0", "--light", "light=2"], d);
    let (off, one, tinted, ceiling2) =
        (image(d, "off.exr"), image(d, "one.exr"), image(d, "tinted.exr"), image(d, "ceiling2.exr"));
    let s = [3.0f32, 0.5, 0.0];
    let mut worst = 0.0f32;
    for i in 0..off.len() {
        let bulb = one[i] - off[i];
        let expected = ceiling2[i] + s[i % 3] * bulb;
        worst = worst.max((tinted[i] - expected).abs() / (expected.abs() + 1e-3));
    }
    assert!(worst < 1e-4, "relighting is not linear: worst relative deviation {worst}");
    assert!(one.iter().zip(&off).map(|(a, b)| a - b).sum::<f32>() > 0.0, "the bulb adds light");

    // A light the dataset does not know, or a moved light, is refused.
    let e = fails(&["render", "two.opds", "-o", "x.exr", "--light", "sun=2"], d);
    assert!(e.contains("sun") && e.contains("bulb"), "{e}");
    let moved = std::fs::read_to_string(&two).unwrap().replace("x=\"0.3\"", "x=\"0.2\"");
    std::fs::write(d.join("moved.xml"), moved).unwrap();
    let e = fails(&["render", "two.opds", "--scene", "moved.xml", "-o", "x.exr"], d);
    assert!(e.contains("bulb") && e.contains("moved"), "{e}");
    // The scene file may change a light's power: that is relighting too.
    let brighter = std::fs::read_to_string(&two).unwrap().replace("0.2, 0.3, 0.5", "0.6, 0.9, 1.5");
    std::fs::write(d.join("brighter.xml"), brighter).unwrap();
    let note = ok(&["render", "two.opds", "--scene", "brighter.xml", "-o", "brighter.exr"], d);
    assert!(note.contains("power changed"), "{note}");
    ok(&["render", "two.opds", "-o", "bulb3.exr", "--light", "bulb=3"], d);
    let (b3, br) = (image(d, "bulb3.exr"), image(d, "brighter.exr"));
    assert!(b3.iter().zip(&br).all(|(a, b)| (a - b).abs() <= 1e-5 * a.abs().max(1e-3)));
}

#[test]
fn merge_and_refine_equal_one_trace_of_all_the_paths() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cornell = scene_file("cornell", "scene.xml");
    let cornell = cornell.to_str().unwrap();
    let n = "1000000";
    ok(&["trace", cornell, "--paths", n, "-o", "s1.opds", "--seed", "1"], d);
    ok(&["trace", cornell, "--paths", n, "-o", "s2.opds", "--seed", "2"], d);
    ok(&["trace", cornell, "--paths", "2000000", "-o", "all.opds", "--seed", "3"], d);
    ok(&["merge", "s1.opds", "s2.opds", "-o", "merged.opds"], d);
    ok(&["trace", cornell, "--paths", n, "-o", "refined.opds", "--seed", "4"], d);
    ok(&["refine", "refined.opds", "--paths", n], d);
    let info = ok(&["info", "refined.opds"], d);
    assert!(info.contains("2000000") && info.contains("stream 1"), "{info}");
    for f in ["s1", "merged", "all", "refined"] {
        ok(&["render", &format!("{f}.opds"), "-o", &format!("{f}.exr")], d);
    }
    let reference = reference("cornell");
    let err = |f: &str| compare(&image(d, &format!("{f}.exr")), &reference);
    let (single, merged, all, refined) = (err("s1"), err("merged"), err("all"), err("refined"));
    eprintln!(
        "relMSE vs reference: 1M {:.3e}, merged 2×1M {:.3e}, 2M {:.3e}, refined 1M+1M {:.3e}",
        single.relmse, merged.relmse, all.relmse, refined.relmse
    );
    for (name, c) in [("merged", &merged), ("refined", &refined)] {
        // Same noise as one trace of all the paths (seed-to-seed spread of relMSE is ~2-3% here).
        assert!((c.relmse / all.relmse - 1.0).abs() < 0.15, "{name}: {} vs {}", c.relmse, all.relmse);
        assert!(single.relmse / c.relmse > 1.6, "{name} must halve the error of 1M paths");
        for r in c.mean_ratio {
            assert!((r - 1.0).abs() < 0.01, "{name}: mean ratio {r}");
        }
    }
}

#[test]
fn add_light_equals_tracing_both_lights() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let two = two_light_scene(d);
    let cornell = scene_file("cornell", "scene.xml");
    // The dataset of the one-light scene, rendered against the two-light scene, lacks the bulb.
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "1000000", "-o", "grow.opds", "--seed", "5"], d);
    let e = fails(&["render", "grow.opds", "--scene", &two, "-o", "x.exr"], d);
    assert!(e.contains("bulb") && e.contains("add-light"), "{e}");
    ok(&["add-light", "grow.opds", "bulb", "--scene", &two, "--paths", "300000"], d);
    ok(&["render", "grow.opds", "--scene", &two, "-o", "grow.exr"], d);
    assert_like_fresh_traces(d, "grow.exr", &two, "1300000", "traced + added light");
    let e = fails(&["add-light", "grow.opds", "bulb", "--scene", &two], d);
    assert!(e.contains("already"), "{e}");
}

#[test]
fn bad_merges_are_refused_and_damage_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cornell = scene_file("cornell", "scene.xml");
    let furnace = scene_file("furnace", "scene.xml");
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "20000", "-o", "c1.opds", "--seed", "1"], d);
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "20000", "-o", "c1again.opds", "--seed", "1"], d);
    ok(&["trace", furnace.to_str().unwrap(), "--paths", "20000", "-o", "f.opds", "--seed", "2"], d);
    let e = fails(&["merge", "c1.opds", "f.opds", "-o", "m.opds"], d);
    assert!(e.contains("different scenes"), "{e}");
    let e = fails(&["merge", "c1.opds", "c1again.opds", "-o", "m.opds"], d);
    assert!(e.contains("seed 1") && e.contains("copies"), "{e}");
    let mut b = std::fs::read(d.join("c1again.opds")).unwrap();
    let n = b.len();
    b[n - 100] ^= 0x40;
    std::fs::write(d.join("flipped.opds"), &b).unwrap();
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "20000", "-o", "c2.opds", "--seed", "2"], d);
    std::fs::copy(d.join("c2.opds"), d.join("m.opds")).unwrap();
    let before = std::fs::read(d.join("m.opds")).unwrap();
    let e = fails(&["merge", "c2.opds", "flipped.opds", "-o", "m.opds"], d);
    assert!(e.contains("flipped.opds"), "{e}");
    assert!(std::fs::read(d.join("m.opds")).unwrap() == before, "a failed merge leaves the output as it was");
    let e = fails(&["merge", "c2.opds", "-o", "m2.opds"], d);
    assert!(e.contains("2") || e.contains("required"), "{e}");
}

#[test]
fn walkthrough_frames_come_from_one_dataset() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cornell = scene_file("cornell", "scene.xml");
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "200000", "-o", "w.opds"], d);
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
    assert!(e.contains("fraction"), "{e}");
    // Bad camera paths are clear errors naming the file.
    std::fs::write(d.join("bad.json"), "{\"keyframes\": [{\"time\": 0, \"eye\": [0,0]}]}").unwrap();
    let e = fails(&["walk", "w.opds", "--path", "bad.json", "-o", "f2"], d);
    assert!(e.contains("bad.json") && e.contains("line"), "{e}");
    let e = fails(&["walk", "w.opds", "--path", "missing.json", "-o", "f2"], d);
    assert!(e.contains("missing.json"), "{e}");
}

/// Runs opticks as if Ctrl-C were pressed once `paths` paths are traced; returns its stderr.
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

/// Header (without wall-clock times) and chunks: what must be identical between two runs.
fn contents(path: &Path) -> (opticks_core::dataset::DatasetHeader, Vec<opticks_core::dataset::Chunk>) {
    let (mut h, chunks) = opticks_io::dataset_file::read_all(path).unwrap();
    h.trace.passes.iter_mut().for_each(|p| p.seconds = 0.0);
    (h, chunks)
}

#[test]
fn an_interrupted_trace_or_refine_resumes_to_exactly_the_uninterrupted_dataset() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cornell = scene_file("cornell", "scene.xml");
    let cornell = cornell.to_str().unwrap();
    // More than one batch of blocks (64 × 4096 paths), so the interruption falls inside the plan;
    // a non-default strategy, which the resumed part and the refinement must keep using.
    let n = "300000";
    let trace = ["trace", cornell, "--paths", n, "--seed", "3", "--roulette", "fixed", "--rr-depth", "2"];
    ok(&[&trace[..], &["-o", "whole.opds"]].concat(), d);
    interrupted(&[&trace[..], &["-o", "cut.opds"]].concat(), d, 1);
    assert!(!d.join("cut.opds").exists());
    let info = ok(&["info", "cut.partial.opds"], d);
    assert!(info.contains("interrupted: 262144 of 300000 planned paths"), "{info}");
    ok(&["resume", "cut.partial.opds"], d);
    assert!(!d.join("cut.partial.opds").exists(), "the partial file is used up");
    assert!(contents(&d.join("cut.opds")) == contents(&d.join("whole.opds")), "resumed trace ≠ trace");
    let e = fails(&["resume", "cut.opds"], d);
    assert!(e.contains("nothing to resume"), "{e}");

    // Refine reuses the dataset's strategy; an interrupted refine leaves the dataset as it was.
    ok(&["refine", "whole.opds", "--paths", n], d);
    let info = ok(&["info", "whole.opds"], d);
    assert_eq!(info.matches("--roulette fixed --rr-depth 2").count(), 2, "{info}");
    let before = std::fs::read(d.join("cut.opds")).unwrap();
    interrupted(&["refine", "cut.opds", "--paths", n], d, 1);
    assert!(std::fs::read(d.join("cut.opds")).unwrap() == before, "the dataset is intact");
    ok(&["resume", "cut.partial.opds"], d);
    assert!(contents(&d.join("cut.opds")) == contents(&d.join("whole.opds")), "resumed refine ≠ refine");
}

#[cfg(unix)]
#[test]
fn ctrl_c_during_refine_or_add_light_leaves_the_dataset_intact() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let two = two_light_scene(d);
    let cornell = scene_file("cornell", "scene.xml");
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "10000", "-o", "data.opds"], d);
    let before = std::fs::read(d.join("data.opds")).unwrap();
    for args in [
        vec!["refine", "data.opds", "--paths", "2000000000"],
        vec!["add-light", "data.opds", "bulb", "--scene", &two, "--paths", "2000000000"],
    ] {
        let child = Command::new(env!("CARGO_BIN_EXE_opticks"))
            .args(&args)
            .current_dir(d)
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(1500));
        assert!(Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap().success());
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains("data.partial.opds"), "{args:?}: {err}");
        assert!(std::fs::read(d.join("data.opds")).unwrap() == before, "{args:?} changed the dataset");
        let partial = opticks_io::dataset_file::DatasetReader::open(&d.join("data.partial.opds")).unwrap();
        partial.verify().unwrap();
        assert!(partial.header().table.total_paths() >= 10000);
        std::fs::remove_file(d.join("data.partial.opds")).unwrap();
    }
    let mut left: Vec<_> = std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name()).collect();
    left.sort();
    assert_eq!(left, ["data.opds", "two.xml"], "no temporary file is left");
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

#[test]
fn a_surface_that_becomes_a_light_is_added_while_a_changed_material_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let green = "<ref id=\"green\"/>";
    let glow = edited_cornell(d, "glow.xml", |x| {
        assert!(x.contains(green));
        x.replace(
            green,
            &format!(
                "{green}<emitter type=\"area\"><rgb name=\"radiance\" value=\"0.3, 0.8, 0.3\"/></emitter>"
            ),
        )
    });
    let repainted =
        edited_cornell(d, "repainted.xml", |x| x.replace("0.570068, 0.0430135", "0.470068, 0.0430135"));
    let cornell = scene_file("cornell", "scene.xml");
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "400000", "-o", "grow.opds", "--seed", "5"], d);
    // Another reflectance: the stored paths were reflected differently — refused.
    let e = fails(&["add-light", "grow.opds", "green_wall", "--scene", &repainted], d);
    assert!(e.contains("different scene"), "{e}");
    // The green wall becomes a light: same triangles, same BSDFs — accepted.
    ok(&["add-light", "grow.opds", "green_wall", "--scene", &glow, "--paths", "200000"], d);
    ok(&["render", "grow.opds", "--scene", &glow, "-o", "grow.exr"], d);
    assert_like_fresh_traces(d, "grow.exr", &glow, "600000", "traced + added surface light");
}

#[test]
fn merge_unites_datasets_whose_lights_differ_and_refuses_a_light_that_moved() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let two = two_light_scene(d);
    let cornell = scene_file("cornell", "scene.xml");
    let cornell = cornell.to_str().unwrap();
    // Worker 1 traced the box; worker 2 too, and then added the bulb.
    ok(&["trace", cornell, "--paths", "300000", "-o", "w1.opds", "--seed", "1"], d);
    ok(&["trace", cornell, "--paths", "300000", "-o", "w2.opds", "--seed", "2"], d);
    ok(&["add-light", "w2.opds", "bulb", "--scene", &two, "--paths", "200000"], d);
    let out = ok(&["merge", "w1.opds", "w2.opds", "-o", "m.opds"], d);
    assert!(out.contains("800000 paths, 2 lights"), "{out}");
    let info = ok(&["info", "m.opds"], d);
    assert!(info.contains("600000") && info.contains("bulb"), "{info}");
    ok(&["render", "m.opds", "--scene", &two, "-o", "m.exr"], d);
    assert_like_fresh_traces(d, "m.exr", &two, "800000", "merged {box} + {box, bulb}");
    // The same name emitting from elsewhere is another light: refused.
    let moved = two.replace("two.xml", "moved.xml");
    std::fs::write(&moved, std::fs::read_to_string(&two).unwrap().replace("x=\"0.3\"", "x=\"-0.3\""))
        .unwrap();
    ok(&["trace", &moved, "--paths", "20000", "-o", "moved.opds", "--seed", "5"], d);
    let e = fails(&["merge", "m.opds", "moved.opds", "-o", "bad.opds"], d);
    assert!(e.contains("'bulb' differs in shape"), "{e}");
    assert!(!d.join("bad.opds").exists());
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
    let mut names: Vec<_> = std::fs::read_dir(d.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
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
