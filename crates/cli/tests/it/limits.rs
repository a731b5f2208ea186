//! Bounded work and meaningful arguments (issue 26): every long loop sees an interrupt after a
//! bounded amount of work whatever the counts asked for, every count that sizes work or memory
//! has a stated bound, an option that would do nothing is refused, and a refusal names the
//! option at fault.

use crate::cli_run::*;
use opticks_testkit::scene_file;

#[test]
fn counts_beyond_their_bounds_are_refused_naming_the_bound() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let e = fails(
        &["render", "x.opds", "-o", "x.png", "--estimator", "bidirectional", "--connections", "5000"],
        d,
    );
    assert!(e.contains("--connections") && e.contains("1024"), "{e}");
}

/// `render --estimator bidirectional --spp 1000000000` stops on SIGINT: the camera pass asks
/// whether to stop within its bands, not only between them (a band's work grows with --spp).
#[cfg(unix)]
#[test]
fn a_bidirectional_render_of_a_billion_paths_per_pixel_stops_on_sigint() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cornell = scene_file("cornell", "scene.xml");
    stdout(&["trace", cornell.to_str().unwrap(), "--paths", "20000", "-o", "data.opds"], d);
    let render =
        ["render", "data.opds", "-o", "x.png", "--estimator", "bidirectional", "--coverage", "everywhere"];
    let mut child = start(&[&render[..], &["--spp", "1000000000", "--size", "16x16"]].concat(), d);
    std::thread::sleep(std::time::Duration::from_millis(1500));
    signal(&child, "-INT");
    // Generous: the interrupt is seen within milliseconds; a render that ignores it runs for days.
    let mut exited = None;
    for _ in 0..600 {
        if let Some(s) = child.try_wait().unwrap() {
            exited = Some(s);
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let Some(status) = exited else {
        child.kill().unwrap();
        child.wait().unwrap();
        panic!("the render went on for a minute after SIGINT");
    };
    assert_eq!(status.code(), Some(130), "128 + SIGINT");
}

/// `bench` holds every traced sample in memory: a count the machine cannot hold is refused
/// before any run, naming the count, the memory it needs and what is available.
#[test]
fn bench_refuses_paths_the_memory_cannot_hold() {
    let dir = tempfile::tempdir().unwrap();
    let e = fails(&["bench", "--paths", "1e15", "--repeat", "1"], dir.path());
    assert!(e.contains("--paths 1000000000000000") && e.contains("available"), "{e}");
}

/// `--threads` is bounded by the cores (100000 threads never finished starting); every verb
/// shares the bound.
#[test]
fn thread_counts_beyond_the_machine_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for verb in [&["trace", "builtin:cornell", "-o", "x.opds"][..], &["bench"], &["demo"]] {
        let e = fails(&[verb, &["--threads", "100000"]].concat(), dir.path());
        assert!(e.contains("--threads") && e.contains("at most") && e.contains("cores"), "{e}");
    }
    assert!(!dir.path().join("x.opds").exists());
}

/// An option that would do nothing is refused, not silently accepted: the bidirectional
/// estimator's options with the light estimator (render and walk), and a focus distance
/// without a lens.
#[test]
fn options_that_would_do_nothing_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cornell = scene_file("cornell", "scene.xml");
    stdout(&["trace", cornell.to_str().unwrap(), "--paths", "20000", "-o", "c.opds"], d);
    for (option, value) in [("--spp", "4"), ("--connections", "2"), ("--camera-seed", "3")] {
        let e = fails(&["render", "c.opds", "-o", "x.png", option, value], d);
        assert!(e.contains(option) && e.contains("--estimator bidirectional"), "{e}");
        let path = opticks_testkit::repo().join("examples/camera-path.json");
        let e =
            fails(&["walk", "c.opds", "--path", path.to_str().unwrap(), "-o", "frames", option, value], d);
        assert!(e.contains(option) && e.contains("--estimator bidirectional"), "{e}");
    }
    let e = fails(&["render", "c.opds", "-o", "x.png", "--focus-distance", "3"], d);
    assert!(e.contains("--focus-distance") && e.contains("--lens-radius"), "{e}");
    // The meter's connection settings with the samples estimator, which has none — also
    // `--direct-samples auto`, which names the defaults but is still given.
    for (option, value) in
        [("--connections", "2"), ("--direct-samples", "8"), ("--direct-samples", "auto"), ("--seed", "3")]
    {
        let e = fails(&["measure", "c.opds", "--surface", "red_wall", "-o", "m.csv", option, value], d);
        assert!(e.contains(option) && e.contains("--estimator connections"), "{e}");
    }
    // A camera on a verb that writes a dataset, which no camera changes.
    let s = cornell.to_str().unwrap();
    for args in [
        &["trace", s, "--paths", "100", "-o", "t.opds"][..],
        &["refine", "c.opds", "--paths", "100"],
        &["add-light", "c.opds", "x", "--paths", "100"],
        &["upgrade", "c.opds", "-o", "u.opds"],
        &["resume", "c.partial.opds"],
    ] {
        let e = fails(&[args, &["--camera", "side"]].concat(), d);
        assert!(e.contains("--camera chooses a view"), "{args:?}: {e}");
    }
    assert_eq!(files(d), ["c.opds"], "nothing written");
    // What they apply to still takes them.
    ok(
        &[
            "render",
            "c.opds",
            "-o",
            "x.png",
            "--lens-radius",
            "0.05",
            "--focus-distance",
            "3",
            "--size",
            "8x8",
        ],
        d,
    );
    // The samples estimator without the flag (its default), and `auto` where it applies.
    ok(&["measure", "c.opds", "--surface", "red_wall", "--cells", "2x2", "-o", "m.csv"], d);
    let plane = ["--plane", "-1,1,-1,2,0,0,0,0,2", "--cells", "2x2", "-o", "n.csv"];
    ok(&[&["measure", "c.opds", "--direct-samples", "auto"][..], &plane].concat(), d);
}

/// Messages name the option at fault and read the way counts are written: `--spp` takes
/// `1e9` like `--paths`, a negative `--paths` is "must be positive" (not clap's `-- -5`), an
/// invalid `--fov` is the option's fault (not the dataset's scene), `--projection`'s help lists
/// orthographic, and `--version` says whether the binary was built with mpi.
#[test]
fn messages_name_the_option_and_read_well() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // --spp 1e9 is parsed (the missing dataset is what stops it), 1e10 is beyond 32 bits.
    let bidirectional = ["render", "missing.opds", "-o", "x.png", "--estimator", "bidirectional", "--spp"];
    let e = fails(&[&bidirectional[..], &["1e9"]].concat(), d);
    assert!(e.contains("missing.opds") && !e.contains("--spp"), "{e}");
    let e = fails(&[&bidirectional[..], &["1e10"]].concat(), d);
    assert!(e.contains("--spp") && e.contains("4294967295"), "{e}");
    for verb in [&["trace", "builtin:cornell", "-o", "x.opds"][..], &["bench"], &["demo"]] {
        let e = fails(&[verb, &["--paths", "-5"]].concat(), d);
        assert!(e.contains("--paths") && e.contains("must be positive") && !e.contains("-- -5"), "{e}");
    }
    let e = fails(&["render", "missing.opds", "-o", "x.png", "--fov", "0"], d);
    assert!(e.contains("--fov 0") && !e.contains("scene") && !e.contains("missing.opds"), "{e}");
    let help = stdout(&["render", "--help"], d);
    let projection = help.split("--projection").nth(1).unwrap().split("Possible values").next().unwrap();
    assert!(projection.contains("orthographic"), "{projection}");
    let version = stdout(&["--version"], d);
    assert!(version.contains("mpi"), "{version}");
}

/// The memory limits on loading are options: `--max-texels` refuses a scene whose texture is
/// larger (naming the file, its size, the limit and the option) when a trace loads it and when
/// a render loads it again for a dataset, and admits it at its size; `--max-mesh-expansion`
/// admits a serialized mesh that zlib shrank beyond the default's 128 times (one triangle
/// and 200,000 unused zero vertices), which the default refuses. Zero is refused as a count.
#[test]
fn loading_limits_change_what_loads() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let textures = opticks_testkit::repo().join("testdata/mitsuba/textures/scene.xml");
    let textures = textures.to_str().unwrap();
    let trace = |extra: &[&'static str]| -> Vec<&str> {
        [&["trace", textures, "--paths", "2000", "-o", "t.opds"][..], extra].concat()
    };
    let e = fails(&trace(&["--max-texels", "127"]), d);
    for part in ["stripes.png", "16 × 8 = 128 texels", "the limit of 127", "--max-texels"] {
        assert!(e.contains(part), "{part:?} missing: {e}");
    }
    ok(&trace(&["--max-texels", "128"]), d);
    let e = fails(&["render", "t.opds", "-o", "t.png", "--max-texels", "1e2"], d);
    assert!(
        e.contains("stripes.png") && e.contains("the limit of 100 ") && e.contains("--max-texels"),
        "{e}"
    );
    ok(&["render", "t.opds", "-o", "t.png", "--size", "8x8"], d);
    for zero in [&["--max-texels", "0"], &["--max-mesh-expansion", "0"]] {
        let e = fails(&trace(zero), d);
        assert!(e.contains(zero[0]) && e.contains("at least 1"), "{e}");
    }

    // Mesh: a triangle then zero vertices, one face; all but its first bytes zeros.
    let vertices = 200_000u64;
    let mut raw = Vec::new();
    raw.extend(0x1000u32.to_le_bytes()); // flags: single precision, no normals
    raw.extend(b"m\0");
    raw.extend(vertices.to_le_bytes());
    raw.extend(1u64.to_le_bytes());
    for i in 0..vertices {
        let p: [f32; 3] = match i {
            1 => [1.0, 0.0, 0.0],
            2 => [0.0, 1.0, 0.0],
            _ => [0.0; 3],
        };
        p.iter().for_each(|x| raw.extend(x.to_le_bytes()));
    }
    [0u32, 1, 2].iter().for_each(|i| raw.extend(i.to_le_bytes()));
    let mut z = flate2::write::ZlibEncoder::new(vec![0x1c, 0x04, 4, 0], flate2::Compression::best());
    std::io::Write::write_all(&mut z, &raw).unwrap();
    std::fs::write(d.join("m.serialized"), z.finish().unwrap()).unwrap();
    std::fs::write(
        d.join("mesh.xml"),
        r#"<scene version="3.0.0">
    <shape type="serialized"><string name="filename" value="m.serialized"/><bsdf type="diffuse"/></shape>
    <emitter type="point"><point name="position" x="0.2" y="0.2" z="1"/><rgb name="intensity" value="1"/></emitter>
</scene>"#,
    )
    .unwrap();
    let trace = |extra: &[&'static str]| -> Vec<&str> {
        [&["trace", "mesh.xml", "--paths", "1000", "-o", "m.opds"][..], extra].concat()
    };
    let e = fails(&trace(&[]), d);
    for part in [
        "m.serialized",
        "200000 vertices and 1 triangles call for",
        "the limit is 128 times",
        "--max-mesh-expansion",
    ] {
        assert!(e.contains(part), "{part:?} missing: {e}");
    }
    ok(&trace(&["--max-mesh-expansion", "2000"]), d);
    assert!(d.join("m.opds").exists());
}

/// "No option is ignored" (README): every option of every verb, as its `--help` lists it, is
/// one this table accounts for — each changes the result or is refused where it would not
/// (the tests named beside it hold that). A new option fails this test until it is added here,
/// with the test that shows it is honoured.
#[test]
fn every_option_of_every_verb_is_accounted_for() {
    let common = ["quiet", "verbose", "help", "version"];
    let view =
        ["eye", "target", "up", "fov", "size", "projection", "lens-radius", "focus-distance", "ortho-width"];
    let strategy = ["rr-depth", "roulette", "directions", "selection", "mis-records"];
    // Every verb that loads a scene (loading_limits_change_what_loads).
    let loading = ["max-texels", "max-mesh-expansion"];
    // verb: its own options (the test modules that hold them in the comments).
    let table: &[(&str, &[&str])] = &[
        ("demo", &["output", "paths", "seed", "exposure", "threads", "export-scene"]), // cli, guarantees
        ("trace", &["paths", "output", "overwrite", "seed", "time", "threads", "camera", "gltf-scene"]), // dataset_product, limits
        (
            "render",
            &[
                "scene",
                "light",
                "camera",
                "gltf-scene",
                "output",
                "exposure",
                "threads",
                "estimator",
                "spp",
                "connections",
                "camera-seed",
                "coverage",
                "time",
            ],
        ), // cli, limits, guarantees
        (
            "refine",
            &["paths", "scene", "camera", "gltf-scene", "output", "overwrite", "seed", "threads", "time"],
        ), // dataset_product
        (
            "add-light",
            &["scene", "camera", "gltf-scene", "paths", "output", "overwrite", "seed", "threads", "time"],
        ), // dataset_product
        (
            "resume",
            &["output", "overwrite", "scene", "camera", "gltf-scene", "threads", "time", "finish-now"],
        ), // dataset_product, guarantees
        ("merge", &["output", "overwrite"]), // dataset_product, guarantees
        (
            "walk",
            &[
                "scene",
                "light",
                "camera",
                "gltf-scene",
                "path",
                "output",
                "fraction",
                "format",
                "exposure",
                "threads",
                "estimator",
                "spp",
                "connections",
                "camera-seed",
                "coverage",
            ],
        ), // dataset_product, limits
        ("info", &["json"]),                 // cli
        ("bench", &["paths", "seed", "repeat", "reference", "threads", "camera", "gltf-scene"]), // cli, limits
        (
            "measure",
            &[
                "scene",
                "light",
                "camera",
                "gltf-scene",
                "surface",
                "plane",
                "points",
                "cells",
                "estimator",
                "connections",
                "direct-samples",
                "seed",
                "output",
                "png",
                "daylight-factor",
                "threads",
            ],
        ), // meter, sensors, limits, daylight
        ("upgrade", &["scene", "camera", "gltf-scene", "output", "overwrite", "mis-records", "threads"]), // cli, guarantees
    ];
    let dir = tempfile::tempdir().unwrap();
    for (verb, own) in table {
        let help = stdout(&[verb, "--help"], dir.path());
        let mut listed: Vec<String> = help
            .lines()
            .filter_map(|l| {
                l.trim_start()
                    .split_once("--")
                    .filter(|(before, _)| before.is_empty() || before.ends_with(", "))
            })
            .map(|(_, rest)| {
                rest.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-')).next().unwrap().to_string()
            })
            .collect();
        listed.sort();
        listed.dedup();
        let mut expected: Vec<String> = own.iter().chain(&common).map(|s| s.to_string()).collect();
        if ["demo", "render", "bench"].contains(verb) {
            expected.extend(view.iter().map(|s| s.to_string()));
        }
        if ["trace", "refine", "add-light", "bench"].contains(verb) {
            expected.extend(strategy.iter().map(|s| s.to_string()));
        }
        if !["demo", "merge", "info"].contains(verb) {
            expected.extend(loading.iter().map(|s| s.to_string()));
        }
        expected.sort();
        expected.dedup();
        assert_eq!(listed, expected, "opticks {verb}: options not accounted for (or gone)");
    }
}
