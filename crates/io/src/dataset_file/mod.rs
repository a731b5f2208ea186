//! The dataset file (`.opds`): the persistent, versioned product of the expensive trace step.
//! This module only encodes, decodes and writes atomically; what a header means, and every
//! operation on datasets, is the core's (`opticks_core::dataset`).
//!
//! One header ([`DatasetHeader`]: magic, format version, scene fingerprint, the trace passes, a
//! free-form label and the light table: name, shape hash, Φ_k, N_k), then append-only chunks of
//! raw 32-byte [`Sample`] records, each with its own checksummed chunk header, then a 32-byte end
//! record. Every byte of the file is covered by a CRC-32, so truncation at any byte and any
//! flipped byte are reported as errors that name the file and the byte offset.
//! `docs/dataset-format.md` gives the layout byte by byte.
//!
//! * [`DatasetWriter`] writes to a temporary file beside the target and renames it into place
//!   only in [`DatasetWriter::finish`]; dropping an unfinished writer removes the temporary file
//!   and leaves any previous file untouched. A run killed outright leaves its temporary file,
//!   whose whole chunks [`salvage`] makes a partial dataset that a resumption completes.
//! * [`DatasetReader`] validates the header, the chunk headers and the end record up front, and
//!   reads a chunk's payload on request (explicit reads, one chunk at a time, so datasets may
//!   exceed RAM and a file truncated underneath is an error, not SIGBUS), verifying its checksum
//!   and samples. It is `Sync`: chunks may be read from many threads.
//!
//! The records are stored in the host's layout, which is the file's little-endian layout on every
//! little-endian host; big-endian hosts are refused with an error rather than misread.
//!
//! [`Sample`]: opticks_core::dataset::Sample
//! [`DatasetHeader`]: opticks_core::dataset::DatasetHeader
//!
//! No `unsafe` (the workspace denies it): records are cast with `bytemuck`'s checked casts.

mod error;
mod format;
mod reader;
mod salvage;
mod writer;

pub use error::{DatasetError, RecordFault, SampleFault};
pub use reader::{DatasetReader, read_all};
pub use salvage::salvage;
pub use writer::{DatasetSummary, DatasetWriter};

/// The first 8 bytes of every dataset file (PNG-style: a high-bit byte, `OPK`, CR LF, DOS EOF,
/// LF — so 7-bit transfers and newline translation are detected as a foreign file).
pub const MAGIC: [u8; 8] = *b"\x89OPK\r\n\x1a\n";
/// The format version this build writes, and the newest it reads (3: MIS records after each
/// chunk's samples, the passes' MIS heuristic and sampling signature; 4: the scene's object
/// hashes after the light table, so a refusal can name the mesh or material that changed).
pub const FORMAT_VERSION: u32 = 4;
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
