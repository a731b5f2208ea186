//! A CIE general sky ([`super::cie`]) placed and scaled by gensky's own arguments, for Mitsuba
//! XML's `<emitter type="ciesky">` (`mitsuba/sky.rs`): the sun's position as gensky reads it
//! (`month day hour` with `-a`, `-o`, `-m`, `-y`, or `-ang altitude azimuth`, through `sun.rs`),
//! the level as gensky states it (`-b` zenith radiance or `-B` horizontal diffuse irradiance:
//! the general sky is a relative distribution, so one is required), and a sun only when its
//! level is given (`-r` radiance or `-R` horizontal direct irradiance, gensky's 0.5° disc).
//! Why gensky's arguments rather than new ones: a scene writer who knows `gensky` knows these,
//! and the sun's position is then computed by the same code as a `!gensky` line's.
//!
//! gensky's sky options (`+s`/`-s`, `+i`/`-i`, `-c`, `-u`, `-t`) choose or tune gensky's own
//! skies; here the type does, so they are errors. Below the horizon is a uniform ground of
//! ρ·E_g/π (`-g` ρ, 0.2 by default, E_g the sky's and the sun's horizontal irradiance), as
//! gensky's ground, without skybright.cal's blend at the horizon.

use super::cie::{CieGeneralSky, SkyModel};
use super::gensky::{SUN_DIAMETER_DEGREES, SUN_SOLID_ANGLE};
use super::sun::{DEG, Site, number, option_word, parse_when, sun_direction};
use super::{Generated, SkyArgsError, SkyFunc, Sun};
use glam::DVec3;
use std::f64::consts::PI;

/// The arguments' usage line.
const USAGE: &str = "month day hour [options] | -ang altitude azimuth [options], with -b zenith radiance or -B horizontal diffuse irradiance";

/// A CIE general sky with its level, sun direction and ground.
#[derive(Clone, Debug, PartialEq)]
pub struct CieSky {
    /// The type.
    pub model: CieGeneralSky,
    /// Zenith radiance, W/(sr·m²).
    pub zenith: f64,
    /// Ground radiance, W/(sr·m²).
    pub ground: f64,
    /// Toward the sun (unit; z up, y north, x east).
    pub sun_dir: DVec3,
}

impl CieSky {
    /// The radiance toward `d` (unit, world: z up), W/(sr·m²): the zenith's × the type's
    /// relative luminance above the horizon, the ground below.
    pub fn brightness(&self, d: DVec3) -> f64 {
        if d.z > 0.0 {
            self.zenith * SkyModel::CieGeneral(self.model).relative_luminance(d, self.sun_dir)
        } else {
            self.ground
        }
    }
}

/// Reads the arguments (see the module docs) into sky type `model`'s sky and its sun.
pub fn ciesky(model: CieGeneralSky, args: &[String]) -> Result<Generated, SkyArgsError> {
    if args.len() < 3 {
        return Err(SkyArgsError::Usage { usage: USAGE });
    }
    let mut site = Site::DEFAULT;
    let when = parse_when(args, true)?;
    let (mut zenith, mut horizontal, mut radiance, mut direct) = (None, None, None, None);
    let (mut rho, mut year) = (0.2, None);
    let mut i = 3;
    while i < args.len() {
        let a = args[i].as_str();
        let (_, letter) = option_word(a)?;
        match letter {
            's' | 'i' | 'c' | 'u' | 't' => {
                return Err(SkyArgsError::SkyTypeOption { option: a.to_string() });
            }
            'y' | 'r' | 'R' | 'b' | 'B' | 'g' | 'a' | 'o' | 'm' => {
                i += 1;
                let v = number(args, i, a)?;
                match letter {
                    'y' => year = Some(v as i32),
                    'r' => (radiance, direct) = (Some(v), None),
                    'R' => (radiance, direct) = (None, Some(v)),
                    'b' => (zenith, horizontal) = (Some(v), None),
                    'B' => (zenith, horizontal) = (None, Some(v)),
                    'g' => rho = v,
                    'a' => site.latitude = v * DEG,
                    'o' => site.longitude = v * DEG,
                    _ => site.meridian = v * DEG,
                }
            }
            _ => return Err(SkyArgsError::UnknownOption { option: a.to_string() }),
        }
        i += 1;
    }
    if let super::sun::When::Date { zone: Some(m), .. } = when {
        site.meridian = m * DEG; // a time zone overrides -m, as in gensky
    }
    if !(0.0..=1.0).contains(&rho) {
        return Err(SkyArgsError::GroundReflectance { value: rho });
    }
    if [zenith, horizontal, radiance, direct].iter().flatten().any(|&v| v < 0.0) {
        return Err(SkyArgsError::NegativeLevel);
    }
    let (altitude, azimuth, _) = site.position(when, year);
    let sun_dir = sun_direction(altitude, azimuth);
    let relative = SkyModel::CieGeneral(model);
    let zenith = match (zenith, horizontal) {
        (Some(z), _) => z,
        (None, Some(e)) => relative.zenith_for(e, sun_dir),
        (None, None) => return Err(SkyArgsError::MissingZenithLevel),
    };
    let solar = match (radiance, direct) {
        _ if sun_dir.z <= 0.0 => 0.0,
        (Some(r), _) => r,
        (None, Some(e)) => e / (SUN_SOLID_ANGLE * sun_dir.z),
        (None, None) => 0.0,
    };
    let global = zenith * relative.horizontal_integral(sun_dir, 256) + solar * SUN_SOLID_ANGLE * sun_dir.z;
    let sun = (solar > 0.0).then_some(Sun {
        radiance: solar,
        toward: sun_dir,
        diameter_degrees: SUN_DIAMETER_DEGREES,
    });
    let func = CieSky { model, zenith, ground: rho * global / PI, sun_dir };
    Ok(Generated { func: SkyFunc::Cie(func), sun, warnings: Vec::new() })
}
