//! Saving the work of a run that was killed before it finished.
//!
//! A run that is stopped (Ctrl-C, a full disk) saves its complete blocks as `NAME.partial.opds`
//! itself. A run killed outright — SIGKILL, the out-of-memory killer, a power cut, a panic in a
//! build with `panic = "abort"` — runs no code at all: what it leaves is its temporary file, the
//! header it wrote first followed by the whole chunks the writer handed to the operating system,
//! perhaps a chunk cut short, and no end record. Every chunk carries its own checksums, and a run
//! writes its blocks in the pass's fixed order, so the whole chunks that verify are a known
//! prefix of the pass: exactly what a stopped run would have saved. [`salvage`] books them
//! (`opticks_core::dataset::salvage_counts`), cuts the file back to them and finishes it, in
//! place (no copy), as a partial dataset that `opticks resume` completes into the dataset the
//! uninterrupted run would have written, bit for bit.
//!
//! A resumption killed outright leaves the same kind of file, starting with the chunks of the
//! partial dataset it resumes: saved over that partial file, it keeps the new blocks too.
//!
//! A salvaged pass is never complete: if every block reached the disk (the run was killed while
//! finishing), the last chunk is dropped, so that resuming retraces it and the file is finished
//! by the usual path. A file whose chunks are not such a prefix (a copy of earlier passes cut
//! short, a foreign file) is not salvaged.

use super::{DatasetError, DatasetReader, DatasetSummary, DatasetWriter};
use opticks_core::dataset::{DatasetHeader, salvage_counts};
use std::path::Path;

/// Makes the temporary file `unfinished` of a killed run a valid partial dataset at `to`: `None`
/// when it holds no new paths (it is then left as it was), else the dataset written. An error
/// when the file cannot be read as a dataset at all.
///
/// With `extending`, the header of the partial dataset at `to` that the killed run was resuming:
/// the file is saved (replacing `to`, atomically) only if that run started from exactly it (its
/// label aside, which a resumption rewrites) — its file then begins with all of `to`'s chunks,
/// so what is saved holds more.
pub fn salvage(
    unfinished: &Path,
    to: &Path,
    extending: Option<&DatasetHeader>,
) -> Result<Option<DatasetSummary>, DatasetError> {
    let mut r = DatasetReader::open_unfinished(unfinished)?;
    if let Some(h) = extending
        && (DatasetHeader { label: h.label.clone(), ..r.header().clone() }) != *h
    {
        return Ok(None);
    }
    // The chunks whose payloads verify (a power cut may leave a chunk of zeros behind its header).
    let whole = (0..r.chunk_count()).find(|&i| r.owned_chunk(i).is_err()).unwrap_or(r.chunk_count());
    r.keep_chunks(whole);
    let first = r.header().clone();
    let Some(header) = book(&r, &first).or_else(|| {
        // Every block made it: drop the last one, so that the pass stays resumable.
        r.keep_chunks(r.chunk_count().checked_sub(1)?);
        book(&r, &first)
    }) else {
        return Ok(None);
    };
    let Some(end) = r.chunks_end() else { return Ok(None) };
    // The booked table's N_k are the kept chunks' paths per light (`salvage_counts`).
    let light_paths = header.table.lights.iter().map(|l| l.paths).collect();
    let counts = (r.chunk_count() as u64, r.total_samples(), light_paths);
    drop(r);
    let writer = DatasetWriter::adopt(unfinished, to, &first, end, counts)?;
    writer.finish(&header.table, &header.trace).map(Some)
}

/// `first` with the chunks of `r` booked as its last pass's interrupted run: `None` if they
/// are not a prefix of it, add no paths, or complete it.
fn book(r: &DatasetReader, first: &DatasetHeader) -> Option<DatasetHeader> {
    let mut kept = vec![0u64; first.table.lights.len()];
    for i in 0..r.chunk_count() {
        let (light, paths, _) = r.chunk_summary(i)?;
        *kept.get_mut(light as usize)? += paths;
    }
    let mut header = first.clone();
    let paths = salvage_counts(&mut header, &kept)?;
    let complete = header.trace.passes.last().is_none_or(|p| p.is_complete());
    (paths > 0 && !complete).then_some(header)
}
