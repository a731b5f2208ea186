//! gendaylit (`src/gen/gendaylit.c`, version 2.6 of 2021-01-29 with the dew point, as Radiance 6
//! ships it) and `perezlum.cal` 1.2: the Perez all-weather sky from measured levels.
//!
//! The model is Perez, Seals & Michalsky, "All-weather model for sky luminance distribution",
//! Solar Energy 50(3) 1993, Table 1 (the coefficient table below), with the luminous efficacies
//! of Perez, Ineichen, Seals, Michalsky & Stewart, Solar Energy 44(5) 1990, Table 4.

use super::sun::{DEG, Site, When, day_of_year, declination, number, option_word, parse_when, sun_direction};
use super::{GENDAYLIT_USAGE, SkyArgsError};
use glam::DVec3;
use std::f64::consts::PI;

/// gendaylit's sun: a disc of this angular diameter (degrees), its `solar source sun … 0.533`.
pub const SUN_DIAMETER_DEGREES: f64 = 0.533;
/// Radiance's luminous efficacy of its "visible watt" (lm/W, `color.h`'s WHTEFFICACY).
pub const WHITE_EFFICACY: f64 = 179.0;
const SOLAR_CONSTANT_E: f64 = 1367.0;
const SOLAR_CONSTANT_L: f64 = 127_500.0;
/// ε's range (gendaylit clamps into it) and Δ's.
const CLEARNESS: (f64, f64) = (1.0, 12.01);
const BRIGHTNESS: (f64, f64) = (0.01, 0.6);
/// The clearness bins' lower bounds (the last bin ends at 12.01).
const BINS: [f64; 8] = [1.0, 1.065, 1.230, 1.500, 1.950, 2.800, 4.500, 6.200];

/// Perez 1993, Table 1: per ε bin, for a, b, c, d, e in turn, (x1, x2, x3, x4) of
/// x1 + x2·Z + Δ(x3 + x4·Z) (bin 1's c and d have their own forms).
#[rustfmt::skip]
const COEFFICIENTS: [[f64; 20]; 8] = [
    [1.3525, -0.2576, -0.2690, -1.4366, -0.7670, 0.0007, 1.2734, -0.1233, 2.8000, 0.6004, 1.2375, 1.0000, 1.8734, 0.6297, 0.9738, 0.2809, 0.0356, -0.1246, -0.5718, 0.9938],
    [-1.2219, -0.7730, 1.4148, 1.1016, -0.2054, 0.0367, -3.9128, 0.9156, 6.9750, 0.1774, 6.4477, -0.1239, -1.5798, -0.5081, -1.7812, 0.1080, 0.2624, 0.0672, -0.2190, -0.4285],
    [-1.1000, -0.2515, 0.8952, 0.0156, 0.2782, -0.1812, -4.5000, 1.1766, 24.7219, -13.0812, -37.7000, 34.8438, -5.0000, 1.5218, 3.9229, -2.6204, -0.0156, 0.1597, 0.4199, -0.5562],
    [-0.5484, -0.6654, -0.2672, 0.7117, 0.7234, -0.6219, -5.6812, 2.6297, 33.3389, -18.3000, -62.2500, 52.0781, -3.5000, 0.0016, 1.1477, 0.1062, 0.4659, -0.3296, -0.0876, -0.0329],
    [-0.6000, -0.3566, -2.5000, 2.3250, 0.2937, 0.0496, -5.6812, 1.8415, 21.0000, -4.7656, -21.5906, 7.2492, -3.5000, -0.1554, 1.4062, 0.3988, 0.0032, 0.0766, -0.0656, -0.1294],
    [-1.0156, -0.3670, 1.0078, 1.4051, 0.2875, -0.5328, -3.8500, 3.3750, 14.0000, -0.9999, -7.1406, 7.5469, -3.4000, -0.1078, -1.0750, 1.5702, -0.0672, 0.4016, 0.3017, -0.4844],
    [-1.0000, 0.0211, 0.5025, -0.5119, -0.3000, 0.1922, 0.7023, -1.6317, 19.0000, -5.0000, 1.2438, -1.9094, -4.0000, 0.0250, 0.3844, 0.2656, 1.0468, -0.3788, -2.4517, 1.4656],
    [-1.0500, 0.0289, 0.4260, 0.3590, -0.3250, 0.1156, 0.7781, 0.0025, 31.0625, -14.5000, -46.1148, 55.3750, -7.2312, 0.4050, 13.3500, 0.6234, 1.5000, -0.6426, 1.8564, 0.5636],
];

/// Perez 1990, Table 4: diffuse horizontal luminous efficacy a + b·W + c·cos Z + d·ln Δ (lm/W).
#[rustfmt::skip]
const DIFFUSE_EFFICACY: [[f64; 4]; 8] = [
    [97.24, -0.46, 12.00, -8.91], [107.22, 1.15, 0.59, -3.95], [104.97, 2.96, -5.53, -8.77],
    [102.39, 5.59, -13.95, -13.90], [100.71, 5.94, -22.75, -23.74], [106.42, 3.83, -36.15, -28.83],
    [141.88, 1.90, -53.24, -14.03], [152.23, 0.35, -45.27, -7.98],
];
/// Direct normal efficacy a + b·W + c·exp(5.73 Z − 5) + d·Δ (lm/W, at least 0).
#[rustfmt::skip]
const DIRECT_EFFICACY: [[f64; 4]; 8] = [
    [57.20, -4.55, -2.98, 117.12], [98.99, -3.46, -1.21, 12.38], [109.83, -4.90, -1.71, -8.81],
    [110.34, -5.84, -1.99, -4.56], [106.36, -3.97, -1.75, -6.16], [107.19, -1.25, -1.51, -26.73],
    [105.75, 0.77, -1.26, -34.44], [101.18, 1.58, -1.10, -8.29],
];

/// The 145 directions of gendaylit's normalisation (its `defangle`): rings at zenith angles
/// 84°, 72°, …, 12° of 30, 30, 24, 24, 18, 12, 6 points, and the zenith.
const RINGS: [(f64, usize); 8] =
    [(84.0, 30), (72.0, 30), (60.0, 24), (48.0, 24), (36.0, 18), (24.0, 12), (12.0, 6), (0.0, 1)];

/// The clearness bin of ε (gendaylit compares in single precision).
fn bin(epsilon: f64) -> usize {
    let e = epsilon as f32;
    BINS.iter().rposition(|&b| e >= b as f32).unwrap_or(0)
}

/// The Perez model's a–e for clearness ε, brightness Δ and solar zenith `z` (radians).
pub fn perez_parameters(epsilon: f64, delta: f64, z: f64) -> [f64; 5] {
    let delta = if epsilon > 1.065 && epsilon < 2.8 { delta.max(0.2) } else { delta };
    let k = bin(epsilon);
    let x = |i: usize, j: usize| COEFFICIENTS[k][4 * i + j];
    let lin = |i: usize| x(i, 0) + x(i, 1) * z + delta * (x(i, 2) + x(i, 3) * z);
    let mut c = [lin(0), lin(1), lin(2), lin(3), lin(4)];
    if k == 0 {
        c[2] = (delta * (x(2, 0) + x(2, 1) * z)).powf(x(2, 2)).exp() - x(2, 3);
        c[3] = -(delta * (x(3, 0) + x(3, 1) * z)).exp() + x(3, 2) + delta * x(3, 3);
    }
    c
}

/// The Perez relative luminance at zenith angle `zeta` and angle `gamma` from the sun.
pub fn perez_relative(c: &[f64; 5], zeta: f64, gamma: f64) -> f64 {
    (1.0 + c[0] * (c[1] / zeta.cos()).exp())
        * (1.0 + c[2] * (c[3] * gamma).exp() + c[4] * gamma.cos().powi(2))
}

/// gendaylit's normalisation: ∫ relative luminance · cos θ dω over its 145 directions
/// (2π/145 each), for a sun at zenith angle `z`.
fn integral_145(c: &[f64; 5], z: f64) -> f64 {
    let mut sum = 0.0;
    for (theta, n) in RINGS {
        let theta = theta * DEG;
        for k in 0..n {
            let phi = (360.0 / n as f64 * k as f64) * DEG;
            let cos_g = z.cos() * theta.cos() + z.sin() * theta.sin() * phi.cos();
            let gamma = if cos_g > 1.0 { 0.0 } else { cos_g.acos() };
            sum += (perez_relative(c, theta, gamma) as f32) as f64 * theta.cos();
        }
    }
    sum * 2.0 * PI / 145.0
}

/// What one `!gendaylit` line describes.
#[derive(Clone, Debug, PartialEq)]
pub struct Gendaylit {
    /// perezlum.cal's A1: the diffuse normalisation (radiance per unit relative luminance).
    pub diffuse_norm: f64,
    /// A2: the ground brightness, W/(sr·m²).
    pub ground: f64,
    /// A3–A7: the Perez a–e.
    pub perez: [f64; 5],
    /// Toward the sun (unit; z up, y north, x east).
    pub sun_dir: DVec3,
    /// Solar altitude and azimuth (degrees, azimuth from south toward west), as printed.
    pub altitude: f64,
    /// Azimuth, degrees.
    pub azimuth: f64,
    /// Local solar time, hours (none with `-ang`).
    pub solar_time: Option<f64>,
    /// The sky's clearness ε and brightness Δ, and the precipitable water (cm).
    pub epsilon: f64,
    /// Δ.
    pub delta: f64,
    /// W.
    pub water: f64,
    /// The sun's radiance, if gendaylit writes a sun (0 under an overcast ε = 1).
    pub solar: Option<f64>,
    /// The diffuse horizontal and direct normal levels in the output's unit (W/m², visible
    /// watts for `-O 0`, lux for `-O 2`) that A1 and the sun were scaled to.
    pub diffuse_horizontal: f64,
    /// Direct normal, same unit.
    pub direct_normal: f64,
    /// gendaylit's warnings; an "error sky" (black, no sun) says so here.
    pub warnings: Vec<String>,
}

/// The Perez quantities gendaylit derives from its inputs.
struct Levels {
    epsilon: f64,
    delta: f64,
    /// Irradiances, W/m² (direct normal, diffuse horizontal).
    dir_irr: f64,
    diff_irr: f64,
    /// Illuminances, lux (when the output needs them).
    dir_ill: f64,
    diff_ill: f64,
}

/// Reads gendaylit's arguments (`args` without the program name) and computes the sky as
/// gendaylit does.
pub fn gendaylit(args: &[String]) -> Result<Gendaylit, SkyArgsError> {
    if args.len() < 3 {
        return Err(SkyArgsError::Usage { usage: GENDAYLIT_USAGE });
    }
    let mut site = Site::DEFAULT;
    let when = parse_when(args, false)?;
    let (mut cloudy, mut dosun, mut rho, mut year, mut output) = (false, true, 0.2, None, 0);
    let mut dew_point = 10.97353115;
    let mut input: Option<(char, f64, f64)> = None;
    let (mut warnings, mut quiet) = (Vec::new(), false);
    let mut i = 3;
    while i < args.len() {
        let a = args[i].as_str();
        let (sign, letter) = option_word(a)?;
        let mut value = |name: &str| {
            i += 1;
            number(args, i, name)
        };
        match letter {
            's' => (cloudy, dosun) = (false, sign == '+'),
            'c' => (cloudy, dosun) = (true, false),
            'w' => quiet = true,
            'P' | 'W' | 'L' | 'G' => input = Some((letter, value(a)?, value(a)?)),
            'E' => input = Some(('E', value(a)?, 0.0)),
            'd' => {
                dew_point = value(a)?;
                if !(-40.0..=40.0).contains(&dew_point) {
                    dew_point = 10.97353115;
                }
            }
            'y' => year = Some(value(a)? as i32),
            'g' => rho = value(a)?,
            'a' => site.latitude = value(a)? * DEG,
            'o' => site.longitude = value(a)? * DEG,
            'm' => site.meridian = value(a)? * DEG,
            'O' => {
                let o = value(a)?;
                output = match o {
                    0.0 => 0,
                    1.0 => 1,
                    2.0 => 2,
                    _ => return Err(SkyArgsError::OutputUnit { value: o }),
                };
            }
            'R' | 't' | 'b' => {
                value(a)?;
                warnings.push(format!("{a} is read and ignored by gendaylit"));
            }
            'C' | 'l' => {
                return Err(SkyArgsError::ColouredSky { option: a.to_string() });
            }
            'i' => return Err(SkyArgsError::TimeInterval { option: a.to_string() }),
            _ => return Err(SkyArgsError::UnknownOption { option: a.to_string() }),
        }
        i += 1;
    }
    let Some((input, v1, v2)) = input else {
        return Err(SkyArgsError::MissingLevels);
    };
    if !(0.0..=1.0).contains(&rho) {
        return Err(SkyArgsError::GroundReflectance { value: rho });
    }
    let water = (0.07 * dew_point - 0.075).exp();
    if let When::Date { solar: false, .. } = when
        && (site.meridian - site.longitude).abs() > 45.0 * DEG
    {
        warnings.push(format!(
            "{:.1} hours btwn. standard meridian and longitude",
            (site.longitude - site.meridian) * 12.0 / PI
        ));
    }
    let (mut altitude, azimuth, solar_time) = site.position(when, year);
    let day = match when {
        When::Date { month, day, .. } => day_of_year(month, day),
        When::Angles(..) => 0,
    };
    let mut sky = Gendaylit {
        diffuse_norm: 0.0,
        ground: 0.0,
        perez: [0.0; 5],
        sun_dir: sun_direction(altitude, azimuth),
        altitude: altitude / DEG,
        azimuth: azimuth / DEG,
        solar_time,
        epsilon: 0.0,
        delta: 0.0,
        water,
        solar: None,
        diffuse_horizontal: 0.0,
        direct_normal: 0.0,
        warnings: Vec::new(),
    };
    let error_sky = |mut sky: Gendaylit, mut warnings: Vec<String>, why: &str| {
        warnings.push(format!("{why}, printing error sky (black, no sun)"));
        sky.warnings = if quiet { Vec::new() } else { warnings };
        Ok(sky)
    };
    if let (When::Date { month, day, .. }, Some(st)) = (when, solar_time) {
        let w = (-(site.latitude.tan() * declination(day_of_year(month, day)).tan())) as f32 as f64;
        let half = (PI / 2.0 - w.atan2((1.0 - w * w).sqrt())) * 180.0 / (PI * 15.0);
        if st < 12.0 - half || st > 12.0 + half {
            return error_sky(sky, warnings, "sun altitude below zero");
        }
    }
    if !cloudy && altitude > 87.0 * DEG {
        warnings.push("sun too close to zenith, reducing altitude to 87 degrees".into());
        altitude = 87.0 * DEG;
    }
    let sun_dir = sun_direction(altitude, azimuth);
    (sky.sun_dir, sky.altitude) = (sun_dir, altitude / DEG);
    let mut zenith_deg = 90.0 - altitude / DEG;
    let e0 = {
        let a = 2.0 * PI * (day as f64 - 1.0) / 365.0;
        1.00011
            + 0.034221 * a.cos()
            + 0.00128 * a.sin()
            + 0.000719 * (2.0 * a).cos()
            + 0.000077 * (2.0 * a).sin()
    };
    let mut air_mass = || {
        if zenith_deg > 90.0 {
            zenith_deg = 90.0;
        }
        1.0 / ((zenith_deg * DEG).cos() + 0.15 * (93.885 - zenith_deg).powf(-1.253))
    };
    let m = air_mass();
    let z = zenith_deg * DEG;
    let z3 = 1.041 * z.powi(3);
    let brightness = |diff: f64| diff * m / (SOLAR_CONSTANT_E * e0);
    let clearness = |diff: f64, dir: f64| ((diff + dir) / diff + z3) / (1.0 + z3);
    let clamp = |e: f64, d: f64| {
        let e = if e < CLEARNESS.0 {
            CLEARNESS.0
        } else if e > CLEARNESS.1 {
            CLEARNESS.1 - 0.001
        } else {
            e
        };
        (e, d.clamp(BRIGHTNESS.0, BRIGHTNESS.1))
    };
    let k_diff = |e: f64, d: f64| {
        let k = DIFFUSE_EFFICACY[bin(e)];
        k[0] + k[1] * water + k[2] * z.cos() + k[3] * d.ln()
    };
    let k_dir = |e: f64, d: f64| {
        let k = DIRECT_EFFICACY[bin(e)];
        (k[0] + k[1] * water + k[2] * (5.73 * z - 5.0).exp() + k[3] * d).max(0.0)
    };
    let mut lv = Levels { epsilon: 0.0, delta: 0.0, dir_irr: v1, diff_irr: v2, dir_ill: 0.0, diff_ill: 0.0 };
    let irradiances = |lv: &mut Levels, warnings: &mut Vec<String>| -> Result<(), &'static str> {
        for (v, what) in [(&mut lv.dir_irr, "direct"), (&mut lv.diff_irr, "diffuse")] {
            if *v < 0.0 {
                warnings.push(format!("{what} irradiance < 0. Using 0.0"));
                *v = 0.0;
            }
        }
        if lv.dir_irr + lv.diff_irr == 0.0 && altitude > 0.0 {
            return Err("zero irradiance at sun altitude > 0");
        }
        if lv.dir_irr > SOLAR_CONSTANT_E {
            return Err("direct irradiance exceeds solar constant");
        }
        Ok(())
    };
    let from_irradiances = |lv: &mut Levels| {
        (lv.epsilon, lv.delta) = clamp(clearness(lv.diff_irr, lv.dir_irr), brightness(lv.diff_irr));
    };
    let check_illuminances = |lv: &mut Levels, warnings: &mut Vec<String>| -> Result<(), &'static str> {
        for (v, what) in [(&mut lv.dir_ill, "direct"), (&mut lv.diff_ill, "diffuse")] {
            if *v < 0.0 {
                warnings.push(format!("{what} illuminance < 0. Using 0.0"));
                *v = 0.0;
            }
        }
        if lv.dir_ill + lv.diff_ill == 0.0 && altitude > 0.0 {
            return Err("zero illuminance at sun altitude > 0");
        }
        if lv.dir_ill > SOLAR_CONSTANT_L {
            return Err("direct illuminance exceeds solar constant");
        }
        Ok(())
    };
    // The illuminances from the irradiances by Perez's efficacies, when the output needs them.
    let illuminances = |lv: &mut Levels, warnings: &mut Vec<String>| -> Result<(), &'static str> {
        if output == 1 {
            return Ok(());
        }
        lv.diff_ill = lv.diff_irr * k_diff(lv.epsilon, lv.delta);
        lv.dir_ill = lv.dir_irr * k_dir(lv.epsilon, lv.delta);
        check_illuminances(lv, warnings)
    };
    let outcome = (|| {
        match input {
            'P' => {
                (lv.epsilon, lv.delta) = clamp(v1, v2);
                lv.diff_irr = lv.delta / m * SOLAR_CONSTANT_E * e0;
                lv.dir_irr = lv.diff_irr * (lv.epsilon - 1.0) * (1.0 + z3);
                irradiances(&mut lv, &mut warnings)?;
                illuminances(&mut lv, &mut warnings)?;
            }
            'W' | 'G' | 'E' => {
                if input == 'G' {
                    (lv.dir_irr, lv.diff_irr) =
                        if altitude <= 0.0 { (0.0, 0.0) } else { (v1 / altitude.sin(), v2) };
                } else if input == 'E' {
                    if altitude <= 0.0 {
                        return Err("sun altitude below zero with -E");
                    }
                    let s0 = SOLAR_CONSTANT_E * e0 * altitude.sin();
                    let g = if v1 > s0 {
                        warnings.push(
                            "global irradiance is higher than the time-dependent solar constant s0".into(),
                        );
                        0.999 * s0
                    } else {
                        v1
                    };
                    let kt = g / s0;
                    let diff = if kt <= 0.22 {
                        g * (1.0 - 0.09 * kt)
                    } else if kt <= 0.8 {
                        g * (0.9511 - 0.1604 * kt + 4.388 * kt.powi(2) - 16.638 * kt.powi(3)
                            + 12.336 * kt.powi(4))
                    } else {
                        g * 0.165
                    };
                    (lv.dir_irr, lv.diff_irr) = ((g - diff) / altitude.sin(), diff);
                }
                irradiances(&mut lv, &mut warnings)?;
                from_irradiances(&mut lv);
                illuminances(&mut lv, &mut warnings)?;
            }
            _ => {
                (lv.dir_ill, lv.diff_ill) = (v1, v2);
                check_illuminances(&mut lv, &mut warnings)?;
                let (v1, v2) = (lv.dir_ill, lv.diff_ill);
                lv.diff_irr = v2 * SOLAR_CONSTANT_E / SOLAR_CONSTANT_L;
                lv.dir_irr = v1 * SOLAR_CONSTANT_E / SOLAR_CONSTANT_L;
                from_irradiances(&mut lv);
                for _ in 0..9 {
                    lv.diff_irr = v2 / k_diff(lv.epsilon, lv.delta);
                    let d_eff = k_dir(lv.epsilon, lv.delta);
                    lv.dir_irr = if d_eff < 0.1 { 0.0 } else { v1 / d_eff };
                    from_irradiances(&mut lv);
                }
            }
        }
        Ok(())
    })();
    if let Err(why) = outcome {
        return error_sky(sky, warnings, why);
    }
    let c = perez_parameters(lv.epsilon, lv.delta, z);
    (sky.epsilon, sky.delta, sky.perez) = (lv.epsilon, lv.delta, c);
    let (diffuse, direct) = match output {
        0 => (lv.diff_ill / WHITE_EFFICACY, lv.dir_ill / WHITE_EFFICACY),
        1 => (lv.diff_irr, lv.dir_irr),
        _ => (lv.diff_ill, lv.dir_ill),
    };
    (sky.diffuse_horizontal, sky.direct_normal) = (diffuse, direct);
    sky.diffuse_norm = diffuse / integral_145(&c, z);
    let solar = direct / (2.0 * PI * (1.0 - (0.5 * SUN_DIAMETER_DEGREES * DEG).cos()));
    let zenith = perez_relative(&c, 0.0, z) * sky.diffuse_norm;
    let normsc = |k: [f64; 5]| {
        let x = (altitude - PI / 4.0) / (PI / 4.0);
        k.iter().rev().fold(0.0, |acc, k| acc * x + k)
    };
    let norm = if lv.epsilon == 1.0 {
        0.777778
    } else if lv.epsilon >= 6.0 {
        let f2 = 0.274 * (0.91 + 10.0 * (-3.0 * (PI / 2.0 - altitude)).exp() + 0.45 * sun_dir.z * sun_dir.z);
        normsc([2.766521, 0.547665, -0.369832, 0.009237, 0.059229]) / f2 / PI
    } else {
        let f2 = (2.739 + 0.9891 * (0.3119 + 2.6 * altitude).sin())
            * (-(PI / 2.0 - altitude) * (0.4441 + 1.48 * altitude)).exp();
        normsc([3.5556, -2.7152, -1.3081, 1.0660, 0.60227]) / f2 / PI
    };
    let mut ground = zenith * norm;
    if dosun && lv.epsilon > 1.0 {
        ground += 6.8e-5 / PI * solar * sun_dir.z;
    }
    sky.ground = ground * rho;
    if c[1] > 0.0 {
        return error_sky(sky, warnings, &format!("positive Perez parameter B (= {:.6})", c[1]))
            .map(|s| Gendaylit { diffuse_norm: 0.0, ground: 0.0, perez: [0.0; 5], ..s });
    }
    if dosun {
        sky.solar = Some(if lv.epsilon > 1.0 { solar } else { 0.0 });
    }
    sky.warnings = if quiet { Vec::new() } else { warnings };
    Ok(sky)
}

impl Gendaylit {
    /// perezlum.cal's `skybright` toward `d` (unit, world: z up), W/(sr·m²) (or cd/m² for
    /// `-O 2`).
    pub fn brightness(&self, d: DVec3) -> f64 {
        let c = &self.perez;
        let cos_gamma = d.dot(self.sun_dir);
        let gamma = cos_gamma.clamp(-1.0, 1.0).acos();
        let dz = if d.z - 0.01 > 0.0 { d.z } else { 0.01 };
        let sky = self.diffuse_norm
            * (1.0 + c[0] * (c[1] / dz).exp())
            * (1.0 + c[2] * (c[3] * gamma).exp() + c[4] * cos_gamma * cos_gamma);
        let (w_sky, w_ground) = ((d.z + 1.01).powi(10), (d.z + 1.01).powi(-10));
        (w_sky * sky + w_ground * self.ground) / (w_sky + w_ground)
    }
}
