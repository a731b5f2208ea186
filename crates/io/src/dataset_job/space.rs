//! Before a long trace: whether the pass fits the most paths a dataset may hold, and whether
//! the dataset it writes, estimated from its sources' bytes per path, fits the free space of
//! its file system — asked before the work, so a full disk is a warning, not a surprise (the
//! job keeps what it wrote in any case).

use super::Source;
use opticks_core::dataset::{LightTable, PassPlan, TooManyPaths, check_path_budget};
use std::path::Path;

/// Stored bytes per path assumed when nothing better is known (a fresh trace): 5 vertices of
/// 32 bytes and a share of the chunk headers. The Cornell box stores 4.4 vertices per path;
/// scenes of higher albedo store more.
pub const ASSUMED_BYTES_PER_PATH: u64 = 5 * 32 + 1;

/// About how large a dataset of `sources` and `new_paths` more paths will be: the sources'
/// sizes, plus the new paths at the sources' bytes per path (or [`ASSUMED_BYTES_PER_PATH`]).
pub fn estimate_bytes(sources: &[Source<'_>], new_paths: u64) -> u64 {
    let bytes: u64 = sources.iter().map(|s| s.reader.file_len()).sum();
    let paths: u64 = sources.iter().map(|s| s.reader.header().table.total_paths()).sum();
    let per_path = if paths > 0 && bytes > 0 { bytes.div_ceil(paths) } else { ASSUMED_BYTES_PER_PATH };
    bytes.saturating_add(new_paths.saturating_mul(per_path))
}

/// A pass's dataset may not fit on its disk: about `needed` bytes, `free` free.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpaceShortfall {
    /// The estimated size.
    pub needed: u64,
    /// Bytes free on the output's file system.
    pub free: u64,
}

/// Before a long trace into `output`: refuses a pass that would take the dataset beyond the
/// most paths a dataset may hold (`opticks_core::dataset::check_path_budget`, which the job
/// checks again), and says whether the dataset, estimated at `estimate` bytes, may not fit in
/// the free space of the output's file system (if it fills up, the paths written so far are
/// kept in [`super::partial_path`]).
pub fn preflight(
    table: &LightTable,
    pass: &PassPlan,
    output: &Path,
    estimate: u64,
) -> Result<Option<SpaceShortfall>, TooManyPaths> {
    check_path_budget(table, pass)?;
    Ok(free_space(output)
        .filter(|&free| free < estimate)
        .map(|free| SpaceShortfall { needed: estimate, free }))
}

/// Bytes free for an unprivileged writer on the file system that `output` is (to be) written to;
/// `None` where that cannot be asked.
pub fn free_space(output: &Path) -> Option<u64> {
    #[cfg(unix)]
    {
        let s = nix::sys::statvfs::statvfs(crate::output_paths::folder_of(output)).ok()?;
        Some((s.blocks_available() as u64).saturating_mul(s.fragment_size() as u64))
    }
    #[cfg(not(unix))]
    {
        let _ = output;
        None
    }
}
