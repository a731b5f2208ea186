//! Every input a fuzz target ever crashed, replayed on the stable toolchain through the same
//! entry points (`fuzz/src/entry.rs`, included here by path): `testdata/fuzz-regressions/TARGET/`
//! holds the inputs of target TARGET, each named after the defect it found. A replay must return
//! (an error is fine) without panicking, aborting or hanging. The fuzz targets themselves run in
//! `.ci/run` for a short bounded time each (nightly, `fuzz/run.sh`); docs/guide.md's reliability section
//! says how many executions each has survived.

#[path = "../../../../fuzz/src/entry.rs"]
mod entry;

use std::path::Path;

/// A fuzz target's entry point.
type Entry = fn(&[u8]);

const TARGETS: [(&str, Entry); 15] = [
    ("mitsuba", entry::mitsuba),
    ("vrml", entry::vrml),
    ("obj_mtl", entry::obj_mtl),
    ("gltf", entry::gltf),
    ("ies", entry::ies),
    ("camera_path", entry::camera_path),
    ("dataset", entry::dataset),
    ("ply", entry::ply),
    ("serialized", entry::serialized),
    ("texture", entry::texture),
    ("spectrum", entry::spectrum),
    ("meter_points", entry::meter_points),
    ("cluster_wire", entry::cluster_wire),
    ("mitsuba_include", entry::mitsuba_include),
    ("radiance", entry::radiance),
];

#[test]
fn every_input_that_ever_crashed_a_fuzz_target_is_handled() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/fuzz-regressions");
    let mut replayed = 0;
    for (target, run) in TARGETS {
        let dir = root.join(target);
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        let mut inputs: Vec<_> = entries.map(|e| e.unwrap().path()).filter(|p| p.is_file()).collect();
        inputs.sort();
        for input in inputs {
            let data = std::fs::read(&input).unwrap();
            eprintln!("replaying {target}/{}", input.file_name().unwrap().to_string_lossy());
            run(&data);
            replayed += 1;
        }
    }
    eprintln!("{replayed} inputs replayed");
    entry::remove_scratch();
}

/// The seeds the targets start from (`fuzz/seed-corpus.sh` copies them from `testdata/`) pass
/// through the same entry points: each target's harness works on stable too, and a seed that
/// stopped loading would show here.
#[test]
fn the_seed_inputs_run_through_every_entry_point() {
    let data = |rel: &str| {
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata").join(rel)).unwrap()
    };
    entry::mitsuba(&data("scenes/cornell/scene.xml"));
    entry::vrml(&data("vrml/cornell.wrl"));
    let obj = [data("obj/cornell.obj"), b"\n#MTL\n".to_vec(), data("obj/cornell.mtl")].concat();
    entry::obj_mtl(&obj);
    entry::ies(&data("ies/asymmetric-wallwasher.ies"));
    entry::gltf(&data("../fuzz/seeds/gltf/cornell.glb"));
    entry::dataset(&data("datasets/cornell-v2.opds"));
    entry::ply(&data("mitsuba/shapes/meshes/octa.ply"));
    entry::serialized(&data("mitsuba/shapes/meshes/two.serialized"));
    entry::texture(&data("mitsuba/textures/stripes.png"));
    entry::texture(&data("mitsuba/envmap/sky.exr"));
    entry::texture(&data("../fuzz/seeds/texture/tiny.jpg"));
    entry::texture(&data("../fuzz/seeds/texture/rle.hdr"));
    entry::spectrum(&data("../fuzz/seeds/spectrum/measured.spd"));
    entry::meter_points(&data("../fuzz/seeds/meter_points/grid.csv"));
    for message in ["job", "blocks", "ready", "chunks", "request"] {
        entry::cluster_wire(&data(&format!("../fuzz/seeds/cluster_wire/{message}.bin")));
    }
    entry::mitsuba_include(&data("mitsuba/shapes/parts/bsdfs.xml"));
    entry::mitsuba_include(&data("../fuzz/seeds/mitsuba_include/nested.xml"));
    entry::radiance(&data("radiance/cornell.rad"));
    entry::radiance(&data("../fuzz/seeds/radiance/include-and-shapes"));
    entry::camera_path(br#"{"fps": 4, "size": [8, 8], "keyframes": [
        {"time": 0, "eye": [0, 0, 3.9], "target": [0, 0, 0]}, {"time": 1, "eye": [1, 0, 3.9], "target": [0, 0, 0]}]}"#);
    entry::remove_scratch();
}
