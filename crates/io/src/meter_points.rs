//! Meter points from a text file (`opticks measure --points`): one point per line,
//! `x,y,z,nx,ny,nz` — the position and the normal of the side whose irradiance is measured, in
//! the scene's units — like the input of Radiance's `rtrace -I`. Fields are separated by commas
//! and/or whitespace (so an `rtrace` point file reads as it is). Blank lines and lines starting
//! with `#` are skipped, and so is a first line that is exactly the header `x,y,z,nx,ny,nz`
//! (case-insensitive, the same separators). The normal need not be of unit length.
//!
//! Every other line must hold six finite numbers and a non-zero normal; anything else is an
//! error naming the file and the line. At most [`MAX_TARGETS`] points, and files of at most
//! [`MAX_BYTES`], are read (checked before reading, so no allocation is sized by the input).

use crate::input_file;
use opticks_core::math::Vec3;
use opticks_core::sensor::meter::{MAX_TARGETS, MeterPoint};
use std::path::{Path, PathBuf};

/// The largest points file read (64 MiB: ~65 536 points need < 10 MB).
pub const MAX_BYTES: u64 = 64 << 20;

/// Why a points file cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum PointsError {
    /// The file cannot be opened or read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The file is too large.
    #[error("{path}: {bytes} bytes; a points file may have at most {MAX_BYTES} bytes")]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size.
        bytes: u64,
    },
    /// A line is not a point.
    #[error("{path}:{line}: {what}")]
    Line {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        what: String,
    },
    /// No points, or too many.
    #[error("{path}: {count} points; a meter needs between 1 and {MAX_TARGETS}")]
    Count {
        /// The file.
        path: PathBuf,
        /// Points found (counted up to one past the limit).
        count: usize,
    },
}

/// Reads the meter points of `path`.
pub fn read_points(path: &Path) -> Result<Vec<MeterPoint>, PointsError> {
    let io = |source| PointsError::Io { path: path.into(), source };
    let (_, bytes) = input_file::open(path).map_err(io)?;
    if bytes > MAX_BYTES {
        return Err(PointsError::TooLarge { path: path.into(), bytes });
    }
    let text = input_file::read_to_string(path).map_err(io)?;
    parse_points(&text).map_err(|e| match e {
        ParseError::Line(line, what) => PointsError::Line { path: path.into(), line, what },
        ParseError::Count(count) => PointsError::Count { path: path.into(), count },
    })
}

/// A parse failure without the file's name.
#[derive(Debug, PartialEq)]
enum ParseError {
    Line(usize, String),
    Count(usize),
}

fn fields(line: &str) -> impl Iterator<Item = &str> {
    line.split([',', ' ', '\t']).filter(|f| !f.is_empty())
}

fn parse_points(text: &str) -> Result<Vec<MeterPoint>, ParseError> {
    let mut points = Vec::new();
    let mut first = true;
    for (k, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let is_first = std::mem::replace(&mut first, false);
        let f: Vec<&str> = fields(line).take(7).collect();
        if is_first
            && f.len() == 6
            && f.iter().zip(["x", "y", "z", "nx", "ny", "nz"]).all(|(a, b)| a.eq_ignore_ascii_case(b))
        {
            continue;
        }
        let err = |what: String| ParseError::Line(k + 1, what);
        if f.len() != 6 {
            let n = if f.len() > 6 { "more than 6".to_string() } else { f.len().to_string() };
            return Err(err(format!("expected 6 numbers x,y,z,nx,ny,nz, found {n} fields in '{line}'")));
        }
        let mut v = [0.0f32; 6];
        for (slot, s) in v.iter_mut().zip(&f) {
            *slot = s.parse().map_err(|_| err(format!("'{s}' is not a number")))?;
            if !slot.is_finite() {
                return Err(err(format!("'{s}' is not a finite number")));
            }
        }
        let point = MeterPoint::new(Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]))
            .map_err(|_| err("the normal nx,ny,nz is zero".into()))?;
        if points.len() == MAX_TARGETS {
            return Err(ParseError::Count(MAX_TARGETS + 1));
        }
        points.push(point);
    }
    if points.is_empty() {
        return Err(ParseError::Count(0));
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_parse_with_header_comments_and_either_separator() {
        let p = parse_points("# workplane\nx,y,z,nx,ny,nz\n0,0.8,1, 0,1,0\n\n1 0.8 1\t0 2 0\n").unwrap();
        assert_eq!(p.len(), 2);
        assert_eq!((p[0].position, p[0].normal), (Vec3::new(0.0, 0.8, 1.0), Vec3::Y));
        assert_eq!(p[1].normal, Vec3::Y, "normalised");
    }

    #[test]
    fn bad_lines_name_their_line() {
        let line = |t: &str| match parse_points(t) {
            Err(ParseError::Line(l, what)) => (l, what),
            other => panic!("{t:?}: {other:?}"),
        };
        assert_eq!(line("0,0,0,0,1,0\n\n1,2,3,0,1\n").0, 3);
        assert!(line("1,2,3,0,1\n").1.contains("found 5"));
        assert!(line("1,2,3,0,1,0,7\n").1.contains("more than 6"));
        assert!(line("0,0,0,0,1,0\n1,2,x,0,1,0\n").1.contains("'x' is not a number"));
        assert!(line("1,2,inf,0,1,0\n").1.contains("finite"));
        assert!(line("1,2,3,0,0,0\n").1.contains("normal"));
        assert_eq!(line("x,y,z,nx,ny,nz\nx,y,z,nx,ny,nz\n").0, 2, "a header only on the first line");
        assert_eq!(parse_points("# nothing\n\n"), Err(ParseError::Count(0)));
        assert_eq!(
            parse_points(&"0,0,0,0,1,0\n".repeat(MAX_TARGETS + 1)),
            Err(ParseError::Count(MAX_TARGETS + 1))
        );
    }

    #[test]
    fn files_are_checked_before_they_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("p.csv");
        std::fs::write(&p, "0,0,0,0,1,0\n1,1\n").unwrap();
        let e = read_points(&p).unwrap_err().to_string();
        assert!(e.contains("p.csv:2:"), "{e}");
        assert!(read_points(dir.path()).unwrap_err().to_string().contains("directory"));
        assert!(read_points(&dir.path().join("none.csv")).is_err());
    }
}
