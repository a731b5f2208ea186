//! The dataset file (`.opds`): the persistent, versioned product of the expensive trace step.
//!
//! One header (magic, format version, scene [`Fingerprint`], the trace passes ([`TraceInfo`]), a
//! free-form label and the light table: name, shape hash, Φ_k, N_k), then append-only chunks of raw 32-byte [`Sample`] records, each
//! with its own checksummed chunk header, then a 32-byte end record. Every byte of the file is
//! covered by a CRC-32, so truncation at any byte and any flipped byte are reported as errors
//! that name the file and the byte offset. `docs/dataset-format.md` gives the layout byte by byte.
//!
//! * [`DatasetWriter`] writes to a temporary file beside the target and renames it into place
//!   only in [`DatasetWriter::finish`]; dropping an unfinished writer removes the temporary file
//!   and leaves any previous file untouched.
//! * [`DatasetReader`] memory-maps the file (datasets may exceed RAM), validates the header, the
//!   chunk headers and the end record up front, and hands out zero-copy [`ChunkView`]s whose
//!   payload checksum is verified on access. It is `Sync`: chunks may be read from many threads.
//!
//! The records are stored in the host's layout, which is the file's little-endian layout on every
//! little-endian host; big-endian hosts are refused with an error rather than misread.
//!
//! [`Sample`]: opticks_core::dataset::Sample
#![deny(unsafe_code)]

mod error;
mod format;
mod reader;
mod writer;

pub use error::DatasetError;
pub use reader::{ChunkView, DatasetReader, read_all};
pub use writer::{DatasetSummary, DatasetWriter};

use opticks_core::dataset::LightTable;
use opticks_core::scene::Fingerprint;
use opticks_core::trace::{Directions, LightPlan, Roulette, Selection, TraceSettings};

/// The first 8 bytes of every dataset file (PNG-style: a high-bit byte, `OPK`, CR LF, DOS EOF,
/// LF — so 7-bit transfers and newline translation are detected as a foreign file).
pub const MAGIC: [u8; 8] = *b"\x89OPK\r\n\x1a\n";
/// The format version this build writes, and the newest it reads.
pub const FORMAT_VERSION: u32 = 2;
/// The oldest format version this build still reads (version 1 had no strategy or plan in its
/// pass records: they read as the default strategy and a complete pass).
pub const OLDEST_VERSION: u32 = 1;
/// Conventional file extension (without the dot).
pub const EXTENSION: &str = "opds";
/// Magic of a chunk header.
pub const CHUNK_MAGIC: [u8; 4] = *b"CHNK";
/// Magic of the end record.
pub const END_MAGIC: [u8; 4] = *b"END\0";
/// Size of a chunk header; also the alignment of every chunk and payload in the file.
pub const CHUNK_HEADER_LEN: usize = 32;
/// Size of the end record.
pub const TRAILER_LEN: usize = 32;
/// Alignment of the header length, chunk headers and sample payloads (= size of a sample).
pub const ALIGN: usize = 32;

/// One run of light sampling that contributed paths to the dataset: a trace, a refinement, an
/// added light, or a dataset merged in. Kept so that refinements pick a fresh random stream and
/// reuse the strategy, merges refuse datasets that share a stream (their paths would be
/// identical, not independent), an interrupted pass can be resumed (its plan says which blocks
/// are missing), and `info` can say how the dataset was made.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TracePass {
    /// Seed of the random streams.
    pub seed: u64,
    /// Stream family within the seed (0 for a first trace, then 1, 2, … for refinements).
    pub stream: u64,
    /// Light paths this pass traced, over all its lights.
    pub paths: u64,
    /// Path depth from which Russian roulette started.
    pub rr_depth: u32,
    /// Wall-clock seconds the pass took.
    pub seconds: f32,
    /// Russian roulette rule.
    pub roulette: Roulette,
    /// Continuation direction sampling.
    pub directions: Directions,
    /// Vertex selection for extension.
    pub selection: Selection,
    /// What the pass set out to trace: (light table index, planned paths) per light, in plan
    /// order. The pass is complete when `paths` reaches their sum; empty = unknown (format
    /// version 1), taken as complete.
    pub planned: Vec<(u32, u64)>,
}

impl TracePass {
    /// A new pass of `settings` planning `plan` (its paths and time are filled in when it ends).
    pub fn new(settings: &TraceSettings, plan: &[LightPlan]) -> Self {
        TracePass {
            seed: settings.seed,
            stream: settings.stream,
            paths: 0,
            rr_depth: settings.rr_depth,
            seconds: 0.0,
            roulette: settings.roulette,
            directions: settings.directions,
            selection: settings.selection,
            planned: plan.iter().map(|p| (p.table_index, p.paths)).collect(),
        }
    }

    /// Paths the pass planned (= `paths` when the plan is unknown).
    pub fn planned_paths(&self) -> u64 {
        if self.planned.is_empty() { self.paths } else { self.planned.iter().map(|p| p.1).sum() }
    }

    /// Whether the pass traced everything it planned (false for an interrupted run).
    pub fn is_complete(&self) -> bool {
        self.paths >= self.planned_paths()
    }

    /// The settings the pass traced with (`paths` = the planned total).
    pub fn settings(&self) -> TraceSettings {
        TraceSettings {
            paths: self.planned_paths(),
            seed: self.seed,
            stream: self.stream,
            rr_depth: self.rr_depth,
            roulette: self.roulette,
            directions: self.directions,
            selection: self.selection,
        }
    }
}

/// How the dataset was traced: its passes, oldest first.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TraceInfo {
    /// The passes.
    pub passes: Vec<TracePass>,
}

impl TraceInfo {
    /// The first stream number not used yet with `seed`.
    pub fn next_stream(&self, seed: u64) -> u64 {
        self.passes.iter().filter(|p| p.seed == seed).map(|p| p.stream + 1).max().unwrap_or(0)
    }

    /// Total tracing time over all passes, seconds.
    pub fn seconds(&self) -> f64 {
        self.passes.iter().map(|p| p.seconds as f64).sum()
    }
}

/// Everything in the file before the chunks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DatasetHeader {
    /// Content hashes of the scene the dataset was traced in.
    pub fingerprint: Fingerprint,
    /// Free-form UTF-8 label, e.g. the scene file's path.
    pub label: String,
    /// Trace settings.
    pub trace: TraceInfo,
    /// The light table: Φ_k and N_k. In a finished file N_k equals the sum of the paths of the
    /// light's chunks.
    pub table: LightTable,
}
