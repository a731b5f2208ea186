//! What Opticks guarantees (the section of that name in docs/guide.md; issue 10's data-loss and
//! silently-wrong items): nothing on disk is lost and nothing is silently wrong, whatever a
//! careless user, a signal, a full disk or a second process does to the command line, end to
//! end. Each test reproduces a way the command line used to destroy data or print a wrong answer
//! with exit code 0. Hostile input and huge requests are `hostile_input.rs`.

use crate::cli_run;
use opticks_testkit as common;

use cli_run::*;
use common::*;
use opticks_io::dataset_file::{DatasetReader, read_all};
use std::path::{Path, PathBuf};
use std::process::Child;
use std::time::Duration;

/// The Cornell box scene (scene.xml and meshes/) copied into `dir/folder`.
fn copy_cornell(dir: &Path, folder: &str) -> PathBuf {
    let to = dir.join(folder);
    std::fs::create_dir_all(to.join("meshes")).unwrap();
    std::fs::copy(scene_file("cornell", "scene.xml"), to.join("scene.xml")).unwrap();
    for e in std::fs::read_dir(scene_file("cornell", "meshes")).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join("meshes").join(e.file_name())).unwrap();
    }
    to.join("scene.xml")
}

/// Starts a long trace (or another long dataset job) and waits until it writes its dataset.
fn start_long(args: &[&str], dir: &Path, target: &str) -> Child {
    let child = start(args, dir);
    let prefix = format!(".{target}.tmp-");
    while !files(dir).iter().any(|f| f.starts_with(&prefix)) {
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(300)); // a few batches traced
    child
}

/// Item 1: no output lands on an input, and no output's extension misnames what it holds.
#[test]
fn outputs_never_replace_inputs_or_take_a_foreign_extension() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = copy_cornell(d, "s");
    let xml = std::fs::read(&scene).unwrap();
    let s = scene.to_str().unwrap();
    ok(&["trace", s, "--paths", "5000", "-o", "mm.opds"], d);
    let data = std::fs::read(d.join("mm.opds")).unwrap();
    for (args, complaint) in [
        (vec!["trace", s, "-o", s, "--paths", "100"], ".opds"),
        (vec!["refine", "mm.opds", "--paths", "100", "-o", s], ".opds"),
        (vec!["trace", s, "--paths", "100", "-o", "s/meshes/light.obj"], ".opds"),
        (vec!["trace", s, "--paths", "100", "-o", "x.png"], ".opds"),
        (vec!["measure", "mm.opds", "--surface", "floor", "-o", "mm.opds"], ".csv"),
        (vec!["measure", "mm.opds", "--surface", "floor", "-o", "q.csv", "--png", "mm.opds"], ".png"),
        (vec!["measure", "mm.opds", "--surface", "floor", "-o", "q.png"], ".csv"),
        (vec!["render", "mm.opds", "-o", "mm.opds"], ".exr or .png"),
        (vec!["demo", "--export-scene", "x.xml"], ".wrl"),
        (vec!["merge", "mm.opds", "mm.opds", "-o", s], ".opds"),
    ] {
        let e = fails(&args, d);
        assert!(e.contains(complaint), "{args:?}: {e}");
    }
    // A dataset (hours of refined work, perhaps) is replaced by a new trace only when asked.
    let e = fails(&["trace", s, "--paths", "100", "-o", "mm.opds"], d);
    assert!(e.contains("mm.opds exists") && e.contains("--overwrite"), "{e}");
    let e = fails(&["merge", "mm.opds", "mm.opds", "-o", "mm.opds", "--overwrite"], d);
    assert!(e.contains("repeats the random stream"), "{e}");
    assert!(std::fs::read(&scene).unwrap() == xml && std::fs::read(d.join("mm.opds")).unwrap() == data);
    assert_eq!(files(d), ["mm.opds", "s"], "nothing else was written");
    // Merging into one of the inputs replaces it: only when asked (issue 26).
    ok(&["trace", s, "--paths", "3000", "--seed", "3", "-o", "other.opds"], d);
    let e = fails(&["merge", "mm.opds", "other.opds", "-o", "./mm.opds"], d);
    assert!(e.contains("is one of the inputs") && e.contains("--overwrite"), "{e}");
    assert!(std::fs::read(d.join("mm.opds")).unwrap() == data);
    ok(&["merge", "mm.opds", "other.opds", "-o", "mm.opds", "--overwrite"], d);
    assert_eq!(DatasetReader::open(&d.join("mm.opds")).unwrap().header().table.total_paths(), 8000);
    ok(&["trace", s, "--paths", "100", "-o", "mm.opds", "--overwrite"], d);
    assert_eq!(DatasetReader::open(&d.join("mm.opds")).unwrap().header().table.total_paths(), 100);
}

/// Item 2: SIGTERM (timeout, Slurm, systemd), SIGHUP (a closed terminal) and a double Ctrl-C
/// all save the partial dataset, leave no temporary file and exit 128 + signal.
#[cfg(unix)]
#[test]
fn every_stop_signal_saves_the_work_and_cleans_up() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (signals, code) in [(&["-TERM"][..], 143), (&["-HUP"], 129), (&["-INT", "-INT"], 130)] {
        let child = start_long(&["trace", "builtin:cornell", "--paths", "4e9", "-o", "s.opds"], d, "s.opds");
        for s in signals {
            signal(&child, s);
        }
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{signals:?}: {err}");
        assert!(err.contains("s.partial.opds"), "{err}");
        let partial = DatasetReader::open(&d.join("s.partial.opds")).unwrap();
        partial.verify().unwrap();
        assert!(partial.header().table.total_paths() > 0);
        assert_eq!(files(d), ["s.partial.opds"], "{signals:?}: no temporary or lock file is left");
        std::fs::remove_file(d.join("s.partial.opds")).unwrap();
    }
}

/// Items 2 and 21: a run killed outright (kill -9) leaves its temporary file; the next run on
/// the same output saves the whole blocks a dataset's holds as its partial dataset and stops,
/// saying so (`dataset_product::a_killed_trace_keeps_its_written_blocks` checks what is saved),
/// or, with nothing to save, removes it and says so — for datasets, images, meter tables and
/// heat maps.
#[cfg(unix)]
#[test]
fn a_killed_runs_temporary_file_is_saved_or_removed_by_the_next_run() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut child = start_long(&["trace", "builtin:cornell", "--paths", "4e9", "-o", "k.opds"], d, "k.opds");
    signal(&child, "-KILL");
    child.wait().unwrap();
    let stale: Vec<String> = files(d).into_iter().filter(|f| f.starts_with(".k.opds.tmp-")).collect();
    assert_eq!(stale.len(), 1, "{:?}", files(d));
    let again = ["trace", "builtin:cornell", "--paths", "4096", "-o", "k.opds"];
    let first = opticks(&again, d);
    let err = String::from_utf8_lossy(&first.stderr);
    if first.status.success() {
        // Killed before a block reached the disk: nothing to save.
        assert!(err.contains(&stale[0]) && err.contains("killed"), "{err}");
    } else {
        assert!(
            err.contains("a run writing k.opds was killed before it finished")
                && err.contains("k.partial.opds")
        );
        DatasetReader::open(&d.join("k.partial.opds")).unwrap().verify().unwrap();
        assert_eq!(files(d), ["k.partial.opds"], "the temporary file became the partial one");
        std::fs::remove_file(d.join("k.partial.opds")).unwrap();
        ok(&again, d);
    }
    assert_eq!(files(d), ["k.opds"]);

    // Images, meter tables and heat maps too: the killed process's temporary files (what a
    // kill -9 during their write leaves) are removed by the next write of the same output.
    let dead = child.id();
    let left: Vec<String> =
        ["k.png", "m.csv", "m.png"].iter().map(|f| format!(".{f}.tmp-{dead}-0")).collect();
    left.iter().for_each(|f| std::fs::write(d.join(f), b"half a file").unwrap());
    let out = ok(&["render", "k.opds", "-o", "k.png", "--size", "16x16"], d);
    assert!(out.contains(&left[0]) && out.contains("killed"), "{out}");
    let out = ok(
        &["measure", "k.opds", "--surface", "light", "--cells", "2x2", "-o", "m.csv", "--png", "m.png"],
        d,
    );
    assert!(out.contains(&left[1]) && out.contains(&left[2]), "{out}");
    assert_eq!(files(d), ["k.opds", "k.png", "m.csv", "m.png"]);
}

/// Item 21: a second writer of a dataset is refused while the first runs; an interrupted run's
/// partial file is not overwritten by another run; resuming it never discards later work.
#[cfg(unix)]
#[test]
fn writers_take_turns_and_partial_runs_are_never_overwritten() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(&["trace", "builtin:cornell", "--paths", "20000", "-o", "d.opds"], d);
    let before = std::fs::read(d.join("d.opds")).unwrap();
    let child = start_long(&["refine", "d.opds", "--paths", "4e9"], d, "d.opds");
    let e = fails(&["refine", "d.opds", "--paths", "4096"], d);
    assert!(e.contains(&format!("d.opds is being written by another process (pid {})", child.id())), "{e}");
    signal(&child, "-TERM");
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(143), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::read(d.join("d.opds")).unwrap() == before);
    let partial = std::fs::read(d.join("d.partial.opds")).unwrap();
    // Another run of d.opds would be interrupted into the same partial file: refused up front.
    for args in [
        &["refine", "d.opds", "--paths", "4096"][..],
        &["trace", "builtin:cornell", "--paths", "4096", "-o", "d.opds", "--overwrite"],
        &["add-light", "d.opds", "x"],
    ] {
        let e = fails(args, d);
        assert!(e.contains("d.partial.opds holds an interrupted run") && e.contains("opticks resume"), "{e}");
    }
    // Refining the partial dataset itself would make it impossible to resume.
    let e = fails(&["refine", "d.partial.opds", "--paths", "4096", "-o", "r.opds"], d);
    assert!(e.contains("interrupted") && e.contains("opticks resume d.partial.opds"), "{e}");
    assert!(std::fs::read(d.join("d.partial.opds")).unwrap() == partial);
    let info = ok(&["info", "d.partial.opds"], d);
    assert!(info.contains("`opticks resume` finishes it"), "{info}");

    // A small interrupted refinement, then d.opds changes (refined elsewhere and copied back):
    // finishing the old run into it would discard that work.
    std::fs::remove_file(d.join("d.partial.opds")).unwrap();
    let cut = [("OPTICKS_INTERRUPT_AFTER_PATHS", "1")]; // stops after the first batch
    let out = opticks_env(&["refine", "d.opds", "--paths", "300000"], d, &cut);
    assert_eq!(out.status.code(), Some(130));
    ok(&["refine", "d.opds", "--paths", "4096", "-o", "later.opds"], d);
    std::fs::copy(d.join("later.opds"), d.join("d.opds")).unwrap();
    let e = fails(&["resume", "d.partial.opds"], d);
    assert!(
        e.contains("d.opds: it has changed since the interrupted run started") && e.contains("-o"),
        "{e}"
    );
    assert!(std::fs::read(d.join("d.opds")).unwrap() == std::fs::read(d.join("later.opds")).unwrap());
    ok(&["resume", "d.partial.opds", "-o", "finished.opds"], d);
    assert_eq!(DatasetReader::open(&d.join("finished.opds")).unwrap().header().table.total_paths(), 320_000);
    assert!(!d.join("d.partial.opds").exists());
}

/// Items 1 and 21 for `upgrade`: it obeys the output rules and the write lock of every other
/// dataset writer (it used to write anywhere: onto another dataset, under any extension, while
/// another process wrote the same file).
#[cfg(unix)]
#[test]
fn upgrade_obeys_the_output_rules_and_the_write_lock() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for name in ["a.opds", "b.opds"] {
        ok(&["trace", "builtin:cornell", "--paths", "4096", "--mis-records", "none", "-o", name], d);
    }
    let b = std::fs::read(d.join("b.opds")).unwrap();
    let e = fails(&["upgrade", "a.opds", "-o", "b.opds"], d);
    assert!(e.contains("b.opds exists and would be replaced") && e.contains("--overwrite"), "{e}");
    let e = fails(&["upgrade", "a.opds", "-o", "a.png"], d);
    assert!(e.contains(".opds"), "{e}");
    assert!(std::fs::read(d.join("b.opds")).unwrap() == b && !d.join("a.png").exists());
    // A second writer of the same output is refused while the first runs.
    let mut child = start_long(&["trace", "builtin:cornell", "--paths", "4e9", "-o", "c.opds"], d, "c.opds");
    let e = fails(&["upgrade", "a.opds", "-o", "c.opds"], d);
    assert!(e.contains(&format!("c.opds is being written by another process (pid {})", child.id())), "{e}");
    signal(&child, "-KILL");
    child.wait().unwrap();
    // In place, and onto another dataset with --overwrite.
    ok(&["upgrade", "a.opds", "-o", "b.opds", "--overwrite"], d);
    ok(&["upgrade", "a.opds"], d);
    assert!(std::fs::read(d.join("b.opds")).unwrap() == std::fs::read(d.join("a.opds")).unwrap());
    assert!(std::fs::read(d.join("b.opds")).unwrap() != b, "the records were added");
}

/// Item 3: a full disk keeps the chunks written so far as a valid, resumable partial dataset,
/// and the error names the target, not the hidden temporary file.
#[test]
fn a_full_disk_keeps_what_was_written_and_resumes_to_the_whole() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fn trace(out: &str) -> Vec<&str> {
        vec!["trace", "builtin:cornell", "--paths", "120000", "--seed", "4", "-o", out]
    }
    let full = [("OPTICKS_FAIL_WRITES_AFTER_BYTES", "5000000")];
    let out = opticks_env(&trace("f.opds"), d, &full);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(err.contains("f.opds: cannot write: No space left on device") && !err.contains(".tmp"), "{err}");
    assert!(
        err.contains("saved in f.partial.opds") && err.contains("opticks resume f.partial.opds"),
        "{err}"
    );
    assert_eq!(files(d), ["f.partial.opds"]);
    let partial = DatasetReader::open(&d.join("f.partial.opds")).unwrap();
    partial.verify().unwrap();
    let kept = partial.header().table.total_paths();
    assert!(kept > 0 && kept < 120_000 && partial.file_len() <= 5_000_000, "{kept} paths kept");
    drop(partial);
    ok(&["resume", "f.partial.opds"], d);
    ok(&trace("whole.opds"), d);
    let chunks = |f: &str| read_all(&d.join(f)).unwrap().1;
    assert!(chunks("f.opds") == chunks("whole.opds"), "resumed after a full disk = uninterrupted");
}

/// Items 5 and 6: the scene is recorded relative to the dataset (and absolute), so every verb
/// works from any directory and after moving the dataset, alone or with its scene.
#[test]
fn the_recorded_scene_is_found_from_anywhere() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    copy_cornell(d, "proj/scene");
    std::fs::create_dir_all(d.join("proj/out")).unwrap();
    std::fs::create_dir_all(d.join("elsewhere")).unwrap();
    ok(&["trace", "scene/scene.xml", "--paths", "5000", "-o", "out/c.opds"], &d.join("proj"));
    let elsewhere = d.join("elsewhere");
    ok(&["render", "../proj/out/c.opds", "-o", "a.exr", "--size", "8x8"], &elsewhere);
    let info = ok(&["info", "../proj/out/c.opds"], &elsewhere);
    assert!(info.contains("../scene/scene.xml (relative to the dataset) (found: used)"), "{info}");
    assert!(info.contains(&format!(
        "{} (absolute) (found)",
        d.canonicalize().unwrap().join("proj/scene/scene.xml").display()
    )));
    // The dataset alone moves: the absolute path finds the scene.
    std::fs::copy(d.join("proj/out/c.opds"), elsewhere.join("alone.opds")).unwrap();
    ok(&["render", "alone.opds", "-o", "b.exr", "--size", "8x8"], &elsewhere);
    // The whole project moves: the relative path finds the moved scene.
    std::fs::rename(d.join("proj"), d.join("moved")).unwrap();
    ok(&["refine", "out/c.opds", "--paths", "4096"], &d.join("moved"));
    let info = ok(&["info", "moved/out/c.opds"], d);
    assert!(info.contains("../scene/scene.xml (relative to the dataset) (found: used)"), "{info}");
    assert!(info.contains(&format!(
        "{} (absolute) (found)",
        d.canonicalize().unwrap().join("moved/scene/scene.xml").display()
    )));
    let e = fails(&["render", "alone.opds", "-o", "c.exr"], &elsewhere);
    assert!(e.contains("cannot find the scene it was traced from") && e.contains("--scene"), "{e}");

    // A merge records the scene of the input that has every light, from the output's folder.
    let scene = d.join("moved/scene/scene.xml");
    let lamp = std::fs::read_to_string(&scene).unwrap().replace(
        "</scene>",
        "<emitter type=\"point\" id=\"lamp\"><point name=\"position\" x=\"0.3\" y=\"-0.2\" z=\"0.6\"/>\
         <rgb name=\"intensity\" value=\"0.2, 0.3, 0.5\"/></emitter></scene>",
    );
    std::fs::write(d.join("moved/scene/lamp.xml"), lamp).unwrap();
    let m = d.join("moved");
    ok(&["add-light", "out/c.opds", "lamp", "--scene", "scene/lamp.xml", "-o", "out/lamp.opds"], &m);
    ok(&["trace", "scene/scene.xml", "--paths", "5000", "--seed", "9", "-o", "other.opds"], &m);
    let out = ok(&["merge", "other.opds", "out/lamp.opds", "-o", "merged.opds"], &m);
    assert!(out.contains("2 lights"), "{out}");
    let out = ok(&["render", "merged.opds", "-o", "m.exr", "--size", "8x8"], &m);
    assert!(!out.contains("lamp"), "the merged dataset renders with its new light: {out}");
}

/// Item 8: a scene whose only light has zero power is refused; an image no sample reached is
/// a warning, not a silent black image.
#[test]
fn nothing_to_trace_or_see_is_said() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = copy_cornell(d, "s");
    let dark = std::fs::read_to_string(&scene).unwrap().replace("18.387, 13.9873, 6.75357", "0, 0, 0");
    std::fs::write(d.join("s/dark.xml"), dark).unwrap();
    let e = fails(&["trace", "s/dark.xml", "--paths", "5000", "-o", "dark.opds"], d);
    assert!(e.contains("no light emits"), "{e}");
    assert!(!d.join("dark.opds").exists());
    ok(&["trace", "builtin:cornell", "--paths", "5000", "-o", "c.opds"], d);
    let out = ok(
        &["render", "c.opds", "-o", "away.exr", "--eye", "0,0,5", "--target", "0,0,9", "--size", "8x8"],
        d,
    );
    assert!(out.contains("warning: 0 of") && out.contains("reached the camera"), "{out}");
    let out = ok(&["render", "c.opds", "-o", "box.exr", "--size", "8x8"], d);
    assert!(!out.contains("warning"), "{out}");
    // Issue 26: every light switched off is said as such, not blamed on walls; -v says more.
    let out = ok(&["render", "c.opds", "-o", "off.exr", "--size", "8x8", "--light", "light=0"], d);
    assert!(out.contains("--light switched every light") && !out.contains("inside a wall"), "{out}");
    let out = ok(&["render", "c.opds", "-o", "v.exr", "--size", "8x8", "-v"], d);
    assert!(out.contains("5000 paths") && out.contains("36 triangles"), "{out}");
}

/// Item 9: options that were silently ignored or combined are errors.
#[test]
fn ignored_or_combined_options_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(&["trace", "builtin:cornell", "--paths", "5000", "-o", "c.opds"], d);
    for (args, complaint) in [
        (&["render", "c.opds", "-o", "x.exr", "--exposure", "1"][..], "--exposure applies to PNG"),
        (&["render", "c.opds", "-o", "x.png", "--exposure", "nan"], "finite"),
        (&["render", "c.opds", "-o", "x.exr", "--projection", "equirect", "--fov", "30"], "--fov"),
        (
            &["render", "c.opds", "-o", "x.exr", "--projection", "equirect", "--size", "64x64"],
            "twice as wide",
        ),
        (&["render", "c.opds", "-o", "x.exr", "--light", "light=2", "--light", "light=3"], "more than one"),
        (&["render", "c.opds", "-o", "x.exr", "--light", "light=2", "--light", "0=3"], "more than one"),
        (&["bench", "--paths", "4096", "--repeat", "0"], "--repeat"),
    ] {
        let e = fails(args, d);
        assert!(e.contains(complaint), "{args:?}: {e}");
    }
    assert_eq!(files(d), ["c.opds"]);
    ok(&["render", "c.opds", "-o", "pano.exr", "--projection", "equirect"], d);
    let (w, h, _) = opticks_io::image_file::read_exr_rgb(&d.join("pano.exr")).unwrap();
    assert_eq!((w, h), (256, 128), "equirect without --size: the scene camera's width, 2:1");
}

/// Item 20 (walk): a time span too long for any frame count (which overflowed to 0 frames), and
/// a camera that only breaks between keyframes (here eye = target half-way), are refused before
/// anything is written.
#[test]
fn walks_are_checked_whole_before_any_frame() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(&["trace", "builtin:cornell", "--paths", "5000", "-o", "c.opds"], d);
    let key = |t: &str, z: &str| format!("{{\"time\": {t}, \"eye\": [0, 0, {z}], \"target\": [0, 0, 0]}}");
    for (keys, complaint) in [
        (format!("{},{}", key("0", "3.9"), key("1e30", "3.9")), "more than a walkthrough renders"),
        (format!("{},{}", key("0", "1"), key("1", "-1")), "frame 500 (t = 0.5 s): invalid camera"),
    ] {
        std::fs::write(d.join("p.json"), format!("{{\"fps\": 1000, \"keyframes\": [{keys}]}}")).unwrap();
        let e = fails(&["walk", "c.opds", "--path", "p.json", "-o", "frames"], d);
        assert!(e.contains(complaint) && e.contains("p.json"), "{e}");
        assert!(!d.join("frames").exists(), "nothing written: {e}");
    }
}

/// "Errors before the expensive work": arguments and output locations are checked before the
/// dataset is even opened, and a command's outputs are written all or none.
#[test]
fn arguments_and_outputs_are_checked_first_and_written_all_or_none() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The dataset does not exist: an error about it would mean the output was checked later.
    let e = fails(&["render", "missing.opds", "-o", "nodir/x.png"], d);
    assert!(e.contains("nodir") && !e.contains("missing.opds"), "{e}");
    let e = fails(&["render", "missing.opds", "-o", "x.png", "--exposure", "nan"], d);
    assert!(e.contains("--exposure") && !e.contains("missing.opds"), "{e}");
    ok(&["trace", "builtin:cornell", "--paths", "5000", "-o", "c.opds"], d);
    let e = fails(&["measure", "c.opds", "--surface", "floor", "-o", "ok.csv", "--png", "nodir/x.png"], d);
    assert!(e.contains("nodir"), "{e}");
    assert!(!d.join("ok.csv").exists());
    // Errors that point the right way.
    std::fs::create_dir(d.join("folder.opds")).unwrap();
    let e = fails(&["render", "folder.opds", "-o", "x.png"], d);
    assert!(e.contains("folder.opds: is a directory, not a dataset"), "{e}");
    let e = fails(&["info", "folder.opds"], d);
    assert!(e.contains("is a directory"), "{e}");
    std::fs::create_dir(d.join("folder.xml")).unwrap();
    let e = fails(&["trace", "folder.xml", "-o", "y.opds"], d);
    assert!(e.contains("folder.xml: is a directory, not a scene file"), "{e}");
    let e = fails(&["trace", "builtin:box", "-o", "y.opds"], d);
    assert!(e.contains("builtin:cornell"), "the built-in scenes are listed: {e}");
    let e = fails(
        &["render", "c.opds", "--scene", scene_file("furnace", "scene.xml").to_str().unwrap(), "-o", "x.png"],
        d,
    );
    // The refusal names the objects that differ (the dataset records their hashes).
    assert!(e.contains("different scene than") && e.contains("mesh 'white' is gone"), "{e}");
    // A scene without lights is named as a different scene, not only as unusable.
    std::fs::write(d.join("dark.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let e = fails(&["render", "c.opds", "--scene", "dark.obj", "-o", "x.png"], d);
    assert!(
        e.contains("c.opds was traced from a different scene than dark.obj: dark.obj has no light source"),
        "{e}"
    );
    std::fs::remove_file(d.join("dark.obj")).unwrap();
    assert_eq!(files(d), ["c.opds", "folder.opds", "folder.xml"]);
}

/// "A new user's first ten minutes": counts as people write them, machine-readable `info`,
/// `--quiet`, and readable messages.
#[test]
fn the_first_ten_minutes_read_well() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = opticks(&["trace", "builtin:cornell", "--paths", "8_192", "-o", "a.opds", "--quiet"], d);
    assert!(out.status.success() && out.stdout.is_empty() && out.stderr.is_empty(), "{out:?}");
    ok(&["trace", "builtin:cornell", "--paths", "8.192k", "--seed", "1", "-o", "b.opds"], d);
    let out = ok(&["merge", "a.opds", "b.opds", "-o", "m.opds"], d);
    assert!(out.contains(", 1 light, "), "{out}");
    let json = opticks(&["info", "m.opds", "--json"], d);
    let v: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!((v["paths"].as_u64(), v["lights"][0]["paths"].as_u64()), (Some(16384), Some(16384)));
    assert_eq!(v["scene"]["builtin"], "builtin:cornell");
    assert_eq!(v["passes"].as_array().unwrap().len(), 2);
    let help = ok(&["trace", "--help"], d);
    assert!(help.contains("VRML97") && help.contains("glTF") && !help.contains('§'), "{help}");
    assert!(help.contains("Russian roulette rule [default: energy]") && !help.contains("refine"), "{help}");
    let refine = ok(&["refine", "--help"], d);
    assert!(refine.contains("Russian roulette rule [default: the dataset's last pass's]"), "{refine}");
    let seed_default = |verb: &str| {
        let h = ok(&[verb, "--help"], d);
        let at = h.find("--seed").unwrap();
        h[at..].lines().take(4).collect::<String>().contains("[default: 0]")
    };
    assert!(seed_default("trace") && seed_default("bench"), "trace and bench share --seed's default");
    let e = fails(&["render", "m.opds", "-o", "x.exr", "--light", "sun=2"], d);
    assert!(e.contains("the dataset's lights are light (give"), "no Debug lists: {e}");
}

/// The guide's examples run on the files committed for them (`examples/`).
#[test]
fn the_readme_examples_run() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let examples = repo().join("examples");
    let cornell = scene_file("cornell", "scene.xml");
    ok(&["trace", cornell.to_str().unwrap(), "--paths", "20000", "-o", "all.opds"], d);
    let lamp = examples.join("scene-with-lamp.xml");
    let out = ok(&["add-light", "all.opds", "desk_lamp", "--scene", lamp.to_str().unwrap()], d);
    assert!(out.contains("added light 'desk_lamp'") && out.contains("2 lights"), "{out}");
    let path = examples.join("camera-path.json");
    let out =
        ok(&["walk", "all.opds", "--path", path.to_str().unwrap(), "-o", "frames", "--fraction", "0.5"], d);
    assert!(out.contains("rendered 9 frames of 128x128"), "{out}");
}

/// The reference scenes' documentation names only what is there, and counts right.
#[test]
fn the_testdata_documentation_matches_the_files() {
    let scenes = repo().join("testdata/scenes");
    let readme = std::fs::read_to_string(scenes.join("README.md")).unwrap();
    let listed: Vec<&str> =
        readme.lines().filter_map(|l| l.strip_prefix("| `")).filter_map(|l| l.split('`').next()).collect();
    assert!(listed.len() >= 4, "{listed:?}");
    for scene in ["cornell", "furnace"] {
        for file in &listed {
            let path = scenes.join(scene).join(file.trim_end_matches("*.obj"));
            assert!(path.exists(), "testdata/scenes/README.md lists {file}, missing in {scene}");
        }
        let doc = std::fs::read_to_string(scenes.join(scene).join("SCENE.md")).unwrap();
        let faces: usize = std::fs::read_dir(scenes.join(scene).join("meshes"))
            .unwrap()
            .map(|e| {
                std::fs::read_to_string(e.unwrap().path())
                    .unwrap()
                    .lines()
                    .filter(|l| l.starts_with("f "))
                    .count()
            })
            .sum();
        if let Some(n) = doc.lines().find_map(|l| l.strip_prefix("## Geometry (`meshes/`, ")) {
            assert_eq!(n, format!("{faces} triangles)"), "{scene}/SCENE.md");
        }
    }
}

/// Item 7 (the part that stays): `measure` says which side it measures, and a plane facing away
/// from the light is not a silent zero.
#[test]
fn the_meter_states_the_side_it_measures() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(&["trace", "builtin:cornell", "--paths", "20000", "-o", "c.opds"], d);
    let up =
        ok(&["measure", "c.opds", "--plane", "-1,-1,-1,0,0,2,2,0,0", "--cells", "2x2", "-o", "up.csv"], d);
    assert!(
        up.contains("front side (light arriving from normal 0.000,1.000,0.000)") && !up.contains("warning"),
        "{up}"
    );
    let down =
        ok(&["measure", "c.opds", "--plane", "-1,-1,-1,2,0,0,0,0,2", "--cells", "2x2", "-o", "down.csv"], d);
    assert!(down.contains("normal 0.000,-1.000,0.000") && down.contains("swap u and v"), "{down}");
    let help = ok(&["measure", "--help"], d);
    assert!(help.contains("u × v") && help.contains("swap u and v"), "{help}");
}

/// The files of `testdata/mitsuba/NAME` (a scene and what it names) copied into `dir/NAME`.
fn copy_testdata_scene(dir: &Path, name: &str) -> PathBuf {
    let to = dir.join(name);
    std::fs::create_dir_all(&to).unwrap();
    for e in std::fs::read_dir(common::files::testdata(&format!("mitsuba/{name}"))).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_file() {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
    to
}

/// Issue 26: no output replaces a file the run reads — here an environment map and a texture
/// the scene names, spelled as the scene does, through `./`, or through a hard link — and the
/// refusal comes before any work; the scene's files are left as they were.
#[test]
fn no_output_replaces_a_file_the_scene_reads() {
    let dir = tempfile::tempdir().unwrap();
    for (folder, file, alias) in
        [("envmap", "sky.exr", "alias.exr"), ("textures", "stripes.png", "alias.png")]
    {
        let d = &copy_testdata_scene(dir.path(), folder);
        ok(&["trace", "scene.xml", "--paths", "2000", "-o", "t.opds"], d);
        std::fs::hard_link(d.join(file), d.join(alias)).unwrap();
        let before = std::fs::read(d.join(file)).unwrap();
        let listing = files(d);
        let dotted = format!("./{file}");
        let mut refused = vec![
            vec!["render", "t.opds", "-o", file],
            vec!["render", "t.opds", "-o", &dotted],
            vec!["render", "t.opds", "-o", alias, "--estimator", "bidirectional"],
        ];
        if file.ends_with(".png") {
            refused.push(vec![
                "measure",
                "t.opds",
                "--plane",
                "-1,0,-1,2,0,0,0,0,2",
                "-o",
                "m.csv",
                "--png",
                file,
            ]);
        }
        for args in refused {
            let e = fails(&args, d);
            assert!(e.contains("may not replace") && e.contains("which this run reads"), "{args:?}: {e}");
        }
        assert!(std::fs::read(d.join(file)).unwrap() == before, "{file} is intact");
        assert_eq!(files(d), listing, "nothing was written");
        // What the scene reads is still there: the dataset renders.
        ok(&["render", "t.opds", "-o", "fine.exr"], d);
    }
}

/// Issue 26: Ctrl-C during a timed bidirectional render writes the image of the camera passes
/// it completed (as the interrupt message promises: "the work done so far is kept") and exits
/// 130; before its first pass is complete there is nothing to write, and nothing is written.
#[cfg(unix)]
#[test]
fn an_interrupted_bidirectional_render_writes_the_passes_it_completed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(&["trace", "builtin:cornell", "--paths", "20000", "-o", "c.opds"], d);
    // The signal must come after the first pass: wait longer each time it came before.
    for wait in [2, 5, 12] {
        let args = [
            "render",
            "c.opds",
            "--estimator",
            "bidirectional",
            "--coverage",
            "everywhere",
            "--time",
            "120",
            "--size",
            "32x24",
        ];
        let child = start(&[&args[..], &["-o", "r.exr"]].concat(), d);
        std::thread::sleep(Duration::from_secs(wait));
        signal(&child, "-INT");
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(130), "{err}");
        if err.contains("interrupted after") {
            assert!(err.contains("their image is written to r.exr"), "{err}");
            let (w, h, rgb) = opticks_io::image_file::read_exr_rgb(&d.join("r.exr")).unwrap();
            assert_eq!((w, h), (32, 24));
            assert!(rgb.iter().all(|v| v.is_finite()) && rgb.iter().any(|&v| v > 0.0));
            assert_eq!(files(d), ["c.opds", "r.exr"], "no temporary file is left");
            return;
        }
        assert_eq!(files(d), ["c.opds"], "{err}");
    }
    panic!("no render was interrupted after its first pass");
}

/// Issue 26: an output in a folder where no file can be created (here /sys, where even root
/// cannot) is refused before the work, as a missing folder is, not after it.
#[cfg(target_os = "linux")]
#[test]
fn an_output_folder_that_cannot_be_written_is_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(&["trace", "builtin:cornell", "--paths", "2000", "-o", "c.opds"], d);
    for args in [
        vec!["render", "c.opds", "-o", "/sys/r.png"],
        vec!["render", "c.opds", "--estimator", "bidirectional", "-o", "/sys/r.exr"],
        vec!["measure", "c.opds", "--plane", "-1,0,-1,2,0,0,0,0,2", "-o", "/sys/m.csv"],
        vec!["trace", "builtin:cornell", "--paths", "1000", "-o", "/sys/t.opds"],
    ] {
        let e = fails(&args, d);
        assert!(e.contains("cannot create a file in /sys"), "{args:?}: {e}");
        assert!(!e.contains("rendered") && !e.contains("traced"), "{args:?}: {e}");
    }
}

/// Issue 26: the light estimator renders a mirror or smooth glass seen directly black (21 % of
/// `mirror-glass`'s pixels, its mean 8 % low) and said nothing; now it warns, as it does of an
/// environment seen directly. The bidirectional estimator, which sees them, does not warn, nor
/// does the light estimator on a diffuse scene.
#[test]
fn the_light_estimator_warns_of_mirrors_and_glass_in_view() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = common::files::testdata("mitsuba/mirror-glass/scene.xml");
    ok(&["trace", scene.to_str().unwrap(), "--paths", "20000", "-o", "m.opds"], d);
    let warning = "of the view is a mirror or smooth glass seen directly";
    let out = ok(&["render", "m.opds", "-o", "light.exr"], d);
    assert!(out.contains(warning) && out.contains("--estimator bidirectional"), "{out}");
    let out = ok(&["render", "m.opds", "-o", "bd.exr", "--estimator", "bidirectional", "--size", "64x64"], d);
    assert!(!out.contains(warning), "{out}");
    ok(&["trace", "builtin:cornell", "--paths", "2000", "-o", "c.opds"], d);
    assert!(!ok(&["render", "c.opds", "-o", "c.exr"], d).contains(warning));
}

/// Issue 26: `upgrade --scene` records the scene it used (it kept the old dataset's label,
/// which did not resolve), and `merge` says when the merged dataset cannot find its scene or
/// has lost the bidirectional estimator to an input without MIS records.
#[test]
fn upgrade_and_merge_record_a_scene_that_resolves_or_say_so() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = scene_file("cornell", "scene.xml");
    let s = scene.to_str().unwrap();
    std::fs::copy(common::files::testdata("datasets/cornell-v2.opds"), d.join("v2.opds")).unwrap();
    fails(&["render", "v2.opds", "-o", "x.exr"], d); // its scene, relative to where it was traced
    ok(&["upgrade", "v2.opds", "--scene", s, "-o", "up.opds"], d);
    ok(&["render", "up.opds", "-o", "u.exr", "--estimator", "bidirectional", "--size", "32x32"], d);
    ok(&["trace", s, "--paths", "4096", "--seed", "3", "-o", "new.opds"], d);
    let out = ok(&["merge", "new.opds", "v2.opds", "-o", "m.opds"], d);
    assert!(out.contains("cannot be rendered with --estimator bidirectional"), "{out}");
    assert!(out.contains("opticks upgrade m.opds"), "{out}");
    // Its label is v2.opds's (the input it takes the light table from), which resolves nowhere.
    assert!(out.contains("give --scene when you use m.opds"), "{out}");
    fails(&["render", "m.opds", "-o", "m.exr"], d);
    ok(&["render", "m.opds", "-o", "m.exr", "--scene", s], d);
    let out = ok(&["merge", "new.opds", "up.opds", "-o", "both.opds"], d);
    assert!(!out.contains("warning"), "{out}");
    ok(&["render", "both.opds", "-o", "b.exr", "--estimator", "bidirectional", "--size", "32x32"], d);
}
