//! The cluster build's front end (`--features mpi`): which verb uses the ranks how, and the
//! CLI's signals and messages as the `opticks-cluster` crate's [`Hooks`]. The cluster's logic
//! is that crate's (docs/cluster.md).

use crate::{Command, interrupt, output};
use opticks_cluster::{Hooks, Role, Served, Session};
use std::process::ExitCode;

/// The CLI's signals and messages, for the cluster.
pub const HOOKS: Hooks =
    Hooks { stop_requested: interrupt::requested, warning: output::warning, note: output::note };

/// How a verb uses the ranks.
pub fn role(command: &Command) -> Role {
    match command {
        Command::Trace(_) | Command::Refine(_) | Command::AddLight(_) | Command::Resume(_) => Role::Serve,
        Command::Render(_) | Command::Walk(_) => Role::Split,
        _ => Role::MasterOnly,
    }
}

/// On a worker rank that does not run the verb itself, its service and exit code (signals do
/// not end a serving worker: the master decides when the job ends). `None`: run the verb.
pub fn serve_if_worker(session: &Session, threads: usize) -> Option<ExitCode> {
    let _graceful = interrupt::graceful();
    Some(match session.run_worker(threads)? {
        Served::Done => ExitCode::SUCCESS,
        Served::GaveUp => interrupt::exit_code().map_or(ExitCode::FAILURE, ExitCode::from),
    })
}
