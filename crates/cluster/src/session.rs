//! The MPI session: which rank runs what ([`Role`]), the patient sends and receives every
//! conversation uses, the end of a job.

use crate::{ClusterError, Hooks};
use mpi::environment::Universe;
use mpi::point_to_point::{Destination, MatchedReceiveVec, Source};
use mpi::topology::{Communicator, SimpleCommunicator};
use std::process::ExitCode;
use std::time::Duration;

/// How a verb uses the ranks (the front end maps its verbs onto these).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// Workers serve blocks to the master's dataset job.
    Serve,
    /// Every rank runs the verb; the work is split (render).
    Split,
    /// The master alone runs the verb.
    MasterOnly,
}

/// An MPI session of more than one rank, held by `main` for the life of the process (MPI is
/// finalised when it ends).
pub struct Session {
    universe: Universe,
    role: Role,
    hooks: Hooks,
}

/// How a worker rank's service of the master's dataset jobs ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Served {
    /// The master ended the session (or the verb needs no worker): success.
    Done,
    /// A stop was asked for and the master then stayed silent for the worker timeout.
    GaveUp,
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
/// runs alone, as in the default build); `role`: how the verb uses the ranks.
pub fn start(role: Role, hooks: Hooks) -> Option<Session> {
    if !launched_by_mpi() {
        return None;
    }
    // Only the main thread calls MPI (the tracing threads only compute).
    let (universe, _) = mpi::initialize_with_threading(mpi::Threading::Funneled)?;
    if universe.world().size() < 2 {
        return None; // one rank: the master traces itself; MPI ends with `universe`
    }
    Some(Session { universe, role, hooks })
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

/// Receives the message a matched probe found, giving up after `timeout`: a sender that dies in
/// the middle of a large message (sent in pieces) would otherwise hold a blocking receive for
/// ever, and the master with it. Given up, the receive stays posted to MPI with a buffer of its
/// own that is leaked (MPI may still write into it): the price of a dead worker's last message.
///
/// The one `unsafe` of this crate: a `'static` receive buffer is needed to keep a receive that
/// may never complete (an `mpi::request::scope` panics on one), and reading it back after the
/// receive has completed takes the raw pointer it was leaked from.
#[allow(unsafe_code)]
pub(crate) fn receive_within(
    (message, status): (mpi::point_to_point::Message, mpi::point_to_point::Status),
    timeout: std::time::Duration,
) -> Option<(Vec<u8>, mpi::point_to_point::Status)> {
    use mpi::datatype::Equivalence;
    let count = usize::try_from(status.count(u8::equivalent_datatype())).unwrap_or(0);
    let raw: *mut [u8] = Box::into_raw(vec![0u8; count].into_boxed_slice());
    // SAFETY: `raw` comes from a live Box that nothing else references; the `'static` borrow
    // is handed to the request and used by MPI alone until the request completes.
    let buffer: &'static mut [u8] = unsafe { &mut *raw };
    let mut request = message.immediate_matched_receive_into(mpi::request::StaticScope, buffer);
    let deadline = std::time::Instant::now() + timeout;
    loop {
        match request.test() {
            Ok(status) => {
                // SAFETY: the request has completed (and is consumed), so MPI no longer
                // writes the buffer and no borrow of it is left: the Box is ours again.
                let bytes = unsafe { Box::from_raw(raw) };
                return Some((bytes.into_vec(), status));
            }
            Err(pending) if std::time::Instant::now() > deadline => {
                std::mem::forget(pending); // still posted: dropping it would panic
                return None;
            }
            Err(pending) => request = pending,
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
/// share is done; the master waits until every worker has (`stop_requested` ends its wait with an
/// error, and a failed worker ends the whole job: [`Session::finish`]).
pub fn share_done(stop_requested: fn() -> bool) -> Result<(), ClusterError> {
    let world = world();
    if world.rank() != 0 {
        world.process_at_rank(0).send_with_tag(&[0u8][..], opticks_io::cluster_wire::DONE);
        return Ok(());
    }
    for r in 1..world.size() {
        let from = world.process_at_rank(r);
        if patient_receive::<u8>(&from, Some(opticks_io::cluster_wire::DONE), &stop_requested).is_none() {
            return Err(ClusterError::InterruptedShare(r));
        }
    }
    Ok(())
}

/// Whether a cluster session runs and this is its master (dataset jobs then go through
/// [`crate::ClusterTracer`]).
pub fn is_master() -> bool {
    active() && world().rank() == 0
}

impl Session {
    /// This rank's number.
    fn rank(&self) -> i32 {
        self.universe.world().rank()
    }

    /// On a worker rank of a dataset verb, serves the master's jobs on `threads` threads (0: all
    /// cores) until the master ends the session; on a worker of a master-only verb, returns at
    /// once. `None` on the master, and on the workers of a split verb: they run the verb.
    /// Signals should not end a serving worker (the master decides when the job ends): the
    /// front end keeps them from doing so while this runs.
    pub fn run_worker(&self, threads: usize) -> Option<Served> {
        if self.rank() == 0 {
            return None;
        }
        match self.role {
            Role::Serve => Some(super::trace::serve(threads, &self.hooks)),
            Role::Split => None,
            Role::MasterOnly => Some(Served::Done),
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
            (Role::Serve, 0) if !super::trace::release_workers(&self.hooks) => {
                (self.hooks.warning)(
                    "ending the cluster job without MPI's final handshake (a worker is lost)",
                );
                self.universe.world().abort(i32::from(failed))
            }
            (Role::Split, _) if failed => {
                (self.hooks.warning)(&format!("on rank {}: ending the cluster job", self.rank()));
                self.universe.world().abort(1)
            }
            _ => {}
        }
        code
    }
}
