//! Who may write a dataset, and what a writer checks before it starts any work.
//!
//! Every verb that writes `NAME.opds` (trace, refine, add-light, resume, merge, upgrade) first calls
//! [`begin_write`], which
//!
//! * takes an advisory, exclusive lock on the hidden file `.NAME.opds.lock` beside the target
//!   for as long as the returned [`WriteLock`] lives (whole-file `flock`: released by the kernel
//!   when the process ends, however it ends). A second writer of the same dataset is refused at
//!   once, naming the process that holds it, instead of both reporting success with one pass
//!   lost. Readers take no lock: the writer replaces the file by an atomic rename, so a reader
//!   keeps seeing the file it opened;
//! * saves or removes the temporary files `.NAME.opds.tmp-*` of earlier runs on the same target
//!   that died without cleaning up (a SIGKILL, a power cut, a panic under `panic = "abort"`):
//!   while the lock is held no live writer can own one, so each is stale by construction. The
//!   whole blocks a killed trace wrote are saved as `NAME.partial.opds`
//!   ([`crate::dataset_file::salvage`]; this run is then refused, as below, naming what was
//!   saved), unless a partial file is already there; the rest is removed and reported;
//! * refuses to start while `NAME.partial.opds` holds an interrupted run (unless this run is
//!   its resumption): a second interrupted run would otherwise replace it;
//! * refuses to replace an existing file at the target unless it is one of the command's own
//!   input datasets (refine or add-light in place: the new file contains all of it), the
//!   resumption's target (checked against the partial file by
//!   `opticks_core::dataset::check_resume_target`), or `overwrite` is given.
//!
//! The lock file is removed when the lock is released. Removing a lock file can race with a
//! process that has opened but not yet locked it; `lock` therefore re-checks after locking
//! that the path still names the file it locked, and retries if not.

use crate::dataset_job::partial_path;
use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// What the run that is about to write a dataset is.
#[derive(Clone, Copy, Debug, Default)]
pub struct WriteIntent<'a> {
    /// The datasets the command reads (the target may be one of them).
    pub inputs: &'a [&'a Path],
    /// The partial dataset this run resumes, if it is `resume`.
    pub resuming: Option<&'a Path>,
    /// Replace an existing file at the target (or, resuming, a target changed since).
    pub overwrite: bool,
}

/// Why a dataset write may not start.
#[derive(Debug, thiserror::Error)]
pub enum WriteRefused {
    /// Another process holds the dataset's lock.
    #[error("{} is being written by another process ({holder}); wait for it to finish", target.display())]
    Busy {
        /// The target.
        target: PathBuf,
        /// "pid N", or "pid unknown".
        holder: String,
    },
    /// An interrupted run of the target waits in its partial file.
    #[error(
        "{} holds an interrupted run of {}: finish it first, or delete it to start over",
        partial.display(),
        target.display()
    )]
    PendingPartial {
        /// The target.
        target: PathBuf,
        /// Its partial file.
        partial: PathBuf,
    },
    /// A run of the target was killed; the blocks it had written are now its partial file.
    #[error(
        "a run writing {} was killed before it finished; the {paths} light paths it had written are saved in \
         {}: finish them with `opticks resume {}`, or delete that file to start over",
        target.display(),
        partial.display(),
        partial.display()
    )]
    Salvaged {
        /// The target.
        target: PathBuf,
        /// The partial file written.
        partial: PathBuf,
        /// The paths it holds (all passes).
        paths: u64,
    },
    /// The target exists and is none of the command's inputs.
    #[error("{} exists and would be replaced", target.display())]
    Exists {
        /// The target.
        target: PathBuf,
    },
    /// The target is a directory or another special file.
    #[error("{} is not a regular file", target.display())]
    NotAFile {
        /// The target.
        target: PathBuf,
    },
    /// The file system refused an operation.
    #[error("{}: cannot {op}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What was being done.
        op: &'static str,
        /// Why.
        #[source]
        source: std::io::Error,
    },
}

/// The lock of a dataset being written, and what starting the write cleaned up.
#[derive(Debug)]
pub struct WriteLock {
    locks: Vec<(PathBuf, File)>,
    /// Stale temporary files of earlier, killed runs that were removed (path, bytes).
    pub removed_stale: Vec<(PathBuf, u64)>,
    /// The partial dataset this run resumes, when the blocks of an earlier resumption of it
    /// that was killed were added to it (the file, its paths now).
    pub extended_partial: Option<(PathBuf, u64)>,
}

impl Drop for WriteLock {
    fn drop(&mut self) {
        // Remove while still holding the lock (see `lock` for why that is safe).
        for (path, file) in self.locks.drain(..) {
            let _ = std::fs::remove_file(&path);
            drop(file);
        }
    }
}

/// Locks `target` for writing and checks the rules of the module documentation. For a
/// resumption, the interrupted run's own target (`NAME.opds` of `NAME.partial.opds`) is locked
/// too when the output goes elsewhere, so two resumptions of one partial file cannot run at once.
pub fn begin_write(target: &Path, intent: WriteIntent<'_>) -> Result<WriteLock, WriteRefused> {
    let mut targets = vec![target.to_owned()];
    if let Some(p) = intent.resuming {
        let own = crate::dataset_job::finished_path(p);
        if !same_file(&own, target) {
            targets.push(own);
        }
    }
    let mut locks = Vec::new();
    for t in &targets {
        locks.push(lock(t)?);
    }
    let mut guard = WriteLock { locks, removed_stale: Vec::new(), extended_partial: None };
    let mut salvaged = None;
    for t in &targets {
        let (removed, saved) = clear_stale_temporaries(t, intent.resuming)?;
        guard.removed_stale.extend(removed);
        match saved {
            Some(Saved::Extended(p, paths)) => guard.extended_partial = Some((p, paths)),
            Some(Saved::New(p, paths)) => salvaged = salvaged.or(Some((p, paths))),
            None => {}
        }
    }
    let partial = partial_path(target);
    let resumes_it = intent.resuming.is_some_and(|p| same_file(p, &partial));
    if let Some((partial, paths)) = salvaged {
        return Err(WriteRefused::Salvaged { target: target.to_owned(), partial, paths });
    }
    if partial.exists() && !resumes_it && !same_file(&partial, target) {
        return Err(WriteRefused::PendingPartial { target: target.to_owned(), partial });
    }
    match std::fs::metadata(target) {
        Ok(m) if !m.is_file() => return Err(WriteRefused::NotAFile { target: target.to_owned() }),
        Ok(_) => {
            let is_input = intent.inputs.iter().any(|i| same_file(i, target));
            if !is_input && intent.resuming.is_none() && !intent.overwrite {
                return Err(WriteRefused::Exists { target: target.to_owned() });
            }
        }
        Err(_) => {}
    }
    Ok(guard)
}

/// `dir/.NAME.lock` for `dir/NAME`.
fn lock_path(target: &Path) -> PathBuf {
    let name = target.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    target.with_file_name(format!(".{name}.lock"))
}

/// Takes the exclusive lock of `target`, writing this process's id into the lock file.
fn lock(target: &Path) -> Result<(PathBuf, File), WriteRefused> {
    let path = lock_path(target);
    let io = |op| {
        let path = path.clone();
        move |source| WriteRefused::Io { path, op, source }
    };
    loop {
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(io("create the lock file"))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => {
                let mut pid = String::new();
                let _ = file.read_to_string(&mut pid);
                let pid = pid.trim();
                let holder = if pid.is_empty() { "pid unknown".into() } else { format!("pid {pid}") };
                return Err(WriteRefused::Busy { target: target.to_owned(), holder });
            }
            Err(TryLockError::Error(e)) => return Err(io("lock")(e)),
        }
        // The previous holder removes the file before it unlocks; if that happened between our
        // open and our lock, we hold a lock on a file nobody else will open: start again.
        let named = std::fs::metadata(&path).ok();
        let held = file.metadata().ok();
        if named.zip(held).is_some_and(|(a, b)| same_inode(&a, &b)) {
            file.set_len(0).map_err(io("write the lock file"))?;
            let _ = write!(file, "{}", std::process::id());
            return Ok((path, file));
        }
    }
}

#[cfg(unix)]
fn same_inode(a: &std::fs::Metadata, b: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    (a.dev(), a.ino()) == (b.dev(), b.ino())
}

#[cfg(not(unix))]
fn same_inode(_: &std::fs::Metadata, _: &std::fs::Metadata) -> bool {
    true
}

/// Whether `a` and `b` name the same existing file (through links too), or are the same path.
pub fn same_file(a: &Path, b: &Path) -> bool {
    if a == b {
        return true;
    }
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => {
            #[cfg(unix)]
            {
                same_inode(&x, &y)
            }
            #[cfg(not(unix))]
            {
                let _ = (x, y);
                std::fs::canonicalize(a).ok() == std::fs::canonicalize(b).ok()
            }
        }
        _ => match (absolute_parent(a), absolute_parent(b)) {
            (Some(x), Some(y)) => x == y,
            _ => false,
        },
    }
}

/// The canonical directory of `p` joined with its file name (for files that do not exist yet).
fn absolute_parent(p: &Path) -> Option<PathBuf> {
    Some(std::fs::canonicalize(crate::output_paths::folder_of(p)).ok()?.join(p.file_name()?))
}

/// What [`clear_stale_temporaries`] saved of a killed run: a new partial dataset, or more
/// blocks in the partial dataset this run resumes (the file, its paths).
enum Saved {
    New(PathBuf, u64),
    Extended(PathBuf, u64),
}

/// Saves the work of one stale temporary file of `target` ([`crate::dataset_file::salvage`]):
/// as its partial dataset when there is none yet, or — when this run resumes that partial
/// dataset (`resuming`) and the file is a killed resumption of it — over it; removes the others
/// (reported, with their sizes). To be called with the target's lock held.
fn clear_stale_temporaries(target: &Path, resuming: Option<&Path>) -> Result<StaleCleared, WriteRefused> {
    let stale = stale_temporaries(target);
    if stale.is_empty() {
        return Ok((Vec::new(), None));
    }
    let partial = partial_path(target);
    let resumed = resuming.filter(|p| same_file(p, &partial));
    let extending = match resumed {
        Some(p) => crate::dataset_file::DatasetReader::open(p).ok().map(|r| r.header().clone()),
        None => None,
    };
    let mut saved = None;
    let mut removed = Vec::new();
    for (path, bytes) in stale {
        if saved.is_none() {
            // The salvage finishes the file into the partial one, or leaves it to be removed.
            let salvaged = match (&extending, partial.exists()) {
                (_, false) => crate::dataset_file::salvage(&path, &partial, None)
                    .map(|s| s.map(|s| Saved::New(partial.clone(), s.paths))),
                (Some(h), true) => crate::dataset_file::salvage(&path, &partial, Some(h))
                    .map(|s| s.map(|s| Saved::Extended(partial.clone(), s.paths))),
                (None, true) => Ok(None),
            };
            if let Ok(Some(s)) = salvaged {
                saved = Some(s);
                continue;
            }
        }
        std::fs::remove_file(&path).map_err(|source| WriteRefused::Io {
            path: path.clone(),
            op: "remove the stale temporary file",
            source,
        })?;
        removed.push((path, bytes));
    }
    Ok((removed, saved))
}

/// What [`clear_stale_temporaries`] removed (paths, bytes) and saved.
type StaleCleared = (Vec<(PathBuf, u64)>, Option<Saved>);

/// `dir/.NAME.tmp-*` (the temporary files of `DatasetWriter` for `dir/NAME`) with their sizes,
/// largest first (the one most likely to hold the most work is the one saved).
fn stale_temporaries(target: &Path) -> Vec<(PathBuf, u64)> {
    let name = target.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let prefix = format!(".{name}.tmp-");
    let dir = crate::output_paths::folder_of(target);
    let Ok(entries) = std::fs::read_dir(dir) else { return Vec::new() };
    let mut found: Vec<_> = entries
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with(&prefix))
        .filter_map(|e| {
            let m = e.metadata().ok()?;
            Some((e.path(), m.len()))
        })
        .collect();
    found.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_writer_is_refused_until_the_first_is_done() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("a.opds");
        let first = begin_write(&target, WriteIntent::default()).unwrap();
        let e = begin_write(&target, WriteIntent::default()).unwrap_err();
        assert!(
            matches!(&e, WriteRefused::Busy { holder, .. } if *holder == format!("pid {}", std::process::id())),
            "{e}"
        );
        drop(first);
        assert!(!lock_path(&target).exists(), "the lock file is removed with the lock");
        drop(begin_write(&target, WriteIntent::default()).unwrap());
    }

    #[test]
    fn stale_temporaries_are_removed_and_reported() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join(".a.opds.tmp-99999-0"), b"half a dataset").unwrap();
        std::fs::write(d.join(".b.opds.tmp-99999-0"), b"another target's").unwrap();
        let lock = begin_write(&d.join("a.opds"), WriteIntent::default()).unwrap();
        assert_eq!(lock.removed_stale, [(d.join(".a.opds.tmp-99999-0"), 14)]);
        assert!(d.join(".b.opds.tmp-99999-0").exists());
    }

    #[test]
    fn existing_targets_and_pending_partials_are_kept() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let (a, b) = (d.join("a.opds"), d.join("b.opds"));
        std::fs::write(&a, b"a dataset").unwrap();
        let e = begin_write(&a, WriteIntent::default()).unwrap_err();
        assert!(matches!(e, WriteRefused::Exists { .. }), "{e}");
        drop(begin_write(&a, WriteIntent { overwrite: true, ..Default::default() }).unwrap());
        let inputs = [Path::new(&a)];
        drop(begin_write(&a, WriteIntent { inputs: &inputs, ..Default::default() }).unwrap());
        // Through another spelling of the same file.
        let other = d.join(".").join("a.opds");
        let inputs = [other.as_path()];
        drop(begin_write(&a, WriteIntent { inputs: &inputs, ..Default::default() }).unwrap());

        std::fs::write(d.join("b.partial.opds"), b"an interrupted run").unwrap();
        let e = begin_write(&b, WriteIntent { overwrite: true, ..Default::default() }).unwrap_err();
        assert!(matches!(e, WriteRefused::PendingPartial { .. }), "{e}");
        let partial = d.join("b.partial.opds");
        drop(begin_write(&b, WriteIntent { resuming: Some(&partial), ..Default::default() }).unwrap());
        let e = begin_write(d, WriteIntent { overwrite: true, ..Default::default() }).unwrap_err();
        assert!(matches!(e, WriteRefused::NotAFile { .. }), "{e}");
    }
}
