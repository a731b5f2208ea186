//! Errors of the dataset file. Every message names the file, and every error about the file's
//! contents names the byte offset where reading went wrong.

use opticks_core::dataset::MisRecord;
use std::path::PathBuf;

/// What can go wrong reading or writing a dataset file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DatasetError {
    /// The operating system refused an operation.
    #[error("{}: cannot {op}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What was being done ("open", "write", "rename into place", …).
        op: &'static str,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The file does not start with the dataset magic.
    #[error("{}: not an Opticks dataset (byte 0: expected magic {}, found {})", path.display(), hex(expected), hex(found))]
    NotADataset {
        /// The file.
        path: PathBuf,
        /// The magic we look for.
        expected: &'static [u8],
        /// The file's first bytes (up to 8).
        found: Vec<u8>,
    },
    /// The file was written by a newer format version.
    #[error("{}: written by a newer Opticks: format version {found}, this build reads {supported} (byte 8)", path.display())]
    NewerVersion {
        /// The file.
        path: PathBuf,
        /// Version in the file.
        found: u32,
        /// Newest version this build reads.
        supported: u32,
    },
    /// The file ends before a structure it needs.
    #[error("{}: truncated at byte {offset}: {detail}", path.display())]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Where the missing structure starts (or the file's length).
        offset: u64,
        /// What was expected.
        detail: String,
    },
    /// A checksum does not match the bytes it covers.
    #[error("{}: corrupt {what} at byte {offset}: CRC-32 stored {stored:08x}, computed {computed:08x}", path.display())]
    Checksum {
        /// The file.
        path: PathBuf,
        /// Start of the checksummed structure.
        offset: u64,
        /// Which structure ("header", "chunk 3 header", "chunk 3 payload", "end record").
        what: String,
        /// Stored checksum.
        stored: u32,
        /// Checksum of the bytes read.
        computed: u32,
    },
    /// A structural inconsistency (bad magic inside the file, impossible length, invalid UTF-8…).
    #[error("{}: corrupt at byte {offset}: {detail}", path.display())]
    Corrupt {
        /// The file.
        path: PathBuf,
        /// Where.
        offset: u64,
        /// What is wrong.
        detail: String,
    },
    /// A chunk names a light the table does not have.
    #[error("{}: chunk {chunk} at byte {offset} names light {light}, but the light table has {lights} lights", path.display())]
    LightOutOfRange {
        /// The file.
        path: PathBuf,
        /// Offset of the chunk header.
        offset: u64,
        /// Chunk index.
        chunk: u64,
        /// The light index found.
        light: u32,
        /// Number of lights in the table.
        lights: usize,
    },
    /// A light's N_k in the header differs from the sum of its chunks' paths.
    #[error("{}: light {light} ({name:?}): the header (N_k at byte {offset}) says {header} paths, the chunks sum to {chunks}", path.display())]
    PathCountMismatch {
        /// The file.
        path: PathBuf,
        /// Offset of the light's N_k field in the header.
        offset: u64,
        /// Light index.
        light: usize,
        /// Light name.
        name: String,
        /// N_k in the header.
        header: u64,
        /// Sum of the chunks' paths.
        chunks: u64,
    },
    /// A sample decodes but cannot be valid (non-finite position, non-finite or negative β).
    #[error("{}: invalid sample {index} of chunk {chunk} at byte {offset}: {detail}", path.display())]
    InvalidSample {
        /// The file.
        path: PathBuf,
        /// Offset of the sample record.
        offset: u64,
        /// Chunk index.
        chunk: u64,
        /// Sample index within the chunk.
        index: usize,
        /// What is wrong.
        detail: SampleFault,
    },
    /// A MIS record decodes but cannot be valid (a negative or NaN quantity, a class that
    /// disagrees with its sample's emission flag).
    #[error("{}: invalid MIS record {index} of chunk {chunk} at byte {offset}: {detail}", path.display())]
    InvalidRecord {
        /// The file.
        path: PathBuf,
        /// Offset of the record.
        offset: u64,
        /// Chunk index.
        chunk: u64,
        /// Record (= sample) index within the chunk.
        index: usize,
        /// What is wrong.
        detail: RecordFault,
    },
    /// The MIS records of a chunk that has none were asked for.
    #[error(
        "{}: chunk {chunk} (header at byte {offset}) has no MIS records: it was traced without them \
         (by an Opticks older than dataset format 3, or with MIS records switched off)",
        path.display()
    )]
    NoRecords {
        /// The file.
        path: PathBuf,
        /// Offset of the chunk header.
        offset: u64,
        /// Chunk index.
        chunk: u64,
    },
    /// `chunk(i)` with `i` out of range.
    #[error("{}: no chunk {index}: the file has {count} chunks", path.display())]
    NoSuchChunk {
        /// The file.
        path: PathBuf,
        /// Requested index.
        index: usize,
        /// Number of chunks.
        count: usize,
    },
    /// The writer was given data it refuses to store.
    #[error("{}: refusing to write: {detail}", path.display())]
    InvalidInput {
        /// The target file.
        path: PathBuf,
        /// What is wrong.
        detail: String,
    },
}

impl DatasetError {
    /// Byte offset in the file where the problem was found, if the error is about the contents.
    pub fn offset(&self) -> Option<u64> {
        match self {
            DatasetError::NotADataset { .. } => Some(0),
            DatasetError::NewerVersion { .. } => Some(8),
            DatasetError::Truncated { offset, .. }
            | DatasetError::Checksum { offset, .. }
            | DatasetError::Corrupt { offset, .. }
            | DatasetError::LightOutOfRange { offset, .. }
            | DatasetError::PathCountMismatch { offset, .. }
            | DatasetError::InvalidSample { offset, .. }
            | DatasetError::InvalidRecord { offset, .. }
            | DatasetError::NoRecords { offset, .. } => Some(*offset),
            DatasetError::Io { .. }
            | DatasetError::NoSuchChunk { .. }
            | DatasetError::InvalidInput { .. } => None,
        }
    }
}

fn hex(b: &[u8]) -> String {
    let s: Vec<String> = b.iter().map(|x| format!("{x:02x}")).collect();
    if s.is_empty() { "nothing (empty file)".into() } else { s.join(" ") }
}

/// What is wrong with a sample that decodes (or is given to the writer) but cannot be valid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SampleFault {
    /// Its position is not finite, or its β is not finite and non-negative (the message names
    /// the position if it is at fault, else β).
    #[error(
        "non-finite or negative {}: position {position:?}, β {beta:?}",
        if position.iter().all(|x| x.is_finite()) { "β" } else { "position" }
    )]
    NonFinite {
        /// The sample's position.
        position: [f32; 3],
        /// The sample's β.
        beta: [f32; 3],
    },
    /// It names a triangle beyond the scene's.
    #[error("triangle {triangle} does not exist: the scene has {triangles} triangles")]
    NoSuchTriangle {
        /// The triangle it names.
        triangle: u32,
        /// The scene's triangle count.
        triangles: u32,
    },
}

/// What is wrong with a MIS record that decodes (or is given to the writer) but cannot be
/// valid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RecordFault {
    /// A quantity is negative or NaN ([`MisRecord::is_valid`]).
    #[error("negative or NaN MIS quantity: {0:?}")]
    Quantity(MisRecord),
    /// The record is of the emitter-hit class, but its sample is a reflection vertex.
    #[error("MIS record of an emission vertex, but its sample is a reflection vertex")]
    HitOnReflection,
    /// The sample is an emission vertex, but its record is not of the emitter-hit class.
    #[error("the sample is an emission vertex, but its MIS record is not one")]
    EmissionWithoutHit,
}
