//! `opticks`: the command line of the Opticks light-sampling renderer.
//!
//! A thin layer: arguments are parsed (clap), validated, and handed to the library crates;
//! errors are reported with their whole chain and a non-zero exit code. No rendering or
//! dataset logic lives here: every dataset law and operation is a function of
//! `opticks_core::dataset`, and every dataset is written by `opticks_io::dataset_job`.
//! Built with the `mpi` feature and started by `mpirun`, one verb runs over many processes
//! (the `opticks-cluster` crate, docs/cluster.md; `cluster.rs` here maps the verbs onto it);
//! without it no MPI code is compiled.

mod camera_args;
#[cfg(feature = "mpi")]
mod cluster;
mod commands;
mod interrupt;
mod output;
mod progress;
mod scene_arg;
mod strategy_args;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// `--version`: the version and whether this binary can run cluster jobs (the `mpi` feature).
const VERSION: &str = if cfg!(feature = "mpi") {
    concat!(env!("CARGO_PKG_VERSION"), " (features: mpi — cluster jobs under mpirun)")
} else {
    concat!(env!("CARGO_PKG_VERSION"), " (features: none — built without mpi, a single process)")
};

/// Opticks: physically based light sampling into a camera-independent dataset.
#[derive(Parser, Debug)]
#[command(name = "opticks", version = VERSION, about, long_about = None, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Print only warnings and errors: no progress bars, notes or summary.
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    quiet: bool,
    /// Also print details: the scene loaded, the plan traced, the files written.
    #[arg(short, long, global = true)]
    verbose: bool,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Trace and render the built-in Cornell box (no files needed).
    Demo(commands::demo::Args),
    /// Trace light paths through a scene into a dataset file.
    Trace(commands::trace::Args),
    /// Render a dataset through a camera into an EXR or PNG image.
    Render(commands::render::Args),
    /// Add paths to a dataset from a fresh random stream.
    Refine(commands::refine::Args),
    /// Trace a light the scene file gained into an existing dataset.
    AddLight(commands::add_light::Args),
    /// Finish an interrupted trace, refine or add-light from its NAME.partial.opds.
    Resume(commands::resume::Args),
    /// Combine datasets of the same scene traced independently.
    Merge(commands::merge::Args),
    /// Render a walkthrough (a camera path of keyframes) from one dataset.
    Walk(commands::walk::Args),
    /// Print a readable summary of a dataset file.
    Info(commands::info::Args),
    /// Measure tracing and rendering speed on a scene (in memory, nothing written).
    Bench(commands::bench::Args),
    /// Measure irradiance (W/m², lux) with standard errors: on a scene surface, on a plane anywhere
    /// (a grid of cells, CSV and a heat map) or at points read from a file (CSV); several surfaces
    /// or planes in one pass (repeat --surface or --plane: one CSV, a `meter` column).
    Measure(commands::measure::Args),
    /// Give a dataset without MIS records its records, by re-tracing its passes bit for bit.
    Upgrade(commands::upgrade::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    output::set_level(cli.quiet, cli.verbose);
    interrupt::install();
    // Every file read from here on is remembered, so that no output can replace it.
    opticks_io::input_file::remember_inputs();
    #[cfg(feature = "mpi")]
    let session = opticks_cluster::start(cluster::role(&cli.command), cluster::HOOKS);
    #[cfg(feature = "mpi")]
    if let Some(code) = session.as_ref().and_then(|s| cluster::serve_if_worker(s, cli.command.threads())) {
        return code;
    }
    let code = run(cli.command);
    #[cfg(feature = "mpi")]
    let code = match session {
        Some(s) => s.finish(code),
        None => code,
    };
    code
}

impl Command {
    /// `--threads` of the verbs that trace (0: all cores): a cluster worker's.
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    fn threads(&self) -> usize {
        match self {
            Command::Trace(a) => a.threads.count(),
            Command::Resume(a) => a.threads.count(),
            Command::Refine(a) => a.extend.threads.count(),
            Command::AddLight(a) => a.extend.threads.count(),
            _ => 0,
        }
    }
}

/// Runs the verb and reports its error.
fn run(command: Command) -> ExitCode {
    let result = match command {
        Command::Demo(a) => commands::demo::run(a),
        Command::Trace(a) => commands::trace::run(a),
        Command::Render(a) => commands::render::run(a),
        Command::Refine(a) => commands::refine::run(a),
        Command::AddLight(a) => commands::add_light::run(a),
        Command::Resume(a) => commands::resume::run(a),
        Command::Merge(a) => commands::merge::run(a),
        Command::Walk(a) => commands::walk::run(a),
        Command::Info(a) => commands::info::run(a),
        Command::Bench(a) => commands::bench::run(a),
        Command::Measure(a) => commands::measure::run(a),
        Command::Upgrade(a) => commands::upgrade::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            output::error(&error_chain(&e));
            // Stopped by a signal: the conventional 128 + signal (130 for SIGINT, 143 SIGTERM).
            interrupt::exit_code().map_or(ExitCode::FAILURE, ExitCode::from)
        }
    }
}

/// The error and its causes as one line ([`opticks_io::error_chain`]: a cause the message
/// before it already ends with is said once).
fn error_chain(e: &anyhow::Error) -> String {
    opticks_io::error_chain(e.as_ref())
}

#[cfg(test)]
mod tests {
    use super::error_chain;

    #[test]
    fn a_cause_already_in_the_message_is_printed_once() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let e = anyhow::Error::new(io).context("scene.xml: cannot read: no such file");
        assert_eq!(error_chain(&e), "scene.xml: cannot read: no such file");
        let e = anyhow::anyhow!("bad value").context("trace");
        assert_eq!(error_chain(&e), "trace: bad value");
    }
}
