//! gensky (`src/gen/gensky.c` 2.31): its options, levels and `skybright.cal`'s CIE skies.

use super::sun::{DEG, Site, When, number, option_word, parse_when, sun_direction};
use super::{GENSKY_USAGE, SkyArgsError};
use glam::DVec3;
use std::f64::consts::PI;

/// Solid angle gensky's 0.5° sun subtends, as its `-R` conversion uses it (sr).
pub const SUN_SOLID_ANGLE: f64 = 5.98e-5;
/// gensky's sun: a disc of this angular diameter (degrees), its `solar source sun … 0.5`.
pub const SUN_DIAMETER_DEGREES: f64 = 0.5;

/// gensky's sky types.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SkyType {
    /// CIE clear sky (`+s`, `-s`).
    Clear,
    /// CIE overcast (`-c`).
    Overcast,
    /// Uniform (`-u`).
    Uniform,
    /// CIE intermediate (`+i`, `-i`).
    Intermediate,
}

impl SkyType {
    fn overcast(self) -> bool {
        matches!(self, SkyType::Overcast | SkyType::Uniform)
    }
}

/// What one `!gensky` line describes.
#[derive(Clone, Debug, PartialEq)]
pub struct Gensky {
    /// The sky's type.
    pub sky: SkyType,
    /// Zenith radiance, W/(sr·m²) (skybright.cal's A2).
    pub zenith: f64,
    /// Ground brightness, W/(sr·m²) (A3).
    pub ground: f64,
    /// Normalisation of the clear and intermediate skies (A4; 0 for the others).
    pub f2: f64,
    /// Toward the sun (unit; z up, y north, x east).
    pub sun_dir: DVec3,
    /// Solar altitude and azimuth, degrees, before the 87° limit.
    pub altitude: f64,
    /// Azimuth, degrees from south, positive toward west.
    pub azimuth: f64,
    /// Local solar time, hours (none with `-ang`).
    pub solar_time: Option<f64>,
    /// The sun's radiance W/(sr·m²), if gensky writes a sun.
    pub solar: Option<f64>,
    /// Warnings gensky would print.
    pub warnings: Vec<String>,
}

/// Reads gensky's arguments (`args` without the program name) and computes the sky as gensky
/// does. Errors are gensky's (bad month, unknown option, …).
pub fn gensky(args: &[String]) -> Result<Gensky, SkyArgsError> {
    if args.len() < 3 {
        return Err(SkyArgsError::Usage { usage: GENSKY_USAGE });
    }
    let mut site = Site::DEFAULT;
    let when = parse_when(args, true)?;
    let zone_meridian = match when {
        When::Date { zone, .. } => zone,
        When::Angles(..) => None,
    };
    let (mut sky, mut dosun) = (SkyType::Clear, true);
    let (mut zenith, mut u_zenith, mut turbidity, mut rho) = (0.0, 0, 2.45, 0.2);
    let (mut solar, mut u_solar, mut year) = (0.0, 0, None);
    let mut i = 3;
    while i < args.len() {
        let a = args[i].as_str();
        let (sign, letter) = option_word(a)?;
        match letter {
            's' | 'i' => {
                sky = if letter == 's' { SkyType::Clear } else { SkyType::Intermediate };
                dosun = sign == '+';
            }
            'c' => sky = SkyType::Overcast,
            'u' => sky = SkyType::Uniform,
            'y' | 'r' | 'R' | 't' | 'b' | 'B' | 'g' | 'a' | 'o' | 'm' => {
                i += 1;
                let v = number(args, i, a)?;
                match letter {
                    'y' => year = Some(v as i32),
                    'r' | 'R' => (u_solar, solar) = (if letter == 'R' { -1 } else { 1 }, v),
                    't' => turbidity = v,
                    'b' | 'B' => (u_zenith, zenith) = (if letter == 'B' { -1 } else { 1 }, v),
                    'g' => rho = v,
                    'a' => site.latitude = v * DEG,
                    'o' => site.longitude = v * DEG,
                    _ => {
                        if zone_meridian.is_none() {
                            site.meridian = v * DEG // a time zone overrides -m
                        }
                    }
                }
            }
            _ => return Err(SkyArgsError::UnknownOption { option: a.to_string() }),
        }
        i += 1;
    }
    if let Some(m) = zone_meridian {
        site.meridian = m * DEG;
    }
    if !(0.0..=1.0).contains(&rho) {
        return Err(SkyArgsError::GroundReflectance { value: rho });
    }
    if zenith < 0.0 || solar < 0.0 {
        return Err(SkyArgsError::NegativeLevel);
    }
    let mut warnings = Vec::new();
    if let When::Date { solar, .. } = when {
        if let Some(y) = year
            && !(1950..=2050).contains(&y)
        {
            warnings.push("year should be in range 1950-2050".into());
        }
        if !solar && (site.meridian - site.longitude).abs() > 45.0 * DEG {
            warnings.push(format!(
                "{:.1} hours btwn. standard meridian and longitude",
                (site.longitude - site.meridian) * 12.0 / PI
            ));
        }
    }
    let (mut altitude, azimuth, solar_time) = site.position(when, year);
    let (reported_alt, reported_azi) = (altitude / DEG, azimuth / DEG);
    if !sky.overcast() && altitude > 87.0 * DEG {
        warnings.push("sun too close to zenith, reducing altitude to 87 degrees".into());
        altitude = 87.0 * DEG;
    }
    let sun_dir = sun_direction(altitude, azimuth);
    let normsc = || {
        let c: [f64; 5] = if sky == SkyType::Intermediate {
            [3.5556, -2.7152, -1.3081, 1.0660, 0.60227]
        } else {
            [2.766521, 0.547665, -0.369832, 0.009237, 0.059229]
        };
        let x = (altitude - PI / 4.0) / (PI / 4.0);
        c.iter().rev().fold(0.0, |acc, k| acc * x + k)
    };
    let mut f2 = 0.0;
    let norm = match sky {
        SkyType::Uniform => 1.0,
        SkyType::Overcast => 0.777778,
        SkyType::Clear => {
            f2 = 0.274 * (0.91 + 10.0 * (-3.0 * (PI / 2.0 - altitude)).exp() + 0.45 * sun_dir.z * sun_dir.z);
            normsc() / f2 / PI
        }
        SkyType::Intermediate => {
            f2 = (2.739 + 0.9891 * (0.3119 + 2.6 * altitude).sin())
                * (-(PI / 2.0 - altitude) * (0.4441 + 1.48 * altitude)).exp();
            normsc() / f2 / PI
        }
    };
    if u_zenith == -1 {
        zenith /= norm * PI;
    } else if u_zenith == 0 {
        zenith = if sky.overcast() {
            8.6 * sun_dir.z + 0.123
        } else {
            (1.376 * turbidity - 1.81) * altitude.tan() + 0.38
        };
        if sky == SkyType::Intermediate {
            zenith = (zenith + 8.6 * sun_dir.z + 0.123) / 2.0;
        }
        zenith = if zenith < 0.0 { 0.0 } else { zenith * 1000.0 / 203.0 };
    }
    let mut ground = zenith * norm;
    let mut sun = None;
    if !sky.overcast() && sun_dir.z > 0.0 && (u_solar == 0 || solar > 0.0) {
        if u_solar == -1 {
            solar /= SUN_SOLID_ANGLE * sun_dir.z;
        } else if u_solar == 0 {
            solar = 1.5e9 / 208.0 * (1.147 - 0.147 / sun_dir.z.max(0.16));
            if sky == SkyType::Intermediate {
                solar *= 0.15;
            }
        }
        ground += 6e-5 / PI * solar * sun_dir.z;
        if dosun {
            sun = Some(solar);
        }
    }
    ground *= rho;
    Ok(Gensky {
        sky,
        zenith,
        ground,
        f2,
        sun_dir,
        altitude: reported_alt,
        azimuth: reported_azi,
        solar_time,
        solar: sun,
        warnings,
    })
}

impl Gensky {
    /// skybright.cal's `skybr` toward `d` (unit, world: z up), W/(sr·m²).
    pub fn brightness(&self, d: DVec3) -> f64 {
        let (a2, a4, s) = (self.zenith, self.f2, self.sun_dir);
        // The angles only where the sky type uses them: the three `acos` of every texel were a
        // fifth of a small overcast case's `trace` (callgrind), for skies that use none.
        let cos_gamma = d.dot(s).clamp(-1.0, 1.0);
        let sky = match self.sky {
            SkyType::Clear => {
                let gamma = cos_gamma.acos();
                let horizon = if d.z - 0.01 > 0.0 { 1.0 - (-0.32 / d.z).exp() } else { 1.0 };
                a2 * (0.91 + 10.0 * (-3.0 * gamma).exp() + 0.45 * cos_gamma * cos_gamma) * horizon / a4
            }
            SkyType::Overcast => a2 * (1.0 + 2.0 * d.z) / 3.0,
            SkyType::Uniform => a2,
            SkyType::Intermediate => {
                let (gamma, zt, eta) =
                    (cos_gamma.acos(), s.z.clamp(-1.0, 1.0).acos(), d.z.clamp(-1.0, 1.0).acos());
                a2 * (((1.35 * (5.631 - 3.59 * eta).sin() + 3.12) * (4.396 - 2.6 * zt).sin()) + 6.37 - eta)
                    / 2.326
                    * (gamma * -0.563 * ((2.629 - eta) * (1.562 - zt) + 0.812)).exp()
                    / a4
            }
        };
        let (w_sky, w_ground) = ((d.z + 1.01).powi(10), (d.z + 1.01).powi(-10));
        (w_sky * sky + w_ground * self.ground) / (w_sky + w_ground)
    }

    /// gensky's horizontal diffuse irradiance (W/m²): π × its zenith radiance × the sky's
    /// normalisation, the closed form `-B` inverts.
    #[cfg(test)]
    pub fn horizontal_irradiance(&self) -> f64 {
        let norm = match self.sky {
            SkyType::Uniform => 1.0,
            SkyType::Overcast => 0.777778,
            SkyType::Clear | SkyType::Intermediate => {
                let alt = self.sun_dir.z.clamp(-1.0, 1.0).asin();
                let c: [f64; 5] = if self.sky == SkyType::Intermediate {
                    [3.5556, -2.7152, -1.3081, 1.0660, 0.60227]
                } else {
                    [2.766521, 0.547665, -0.369832, 0.009237, 0.059229]
                };
                let x = (alt - PI / 4.0) / (PI / 4.0);
                c.iter().rev().fold(0.0, |acc, k| acc * x + k) / self.f2 / PI
            }
        };
        PI * self.zenith * norm
    }
}
