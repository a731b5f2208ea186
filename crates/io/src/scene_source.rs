//! The scene a front end works on — a built-in scene or a scene file — as a typed reference
//! ([`SceneRef`]), loaded into a description and built into a validated scene, with typed
//! errors and the loader's warnings as values for the front end to print.
//!
//! Dataset labels keep the `builtin:NAME` spelling on disk (older datasets record it so), but
//! only [`SceneRef::parse`] and [`SceneRef::label`] read or write it: no other code builds or
//! parses that string.

use crate::scene_formats::{LoadOptions, LoadedScene, SceneFileError};
use opticks_core::scene::{Scene, SceneDescription, SceneError, cornell_box};
use std::fmt;
use std::path::{Path, PathBuf};

/// The prefix of a built-in scene's name on the command line and in dataset labels.
const BUILTIN_PREFIX: &str = "builtin:";

/// A scene compiled into Opticks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Builtin {
    /// The Cornell box of Mitsuba's `cornell_box()` ([`opticks_core::scene::cornell_box`]).
    Cornell,
}

impl Builtin {
    /// Every built-in scene.
    pub const ALL: &'static [Builtin] = &[Builtin::Cornell];

    /// Its name, as `builtin:NAME` gives it.
    pub fn name(self) -> &'static str {
        match self {
            Builtin::Cornell => "cornell",
        }
    }

    /// The scene.
    pub fn description(self) -> SceneDescription {
        match self {
            Builtin::Cornell => cornell_box(),
        }
    }
}

/// The scene a command, a binding or a dataset refers to.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum SceneRef {
    /// A built-in scene.
    Builtin(Builtin),
    /// A scene file (Mitsuba 3 XML, VRML97, OBJ/MTL, glTF, Radiance): its format from its
    /// extension.
    File(PathBuf),
    /// Several Radiance `.rad` files read in order as one scene, as `oconv a.rad b.rad` reads
    /// them (at least two: one is a [`SceneRef::File`]); built by [`SceneRef::joined`].
    Files(Vec<PathBuf>),
}

impl SceneRef {
    /// The reference written `spec`: `builtin:NAME`, a file path, or several `.rad` files one
    /// a line (how [`SceneRef::label`] writes them).
    pub fn parse(spec: &str) -> Result<SceneRef, SceneSourceError> {
        if spec.contains('\n') {
            let files = spec.split('\n').map(SceneRef::parse).collect::<Result<Vec<_>, _>>()?;
            return SceneRef::joined(files);
        }
        match spec.strip_prefix(BUILTIN_PREFIX) {
            Some(name) => Builtin::ALL
                .iter()
                .find(|b| b.name() == name)
                .map(|&b| SceneRef::Builtin(b))
                .ok_or_else(|| SceneSourceError::UnknownBuiltin { given: spec.to_string() }),
            None => Ok(SceneRef::File(PathBuf::from(spec))),
        }
    }

    /// The built-in Cornell box.
    pub fn cornell() -> SceneRef {
        SceneRef::Builtin(Builtin::Cornell)
    }

    /// The scene `given` several times on the command line: one reference as it is; several
    /// only if all are Radiance `.rad` files, read in order as one scene (as oconv reads them).
    pub fn joined(given: Vec<SceneRef>) -> Result<SceneRef, SceneSourceError> {
        let mut files = Vec::new();
        for g in &given {
            match g {
                SceneRef::File(p) if is_rad(p) => files.push(p.clone()),
                SceneRef::Files(ps) => files.extend(ps.iter().cloned()),
                _ if given.len() > 1 => return Err(SceneSourceError::NotRadiance { given: g.to_string() }),
                _ => {}
            }
        }
        match given.len() {
            0 => Err(SceneSourceError::NotRadiance { given: String::new() }),
            1 => Ok(given.into_iter().next().expect("one")),
            _ => Ok(SceneRef::Files(files)),
        }
    }

    /// How a dataset's label and the command line write it (`builtin:cornell`, the path, or
    /// the paths one a line).
    pub fn label(&self) -> String {
        match self {
            SceneRef::Files(ps) => ps.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join("\n"),
            _ => self.to_string(),
        }
    }

    /// The scene files (which no output may replace): none for a built-in scene.
    pub fn files(&self) -> Vec<&Path> {
        match self {
            SceneRef::File(p) => vec![p.as_path()],
            SceneRef::Files(ps) => ps.iter().map(PathBuf::as_path).collect(),
            SceneRef::Builtin(_) => Vec::new(),
        }
    }
}

/// Whether `path` is a Radiance scene file, by its extension.
fn is_rad(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("rad"))
}

impl fmt::Display for SceneRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneRef::Builtin(b) => write!(f, "{BUILTIN_PREFIX}{}", b.name()),
            SceneRef::File(p) => write!(f, "{}", p.display()),
            SceneRef::Files(ps) => {
                let names: Vec<String> = ps.iter().map(|p| p.display().to_string()).collect();
                write!(f, "{}", names.join(" "))
            }
        }
    }
}

/// Why a scene could not be loaded or built.
#[derive(Debug, thiserror::Error)]
pub enum SceneSourceError {
    /// `builtin:NAME` names no built-in scene.
    #[error("there is no built-in scene '{given}' (built-in scenes: {})", builtin_names())]
    UnknownBuiltin {
        /// What was given.
        given: String,
    },
    /// Several scenes given, one of them not a Radiance `.rad` file.
    #[error(
        "several scene files are read as one scene only in Radiance's format (.rad files, in order, as oconv reads them); {given} is not a .rad file: give one scene file of any other format"
    )]
    NotRadiance {
        /// The one that is not a `.rad` file.
        given: String,
    },
    /// Load options that choose within a scene file, given for a built-in scene.
    #[error("{what} {scene} has {has}")]
    BuiltinOptions {
        /// The built-in scene.
        scene: SceneRef,
        /// What was given ("-D gives parameters of a scene file;" …).
        what: &'static str,
        /// What the built-in scene has instead.
        has: &'static str,
    },
    /// The scene file cannot be opened as one (missing, a directory, unreadable).
    #[error(transparent)]
    Unreadable(std::io::Error),
    /// The scene file is malformed or uses what Opticks does not read.
    #[error(transparent)]
    Load(#[from] SceneFileError),
    /// The scene loaded but cannot be rendered (no light, bad values).
    #[error("invalid scene {scene}")]
    Invalid {
        /// The scene.
        scene: SceneRef,
        /// Why.
        #[source]
        source: Box<SceneError>,
    },
}

fn builtin_names() -> String {
    let names: Vec<String> = Builtin::ALL.iter().map(|&b| SceneRef::Builtin(b).label()).collect();
    names.join(", ")
}

/// Loads the description of `scene` with `options` (scene parameters, camera, glTF scene),
/// with the loader's warnings.
pub fn load(scene: &SceneRef, options: &LoadOptions) -> Result<LoadedScene, SceneSourceError> {
    match scene {
        SceneRef::Builtin(b) => {
            if !options.defines.is_empty() {
                return Err(SceneSourceError::BuiltinOptions {
                    scene: scene.clone(),
                    what: "-D gives parameters of a scene file;",
                    has: "none",
                });
            }
            if options.camera.is_some() || options.gltf_scene.is_some() {
                return Err(SceneSourceError::BuiltinOptions {
                    scene: scene.clone(),
                    what: "--camera and --gltf-scene choose within a scene file;",
                    has: "one camera and one scene",
                });
            }
            Ok(LoadedScene { description: b.description(), warnings: Vec::new() })
        }
        SceneRef::File(path) => {
            crate::output_paths::check_input_file(path, "a scene file")
                .map_err(SceneSourceError::Unreadable)?;
            Ok(crate::scene_formats::load_scene_with(path, options)?)
        }
        SceneRef::Files(paths) => {
            for path in paths {
                crate::output_paths::check_input_file(path, "a scene file")
                    .map_err(SceneSourceError::Unreadable)?;
            }
            Ok(crate::scene_formats::radiance::load_files(paths, options)?)
        }
    }
}

/// A validated scene (its BVH built) and what building it dropped.
pub struct Built {
    /// The scene.
    pub scene: Scene,
    /// "FILE: dropped N degenerate (zero-area) triangles" and/or "N triangles too large for
    /// single precision", when some were.
    pub warning: Option<String>,
}

/// Validates the loaded `description` of `scene` into a scene.
pub fn build(scene: &SceneRef, description: &SceneDescription) -> Result<Built, SceneSourceError> {
    let built = Scene::build(description)
        .map_err(|source| SceneSourceError::Invalid { scene: scene.clone(), source: Box::new(source) })?;
    let mut dropped = Vec::new();
    if built.dropped_triangles > 0 {
        dropped.push(format!("{} degenerate (zero-area) triangles", built.dropped_triangles));
    }
    if built.oversized_triangles > 0 {
        dropped.push(format!(
            "{} triangles too large for single precision (their area overflows f32)",
            built.oversized_triangles
        ));
    }
    let warning = (!dropped.is_empty()).then(|| format!("{scene}: dropped {}", dropped.join(" and ")));
    Ok(Built { scene: built, warning })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_parse_and_print_as_labels() {
        assert_eq!(SceneRef::parse("builtin:cornell").unwrap(), SceneRef::cornell());
        assert_eq!(SceneRef::cornell().label(), "builtin:cornell");
        assert_eq!(SceneRef::parse("a/b.xml").unwrap(), SceneRef::File("a/b.xml".into()));
        assert_eq!(SceneRef::parse("a/b.xml").unwrap().files(), vec![Path::new("a/b.xml")]);
        let e = SceneRef::parse("builtin:teapot").unwrap_err().to_string();
        assert_eq!(e, "there is no built-in scene 'builtin:teapot' (built-in scenes: builtin:cornell)");
    }

    #[test]
    fn several_files_are_one_radiance_scene() {
        let two =
            SceneRef::joined(vec![SceneRef::parse("a.rad").unwrap(), SceneRef::parse("b.RAD").unwrap()]);
        let two = two.unwrap();
        assert_eq!(two, SceneRef::Files(vec!["a.rad".into(), "b.RAD".into()]));
        assert_eq!(SceneRef::parse(&two.label()).unwrap(), two);
        assert_eq!(two.to_string(), "a.rad b.RAD");
        assert_eq!(two.files(), vec![Path::new("a.rad"), Path::new("b.RAD")]);
        let one = SceneRef::joined(vec![SceneRef::parse("a.xml").unwrap()]).unwrap();
        assert_eq!(one, SceneRef::File("a.xml".into()));
        for other in ["a.xml", "builtin:cornell"] {
            let given = vec![SceneRef::parse("a.rad").unwrap(), SceneRef::parse(other).unwrap()];
            let e = SceneRef::joined(given).unwrap_err().to_string();
            assert!(e.contains(&format!("{other} is not a .rad file")), "{e}");
        }
    }

    #[test]
    fn builtins_refuse_options_of_scene_files() {
        let defines = LoadOptions { defines: vec![("a".into(), "1".into())], ..LoadOptions::default() };
        let e = load(&SceneRef::cornell(), &defines).map(|_| ()).unwrap_err().to_string();
        assert!(e.contains("-D") && e.contains("has none"), "{e}");
        let camera = LoadOptions { camera: Some("x".into()), ..LoadOptions::default() };
        assert!(load(&SceneRef::cornell(), &camera).is_err());
        let ok = load(&SceneRef::cornell(), &LoadOptions::default()).unwrap();
        assert!(build(&SceneRef::cornell(), &ok.description).unwrap().warning.is_none());
    }
}
