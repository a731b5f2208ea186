//! `!gensky` interpreted, never run: its arguments, the sun's position, the CIE sky it
//! describes (the `skyfunc` brightness of `skybright.cal`) and its `solar` source.
//!
//! Written from the formulas of Radiance's own sources (LBNL-ETA/Radiance, `src/gen/gensky.c`
//! 2.31, `src/gen/sun.c` 2.7, `src/gen/skybright.cal` 2.7, `src/common/color.h`), not from their
//! code:
//!
//! * **Sun position** (`sun.c`). Day of the year J (no leap years), solar declination
//!   δ = 0.4093·sin(2π(J − 81)/365), solar time t = hour + 0.170·sin(4π(J − 80)/373)
//!   − 0.129·sin(2π(J − 8)/355) + 12(meridian − longitude)/π (longitudes and meridians in radians
//!   **west** of Greenwich, Radiance's sign), altitude a = asin(sin φ sin δ − cos φ cos δ cos(πt/12))
//!   and azimuth A = −atan2(cos δ sin(πt/12), −cos φ sin δ − sin φ cos δ cos(πt/12)) (from south,
//!   positive toward west). With `-y year`, the Michalsky (1988) almanac algorithm instead, as
//!   gensky. The sun's direction is (−sin A cos a, −cos A cos a, sin a): x east, y north, z up.
//! * **Levels** (`gensky.c`). Zenith luminance (kcd/m²) (1.376T − 1.81)·tan a + 0.38 for clear
//!   skies, 8.6 sin a + 0.123 for overcast and uniform, their mean for intermediate, as radiance
//!   ×1000/203 (Radiance's sky efficacy, D65's); or from `-b` (radiance) or `-B` (horizontal
//!   diffuse irradiance E, zenith = E/(π·n)) with n the sky's normalisation (1 uniform, 7/9
//!   overcast, the polynomial `normsc`/F2/π for clear and intermediate). Solar radiance
//!   1.5·10⁹/208·(1.147 − 0.147/max(sin a, 0.16)) (×0.15 for intermediate), or `-r` radiance,
//!   or `-R` horizontal direct irradiance ÷ (5.98·10⁻⁵·sin a). Ground brightness
//!   ρ_g·(zenith·n + 6·10⁻⁵/π·solar·sin a).
//! * **Sky brightness** (`skybright.cal`): the CIE clear, overcast ((1 + 2 cos θ)/3), uniform and
//!   intermediate distributions, blended toward the ground brightness by the weights
//!   (D_z + 1.01)^±10 near and below the horizon.

use glam::DVec3;
use std::f64::consts::PI;

const DEG: f64 = PI / 180.0;
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

/// gensky's time zones and their standard meridians (degrees west).
const ZONES: &[(&str, f64)] = &[
    ("YST", 135.0),
    ("YDT", 120.0),
    ("PST", 120.0),
    ("PDT", 105.0),
    ("MST", 105.0),
    ("MDT", 90.0),
    ("CST", 90.0),
    ("CDT", 75.0),
    ("EST", 75.0),
    ("EDT", 60.0),
    ("AST", 60.0),
    ("ADT", 45.0),
    ("NST", 52.5),
    ("NDT", 37.5),
    ("GMT", 0.0),
    ("BST", -15.0),
    ("CET", -15.0),
    ("CEST", -30.0),
    ("EET", -30.0),
    ("EEST", -45.0),
    ("GST", -60.0),
    ("GDT", -75.0),
    ("IST", -82.5),
    ("IDT", -97.5),
    ("JST", -135.0),
    ("NZST", -180.0),
    ("NZDT", -195.0),
];

/// An hour `h`, `h.frac`, `h:mm`, optionally `+` first (solar time) or a time zone after:
/// (hour, solar time?, the zone's meridian in degrees).
fn parse_hour(s: &str) -> Result<(f64, bool, Option<f64>), String> {
    let (solar, rest) = match s.strip_prefix('+') {
        Some(r) => (true, r),
        None => (false, s),
    };
    let end = rest.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(rest.len());
    let (time, zone) = rest.split_at(end);
    let hour = match time.split_once(':') {
        Some((h, m)) => {
            let h: u32 = h.parse().map_err(|_| format!("bad time format: {s}"))?;
            let m: u32 = m.parse().map_err(|_| format!("bad time format: {s}"))?;
            h as f64 + m as f64 / 60.0
        }
        None => time.parse::<f64>().map_err(|_| format!("bad time format: {s}"))?,
    };
    if !hour.is_finite() {
        return Err(format!("bad time format: {s}"));
    }
    if zone.is_empty() {
        return Ok((hour, solar, None));
    }
    if solar {
        return Err(format!("bad time format: {s} (solar time takes no time zone)"));
    }
    let upper = zone.to_ascii_uppercase();
    match ZONES.iter().find(|(z, _)| *z == upper) {
        Some((_, m)) => Ok((hour, false, Some(*m))),
        None => Err(format!(
            "unknown time zone: {zone} (known: {})",
            ZONES.iter().map(|(z, _)| *z).collect::<Vec<_>>().join(" ")
        )),
    }
}

/// Day of the year, no leap years (sun.c's `jdate`).
fn day_of_year(month: u32, day: u32) -> i32 {
    const START: [i32; 12] = [0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334];
    START[month as usize - 1] + day as i32
}

/// The site: latitude, longitude and standard meridian, radians (west positive).
#[derive(Clone, Copy, Debug)]
pub struct Site {
    /// Latitude, north positive.
    pub latitude: f64,
    /// Longitude, west positive.
    pub longitude: f64,
    /// Standard meridian, west positive.
    pub meridian: f64,
}

impl Site {
    /// Solar time − standard time, hours, on day `jd`.
    pub fn time_adjustment(&self, jd: i32) -> f64 {
        let j = jd as f64;
        0.170 * (4.0 * PI / 373.0 * (j - 80.0)).sin() - 0.129 * (2.0 * PI / 355.0 * (j - 8.0)).sin()
            + 12.0 / PI * (self.meridian - self.longitude)
    }

    /// Solar (altitude, azimuth), radians, at declination `sd` and solar time `st` (hours).
    pub fn sun(&self, sd: f64, st: f64) -> (f64, f64) {
        let (h, lat) = (st * PI / 12.0, self.latitude);
        let alt = (lat.sin() * sd.sin() - lat.cos() * sd.cos() * h.cos()).asin();
        let azi = -(sd.cos() * h.sin()).atan2(-lat.cos() * sd.sin() - lat.sin() * sd.cos() * h.cos());
        (alt, azi)
    }

    /// Michalsky: days from noon UT on 1 January 2000 (sun.c's `mjdate`).
    fn almanac_date(&self, year: i32, month: u32, day: u32, hour: f64) -> f64 {
        let mut jd = day_of_year(month, day);
        jd += i32::from(month > 2 && year % 4 == 0);
        jd += (year - 1949) * 365 + (year - 1949) / 4;
        let hour = hour + self.meridian * 12.0 / PI;
        jd as f64 + hour / 24.0 + (2432916.5 - 2451545.0)
    }

    /// Michalsky: declination and (for standard time) solar time (sun.c's `msdec`).
    fn almanac_sun(&self, mjd: f64) -> (f64, f64) {
        let wrap = |r: f64, p: f64| r.rem_euclid(p);
        let l_mean = wrap(280.460 * DEG + 0.9856474 * DEG * mjd, 2.0 * PI);
        let g = wrap(357.528 * DEG + 0.9856003 * DEG * mjd, 2.0 * PI);
        let l = l_mean + 1.915 * DEG * g.sin() + 0.020 * DEG * (2.0 * g).sin();
        let ep = 23.439 * DEG - 4e-7 * DEG * mjd;
        let ra = (l.sin() * ep.cos()).atan2(l.cos());
        let utime = 24.0 * (mjd - mjd.floor()) + 12.0;
        let gmst = 6.697375 + 0.0657098242 * mjd + utime;
        let lmst = gmst - self.longitude * 12.0 / PI;
        ((ep.sin() * l.sin()).asin(), wrap(lmst - ra * 12.0 / PI + 12.0, 24.0))
    }
}

fn number(args: &[String], i: usize, option: &str) -> Result<f64, String> {
    let s = args.get(i).ok_or_else(|| format!("{option} needs a value"))?;
    s.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("{option}: \"{s}\" is not a number"))
}

/// Reads gensky's arguments (`args` without the program name) and computes the sky as gensky
/// does. Errors are gensky's (bad month, unknown option, …).
pub fn gensky(args: &[String]) -> Result<Gensky, String> {
    if args.len() < 3 {
        return Err("usage: gensky month day hour [options] | -ang altitude azimuth [options]".into());
    }
    let mut site = Site { latitude: 0.66, longitude: 2.13, meridian: 120.0 * DEG };
    let (mut altitude, mut azimuth) = (0.0, 0.0);
    let mut date = None;
    let mut zone_meridian = None;
    if args[0] == "-ang" {
        altitude = number(args, 1, "-ang")? * DEG;
        azimuth = number(args, 2, "-ang")? * DEG;
    } else {
        let month: u32 = args[0].parse().ok().filter(|m| (1..=12).contains(m)).ok_or("bad month")?;
        let day: u32 = args[1].parse().ok().filter(|d| (1..=31).contains(d)).ok_or("bad day")?;
        let (hour, solar_time, zone) = parse_hour(&args[2])?;
        zone_meridian = zone;
        date = Some((month, day, hour, solar_time));
    }
    let (mut sky, mut dosun) = (SkyType::Clear, true);
    let (mut zenith, mut u_zenith, mut turbidity, mut rho) = (0.0, 0, 2.45, 0.2);
    let (mut solar, mut u_solar, mut year) = (0.0, 0, None);
    let mut i = 3;
    while i < args.len() {
        let a = args[i].as_str();
        let (sign, letter) = match (a.chars().next(), a.chars().nth(1)) {
            (Some(s @ ('-' | '+')), Some(l)) if a.len() == 2 => (s, l),
            _ => return Err(format!("bad option: {a}")),
        };
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
            _ => return Err(format!("unknown option: {a}")),
        }
        i += 1;
    }
    if let Some(m) = zone_meridian {
        site.meridian = m * DEG;
    }
    if !(0.0..=1.0).contains(&rho) {
        return Err(format!("-g {rho}: a ground reflectance is in [0, 1]"));
    }
    if zenith < 0.0 || solar < 0.0 {
        return Err("-b/-B and -r/-R take values ≥ 0".into());
    }
    let mut warnings = Vec::new();
    let mut solar_time = None;
    if let Some((month, day, hour, tsolar)) = date {
        if let Some(y) = year
            && !(1950..=2050).contains(&y)
        {
            warnings.push("year should be in range 1950-2050".into());
        }
        if !tsolar && (site.meridian - site.longitude).abs() > 45.0 * DEG {
            warnings.push(format!(
                "{:.1} hours btwn. standard meridian and longitude",
                (site.longitude - site.meridian) * 12.0 / PI
            ));
        }
        let (sd, st) = match year {
            Some(y) => {
                let (sd, st) = site.almanac_sun(site.almanac_date(y, month, day, hour));
                (sd, if tsolar { hour } else { st })
            }
            None => {
                let jd = day_of_year(month, day);
                let sd = 0.4093 * (2.0 * PI / 365.0 * (jd as f64 - 81.0)).sin();
                (sd, if tsolar { hour } else { hour + site.time_adjustment(jd) })
            }
        };
        (altitude, azimuth) = site.sun(sd, st);
        solar_time = Some(st);
    }
    let (reported_alt, reported_azi) = (altitude / DEG, azimuth / DEG);
    if !sky.overcast() && altitude > 87.0 * DEG {
        warnings.push("sun too close to zenith, reducing altitude to 87 degrees".into());
        altitude = 87.0 * DEG;
    }
    let sun_dir =
        DVec3::new(-azimuth.sin() * altitude.cos(), -azimuth.cos() * altitude.cos(), altitude.sin());
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
        let cos_gamma = d.dot(s).clamp(-1.0, 1.0);
        let gamma = cos_gamma.acos();
        let zt = s.z.clamp(-1.0, 1.0).acos();
        let eta = d.z.clamp(-1.0, 1.0).acos();
        let sky = match self.sky {
            SkyType::Clear => {
                let horizon = if d.z - 0.01 > 0.0 { 1.0 - (-0.32 / d.z).exp() } else { 1.0 };
                a2 * (0.91 + 10.0 * (-3.0 * gamma).exp() + 0.45 * cos_gamma * cos_gamma) * horizon / a4
            }
            SkyType::Overcast => a2 * (1.0 + 2.0 * d.z) / 3.0,
            SkyType::Uniform => a2,
            SkyType::Intermediate => {
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

/// The solid angle of a cone of full angle `angle_degrees` (a `source`'s fourth real), sr.
pub fn cone_solid_angle(angle_degrees: f64) -> f64 {
    2.0 * PI * (1.0 - (0.5 * angle_degrees.min(360.0) * DEG).cos())
}

/// An equirectangular map (Mitsuba's convention, `opticks_core::light::environment`, map +y
/// being world +z) of `radiance(d)` for the directions d within `half_angle` of `axis`, zero
/// elsewhere: `width` × `height` texels, the rows at polar angles πj/(height − 1).
pub fn rasterise(
    width: usize,
    height: usize,
    axis: DVec3,
    half_angle: f64,
    radiance: impl Fn(DVec3) -> f64,
) -> Vec<f64> {
    let cos_limit = half_angle.min(PI).cos() - 1e-9;
    let mut texels = Vec::with_capacity(width * height);
    for j in 0..height {
        let theta = PI * j as f64 / (height - 1) as f64;
        for i in 0..width {
            let phi = 2.0 * PI * (i as f64 + 0.5) / width as f64;
            let d = map_to_world(phi, theta);
            texels.push(if d.dot(axis) >= cos_limit { radiance(d) } else { 0.0 });
        }
    }
    texels
}

/// The world direction (z up) of the map's (φ, θ): the map's d = (sin φ sin θ, cos θ,
/// −cos φ sin θ) under [`MAP_TO_WORLD`].
pub fn map_to_world(phi: f64, theta: f64) -> DVec3 {
    DVec3::new(phi.sin() * theta.sin(), phi.cos() * theta.sin(), theta.cos())
}

/// The rotation from the map's frame (+y up) to Radiance's world (+z up): x → x, y → z,
/// z → −y.
pub const MAP_TO_WORLD: glam::Mat3 = glam::Mat3::from_cols(
    glam::Vec3::new(1.0, 0.0, 0.0),
    glam::Vec3::new(0.0, 0.0, 1.0),
    glam::Vec3::new(0.0, -1.0, 0.0),
);

#[cfg(test)]
mod tests;
