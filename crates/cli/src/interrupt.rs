//! Signals: long work stops cleanly instead of dying mid-write. SIGINT (Ctrl-C), SIGTERM (what
//! `timeout`, Slurm and systemd send) and SIGHUP (a closed terminal) are treated alike.
//!
//! While a verb is inside its *graceful section* ([`graceful`]: a dataset job, a render loop),
//! the first signal sets a flag that the work checks between batches: a trace saves the paths
//! done so far as a valid dataset beside the target (`NAME.partial.opds`) and removes its
//! temporary file, and whatever was on disk before stays intact; verbs that only read a dataset
//! (`render`, `walk`, `measure`) and `merge` stop at the next batch and write nothing
//! (`commands::unless_interrupted`). Further signals (a double Ctrl-C, `timeout -s INT`, which
//! reaches the process twice) do not cut the saving short: only SIGKILL does, and the next run
//! on the same output then removes the temporary file it left (`opticks_io::dataset_lock`).
//! Outside a graceful section (loading a scene, `info`, `bench`) there is nothing to save, and a
//! signal ends the process at once. Either way the exit code is the conventional 128 + signal:
//! 130 (SIGINT), 143 (SIGTERM), 129 (SIGHUP).
//!
//! For tests, `OPTICKS_INTERRUPT_AFTER_PATHS=N` acts as a SIGINT received as soon as a trace
//! has completed N paths: interrupted runs (and their resumption) become reproducible.

use std::io::Write;
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

/// The first signal received (0: none).
static SIGNAL: AtomicI32 = AtomicI32::new(0);
/// Whether a graceful section is running.
static GRACEFUL: AtomicBool = AtomicBool::new(false);

const SIGINT: i32 = 2;

/// Installs the handler (once, at start-up). Failure to install is not fatal: a signal then
/// kills the process, which still leaves the previous output file intact.
pub fn install() {
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
        let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
            return;
        };
        std::thread::spawn(move || {
            for signal in signals.forever() {
                received(signal);
            }
        });
    }
    #[cfg(not(unix))]
    {
        let _ = ctrlc::set_handler(|| received(SIGINT));
    }
}

/// What a signal does: a stop request inside a graceful section, the end of the process outside.
fn received(signal: i32) {
    let first = SIGNAL.compare_exchange(0, signal, Ordering::SeqCst, Ordering::SeqCst).is_ok();
    let name = signal_name(signal);
    // A closed terminal (SIGHUP) makes writes to it fail: never panic over a message.
    let mut err = std::io::stderr();
    if !GRACEFUL.load(Ordering::SeqCst) {
        let _ = writeln!(err, "\ninterrupted ({name}): nothing to save, stopping now");
        std::process::exit(exit_code_of(signal));
    }
    let _ = if first {
        writeln!(err, "\ninterrupted ({name}): stopping at the next batch; the work done so far is kept")
    } else {
        writeln!(err, "\n{name}: already stopping; saving the work done so far (SIGKILL abandons it)")
    };
}

/// `SIGINT`, `SIGTERM`, … for messages.
fn signal_name(signal: i32) -> String {
    match signal {
        1 => "SIGHUP".into(),
        2 => "SIGINT".into(),
        15 => "SIGTERM".into(),
        n => format!("signal {n}"),
    }
}

fn exit_code_of(signal: i32) -> i32 {
    128 + signal
}

/// Whether a signal asked the work to stop.
pub fn requested() -> bool {
    SIGNAL.load(Ordering::SeqCst) != 0
}

/// The conventional exit code of the signal that stopped the work (128 + signal), if any.
pub fn exit_code() -> Option<u8> {
    match SIGNAL.load(Ordering::SeqCst) {
        0 => None,
        s => u8::try_from(exit_code_of(s)).ok(),
    }
}

/// While the returned guard lives, signals request a stop instead of ending the process.
pub fn graceful() -> Graceful {
    GRACEFUL.store(true, Ordering::SeqCst);
    Graceful(())
}

/// The graceful section of [`graceful`]; ends when dropped.
pub struct Graceful(());

impl Drop for Graceful {
    fn drop(&mut self) {
        GRACEFUL.store(false, Ordering::SeqCst);
    }
}

/// Raises the flag (as a SIGINT) once `paths_done` reaches `$OPTICKS_INTERRUPT_AFTER_PATHS`
/// (if set).
pub fn simulate_after(paths_done: u64) {
    static AFTER: std::sync::OnceLock<Option<u64>> = std::sync::OnceLock::new();
    let after = AFTER.get_or_init(|| std::env::var("OPTICKS_INTERRUPT_AFTER_PATHS").ok()?.parse().ok());
    if after.is_some_and(|n| paths_done >= n) {
        let _ = SIGNAL.compare_exchange(0, SIGINT, Ordering::SeqCst, Ordering::SeqCst);
    }
}
