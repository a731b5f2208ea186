//! The rules every output path obeys, checked before any work is done.
//!
//! * Its extension fits what is written there ([`OutputKind`]): a dataset only to `.opds`, an
//!   image to `.exr` or `.png`, a table to `.csv`, a VRML scene to `.wrl` — so that a slip of
//!   the keyboard (`-o scene.xml`, `--png data.opds`) cannot turn one kind of file into another.
//! * Its directory exists and a file can be created in it (the write's temporary file,
//!   [`create_temporary`], is created and removed: a read-only folder is refused before the
//!   work, not after it), and the path is not a directory.
//! * It is none of the command's inputs (scene file, dataset, camera path, reference image),
//!   however spelled (links included), nor any file the run has read so far through
//!   [`crate::input_file`] — the textures, environment maps, meshes, includes, IES and spectrum
//!   files a scene names (see [`crate::input_file::remember_inputs`]); a command checks again
//!   once its scene is loaded, before its work. The one exception is a dataset verb's documented
//!   in-place update (`refine` and `add-light` without `-o`), which `crate::dataset_lock`
//!   handles: the new dataset contains all of the old one.
//! * Two outputs of one command are not the same file.

use crate::dataset_lock::same_file;
use std::path::{Path, PathBuf};

/// What an output holds, which fixes the extensions it may have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputKind {
    /// A dataset (`.opds`).
    Dataset,
    /// A rendered image (`.exr` linear, `.png` sRGB).
    Image,
    /// A PNG picture (heat map).
    Png,
    /// A CSV table.
    Csv,
    /// A VRML97 scene.
    Vrml,
}

impl OutputKind {
    /// The extensions allowed (lower case, without the dot).
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            OutputKind::Dataset => &["opds"],
            OutputKind::Image => &["exr", "png"],
            OutputKind::Png => &["png"],
            OutputKind::Csv => &["csv"],
            OutputKind::Vrml => &["wrl"],
        }
    }

    fn what(self) -> &'static str {
        match self {
            OutputKind::Dataset => "a dataset",
            OutputKind::Image => "an image",
            OutputKind::Png => "a PNG image",
            OutputKind::Csv => "a CSV table",
            OutputKind::Vrml => "a VRML97 scene",
        }
    }
}

/// Why an output path is refused.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The extension does not fit the kind of output.
    #[error("{}: {} is written here, so the file name must end in {}", path.display(), kind.what(), list(kind.extensions()))]
    Extension {
        /// The output.
        path: PathBuf,
        /// What would be written.
        kind: OutputKind,
    },
    /// The output is one of the command's inputs.
    #[error("{}: an output may not replace an input of the command", path.display())]
    IsInput {
        /// The output.
        path: PathBuf,
    },
    /// The output is a file the run has read (one the scene names, or the dataset).
    #[error("{}: an output may not replace {}, which this run reads", path.display(), input.display())]
    ReadByRun {
        /// The output.
        path: PathBuf,
        /// The input as the run named it.
        input: PathBuf,
    },
    /// Two outputs are the same file.
    #[error("{}: given as two outputs of the command", path.display())]
    Twice {
        /// The output.
        path: PathBuf,
    },
    /// The output's directory does not exist.
    #[error("{}: the directory {} does not exist", path.display(), dir.display())]
    NoDirectory {
        /// The output.
        path: PathBuf,
        /// Its directory.
        dir: PathBuf,
    },
    /// No file can be created in the output's directory (read-only, no permission).
    #[error("{}: cannot create a file in {}: {source}", path.display(), dir.display())]
    NotWritable {
        /// The output.
        path: PathBuf,
        /// Its directory.
        dir: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The output is a directory.
    #[error("{}: is a directory, not a file", path.display())]
    IsDirectory {
        /// The output.
        path: PathBuf,
    },
}

fn list(extensions: &[&str]) -> String {
    let dotted: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
    dotted.join(" or ")
}

/// Checks `outputs` (path and kind) against the module's rules and the command's `inputs`.
pub fn check_outputs(outputs: &[(&Path, OutputKind)], inputs: &[&Path]) -> Result<(), OutputError> {
    check_outputs_in_place(outputs, inputs, &[])
}

/// [`check_outputs`] for a command that updates the files `in_place` (a dataset it read) by
/// replacing them: those alone may be both read and written.
pub fn check_outputs_in_place(
    outputs: &[(&Path, OutputKind)],
    inputs: &[&Path],
    in_place: &[&Path],
) -> Result<(), OutputError> {
    for (i, &(path, kind)) in outputs.iter().enumerate() {
        let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase());
        if !ext.is_some_and(|e| kind.extensions().contains(&e.as_str())) {
            return Err(OutputError::Extension { path: path.to_owned(), kind });
        }
        if path.is_dir() {
            return Err(OutputError::IsDirectory { path: path.to_owned() });
        }
        let dir = folder_of(path);
        if !dir.is_dir() {
            return Err(OutputError::NoDirectory { path: path.to_owned(), dir: dir.to_owned() });
        }
        // The temporary file the write will create there, created and removed.
        create_temporary(path).and_then(|(probe, _)| std::fs::remove_file(probe)).map_err(|source| {
            OutputError::NotWritable { path: path.to_owned(), dir: dir.to_owned(), source }
        })?;
        if inputs.iter().any(|input| same_file(input, path)) {
            return Err(OutputError::IsInput { path: path.to_owned() });
        }
        if !in_place.iter().any(|p| same_file(p, path)) {
            spares_what_was_read(path)?;
        }
        if outputs[..i].iter().any(|&(other, _)| same_file(other, path)) {
            return Err(OutputError::Twice { path: path.to_owned() });
        }
    }
    Ok(())
}

/// The folder `path` is in (`.` for a bare file name).
pub fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Creates a fresh hidden temporary file `.NAME.tmp-PID-N` beside `path` = `dir/NAME`, where
/// an atomic write puts its bytes before renaming them onto `path` (images, tables, datasets).
/// `create_new` never takes another writer's file; the name is what the next writer recognises
/// a killed run's leftover by.
pub fn create_temporary(path: &Path) -> std::io::Result<(PathBuf, std::fs::File)> {
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::InvalidInput, "the path has no file name"))?;
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let mut tmp_name = std::ffi::OsString::from(".");
        tmp_name.push(name);
        tmp_name.push(format!(".tmp-{}-{n}", std::process::id()));
        let tmp = folder_of(path).join(tmp_name);
        match std::fs::File::options().write(true).create_new(true).open(&tmp) {
            Ok(file) => return Ok((tmp, file)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

/// `Err` if `path` is a file this run has read ([`crate::input_file::read_by_this_run`]): what
/// a writer asks last, just before it renames its finished file into place.
pub fn spares_what_was_read(path: &Path) -> Result<(), OutputError> {
    match crate::input_file::read_by_this_run(path) {
        Some(input) => Err(OutputError::ReadByRun { path: path.to_owned(), input }),
        None => Ok(()),
    }
}

/// Checks one output.
pub fn check_output(path: &Path, kind: OutputKind, inputs: &[&Path]) -> Result<(), OutputError> {
    check_outputs(&[(path, kind)], inputs)
}

/// An input that must be a regular file (a dataset, a scene, a camera path): a directory or a
/// missing file is said to be one, before any reader gives a less direct error.
pub fn check_input_file(path: &Path, what: &str) -> Result<(), std::io::Error> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(std::io::Error::new(
            std::io::ErrorKind::IsADirectory,
            format!("{}: is a directory, not {what}", path.display()),
        )),
        Ok(_) => Ok(()),
        Err(e) => Err(std::io::Error::new(e.kind(), format!("{}: cannot open {what}: {e}", path.display()))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn files_in(d: &Path) -> Vec<String> {
        std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect()
    }

    #[test]
    fn outputs_must_fit_their_kind_and_spare_the_inputs() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let scene = d.join("scene.xml");
        std::fs::write(&scene, "<scene/>").unwrap();
        let out = |name: &str| d.join(name);
        let refused =
            |path: &Path, kind, inputs: &[&Path]| check_output(path, kind, inputs).unwrap_err().to_string();

        assert!(refused(&scene, OutputKind::Dataset, &[&scene]).ends_with("must end in .opds"));
        assert!(refused(&out("x.png"), OutputKind::Dataset, &[]).contains("a dataset"));
        assert!(refused(&out("m.opds"), OutputKind::Csv, &[]).ends_with(".csv"));
        assert!(refused(&out("q.png"), OutputKind::Csv, &[]).ends_with(".csv"));
        assert!(refused(&out("x.xml"), OutputKind::Vrml, &[]).ends_with(".wrl"));
        assert!(refused(&out("noext"), OutputKind::Image, &[]).ends_with(".exr or .png"));
        assert!(refused(&out("nodir/x.png"), OutputKind::Image, &[]).contains("does not exist"));
        let data = out("a.opds");
        std::fs::write(&data, b"x").unwrap();
        let inputs = [data.as_path()];
        let e = refused(&d.join(".").join("a.opds"), OutputKind::Dataset, &inputs);
        assert!(e.contains("may not replace an input"), "{e}");
        std::fs::create_dir(out("dir.png")).unwrap();
        assert!(refused(&out("dir.png"), OutputKind::Image, &[]).contains("is a directory"));
        let e = check_outputs(&[(&out("x.png"), OutputKind::Image), (&out("x.png"), OutputKind::Png)], &[])
            .unwrap_err();
        assert!(matches!(e, OutputError::Twice { .. }), "{e}");

        check_output(&out("x.EXR"), OutputKind::Image, &inputs).unwrap();
        check_output(&out("b.opds"), OutputKind::Dataset, &inputs).unwrap();
        assert!(
            check_input_file(d, "a dataset")
                .unwrap_err()
                .to_string()
                .contains("is a directory, not a dataset")
        );
        assert!(check_input_file(&out("none"), "a scene").is_err());
        // A folder where nothing can be created, even by root: refused before any work.
        #[cfg(target_os = "linux")]
        {
            let e = check_output(Path::new("/sys/x.png"), OutputKind::Image, &[]).unwrap_err();
            assert!(matches!(e, OutputError::NotWritable { .. }), "{e}");
            assert!(e.to_string().contains("cannot create a file in /sys"), "{e}");
        }
        assert!(files_in(d).iter().all(|f| !f.contains(".tmp-")), "the probe is removed");
        check_input_file(&data, "a dataset").unwrap();
    }
}
