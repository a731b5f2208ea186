//! Tests of environment lights: the lookup against Mitsuba 3.9's `envmap` (numbers printed by
//! `testdata/mitsuba/envmap/eval_points.py`), the exact ∫L dω and power against quadrature,
//! χ² of the direction sampling against its pdf, the emission weights' mean, and what a map
//! or a frame cannot be.
#![allow(clippy::excessive_precision)] // the reference numbers as Mitsuba's script printed them

use super::*;
use crate::bsdf::chi2::Chi2Test;
use crate::sampling::RandomStream;

/// The 5 × 4 map of `testdata/mitsuba/envmap/eval_points.py`.
fn test_map() -> Vec<Rgb> {
    let mut t = Vec::new();
    for j in 0..4 {
        for i in 0..5 {
            t.push(Rgb::new((1 + i + 10 * j) as f32, (2 + 3 * i) as f32, 0.5 + j as f32));
        }
    }
    t
}

/// A 32 × 16 map with a bright sun-like patch and a dim sky, as the end-to-end test's.
fn sun_map() -> LatLong {
    let (w, h) = (32, 16);
    let mut t = vec![Rgb::new(0.2, 0.3, 0.5); w * h];
    for j in 3..5 {
        for i in 6..8 {
            t[j * w + i] = Rgb::new(40.0, 35.0, 30.0);
        }
    }
    t[15 * w + 31] = Rgb::new(0.0, 3.0, 0.0);
    LatLong::new(w, h, &t, 1.5).unwrap()
}

fn light(radiance: EnvRadiance, to_world: Mat3) -> EnvironmentLight {
    EnvironmentLight::new("env".into(), radiance, to_world, (Vec3::new(0.5, -1.0, 2.0), 3.0)).unwrap()
}

/// Mitsuba's `to_world` of the reference: rotate(axis (1, 2, 3)/√14, 40°), its rows.
fn mitsuba_rotation() -> Mat3 {
    Mat3::from_cols_array_2d(&[
        [0.782755554, -0.481954396, 0.393717766],
        [0.548798859, 0.832888901, -0.071525536],
        [-0.293451071, 0.272058874, 0.916444480],
    ])
    .transpose()
}

/// L(ω) is Mitsuba 3.9's `envmap` eval, to f32 rounding: the lat-long convention, the
/// bilinear texel-centred, periodic-in-u and corner-aligned, clamped-in-v lookup and the
/// inverse of `to_world` (numbers printed by `testdata/mitsuba/envmap/eval_points.py`).
#[test]
fn lookup_matches_mitsuba() {
    let map = LatLong::new(5, 4, &test_map(), 1.0).unwrap();
    let env = light(EnvRadiance::Map(map), mitsuba_rotation());
    let reference: [([f32; 3], [f32; 3]); 9] = [
        ([0.000000000, 1.000000000, 0.000000000], [7.247424, 3.940602, 1.060056]),
        ([0.000000000, -1.000000000, 0.000000000], [28.546310, 11.440601, 2.939944]),
        ([1.000000000, 0.000000000, 0.000000000], [21.923050, 5.362579, 2.480219]),
        ([0.000000000, 0.000000000, -1.000000000], [19.644726, 5.040770, 2.263113]),
        ([0.303045763, 0.505076272, -0.808122036], [15.654890, 2.534256, 1.947680]),
        ([-0.952579344, 0.136082763, 0.272165527], [12.679063, 12.175807, 1.328713]),
        ([0.050702013, -0.912636228, 0.405616101], [25.784573, 10.157330, 2.706546]),
        ([0.904534034, 0.301511345, 0.301511345], [18.259548, 5.828717, 2.098331]),
        ([-0.201773309, -0.201773309, -0.958423217], [21.184776, 7.872682, 2.322721]),
    ];
    for (d, want) in reference {
        let got = env.radiance(Vec3::from_array(d));
        let want = Rgb::from_array(want);
        assert!(
            (got - want).abs().max_element() <= 2e-4 * want.max_element(),
            "{d:?}: {got} vs Mitsuba {want}"
        );
    }
    // The identity frame: (1, 0, 0) is u = ¼, v = ½ (by hand: 16.75, 4.25, 2); +y is the top
    // row at u = atan2(0, −0)/2π = ½, column 2.
    let map = LatLong::new(5, 4, &test_map(), 2.0).unwrap();
    let env = light(EnvRadiance::Map(map), Mat3::IDENTITY);
    assert!((env.radiance(Vec3::X) - 2.0 * Rgb::new(16.75, 4.25, 2.0)).abs().max_element() < 1e-4);
    assert!((env.radiance(Vec3::Y) - 2.0 * Rgb::new(3.0, 8.0, 0.5)).abs().max_element() < 1e-4);
}

/// ∫L dω, computed cell by cell in closed form, against a fine midpoint quadrature of L over
/// (φ, θ); and Φ = π r² ∫L dω. A 1 × 1 map (padded as Mitsuba pads it) is a constant.
#[test]
fn integral_and_power_are_exact() {
    for (map, to_world) in
        [(LatLong::new(5, 4, &test_map(), 1.0).unwrap(), mitsuba_rotation()), (sun_map(), Mat3::IDENTITY)]
    {
        let env = light(EnvRadiance::Map(map.clone()), to_world);
        let (nphi, ntheta) = (2048, 1024);
        let mut sum = glam::DVec3::ZERO;
        for j in 0..ntheta {
            let theta = (j as f64 + 0.5) * PI64 / ntheta as f64;
            for i in 0..nphi {
                let phi = (i as f64 + 0.5) * 2.0 * PI64 / nphi as f64;
                let (u, v) = ((phi / (2.0 * PI64)) as f32, (theta / PI64) as f32);
                sum += map.eval_uv(u, v).as_dvec3() * theta.sin();
            }
        }
        let quadrature = sum * (2.0 * PI64 / nphi as f64) * (PI64 / ntheta as f64);
        let exact = map.integral().as_dvec3();
        assert!(((exact - quadrature) / quadrature).abs().max_element() < 2e-3, "{exact} vs {quadrature}");
        let power = env.power().as_dvec3();
        let want = exact * (PI64 * 9.0);
        assert!(((power - want) / want).abs().max_element() < 1e-6);
    }
    let one = LatLong::new(1, 1, &[Rgb::new(1.0, 2.0, 3.0)], 1.0).unwrap();
    assert_eq!(one.size(), (2, 3));
    let want = Rgb::new(1.0, 2.0, 3.0) * (4.0 * std::f32::consts::PI);
    assert!((one.integral() - want).abs().max_element() < 1e-5 * want.max_element());
    let constant = light(EnvRadiance::Constant(Rgb::new(1.0, 2.0, 3.0)), Mat3::IDENTITY);
    assert!(
        (constant.power() - light(EnvRadiance::Map(one), Mat3::IDENTITY).power()).abs().max_element() < 1e-3
    );
}

/// The irradiance facing the pole, cell by cell in closed form, against a fine midpoint
/// quadrature of L(ω)·cos θ over the world hemisphere around [`EnvironmentLight::pole`] — a
/// map whose horizon falls inside a row of cells (4 rows: θ = 0, π/3, 2π/3, π) and one whose
/// horizon is a row boundary; a constant and a uniform map give π·L.
#[test]
fn pole_irradiance_is_exact() {
    for (map, to_world) in
        [(LatLong::new(5, 4, &test_map(), 1.0).unwrap(), mitsuba_rotation()), (sun_map(), Mat3::IDENTITY)]
    {
        let env = light(EnvRadiance::Map(map), to_world);
        let frame = Frame::from_normal(env.pole());
        let (nphi, ntheta) = (2048, 1024);
        let mut sum = glam::DVec3::ZERO;
        for j in 0..ntheta {
            let theta = (j as f64 + 0.5) * 0.5 * PI64 / ntheta as f64;
            for i in 0..nphi {
                let phi = (i as f64 + 0.5) * 2.0 * PI64 / nphi as f64;
                let (st, ct) = (theta.sin() as f32, theta.cos() as f32);
                let d = frame.s * (st * phi.cos() as f32) + frame.t * (st * phi.sin() as f32) + frame.n * ct;
                sum += env.radiance(d.normalize()).as_dvec3() * (theta.sin() * theta.cos());
            }
        }
        let quadrature = sum * (2.0 * PI64 / nphi as f64) * (0.5 * PI64 / ntheta as f64);
        let exact = env.pole_irradiance().as_dvec3();
        assert!(((exact - quadrature) / quadrature).abs().max_element() < 2e-3, "{exact} vs {quadrature}");
    }
    let c = Rgb::new(1.0, 2.0, 3.0);
    let want = c * std::f32::consts::PI;
    let uniform = LatLong::new(8, 9, &[c; 72], 1.0).unwrap();
    assert!((uniform.pole_irradiance() - want).abs().max_element() < 1e-5 * want.max_element());
    let constant = light(EnvRadiance::Constant(c), Mat3::IDENTITY);
    assert!((constant.pole_irradiance() - want).abs().max_element() < 1e-6 * want.max_element());
}

/// χ² of the map's direction sampling against its pdf (which the harness also integrates to
/// 1 over the sphere), for a map with a sun and a rotated frame, and for a constant.
#[test]
fn chi2_sampling_matches_pdf() {
    let rotated = light(EnvRadiance::Map(sun_map()), mitsuba_rotation());
    let small = light(EnvRadiance::Map(LatLong::new(5, 4, &test_map(), 1.0).unwrap()), Mat3::IDENTITY);
    let constant = light(EnvRadiance::Constant(Rgb::ONE), Mat3::IDENTITY);
    for (k, env) in [rotated, small, constant].iter().enumerate() {
        Chi2Test::new(Vec3::Y, 900 + k as u64)
            .run(|_, u| Some(env.sample_direction(u)), |w| env.direction_pdf(w))
            .assert_ok(&format!("environment {k}"));
    }
}

/// Emission: the start lies outside the bounding sphere and travels along −ω toward it, within
/// the disk of radius r; the weight is 1 for a constant and has mean 1 per channel for a map
/// (within 5 standard errors, measured), and pdf(ω) of the sample is `emission_pdfs`'s.
#[test]
fn emission_weights_have_mean_one() {
    let centre = Vec3::new(0.5, -1.0, 2.0);
    let constant = light(EnvRadiance::Constant(Rgb::new(0.3, 0.0, 2.0)), Mat3::IDENTITY);
    let mut rng = RandomStream::new(7, &[]);
    for _ in 0..1000 {
        let e = constant.sample_emission(rng.next_2d(), rng.next_2d());
        assert_eq!(e.weight, Rgb::new(1.0, 0.0, 1.0));
        let to_centre = centre - e.origin;
        assert!(to_centre.length() > 3.0);
        let along = to_centre.dot(e.dir);
        assert!(along > 3.0 && (to_centre - along * e.dir).length() <= 3.0 + 1e-3);
    }
    let env = light(EnvRadiance::Map(sun_map()), mitsuba_rotation());
    let n = 400_000;
    let (mut sum, mut sq) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
    for _ in 0..n {
        let e = env.sample_emission(rng.next_2d(), rng.next_2d());
        let w = e.weight.as_dvec3();
        sum += w;
        sq += w * w;
        let pdf = env.direction_pdf(-e.dir);
        assert!(pdf > 0.0);
    }
    let mean = sum / n as f64;
    let se = ((sq / n as f64 - mean * mean) / n as f64).max(glam::DVec3::ZERO).sqrt();
    for c in 0..3 {
        assert!((mean[c] - 1.0).abs() < 5.0 * se[c] + 1e-9, "channel {c}: mean {} ± {}", mean[c], se[c]);
    }
}

/// What a map or frame cannot be.
#[test]
fn bad_maps_and_frames_are_refused() {
    let err = |r: Result<LatLong, LightError>| r.unwrap_err().to_string();
    assert!(err(LatLong::new(0, 4, &[], 1.0)).contains("no texels"));
    assert!(err(LatLong::new(2, 2, &[Rgb::ONE; 3], 1.0)).contains("has 3 texels"));
    let mut t = vec![Rgb::ONE; 4];
    t[3] = Rgb::new(0.0, -1.0, 0.0);
    assert!(err(LatLong::new(2, 2, &t, 1.0)).contains("texel (1, 1)"));
    t[3] = Rgb::new(f32::NAN, 0.0, 0.0);
    assert!(err(LatLong::new(2, 2, &t, 1.0)).contains("texel (1, 1)"));
    assert!(err(LatLong::new(2, 2, &[Rgb::ONE; 4], -1.0)).contains("scale"));
    // The size is bounded by the texels given (the reader bounds those), whatever it claims.
    assert!(err(LatLong::new(1 << 14, 1 << 14, &[], 1.0)).contains("16384 × 16384 but has 0 texels"));
    assert!(err(LatLong::new(usize::MAX, 2, &[Rgb::ONE; 4], 1.0)).contains("but has 4 texels"));
    let scaled = EnvironmentLight::new(
        "e".into(),
        EnvRadiance::Constant(Rgb::ONE),
        Mat3::from_diagonal(Vec3::splat(2.0)),
        (Vec3::ZERO, 1.0),
    );
    assert!(matches!(scaled, Err(LightError::EnvironmentFrame(_))));
    let sheared = EnvironmentLight::new(
        "e".into(),
        EnvRadiance::Constant(Rgb::ONE),
        Mat3::from_cols(Vec3::X, Vec3::new(0.1, 1.0, 0.0), Vec3::Z),
        (Vec3::ZERO, 1.0),
    );
    assert!(matches!(sheared, Err(LightError::EnvironmentFrame(_))));
    // A mirrored frame maps directions as well as a rotation (Mitsuba's `<scale x="-1"/>`).
    let mirrored = Mat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0));
    let map = LatLong::new(5, 4, &test_map(), 1.0).unwrap();
    let m = light(EnvRadiance::Map(map.clone()), mirrored);
    let plain = light(EnvRadiance::Map(map), Mat3::IDENTITY);
    let d = Vec3::new(0.3, 0.5, -0.8).normalize();
    assert_eq!(m.radiance(d), plain.radiance(Vec3::new(-d.x, d.y, d.z)));
    let black = LatLong::new(2, 2, &[Rgb::ZERO; 4], 1.0).unwrap();
    let env = light(EnvRadiance::Map(black), Mat3::IDENTITY);
    assert_eq!(env.power(), Rgb::ZERO);
    assert!(env.direction_pdf(Vec3::X) > 0.0);
}
