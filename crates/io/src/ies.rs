//! IES LM-63 photometric files (`.ies`): the 1986 (no format line), 1991 (`IESNA91`), 1995
//! (`IESNA:LM-63-1995`), 2002 (`IESNA:LM-63-2002`) and 2019 (`IESNA:LM-63-2019`, also spelled
//! `IES:LM-63-2019`) variants, read into a core [`IesProfile`] (angles and a candela grid).
//!
//! # Layout
//!
//! ```text
//! IESNA:LM-63-2002                 optional format line (absent in LM-63-1986 files)
//! [TEST] ...  [MANUFAC] ...        keyword lines, kept in `IesFile::keywords` (1986: free text)
//! TILT=NONE                        required; TILT=INCLUDE / TILT=<file> are refused
//! lamps lumens/lamp multiplier #vertical #horizontal photometric-type units width length height
//! ballast-factor  field-2  input-watts
//!     field-2: ballast-lamp photometric factor (1986, 1991, 1995), "future use" (2002),
//!              file generation type (2019, e.g. 1.00001)
//! vertical angles (#vertical numbers)
//! horizontal angles (#horizontal numbers)
//! candela: for each horizontal angle, #vertical values
//! ```
//!
//! After the `TILT` line, numbers are separated by any whitespace (or commas) and may wrap
//! lines freely. Only photometric type C (1) is supported: vertical angle 0° is the luminaire's
//! nadir (its axis), horizontal 0° its local x axis; types A and B are refused with a clear
//! error. The horizontal angles must start at 0° and end at 0° (rotational symmetry), 90°
//! (quadrant), 180° (bilateral) or 360° (none).
//!
//! The candela values in the profile have the **candela multiplier and the ballast factor**
//! applied, and in 1995-and-earlier files also the **ballast-lamp photometric factor** (the
//! LM-63 reading). The 2002 edition turned that field into "future use" and the 2019 edition
//! into the *file generation type* (a code, not a factor: it is kept in
//! [`IesFile::file_generation_type`] and never multiplied in). The file's rated flux
//! (lamps × lumens per lamp × multiplier, `None` for −1 "absolute photometry") is reported in
//! [`IesFile::rated_lumens`], but a light's power comes from integrating the candela
//! distribution (see `opticks_core::light::profile`): that is the flux the file's distribution
//! really carries.
//!
//! Every error names the file and the 1-based line, e.g.
//! `lamp.ies:14: candela value 3 of horizontal angle 2 is negative (-5)`.

// `!(x > 0.0)` rejects NaN along with the out-of-range values: deliberate.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use opticks_core::light::ies::IesAxis;
use opticks_core::light::{IesProfile, IesTableError};
use std::fmt;
use std::path::{Path, PathBuf};

/// The LM-63 edition a file follows, from its first line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum IesVersion {
    /// No format line.
    Lm63_1986,
    /// `IESNA91`.
    Lm63_1991,
    /// `IESNA:LM-63-1995`.
    Lm63_1995,
    /// `IESNA:LM-63-2002`.
    Lm63_2002,
    /// `IESNA:LM-63-2019` (or `IES:LM-63-2019`).
    Lm63_2019,
}

impl IesVersion {
    /// The edition named by a first line, `None` if it is not a format line.
    fn from_format_line(line: &str) -> Option<Result<Self, ()>> {
        let v = line.trim().to_ascii_uppercase();
        if v == "IESNA91" {
            return Some(Ok(IesVersion::Lm63_1991));
        }
        if !(v.starts_with("IESNA") || v.starts_with("IES:")) {
            return None;
        }
        Some(if v.contains("LM-63-1995") {
            Ok(IesVersion::Lm63_1995)
        } else if v.contains("LM-63-2002") {
            Ok(IesVersion::Lm63_2002)
        } else if v.contains("LM-63-2019") {
            Ok(IesVersion::Lm63_2019)
        } else {
            Err(())
        })
    }
}

/// A parsed IES file.
#[derive(Clone, Debug, PartialEq)]
pub struct IesFile {
    /// The edition (from the format line).
    pub version: IesVersion,
    /// The photometric grid (candela with all multipliers applied).
    pub profile: IesProfile,
    /// `[KEYWORD] value` lines, in file order.
    pub keywords: Vec<(String, String)>,
    /// Number of lamps.
    pub lamps: f32,
    /// Lumens per lamp, `None` for −1 (absolute photometry).
    pub lumens_per_lamp: Option<f32>,
    /// Candela multiplier.
    pub multiplier: f32,
    /// Ballast factor, times the ballast-lamp photometric factor in 1995-and-earlier files.
    pub ballast_factor: f32,
    /// The 2019 edition's file generation type (the second field of the ballast line).
    pub file_generation_type: Option<f32>,
    /// Luminous opening width, length, height (as given, in `units`).
    pub dimensions: [f32; 3],
    /// Units type: 1 = feet, 2 = metres.
    pub units: u32,
    /// Input watts.
    pub input_watts: f32,
}

impl IesFile {
    /// The flux the file claims: lamps × lumens per lamp × multiplier × ballast factor, if given.
    pub fn rated_lumens(&self) -> Option<f32> {
        self.lumens_per_lamp.map(|l| self.lamps * l * self.multiplier * self.ballast_factor)
    }
}

/// What is wrong with an IES file, and where.
#[derive(Debug)]
pub struct IesError {
    /// The file.
    pub file: PathBuf,
    /// 1-based line (0 when the file could not be read).
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for IesError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line > 0 {
            write!(f, "{}:{}: {}", self.file.display(), self.line, self.message)
        } else {
            write!(f, "{}: {}", self.file.display(), self.message)
        }
    }
}

impl std::error::Error for IesError {}

/// Reads and parses an IES file.
pub fn load_ies(path: &Path) -> Result<IesFile, IesError> {
    let bytes = crate::input_file::read(path).map_err(|e| IesError {
        file: path.to_path_buf(),
        line: 0,
        message: format!("cannot read the IES file: {e}"),
    })?;
    // LM-63 files are ASCII; tolerate Latin-1 bytes in keyword lines.
    let text: String = bytes.iter().map(|&b| b as char).collect();
    parse_ies(&text, path)
}

/// Numbers after the TILT line, with their lines.
struct Tokens<'a> {
    toks: Vec<(&'a str, usize)>,
    pos: usize,
    file: &'a Path,
    last_line: usize,
}

impl<'a> Tokens<'a> {
    fn err(&self, line: usize, message: impl Into<String>) -> IesError {
        IesError { file: self.file.to_path_buf(), line, message: message.into() }
    }

    fn number(&mut self, what: &str) -> Result<(f64, usize), IesError> {
        let Some(&(t, line)) = self.toks.get(self.pos) else {
            return Err(self.err(self.last_line, format!("the file ends before the {what} (truncated?)")));
        };
        self.pos += 1;
        let v: f64 = t.parse().map_err(|_| self.err(line, format!("{what}: \"{t}\" is not a number")))?;
        if !v.is_finite() || (v as f32).is_infinite() {
            return Err(self.err(line, format!("{what}: \"{t}\" is not a finite number")));
        }
        Ok((v, line))
    }

    fn count(&mut self, what: &str) -> Result<usize, IesError> {
        let (v, line) = self.number(what)?;
        if v.fract() != 0.0 || !(1.0..=100_000.0).contains(&v) {
            return Err(self.err(line, format!("{what} must be a whole number from 1 to 100000, found {v}")));
        }
        Ok(v as usize)
    }
}

/// Parses the text of an IES file; `file` is only used in messages.
pub fn parse_ies(text: &str, file: &Path) -> Result<IesFile, IesError> {
    let err = |line: usize, message: String| IesError { file: file.to_path_buf(), line, message };
    let lines: Vec<&str> = text.lines().collect();
    let mut keywords = Vec::new();
    let mut tilt_line = None;
    let mut version = IesVersion::Lm63_1986;
    for (i, raw) in lines.iter().enumerate() {
        let l = raw.trim();
        if i == 0 {
            match IesVersion::from_format_line(l) {
                Some(Ok(v)) => {
                    version = v;
                    continue;
                }
                Some(Err(())) => {
                    return Err(err(
                        1,
                        format!(
                            "unknown IES format line \"{l}\" (supported: none for LM-63-1986, IESNA91, \
                             IESNA:LM-63-1995, IESNA:LM-63-2002, IESNA:LM-63-2019)"
                        ),
                    ));
                }
                None => {}
            }
        }
        if let Some(rest) = l.strip_prefix("TILT=").or_else(|| l.strip_prefix("TILT =")) {
            let rest = rest.trim();
            if rest != "NONE" {
                return Err(err(
                    i + 1,
                    format!(
                        "TILT={rest} is not supported (only TILT=NONE: lamp-tilt multiplier tables are not implemented)"
                    ),
                ));
            }
            tilt_line = Some(i);
            break;
        }
        if let Some(k) = l.strip_prefix('[')
            && let Some(end) = k.find(']')
        {
            keywords.push((k[..end].to_string(), k[end + 1..].trim().to_string()));
            continue;
        }
        // Free text lines are allowed before TILT in LM-63-1986 files.
    }
    let Some(tilt) = tilt_line else {
        return Err(err(
            lines.len().max(1),
            "no TILT= line: this is not an IES LM-63 file (or it is truncated before the photometric data)"
                .into(),
        ));
    };
    let mut toks = Vec::new();
    for (i, l) in lines.iter().enumerate().skip(tilt + 1) {
        for t in l.split(|c: char| c.is_whitespace() || c == ',').filter(|t| !t.is_empty()) {
            toks.push((t, i + 1));
        }
    }
    let mut t = Tokens { toks, pos: 0, file, last_line: lines.len().max(1) };
    let (lamps, lamps_line) = t.number("number of lamps")?;
    if !(lamps > 0.0) {
        return Err(err(lamps_line, format!("the number of lamps must be positive, found {lamps}")));
    }
    let (lumens, lumens_line) = t.number("lumens per lamp")?;
    if !(lumens > 0.0 || lumens == -1.0) {
        return Err(err(
            lumens_line,
            format!("lumens per lamp must be positive or -1 (absolute), found {lumens}"),
        ));
    }
    let (multiplier, mline) = t.number("candela multiplier")?;
    if !(multiplier > 0.0) {
        return Err(err(mline, format!("the candela multiplier must be positive, found {multiplier}")));
    }
    let nv = t.count("number of vertical angles")?;
    let nh = t.count("number of horizontal angles")?;
    let (ptype, pline) = t.number("photometric type")?;
    match ptype as i64 {
        1 if ptype == 1.0 => {}
        2 | 3 if ptype.fract() == 0.0 => {
            return Err(err(
                pline,
                format!(
                    "photometric type {} ({}) is not supported: only type C (1), the usual one for luminaires",
                    ptype,
                    if ptype == 2.0 { "B" } else { "A" }
                ),
            ));
        }
        _ => {
            return Err(err(pline, format!("photometric type must be 1 (C), 2 (B) or 3 (A), found {ptype}")));
        }
    }
    let (units, uline) = t.number("units type")?;
    if units != 1.0 && units != 2.0 {
        return Err(err(uline, format!("units type must be 1 (feet) or 2 (metres), found {units}")));
    }
    let mut dims = [0.0f32; 3];
    for (d, what) in dims.iter_mut().zip(["width", "length", "height"]) {
        *d = t.number(&format!("luminous opening {what}"))?.0 as f32;
    }
    let (ballast, bline) = t.number("ballast factor")?;
    let second = match version {
        IesVersion::Lm63_2019 => "file generation type",
        IesVersion::Lm63_2002 => "future-use field of the ballast line",
        _ => "ballast-lamp photometric factor",
    };
    let (field2, line2) = t.number(second)?;
    let (watts, _) = t.number("input watts")?;
    if !(ballast > 0.0) {
        return Err(err(bline, format!("the ballast factor must be positive, found {ballast}")));
    }
    // Only 1995-and-earlier files carry a photometric factor there; 2002 reserved the field and
    // 2019 made it the file generation type (a code such as 1.00001, not a factor).
    let ballast_lamp = if version <= IesVersion::Lm63_1995 {
        if !(field2 > 0.0) {
            return Err(err(line2, format!("the {second} must be positive, found {field2}")));
        }
        field2
    } else {
        1.0
    };
    if version == IesVersion::Lm63_2019 && !(1.0..2.0).contains(&field2) {
        return Err(err(
            line2,
            format!("the {second} must be a code from 1.00000 to 1.99999, found {field2}"),
        ));
    }
    let factor = multiplier * ballast * ballast_lamp;
    let angles = |n: usize, what: &str, t: &mut Tokens| -> Result<Vec<(f32, usize)>, IesError> {
        (0..n)
            .map(|k| t.number(&format!("{what} angle {} of {n}", k + 1)).map(|(a, line)| (a as f32, line)))
            .collect()
    };
    let va = angles(nv, "vertical", &mut t)?;
    let ha = angles(nh, "horizontal", &mut t)?;
    let (vline, hline) = (va[nv - 1].1, ha[nh - 1].1);
    let (va, va_lines): (Vec<f32>, Vec<usize>) = va.into_iter().unzip();
    let (ha, ha_lines): (Vec<f32>, Vec<usize>) = ha.into_iter().unzip();
    // The grid's constraints are the core's, reported at the offending value's line.
    IesProfile::check_angles(&va, &ha).map_err(|e| {
        let line = match e {
            IesTableError::NotIncreasing { axis: IesAxis::Vertical, index, .. } => va_lines[index],
            IesTableError::NotIncreasing { axis: IesAxis::Horizontal, index, .. } => ha_lines[index],
            IesTableError::HorizontalRange { .. } => hline,
            _ => vline,
        };
        err(line, e.to_string())
    })?;
    // Never allocate from an unchecked count: no more values than the file has numbers left (a
    // 2 MB file declaring 100000 × 100000 angles asked for 40 GB here).
    let mut candela = Vec::with_capacity((nv * nh).min(t.toks.len() - t.pos));
    for h in 0..nh {
        for v in 0..nv {
            let what = format!(
                "candela value {} of horizontal angle {} ({} values expected)",
                v + 1,
                h + 1,
                nv * nh
            );
            let (c, line) = t.number(&what)?;
            let c = (c * factor) as f32;
            IesProfile::check_candela(h, v, c).map_err(|e| err(line, e.to_string()))?;
            candela.push(c);
        }
    }
    if let Some(&(extra, line)) = t.toks.get(t.pos) {
        return Err(err(
            line,
            format!(
                "unexpected \"{extra}\" after the {} candela values ({} extra values: do the angle counts match the data?)",
                nv * nh,
                t.toks.len() - t.pos
            ),
        ));
    }
    Ok(IesFile {
        version,
        profile: IesProfile { vertical_angles: va, horizontal_angles: ha, candela },
        keywords,
        lamps: lamps as f32,
        lumens_per_lamp: (lumens > 0.0).then_some(lumens as f32),
        multiplier: multiplier as f32,
        ballast_factor: (ballast * ballast_lamp) as f32,
        file_generation_type: (version == IesVersion::Lm63_2019).then_some(field2 as f32),
        dimensions: dims,
        units: units as u32,
        input_watts: watts as f32,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "IESNA:LM-63-2002\n[TEST] unit\n[MANUFAC] none\nTILT=NONE\n1 1000 2 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n200 100 0\n";

    fn parse(s: &str) -> Result<IesFile, IesError> {
        parse_ies(s, Path::new("t.ies"))
    }

    #[test]
    fn parses_a_symmetric_file() {
        let f = parse(GOOD).unwrap();
        assert_eq!(f.profile.vertical_angles, vec![0.0, 90.0, 180.0]);
        assert_eq!(f.profile.horizontal_angles, vec![0.0]);
        assert_eq!(f.profile.candela, vec![400.0, 200.0, 0.0], "multiplier 2 applied");
        assert_eq!(f.keywords[0], ("TEST".into(), "unit".into()));
        assert_eq!(f.rated_lumens(), Some(2000.0));
    }

    /// The hand-written per-edition files of testdata/ies/ (testdata/README.md): the same
    /// 3-angle symmetric distribution (multiplier 2, ballast factor 0.9) with 0.5 in the
    /// ballast line's second field, which is a photometric factor only up to LM-63-1995.
    #[test]
    fn every_lm63_edition_is_read_with_its_own_ballast_line() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/ies");
        let cases = [
            ("lm63-1986.ies", IesVersion::Lm63_1986, 0.45, None),
            ("lm63-1991.ies", IesVersion::Lm63_1991, 0.45, None),
            ("lm63-1995.ies", IesVersion::Lm63_1995, 0.45, None),
            ("lm63-2002.ies", IesVersion::Lm63_2002, 0.9, None),
            ("lm63-2019.ies", IesVersion::Lm63_2019, 0.9, Some(1.10001)),
        ];
        for (name, version, ballast, generation) in cases {
            let f = load_ies(&dir.join(name)).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(f.version, version, "{name}");
            assert!((f.ballast_factor - ballast).abs() < 1e-6, "{name}: {}", f.ballast_factor);
            assert_eq!(f.file_generation_type, generation, "{name}");
            let want = [200.0, 100.0, 0.0].map(|c| c * 2.0 * ballast);
            for (c, w) in f.profile.candela.iter().zip(want) {
                assert!((c - w).abs() < 1e-3, "{name}: candela {:?} vs {want:?}", f.profile.candela);
            }
            assert_eq!(f.profile.vertical_angles, vec![0.0, 90.0, 180.0], "{name}");
        }
        let f = load_ies(&dir.join("lm63-1986.ies")).unwrap();
        assert!(f.keywords.is_empty(), "1986 header lines are free text: {:?}", f.keywords);
    }

    #[test]
    fn edition_specific_fields_are_checked() {
        let body = "TILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 X 10\n0 90 180\n0\n1 1 1\n";
        let with = |first: &str, x: &str| format!("{first}{}", body.replace('X', x));
        // A zero factor is refused only where it is a factor; 2019 wants a generation code.
        let e = parse(&with("IESNA:LM-63-1995\n", "0")).unwrap_err().to_string();
        assert!(e.starts_with("t.ies:4: the ballast-lamp photometric factor must be positive"), "{e}");
        assert!(parse(&with("", "-1")).is_err());
        assert_eq!(parse(&with("IESNA:LM-63-2002\n", "0")).unwrap().ballast_factor, 1.0);
        let e = parse(&with("IESNA:LM-63-2019\n", "0.5")).unwrap_err().to_string();
        assert!(e.starts_with("t.ies:4: the file generation type must be a code"), "{e}");
        let f = parse(&with("IES:LM-63-2019\n", "1.00001")).unwrap();
        assert_eq!((f.version, f.profile.candela[0]), (IesVersion::Lm63_2019, 1.0));
        let e = parse(&with("IESNA:LM-63-2031\n", "1")).unwrap_err().to_string();
        assert!(e.starts_with("t.ies:1: unknown IES format line"), "{e}");
    }

    /// Issue 10, item 12: a 2 MB file declaring 100000 × 100000 angles (valid, increasing ones)
    /// made the reader reserve 40 GB for the candela table and abort. The counts are checked
    /// against the numbers the file holds before anything is allocated from them.
    #[test]
    fn angle_counts_allocate_no_more_than_the_file_holds() {
        let n = 100_000;
        let mut text =
            format!("IESNA:LM-63-2002\nTILT=NONE\n1 -1 1.0 {n} {n} 1 2 0.1 0.3 0.05\n1.0 1.0 35\n");
        for k in 0..n {
            text += &format!("{} ", k as f64 * 90.0 / (n - 1) as f64);
        }
        text += "\n";
        for k in 0..n {
            text += &format!("{} ", k as f64 * 360.0 / (n - 1) as f64);
        }
        text += "\n1 2 3\n";
        let e = parse(&text).unwrap_err();
        assert_eq!(e.line, 7, "{e}");
        assert!(
            e.to_string().contains("the file ends before the candela value 4 of horizontal angle 1"),
            "{e}"
        );
    }

    #[test]
    fn malformed_files_name_file_and_line() {
        let cases = [
            ("IESNA:LM-63-2002\n[TEST] x\n1 1000 1 3 1 1 2 0 0 0\n", "t.ies:3: no TILT= line"),
            ("TILT=INCLUDE\n1\n", "t.ies:1: TILT=INCLUDE is not supported"),
            (
                "TILT=NONE\n1 1000 1 0 1 1 2 0 0 0\n",
                "t.ies:2: number of vertical angles must be a whole number",
            ),
            ("TILT=NONE\n1 1000 1 3 1.5 1 2 0 0 0\n", "t.ies:2: number of horizontal angles must be"),
            (
                "TILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 90 abc\n0\n1 1 1\n",
                "t.ies:4: vertical angle 3 of 3: \"abc\" is not a number",
            ),
            (
                "TILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n1 1\n",
                "t.ies:6: the file ends before the candela value 3",
            ),
            (
                "TILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n1\n-5 1\n",
                "t.ies:7: candela value 2 of horizontal angle 1 is negative",
            ),
            (
                "TILT=NONE\n1 1000 1 3 1 3 2 0 0 0\n1 1 10\n0 90 180\n0\n1 1 1\n",
                "t.ies:2: photometric type 3 (A) is not supported",
            ),
            (
                "TILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 90 180\n0\n1 1 1 7\n",
                "t.ies:6: unexpected \"7\"",
            ),
            (
                "TILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 90 90\n0\n1 1 1\n",
                "t.ies:4: vertical angles must increase",
            ),
            (
                "TILT=NONE\n1 1000 1 3 2 1 2 0 0 0\n1 1 10\n0 90 180\n0 45\n1 1 1 1 1 1\n",
                "t.ies:5: horizontal angles 0..45",
            ),
            ("TILT=NONE\n1 1000 -1 3 1 1 2 0 0 0\n", "t.ies:2: the candela multiplier must be positive"),
            (
                "TILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 90 200\n0\n1 1 1\n",
                "t.ies:4: vertical angles must lie in [0, 180]",
            ),
            (
                "TILT=NONE\n1 1000 1 3 1 1 2 0 0 nan\n",
                "t.ies:2: luminous opening height: \"nan\" is not a finite",
            ),
        ];
        for (text, want) in cases {
            let e = parse(text).expect_err(text).to_string();
            assert!(e.starts_with(want), "{text:?}\n got: {e}\nwant: {want}");
        }
    }
}
