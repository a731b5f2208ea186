//! Ctrl-C: long work stops cleanly instead of dying mid-write. The first Ctrl-C sets a flag that
//! the trace loop checks between batches; the paths traced so far are saved as a valid dataset
//! beside the target (`NAME.partial.opds`), and whatever was on disk before stays intact.
//! A second Ctrl-C exits at once.

use std::sync::atomic::{AtomicBool, Ordering};

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Installs the handler (once, at start-up). Failure to install is not fatal: Ctrl-C then
/// kills the process, which still leaves the previous output file intact.
pub fn install() {
    let _ = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
        eprintln!("\ninterrupted: stopping after the current batch (Ctrl-C again to quit at once)");
    });
}

/// Whether Ctrl-C was pressed.
pub fn requested() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}
