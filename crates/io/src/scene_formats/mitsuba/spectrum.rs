//! Spectra in an RGB renderer, converted the way Mitsuba 3's RGB variants convert them
//! (`Properties::get_texture` and `spectrum_list_to_srgb` in Mitsuba's sources), so that a scene
//! written for Mitsuba renders with the colours Mitsuba's `*_rgb` variants give it:
//!
//! * a tabulated spectrum — `<spectrum value="λ₁:v₁, λ₂:v₂, …">` (nm, increasing) or
//!   `<spectrum filename="x.spd">` (lines `λ v`, `#` comments) — is integrated against the CIE
//!   1931 colour matching functions, times the D65 illuminant (normalised to luminance 1) for a
//!   reflectance or an index and without it for an emitter; 1000 steps over 360–830 nm, the
//!   spectrum linear between its samples and zero outside them; the XYZ are scaled so that a
//!   constant 1 has Y = 1 and converted to linear sRGB. Negative channels become 0; a
//!   reflectance's channels are also clamped to 1 (Mitsuba's `bounded`), an emitter's and an
//!   index's are not;
//! * a constant `<spectrum value="v">` is v for a reflectance, and v·M·(1, 1, 1) =
//!   v·(1.2048, 0.9483, 0.9093) for an emitter: Mitsuba's RGB variants give a uniform emission
//!   spectrum that slightly purple colour, the sRGB response of an equal-energy illuminant, so
//!   that they match its spectral variants;
//! * `<rgb>` is taken as linear sRGB as it is.
//!
//! The tables are Mitsuba's ([`super::cie`], written from Mitsuba by `tools/mitsuba/cie_tables.py`).

use super::cie::NODES;
use glam::{DMat3, DVec3};

/// The linear-sRGB colour of a tabulated spectrum (`wavelengths` increasing, nm), by Mitsuba's
/// rule (module docs): with the D65 illuminant for a reflectance or index (`d65`), clamped to
/// [0, 1] if `bounded`, else only to ≥ 0.
pub fn to_srgb(wavelengths: &[f64], values: &[f64], bounded: bool, d65: bool) -> DVec3 {
    const STEPS: usize = 1000;
    const MIN: f64 = 360.0;
    const MAX: f64 = 830.0;
    let mut xyz = DVec3::ZERO;
    let n = wavelengths.len();
    for i in 0..STEPS {
        let w = MIN + (i as f64 / (STEPS - 1) as f64) * (MAX - MIN);
        if n < 2 || w < wavelengths[0] || w > wavelengths[n - 1] {
            continue;
        }
        // The last interval [k, k+1] with wavelengths[k] ≤ w.
        let k = wavelengths.partition_point(|&x| x <= w).clamp(1, n - 1) - 1;
        let (w0, w1, v0, v1) = (wavelengths[k], wavelengths[k + 1], values[k], values[k + 1]);
        let v = ((w - w1) * v0 + (w0 - w) * v1) / (w0 - w1);
        let [x, y, z, d] = node(w);
        xyz += DVec3::new(x, y, z) * v * if d65 { d } else { 1.0 };
    }
    // Mitsuba's MI_CIE_Y_NORMALIZATION = 1/106.75025939941406: a constant 1 has Y = 1.
    xyz *= (MAX - MIN) / 106.750_259_399_414_06 / STEPS as f64;
    let rgb = xyz_to_srgb(xyz).max(DVec3::ZERO);
    if bounded { rgb.min(DVec3::ONE) } else { rgb }
}

/// Mitsuba's colour of a constant spectrum `v` on an emitter: v·M·(1, 1, 1).
pub fn uniform_emission(v: f64) -> DVec3 {
    xyz_to_srgb(DVec3::ONE) * v
}

/// CIE XYZ → linear sRGB (Mitsuba's matrix).
fn xyz_to_srgb(xyz: DVec3) -> DVec3 {
    let m = DMat3::from_cols_array(&[
        3.240479, -0.969256, 0.055648, -1.537150, 1.875991, -0.204043, -0.498535, 0.041556, 1.057311,
    ]);
    m * xyz
}

/// (x̄, ȳ, z̄, D65) at `w` nm, linear between Mitsuba's nodes.
fn node(w: f64) -> [f64; 4] {
    let t = (w - 360.0) * (94.0 / 470.0);
    let i0 = (t.max(0.0) as usize).min(93);
    let f = t - i0 as f64;
    std::array::from_fn(|c| (1.0 - f) * NODES[i0][c] as f64 + f * NODES[i0 + 1][c] as f64)
}

/// Why a tabulated spectrum is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpectrumError {
    /// An item of a `value="λ:v, …"` list is not two finite numbers joined by `:`.
    #[error("\"{0}\" is not wavelength:value")]
    NotAPair(String),
    /// Fewer than two samples.
    #[error("a spectrum needs at least two wavelength:value pairs")]
    TooFew,
    /// A wavelength not above the one before it.
    #[error("wavelengths must increase: {next} nm follows {previous} nm")]
    NotIncreasing {
        /// The earlier wavelength (nm).
        previous: f64,
        /// The one after it (nm).
        next: f64,
    },
}

/// A line of a `.spd` file that is not two finite numbers (the message leaves the file's path and
/// the line number to the caller).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("expected \"wavelength value\", found \"{found}\"")]
pub struct BadSpdLine {
    /// 1-based line number.
    pub line: u32,
    /// The line, comment and surrounding blanks removed.
    pub found: String,
}

/// The wavelength–value pairs of a `.spd` file's text (`λ v` per line, `#` comments, blank lines).
pub fn parse_spd(text: &str) -> Result<(Vec<f64>, Vec<f64>), BadSpdLine> {
    let (mut w, mut v) = (Vec::new(), Vec::new());
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let nums: Vec<&str> = line.split_whitespace().collect();
        let parse = |s: &str| s.parse::<f64>().ok().filter(|x| x.is_finite());
        match (nums.as_slice(), nums.first().and_then(|s| parse(s)), nums.get(1).and_then(|s| parse(s))) {
            ([_, _], Some(a), Some(b)) => {
                w.push(a);
                v.push(b);
            }
            _ => return Err(BadSpdLine { line: i as u32 + 1, found: line.to_string() }),
        }
    }
    Ok((w, v))
}

/// The pairs of a `value="λ:v, λ:v, …"` attribute.
pub fn parse_pairs(text: &str) -> Result<(Vec<f64>, Vec<f64>), SpectrumError> {
    let (mut w, mut v) = (Vec::new(), Vec::new());
    for pair in text.split(|c: char| c == ',' || c.is_whitespace()).filter(|t| !t.is_empty()) {
        let parsed = pair
            .split_once(':')
            .and_then(|(a, b)| Some((a.trim().parse::<f64>().ok()?, b.trim().parse::<f64>().ok()?)))
            .filter(|(a, b)| a.is_finite() && b.is_finite());
        let Some((a, b)) = parsed else { return Err(SpectrumError::NotAPair(pair.to_string())) };
        w.push(a);
        v.push(b);
    }
    Ok((w, v))
}

/// An error unless the wavelengths are at least two and strictly increasing.
pub fn check(wavelengths: &[f64]) -> Result<(), SpectrumError> {
    if wavelengths.len() < 2 {
        return Err(SpectrumError::TooFew);
    }
    if let Some(i) = (1..wavelengths.len()).find(|&i| wavelengths[i] <= wavelengths[i - 1]) {
        return Err(SpectrumError::NotIncreasing { previous: wavelengths[i - 1], next: wavelengths[i] });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The values Mitsuba 3.9's `spectrum_list_to_srgb` gives for the same spectra
    /// (`tools/mitsuba/cie_tables.py` prints them).
    #[test]
    fn conversion_is_mitsubas() {
        let (w, v) = ([400.0, 500.0, 600.0, 700.0], [0.1, 0.9, 0.3, 0.5]);
        let near = |a: DVec3, b: [f64; 3]| (a - DVec3::from_array(b)).abs().max_element() < 2e-5;
        let r = to_srgb(&w, &v, true, true);
        assert!(near(r, [0.17351087927818298, 0.6833183169364929, 0.5242169499397278]), "{r}");
        let e = to_srgb(&w, &v, false, false);
        assert!(near(e, [0.2630835175514221, 0.6451127529144287, 0.46486055850982666]), "{e}");
        let flat = to_srgb(&[300.0, 900.0], &[1.0, 1.0], false, false);
        assert!(near(flat, [1.2048826217651367, 0.9482288956642151, 0.9092667698860168]), "{flat}");
        assert!((uniform_emission(1.0) - flat).abs().max_element() < 1e-3);
        // A constant reflectance under D65 is grey.
        let grey = to_srgb(&[360.0, 830.0], &[0.5, 0.5], true, true);
        assert!((grey - DVec3::splat(0.5)).abs().max_element() < 2e-3, "{grey}");
    }

    #[test]
    fn text_forms_parse_and_bad_ones_are_located() {
        assert_eq!(
            parse_pairs("400:0.5, 500:1,600:2").unwrap(),
            (vec![400.0, 500.0, 600.0], vec![0.5, 1.0, 2.0])
        );
        assert_eq!(parse_pairs("400:0.5, 500").unwrap_err(), SpectrumError::NotAPair("500".into()));
        assert_eq!(parse_pairs("400:0.5, 500").unwrap_err().to_string(), "\"500\" is not wavelength:value");
        assert_eq!(parse_spd("# c\n400 1\n\n500 2 # x\n").unwrap(), (vec![400.0, 500.0], vec![1.0, 2.0]));
        assert_eq!(parse_spd("400 1\n500 x\n").unwrap_err(), BadSpdLine { line: 2, found: "500 x".into() });
        assert_eq!(check(&[400.0]), Err(SpectrumError::TooFew));
        assert_eq!(
            check(&[500.0, 400.0]).unwrap_err().to_string(),
            "wavelengths must increase: 400 nm follows 500 nm"
        );
    }
}
