//! Several meters in one `opticks measure` run (`--surface` and `--plane` repeated): one pass
//! over the dataset, one CSV whose first column names each line's meter, and every meter's lines
//! the same, to the bit, as that meter measured alone with the same settings (the CSV's `{:e}`
//! values round-trip exactly, so equal text is equal values). One meter's CSV has no such
//! column. Argument errors are refused before any work, and nothing is written.

use crate::cli_run::{fails, ok};
use opticks_testkit::files::testdata;

const WALLS: [&str; 6] = ["floor", "ceiling", "wall_xm", "wall_xp", "wall_ym", "wall_yp"];

/// The CSV `measure ARGS -o out.csv` writes in `d`.
fn measure(d: &std::path::Path, args: &[&str]) -> String {
    let mut all = vec!["measure", "b.opds", "-o", "out.csv"];
    all.extend(args);
    ok(&all, d);
    std::fs::read_to_string(d.join("out.csv")).unwrap()
}

/// `together` (a several-meter CSV) is `alone` (each meter's own CSV, in order, with its name)
/// line for line: the header with `meter,` before it, every line with the meter's name before it.
fn assert_same_as_alone(together: &str, alone: &[(String, String)]) {
    let mut lines = together.lines();
    let header = alone[0].1.lines().next().unwrap();
    assert_eq!(lines.next(), Some(format!("meter,{header}").as_str()));
    for (name, csv) in alone {
        assert!(!csv.starts_with("meter,"), "one meter's CSV has no meter column: {csv}");
        for line in csv.lines().skip(1) {
            assert_eq!(lines.next(), Some(format!("{name},{line}").as_str()), "meter {name}");
        }
    }
    assert_eq!(lines.next(), None, "nothing more");
}

#[test]
fn several_meters_in_one_run_read_what_each_reads_alone() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = testdata("cie171/box-80.xml");
    ok(&["trace", scene.to_str().unwrap(), "--paths", "20k", "-o", "b.opds"], d);

    // The samples estimator (a surface's default): the box's six walls, 2x3 cells each.
    let alone: Vec<(String, String)> =
        WALLS.iter().map(|w| (w.to_string(), measure(d, &["--surface", w, "--cells", "2x3"]))).collect();
    let mut args = vec!["--cells", "2x3"];
    WALLS.iter().for_each(|w| args.extend(["--surface", w]));
    let out = ok(&[&["measure", "b.opds", "-o", "all.csv"][..], &args].concat(), d);
    assert_same_as_alone(&std::fs::read_to_string(d.join("all.csv")).unwrap(), &alone);
    for w in WALLS {
        assert!(out.contains(&format!("{w}: 2x3 cells on")), "each meter's summary is named: {out}");
    }

    // The connections estimator, seeded, with direct samples: two walls, in the other order.
    let set = ["--estimator", "connections", "--seed", "7", "--direct-samples", "16", "--cells", "2x2"];
    let alone: Vec<(String, String)> = ["wall_yp", "floor"]
        .iter()
        .map(|w| (w.to_string(), measure(d, &[&["--surface", w][..], &set].concat())))
        .collect();
    let together = measure(d, &[&["--surface", "wall_yp", "--surface", "floor"][..], &set].concat());
    assert_same_as_alone(&together, &alone);

    // Planes in the air (connections, their default), named plane1, plane2 in order.
    let planes = ["-1,-1,1, 2,0,0, 0,2,0", "-1,1.4,0.2, 2,0,0, 0,0,2"];
    let alone: Vec<(String, String)> = planes
        .iter()
        .enumerate()
        .map(|(k, p)| (format!("plane{}", k + 1), measure(d, &["--plane", p, "--cells", "3x2"])))
        .collect();
    let together = measure(d, &["--plane", planes[0], "--plane", planes[1], "--cells", "3x2"]);
    assert_same_as_alone(&together, &alone);
}

#[test]
fn several_meters_refuse_what_cannot_mean_anything() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = testdata("cie171/box-00.xml");
    ok(&["trace", scene.to_str().unwrap(), "--paths", "4096", "-o", "b.opds"], d);
    let two = ["--surface", "floor", "--surface", "ceiling"];
    for (args, msg) in [
        (vec!["--png", "m.png"], "--png draws one meter's heat map, and 2 meters were given"),
        (vec!["--surface", "floor"], "--surface floor is given twice"),
        (vec!["--plane", "0,0,1,1,0,0,0,1,0"], "cannot be used with"),
        (vec!["--surface", "nope"], "no mesh named 'nope'"),
    ] {
        let mut all = vec!["measure", "b.opds", "-o", "never.csv"];
        all.extend(two);
        all.extend(args);
        let err = fails(&all, d);
        assert!(err.contains(msg), "{all:?}: {err}");
        assert!(!d.join("never.csv").exists() && !d.join("m.png").exists(), "{all:?} wrote something");
    }
    // One meter keeps its heat map.
    ok(&["measure", "b.opds", "--surface", "floor", "-o", "one.csv", "--png", "one.png"], d);
    assert!(d.join("one.png").exists());
}
