//! Radiance's sky generators interpreted, never run: `!gensky` (the CIE clear, intermediate,
//! overcast and uniform skies of `skybright.cal`) and `!gendaylit` (the Perez all-weather sky of
//! `perezlum.cal`), each a `skyfunc` brightness and a `solar` source; and, for front ends
//! other than Radiance's, the CIE general skies ([`cie`]), which Mitsuba XML's `ciesky` emitter
//! places and scales with gensky's arguments ([`ciesky()`]).
//!
//! Written from the formulas of Radiance's own sources (LBNL-ETA/Radiance, as Radiance 6 and
//! pyradiance 1.3.1 ship them), not from their code:
//!
//! | file | source |
//! |---|---|
//! | `sun.rs` | `src/gen/sun.c` 2.7: the site, the date and hour or `-ang`, the sun's position |
//! | `gensky.rs` | `src/gen/gensky.c` 2.31, `src/gen/skybright.cal` 2.7 |
//! | `perez.rs` | `src/gen/gendaylit.c` 2.6 (2021-01-29, with the dew point; RCS 2.21), `lib/perezlum.cal` 1.2 |
//! | `cie.rs` | ISO 15469:2004 / CIE S 011/E:2003, the 15 general skies |
//! | `ciesky.rs` | a general sky under gensky's arguments (`sun.rs`'s sun, `-b`/`-B`, `-r`/`-R`) |
//!
//! * **Sun position** (`sun.c`). Day of the year J (no leap years), solar declination
//!   δ = 0.4093·sin(2π(J − 81)/365), solar time t = hour + 0.170·sin(4π(J − 80)/373)
//!   − 0.129·sin(2π(J − 8)/355) + 12(meridian − longitude)/π (longitudes and meridians in radians
//!   **west** of Greenwich, Radiance's sign), altitude a = asin(sin φ sin δ − cos φ cos δ cos(πt/12))
//!   and azimuth A = −atan2(cos δ sin(πt/12), −cos φ sin δ − sin φ cos δ cos(πt/12)) (from south,
//!   positive toward west). With `-y year`, the Michalsky (1988) almanac algorithm instead, as
//!   both programs. The sun's direction is (−sin A cos a, −cos A cos a, sin a): x east, y north,
//!   z up.
//! * **gensky's levels** (`gensky.c`). Zenith luminance (kcd/m²) (1.376T − 1.81)·tan a + 0.38 for
//!   clear skies, 8.6 sin a + 0.123 for overcast and uniform, their mean for intermediate, as
//!   radiance ×1000/203 (Radiance's sky efficacy, D65's); or from `-b` (radiance) or `-B`
//!   (horizontal diffuse irradiance E, zenith = E/(π·n)) with n the sky's normalisation (1
//!   uniform, 7/9 overcast, the polynomial `normsc`/F2/π for clear and intermediate). Solar
//!   radiance 1.5·10⁹/208·(1.147 − 0.147/max(sin a, 0.16)) (×0.15 for intermediate), or `-r`
//!   radiance, or `-R` horizontal direct irradiance ÷ (5.98·10⁻⁵·sin a). Ground brightness
//!   ρ_g·(zenith·n + 6·10⁻⁵/π·solar·sin a).
//! * **gensky's sky** (`skybright.cal`): the CIE clear, overcast ((1 + 2 cos θ)/3), uniform and
//!   intermediate distributions, blended toward the ground brightness by the weights
//!   (D_z + 1.01)^±10 near and below the horizon.
//! * **gendaylit's levels** (`gendaylit.c`). From direct normal and diffuse horizontal
//!   irradiance (`-W`; `-G` gives the direct on the horizontal, ÷ sin a; `-E` the global,
//!   split by Erbs's correlation), the sky's brightness Δ = E_d·m/(1367·E₀) (air mass
//!   m = 1/(cos Z + 0.15·(93.885 − Z°)^−1.253), eccentricity E₀ of the day, day 0 with `-ang`)
//!   and clearness ε = ((E_d + E_n)/E_d + 1.041 Z³)/(1 + 1.041 Z³), clamped to [1, 12.01) and
//!   [0.01, 0.6]; `-P ε Δ` gives them directly, `-L` illuminances are turned into irradiances by
//!   nine rounds of the efficacy models. The luminous efficacies of Perez 1990 (precipitable
//!   water W = exp(0.07 T_d − 0.075), T_d the dew point `-d`, default 2 cm) give the
//!   illuminances. The Perez 1993 coefficients a–e (Δ raised to 0.2 for 1.065 < ε < 2.8) give
//!   the relative luminance (1 + a e^{b/cos ζ})(1 + c e^{dγ} + e cos²γ); gendaylit scales it so
//!   that its sum over 145 directions (2π/145 each, rings 12° apart) times cos θ is the diffuse
//!   horizontal level: illuminance/179 (`-O 0`, Radiance's visible watts), irradiance (`-O 1`)
//!   or illuminance (`-O 2`). The sun: a 0.533° disc of radiance direct/Ω (Ω its solid angle),
//!   so that its normal irradiance is the direct level in the same unit. Ground brightness
//!   ρ_g·(zenith·n + 6.8·10⁻⁵/π·solar·sin a), n gensky's normalisation of the CIE sky nearest
//!   ε (overcast at ε = 1, intermediate below 6, clear above). Days with the sun below the
//!   horizon, a positive b, and out-of-range levels give gendaylit's "error sky": black, no sun.
//! * **gendaylit's sky** (`perezlum.cal`): A1·(1 + a e^{b/max(D_z, 0.01)})(1 + c e^{dγ} + e cos²γ),
//!   blended toward the ground as gensky's.

mod ciesky;
mod gensky;
mod perez;
mod sun;

pub mod cie;

pub use ciesky::{CieSky, ciesky};
pub use gensky::{Gensky, SUN_DIAMETER_DEGREES, SUN_SOLID_ANGLE, gensky};
pub use perez::{Gendaylit, SUN_DIAMETER_DEGREES as GENDAYLIT_SUN_DIAMETER_DEGREES, gendaylit};

use glam::DVec3;
use std::f64::consts::PI;

const DEG: f64 = PI / 180.0;

/// gensky's usage line.
const GENSKY_USAGE: &str = "gensky month day hour [options] | -ang altitude azimuth [options]";
/// gendaylit's usage line.
const GENDAYLIT_USAGE: &str = "gendaylit month day hour [-y year] | -ang altitude azimuth, then -P epsilon delta, -W|-L|-G direct diffuse or -E global [options]";

/// Why [`gensky`] or [`gendaylit`] refuses its arguments: the programs' own complaints, and
/// what this reading of them does not support.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SkyArgsError {
    /// Fewer than three arguments: the program's usage line.
    #[error("usage: {usage}")]
    Usage {
        /// The usage line.
        usage: &'static str,
    },
    /// An option's value is missing.
    #[error("{option} needs a value")]
    MissingValue {
        /// The option.
        option: String,
    },
    /// An option's value is not a finite number.
    #[error("{option}: \"{word}\" is not a number")]
    NotANumber {
        /// The option.
        option: String,
        /// The word found.
        word: String,
    },
    /// The month is not an integer in 1–12.
    #[error("bad month")]
    BadMonth {
        /// The word found.
        word: String,
    },
    /// The day is not an integer in 1–31.
    #[error("bad day")]
    BadDay {
        /// The word found.
        word: String,
    },
    /// gendaylit's hour is not a number in [0, 24).
    #[error("bad hour: {word} (a number in [0, 24), + first for solar time)")]
    BadHour {
        /// The word found.
        word: String,
    },
    /// gensky's hour is not `h`, `h.frac` or `h:mm` (with an optional `+` or time zone).
    #[error("bad time format: {word}")]
    BadTime {
        /// The word found.
        word: String,
    },
    /// gensky's hour is solar time (`+` first) and names a time zone.
    #[error("bad time format: {word} (solar time takes no time zone)")]
    SolarTimeWithZone {
        /// The word found.
        word: String,
    },
    /// gensky's hour names a time zone gensky does not know.
    #[error("unknown time zone: {zone} (known: {})", sun::zone_names())]
    UnknownZone {
        /// The zone as written.
        zone: String,
    },
    /// An argument after the first three is not an option (a sign and one letter).
    #[error("bad option: {option}")]
    BadOption {
        /// The argument.
        option: String,
    },
    /// An option the program does not have.
    #[error("unknown option: {option}")]
    UnknownOption {
        /// The option.
        option: String,
    },
    /// `-g` outside [0, 1].
    #[error("-g {value}: a ground reflectance is in [0, 1]")]
    GroundReflectance {
        /// The value given.
        value: f64,
    },
    /// gensky's `-b`/`-B` or `-r`/`-R` is negative.
    #[error("-b/-B and -r/-R take values ≥ 0")]
    NegativeLevel,
    /// gendaylit's `-O` is not 0, 1 or 2.
    #[error("-O {value}: the output is 0 (visible watts), 1 (solar watts) or 2 (lumens)")]
    OutputUnit {
        /// The value given.
        value: f64,
    },
    /// gendaylit's `-C` or `-l` (the coloured sky of `perezlum_c.cal`), not supported.
    #[error("{option}: gendaylit's coloured sky (perezlum_c.cal) is not supported")]
    ColouredSky {
        /// The option.
        option: String,
    },
    /// gendaylit's `-i` (a time interval), not supported.
    #[error("{option}: gendaylit's time interval is not supported")]
    TimeInterval {
        /// The option.
        option: String,
    },
    /// One of gensky's sky options where the CIE type chooses the sky (`ciesky`).
    #[error(
        "{option}: gensky's sky options (+s/-s, +i/-i, -c, -u, -t) do not apply: the CIE type chooses the sky (give -r or -R for a sun)"
    )]
    SkyTypeOption {
        /// The option.
        option: String,
    },
    /// A CIE general sky without `-b` or `-B`.
    #[error(
        "the sky's level is missing: give -b zenith radiance (W/(sr·m²)) or -B horizontal diffuse irradiance (W/m²)"
    )]
    MissingZenithLevel,
    /// gendaylit without `-W`, `-L`, `-G`, `-P` or `-E`.
    #[error(
        "the sky's levels are missing: give -W direct diffuse (W/m²), -L (lux), -G, -P epsilon delta or -E global"
    )]
    MissingLevels,
}

/// A `skyfunc` as a generator defines it: its brightness toward a direction.
#[derive(Clone, Debug, PartialEq)]
pub enum SkyFunc {
    /// `!gensky`'s (skybright.cal).
    Gensky(Gensky),
    /// `!gendaylit`'s (perezlum.cal).
    Gendaylit(Gendaylit),
    /// A CIE general sky (Mitsuba XML's `ciesky`; no Radiance line makes one).
    Cie(CieSky),
}

impl SkyFunc {
    /// The brightness toward `d` (unit, world: z up), W/(sr·m²).
    pub fn brightness(&self, d: DVec3) -> f64 {
        match self {
            SkyFunc::Gensky(g) => g.brightness(d),
            SkyFunc::Gendaylit(g) => g.brightness(d),
            SkyFunc::Cie(c) => c.brightness(d),
        }
    }

    /// The sky's model, which the daylight factor asks for (`opticks_io::measurement`).
    pub fn model(&self) -> opticks_core::scene::SkyModel {
        use opticks_core::scene::SkyModel;
        let other = |s: &str| SkyModel::Other(s.into());
        match self {
            SkyFunc::Gensky(g) => match g.sky {
                gensky::SkyType::Overcast => SkyModel::CieOvercast,
                gensky::SkyType::Clear => other("a CIE clear sky (gensky +s or -s)"),
                gensky::SkyType::Uniform => other("a uniform sky (gensky -u)"),
                gensky::SkyType::Intermediate => other("a CIE intermediate sky (gensky +i or -i)"),
            },
            SkyFunc::Gendaylit(_) => other("a Perez all-weather sky (gendaylit)"),
            SkyFunc::Cie(c) => {
                SkyModel::Other(format!("a CIE general sky of type {} (ciesky)", c.model.number()))
            }
        }
    }
}

/// The size of the equirectangular map a sky is rasterised into: 0.7° texels, whose bilinear
/// interpolant's horizontal irradiance is within 10⁻³ of the analytic sky's (measured,
/// `tests::rasterisation_error_of_the_horizontal_irradiance`); about 4.7 MB a light.
pub const SKY_MAP_WIDTH: usize = 512;
/// Rows of the sky map (odd: the horizon is a row).
pub const SKY_MAP_HEIGHT: usize = 257;

/// Radiance's two sky generators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Generator {
    /// `gensky`: the CIE clear, intermediate, overcast and uniform skies.
    Gensky,
    /// `gendaylit`: the Perez all-weather sky.
    Gendaylit,
}

impl Generator {
    /// The generator of this program name, if it is one.
    pub fn named(program: &str) -> Option<Generator> {
        match program {
            "gensky" => Some(Generator::Gensky),
            "gendaylit" => Some(Generator::Gendaylit),
            _ => None,
        }
    }

    /// Its program name.
    pub fn name(self) -> &'static str {
        match self {
            Generator::Gensky => "gensky",
            Generator::Gendaylit => "gendaylit",
        }
    }
}

/// A sun as a generator writes it: Radiance's `solar` light on a `source` disc.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sun {
    /// Radiance of the disc, W/(sr·m²) (0: the generator wrote a black sun).
    pub radiance: f64,
    /// Toward the sun (unit; z up, y north, x east).
    pub toward: DVec3,
    /// The disc's angular diameter, degrees.
    pub diameter_degrees: f64,
}

/// One generator line interpreted: the sky's brightness, its sun, and what the generator would
/// print.
#[derive(Clone, Debug, PartialEq)]
pub struct Generated {
    /// The `skyfunc` brightness.
    pub func: SkyFunc,
    /// The sun, when the generator writes one.
    pub sun: Option<Sun>,
    /// The generator's warnings.
    pub warnings: Vec<String>,
}

/// Interprets `generator` run with `args` (never runs it): what both the `.rad` reader's
/// `!gensky`/`!gendaylit` lines and the Mitsuba XML extension emitters describe.
pub fn generate(generator: Generator, args: &[String]) -> Result<Generated, SkyArgsError> {
    Ok(match generator {
        Generator::Gensky => {
            let g = gensky(args)?;
            let sun = g.solar.map(|radiance| Sun {
                radiance,
                toward: g.sun_dir,
                diameter_degrees: SUN_DIAMETER_DEGREES,
            });
            Generated { warnings: g.warnings.clone(), sun, func: SkyFunc::Gensky(g) }
        }
        Generator::Gendaylit => {
            let g = gendaylit(args)?;
            let sun = (g.solar).map(|radiance| Sun {
                radiance,
                toward: g.sun_dir,
                diameter_degrees: GENDAYLIT_SUN_DIAMETER_DEGREES,
            });
            Generated { warnings: g.warnings.clone(), sun, func: SkyFunc::Gendaylit(g) }
        }
    })
}

/// The solid angle of a sun disc of full angle `diameter_degrees` as Radiance counts it:
/// gensky's 0.5° sun as its `-R` conversion does ([`SUN_SOLID_ANGLE`]), any other disc exactly.
pub fn disc_solid_angle(diameter_degrees: f64) -> f64 {
    if diameter_degrees == SUN_DIAMETER_DEGREES {
        SUN_SOLID_ANGLE
    } else {
        cone_solid_angle(diameter_degrees)
    }
}

/// The solid angle of a cone of full angle `angle_degrees` (a `source`'s fourth real), sr.
pub fn cone_solid_angle(angle_degrees: f64) -> f64 {
    2.0 * PI * (1.0 - (0.5 * angle_degrees.min(360.0) * DEG).cos())
}

/// An equirectangular map (Mitsuba's convention, `opticks_core::light::environment`, map +y
/// being world +z) of `radiance(d)` for the directions d within `half_angle` of `axis`, zero
/// elsewhere: `width` × `height` texels, the rows at polar angles πj/(height − 1). A texel on
/// the cone's edge (within 10⁻⁹ of it) takes half its radiance, so that two cones meeting there
/// — a sky dome and its ground dome, both 180° — sum to the radiance once: counted in both,
/// the horizon row was twice as bright, about 0.6 % too much light on a vertical window under
/// an overcast sky.
pub fn rasterise(
    width: usize,
    height: usize,
    axis: DVec3,
    half_angle: f64,
    radiance: impl Fn(DVec3) -> f64,
) -> Vec<f64> {
    let whole = half_angle >= PI;
    let cos_limit = half_angle.min(PI).cos();
    let mut texels = Vec::with_capacity(width * height);
    // φ's sine and cosine once per column, θ's per row ([`map_to_world`]'s values): per texel,
    // two sincos of the 131 k texels were a sixth of a sky scene's load.
    let columns: Vec<(f64, f64)> =
        (0..width).map(|i| (2.0 * PI * (i as f64 + 0.5) / width as f64).sin_cos()).collect();
    for j in 0..height {
        let row = (PI * j as f64 / (height - 1) as f64).sin_cos();
        for &column in &columns {
            let d = direction_of(column, row);
            let c = d.dot(axis) - cos_limit;
            texels.push(match () {
                _ if whole || c > 1e-9 => radiance(d),
                _ if c >= -1e-9 => 0.5 * radiance(d),
                _ => 0.0,
            });
        }
    }
    texels
}

/// A sky, or one of its domes, as an environment light's radiance: `rgb` × `radiance(d)` within
/// `half_angle` of `axis` ([`rasterise`]), in a [`SKY_MAP_WIDTH`] × [`SKY_MAP_HEIGHT`] map whose
/// frame is [`MAP_TO_WORLD`].
pub fn sky_map(
    axis: DVec3,
    half_angle: f64,
    rgb: opticks_core::math::Rgb,
    radiance: impl Fn(DVec3) -> f64,
) -> opticks_core::scene::EnvironmentRadiance {
    let texels = rasterise(SKY_MAP_WIDTH, SKY_MAP_HEIGHT, axis, half_angle, radiance);
    opticks_core::scene::EnvironmentRadiance::Map {
        width: SKY_MAP_WIDTH,
        height: SKY_MAP_HEIGHT,
        texels: texels.into_iter().map(|v| rgb * v as f32).collect(),
        scale: 1.0,
        file: None,
    }
}

/// The world direction (z up) of the map's (φ, θ): the map's d = (sin φ sin θ, cos θ,
/// −cos φ sin θ) under [`MAP_TO_WORLD`].
pub fn map_to_world(phi: f64, theta: f64) -> DVec3 {
    direction_of(phi.sin_cos(), theta.sin_cos())
}

/// [`map_to_world`] from (sin φ, cos φ) and (sin θ, cos θ): the rasteriser computes them once
/// per column and per row, not per texel.
#[inline]
fn direction_of((sin_p, cos_p): (f64, f64), (sin_t, cos_t): (f64, f64)) -> DVec3 {
    DVec3::new(sin_p * sin_t, cos_p * sin_t, cos_t)
}

/// The rotation from the map's frame (+y up) to Radiance's world (+z up): x → x, y → z,
/// z → −y.
pub const MAP_TO_WORLD: glam::Mat3 = glam::Mat3::from_cols(
    glam::Vec3::new(1.0, 0.0, 0.0),
    glam::Vec3::new(0.0, 0.0, 1.0),
    glam::Vec3::new(0.0, -1.0, 0.0),
);

#[cfg(test)]
mod daylight_tests;
#[cfg(test)]
mod tests;
