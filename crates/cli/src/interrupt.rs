//! Ctrl-C (and SIGTERM, what batch schedulers send): long work stops cleanly instead of dying
//! mid-write. The first Ctrl-C sets a flag that
//! the trace loop checks between batches; the paths traced so far are saved as a valid dataset
//! beside the target (`NAME.partial.opds`), and whatever was on disk before stays intact.
//! Verbs that only read a dataset (`render`, `walk`, `measure`) and `merge` stop at the next
//! batch and write nothing (`commands::unless_interrupted`).
//! A second Ctrl-C exits at once.
//!
//! For tests, `OPTICKS_INTERRUPT_AFTER_PATHS=N` acts as a Ctrl-C pressed as soon as a trace has
//! completed N paths: interrupted runs (and their resumption) become reproducible.

use std::sync::atomic::{AtomicBool, Ordering};

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Installs the handler (once, at start-up). Failure to install is not fatal: Ctrl-C then
/// kills the process, which still leaves the previous output file intact.
pub fn install() {
    let _ = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
        eprintln!("\ninterrupted: stopping at the next batch (Ctrl-C again to quit at once)");
    });
}

/// Whether Ctrl-C was pressed.
pub fn requested() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

/// Raises the flag once `paths_done` reaches `$OPTICKS_INTERRUPT_AFTER_PATHS` (if set).
pub fn simulate_after(paths_done: u64) {
    static AFTER: std::sync::OnceLock<Option<u64>> = std::sync::OnceLock::new();
    let after = AFTER.get_or_init(|| std::env::var("OPTICKS_INTERRUPT_AFTER_PATHS").ok()?.parse().ok());
    if after.is_some_and(|n| paths_done >= n) {
        INTERRUPTED.store(true, Ordering::SeqCst);
    }
}
