//! The entry points of the fuzz targets, one per reader, shared by the cargo-fuzz binaries
//! (`fuzz/fuzz_targets/`, nightly) and the stable regression test that replays every input that
//! ever crashed (`crates/io/tests/it/fuzz_regressions.rs`, which includes this file by path).
//!
//! Each entry point feeds the bytes to a reader through its public API, exactly as a user's file
//! reaches it (written to a file in a private temporary folder when the reader takes a path), and
//! then exercises whatever loaded: the scene build (bad values bite there), a short trace and a
//! tiny render. Errors are the expected outcome for almost every input; what a target reports is
//! a panic, an abort, a hang, a stack overflow or an out-of-memory, and the invariants asserted
//! here: every traced sample is finite with β ≥ 0 (a dataset writer would refuse it), and every
//! rendered pixel is finite.

use opticks_core::dataset::{Chunk, check_scene, lighting};
use opticks_core::scene::{CameraDesc, Scene, cornell_box};
use opticks_core::sensor::{Pinhole, SampleBatch, Sensor, render};
use opticks_core::trace::{TraceSettings, trace};
use opticks_io::LoadedScene;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

thread_local! {
    /// A folder of this thread's own for the files the readers are given.
    static SCRATCH: PathBuf = {
        let base = Path::new("/dev/shm");
        let base = if base.is_dir() { base.to_path_buf() } else { std::env::temp_dir() };
        let id = format!("{:?}", std::thread::current().id()).replace(|c: char| !c.is_ascii_digit(), "");
        let dir = base.join(format!("opticks-fuzz-{}-{id}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("cannot create the fuzz scratch folder");
        dir
    };
}

fn scratch() -> PathBuf {
    SCRATCH.with(|d| d.clone())
}

/// Removes this thread's scratch folder (the regression test's cleanup; a fuzzing process
/// leaves it, with the last input in it, for inspection).
pub fn remove_scratch() {
    let _ = std::fs::remove_dir_all(scratch());
}

/// Writes `data` to `name` in the scratch folder; returns its path.
fn file(name: &str, data: &[u8]) -> PathBuf {
    let path = scratch().join(name);
    std::fs::write(&path, data).expect("cannot write a fuzz input file");
    path
}

/// Builds, traces and renders a loaded scene, checking the invariants of the module docs.
fn exercise(loaded: &LoadedScene) {
    let Ok(scene) = Scene::build(&loaded.description) else { return };
    let settings = TraceSettings { paths: 16, seed: 1, ..Default::default() };
    let mut chunks: Vec<Chunk> = Vec::new();
    let table = match trace(
        &scene,
        &settings,
        |c| {
            chunks.push(c);
            Ok::<_, ()>(())
        },
        |_| {},
    ) {
        Ok(t) => t,
        Err(()) => unreachable!("the sink never fails"),
    };
    for s in chunks.iter().flat_map(|c| &c.samples) {
        assert!(s.position.iter().all(|x| x.is_finite()), "traced a non-finite position {s:?}");
        assert!(s.beta.iter().all(|b| *b >= 0.0 && b.is_finite()), "traced an invalid β {s:?}");
        assert!((s.triangle() as usize) < scene.triangles.len(), "traced a missing triangle {s:?}");
    }
    let Some(camera) = loaded.description.camera else { return };
    let small = CameraDesc { width: camera.width.min(8), height: camera.height.min(8), ..camera };
    let Ok(pinhole) = Pinhole::new(&small) else { return };
    let sensor: Sensor = pinhole.into();
    let batch = |i: usize| {
        let c: &Chunk = &chunks[i];
        Ok::<_, ()>(SampleBatch { flux_per_path: table.flux_per_path(c.light as usize), samples: &c.samples })
    };
    let film = render(&scene, &sensor, chunks.len(), batch, |_| {}).unwrap_or_else(|()| unreachable!());
    assert!(film.pixels.iter().flatten().all(|x| x.is_finite()), "rendered a non-finite pixel");
}

/// A Mitsuba 3 XML scene (meshes it names are looked up beside it, in the scratch folder).
pub fn mitsuba(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let path = scratch().join("fuzz.xml");
    if let Ok(loaded) = opticks_io::scene_formats::mitsuba::parse(text, &path, &Default::default()) {
        exercise(&loaded);
    }
}

/// A VRML97 scene (plain or gzip-compressed).
pub fn vrml(data: &[u8]) {
    if let Ok(loaded) = opticks_io::load_scene(&file("fuzz.wrl", data)) {
        exercise(&loaded);
    }
}

/// An OBJ scene and its MTL library: the input is the OBJ text, then, after a line `#MTL`, the
/// MTL text (the OBJ names the library `fuzz.mtl` first).
pub fn obj_mtl(data: &[u8]) {
    let (obj, mtl) = match data.windows(6).position(|w| w == b"\n#MTL\n") {
        Some(i) => (&data[..i], &data[i + 6..]),
        None => (data, &b""[..]),
    };
    file("fuzz.mtl", mtl);
    let obj = [&b"mtllib fuzz.mtl\n"[..], obj].concat();
    if let Ok(loaded) = opticks_io::load_scene(&file("fuzz.obj", &obj)) {
        exercise(&loaded);
    }
}

/// A Radiance scene and a file it may include: the input is the scene text, then, after a line
/// `#INC`, the text of `inc.rad` (which the scene includes with `!xform … inc.rad`; it may
/// include itself or the scene, a cycle the reader refuses).
pub fn radiance(data: &[u8]) {
    let (scene, inc) = match data.windows(6).position(|w| w == b"\n#INC\n") {
        Some(i) => (&data[..i], &data[i + 6..]),
        None => (data, &b""[..]),
    };
    file("inc.rad", inc);
    if let Ok(loaded) = opticks_io::load_scene(&file("fuzz.rad", scene)) {
        exercise(&loaded);
    }
}

/// A glTF 2.0 scene: binary (GLB) if it starts with the GLB magic, else JSON.
pub fn gltf(data: &[u8]) {
    let name = if data.starts_with(b"glTF") { "fuzz.glb" } else { "fuzz.gltf" };
    if let Ok(loaded) = opticks_io::load_scene(&file(name, data)) {
        exercise(&loaded);
    }
}

/// An IES LM-63 file, read alone and then as the profile of a Mitsuba `ies` emitter lighting a
/// floor (so the table also goes through the core's checks, sampling grid and tracer).
pub fn ies(data: &[u8]) {
    let path = file("fuzz.ies", data);
    if opticks_io::ies::load_ies(&path).is_err() {
        return;
    }
    let xml = "<scene version=\"3.0.0\">\
        <sensor type=\"perspective\"><float name=\"fov\" value=\"60\"/>\
        <transform name=\"to_world\"><lookat origin=\"0,3,3\" target=\"0,0,0\" up=\"0,1,0\"/></transform></sensor>\
        <emitter type=\"ies\"><string name=\"filename\" value=\"fuzz.ies\"/><point name=\"position\" value=\"0,1,0\"/></emitter>\
        <shape type=\"rectangle\"><transform name=\"to_world\"><rotate x=\"1\" angle=\"-90\"/><scale value=\"4\"/></transform></shape>\
        </scene>";
    if let Ok(loaded) =
        opticks_io::scene_formats::mitsuba::parse(xml, &scratch().join("ies.xml"), &Default::default())
    {
        exercise(&loaded);
    }
}

/// A Mitsuba scene of one mesh shape `shape` (its other properties in `params`), a camera and
/// a constant environment, so that whatever loads is also built, traced and rendered.
fn mesh_scene(shape: &str, params: &str) {
    let xml = format!(
        "<scene version=\"3.0.0\">\
         <sensor type=\"perspective\"><float name=\"fov\" value=\"60\"/>\
         <transform name=\"to_world\"><lookat origin=\"0,0,4\" target=\"0,0,0\" up=\"0,1,0\"/></transform></sensor>\
         <emitter type=\"constant\"/><shape type=\"{shape}\">{params}</shape></scene>"
    );
    let path = scratch().join(format!("{shape}.xml"));
    if let Ok(loaded) = opticks_io::scene_formats::mitsuba::parse(&xml, &path, &Default::default()) {
        exercise(&loaded);
    }
}

/// A PLY mesh (ASCII or binary), loaded by a Mitsuba `ply` shape, then again with its vertex
/// colours asked for (so the attribute reader runs too; a file without them is an error there).
pub fn ply(data: &[u8]) {
    file("fuzz.ply", data);
    let filename = "<string name=\"filename\" value=\"fuzz.ply\"/>";
    mesh_scene("ply", filename);
    mesh_scene(
        "ply",
        &format!(
            "{filename}<bsdf type=\"diffuse\"><texture type=\"mesh_attribute\" name=\"reflectance\">\
             <string name=\"name\" value=\"vertex_color\"/></texture></bsdf>"
        ),
    );
}

/// A Mitsuba `.serialized` mesh file, its meshes 0 and 1 each loaded by a `serialized` shape.
pub fn serialized(data: &[u8]) {
    file("fuzz.serialized", data);
    for index in 0..2 {
        mesh_scene(
            "serialized",
            &format!(
                "<string name=\"filename\" value=\"fuzz.serialized\"/><integer name=\"shape_index\" value=\"{index}\"/>"
            ),
        );
    }
}

/// A walkthrough camera path (JSON keyframes), evaluated at its ends and between.
pub fn camera_path(data: &[u8]) {
    let Ok(walk) = opticks_io::camera_path_file::read_camera_path(&file("fuzz.json", data), 45.0) else {
        return;
    };
    let (t0, t1) = walk.path.span();
    let (w, h) = walk.size.unwrap_or((8, 8));
    for k in 0..=4 {
        let t = t0 + (t1 - t0) * k as f32 / 4.0;
        let desc = walk.path.at(t, w, h);
        let _ = Pinhole::new(&desc);
    }
}

/// A dataset file: opened, every chunk read and checked; if it belongs to the built-in Cornell
/// box, also checked against it, lit and rendered as `render` does.
pub fn dataset(data: &[u8]) {
    static CORNELL: OnceLock<Scene> = OnceLock::new();
    let scene = CORNELL.get_or_init(|| Scene::build(&cornell_box()).expect("the built-in box builds"));
    let Ok(mut reader) = opticks_io::dataset_file::DatasetReader::open(&file("fuzz.opds", data)) else {
        return;
    };
    let _ = reader.verify();
    if check_scene(reader.header(), scene).is_err() {
        return;
    }
    reader.check_triangles(scene.triangles.len());
    let Ok(lit) = lighting(&reader.header().table, scene, &[]) else { return };
    let camera = CameraDesc { width: 8, height: 8, ..scene.camera.expect("the box has a camera") };
    let sensor: Sensor = Pinhole::new(&camera).expect("a valid camera").into();
    let batch = |i: usize| {
        reader.chunk(i).map(|c| opticks_core::sensor::OwnedBatch {
            flux_per_path: lit.flux_per_path[c.light as usize],
            samples: c.samples,
        })
    };
    if let Ok(film) = render(scene, &sensor, reader.chunk_count(), batch, |_| {}) {
        assert!(film.pixels.iter().flatten().all(|x| x.is_finite()), "rendered a non-finite pixel");
    }
}

/// An image file (PNG, JPEG, Radiance HDR, OpenEXR), read as a texture under each extension in
/// turn (`.png`: sRGB-decoded, the format guessed from the bytes; `.hdr`: linear; `.exr`), as
/// an in-memory glTF image, and as a reference image (`read_exr_rgb`, which `opticks bench`
/// calls without a texture's checks). Every image read holds as many texels as its size says.
pub fn texture(data: &[u8]) {
    let check = |t: opticks_io::texture_file::TextureImage| {
        assert_eq!(t.texels.len(), t.width * t.height, "a texture of the wrong size");
    };
    for (ext, raw) in [("png", false), ("hdr", false), ("exr", true)] {
        if let Ok(t) = opticks_io::texture_file::read_texture(&file(&format!("fuzz.{ext}"), data), raw) {
            check(t);
        }
    }
    if let Ok(t) = opticks_io::texture_file::decode_texture(data, true) {
        check(t);
    }
    if let Ok((w, h, rgb)) = opticks_io::image_file::read_exr_rgb(&scratch().join("fuzz.exr")) {
        assert_eq!(rgb.len(), w as usize * h as usize * 3, "an EXR image of the wrong size");
    }
}

/// A `.spd` spectrum file, named by a Mitsuba scene three times: as an emitter's radiance, a
/// diffuse reflectance (clamped) and a conductor's `eta` and `k` (unbounded), so each of the
/// conversions runs on it; whatever loads is built, traced and rendered.
pub fn spectrum(data: &[u8]) {
    file("fuzz.spd", data);
    let spd = |name: &str| format!("<spectrum name=\"{name}\" filename=\"fuzz.spd\"/>");
    let xml = format!(
        "<scene version=\"3.0.0\">\
         <sensor type=\"perspective\"><float name=\"fov\" value=\"60\"/>\
         <transform name=\"to_world\"><lookat origin=\"0,0,4\" target=\"0,0,0\" up=\"0,1,0\"/></transform></sensor>\
         <emitter type=\"constant\">{}</emitter>\
         <shape type=\"sphere\"><bsdf type=\"diffuse\">{}</bsdf></shape>\
         <shape type=\"rectangle\"><transform name=\"to_world\"><translate z=\"-2\"/></transform>\
         <bsdf type=\"conductor\">{}{}</bsdf></shape></scene>",
        spd("radiance"),
        spd("reflectance"),
        spd("eta"),
        spd("k"),
    );
    if let Ok(loaded) =
        opticks_io::scene_formats::mitsuba::parse(&xml, &scratch().join("spectrum.xml"), &Default::default())
    {
        exercise(&loaded);
    }
}

/// A meter points file (`opticks measure --points`): what it reads is a valid layout of finite
/// points with unit normals.
pub fn meter_points(data: &[u8]) {
    let Ok(points) = opticks_io::meter_points::read_points(&file("fuzz.csv", data)) else { return };
    for p in &points {
        assert!(p.position.is_finite(), "a non-finite point {p:?}");
        assert!((p.normal.length() - 1.0).abs() < 1e-4, "a normal not of unit length {p:?}");
    }
    opticks_core::sensor::meter::MeterLayout::points(points).expect("the points file gave a valid layout");
}

/// A cluster message (`opticks_io::cluster_wire`), given to the decoder of every kind; what
/// decodes encodes back to the same bytes (each decoder reads all of its message).
pub fn cluster_wire(data: &[u8]) {
    use opticks_io::cluster_wire as w;
    if let Ok(job) = w::decode_job(data) {
        assert_eq!(w::encode_job(&job), data, "a job that does not encode back");
    }
    if let Ok(blocks) = w::decode_blocks(data) {
        assert_eq!(w::encode_blocks(&blocks), data, "blocks that do not encode back");
    }
    if let Ok((host, want)) = w::decode_ready(data) {
        assert_eq!(w::encode_ready(&host, want), data, "a ready message that does not encode back");
    }
    if let Ok(chunks) = w::decode_chunks(data) {
        assert_eq!(w::encode_chunks(&chunks), data, "chunks that do not encode back");
    }
    if let Ok(want) = w::decode_request(data) {
        assert_eq!(w::encode_request(want), data, "a request that does not encode back");
    }
}

/// A Mitsuba file included by a scene (`<include filename="$inc"/>`, the name a `<default>`),
/// which also declares the parameters the seeds use (`$spp`, `$floor`) and a `<path>` folder
/// `parts` holding `box.xml` (a cube), so the included file can include that by its bare name.
pub fn mitsuba_include(data: &[u8]) {
    std::fs::create_dir_all(scratch().join("parts")).expect("cannot create the fuzz parts folder");
    file("parts/box.xml", b"<shape version=\"3.0.0\" type=\"cube\"><bsdf type=\"diffuse\"/></shape>");
    file("inc.xml", data);
    let xml = "<scene version=\"3.0.0\">\
        <default name=\"spp\" value=\"4\"/><default name=\"floor\" value=\"0.5\"/>\
        <default name=\"inc\" value=\"inc.xml\"/><path value=\"parts\"/>\
        <sensor type=\"perspective\"><float name=\"fov\" value=\"60\"/>\
        <transform name=\"to_world\"><lookat origin=\"0,0,4\" target=\"0,0,0\" up=\"0,1,0\"/></transform></sensor>\
        <emitter type=\"constant\"/><include filename=\"$inc\"/></scene>";
    if let Ok(loaded) =
        opticks_io::scene_formats::mitsuba::parse(xml, &scratch().join("main.xml"), &Default::default())
    {
        exercise(&loaded);
    }
}
