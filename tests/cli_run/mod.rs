//! Running the `opticks` binary from the end-to-end tests of the CLI package (which alone has
//! `CARGO_BIN_EXE_opticks`): run it in a folder, expect success or a clean failure.

#![allow(dead_code)] // each test binary uses a different subset

use std::path::Path;
use std::process::{Command, Output};

/// Runs `opticks ARGS` in `dir` with extra environment variables.
pub fn opticks_env(args: &[&str], dir: &Path, env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_opticks"));
    c.args(args).current_dir(dir);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("runs opticks")
}

/// Runs `opticks ARGS` in `dir`.
pub fn opticks(args: &[&str], dir: &Path) -> Output {
    opticks_env(args, dir, &[])
}

/// Runs it, expects success, returns stdout and stderr.
pub fn ok(args: &[&str], dir: &Path) -> String {
    let out = opticks(args, dir);
    let (so, se) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "opticks {args:?} failed:\nstdout: {so}\nstderr: {se}");
    format!("{so}{se}")
}

/// Runs it, expects a clean failure (an `error:` line, no panic), returns stderr.
pub fn fails(args: &[&str], dir: &Path) -> String {
    let out = opticks(args, dir);
    let se = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "expected {args:?} to fail; stderr: {se}");
    assert!(se.lines().any(|l| l.starts_with("error: ")) && !se.contains("panicked"), "{se}");
    se
}
