//! Hostile input and huge requests end to end, through the `opticks` binary (issue 10's crash
//! and memory items): each is a clear error naming what is wrong, or work that starts at once
//! and stops on Ctrl-C — never an abort, a panic, a signal or an allocation sized by an unchecked
//! number. The readers' own hostile-input tests are beside them (`crates/io/tests/`), and every
//! input a fuzzer ever crashed is replayed by `crates/io/tests/it/fuzz_regressions.rs`.

use crate::cli_run;
use opticks_testkit as common;

use cli_run::*;
#[allow(unused_imports)]
use common::*;
use opticks_io::dataset_file::{DatasetReader, DatasetWriter, read_all};

/// Issue 10, item 10: `--paths 18446744073709551615` aborted allocating 2·10¹⁷ bytes of block
/// plan. Now the plan is lazy and a count beyond the documented bound (2^53) is refused before
/// anything is written.
#[test]
fn path_counts_beyond_the_bound_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let e =
        fails(&["trace", "builtin:cornell", "--paths", "18446744073709551615", "-o", "a.opds"], dir.path());
    assert!(e.contains("a.opds") && e.contains("maximum of 9007199254740992 paths"), "{e}");
    assert!(files(dir.path()).is_empty(), "nothing written: {:?}", files(dir.path()));
}

/// Issue 10, item 10: `--paths 10^12` spent a minute and 11.4 GB planning, deaf to Ctrl-C. The
/// plan is now made a batch at a time: the trace starts at once and an interrupt saves a partial.
#[test]
fn a_huge_trace_starts_at_once_and_stops_on_ctrl_c() {
    let dir = tempfile::tempdir().unwrap();
    let child =
        start(&["trace", "builtin:cornell", "--paths", "1000000000000", "-o", "big.opds"], dir.path());
    std::thread::sleep(std::time::Duration::from_millis(1500));
    signal(&child, "-INT");
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("big.partial.opds"), "{err}");
    let partial = DatasetReader::open(&dir.path().join("big.partial.opds")).unwrap();
    assert_eq!(partial.header().trace.passes[0].planned_paths(), 1_000_000_000_000);
    assert!(partial.header().table.total_paths() > 0, "tracing had started");
}

/// Issue 10, item 15: a dataset with valid checksums whose sample names triangle 2147483647 of
/// a 36-triangle scene panicked `render` (index out of bounds) while `info` called it verified.
/// Both now refuse it, naming the file and the sample's byte offset.
#[test]
fn a_sample_naming_a_missing_triangle_is_refused_by_render_and_info() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = opticks(&["trace", "builtin:cornell", "--paths", "20000", "-o", "good.opds"], d);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (header, mut chunks) = read_all(&d.join("good.opds")).unwrap();
    chunks[1].samples[2].prim = 2_147_483_647;
    let mut w = DatasetWriter::create(&d.join("bad.opds"), &header).unwrap();
    for c in &chunks {
        w.write_chunk(c).unwrap();
    }
    w.finish(&header.table, &header.trace).unwrap();
    for verb in ["render", "info"] {
        let args: &[&str] =
            if verb == "render" { &["render", "bad.opds", "-o", "x.exr"] } else { &["info", "bad.opds"] };
        let e = fails(args, d);
        assert!(
            e.contains("bad.opds") && e.contains("byte") && e.contains("triangle 2147483647 does not exist"),
            "{verb}: {e}"
        );
    }
    assert!(!d.join("x.exr").exists());
    let info = opticks(&["info", "good.opds"], d);
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(
        info.status.success() && text.contains("every sample checked against its scene's 36 triangles"),
        "{text}"
    );
}

/// Issue 10, items 11 and 18: `render --size 32768x32768` (the documented maximum: a 25.8 GB
/// film) and `measure --cells 65536x65536` (103 GB) aborted or were killed after the trace had
/// been read. A film that cannot fit in the memory available is refused before any work, and
/// sizes beyond the maximum, from the command line or a scene file, are refused as they are read.
#[test]
fn films_that_cannot_fit_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = opticks(&["trace", "builtin:cornell", "--paths", "5000", "-o", "c.opds"], d);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let available = opticks_io::memory::available_bytes().unwrap_or(u64::MAX);
    if available < 40 << 30 {
        let e = fails(&["render", "c.opds", "-o", "big.exr", "--size", "32768x32768"], d);
        assert!(e.contains("an image of 32768x32768 needs about") && e.contains("available"), "{e}");
        assert!(!d.join("big.exr").exists());
    }
    // A meter holds per-cell error statistics per light and thread: at most 65536 cells, refused
    // as the argument is read.
    let e = fails(&["measure", "c.opds", "--surface", "red", "--cells", "65536x65536", "-o", "m.csv"], d);
    assert!(e.contains("at most 65536 cells in all"), "{e}");
    let e = fails(&["render", "c.opds", "-o", "x.exr", "--size", "32769x2"], d);
    assert!(e.contains("image size 32769x2 must be between 1x1 and 32768x32768"), "{e}");
    // Scene files: a Mitsuba film of 100000² and a VRML PhysicalViewpoint of 2147483647².
    let xml = "<scene version=\"3.0.0\"><sensor type=\"perspective\"><film type=\"hdrfilm\">\
               <integer name=\"width\" value=\"100000\"/><integer name=\"height\" value=\"100000\"/></film>\
               </sensor><shape type=\"rectangle\"><emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/>\
               </emitter></shape></scene>";
    std::fs::write(d.join("film.xml"), xml).unwrap();
    let e = fails(&["trace", "film.xml", "--paths", "100", "-o", "f.opds"], d);
    assert!(
        e.contains("film.xml:1:") && e.contains("width 100000 must be an integer from 1 to 32768"),
        "{e}"
    );
    let wrl = "#VRML V2.0 utf8\nPROTO PhysicalViewpoint [ field SFVec3f position 0 0 10 field SFRotation orientation 0 0 1 0 \
               field SFFloat fieldOfView 0.785398 field SFString description \"\" field SFInt32 width 512 \
               field SFInt32 height 512 ] { Viewpoint { position IS position orientation IS orientation \
               fieldOfView IS fieldOfView description IS description } }\n\
               PhysicalViewpoint { width 2147483647 height 2147483647 }\n";
    std::fs::write(d.join("v.wrl"), wrl).unwrap();
    let e = fails(&["trace", "v.wrl", "--paths", "100", "-o", "v.opds"], d);
    assert!(e.contains("v.wrl:") && e.contains("2147483647x2147483647 must be between"), "{e}");
}

/// Issue 12: a Mitsuba film's crop window and reconstruction filter are checked where the file
/// gives them — a window outside the film, a negative or empty size, an unknown filter, a
/// stddev that is not a finite positive number — each refused with the file and line, never a
/// panic.
#[test]
fn bad_crops_and_filters_are_refused_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let scene = |film: &str| {
        format!(
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\">\n<film type=\"hdrfilm\">\n\
             <integer name=\"width\" value=\"32\"/><integer name=\"height\" value=\"24\"/>\n{film}\n</film>\n\
             </sensor>\n<shape type=\"rectangle\"><emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/>\
             </emitter></shape>\n</scene>\n"
        )
    };
    let cases = [
        (
            "<integer name=\"crop_offset_x\" value=\"30\"/><integer name=\"crop_width\" value=\"8\"/>",
            "crop window",
        ),
        ("<integer name=\"crop_offset_y\" value=\"-2\"/>", "crop_offset_y -2 must be a non-negative integer"),
        ("<integer name=\"crop_width\" value=\"-8\"/>", "crop_width -8 must be a non-negative integer"),
        ("<integer name=\"crop_height\" value=\"0\"/>", "must be at least 1x1"),
        ("<integer name=\"crop_offset_x\" value=\"4\"/>", "lie within the 32x24 film"),
        ("<rfilter type=\"mitchell\"/>", "unsupported reconstruction filter \"mitchell\""),
        (
            "<rfilter type=\"gaussian\"><float name=\"stddev\" value=\"nan\"/></rfilter>",
            "\"nan\" is not a finite number",
        ),
        (
            "<rfilter type=\"gaussian\"><float name=\"stddev\" value=\"1e30\"/></rfilter>",
            "radius of at most 16 pixels",
        ),
        ("<rfilter type=\"gaussian\"><float name=\"stddev\" value=\"-1\"/></rfilter>", "gaussian stddev -1"),
        ("<rfilter type=\"tent\"><float name=\"radius\" value=\"0\"/></rfilter>", "tent radius 0"),
        ("<rfilter type=\"box\"/><rfilter type=\"tent\"/>", "one <rfilter>"),
    ];
    for (k, (film, message)) in cases.iter().enumerate() {
        let path = dir.path().join(format!("bad{k}.xml"));
        std::fs::write(&path, scene(film)).unwrap();
        let e = match opticks_io::scene_formats::load_scene(&path) {
            Ok(_) => panic!("{film}: accepted"),
            Err(e) => format!("{e:#}"),
        };
        assert!(e.contains(&format!("bad{k}.xml:5:")) && e.contains(message), "{film}: {e}");
    }
    // A good one loads: the crop is the image, the filter the file's.
    let path = dir.path().join("good.xml");
    let film = "<integer name=\"crop_offset_x\" value=\"4\"/><integer name=\"crop_width\" value=\"20\"/>\
                <rfilter type=\"tent\"/>";
    std::fs::write(&path, scene(film)).unwrap();
    let loaded = opticks_io::scene_formats::load_scene(&path).unwrap();
    let sensor = opticks_core::sensor::Sensor::new(&loaded.description.camera.unwrap()).unwrap();
    assert_eq!((sensor.width(), sensor.height()), (20, 24));
}
