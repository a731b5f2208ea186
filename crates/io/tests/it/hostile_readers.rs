//! Hostile input for every reader, through the public loaders (issue 10's reader items): deep
//! nesting, entity bombs, `USE` bombs, special files and huge declared sizes are each a clear
//! error naming the file and line, found before memory or the stack grows. The readers' ordinary
//! errors are in each format's own test file; inputs found by fuzzing are replayed by
//! `fuzz_regressions.rs`.

use opticks_testkit::files as common;

use common::*;
use opticks_io::LoadOptions;
use opticks_io::scene_formats::mitsuba;
use std::path::Path;

fn mitsuba_err(xml: &str) -> String {
    match mitsuba::parse(xml, Path::new("dir/test.xml"), &LoadOptions::default()) {
        Ok(_) => panic!("should fail:\n{}", &xml[..xml.len().min(300)]),
        Err(e) => e.to_string(),
    }
}

/// Issue 10, item 17: 8,500 nested `<bsdf type="twosided">` (246 KB) overflowed the stack.
#[test]
fn deeply_nested_mitsuba_elements_are_an_error_not_a_stack_overflow() {
    for n in [65, 8_500, 100_000] {
        let xml = format!(
            "<scene version=\"3.0.0\">\n<shape type=\"rectangle\">{}<bsdf type=\"diffuse\"/>{}</shape></scene>",
            "<bsdf type=\"twosided\">".repeat(n),
            "</bsdf>".repeat(n)
        );
        let e = mitsuba_err(&xml);
        assert!(
            e.starts_with("dir/test.xml:2:") && e.contains("nested more than 64 levels deep"),
            "{n}: {e}"
        );
    }
    // 60 levels are fine (and Mitsuba's twosided of twosided is refused by the BSDF rules, not
    // by depth).
    let ok = format!(
        "<scene version=\"3.0.0\"><shape type=\"rectangle\">{}<bsdf type=\"diffuse\"/>{}</shape></scene>",
        "<transform name=\"x\">".repeat(2),
        "</transform>".repeat(2)
    );
    let e = mitsuba::parse(&ok, Path::new("t.xml"), &LoadOptions::default()).err().map(|e| e.to_string());
    assert!(e.as_ref().is_none_or(|e| !e.contains("nested")), "{e:?}");
}

/// Issue 10, item 19: one flat 100 KB entity referenced 1,000 times cost 6.3 s and 590 MB
/// (20,000 times: over 60 s, 2 GB). Declared entities are refused before the parser expands
/// them (Mitsuba does not expand them either); predefined entities still work.
#[test]
fn declared_xml_entities_are_refused_before_expansion() {
    let xml = format!(
        "<?xml version=\"1.0\"?>\n<!DOCTYPE scene [\n  <!ENTITY e \"{}\">\n]>\n<scene version=\"3.0.0\">{}</scene>",
        "a".repeat(100_000),
        "<string name=\"x\" value=\"&e;\"/>".repeat(20_000)
    );
    let e = mitsuba_err(&xml);
    assert!(
        e.starts_with("dir/test.xml:3:3:") && e.contains("<!ENTITY> declarations are not supported"),
        "{e}"
    );
    let plain =
        "<!DOCTYPE scene>\n<scene version=\"3.0.0\"><shape type=\"rectangle\" id=\"a&amp;b&#x41;\"/></scene>";
    let s = mitsuba::parse(plain, Path::new("t.xml"), &LoadOptions::default()).unwrap();
    assert_eq!(s.description.meshes[0].name, "a&bA");
}

/// Issue 10, item 19: `/dev/zero` as a mesh, MTL or buffer path was read until memory ran out,
/// a FIFO blocked forever. Special files are refused by name, for every file a scene refers to.
#[cfg(unix)]
#[test]
fn special_files_are_refused_wherever_a_scene_names_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n";
    for special in ["/dev/zero", fifo.to_str().unwrap()] {
        let cases: Vec<(&str, String)> = vec![
            (
                "scene.xml",
                format!(
                    "<scene version=\"3.0.0\"><shape type=\"obj\"><string name=\"filename\" value=\"{special}\"/></shape></scene>"
                ),
            ),
            ("scene.obj", format!("mtllib {special}\n{quad}")),
            ("scene.rad", format!("!xform -t 1 0 0 {special}\n")),
            (
                "scene.gltf",
                format!(
                    "{{\"asset\":{{\"version\":\"2.0\"}},\"buffers\":[{{\"uri\":\"{special}\",\"byteLength\":12}}]}}"
                ),
            ),
        ];
        for (name, text) in cases {
            let (_d, r) = load_files(&[(name, text.as_bytes())]);
            let msg = match r {
                Ok(s) => s.warnings.join("\n"), // a missing MTL library is a warning
                Err(e) => e.to_string(),
            };
            assert!(msg.contains("not a regular file"), "{name} → {special}: {msg}");
        }
        let e = opticks_io::load_scene(Path::new(special)).unwrap_err().to_string();
        assert!(e.contains("not a regular file") || e.contains("unsupported"), "{special}: {e}");
        let e = opticks_io::ies::load_ies(Path::new(special)).unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{e}");
        let e = opticks_io::dataset_file::DatasetReader::open(Path::new(special)).unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{e}");
        let e =
            opticks_io::camera_path_file::read_camera_path(Path::new(special), 45.0).unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{e}");
    }
}

/// Issue 26: `<include>` and `<spectrum filename>` read through `std::fs` directly, past the
/// regular-file check: `/dev/zero` was read until memory ran out, a FIFO blocked forever. Each
/// load runs on a thread of its own so that a regression fails here instead of hanging (the
/// FIFO first: if it blocks, `/dev/zero` is never tried). PLY and serialized meshes too.
#[cfg(unix)]
#[test]
fn includes_and_spectrum_files_refuse_special_files_quickly() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    for special in [fifo.to_str().unwrap().to_string(), "/dev/zero".to_string()] {
        let cases = [
            ("include", format!("<scene version=\"3.0.0\"><include filename=\"{special}\"/></scene>")),
            (
                "spectrum",
                format!(
                    "<scene version=\"3.0.0\"><bsdf type=\"diffuse\" id=\"b\"><spectrum name=\"reflectance\" \
                     filename=\"{special}\"/></bsdf><shape type=\"rectangle\"><ref id=\"b\"/></shape></scene>"
                ),
            ),
            (
                "ply",
                format!(
                    "<scene version=\"3.0.0\"><shape type=\"ply\"><string name=\"filename\" value=\"{special}\"/></shape></scene>"
                ),
            ),
            (
                "serialized",
                format!(
                    "<scene version=\"3.0.0\"><shape type=\"serialized\"><string name=\"filename\" value=\"{special}\"/></shape></scene>"
                ),
            ),
        ];
        for (what, xml) in cases {
            let (tx, rx) = std::sync::mpsc::channel();
            std::thread::spawn(move || {
                let (_d, r) = load_files(&[("scene.xml", xml.as_bytes())]);
                let _ = tx.send(r.map(|_| ()).map_err(|e| e.to_string()));
            });
            let r = rx.recv_timeout(std::time::Duration::from_secs(20));
            let e = match r {
                Ok(Err(e)) => e,
                Ok(Ok(())) => panic!("{what} → {special}: loaded"),
                Err(_) => panic!("{what} → {special}: no answer within 20 s"),
            };
            assert!(
                e.contains("scene.xml:1:") && e.contains("not a regular file"),
                "{what} → {special}: {e}"
            );
        }
    }
}
