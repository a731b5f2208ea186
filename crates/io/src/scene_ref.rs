//! The scene file a dataset belongs to, as its header's label records it.
//!
//! A dataset is rendered, refined and extended against the scene it was traced from, so it
//! records where that scene is — in a way that survives the commands being run from another
//! directory and the dataset being moved together with its scene:
//!
//! ```text
//! ../scenes/cornell.xml            ← line 1: relative to the dataset's own directory
//! /home/me/project/scenes/cornell.xml   ← line 2: absolute, the fallback
//! ```
//!
//! [`resolve`] tries the relative path first (a folder of dataset and scene moved or copied
//! whole keeps working), then the absolute one (the dataset alone moved). Built-in scenes
//! (`builtin:cornell`) are recorded as they are named. A label of one line is a dataset written
//! before this rule: its path was relative to the directory `trace` ran in, so it is tried as
//! given (from the current directory) and then from the dataset's directory. Every verb that
//! writes a dataset records the scene file it actually used ([`label_for`]); `merge`, which
//! loads no scene, moves the label of the input it takes to the output's location
//! ([`rebase`]).
//!
//! The parameters the scene was loaded with that change it — Mitsuba `-D NAME=VALUE` values and
//! the glTF scene chosen (`--gltf-scene`) — follow as further lines ([`with_options`]), so a
//! dataset renders, refines and resumes against the scene it was traced in without the user
//! repeating them ([`recorded_options`]; options given on the command line replace them):
//!
//! ```text
//! -D wall=0.5
//! --gltf-scene Night
//! ```
//!
//! A scene of several Radiance files (`opticks trace sky.rad room.rad`) records its first file
//! so, and each further one, in order, as two lines marked `+ ` (relative, then absolute),
//! before the options; each is found as the first is:
//!
//! ```text
//! ../scenes/sky.rad
//! /home/me/project/scenes/sky.rad
//! + ../scenes/room.rad
//! + /home/me/project/scenes/room.rad
//! ```
//!
//! The camera is not recorded: any camera renders a dataset. Nor are the memory limits
//! ([`crate::scene_formats::LoadLimits`]): they change no scene that loads.

use crate::output_paths::folder_of;
use crate::scene_formats::LoadOptions;
use std::path::{Component, Path, PathBuf};

const DEFINE: &str = "-D ";
const GLTF_SCENE: &str = "--gltf-scene ";
const FURTHER: &str = "+ ";

/// `label` followed by the lines recording the `defines` and `gltf_scene` of `options` (see the
/// module docs). Values holding a line break cannot be recorded: then none is.
pub fn with_options(label: &str, options: &LoadOptions) -> String {
    let mut lines: Vec<String> = options.defines.iter().map(|(k, v)| format!("{DEFINE}{k}={v}")).collect();
    lines.extend(options.gltf_scene.iter().map(|s| format!("{GLTF_SCENE}{s}")));
    if lines.is_empty() || lines.iter().any(|l| l.contains('\n')) {
        return label.to_string();
    }
    format!("{label}\n{}", lines.join("\n"))
}

/// The loading options a label records ([`with_options`]); no camera.
pub fn recorded_options(label: &str) -> LoadOptions {
    let mut options = LoadOptions::default();
    for line in option_lines(label) {
        if let Some((k, v)) = line.strip_prefix(DEFINE).and_then(|d| d.split_once('=')) {
            options.defines.push((k.to_string(), v.to_string()));
        } else if let Some(s) = line.strip_prefix(GLTF_SCENE) {
            options.gltf_scene = Some(s.to_string());
        }
    }
    options
}

/// The label's lines after its scene reference.
fn option_lines(label: &str) -> impl Iterator<Item = &str> {
    label.split('\n').skip(1).filter(|l| is_option(l))
}

fn is_option(line: &str) -> bool {
    line.starts_with(DEFINE) || line.starts_with(GLTF_SCENE)
}

/// The scene reference of a label, parsed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RecordedScene {
    /// A built-in scene (`builtin:NAME`).
    Builtin(String),
    /// A scene file: relative to the dataset's directory, and absolute.
    File {
        /// Relative to the dataset's directory.
        relative: PathBuf,
        /// Absolute, when the dataset was written.
        absolute: PathBuf,
    },
    /// A label of one line (older datasets): relative to where the trace ran, or anything.
    Legacy(String),
}

/// Parses a dataset label.
pub fn parse(label: &str) -> RecordedScene {
    let mut lines = label.split('\n');
    let first = lines.next().unwrap_or_default();
    if first.starts_with("builtin:") {
        return RecordedScene::Builtin(first.to_string());
    }
    match lines.next().filter(|l| !is_option(l)) {
        Some(absolute) => {
            RecordedScene::File { relative: PathBuf::from(first), absolute: PathBuf::from(absolute) }
        }
        None => RecordedScene::Legacy(first.to_string()),
    }
}

/// The label recording scene `spec` (a file path, several one a line, or a built-in name; as
/// `SceneRef::label` writes it) for a dataset written to `dataset`: each file's path relative
/// to the dataset's directory and its absolute path. A file that cannot be made absolute (it
/// does not exist) is recorded as given.
pub fn label_for(spec: &str, dataset: &Path) -> String {
    if spec.starts_with("builtin:") {
        return spec.to_string();
    }
    let mut files = spec.split('\n');
    let first = files.next().unwrap_or_default();
    let mut label = match record(Path::new(first), dataset) {
        Some((r, a)) => format!("{r}\n{a}"),
        None => first.to_string(),
    };
    for file in files {
        let (r, a) = record(Path::new(file), dataset).unwrap_or_else(|| (file.into(), file.into()));
        label += &format!("\n{FURTHER}{r}\n{FURTHER}{a}");
    }
    label
}

fn record(scene: &Path, dataset: &Path) -> Option<(String, String)> {
    let absolute = std::fs::canonicalize(scene).ok()?;
    let dir = std::fs::canonicalize(folder_of(dataset)).ok()?;
    let relative = relative_path(&absolute, &dir)?;
    let (r, a) = (relative.to_str()?, absolute.to_str()?);
    if r.contains('\n') || a.contains('\n') {
        return None;
    }
    Some((r.to_string(), a.to_string()))
}

/// The further files of a scene of several (see the module docs): relative and absolute.
pub fn further_files(label: &str) -> Vec<(PathBuf, PathBuf)> {
    let lines: Vec<&str> = label.split('\n').skip(1).filter_map(|l| l.strip_prefix(FURTHER)).collect();
    lines.chunks_exact(2).map(|p| (PathBuf::from(p[0]), PathBuf::from(p[1]))).collect()
}

/// `path` relative to `base` (both absolute and normalised), e.g. `../scenes/a.xml`.
fn relative_path(path: &Path, base: &Path) -> Option<PathBuf> {
    let (p, b): (Vec<Component>, Vec<Component>) = (path.components().collect(), base.components().collect());
    if p.first() != b.first() {
        return None; // another drive or root: only the absolute path can say it
    }
    let common = p.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &p[common..] {
        out.push(c.as_os_str());
    }
    Some(out)
}

/// The places `label` may name for the dataset at `dataset`, in the order they are tried.
pub fn candidates(label: &str, dataset: &Path) -> Vec<PathBuf> {
    match parse(label) {
        RecordedScene::Builtin(name) => vec![PathBuf::from(name)],
        RecordedScene::File { relative, absolute } => vec![folder_of(dataset).join(relative), absolute],
        RecordedScene::Legacy(path) => {
            let p = PathBuf::from(&path);
            if p.is_absolute() { vec![p] } else { vec![p.clone(), folder_of(dataset).join(p)] }
        }
    }
}

/// The scene the dataset at `dataset` records: a built-in name, or the first of its
/// [`candidates`] that exists (and so for each further file, the found ones one a line).
/// `Err` lists the places tried.
pub fn resolve(label: &str, dataset: &Path) -> Result<String, Vec<PathBuf>> {
    if let RecordedScene::Builtin(name) = parse(label) {
        return Ok(name);
    }
    let mut places = vec![candidates(label, dataset)];
    places.extend(further_files(label).into_iter().map(|(r, a)| vec![folder_of(dataset).join(r), a]));
    let mut found = Vec::new();
    for tried in places {
        match tried.iter().find(|p| p.is_file()) {
            Some(p) => found.push(p.to_string_lossy().into_owned()),
            None => return Err(tried),
        }
    }
    Ok(found.join("\n"))
}

/// `label` of the dataset at `from`, recorded again for a dataset written to `to` (which
/// `merge` writes from inputs elsewhere). A scene that can be found is recorded from where it
/// is; otherwise the label is kept.
pub fn rebase(label: &str, from: &Path, to: &Path) -> String {
    match resolve(label, from) {
        Ok(spec) => with_options(&label_for(&spec, to), &recorded_options(label)),
        Err(_) => label.to_string(),
    }
}

/// How `opticks info` shows the recorded scene: one line per place, each saying whether a file
/// is there, and which one the verbs use (the first found, in [`candidates`] order).
pub fn describe(label: &str, dataset: &Path) -> Vec<String> {
    let found = resolve(label, dataset).ok();
    match parse(label) {
        RecordedScene::Builtin(name) => vec![format!("{name} (built in)")],
        RecordedScene::File { relative, absolute } => {
            let mut lines = Vec::new();
            let found: Vec<String> = found.iter().flat_map(|f| f.split('\n')).map(str::to_owned).collect();
            let files = std::iter::once((relative, absolute)).chain(further_files(label));
            for (i, (relative, absolute)) in files.enumerate() {
                let from_here = folder_of(dataset).join(&relative);
                let used = |p: &Path| found.get(i).is_some_and(|f| *f == p.to_string_lossy());
                let mark = |p: &Path| match (p.is_file(), used(p)) {
                    (true, true) => " (found: used)",
                    (true, false) => " (found)",
                    (false, _) => " (missing)",
                };
                let plus = if i == 0 { "" } else { FURTHER };
                lines.push(format!(
                    "{plus}{} (relative to the dataset){}",
                    relative.display(),
                    mark(&from_here)
                ));
                lines.push(format!("{plus}{} (absolute){}", absolute.display(), mark(&absolute)));
            }
            lines
        }
        RecordedScene::Legacy(path) => {
            let state = if found.is_some() { "found" } else { "missing" };
            vec![format!(
                "{path} (as recorded by an older Opticks: relative to where it was traced; {state})"
            )]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loading_options_are_recorded_after_the_scene_and_read_back() {
        let options = LoadOptions {
            defines: vec![("wall".into(), "0.5".into()), ("spp".into(), "x=y".into())],
            camera: Some("side".into()),
            gltf_scene: Some("Night".into()),
            limits: crate::scene_formats::LoadLimits { max_texels: 10, max_mesh_expansion: 1000 },
        };
        let label = with_options("../s.gltf\n/abs/s.gltf", &options);
        assert_eq!(label, "../s.gltf\n/abs/s.gltf\n-D wall=0.5\n-D spp=x=y\n--gltf-scene Night");
        assert_eq!(
            parse(&label),
            RecordedScene::File { relative: "../s.gltf".into(), absolute: "/abs/s.gltf".into() }
        );
        assert_eq!(
            recorded_options(&label),
            LoadOptions { camera: None, limits: Default::default(), ..options.clone() },
            "no camera, no limits"
        );
        assert_eq!(with_options("builtin:cornell", &LoadOptions::default()), "builtin:cornell");
        let builtin = with_options("builtin:cornell", &options);
        assert_eq!(parse(&builtin), RecordedScene::Builtin("builtin:cornell".into()));
        assert_eq!(recorded_options(&builtin).defines.len(), 2);
        assert_eq!(recorded_options("old/scene.xml"), LoadOptions::default());
        let one_line = with_options("scene.xml", &options);
        assert_eq!(
            parse(&one_line),
            RecordedScene::Legacy("scene.xml".into()),
            "a path as given, then options"
        );
        assert_eq!(recorded_options(&one_line).gltf_scene.as_deref(), Some("Night"));
        let broken = LoadOptions { defines: vec![("a".into(), "1\n2".into())], ..Default::default() };
        assert_eq!(with_options("x\ny", &broken), "x\ny", "a line break cannot be recorded");
    }

    #[test]
    fn a_scene_is_found_from_anywhere_and_after_moving_the_dataset_or_both() {
        let dir = tempfile::tempdir().unwrap();
        let root = std::fs::canonicalize(dir.path()).unwrap();
        std::fs::create_dir_all(root.join("scenes")).unwrap();
        std::fs::create_dir_all(root.join("out/deep")).unwrap();
        std::fs::write(root.join("scenes/a.xml"), "<scene/>").unwrap();
        let dataset = root.join("out/deep/a.opds");
        let label = label_for(root.join("scenes/a.xml").to_str().unwrap(), &dataset);
        let absolute = root.join("scenes/a.xml");
        assert_eq!(label, format!("../../scenes/a.xml\n{}", absolute.display()));
        assert_eq!(
            parse(&label),
            RecordedScene::File { relative: "../../scenes/a.xml".into(), absolute: absolute.clone() }
        );
        let found = |dataset: &Path| resolve(&label, dataset).map(PathBuf::from);
        assert_eq!(found(&dataset).unwrap().canonicalize().unwrap(), absolute);
        // The dataset alone moved: the absolute path finds it.
        assert_eq!(found(&root.join("a.opds")).unwrap(), absolute);
        // Dataset and scene moved together: the relative path finds the moved scene.
        let moved = root.join("copy");
        std::fs::create_dir_all(moved.join("scenes")).unwrap();
        std::fs::create_dir_all(moved.join("out/deep")).unwrap();
        std::fs::write(moved.join("scenes/a.xml"), "<scene/>").unwrap();
        let there = found(&moved.join("out/deep/a.opds")).unwrap();
        // Both places hold the scene: `info` says both are there, and which one is used (it
        // called the absolute one missing).
        let shown = describe(&label, &moved.join("out/deep/a.opds"));
        assert!(shown[0].ends_with("(found: used)") && shown[1].ends_with("(found)"), "{shown:?}");
        assert_eq!(there.canonicalize().unwrap(), moved.join("scenes/a.xml"));
        // Gone everywhere: the places tried are listed.
        std::fs::remove_file(&absolute).unwrap();
        assert_eq!(
            resolve(&label, &root.join("x.opds")).unwrap_err(),
            [root.join("../../scenes/a.xml"), absolute]
        );
        let shown = describe(&label, &dataset);
        assert!(shown[0].contains("relative to the dataset") && shown[1].ends_with("(missing)"), "{shown:?}");
    }

    #[test]
    fn several_files_are_recorded_and_found_each() {
        let dir = tempfile::tempdir().unwrap();
        let root = std::fs::canonicalize(dir.path()).unwrap();
        std::fs::create_dir_all(root.join("out")).unwrap();
        for f in ["sky.rad", "room.rad"] {
            std::fs::write(root.join(f), "").unwrap();
        }
        let (sky, room) = (root.join("sky.rad"), root.join("room.rad"));
        let spec = format!("{}\n{}", sky.display(), room.display());
        let dataset = root.join("out/a.opds");
        let label = with_options(
            &label_for(&spec, &dataset),
            &LoadOptions { defines: vec![("a".into(), "1".into())], ..Default::default() },
        );
        let want = format!("../sky.rad\n{}\n+ ../room.rad\n+ {}\n-D a=1", sky.display(), room.display());
        assert_eq!(label, want);
        assert_eq!(
            parse(&label),
            RecordedScene::File { relative: "../sky.rad".into(), absolute: sky.clone() }
        );
        assert_eq!(further_files(&label), [(PathBuf::from("../room.rad"), room.clone())]);
        assert_eq!(recorded_options(&label).defines.len(), 1);
        let found = resolve(&label, &dataset).unwrap();
        let found: Vec<PathBuf> = found.split('\n').map(|f| Path::new(f).canonicalize().unwrap()).collect();
        assert_eq!(found, [sky.clone(), room.clone()]);
        assert_eq!(describe(&label, &dataset).len(), 4);
        std::fs::remove_file(&room).unwrap();
        assert_eq!(resolve(&label, &dataset).unwrap_err(), [root.join("out/../room.rad"), room]);
    }

    #[test]
    fn built_in_and_older_labels_keep_their_meaning() {
        assert_eq!(label_for("builtin:cornell", Path::new("x.opds")), "builtin:cornell");
        assert_eq!(resolve("builtin:cornell", Path::new("/nowhere/x.opds")), Ok("builtin:cornell".into()));
        assert_eq!(
            candidates("scenes/a.xml", Path::new("out/x.opds")),
            [PathBuf::from("scenes/a.xml"), PathBuf::from("out/scenes/a.xml")]
        );
        assert_eq!(relative_path(Path::new("/a/b/c.xml"), Path::new("/a/b")), Some("c.xml".into()));
        assert_eq!(relative_path(Path::new("/a/c.xml"), Path::new("/a/b/d")), Some("../../c.xml".into()));
    }
}
