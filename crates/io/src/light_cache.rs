//! The bidirectional estimator's light vertex cache, read from a dataset file: the chunks to
//! render are read with explicit reads (samples and MIS records, each chunk verified: CRCs,
//! values, records) into memory, in parallel, and the core gets borrowed views of them
//! ([`opticks_core::sensor::bidirectional::CacheChunk`]).
//!
//! Why in memory: connections draw vertices uniformly from the whole cache, so every camera
//! vertex reads one random sample and record anywhere in the file. A memory map would serve
//! those reads from the page cache, but a file truncated underneath would then kill the process
//! with SIGBUS (issue 10), which explicit reads turn into an error naming the file; and random
//! positioned reads per connection would cost a system call each. So the cache costs 48 bytes
//! per stored vertex of the lights rendered (32 of sample, 16 of record), read once per render
//! or walkthrough — never more than the file's own size, whose every count the reader has
//! checked against the file before anything is allocated. The light estimator keeps streaming
//! one chunk per thread.

use crate::dataset_file::{DatasetError, DatasetReader};
use opticks_core::dataset::Chunk;
use opticks_core::sensor::bidirectional::CacheChunk;
use rayon::prelude::*;

/// The chunks `chunks` of `reader`, read and verified, in that order; a chunk without records
/// (format 1 or 2, or traced without them) gets none.
pub fn read_cache(reader: &DatasetReader, chunks: &[usize]) -> Result<Vec<Chunk>, DatasetError> {
    chunks.par_iter().map(|&i| reader.owned_chunk(i)).collect()
}

/// The core's views of chunks read by [`read_cache`] (`reader` names the file in errors).
pub fn cache_views<'a>(
    reader: &DatasetReader,
    chunks: &'a [Chunk],
) -> Result<Vec<CacheChunk<'a>>, DatasetError> {
    chunks
        .iter()
        .enumerate()
        .map(|(i, c)| {
            CacheChunk::new(c.light, c.paths, &c.samples, &c.records).map_err(|e| {
                DatasetError::InvalidInput {
                    path: reader.path().to_owned(),
                    detail: format!("chunk {i}: {e}"),
                }
            })
        })
        .collect()
}
