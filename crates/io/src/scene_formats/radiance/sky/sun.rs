//! What gensky and gendaylit share (Radiance's `sun.c` 2.7 and the two programs' first
//! arguments): the site, the day and hour or the sun's angles, and the sun's position.

use super::SkyArgsError;
use glam::DVec3;
use std::f64::consts::PI;

pub(super) const DEG: f64 = PI / 180.0;

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

/// gensky's time zones, separated by spaces.
pub(super) fn zone_names() -> String {
    ZONES.iter().map(|(z, _)| *z).collect::<Vec<_>>().join(" ")
}

/// An hour `h`, `h.frac`, `h:mm`, optionally `+` first (solar time) or a time zone after:
/// (hour, solar time?, the zone's meridian in degrees).
pub(super) fn parse_hour(s: &str) -> Result<(f64, bool, Option<f64>), SkyArgsError> {
    let (solar, rest) = match s.strip_prefix('+') {
        Some(r) => (true, r),
        None => (false, s),
    };
    let bad = || SkyArgsError::BadTime { word: s.to_string() };
    let end = rest.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(rest.len());
    let (time, zone) = rest.split_at(end);
    let hour = match time.split_once(':') {
        Some((h, m)) => {
            let h: u32 = h.parse().map_err(|_| bad())?;
            let m: u32 = m.parse().map_err(|_| bad())?;
            h as f64 + m as f64 / 60.0
        }
        None => time.parse::<f64>().map_err(|_| bad())?,
    };
    if !hour.is_finite() {
        return Err(bad());
    }
    if zone.is_empty() {
        return Ok((hour, solar, None));
    }
    if solar {
        return Err(SkyArgsError::SolarTimeWithZone { word: s.to_string() });
    }
    let upper = zone.to_ascii_uppercase();
    match ZONES.iter().find(|(z, _)| *z == upper) {
        Some((_, m)) => Ok((hour, false, Some(*m))),
        None => Err(SkyArgsError::UnknownZone { zone: zone.to_string() }),
    }
}

/// Day of the year, no leap years (sun.c's `jdate`).
pub(super) fn day_of_year(month: u32, day: u32) -> i32 {
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

/// A generator's option word, `-x` or `+x`: its sign and letter (gensky's and gendaylit's
/// options are all one letter).
pub(super) fn option_word(a: &str) -> Result<(char, char), SkyArgsError> {
    match (a.chars().next(), a.chars().nth(1)) {
        (Some(s @ ('-' | '+')), Some(l)) if a.len() == 2 => Ok((s, l)),
        _ => Err(SkyArgsError::BadOption { option: a.to_string() }),
    }
}

/// Argument `i` as the number `option` takes.
pub(super) fn number(args: &[String], i: usize, option: &str) -> Result<f64, SkyArgsError> {
    let s = args.get(i).ok_or_else(|| SkyArgsError::MissingValue { option: option.to_string() })?;
    s.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| SkyArgsError::NotANumber { option: option.to_string(), word: s.to_string() })
}

/// The first arguments of both generators: a date and hour, or the sun's angles.
#[derive(Clone, Copy, Debug)]
pub(super) enum When {
    /// `-ang altitude azimuth`, radians.
    Angles(f64, f64),
    /// `month day hour`: the hour, whether it is solar time, a time zone's meridian (degrees).
    Date { month: u32, day: u32, hour: f64, solar: bool, zone: Option<f64> },
}

/// Reads `month day hour` or `-ang altitude azimuth` (the first three arguments). `zones`:
/// whether the hour may be `h:mm` or carry a time zone (gensky's), else it is a number in
/// [0, 24), `+` first for solar time (gendaylit's).
pub(super) fn parse_when(args: &[String], zones: bool) -> Result<When, SkyArgsError> {
    if args[0] == "-ang" {
        return Ok(When::Angles(number(args, 1, "-ang")? * DEG, number(args, 2, "-ang")? * DEG));
    }
    let month: u32 = (args[0].parse().ok().filter(|m| (1..=12).contains(m)))
        .ok_or_else(|| SkyArgsError::BadMonth { word: args[0].clone() })?;
    let day: u32 = (args[1].parse().ok().filter(|d| (1..=31).contains(d)))
        .ok_or_else(|| SkyArgsError::BadDay { word: args[1].clone() })?;
    let (hour, solar, zone) = if zones {
        parse_hour(&args[2])?
    } else {
        let h = args[2].parse::<f64>().ok().filter(|h| (0.0..24.0).contains(h));
        let h = h.ok_or_else(|| SkyArgsError::BadHour { word: args[2].clone() })?;
        (h, args[2].starts_with('+'), None)
    };
    Ok(When::Date { month, day, hour, solar, zone })
}

impl Site {
    /// gensky's and gendaylit's default site (sun.c): 0.66 rad N, 2.13 rad W, meridian 120° W.
    pub const DEFAULT: Site = Site { latitude: 0.66, longitude: 2.13, meridian: 120.0 * DEG };

    /// The sun's (altitude, azimuth) in radians and the solar time (none for `-ang`): sun.c's
    /// `sdec`/`stadj`, or Michalsky's algorithm with a `year`.
    pub(super) fn position(&self, when: When, year: Option<i32>) -> (f64, f64, Option<f64>) {
        let When::Date { month, day, hour, solar, .. } = when else {
            let When::Angles(alt, azi) = when else { unreachable!() };
            return (alt, azi, None);
        };
        let (sd, st) = self.declination_and_time(month, day, hour, solar, year);
        let (alt, azi) = self.sun(sd, st);
        (alt, azi, Some(st))
    }

    /// Solar declination (radians) and solar time (hours) at a date and hour.
    pub(super) fn declination_and_time(
        &self,
        month: u32,
        day: u32,
        hour: f64,
        solar: bool,
        year: Option<i32>,
    ) -> (f64, f64) {
        match year {
            Some(y) => {
                let (sd, st) = self.almanac_sun(self.almanac_date(y, month, day, hour));
                (sd, if solar { hour } else { st })
            }
            None => {
                let jd = day_of_year(month, day);
                (declination(jd), if solar { hour } else { hour + self.time_adjustment(jd) })
            }
        }
    }
}

/// sun.c's `sdec`: the solar declination on day `jd`, radians.
pub(super) fn declination(jd: i32) -> f64 {
    0.4093 * (2.0 * PI / 365.0 * (jd as f64 - 81.0)).sin()
}

/// Toward the sun (z up, y north, x east) at altitude and azimuth (radians, from south, west
/// positive).
pub(super) fn sun_direction(altitude: f64, azimuth: f64) -> DVec3 {
    DVec3::new(-azimuth.sin() * altitude.cos(), -azimuth.cos() * altitude.cos(), altitude.sin())
}
