//! What the command line prints, and how much. Results (the one-line summary of what a verb
//! did) go to stdout; notes, warnings and details to stderr. `--quiet` keeps only warnings and
//! errors (no progress bars, no notes, no summary); `--verbose` adds details (the scene loaded,
//! the plan, the files written). Nothing here panics when the terminal has gone away (SIGHUP):
//! a failed write to it is ignored.
//! Also the number formats of messages: byte sizes, counts with their noun ("1 light").

use std::io::Write;
use std::sync::atomic::{AtomicU8, Ordering};

const QUIET: u8 = 0;
const NORMAL: u8 = 1;
const VERBOSE: u8 = 2;

static LEVEL: AtomicU8 = AtomicU8::new(NORMAL);

/// Sets the level from `--quiet` and `--verbose` (which clap keeps from being given together).
pub fn set_level(quiet: bool, verbose: bool) {
    let level = if quiet {
        QUIET
    } else if verbose {
        VERBOSE
    } else {
        NORMAL
    };
    LEVEL.store(level, Ordering::Relaxed);
}

/// Whether `--quiet` was given.
pub fn is_quiet() -> bool {
    LEVEL.load(Ordering::Relaxed) == QUIET
}

/// A verb's summary line (stdout; not with `--quiet`).
pub fn result(line: &str) {
    if !is_quiet() {
        let _ = writeln!(std::io::stdout(), "{line}");
    }
}

/// Machine-readable output that was asked for (`info --json`, bench's JSON line): always.
pub fn data(line: &str) {
    let _ = writeln!(std::io::stdout(), "{line}");
}

/// A note (stderr; not with `--quiet`).
pub fn note(msg: &str) {
    if !is_quiet() {
        let _ = writeln!(std::io::stderr(), "note: {msg}");
    }
}

/// A detail (stderr; only with `--verbose`).
pub fn detail(msg: &str) {
    if LEVEL.load(Ordering::Relaxed) == VERBOSE {
        let _ = writeln!(std::io::stderr(), "{msg}");
    }
}

/// A warning (stderr; always).
pub fn warning(msg: &str) {
    let _ = writeln!(std::io::stderr(), "warning: {msg}");
}

/// An error (stderr; always).
pub fn error(msg: &str) {
    let _ = writeln!(std::io::stderr(), "error: {msg}");
}

/// `n` bytes readably ([`opticks_io::memory::readable_bytes`]).
pub fn bytes(n: u64) -> String {
    opticks_io::memory::readable_bytes(n)
}

/// "1 light", "2 lights".
pub fn count(n: u64, noun: &str) -> String {
    if n == 1 { format!("1 {noun}") } else { format!("{n} {noun}s") }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_read_well() {
        assert_eq!(count(1, "light"), "1 light");
        assert_eq!(count(0, "light"), "0 lights");
        assert_eq!(count(3, "dataset"), "3 datasets");
    }
}
