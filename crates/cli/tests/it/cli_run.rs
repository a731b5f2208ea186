//! Running the `opticks` binary from the end-to-end tests of the CLI package (which alone has
//! `CARGO_BIN_EXE_opticks`): run it in a folder, expect success or a clean failure, list what
//! it left there. Every end-to-end test that runs the binary uses these (one definition of what
//! "a clean failure" is).

#![allow(dead_code)] // each test binary uses a different subset

use std::path::Path;
use std::process::{Child, Command, Output, Stdio};

/// Starts `opticks ARGS` in `dir` (stderr piped, stdout dropped), for a test that signals it.
pub fn start(args: &[&str], dir: &Path) -> Child {
    Command::new(env!("CARGO_BIN_EXE_opticks"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts opticks")
}

/// Sends `signal` (as `kill` takes it: `-INT`, `-TERM`, `-KILL`) to `child`.
#[cfg(unix)]
pub fn signal(child: &Child, signal: &str) {
    assert!(Command::new("kill").args([signal, &child.id().to_string()]).status().unwrap().success());
}

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
#[track_caller]
pub fn ok(args: &[&str], dir: &Path) -> String {
    let out = opticks(args, dir);
    let (so, se) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "opticks {args:?} failed:\nstdout: {so}\nstderr: {se}");
    format!("{so}{se}")
}

/// Runs it, expects success, returns stdout alone (for output a test parses: `--help`, JSON).
#[track_caller]
pub fn stdout(args: &[&str], dir: &Path) -> String {
    let out = opticks(args, dir);
    let (so, se) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "opticks {args:?} failed:\nstdout: {so}\nstderr: {se}");
    so.into_owned()
}

/// Runs it, expects a clean failure, returns stderr: exit code 1 (an error) or 2 (clap's usage
/// errors) — never a signal (no exit code) or an abort (134) — with an `error:` line and no panic.
#[track_caller]
pub fn fails(args: &[&str], dir: &Path) -> String {
    let out = opticks(args, dir);
    let se = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(matches!(out.status.code(), Some(1 | 2)), "expected a clean failure of {args:?}; stderr: {se}");
    assert!(se.lines().any(|l| l.starts_with("error: ")) && !se.contains("panicked"), "{se}");
    se
}

/// The names of the files in `dir`, sorted.
pub fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}
