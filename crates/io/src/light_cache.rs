//! The bidirectional estimator's light vertex cache over a memory-mapped dataset file: each
//! chunk to render is verified once (payload checksum and sample checks, in parallel) and
//! handed to the core as a borrowed view ([`opticks_core::sensor::bidirectional::CacheChunk`]),
//! so the cache's own memory is a few words per chunk whatever the file's size, and its random
//! accesses read the mapped file directly.

use crate::dataset_file::{DatasetError, DatasetReader};
use opticks_core::sensor::bidirectional::CacheChunk;
use rayon::prelude::*;

/// Views of the chunks `chunks` of `reader` (verified), in that order.
pub fn cache_chunks<'a>(
    reader: &'a DatasetReader,
    chunks: &[usize],
) -> Result<Vec<CacheChunk<'a>>, DatasetError> {
    chunks
        .par_iter()
        .map(|&i| {
            let c = reader.chunk(i)?;
            CacheChunk::new(c.light, c.paths, c.samples, &[]).map_err(|e| DatasetError::InvalidInput {
                path: reader.path().to_owned(),
                detail: format!("chunk {i}: {e}"),
            })
        })
        .collect()
}
