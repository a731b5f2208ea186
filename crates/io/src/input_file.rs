//! Opening the files readers read: only regular files, read no further than the size they had
//! when opened, so that a reader's memory and work are bounded by its input. A FIFO (which would
//! block forever), a device such as `/dev/zero` (which never ends), a socket or a directory
//! named as a scene, mesh, MTL file, buffer, IES file, camera path or dataset is an error, not a
//! hang or an allocation until memory runs out. Every reader of `opticks-io` goes through here.
//!
//! Being the one way in, it is also where a program learns what it has read: once
//! [`remember_inputs`] is called (the CLI does at start), every file opened here is remembered
//! by its identity (device and inode), and [`read_by_this_run`] says whether a path is one of
//! them. `output_paths` and the atomic writers ask it, so that no output — an image, a table,
//! a dataset — can replace a texture, an environment map, a mesh or any other file the scene
//! named, however the two paths are spelled. It is opt-in so that a long-lived library user (a
//! fuzzer, a server) does not accumulate a record it never asks for.

use std::fs::File;
use std::io::{self, Read};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

static REMEMBER: AtomicBool = AtomicBool::new(false);
static INPUTS: Mutex<Vec<(FileId, PathBuf)>> = Mutex::new(Vec::new());

/// What makes two paths one file: device and inode on Unix, the canonical path elsewhere.
#[derive(Clone, Debug, PartialEq, Eq)]
struct FileId(#[cfg(unix)] (u64, u64), #[cfg(not(unix))] PathBuf);

impl FileId {
    #[cfg(unix)]
    fn of(_path: &Path, meta: &std::fs::Metadata) -> Option<FileId> {
        use std::os::unix::fs::MetadataExt;
        Some(FileId((meta.dev(), meta.ino())))
    }

    #[cfg(not(unix))]
    fn of(path: &Path, _meta: &std::fs::Metadata) -> Option<FileId> {
        std::fs::canonicalize(path).ok().map(FileId)
    }
}

/// From now on, every file this process opens through [`open`] is remembered (see the module
/// docs). Called once by a program that writes outputs.
pub fn remember_inputs() {
    REMEMBER.store(true, Ordering::Relaxed);
}

/// If `path` names a file this process has opened as an input since [`remember_inputs`], the
/// path it was opened by; `None` otherwise (also when `path` does not exist).
pub fn read_by_this_run(path: &Path) -> Option<PathBuf> {
    let meta = std::fs::metadata(path).ok()?;
    let id = FileId::of(path, &meta)?;
    let inputs = INPUTS.lock().unwrap_or_else(|e| e.into_inner());
    inputs.iter().find(|(known, _)| *known == id).map(|(_, p)| p.clone())
}

/// Forgets that `path` was read: for a command that replaces a file it read by design, after
/// checking that it may (`resume` replacing the dataset its interrupted run started from).
pub fn forget(path: &Path) {
    let Some(id) = std::fs::metadata(path).ok().and_then(|m| FileId::of(path, &m)) else { return };
    INPUTS.lock().unwrap_or_else(|e| e.into_inner()).retain(|(known, _)| *known != id);
}

fn remember(path: &Path, meta: &std::fs::Metadata) {
    if !REMEMBER.load(Ordering::Relaxed) {
        return;
    }
    let Some(id) = FileId::of(path, meta) else { return };
    let mut inputs = INPUTS.lock().unwrap_or_else(|e| e.into_inner());
    if !inputs.iter().any(|(known, _)| *known == id) {
        inputs.push((id, path.to_owned()));
    }
}

/// `Ok` if `path` (after symbolic links) is a regular file; otherwise an error saying what it is.
/// Asked before the file is opened: opening a FIFO blocks until a writer appears.
pub fn check_regular(path: &Path) -> io::Result<()> {
    let kind = std::fs::metadata(path)?.file_type();
    if kind.is_file() {
        return Ok(());
    }
    Err(io::Error::new(io::ErrorKind::InvalidInput, format!("not a regular file but {}", describe(kind))))
}

#[cfg(unix)]
fn describe(kind: std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    match () {
        _ if kind.is_dir() => "a directory",
        _ if kind.is_fifo() => "a FIFO (named pipe)",
        _ if kind.is_char_device() => "a character device",
        _ if kind.is_block_device() => "a block device",
        _ if kind.is_socket() => "a socket",
        _ => "a special file",
    }
}

#[cfg(not(unix))]
fn describe(kind: std::fs::FileType) -> &'static str {
    if kind.is_dir() { "a directory" } else { "a special file" }
}

/// Opens a regular file for reading; returns it with its length.
pub fn open(path: &Path) -> io::Result<(File, u64)> {
    check_regular(path)?;
    let file = File::open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        // Replaced between the check and the open.
        return Err(io::Error::new(io::ErrorKind::InvalidInput, "not a regular file"));
    }
    remember(path, &meta);
    Ok((file, meta.len()))
}

/// The bytes of the regular file `path`, no more than its length when opened (a file growing
/// while it is read is cut there).
pub fn read(path: &Path) -> io::Result<Vec<u8>> {
    let (file, len) = open(path)?;
    let mut bytes = Vec::new();
    bytes.try_reserve_exact(usize::try_from(len).unwrap_or(usize::MAX)).map_err(io::Error::other)?;
    file.take(len).read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// [`read`] as UTF-8 text.
pub fn read_to_string(path: &Path) -> io::Result<String> {
    String::from_utf8(read(path)?).map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e.utf8_error()))
}

/// Fills `buf` from byte `offset` of `file` (positioned reads: many threads may share the file).
/// `UnexpectedEof` if the file ends first.
pub fn read_exact_at(file: &File, offset: u64, buf: &mut [u8]) -> io::Result<()> {
    #[cfg(unix)]
    {
        std::os::unix::fs::FileExt::read_exact_at(file, buf, offset)
    }
    #[cfg(windows)]
    {
        let (mut done, mut offset) = (0, offset);
        while done < buf.len() {
            match std::os::windows::fs::FileExt::seek_read(file, &mut buf[done..], offset)? {
                0 => return Err(io::ErrorKind::UnexpectedEof.into()),
                n => (done, offset) = (done + n, offset + n as u64),
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn special_files_are_refused_and_regular_ones_read() {
        let dir = tempfile::tempdir().unwrap();
        let e = read(dir.path()).unwrap_err();
        assert!(e.to_string().contains("not a regular file but a directory"), "{e}");
        #[cfg(unix)]
        {
            let e = read(Path::new("/dev/zero")).unwrap_err();
            assert!(e.to_string().contains("character device"), "{e}");
            let fifo = dir.path().join("fifo");
            assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
            let e = read(&fifo).unwrap_err(); // before: blocked forever in open()
            assert!(e.to_string().contains("FIFO"), "{e}");
        }
        let f = dir.path().join("f.txt");
        std::fs::write(&f, "abc").unwrap();
        assert_eq!(read_to_string(&f).unwrap(), "abc");
        let file = File::open(&f).unwrap();
        let mut b = [0u8; 2];
        read_exact_at(&file, 1, &mut b).unwrap();
        assert_eq!(&b, b"bc");
        assert_eq!(read_exact_at(&file, 2, &mut b).unwrap_err().kind(), io::ErrorKind::UnexpectedEof);
    }
}
