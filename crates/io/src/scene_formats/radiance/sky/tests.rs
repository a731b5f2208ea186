//! gensky's own output as the reference: each case's command (Radiance 6 via pyradiance's
//! `gensky`, `RAYPATH` its `lib`) and the numbers it printed. gensky prints altitude and
//! azimuth to 0.1°, solar time to 0.01 h, directions to 10⁻⁶ and levels to 4 digits.
#![allow(clippy::approx_constant, clippy::needless_range_loop)] // gensky's digits, as printed

use super::*;

fn run(cmd: &str) -> Gensky {
    let args: Vec<String> = cmd.split_whitespace().map(str::to_string).collect();
    gensky(&args).unwrap_or_else(|e| panic!("{cmd}: {e}"))
}

fn close(what: &str, got: f64, want: f64, tol: f64) {
    assert!((got - want).abs() <= tol, "{what}: {got} vs gensky's {want} (±{tol})");
}

/// (arguments, solar time, altitude, azimuth, sun direction, zenith, ground, F2, solar radiance)
#[allow(clippy::type_complexity)]
const CASES: &[(&str, Option<f64>, f64, f64, [f64; 3], f64, f64, f64, Option<f64>)] = &[
    // gensky 3 21 12 -a 40 -o 105 -m 105
    (
        "3 21 12 -a 40 -o 105 -m 105",
        Some(11.88),
        49.6,
        -2.9,
        [0.032292, -0.647833, 0.761097],
        10.90,
        23.00,
        0.6505,
        Some(6.879e6),
    ),
    // gensky 6 21 10 -a 37.8 -o 122.4 -m 120
    (
        "6 21 10 -a 37.8 -o 122.4 -m 120",
        Some(9.82),
        58.6,
        -72.3,
        [0.496299, -0.158445, 0.853571],
        14.47,
        25.99,
        0.8686,
        Some(7.030e6),
    ),
    // gensky 12 21 15.5 -a 51.5 -o 0 -m 0
    (
        "12 21 15.5 -a 51.5 -o 0 -m 0",
        Some(15.55),
        1.8,
        47.3,
        [-0.734394, -0.678023, 0.030814],
        2.109,
        1.137,
        0.2765,
        Some(1.646e6),
    ),
    // gensky 9 1 8:30 -a -33.9 -o -151.2 -m -150
    (
        "9 1 8:30 -a -33.9 -o -151.2 -m -150",
        Some(8.57),
        26.0,
        -120.5,
        [0.774308, 0.456461, 0.438282],
        5.622,
        12.19,
        0.3690,
        Some(5.853e6),
    ),
    // gensky 7 4 14EDT -a 40.7 -o 74 +s
    (
        "7 4 14EDT -a 40.7 -o 74 +s",
        Some(13.00),
        68.2,
        39.9,
        [-0.238434, -0.285416, 0.928271],
        21.07,
        28.51,
        1.229,
        Some(7.130e6),
    ),
    // gensky 6 21 12 +s -a 10 -o 0 -m 0
    (
        "6 21 12 +s -a 10 -o 0 -m 0",
        Some(11.98),
        76.5,
        -178.6,
        [0.005614, 0.232616, 0.972553],
        34.02,
        30.44,
        1.720,
        Some(7.182e6),
    ),
    // gensky 3 21 12 +i -a 40 -o 105 -m 105
    (
        "3 21 12 +i -a 40 -o 105 -m 105",
        Some(11.88),
        49.6,
        -2.9,
        [0.032292, -0.647833, 0.761097],
        21.87,
        7.683,
        0.9717,
        Some(1.032e6),
    ),
    // gensky 3 21 12 -i -b 10  (default site: 0.66 rad N, 2.13 rad W, meridian 120° W)
    ("3 21 12 -i -b 10", Some(11.74), 51.6, -6.3, [0.067850, -0.617254, 0.783832], 10.0, 5.156, 0.9735, None),
    // gensky -ang 45 30 +s -g 0.3 -t 3
    (
        "-ang 45 30 +s -g 0.3 -t 3",
        None,
        45.0,
        30.0,
        [-0.353553, -0.612372, 0.707107],
        13.29,
        33.59,
        0.5707,
        Some(6.772e6),
    ),
    // gensky -ang 45 30 +s -R 500 -B 100
    (
        "-ang 45 30 +s -R 500 -B 100",
        None,
        45.0,
        30.0,
        [-0.353553, -0.612372, 0.707107],
        20.63,
        38.30,
        0.5707,
        Some(1.182e7),
    ),
    // gensky 1 15 9 -y 2024 -a 40 -o 105 -m 105  (Michalsky)
    (
        "1 15 9 -y 2024 -a 40 -o 105 -m 105",
        Some(8.85),
        14.6,
        -45.1,
        [0.685746, -0.682581, 0.252657],
        3.880,
        5.716,
        0.3102,
        Some(4.076e6),
    ),
];

#[test]
fn gensky_matches_its_own_output() {
    for &(cmd, st, alt, azi, dir, zenith, ground, f2, solar) in CASES {
        let g = run(cmd);
        if let Some(st) = st {
            close(&format!("{cmd}: solar time"), g.solar_time.unwrap(), st, 0.0051);
        }
        close(&format!("{cmd}: altitude"), g.altitude, alt, 0.051);
        close(&format!("{cmd}: azimuth"), g.azimuth, azi, 0.051);
        for k in 0..3 {
            close(&format!("{cmd}: sun direction {k}"), g.sun_dir[k], dir[k], 1.5e-6);
        }
        close(&format!("{cmd}: zenith"), g.zenith, zenith, 0.0006 * zenith);
        close(&format!("{cmd}: ground"), g.ground, ground, 0.0006 * ground);
        close(&format!("{cmd}: F2"), g.f2, f2, 0.0006 * f2);
        match (g.solar, solar) {
            (Some(a), Some(b)) => close(&format!("{cmd}: solar"), a, b, 0.0006 * b),
            (a, b) => assert_eq!(a, b, "{cmd}: sun"),
        }
    }
}

#[test]
fn overcast_and_uniform_levels_are_gensky_s() {
    // gensky 3 21 12 -c -B 100 → "3 2 4.093e+01 6.366e+00"
    let g = run("3 21 12 -c -B 100");
    close("overcast zenith", g.zenith, 40.93, 0.01);
    close("overcast ground", g.ground, 6.366, 0.001);
    assert_eq!(g.solar, None);
    // gensky -ang 30 -60 -u -B 50 → "3 3 1.592e+01 3.183e+00"
    let g = run("-ang 30 -60 -u -B 50");
    close("uniform zenith", g.zenith, 15.92, 0.005);
    close("uniform ground", g.ground, 3.183, 0.0005);
}

/// Published geometry rather than a table (no calculator was reachable offline): at solar noon
/// on the June solstice the sun is due south at altitude 90° − φ + ε, ε = 23.44° (the obliquity;
/// gensky's declination peaks at 0.4093 rad = 23.45°, its Michalsky option gives the almanac's).
#[test]
fn sun_position_at_the_solstice_noon() {
    let g = run("6 21 +12 -a 40.015 -o 105.27 -m 90");
    close("altitude", g.altitude, 90.0 - 40.015 + 23.45, 0.02);
    close("azimuth", g.azimuth, 0.0, 1e-9);
    let g = run("6 20 +12 -a 40.015 -o 105.27 -m 90 -y 2024");
    close("altitude (Michalsky)", g.altitude, 90.0 - 40.015 + 23.44, 0.02);
}

/// ∫ f(d) cos θ dω over the upper hemisphere, midpoint rule in (cos θ, φ) (the daylight
/// tests' too).
pub(super) fn horizontal(f: impl Fn(DVec3) -> f64, n: usize) -> f64 {
    let mut sum = 0.0;
    for a in 0..n {
        let mu = (a as f64 + 0.5) / n as f64;
        let s = (1.0 - mu * mu).sqrt();
        for b in 0..2 * n {
            let phi = PI * (b as f64 + 0.5) / n as f64;
            sum += f(DVec3::new(s * phi.cos(), s * phi.sin(), mu)) * mu;
        }
    }
    sum * (1.0 / n as f64) * (PI / n as f64)
}

#[test]
fn sky_ratios_are_the_closed_forms() {
    let up = DVec3::Z;
    let horizon = DVec3::new(0.6, 0.8, 0.0);
    let blend = |sky: f64, ground: f64| {
        let (a, b) = (1.01f64.powi(10), 1.01f64.powi(-10));
        (a * sky + b * ground) / (a + b)
    };
    // CIE overcast: zenith 3 × horizon (before gensky's blend toward the ground).
    let g = run("3 21 12 -c -B 100");
    close("overcast zenith", g.brightness(up), g.zenith, 1e-5 * g.zenith);
    close("overcast horizon", g.brightness(horizon), blend(g.zenith / 3.0, g.ground), 1e-9);
    // Uniform.
    let g = run("-ang 30 -60 -u -B 50");
    close("uniform zenith", g.brightness(up), g.zenith, 1e-5 * g.zenith);
    let (a, b) = (1.51f64.powi(10), 1.51f64.powi(-10));
    let want = (a * g.zenith + b * g.ground) / (a + b);
    close("uniform 30°", g.brightness(DVec3::new(0.0, 0.75f64.sqrt(), 0.5)), want, 1e-9 * want);
    // CIE clear: the zenith is the zenith radiance up to 1 − e^−0.32 vs 0.274.
    let g = run("-ang 45 30 +s -g 0.3 -t 3");
    close("clear zenith", g.brightness(up), g.zenith * (1.0 - (-0.32f64).exp()) / 0.274, 1e-5 * g.zenith);
    // Ground: the ground brightness straight down.
    close("clear nadir", g.brightness(-up), g.ground, 1e-9 * g.ground);
    // Intermediate at the zenith: A2·((1.35 sin(5.631) + 3.12) sin(4.396 − 2.6 zt) + 6.37)/2.326
    // · exp(−0.563 zt ((2.629)(1.562 − zt) + 0.812))/F2.
    let g = run("-ang 45 30 -i -b 10");
    let zt = PI / 4.0;
    let want = 10.0 * ((1.35 * 5.631f64.sin() + 3.12) * (4.396 - 2.6 * zt).sin() + 6.37) / 2.326
        * (-0.563 * zt * (2.629 * (1.562 - zt) + 0.812)).exp()
        / g.f2;
    close("intermediate zenith", g.brightness(up), want, 1e-5 * want);
}

/// The horizontal illuminance of each sky (the hemisphere's ∫ L cos θ dω, quadrature) against
/// gensky's closed form π·zenith·normalisation (= `-B` when given). The clear and intermediate
/// normalisations are gensky's polynomial fits, and skybright.cal blends the sky toward the
/// ground near the horizon; the measured differences (printed) bound the tolerance.
#[test]
fn horizontal_irradiance_is_the_closed_form() {
    for (cmd, b, tol) in [
        ("3 21 12 -c -B 100", 100.0, 0.005),
        ("-ang 30 -60 -u -B 50", 50.0, 0.005),
        ("-ang 45 30 -s -B 100", 100.0, 0.02),
        ("-ang 20 30 -s -B 100", 100.0, 0.02),
        ("-ang 70 30 -s -B 100", 100.0, 0.02),
        ("-ang 45 30 -i -B 100", 100.0, 0.02),
        ("-ang 20 30 -i -B 100", 100.0, 0.02),
        ("-ang 70 30 -i -B 100", 100.0, 0.02),
    ] {
        let g = run(cmd);
        close(&format!("{cmd}: closed form"), g.horizontal_irradiance(), b, 1e-4 * b);
        let e = horizontal(|d| g.brightness(d), 400);
        let rel = e / g.horizontal_irradiance() - 1.0;
        eprintln!("{cmd}: E_h {e:.3} vs {:.3}: {:+.4}", g.horizontal_irradiance(), rel);
        assert!(
            rel.abs() < tol,
            "{cmd}: E_h {e} vs the closed form {} ({rel:+.4})",
            g.horizontal_irradiance()
        );
    }
}

/// The rasterised map's horizontal irradiance (the core's bilinear lookup, integrated finely)
/// against the analytic sky's: the resolution's error, measured (printed).
#[test]
fn rasterisation_error_of_the_horizontal_irradiance() {
    use opticks_core::light::LatLong;
    use opticks_core::math::Rgb;
    for cmd in ["-ang 45 30 -s -B 100", "-ang 10 30 -s -B 100", "3 21 12 -c -B 100", "-ang 30 0 -i -B 100"] {
        let g = run(cmd);
        let (w, h) = (super::SKY_MAP_WIDTH, super::SKY_MAP_HEIGHT);
        let texels: Vec<Rgb> = rasterise(w, h, DVec3::Z, PI / 2.0, |d| g.brightness(d))
            .into_iter()
            .map(|v| Rgb::splat(v as f32))
            .collect();
        let map = LatLong::new(w, h, &texels, 1.0).unwrap();
        let lookup = |d: DVec3| {
            // World (z up) → the map's frame: x, y_map = z, z_map = −y.
            let theta = d.z.clamp(-1.0, 1.0).acos();
            let phi = d.x.atan2(d.y).rem_euclid(2.0 * PI);
            map.eval_uv((phi / (2.0 * PI)) as f32, (theta / PI) as f32).x as f64
        };
        let exact = horizontal(|d| g.brightness(d), 600);
        let raster = horizontal(lookup, 600);
        let rel = raster / exact - 1.0;
        eprintln!("{cmd}: {w}×{h}: map {raster:.4} vs {exact:.4}: {rel:+.2e}");
        assert!(rel.abs() < 1e-3, "{cmd}: {rel}");
    }
}

/// gensky's refusals, typed and word for word (the texts the `.rad` reader wraps with the file,
/// line and the line itself).
#[test]
fn bad_lines_are_typed_errors_with_gensky_s_words() {
    let zones = "YST YDT PST PDT MST MDT CST CDT EST EDT AST ADT NST NDT GMT BST CET CEST EET EEST GST GDT IST IDT JST NZST NZDT";
    for (cmd, want, text) in [
        (
            "3 21",
            SkyArgsError::Usage { usage: GENSKY_USAGE },
            "usage: gensky month day hour [options] | -ang altitude azimuth [options]".to_string(),
        ),
        ("13 21 12", SkyArgsError::BadMonth { word: "13".into() }, "bad month".into()),
        ("3 0 12", SkyArgsError::BadDay { word: "0".into() }, "bad day".into()),
        ("3 21 12:x", SkyArgsError::BadTime { word: "12:x".into() }, "bad time format: 12:x".into()),
        (
            "3 21 +12EST",
            SkyArgsError::SolarTimeWithZone { word: "+12EST".into() },
            "bad time format: +12EST (solar time takes no time zone)".into(),
        ),
        (
            "3 21 12XYZ",
            SkyArgsError::UnknownZone { zone: "XYZ".into() },
            format!("unknown time zone: XYZ (known: {zones})"),
        ),
        ("3 21 12 -t", SkyArgsError::MissingValue { option: "-t".into() }, "-t needs a value".into()),
        (
            "3 21 12 -t x",
            SkyArgsError::NotANumber { option: "-t".into(), word: "x".into() },
            "-t: \"x\" is not a number".into(),
        ),
        ("3 21 12 foo", SkyArgsError::BadOption { option: "foo".into() }, "bad option: foo".into()),
        ("3 21 12 -q", SkyArgsError::UnknownOption { option: "-q".into() }, "unknown option: -q".into()),
        (
            "3 21 12 -g 1.5",
            SkyArgsError::GroundReflectance { value: 1.5 },
            "-g 1.5: a ground reflectance is in [0, 1]".into(),
        ),
        ("3 21 12 -b -1", SkyArgsError::NegativeLevel, "-b/-B and -r/-R take values ≥ 0".into()),
    ] {
        let args: Vec<String> = cmd.split_whitespace().map(str::to_string).collect();
        let e = gensky(&args).expect_err(cmd);
        assert_eq!(e, want, "{cmd}");
        assert_eq!(e.to_string(), text, "{cmd}");
    }
}
