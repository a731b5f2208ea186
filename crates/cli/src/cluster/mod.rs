//! The cluster build (`--features mpi`): one `opticks` job over the ranks of an MPI run
//! (`mpirun -n N opticks trace …`, or `srun` under Slurm), the thesis's master/worker
//! parallelisation (§6.2.4) built on the standard of HPC sites instead of a protocol of our own.
//! Nothing here is compiled without the feature; docs/cluster.md is the user's manual.
//!
//! Rank 0 is the master, every other rank a worker; with one rank there is no cluster and the
//! verb runs as always.
//!
//! * **Dataset verbs** (`trace`, `refine`, `add-light`, `resume`): only the master runs the
//!   verb: it parses, opens, plans, and writes the one dataset through
//!   `opticks_io::dataset_job` exactly as a single process does. Its tracer
//!   ([`trace::ClusterTracer`], its bookkeeping the core's `PassDispatch`) hands the pass's
//!   blocks out **on demand** to the workers, which
//!   wait in [`trace::serve`]: a worker gets the job (the scene's path, its fingerprint and the
//!   pass's settings), loads the scene **itself** from the shared file system — a scene file is
//!   small and every site has one, while a built scene (BVH, lights) has no wire format, and
//!   loading in parallel costs the master nothing — refuses the job if its fingerprint differs
//!   from the master's, then asks for blocks, traces them on all its cores and returns each
//!   block's chunk (its samples in their 32-byte form, `opticks_io::cluster_wire`). The master writes the chunks
//!   in block order, so **the dataset is the single-process one, sample for sample**, whatever
//!   N and the thread counts. Stopping (`--time`, a signal) stops the handing out; the blocks
//!   in flight are awaited, and the file is a valid partial that `opticks resume` completes. A
//!   block outstanding for longer than the worker timeout is handed to another worker (and its
//!   late result ignored); with no worker left the master traces the rest itself.
//! * **`render`**: every rank runs the verb (reading the dataset is read-only); the run films
//!   of the core's fixed partition (`opticks_core::sensor::render_runs`) are split over the
//!   workers, run r to worker 1 + r mod (N − 1), and the master adds them in run order
//!   ([`render::render`]): the image is the single-process one, bit for bit.
//! * **`walk`**: every rank runs the verb and renders the frames f with f mod N = its rank,
//!   writing them itself (the output folder is on the shared file system); the master waits
//!   for every rank's [`share_done`] before it encodes the video. Each frame is rendered exactly
//!   as a single process renders it, so the frames are the same files.
//! * **Other verbs** run on the master only; workers exit at once.

pub mod render;
pub mod trace;

use crate::Command;
use mpi::environment::Universe;
use mpi::point_to_point::{Destination, MatchedReceiveVec, Source};
use mpi::topology::{Communicator, SimpleCommunicator};
use std::process::ExitCode;
use std::time::Duration;

/// How a verb uses the ranks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    /// Workers serve blocks to the master's dataset job.
    Serve,
    /// Every rank runs the verb; the work is split (render).
    Split,
    /// The master alone runs the verb.
    MasterOnly,
}

fn role(command: &Command) -> Role {
    match command {
        Command::Trace(_) | Command::Refine(_) | Command::AddLight(_) | Command::Resume(_) => Role::Serve,
        Command::Render(_) | Command::Walk(_) => Role::Split,
        _ => Role::MasterOnly,
    }
}

/// An MPI session of more than one rank, held by `main` for the life of the process (MPI is
/// finalised when it ends).
pub struct Session {
    universe: Universe,
    role: Role,
}

/// Whether this process was started by an MPI launcher (Open MPI's `mpirun`, MPICH's Hydra,
/// Slurm's PMI): only then is MPI initialised, so the cluster build run by hand behaves like
/// the default build.
fn launched_by_mpi() -> bool {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK"]
        .iter()
        .any(|v| std::env::var_os(v).is_some())
}

/// Starts MPI when launched by `mpirun` with more than one rank (`None` otherwise: the verb
/// runs alone, as in the default build).
pub fn start(command: &Command) -> Option<Session> {
    if !launched_by_mpi() {
        return None;
    }
    // Only the main thread calls MPI (the tracing threads only compute).
    let (universe, _) = mpi::initialize_with_threading(mpi::Threading::Funneled)?;
    if universe.world().size() < 2 {
        return None; // one rank: the master traces itself; MPI ends with `universe`
    }
    Some(Session { universe, role: role(command) })
}

/// The world communicator (valid while a [`Session`] lives).
pub(crate) fn world() -> SimpleCommunicator {
    SimpleCommunicator::world()
}

/// How long a rank sleeps between looks at a message it waits for.
const PATIENCE: Duration = Duration::from_micros(50);

/// Receives the next message from `from`, sleeping between looks: MPI's blocking receive
/// busy-polls a core away (on a node it does not know to be shared) while the rank waits;
/// `tag`: only a message of that tag. `None` once `give_up` says so (it is asked between looks).
pub(crate) fn patient_receive<T: mpi::datatype::Equivalence>(
    from: &mpi::topology::Process<'_>,
    tag: Option<i32>,
    give_up: &dyn Fn() -> bool,
) -> Option<(Vec<T>, mpi::point_to_point::Status)> {
    loop {
        let probed = match tag {
            Some(t) => from.immediate_matched_probe_with_tag(t),
            None => from.immediate_matched_probe(),
        };
        if let Some(probed) = probed {
            return Some(probed.matched_receive_vec::<T>());
        }
        if give_up() {
            return None;
        }
        std::thread::sleep(PATIENCE);
    }
}

/// Sends `bytes` to `to`, sleeping while the receiver has not taken them yet (a large message
/// waits for its receiver), for the reason of [`patient_receive`].
pub(crate) fn patient_send<T: mpi::datatype::Equivalence>(
    to: &mpi::topology::Process<'_>,
    bytes: &[T],
    tag: i32,
) {
    mpi::request::scope(|scope| {
        let mut request = to.immediate_send_with_tag(scope, bytes, tag);
        loop {
            match request.test() {
                Ok(_) => return,
                Err(pending) => request = pending,
            }
            std::thread::sleep(PATIENCE);
        }
    })
}

/// Whether a cluster session of more than one rank runs.
pub fn active() -> bool {
    mpi::environment::is_initialized() && !mpi::environment::is_finalized() && world().size() > 1
}

/// This rank and the number of ranks (valid while a [`Session`] lives).
pub fn rank_and_size() -> (usize, usize) {
    let world = world();
    (world.rank() as usize, world.size() as usize)
}

/// The end of a split verb's independent shares (walk's frames): a worker tells the master its
/// share is done; the master waits until every worker has (a signal ends its wait with an error,
/// and a failed worker ends the whole job: [`Session::finish`]).
pub fn share_done() -> anyhow::Result<()> {
    let world = world();
    if world.rank() != 0 {
        world.process_at_rank(0).send_with_tag(&[0u8][..], opticks_io::cluster_wire::DONE);
        return Ok(());
    }
    for r in 1..world.size() {
        let from = world.process_at_rank(r);
        let got =
            patient_receive::<u8>(&from, Some(opticks_io::cluster_wire::DONE), &crate::interrupt::requested);
        if got.is_none() {
            anyhow::bail!("interrupted while waiting for rank {r}'s frames");
        }
    }
    Ok(())
}

/// Whether a cluster session runs and this is its master (dataset jobs then go through
/// [`trace::ClusterTracer`]).
pub fn is_master() -> bool {
    active() && world().rank() == 0
}

impl Session {
    /// This rank's number.
    fn rank(&self) -> i32 {
        self.universe.world().rank()
    }

    /// On a worker rank of a dataset verb, serves the master and returns the exit code; on a
    /// worker of a master-only verb, returns at once. `None` on the master, and on the workers
    /// of a split verb: they run the verb.
    pub fn run_worker(&self, threads: usize) -> Option<ExitCode> {
        if self.rank() == 0 {
            return None;
        }
        match self.role {
            Role::Serve => Some(trace::serve(threads)),
            Role::Split => None,
            Role::MasterOnly => Some(ExitCode::SUCCESS),
        }
    }

    /// Ends the session with the verb's outcome `code`. The master of a dataset verb releases
    /// its workers (they answer and exit); a failure on any rank of a split verb ends the whole
    /// job (`MPI_Abort`), since the other ranks would wait for it.
    pub fn finish(self, code: ExitCode) -> ExitCode {
        let failed = code != ExitCode::SUCCESS;
        match (self.role, self.rank()) {
            // MPI_Finalize would wait for a lost rank forever: end the job instead (everything
            // is written by now), with the verb's outcome as its code.
            (Role::Serve, 0) if !trace::release_workers() => {
                crate::output::warning(
                    "ending the cluster job without MPI's final handshake (a worker is lost)",
                );
                self.universe.world().abort(i32::from(failed))
            }
            (Role::Split, _) if failed => {
                crate::output::error(&format!("on rank {}: ending the cluster job", self.rank()));
                self.universe.world().abort(1)
            }
            _ => {}
        }
        code
    }
}
