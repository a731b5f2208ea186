//! Wavefront MTL material libraries: the statements Opticks maps to its materials (see the table
//! in [`super`]), parsed into [`MtlMaterial`] records with the line of every value, and the
//! conversion of a record to a core [`Material`] (Lambert or Modified Phong) plus an optional
//! emitted radiance.
//!
//! Parsing never fails on things that are merely unsupported (textures, transparency, the PBR
//! extension): those become warnings. It fails, with the line, on values that cannot be read (a
//! colour that is not one or three numbers, a non-finite number, `newmtl` without a name).

use super::super::{FileLocation, SceneFileError};
use super::err;
use opticks_core::bsdf::{Bsdf, Lambert, Material, MaterialError, ModifiedPhong};
use opticks_core::light::check::check_emission;
use opticks_core::math::Rgb;
use std::path::Path;

/// A value and the 1-based line it was read from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AtLine<T> {
    /// The value.
    pub value: T,
    /// Its line in the MTL file.
    pub line: u32,
}

/// One `newmtl` block: the statements Opticks uses.
#[derive(Clone, Debug, PartialEq)]
pub struct MtlMaterial {
    /// The material name (`newmtl` argument).
    pub name: String,
    /// The `newmtl` line.
    pub line: u32,
    /// Diffuse reflectance `Kd`.
    pub kd: Option<AtLine<Rgb>>,
    /// Specular reflectance `Ks`.
    pub ks: Option<AtLine<Rgb>>,
    /// Phong exponent `Ns`.
    pub ns: Option<AtLine<f32>>,
    /// Emitted radiance `Ke`, W/(m²·sr).
    pub ke: Option<AtLine<Rgb>>,
    /// Line of a `map_Ke` statement, if any (then `Ke` is a texture multiplier: no emission).
    pub map_ke: Option<u32>,
}

/// A parsed MTL file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MtlLibrary {
    /// Materials in file order.
    pub materials: Vec<MtlMaterial>,
    /// Unsupported or ignored statements, `file:line: message`.
    pub warnings: Vec<String>,
}

/// Parses MTL text. `file` is used in messages only.
pub fn parse_mtl(data: &[u8], file: &Path) -> Result<MtlLibrary, SceneFileError> {
    let text = String::from_utf8_lossy(data);
    let mut lib = MtlLibrary::default();
    let mut unknown_seen: Vec<String> = Vec::new();
    let mut warnings: Vec<String> = Vec::new();
    for (i, raw) in text.split('\n').enumerate() {
        let line_no = u32::try_from(i + 1).unwrap_or(u32::MAX);
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut tokens = line.split_ascii_whitespace();
        let Some(keyword) = tokens.next() else { continue };
        let rest = line[keyword.len()..].trim();
        let args: Vec<&str> = tokens.collect();
        let warn = |warnings: &mut Vec<String>, msg: String| {
            warnings.push(format!("{}:{line_no}: {msg}", file.display()));
        };
        if keyword == "newmtl" {
            if rest.is_empty() {
                return Err(err(file, line_no, "newmtl without a material name".into()));
            }
            if lib.materials.iter().any(|m| m.name == rest) {
                warn(
                    &mut warnings,
                    format!("material {rest:?} is defined a second time; the first definition is used"),
                );
            }
            lib.materials.push(MtlMaterial {
                name: rest.to_string(),
                line: line_no,
                kd: None,
                ks: None,
                ns: None,
                ke: None,
                map_ke: None,
            });
            continue;
        }
        let Some(current) = lib.materials.last_mut() else {
            warn(&mut warnings, format!("{keyword}: statement before the first newmtl is ignored"));
            continue;
        };
        match keyword {
            "Kd" | "Ks" | "Ke" => {
                let Some(rgb) = parse_colour(keyword, &args, file, line_no)? else {
                    warn(
                        &mut warnings,
                        format!(
                            "{keyword} {}: spectral and CIE XYZ colours are not supported; the statement is ignored",
                            args.first().copied().unwrap_or("")
                        ),
                    );
                    continue;
                };
                let v = Some(AtLine { value: rgb, line: line_no });
                match keyword {
                    "Kd" => current.kd = v,
                    "Ks" => current.ks = v,
                    _ => current.ke = v,
                }
            }
            "Ns" => {
                let [tok] = args[..] else {
                    return Err(err(file, line_no, format!("Ns takes one number, got {}", args.len())));
                };
                let ns = parse_number(tok, "Ns", file, line_no)?;
                current.ns = Some(AtLine { value: ns, line: line_no });
            }
            "map_Ke" => {
                current.map_ke = Some(line_no);
                warn(
                    &mut warnings,
                    format!(
                        "map_Ke: textures are not supported, and with an emission texture Ke is only its multiplier: material {:?} does not emit",
                        current.name
                    ),
                );
            }
            "map_Kd" | "map_Ks" | "map_Ns" | "map_d" | "map_Ka" | "bump" | "map_bump" | "disp" | "decal"
            | "refl" | "norm" | "map_Pr" | "map_Pm" => {
                let used = match keyword {
                    "map_Kd" => "the constant Kd is used",
                    "map_Ks" => "the constant Ks is used",
                    "map_Ns" => "the constant Ns is used",
                    _ => "it is ignored",
                };
                warn(&mut warnings, format!("{keyword}: textures are not supported; {used}"));
            }
            "d" | "Tr" => {
                let v = args.first().and_then(|t| t.parse::<f32>().ok());
                let opaque = match (keyword, v) {
                    ("d", Some(d)) => d >= 1.0,
                    ("Tr", Some(t)) => t <= 0.0,
                    _ => true,
                };
                if !opaque {
                    warn(
                        &mut warnings,
                        format!("{keyword} {}: transparency is not supported; the surface is opaque", rest),
                    );
                }
            }
            // Read but meaningless for Opticks: ambient colour, illumination model (Ks decides),
            // index of refraction, transmission filter, reflection-map sharpness.
            "Ka" | "illum" | "Ni" | "Tf" | "sharpness" => {}
            other => {
                if !unknown_seen.iter().any(|u| u == other) {
                    unknown_seen.push(other.to_string());
                    warn(
                        &mut warnings,
                        format!("{other}: unsupported statement, ignored (reported once per file)"),
                    );
                }
            }
        }
    }
    lib.warnings = warnings;
    Ok(lib)
}

fn parse_number(tok: &str, what: &str, file: &Path, line: u32) -> Result<f32, SceneFileError> {
    match tok.parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(err(file, line, format!("{what} value {tok:?} is not finite"))),
        Err(_) => Err(err(file, line, format!("{what} value {tok:?} is not a number"))),
    }
}

/// `K? r g b` or `K? r` (grey). `None` for the `spectral` and `xyz` forms.
fn parse_colour(what: &str, args: &[&str], file: &Path, line: u32) -> Result<Option<Rgb>, SceneFileError> {
    if matches!(args.first(), Some(&"spectral") | Some(&"xyz")) {
        return Ok(None);
    }
    match *args {
        [g] => Ok(Some(Rgb::splat(parse_number(g, what, file, line)?))),
        [r, g, b] => Ok(Some(Rgb::new(
            parse_number(r, what, file, line)?,
            parse_number(g, what, file, line)?,
            parse_number(b, what, file, line)?,
        ))),
        _ => Err(err(file, line, format!("{what} takes 1 or 3 numbers, got {}", args.len()))),
    }
}

/// Diffuse reflectance of a material without `Kd`: 0.5, like the default material.
pub const DEFAULT_KD: f32 = 0.5;

/// A material converted for the core, with what had to be adjusted.
#[derive(Clone, Debug, PartialEq)]
pub struct Converted {
    /// The core material (two-sided).
    pub material: Material,
    /// Emitted radiance, W/(m²·sr), if `Ke` > 0 and there is no `map_Ke`.
    pub emission: Option<Rgb>,
    /// Adjustments made (Kd + Ks scaled down), `file:line: message`.
    pub warnings: Vec<String>,
}

/// Maps an MTL material to the core (see the table in [`super`]).
pub fn convert(m: &MtlMaterial, file: &Path) -> Result<Converted, SceneFileError> {
    let element = format!("newmtl {}", m.name);
    let loc = |line: u32| FileLocation { file: file.to_path_buf(), line, column: 0 };
    if let Some(ke) = m.ke {
        check_emission(ke.value).map_err(|e| SceneFileError::Invalid {
            at: loc(ke.line),
            element: element.clone(),
            message: format!("Ke: {e}"),
        })?;
    }
    let mut warnings = Vec::new();
    let mut kd = m.kd.map_or(Rgb::splat(DEFAULT_KD), |v| v.value);
    let mut ks = m.ks.map_or(Rgb::ZERO, |v| v.value);
    // In f64: Kd + Ks of two values near f32::MAX does not overflow, and the scale of a huge
    // peak is no f32 subnormal that a step-down loop could never move (`Kd 3.3e38` hung here).
    let sum = kd.as_dvec3() + ks.as_dvec3();
    let peak = sum.max_element();
    if peak > 1.0 {
        let scale = 1.0 / peak;
        kd = (kd.as_dvec3() * scale).as_vec3();
        ks = (ks.as_dvec3() * scale).as_vec3();
        // Rounding to f32 may leave the sum an ulp above 1; the largest channel is about 1, so
        // each step moves it, and a few steps suffice.
        for _ in 0..8 {
            if (kd + ks).max_element() <= 1.0 {
                break;
            }
            kd *= 1.0 - f32::EPSILON;
            ks *= 1.0 - f32::EPSILON;
        }
        let line = m.ks.or(m.kd).map_or(m.line, |v| v.line);
        warnings.push(format!(
            "{}: {element}: Kd + Ks = ({}, {}, {}) exceeds 1, which would create energy: both scaled by {}",
            loc(line),
            sum.x as f32,
            sum.y as f32,
            sum.z as f32,
            scale as f32
        ));
    }
    // The core checks the values (a negative Ks, too, makes a Modified Phong it refuses).
    let bsdf = if ks == Rgb::ZERO {
        Lambert::new(kd).map(Bsdf::Lambert)
    } else {
        let ns = m.ns.map_or(0.0, |v| v.value);
        ModifiedPhong::new(kd, ks, ns).map(Bsdf::ModifiedPhong)
    }
    .map_err(|source| {
        let (source, line) = in_mtl_terms(source, m);
        SceneFileError::Material { at: loc(line.unwrap_or(m.line)), element: element.clone(), source }
    })?;
    let emission = match (m.ke, m.map_ke) {
        (Some(ke), None) if ke.value.max_element() > 0.0 => Some(ke.value),
        _ => None,
    };
    Ok(Converted { material: Material { name: m.name.clone(), bsdf, two_sided: true }, emission, warnings })
}

/// The core's error about one of its parameters (`reflectance` or `kd`, `ks`, `exponent`) said
/// with the MTL statement that gave it (`Kd`, `Ks`, `Ns`), and that statement's line (`Ks` or
/// else `Kd` for an error about both).
fn in_mtl_terms(e: MaterialError, m: &MtlMaterial) -> (MaterialError, Option<u32>) {
    let statement = |name: &'static str| match name {
        "reflectance" | "kd" => "Kd",
        "ks" => "Ks",
        "exponent" => "Ns",
        other => other,
    };
    let e = match e {
        MaterialError::NotFinite(n) => MaterialError::NotFinite(statement(n)),
        MaterialError::Negative(n) => MaterialError::Negative(statement(n)),
        MaterialError::NotPositive(n) => MaterialError::NotPositive(statement(n)),
        MaterialError::AboveOne(n) => MaterialError::AboveOne(statement(n)),
        MaterialError::TooLarge { name, value, max } => {
            MaterialError::TooLarge { name: statement(name), value, max }
        }
        other => other,
    };
    let at = |v: Option<AtLine<Rgb>>| v.map(|v| v.line);
    let line = match &e {
        MaterialError::NotFinite("Kd") | MaterialError::Negative("Kd") => at(m.kd),
        MaterialError::NotFinite("Ks") | MaterialError::Negative("Ks") => at(m.ks),
        MaterialError::TooLarge { name: "Ns", .. }
        | MaterialError::Negative("Ns")
        | MaterialError::NotFinite("Ns") => m.ns.map(|v| v.line),
        _ => at(m.ks.or(m.kd)),
    };
    (e, line)
}
