//! The `opticks` binary end to end, in a temporary directory, as a user would run it.

use crate::cli_run;
use opticks_testkit as common;

use cli_run::*;
use common::*;
use opticks_io::dataset_file::{DatasetReader, read_all};
use opticks_io::image_file::read_exr_rgb;
use std::path::Path;

fn mean(rgb: &[f32]) -> [f64; 3] {
    let mut m = [0.0; 3];
    for p in rgb.chunks(3) {
        for c in 0..3 {
            m[c] += p[c] as f64;
        }
    }
    m.map(|x| x / (rgb.len() / 3) as f64)
}

fn assert_mean_close(rgb: &[f32], name: &str, tol: f64) {
    let (m, r) = (mean(rgb), mean(&reference(name)));
    for c in 0..3 {
        assert!((m[c] / r[c] - 1.0).abs() < tol, "channel {c}: mean {} vs reference {}", m[c], r[c]);
    }
}

#[test]
fn demo_writes_png_and_exr() {
    let dir = tempfile::tempdir().unwrap();
    let out = stdout(&["demo", "--paths", "300000"], dir.path());
    assert!(out.contains("opticks-demo/cornell.png") && out.contains("opticks-demo/cornell.exr"), "{out}");
    let folder = dir.path().join("opticks-demo");
    let png = image::ImageReader::open(folder.join("cornell.png")).unwrap().decode().unwrap();
    assert_eq!((png.width(), png.height()), (256, 256));
    let (w, h, rgb) = read_exr_rgb(&folder.join("cornell.exr")).unwrap();
    let mut left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    left.sort();
    assert_eq!(left, ["opticks-demo"], "the demo writes into a folder of its own");
    assert_eq!((w, h), (256, 256));
    // The demo is the reference Cornell box: its mean matches Mitsuba's within noise (3%).
    assert_mean_close(&rgb, "cornell", 0.03);
}

#[test]
fn trace_info_render_from_the_scene_camera_and_another() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_file("cornell", "scene.xml");
    let scene = scene.to_str().unwrap();
    stdout(&["trace", scene, "--paths", "500000", "-o", "c.opds", "--seed", "3"], dir.path());
    let info = stdout(&["info", "c.opds"], dir.path());
    for needle in ["500000", "light", "samples", "bytes/sample", "seed 3"] {
        assert!(info.contains(needle), "info lacks '{needle}':\n{info}");
    }
    stdout(&["render", "c.opds", "-o", "c.exr"], dir.path());
    let (w, h, rgb) = read_exr_rgb(&dir.path().join("c.exr")).unwrap();
    assert_eq!((w, h), (256, 256));
    assert_mean_close(&rgb, "cornell", 0.02);
    // The same dataset from elsewhere: no re-trace, another camera, another size.
    stdout(
        &[
            "render",
            "c.opds",
            "-o",
            "side.exr",
            "--eye",
            "0.5,0.3,2.5",
            "--target",
            "0,-0.3,0",
            "--size",
            "64x48",
            "--fov",
            "60",
        ],
        dir.path(),
    );
    let (w, h, side) = read_exr_rgb(&dir.path().join("side.exr")).unwrap();
    assert_eq!((w, h), (64, 48));
    assert!(mean(&side)[0] > 0.05, "the box is visible from the new viewpoint");
    stdout(&["render", "c.opds", "-o", "c.png", "--exposure", "1"], dir.path());
    assert!(dir.path().join("c.png").exists());
}

#[test]
fn a_seed_gives_the_same_dataset_whatever_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_file("cornell", "scene.xml");
    let scene = scene.to_str().unwrap();
    stdout(&["trace", scene, "--paths", "100000", "-o", "one.opds", "--threads", "1"], dir.path());
    stdout(&["trace", scene, "--paths", "100000", "-o", "two.opds", "--threads", "2"], dir.path());
    stdout(&["trace", scene, "--paths", "100000", "-o", "other.opds", "--seed", "1"], dir.path());
    // Everything but the passes' wall-clock times must be identical.
    let read = |f: &str| {
        let (mut h, chunks) = read_all(&dir.path().join(f)).unwrap();
        h.trace.passes.iter_mut().for_each(|p| p.seconds = 0.0);
        (h, chunks)
    };
    assert!(read("one.opds") == read("two.opds"), "thread count changed the dataset");
    assert!(read("one.opds").1 != read("other.opds").1, "the seed must matter");
}

#[test]
fn bad_scenes_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let write = |name: &str, text: &str| std::fs::write(d.join(name), text).unwrap();
    write("malformed.xml", "<scene version=\"3.0.0\">\n  <shape type=\"obj\">\n</scene>\n");
    let e = fails(&["trace", "malformed.xml", "--paths", "10", "-o", "x.opds"], d);
    assert!(e.contains("malformed.xml") && e.contains(":3"), "{e}");
    write(
        "missing.xml",
        "<scene version=\"3.0.0\">\n<shape type=\"obj\">\n<string name=\"filename\" value=\"nowhere.obj\"/>\n</shape>\n</scene>\n",
    );
    let e = fails(&["trace", "missing.xml", "--paths", "10", "-o", "x.opds"], d);
    assert!(e.contains("nowhere.obj") && e.contains("missing.xml"), "{e}");
    std::fs::copy(scene_file("cornell", "meshes/light.obj"), d.join("light.obj")).unwrap();
    write(
        "nan.xml",
        "<scene version=\"3.0.0\">\n<shape type=\"obj\">\n<string name=\"filename\" value=\"light.obj\"/>\n\
         <transform name=\"to_world\"><translate x=\"nan\" y=\"0\" z=\"0\"/></transform>\n\
         <emitter type=\"area\"><rgb name=\"radiance\" value=\"1,1,1\"/></emitter>\n</shape>\n</scene>\n",
    );
    let e = fails(&["trace", "nan.xml", "--paths", "10", "-o", "x.opds"], d);
    assert!(e.contains("nan.xml") && e.contains(":4"), "{e}");
    let e = fails(&["trace", "no-such-scene.xml", "--paths", "10", "-o", "x.opds"], d);
    assert!(e.contains("no-such-scene.xml"), "{e}");
    assert!(!d.join("x.opds").exists(), "no dataset is left behind by a failed trace");
}

#[test]
fn bad_datasets_are_clear_errors_and_never_damage_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cornell = scene_file("cornell", "scene.xml");
    let furnace = scene_file("furnace", "scene.xml");
    stdout(&["trace", cornell.to_str().unwrap(), "--paths", "20000", "-o", "good.opds"], d);
    let good = std::fs::read(d.join("good.opds")).unwrap();

    std::fs::write(d.join("truncated.opds"), &good[..good.len() * 2 / 3]).unwrap();
    let e = fails(&["render", "truncated.opds", "-o", "t.exr"], d);
    assert!(e.contains("truncated.opds"), "{e}");

    let mut flipped = good.clone();
    let at = good.len() / 2;
    flipped[at] ^= 0x10;
    std::fs::write(d.join("flipped.opds"), &flipped).unwrap();
    let e = fails(&["render", "flipped.opds", "-o", "f.exr"], d);
    assert!(e.contains("flipped.opds"), "{e}");
    let e = fails(&["info", "flipped.opds"], d).to_lowercase();
    assert!(e.contains("flipped.opds") || e.contains("checksum"), "{e}");

    std::fs::write(d.join("foreign.opds"), b"P6\n1 1\n255\n\0\0\0").unwrap();
    let e = fails(&["info", "foreign.opds"], d);
    assert!(e.contains("foreign.opds"), "{e}");

    let e = fails(&["render", "good.opds", "--scene", furnace.to_str().unwrap(), "-o", "w.exr"], d);
    assert!(e.contains("different scene"), "{e}");
    assert!(!d.join("w.exr").exists() && !d.join("t.exr").exists() && !d.join("f.exr").exists());

    // A failing trace over an existing dataset leaves it intact.
    let e = fails(&["trace", "missing.xml", "--paths", "10", "-o", "good.opds", "--overwrite"], d);
    assert!(e.contains("missing.xml"), "{e}");
    assert!(std::fs::read(d.join("good.opds")).unwrap() == good);
}

#[test]
fn bad_arguments_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = opticks(&["render"], d);
    assert!(!out.status.success());
    let e = fails(&["demo", "--paths", "1000", "-o", "image.bmp"], d);
    assert!(e.contains("image.bmp"), "{e}");
    let e = fails(&["demo", "--paths", "1000", "--size", "0x5"], d);
    assert!(e.contains("0x5") || e.contains("size"), "{e}");
    for verb in [&["demo"][..], &["trace", "builtin:cornell", "-o", "x.opds"], &["bench"]] {
        let e = fails(&[verb, &["--paths", "0"]].concat(), d);
        assert!(e.contains("--paths") && e.contains('0'), "{e}");
    }
}

#[cfg(unix)]
#[test]
fn ctrl_c_saves_the_paths_traced_so_far_and_leaves_the_old_dataset() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cornell = scene_file("cornell", "scene.xml");
    let cornell = cornell.to_str().unwrap();
    stdout(&["trace", cornell, "--paths", "10000", "-o", "data.opds"], d);
    let before = std::fs::read(d.join("data.opds")).unwrap();
    let child = start(&["trace", cornell, "--paths", "2000000000", "-o", "data.opds", "--overwrite"], d);
    std::thread::sleep(std::time::Duration::from_millis(1500));
    signal(&child, "-INT");
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("interrupted") && err.contains("data.partial.opds"), "{err}");
    assert_eq!(out.status.code(), Some(130), "128 + SIGINT");
    assert!(std::fs::read(d.join("data.opds")).unwrap() == before, "the old dataset is intact");
    // The work done is a valid dataset of its own (every chunk complete, N_k = paths done).
    let partial = DatasetReader::open(&d.join("data.partial.opds")).unwrap();
    partial.verify().unwrap();
    let n = partial.header().table.total_paths();
    assert!(n > 0 && n < 2_000_000_000, "{n} paths saved");
    assert_eq!(partial.header().trace.passes[0].paths, n);
    let mut left: Vec<_> = std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name()).collect();
    left.sort();
    assert_eq!(left, ["data.opds", "data.partial.opds"], "no temporary file is left");
}

#[test]
fn demo_exports_its_scene_as_vrml_that_traces_like_the_builtin() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    stdout(&["demo", "--export-scene", "cornell.wrl"], d);
    let text = std::fs::read_to_string(d.join("cornell.wrl")).unwrap();
    assert!(
        text.starts_with("#VRML V2.0 utf8") && text.contains("PROTO PhysicalMaterial"),
        "{}",
        &text[..200]
    );
    stdout(&["trace", "cornell.wrl", "--paths", "300000", "-o", "w.opds"], d);
    stdout(&["render", "w.opds", "-o", "w.exr"], d);
    let (w, h, rgb) = read_exr_rgb(&d.join("w.exr")).unwrap();
    assert_eq!((w, h), (256, 256));
    assert_mean_close(&rgb, "cornell", 0.03);
}

/// Every verb `opticks --help` lists answers `--help` with its usage (exit 0); the list is read
/// from the top-level help, so a verb added later is covered too.
#[test]
fn every_verb_has_help() {
    let dir = tempfile::tempdir().unwrap();
    let top = stdout(&["--help"], dir.path());
    let verbs: Vec<&str> = top
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|&v| v != "help")
        .collect();
    for verb in ["demo", "trace", "render", "info", "refine", "merge", "walk", "bench", "measure"] {
        assert!(verbs.contains(&verb), "`opticks --help` lists {verbs:?}, not {verb}");
    }
    for verb in verbs {
        let help = stdout(&[verb, "--help"], dir.path());
        assert!(help.contains(&format!("Usage: opticks {verb}")), "{verb} --help:\n{help}");
    }
}

/// `opticks bench` reports trace and render speed and, with a reference, the image error; its
/// JSON line carries the same figures for scripts.
#[test]
fn bench_reports_speed_and_quality() {
    let dir = tempfile::tempdir().unwrap();
    let reference = scene_file("cornell", "reference.exr");
    let out = stdout(
        &["bench", "--paths", "65536", "--repeat", "1", "--reference", reference.to_str().unwrap()],
        dir.path(),
    );
    for field in ["M paths/s", "M samples/s", "samples/path", "relMSE", "efficiency"] {
        assert!(out.contains(field), "bench output lacks {field}:\n{out}");
    }
    let json: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
    assert_eq!(json["paths"], 65536);
    assert!(json["trace_s"].as_f64().unwrap() > 0.0 && json["render_s"].as_f64().unwrap() > 0.0);
    let samples = json["samples"].as_f64().unwrap();
    assert!((3.0..6.0).contains(&(samples / 65536.0)), "{samples} samples for 65536 paths");
    // 65536 paths: relMSE ≈ 4.0e-3 × 64 ≈ 0.26 against the Cornell reference (it scales as 1/N).
    let relmse = json["relmse"].as_f64().unwrap();
    assert!((0.15..0.4).contains(&relmse), "relMSE {relmse}");
    // Mean radiance of the reference (SCENE.md), to 3%: 65536 paths give ~0.5% noise per channel.
    for (got, want) in json["mean_rgb"].as_array().unwrap().iter().zip([0.244475, 0.141444, 0.060009]) {
        let got = got.as_f64().unwrap();
        assert!((got / want - 1.0).abs() < 0.03, "mean {got} vs reference {want}");
    }
}

/// Every dataset law and operation is a core function (ARCHITECTURE.md): the command line's
/// sources build no light record, pass or plan of their own, touch no N_k, and write no dataset
/// file themselves (`opticks_io::dataset_job` does).
#[test]
fn the_cli_holds_no_dataset_logic() {
    fn sources(dir: &Path, out: &mut Vec<(String, String)>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                sources(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push((path.display().to_string(), std::fs::read_to_string(&path).unwrap()));
            }
        }
    }
    let mut files = Vec::new();
    sources(&repo().join("crates/cli/src"), &mut files);
    assert!(files.len() > 10, "{} files", files.len());
    let dataset_logic = [
        "LightRecord",
        "TracePass",
        "LightPlan",
        "path_quotas",
        "merge_tables",
        "blocks_done",
        "trace_plan",
        "DatasetWriter",
        "geometry_v1",
        "light_shapes",
        "next_stream",
        "paths +=",
        ".planned.",
        "PassPlan {",
    ];
    for (file, text) in &files {
        for word in dataset_logic {
            assert!(
                !text.contains(word),
                "{file} uses `{word}`: dataset logic belongs in opticks_core::dataset"
            );
        }
    }
}

/// `render --estimator bidirectional`: a fixed number of camera paths per pixel, or passes until
/// `--time` is up, and the same option on `walk`; the mean matches Mitsuba's reference. The
/// light estimator is the default; `--time` is refused with it; a dataset without MIS records
/// (format 2) is refused with the fix.
#[test]
fn render_and_walk_with_the_bidirectional_estimator() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = scene_file("cornell", "scene.xml");
    stdout(&["trace", scene.to_str().unwrap(), "--paths", "200000", "-o", "c.opds"], d);
    let everywhere = ["--estimator", "bidirectional", "--coverage", "everywhere"];
    let out = stdout(&[&["render", "c.opds", "-o", "b.exr", "--spp", "4"][..], &everywhere[..]].concat(), d);
    assert!(out.contains("bidirectionally") && out.contains("4 camera paths per pixel in 100.0 %"), "{out}");
    let (w, h, rgb) = read_exr_rgb(&d.join("b.exr")).unwrap();
    assert_eq!((w, h), (256, 256));
    assert_mean_close(&rgb, "cornell", 0.02);
    // By default only pixels that may see something but a diffuse surface get camera paths: in
    // the diffuse Cornell box none, and the image is the light estimator's, bit for bit.
    let out = stdout(&["render", "c.opds", "-o", "n.exr", "--estimator", "bidirectional"], d);
    assert!(out.contains("in 0.0 % of the pixels"), "{out}");
    stdout(&["render", "c.opds", "-o", "l.exr"], d);
    assert_eq!(read_exr_rgb(&d.join("n.exr")).unwrap(), read_exr_rgb(&d.join("l.exr")).unwrap());
    let out = stdout(
        &[
            "render",
            "c.opds",
            "-o",
            "t.exr",
            "--estimator",
            "bidirectional",
            "--coverage",
            "everywhere",
            "--spp",
            "1",
            "--time",
            "1.5",
            "--size",
            "64x64",
        ],
        d,
    );
    assert!(out.contains("passes") && out.contains("estimated relative error"), "{out}");
    let e = fails(&["render", "c.opds", "-o", "x.exr", "--time", "1"], d);
    assert!(e.contains("--time applies to --estimator bidirectional"), "{e}");
    let v2 = repo().join("testdata/datasets/cornell-v2.opds");
    let e = fails(
        &[
            "render",
            v2.to_str().unwrap(),
            "--scene",
            scene.to_str().unwrap(),
            "-o",
            "x.exr",
            "--estimator",
            "bidirectional",
        ],
        d,
    );
    assert!(
        e.contains("without MIS records") && e.contains("opticks upgrade") && e.contains("--estimator light"),
        "{e}"
    );
    std::fs::write(
        d.join("path.json"),
        r#"{"fps": 2, "size": [32, 32], "keyframes": [{"time": 0, "eye": [0, 0, 3.9], "target": [0, 0, 0]}, {"time": 1, "eye": [0.3, 0, 3.9], "target": [0, 0, 0]}]}"#,
    )
    .unwrap();
    stdout(
        &[
            "walk",
            "c.opds",
            "--path",
            "path.json",
            "-o",
            "frames",
            "--format",
            "exr",
            "--estimator",
            "bidirectional",
            "--spp",
            "2",
        ],
        d,
    );
    assert!(d.join("frames/frame_00002.exr").exists());
}

#[test]
fn every_verb_that_loads_a_scene_takes_its_parameters() {
    let dir = tempfile::tempdir().unwrap();
    let xml = r#"<scene version="3.0.0">
  <default name="r" value="0.5"/>
  <sensor type="perspective"><float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film></sensor>
  <shape type="rectangle"><bsdf type="diffuse"><float name="reflectance" value="$r"/></bsdf></shape>
  <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="180"/><translate z="2"/></transform>
    <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>"#;
    std::fs::write(dir.path().join("s.xml"), xml).unwrap();
    let d = dir.path();
    stdout(&["trace", "s.xml", "--paths", "20000", "-o", "a.opds", "-D", "r=0.25"], d);
    // The dataset records its parameters (issue 26: they had to be repeated), and given ones
    // replace them.
    let e = fails(&["render", "a.opds", "-o", "a.exr", "-D", "r=0.5"], d);
    assert!(e.contains("different scene") && e.contains("-D parameters or --gltf-scene"), "{e}");
    for verb in [&["render", "a.opds", "-o", "a.exr"][..], &["refine", "a.opds", "--paths", "4096"]] {
        stdout(verb, d);
        stdout(&[verb, &["-Dr=0.25"]].concat(), d);
    }
    stdout(&["render", "a.opds", "-o", "a.exr"], d);
    stdout(&["bench", "s.xml", "--paths", "4096", "--repeat", "1", "-D", "r=0.75"], d);
    let e = fails(&["trace", "s.xml", "--paths", "10", "-o", "b.opds", "-D", "r"], d);
    assert!(e.contains("expected NAME=VALUE"), "{e}");
    let e = fails(&["trace", "builtin:cornell", "--paths", "10", "-o", "b.opds", "-D", "r=1"], d);
    assert!(e.contains("has none"), "{e}");
    let out = opticks(&["trace", "s.xml", "--paths", "10", "-o", "b.opds", "-D", "q=1"], d);
    assert!(String::from_utf8_lossy(&out.stderr).contains("never uses $q"));
}

#[test]
fn a_gltf_scene_and_camera_are_chosen_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let gltf = repo().join("testdata/gltf/textured.gltf");
    let gltf = gltf.to_str().unwrap();
    stdout(&["trace", gltf, "--paths", "20000", "-o", "night.opds", "--gltf-scene", "Night"], d);
    // Rendered against another scene ("Day"), it is another scene; against its own, fine —
    // which the dataset records (issue 26: it had to be repeated) — from the scene's camera or
    // from one chosen by name (768×512: aspect 1.5).
    let e = fails(&["render", "night.opds", "-o", "a.exr", "--gltf-scene", "Day"], d);
    assert!(e.contains("different scene") && e.contains("--gltf-scene"), "{e}");
    stdout(&["render", "night.opds", "-o", "a.exr"], d);
    stdout(&["render", "night.opds", "-o", "a.exr", "--gltf-scene", "Night"], d);
    stdout(&["render", "night.opds", "-o", "b.exr", "--gltf-scene", "Night", "--camera", "Detail.night"], d);
    let (w, h, rgb) = read_exr_rgb(&d.join("b.exr")).unwrap();
    assert_eq!((w, h), (768, 512));
    assert!(mean(&rgb)[0] > 0.0, "the lit floor is seen");
    let e =
        fails(&["render", "night.opds", "-o", "c.exr", "--gltf-scene", "Night", "--camera", "Overview"], d);
    assert!(e.contains("no camera of that name") && e.contains("\"Detail.night\""), "{e}");
    let e = fails(&["bench", "builtin:cornell", "--paths", "10", "--repeat", "1", "--camera", "a"], d);
    assert!(e.contains("one camera and one scene"), "{e}");
    let e = fails(&["trace", gltf, "--paths", "10", "-o", "x.opds", "--camera", "Overview"], d);
    assert!(e.contains("--camera chooses a view"), "{e}");
}

/// A Radiance room (testdata/radiance: a window, a ceiling panel, a table included by
/// `!xform`) traces and renders: from the overview camera the loader gives a `.rad` file, and
/// from a Radiance view file inside the room, where the lit walls show.
#[test]
fn radiance_room_traces_and_renders() {
    let dir = tempfile::tempdir().unwrap();
    let room = repo().join("testdata/radiance/room.rad");
    let view = repo().join("testdata/radiance/room.vf");
    stdout(&["trace", room.to_str().unwrap(), "--paths", "1000", "-o", "room.opds"], dir.path());
    stdout(&["render", "room.opds", "-o", "overview.exr"], dir.path());
    let (w, h, _) = read_exr_rgb(&dir.path().join("overview.exr")).unwrap();
    assert_eq!((w, h), (512, 512));
    stdout(&["trace", room.to_str().unwrap(), "--paths", "20000", "-o", "inside.opds"], dir.path());
    stdout(
        &["render", "inside.opds", "-o", "inside.exr", "--camera", view.to_str().unwrap(), "--size", "64x52"],
        dir.path(),
    );
    let (w, h, rgb) = read_exr_rgb(&dir.path().join("inside.exr")).unwrap();
    assert_eq!((w, h), (64, 52));
    let m = mean(&rgb);
    assert!(m.iter().all(|&c| c > 0.0 && c.is_finite()), "{m:?}");
}

/// A Radiance room split over three files — materials, geometry (using them), a sky — given as
/// `trace mats.rad room.rad sky.rad` is the room of one file: the same triangles and fingerprint,
/// the same `measure` reading for the same seeds; the dataset records every file, so `measure`
/// finds them all without `--scene` (or with it repeated). A missing file is named; joining a
/// `.rad` with another format is refused.
#[test]
fn radiance_scene_of_several_files_is_the_one_file_scene() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mats = "void plastic grey 0 0 5 0.5 0.5 0.5 0 0\nvoid plastic floor 0 0 5 0.2 0.2 0.2 0 0\n";
    let room = "floor polygon f 0 0 12 -2 -2 0 2 -2 0 2 2 0 -2 2 0\n\
        grey polygon s 0 0 12 -2 -2 0 -2 -2 3 2 -2 3 2 -2 0\ngrey polygon n 0 0 12 -2 2 0 2 2 0 2 2 3 -2 2 3\n\
        grey polygon w 0 0 12 -2 -2 0 -2 2 0 -2 2 3 -2 -2 3\ngrey polygon e 0 0 12 2 -2 0 2 -2 3 2 2 3 2 2 0\n\
        grey polygon r1 0 0 12 -2 -2 3 -2 -1 3 2 -1 3 2 -2 3\ngrey polygon r2 0 0 12 -2 1 3 -2 2 3 2 2 3 2 1 3\n";
    let sky = "!gensky -ang 45 0 -c -b 10\nskyfunc glow sky_glow 0 0 4 1 1 1 0\nsky_glow source sky 0 0 4 0 0 1 180\n";
    for (name, text) in [("mats.rad", mats), ("room.rad", room), ("sky.rad", sky)] {
        std::fs::write(d.join(name), text).unwrap();
    }
    std::fs::write(d.join("one.rad"), format!("{mats}{room}{sky}")).unwrap();
    std::fs::write(d.join("p.csv"), "0 0 0, 0 0 1\n1 0.5 1, 0 0 1\n").unwrap();
    let trace = |scene: &[&str], out: &str| {
        let mut args = vec!["trace"];
        args.extend(scene);
        args.extend(["--paths", "20000", "--seed", "3", "-o", out]);
        ok(&args, d);
    };
    trace(&["mats.rad", "room.rad", "sky.rad"], "three.opds");
    trace(&["one.rad"], "one.opds");
    let header = |f: &str| DatasetReader::open(&d.join(f)).unwrap().header().clone();
    let (three, one) = (header("three.opds"), header("one.opds"));
    assert_eq!(three.fingerprint, one.fingerprint);
    assert_eq!(three.table.total_paths(), one.table.total_paths());
    assert!(
        three.label.contains("\n+ room.rad\n") && three.label.contains("\n+ sky.rad\n"),
        "{}",
        three.label
    );
    let triangles = |files: &[&str]| {
        let refs = files.iter().map(|f| opticks_io::scene_source::SceneRef::File(d.join(f))).collect();
        let scene = opticks_io::scene_source::SceneRef::joined(refs).unwrap();
        let loaded = opticks_io::scene_source::load(&scene, &Default::default()).unwrap();
        opticks_io::scene_source::build(&scene, &loaded.description).unwrap().scene.triangles.len()
    };
    assert_eq!(triangles(&["mats.rad", "room.rad", "sky.rad"]), triangles(&["one.rad"]));
    // `info --json` lists every file, in order; `scene` stays the first.
    let json: serde_json::Value = serde_json::from_str(&ok(&["info", "three.opds", "--json"], d)).unwrap();
    let files: Vec<&str> =
        json["scene_files"].as_array().unwrap().iter().map(|f| f["relative"].as_str().unwrap()).collect();
    assert_eq!(files, ["mats.rad", "room.rad", "sky.rad"], "{json}");
    assert_eq!(json["scene"]["relative"], "mats.rad");
    assert_eq!(json["scene_found"].as_str().unwrap().lines().count(), 3, "{json}");
    let measure = |data: &str, out: &str, scene: &[&str]| {
        let mut args = vec!["measure", data, "--points", "p.csv", "-o", out, "--direct-samples", "64"];
        for s in scene {
            args.extend(["--scene", s]);
        }
        ok(&args, d);
        std::fs::read_to_string(d.join(out)).unwrap()
    };
    let reading = measure("one.opds", "one.csv", &[]);
    assert_eq!(measure("three.opds", "three.csv", &[]), reading, "the recorded files, found");
    assert_eq!(measure("three.opds", "again.csv", &["mats.rad", "room.rad", "sky.rad"]), reading);
    let e = fails(&["trace", "mats.rad", "gone.rad", "sky.rad", "-o", "x.opds"], d);
    assert!(e.contains("gone.rad: cannot open a scene file"), "{e}");
    let e = fails(&["trace", "mats.rad", "builtin:cornell", "-o", "x.opds"], d);
    assert!(e.contains("builtin:cornell is not a .rad file"), "{e}");
    let e = fails(&["measure", "three.opds", "--points", "p.csv", "-o", "y.csv", "--scene", "room.rad"], d);
    assert!(e.contains("undefined modifier \"floor\"") && e.contains("room.rad:1:1"), "{e}");
}
