//! The cluster build (this crate's `mpi` feature, the CLI's `--features mpi`): one `opticks` job over the ranks of an MPI run
//! (`mpirun -n N opticks trace …`, or `srun` under Slurm), the thesis's master/worker
//! parallelisation (§6.2.4) built on the standard of HPC sites instead of a protocol of our own.
//! Nothing here is compiled without the feature; docs/cluster.md is the user's manual. It is a
//! library, not part of the CLI, so that any front end can run its verbs over the ranks: the
//! front end says how to ask whether to stop and where messages go ([`Hooks`]), and maps its
//! verbs onto a `Role`.
//!
//! Rank 0 is the master, every other rank a worker; with one rank there is no cluster and the
//! verb runs as always.
//!
//! * **Dataset verbs** (`trace`, `refine`, `add-light`, `resume`): only the master runs the
//!   verb: it parses, opens, plans, and writes the one dataset through
//!   `opticks_io::dataset_job` exactly as a single process does. Its tracer
//!   (`ClusterTracer`, its bookkeeping the core's `PassDispatch`) hands the pass's
//!   blocks out **on demand** to the workers, which
//!   wait in `trace::serve`: a worker gets the job (the scene's path, its fingerprint and the
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
//!   (`render`): the image is the single-process one, bit for bit.
//! * **`walk`**: every rank runs the verb and renders the frames f with f mod N = its rank,
//!   writing them itself (the output folder is on the shared file system); the master waits
//!   for every rank's `share_done` before it encodes the video. Each frame is rendered exactly
//!   as a single process renders it, so the frames are the same files.
//! * **Other verbs** run on the master only; workers exit at once.

#[cfg(feature = "mpi")]
mod render;
#[cfg(feature = "mpi")]
mod session;
#[cfg(feature = "mpi")]
mod trace;

#[cfg(feature = "mpi")]
pub use render::render;
#[cfg(feature = "mpi")]
pub use session::{Role, Served, Session, active, is_master, rank_and_size, share_done, start};
#[cfg(feature = "mpi")]
pub use trace::ClusterTracer;

/// How the cluster talks to its front end: whether a stop was asked for (a signal), and where
/// its warnings and notes go. Plain function pointers: the front end's are process-wide.
#[derive(Clone, Copy, Debug)]
pub struct Hooks {
    /// Whether the work should stop (a signal arrived).
    pub stop_requested: fn() -> bool,
    /// A warning for the user (a lost worker, an abandoned handshake).
    pub warning: fn(&str),
    /// A note for the user (the master's traffic summary).
    pub note: fn(&str),
}

/// Why a cluster step failed.
#[derive(Debug, thiserror::Error)]
pub enum ClusterError {
    /// A stop was asked for while waiting for another rank.
    #[error("interrupted: stopped, nothing written")]
    Interrupted,
    /// A worker sent a film of the wrong size.
    #[error("rank {rank} sent a film of {values} values for {width}x{height}")]
    BadFilm {
        /// The worker.
        rank: usize,
        /// How many values it sent.
        values: usize,
        /// The image's width.
        width: u32,
        /// The image's height.
        height: u32,
    },
    /// A stop was asked for while waiting for a worker's share of independent items.
    #[error("interrupted while waiting for rank {0}'s frames")]
    InterruptedShare(i32),
}
