//! House rules that a compiler does not check (rust-analyzer's "tidy" tests): every Rust source
//! file opens with `//!` module docs saying what lives there and why, and each crate has one
//! integration-test binary (`tests/it/`) besides the few that need a process of their own.

use opticks_testkit::files::files_with_extension;
use std::path::Path;

#[test]
fn every_source_file_has_module_docs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = Vec::new();
    for dir in ["crates", "fuzz/src", "fuzz/fuzz_targets"] {
        files_with_extension(&root.join(dir), "rs", &mut files);
    }
    assert!(files.len() > 20, "found only {} files", files.len());
    let missing: Vec<_> = files
        .iter()
        .filter(|f| !std::fs::read_to_string(f).unwrap().trim_start().starts_with("//!"))
        .map(|f| f.strip_prefix(&root).unwrap_or(f).display().to_string())
        .collect();
    assert!(missing.is_empty(), "files without `//!` module docs: {missing:#?}");
}

/// Every test executable links the whole workspace again: one per crate (`tests/it/main.rs`
/// with a module per subject, helpers in `opticks-testkit`), plus only those that need a process
/// of their own (a process-wide allocator peak, MPI).
#[test]
fn one_integration_test_binary_per_crate() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let own_process = ["crates/io/tests/peak_memory.rs", "crates/cli/tests/cluster.rs"];
    let mut binaries = Vec::new();
    for krate in std::fs::read_dir(root.join("crates")).unwrap() {
        let tests = krate.unwrap().path().join("tests");
        let Ok(entries) = std::fs::read_dir(&tests) else { continue };
        for entry in entries {
            let path = entry.unwrap().path();
            let rel = path.strip_prefix(&root).unwrap().display().to_string();
            if path.is_dir() {
                assert!(
                    path.ends_with("it") && path.join("main.rs").is_file(),
                    "{rel}: tests go in tests/it/"
                );
                binaries.push(rel);
            } else if path.extension().is_some_and(|e| e == "rs") {
                assert!(
                    own_process.contains(&rel.as_str()),
                    "{rel}: a test binary of its own; make it a module of tests/it/"
                );
                binaries.push(rel);
            }
        }
    }
    assert!(binaries.len() <= 6, "{} integration-test binaries: {binaries:#?}", binaries.len());
    assert!(
        !root.join("tests").exists(),
        "tests/ at the root: integration tests live in their crate's tests/it/"
    );
}

/// ARCHITECTURE's invariant on the core's imports: sensors may use what the dataset stores, but
/// nothing in `dataset/` or `trace/` reaches into `sensor/` (the tracer and the stored data must
/// not depend on how a camera reads them).
#[test]
fn dataset_and_trace_never_import_from_sensor() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../core/src");
    let mut files = Vec::new();
    for dir in ["dataset", "trace"] {
        files_with_extension(&src.join(dir), "rs", &mut files);
    }
    assert!(files.len() > 10, "found only {} files", files.len());
    let offenders: Vec<_> = files
        .iter()
        .flat_map(|f| {
            let text = std::fs::read_to_string(f).unwrap();
            let rel = f.strip_prefix(&src).unwrap().display().to_string();
            text.lines()
                .enumerate()
                .filter(|(_, l)| {
                    let code = l.split("//").next().unwrap_or("");
                    code.contains("crate::sensor") || code.contains("super::sensor")
                })
                .map(|(i, l)| format!("{rel}:{}: {}", i + 1, l.trim()))
                .collect::<Vec<_>>()
        })
        .collect();
    assert!(offenders.is_empty(), "dataset/trace import from sensor: {offenders:#?}");
}

/// Issue 24's sizes: no library or binary source file over 800 lines (a file that long holds
/// more than one job), and the CLI under 3,000 lines (it parses, calls the libraries and
/// prints; what a second front end needs lives in them).
#[test]
fn source_files_and_the_cli_stay_small() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = Vec::new();
    files_with_extension(&root.join("crates"), "rs", &mut files);
    let lines = |f: &Path| std::fs::read_to_string(f).unwrap().lines().count();
    let sources: Vec<_> = files.iter().filter(|f| f.components().all(|c| c.as_os_str() != "tests")).collect();
    let long: Vec<_> = (sources.iter())
        .filter(|f| lines(f) > 800)
        .map(|f| format!("{} ({} lines)", f.strip_prefix(&root).unwrap_or(f).display(), lines(f)))
        .collect();
    assert!(long.is_empty(), "source files over 800 lines: {long:#?}");
    let cli = root.join("crates/cli/src");
    let cli_lines: usize = sources.iter().filter(|f| f.starts_with(&cli)).map(|f| lines(f)).sum();
    assert!(cli_lines > 1000 && cli_lines < 3000, "the CLI has {cli_lines} lines");
}
