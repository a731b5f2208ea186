//! `xform`'s arguments, read (never run): the transform, the options that rename or re-modify
//! what it includes, and the files. Transforms are Radiance's: each applies after the ones
//! before it, and they preserve shape (rotations, translations, a uniform scale, mirrors), so
//! every primitive stays the same kind of primitive with transformed parameters, as `xform`
//! itself writes them. [`parse_transform`] reads the same options where a primitive carries its
//! own transform (`mesh`), so that both compose alike.

use super::lexer::{NumberError, option_number};
use glam::{DMat3, DVec3};

/// Why `xform`'s arguments cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum XformError {
    /// An option's number is missing or not a number.
    #[error(transparent)]
    Number(#[from] NumberError),
    /// `-s 0`.
    #[error("-s 0 collapses the scene to a point")]
    ZeroScale,
    /// `-n` or `-m` is the last word.
    #[error("{option} needs a name")]
    MissingName {
        /// The option.
        option: String,
    },
    /// An option this reader does not do.
    #[error(
        "unsupported xform option {option} (supported: -t, -rx, -ry, -rz, -s, -mx, -my, -mz, -n, -m, -I, -e, -c; arrays -a and -i, and -f, are not)"
    )]
    Unsupported {
        /// The option.
        option: String,
    },
    /// No file after the options: `xform` would read standard input.
    #[error("xform without a file would read standard input: name the file to include")]
    NoFile,
    /// A word of a primitive's transform that is not a transform option.
    #[error("\"{word}\" is not a transform option (a transform takes -t, -rx, -ry, -rz, -s, -mx, -my, -mz)")]
    NotTransform {
        /// The word.
        word: String,
    },
    /// An option after the first file.
    #[error("option {option} after the first file")]
    OptionAfterFile {
        /// The option.
        option: String,
    },
}

/// A similarity transform x ↦ s·R·x + t, R orthogonal (a mirror when its determinant is −1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Similarity {
    /// s·R.
    pub linear: DMat3,
    /// t.
    pub translation: DVec3,
    /// |s|: how lengths (radii) scale.
    pub scale: f64,
}

impl Default for Similarity {
    fn default() -> Self {
        Similarity { linear: DMat3::IDENTITY, translation: DVec3::ZERO, scale: 1.0 }
    }
}

impl Similarity {
    /// A point transformed.
    pub fn point(&self, p: DVec3) -> DVec3 {
        self.linear * p + self.translation
    }

    /// A direction transformed (without translation; normals too, R being orthogonal).
    pub fn vector(&self, v: DVec3) -> DVec3 {
        self.linear * v
    }

    /// Whether it mirrors (reverses handedness).
    pub fn mirrors(&self) -> bool {
        self.linear.determinant() < 0.0
    }

    /// `self` applied after `inner`.
    pub fn then_after(&self, inner: &Similarity) -> Similarity {
        Similarity {
            linear: self.linear * inner.linear,
            translation: self.linear * inner.translation + self.translation,
            scale: self.scale * inner.scale,
        }
    }

    fn then(self, linear: DMat3, translation: DVec3, scale: f64) -> Similarity {
        Similarity { linear, translation, scale }.then_after(&self)
    }
}

/// An `xform` command, read.
#[derive(Clone, Debug, PartialEq)]
pub struct Xform {
    /// The transform of the included files.
    pub transform: Similarity,
    /// `-n name`: surfaces' identifiers become `name.identifier`.
    pub prefix: Option<String>,
    /// `-m modifier`: surfaces take this modifier instead of their own.
    pub modifier: Option<String>,
    /// `-I`: surfaces are turned inside out.
    pub invert: bool,
    /// The files, as written (relative to the including file).
    pub files: Vec<String>,
}

/// Reads `xform`'s arguments (the words after `xform`). An unknown option, a missing or bad
/// number, or no file (standard input) is an error.
pub fn parse(args: &[String]) -> Result<Xform, XformError> {
    let mut x = Xform {
        transform: Similarity::default(),
        prefix: None,
        modifier: None,
        invert: false,
        files: Vec::new(),
    };
    let mut i = 0;
    while i < args.len() {
        let a = args[i].as_str();
        if !a.starts_with('-') || a == "-" {
            break;
        }
        if let Some(next) = transform_option(args, i, &mut x.transform)? {
            i = next;
            continue;
        }
        match a {
            "-n" | "-m" => {
                let Some(name) = args.get(i + 1) else {
                    return Err(XformError::MissingName { option: a.to_string() });
                };
                let slot = if a == "-n" { &mut x.prefix } else { &mut x.modifier };
                *slot = Some(match (a, slot.take()) {
                    // Repeated -n options nest, as xform's do; the first -m wins.
                    ("-n", Some(outer)) => format!("{outer}.{name}"),
                    (_, Some(first)) => first,
                    (_, None) => name.clone(),
                });
                i += 2;
            }
            "-I" => {
                x.invert = !x.invert;
                i += 1;
            }
            // Whether commands in the included file are expanded now or later: here they are
            // read (and refused unless they are xform) either way.
            "-e" | "-c" => i += 1,
            _ => {
                return Err(XformError::Unsupported { option: a.to_string() });
            }
        }
    }
    x.files = args[i..].to_vec();
    if x.files.is_empty() {
        return Err(XformError::NoFile);
    }
    if let Some(f) = x.files.iter().find(|f| f.starts_with('-')) {
        return Err(XformError::OptionAfterFile { option: f.clone() });
    }
    Ok(x)
}

/// A transform alone, as a `mesh` (or `instance`) primitive's string arguments after its file
/// give it (Radiance's `xf` arguments): the options `-t`, `-rx`, `-ry`, `-rz`, `-s`, `-mx`,
/// `-my`, `-mz`, composed exactly as in an `xform` line; none is the identity. Anything else
/// (a file, `-n`, `-m`, `-I`, an array) is an error.
pub fn parse_transform(args: &[String]) -> Result<Similarity, XformError> {
    let mut t = Similarity::default();
    let mut i = 0;
    while i < args.len() {
        match transform_option(args, i, &mut t)? {
            Some(next) => i = next,
            None => return Err(XformError::NotTransform { word: args[i].clone() }),
        }
    }
    Ok(t)
}

/// If `args[i]` is a transform option, applies it (after `t`) and returns the index of the word
/// after its numbers; `None` for any other word. The one reading of the transform options, for
/// `xform` lines and primitives' transforms alike.
fn transform_option(args: &[String], i: usize, t: &mut Similarity) -> Result<Option<usize>, XformError> {
    let a = args[i].as_str();
    let number = |i: usize| option_number(args, i, a);
    Ok(Some(match a {
        "-t" => {
            let v = DVec3::new(number(i + 1)?, number(i + 2)?, number(i + 3)?);
            *t = t.then(DMat3::IDENTITY, v, 1.0);
            i + 4
        }
        "-rx" | "-ry" | "-rz" => {
            let angle = number(i + 1)?.to_radians();
            let r = match a {
                "-rx" => DMat3::from_rotation_x(angle),
                "-ry" => DMat3::from_rotation_y(angle),
                _ => DMat3::from_rotation_z(angle),
            };
            *t = t.then(r, DVec3::ZERO, 1.0);
            i + 2
        }
        "-s" => {
            let s = number(i + 1)?;
            if s == 0.0 {
                return Err(XformError::ZeroScale);
            }
            *t = t.then(DMat3::from_diagonal(DVec3::splat(s)), DVec3::ZERO, s.abs());
            i + 2
        }
        "-mx" | "-my" | "-mz" => {
            let d = match a {
                "-mx" => DVec3::new(-1.0, 1.0, 1.0),
                "-my" => DVec3::new(1.0, -1.0, 1.0),
                _ => DVec3::new(1.0, 1.0, -1.0),
            };
            *t = t.then(DMat3::from_diagonal(d), DVec3::ZERO, 1.0);
            i + 1
        }
        _ => return Ok(None),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(str::to_string).collect()
    }

    #[test]
    fn transforms_compose_in_order() {
        let x = parse(&args("-rz 90 -t 1 0 0 -s 2 a.rad")).unwrap();
        // (1, 0, 0) → rotated (0, 1, 0) → moved (1, 1, 0) → scaled (2, 2, 0).
        let p = x.transform.point(DVec3::X);
        assert!((p - DVec3::new(2.0, 2.0, 0.0)).length() < 1e-12, "{p}");
        assert_eq!((x.transform.scale, x.files.clone()), (2.0, vec!["a.rad".to_string()]));
        assert!(!x.transform.mirrors());
        assert!(parse(&args("-mx a.rad")).unwrap().transform.mirrors());
        assert!(parse(&args("-s -1 a.rad")).unwrap().transform.mirrors());
        let x = parse(&args("-n a -n b -m glass -I a.rad b.rad")).unwrap();
        assert_eq!(
            (x.prefix.as_deref(), x.modifier.as_deref(), x.invert),
            (Some("a.b"), Some("glass"), true)
        );
        assert_eq!(x.files.len(), 2);
    }

    #[test]
    fn refuses_what_it_does_not_do() {
        let e = |s: &str| parse(&args(s)).unwrap_err();
        assert!(e("-a 3 -t 1 0 0 a.rad").to_string().starts_with("unsupported xform option -a (supported:"));
        assert_eq!(e("-i 2 a.rad"), XformError::Unsupported { option: "-i".into() });
        assert_eq!(e("-t 1 0").to_string(), "-t needs a number");
        assert_eq!(e("-rx x a.rad").to_string(), "-rx: \"x\" is not a number");
        assert_eq!(e("-t 1 2 3"), XformError::NoFile);
        assert_eq!(e("-s 0 a.rad"), XformError::ZeroScale);
        assert_eq!(e("a.rad -t 1 2 3").to_string(), "option -t after the first file");
    }

    #[test]
    fn a_primitives_transform_is_read_as_xforms() {
        let t = parse_transform(&args("-rz 90 -t 1 0 0 -s 2")).unwrap();
        assert_eq!(t, parse(&args("-rz 90 -t 1 0 0 -s 2 a.rad")).unwrap().transform);
        assert_eq!(parse_transform(&[]).unwrap(), Similarity::default());
        let e = |s: &str| parse_transform(&args(s)).unwrap_err();
        assert_eq!(e("-t 1 0 0 a.rad"), XformError::NotTransform { word: "a.rad".into() });
        assert_eq!(e("-n x"), XformError::NotTransform { word: "-n".into() });
        assert_eq!(e("-s 0"), XformError::ZeroScale);
    }
}
