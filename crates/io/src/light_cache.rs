//! The bidirectional estimator's light vertex cache over a memory-mapped dataset file: each
//! chunk to render is verified once (its samples' and its MIS records' checksums and checks, in
//! parallel) and handed to the core as a borrowed view ([`opticks_core::sensor::bidirectional::CacheChunk`]),
//! so the cache's own memory is a few words per chunk whatever the file's size, and its random
//! accesses read the mapped file directly.

use crate::dataset_file::{DatasetError, DatasetReader};
use opticks_core::sensor::bidirectional::CacheChunk;
use rayon::prelude::*;

/// Views of the chunks `chunks` of `reader` (verified), in that order; a chunk without records
/// (format 1 or 2, or traced without them) gets none.
pub fn cache_chunks<'a>(
    reader: &'a DatasetReader,
    chunks: &[usize],
) -> Result<Vec<CacheChunk<'a>>, DatasetError> {
    chunks
        .par_iter()
        .map(|&i| {
            let c = reader.chunk(i)?;
            let records = if reader.has_records(i) == Some(true) { reader.chunk_records(i)? } else { &[] };
            CacheChunk::new(c.light, c.paths, c.samples, records).map_err(|e| DatasetError::InvalidInput {
                path: reader.path().to_owned(),
                detail: format!("chunk {i}: {e}"),
            })
        })
        .collect()
}
