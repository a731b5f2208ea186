//! Light sources beyond the isotropic point and the Lambertian area light: IES profiles, spot
//! lights, cosⁿ area lights, directional (sun) lights, and their Mitsuba XML extensions.
//!
//! Every flux check is statistical: per-path sums of Φ·β are independent, so their standard
//! error σ is measured and the result must be within 4σ of the closed form (and, where stated,
//! within a fixed relative band that the path count makes meaningful).

use opticks_testkit as common;

use common::*;

use opticks_core::bsdf::{Bsdf, Lambert, Material};
use opticks_core::light::{EmissionProfile, LUMENS_PER_WATT, Light};
use opticks_core::math::{Frame, Rgb, Vec3};
use opticks_core::sampling::RandomStream;
use opticks_core::scene::{
    AreaEmission, CameraDesc, CameraKind, DirectionalLightDesc, MeshDesc, PointLightDesc, Scene,
    SceneDescription,
};
use opticks_core::trace::{PathScratch, TraceSettings, trace_path};
use opticks_io::ies::load_ies;
use opticks_testkit::files::testdata;
use std::f64::consts::PI;
use std::path::Path;

fn black() -> Material {
    Material { name: "black".into(), bsdf: Bsdf::Lambert(Lambert::new(Rgb::ZERO).unwrap()), two_sided: true }
}

fn quad(name: &str, q: [Vec3; 4], emission: Option<Rgb>) -> MeshDesc {
    MeshDesc {
        name: name.into(),
        positions: q.to_vec(),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material: 0,
        emission: emission.map(AreaEmission::lambertian),
        ..Default::default()
    }
}

/// An icosphere of radius `radius` about the origin, normals pointing **inward**.
fn inward_icosphere(radius: f32, levels: u32) -> MeshDesc {
    turned_inside_out(icosphere("sphere", Vec3::ZERO, radius, levels, 0))
}

/// Per path, the flux (channel 0) its stored non-emission vertices carry, and where.
fn trace_fluxes(scene: &Scene, paths: usize, seed: u64, mut keep: impl FnMut(Vec3) -> bool) -> Vec<f64> {
    let phi = scene.lights[0].power().x as f64;
    let mut rng = RandomStream::new(seed, &[]);
    let (mut out, mut stack) = (Vec::new(), PathScratch::default());
    let settings = TraceSettings::default();
    (0..paths)
        .map(|_| {
            out.clear();
            trace_path(scene, 0, &settings, &mut rng, &mut out, &mut Vec::new(), &mut stack);
            out.iter()
                .filter(|s| !s.is_emission() && keep(s.position()))
                .map(|s| phi * s.beta[0] as f64)
                .sum::<f64>()
        })
        .collect()
}

/// A point light with `profile` inside a closed black sphere: the flux incident on the sphere,
/// measured through the stored samples, with its standard error.
fn sphere_flux(light: PointLightDesc, paths: usize, seed: u64) -> (f64, f64, f64) {
    let desc = SceneDescription {
        materials: vec![black()],
        meshes: vec![inward_icosphere(2.0, 3)],
        point_lights: vec![light],
        ..Default::default()
    };
    let scene = Scene::build(&desc).unwrap();
    let phi = scene.lights[0].power().x as f64;
    let (m, e) = mean_and_error(&trace_fluxes(&scene, paths, seed, |_| true));
    (phi, m, e)
}

fn check(name: &str, measured: f64, err: f64, expected: f64, rel: f64) {
    eprintln!(
        "{name}: {measured:.6} ± {err:.6} (4σ = {:.3} %), expected {expected:.6}, off by {:+.3} %",
        400.0 * err / expected,
        100.0 * (measured / expected - 1.0)
    );
    assert!(
        4.0 * err / expected < rel,
        "{name}: the 4σ band {} is wider than the tolerance {rel}",
        4.0 * err / expected
    );
    assert!((measured - expected).abs() < 4.0 * err, "{name}: {measured} ± {err} vs {expected}");
    assert!((measured / expected - 1.0).abs() < rel, "{name}: {measured} vs {expected}");
}

/// testdata/ies/symmetric-3.ies carries exactly 400π lm (1256.637 lm: 200 cd down, 100 cd
/// sideways, 0 up, bilinear): a white light of that profile has Φ = 400π/683 W per channel, and
/// the flux arriving on a closed sphere around it is that, within 0.5 %.
#[test]
fn ies_flux_on_closed_sphere() {
    let ies = load_ies(&testdata("ies/symmetric-3.ies")).unwrap();
    assert!((ies.rated_lumens().unwrap() as f64 / (400.0 * PI) - 1.0).abs() < 1e-6);
    let expected = 400.0 * PI / LUMENS_PER_WATT as f64;
    let light = PointLightDesc {
        name: "ies".into(),
        intensity: Rgb::ONE,
        profile: Some(EmissionProfile::Ies(ies.profile)),
        orientation: Some(Frame::from_normal(-Vec3::Y)),
        ..Default::default()
    };
    let (phi, m, e) = sphere_flux(light, 400_000, 1);
    assert!((phi / expected - 1.0).abs() < 1e-5, "Φ = {phi} W, expected {expected}");
    check("symmetric IES, sphere flux", m, e, expected, 0.005);

    // The asymmetric file (absolute photometry): the sphere flux equals its computed Φ.
    let ies = load_ies(&testdata("ies/asymmetric-wallwasher.ies")).unwrap();
    assert_eq!(ies.rated_lumens(), None);
    let light = PointLightDesc {
        name: "ww".into(),
        intensity: Rgb::ONE,
        profile: Some(EmissionProfile::Ies(ies.profile.clone())),
        orientation: Some(Frame { s: Vec3::X, t: Vec3::Z, n: -Vec3::Y }),
        ..Default::default()
    };
    let (phi, m, e) = sphere_flux(light, 400_000, 2);
    let lm = wallwasher_lumens(&ies.profile, 0.0, 180.0);
    eprintln!("asymmetric IES: Φ = {:.3} lm by the table, {lm:.3} lm by quadrature", phi * 683.0);
    assert!((phi * LUMENS_PER_WATT as f64 / lm - 1.0).abs() < 1e-4);
    check("asymmetric IES, sphere flux", m, e, phi, 0.005);
}

/// Lumens of testdata/ies/asymmetric-wallwasher.ies (bilateral: φ in [0°, 180°] mirrored; θ up
/// to 90°) between the horizontal angles `from`° and `to`° and their mirror images, by an
/// independent midpoint quadrature of the bilinear interpolant.
fn wallwasher_lumens(ies: &opticks_core::light::IesProfile, from: f64, to: f64) -> f64 {
    let (va, ha, cd) = (&ies.vertical_angles, &ies.horizontal_angles, &ies.candela);
    assert_eq!((ha[ha.len() - 1], va[va.len() - 1]), (180.0, 90.0), "bilateral, lower hemisphere");
    let lerp = |xs: &[f32], x: f64, f: &dyn Fn(usize) -> f64| -> f64 {
        let i = xs.iter().position(|&a| a as f64 > x).unwrap_or(xs.len() - 1).max(1);
        let t = (x - xs[i - 1] as f64) / (xs[i] - xs[i - 1]) as f64;
        f(i - 1) * (1.0 - t) + f(i) * t
    };
    let (nt, np) = (900, (2.0 * (to - from)).round() as usize);
    let mut lm = 0.0;
    for i in 0..nt {
        let th = (i as f64 + 0.5) / nt as f64 * 90.0;
        for j in 0..np {
            let ph = from + (j as f64 + 0.5) / np as f64 * (to - from);
            let c = lerp(ha, ph, &|h| lerp(va, th, &|v| cd[h * va.len() + v] as f64));
            lm += c * th.to_radians().sin();
        }
    }
    lm * 2.0 * (90f64.to_radians() / nt as f64) * ((to - from).to_radians() / np as f64)
}

/// A 1 cm² area light facing −y at the origin (counter-clockwise seen from below) inside a
/// closed black sphere, with `profile`, radiance `radiance` and horizontal-0° `tangent`.
fn ies_panel_in_sphere(profile: EmissionProfile, radiance: f32, tangent: Option<Vec3>) -> Scene {
    let s = 0.005;
    let panel = MeshDesc {
        emission: Some(AreaEmission {
            profile: Some(profile),
            tangent,
            ..AreaEmission::lambertian(Rgb::splat(radiance))
        }),
        ..quad(
            "panel",
            [Vec3::new(-s, 0.0, -s), Vec3::new(s, 0.0, -s), Vec3::new(s, 0.0, s), Vec3::new(-s, 0.0, s)],
            None,
        )
    };
    let desc = SceneDescription {
        materials: vec![black()],
        meshes: vec![panel, inward_icosphere(2.0, 3)],
        ..Default::default()
    };
    Scene::build(&desc).unwrap()
}

/// An area light with testdata/ies/symmetric-3.ies emits the file's flux into its front
/// hemisphere, 2π·(200 − 200/π) = 400π − 400 lm per unit radiance·area (the 400 lm above 90° are
/// cut: the light is one-sided), and a closed sphere receives it within 0.5 %; with a power
/// given, the radiance follows so that Φ is that power.
#[test]
fn ies_area_light_flux_on_closed_sphere() {
    let ies = load_ies(&testdata("ies/symmetric-3.ies")).unwrap();
    let expected = (400.0 * PI - 400.0) / LUMENS_PER_WATT as f64;
    let scene = ies_panel_in_sphere(EmissionProfile::Ies(ies.profile.clone()), 1e4, None);
    let phi = scene.lights[0].power().x as f64;
    assert!((phi / expected - 1.0).abs() < 1e-5, "Φ = {phi} W, expected {expected}");
    let (m, e) = mean_and_error(&trace_fluxes(&scene, 400_000, 31, |_| true));
    check("symmetric IES area light, sphere flux", m, e, expected, 0.005);

    let mut desc = SceneDescription {
        materials: vec![black()],
        meshes: vec![MeshDesc {
            emission: Some(AreaEmission {
                power: Some(Rgb::new(1.0, 2.0, 3.0)),
                profile: Some(EmissionProfile::Ies(ies.profile)),
                ..AreaEmission::lambertian(Rgb::ONE)
            }),
            ..quad("p", [Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Z, Vec3::Z], None)
        }],
        ..Default::default()
    };
    let scene = Scene::build(&desc).unwrap();
    let p = scene.lights[0].power();
    assert!((p - Rgb::new(1.0, 2.0, 3.0)).abs().max_element() < 1e-5, "Φ = {p}");
    fn emission(d: &mut SceneDescription) -> &mut AreaEmission {
        d.meshes[0].emission.as_mut().unwrap()
    }
    emission(&mut desc).power = Some(Rgb::new(1.0, -1.0, 1.0));
    let e = Scene::build(&desc).unwrap_err().to_string();
    assert!(e.contains("'p'") && e.contains("power"), "{e}");
    emission(&mut desc).power = None;
    emission(&mut desc).tangent = Some(Vec3::ZERO);
    let e = Scene::build(&desc).unwrap_err().to_string();
    assert!(e.contains("'p'") && e.contains("tangent"), "{e}");
}

/// An area light with the asymmetric wall washer: its Φ is the table's integral, and the lobe
/// points along the tangent: the flux reaching the sphere on the +x side vs the −x side matches
/// the quadrature of φ ∈ [−90°, 90°] vs [90°, 270°] for tangent +x, and the two swap for
/// tangent −x. The sensor's factor for emitters seen directly uses the same frame.
#[test]
fn ies_area_light_lobe_follows_tangent() {
    let ies = load_ies(&testdata("ies/asymmetric-wallwasher.ies")).unwrap();
    let (front, back) =
        (wallwasher_lumens(&ies.profile, 0.0, 90.0), wallwasher_lumens(&ies.profile, 90.0, 180.0));
    let total = (front + back) / LUMENS_PER_WATT as f64;
    eprintln!("wall washer: {front:.2} lm towards φ = 0°, {back:.2} lm away");
    for (tangent, seed) in [(Vec3::X, 41), (-Vec3::X, 42)] {
        let scene = ies_panel_in_sphere(EmissionProfile::Ies(ies.profile.clone()), 1e4, Some(tangent));
        let phi = scene.lights[0].power().x as f64;
        assert!((phi / total - 1.0).abs() < 1e-4, "Φ = {phi} W, quadrature {total}");
        let plus = mean_and_error(&trace_fluxes(&scene, 400_000, seed, |p| p.x > 0.0));
        let minus = mean_and_error(&trace_fluxes(&scene, 400_000, seed + 10, |p| p.x < 0.0));
        let (want_plus, want_minus) = if tangent.x > 0.0 { (front, back) } else { (back, front) };
        let w = |lm: f64| lm / LUMENS_PER_WATT as f64;
        check(&format!("tangent {tangent}: flux into x > 0"), plus.0, plus.1, w(want_plus), 0.01);
        check(&format!("tangent {tangent}: flux into x < 0"), minus.0, minus.1, w(want_minus), 0.01);

        // Seen directly at θ = 40° on the tangent's side (φ = 0°) vs the opposite side (φ = 180°):
        // L_e·A/Φ = candela/683/Φ/cos θ (radiance·area = 1 here), from the file's grid nodes.
        let (c, s) = (40f32.to_radians().cos(), 40f32.to_radians().sin());
        let cd = |h: usize| ies.profile.candela[h * ies.profile.vertical_angles.len() + 4] as f64;
        assert_eq!(ies.profile.vertical_angles[4], 40.0);
        for (side, h) in [(1.0f32, 0), (-1.0, ies.profile.horizontal_angles.len() - 1)] {
            let dir = Vec3::new(side * tangent.x * s, -c, 0.0);
            let got = scene.lights[0].emitted_fraction(-Vec3::Y, dir) as f64;
            let want = cd(h) / LUMENS_PER_WATT as f64 / phi / c as f64;
            assert!((got / want - 1.0).abs() < 1e-3, "side {side}: {got} vs {want}");
        }
    }
}

/// Mitsuba's spot: Φ = I·2π·(1 − (sin γ − sin β)/(γ − β)); the sphere receives it.
#[test]
fn spot_power_matches_closed_form() {
    let (i, g, b) = (2.0f64, 30f64.to_radians(), 20f64.to_radians());
    let light = PointLightDesc {
        name: "spot".into(),
        intensity: Rgb::splat(i as f32),
        profile: Some(EmissionProfile::Spot { cutoff_angle: g as f32, beam_width: b as f32 }),
        orientation: Some(Frame::from_normal(Vec3::new(0.3, -1.0, 0.2).normalize())),
        ..Default::default()
    };
    let expected = i * 2.0 * PI * (1.0 - (g.sin() - b.sin()) / (g - b));
    let (phi, m, e) = sphere_flux(light, 300_000, 3);
    assert!((phi / expected - 1.0).abs() < 1e-5, "Φ = {phi}, closed form {expected}");
    check("spot, sphere flux", m, e, expected, 0.005);
}

/// A small cosⁿ emitter (n = 8) facing down at height h: the illuminance of floor patches
/// below (at 0, 0.3 and 0.6 m off-axis) matches E = Φ·(n+1)/(2π)·cosⁿθ·cos θ/d² averaged over the patch.
#[test]
fn cos_power_area_light_illuminance() {
    let (n, h, a, le) = (8.0f32, 1.0f32, 0.02f32, 50.0f32);
    let s = 0.5 * a;
    // Counter-clockwise seen from below: normal −y.
    let emitter = MeshDesc {
        emission: Some(AreaEmission {
            profile: Some(EmissionProfile::CosinePower { exponent: n }),
            ..AreaEmission::lambertian(Rgb::splat(le))
        }),
        ..quad(
            "lamp",
            [Vec3::new(-s, h, -s), Vec3::new(s, h, -s), Vec3::new(s, h, s), Vec3::new(-s, h, s)],
            None,
        )
    };
    let f = 20.0;
    let floor = quad(
        "floor",
        [Vec3::new(-f, 0.0, -f), Vec3::new(-f, 0.0, f), Vec3::new(f, 0.0, f), Vec3::new(f, 0.0, -f)],
        None,
    );
    let desc =
        SceneDescription { materials: vec![black()], meshes: vec![emitter, floor], ..Default::default() };
    let scene = Scene::build(&desc).unwrap();
    let Light::Area(l) = &scene.lights[0] else { panic!() };
    assert!(l.profile.eval(Vec3::Z) > 0.0 && scene.lights[0].emitted_fraction(-Vec3::Y, -Vec3::Y) > 0.0);
    let phi = scene.lights[0].power().x as f64;
    let expected_phi = (le * a * a) as f64 * 2.0 * PI / (n as f64 + 1.0);
    assert!((phi / expected_phi - 1.0).abs() < 1e-5, "Φ = {phi}, expected {expected_phi}");
    // L_e·A/Φ = f_e/cos θ = (n+1)/(2π)·cos^(n−1)θ.
    let d = Vec3::new(0.6, -0.8, 0.0);
    let ef = scene.lights[0].emitted_fraction(-Vec3::Y, d) as f64;
    let want = (n as f64 + 1.0) / (2.0 * PI) * 0.8f64.powf(n as f64 - 1.0);
    assert!((ef / want - 1.0).abs() < 1e-4, "emitted fraction {ef} vs {want}");
    let half = 0.05f32;
    for x0 in [0.0f32, 0.3, 0.6] {
        let inside = |p: Vec3| p.y.abs() < 1e-4 && (p.x - x0).abs() < half && p.z.abs() < half;
        let fluxes = trace_fluxes(&scene, 8_000_000, 10 + (x0 * 10.0) as u64, inside);
        let (m, e) = mean_and_error(&fluxes);
        let area = (2.0 * half as f64).powi(2);
        // Analytic illuminance averaged over the patch (40×40 midpoints).
        let k = 40;
        let mut avg = 0.0;
        for i in 0..k {
            for j in 0..k {
                let x = x0 as f64 - half as f64 + (i as f64 + 0.5) / k as f64 * 2.0 * half as f64;
                let z = -(half as f64) + (j as f64 + 0.5) / k as f64 * 2.0 * half as f64;
                let d2 = x * x + z * z + (h as f64).powi(2);
                let c = h as f64 / d2.sqrt();
                avg += phi * (n as f64 + 1.0) / (2.0 * PI) * c.powf(n as f64) * c / d2;
            }
        }
        avg /= (k * k) as f64;
        check(&format!("cos^8 emitter, illuminance at x = {x0}"), m / area, e / area, avg, 0.03);
    }
}

/// A directional light of irradiance E: a patch of a plane perpendicular to it receives E·area,
/// a plane tilted by 60° E·cos 60°; Φ = E·π·r² with r the scene's bounding radius.
#[test]
fn directional_irradiance_on_plane() {
    let e_irr = 3.0f32;
    let f = 2.0f32;
    let plane = quad(
        "plane",
        [Vec3::new(-f, 0.0, -f), Vec3::new(-f, 0.0, f), Vec3::new(f, 0.0, f), Vec3::new(f, 0.0, -f)],
        None,
    );
    for (dir, factor) in [(-Vec3::Y, 1.0f64), (Vec3::new(60f32.to_radians().sin(), -0.5, 0.0), 0.5)] {
        let desc = SceneDescription {
            materials: vec![black()],
            meshes: vec![plane.clone()],
            directional_lights: vec![DirectionalLightDesc {
                name: "sun".into(),
                direction: dir,
                irradiance: Rgb::splat(e_irr),
                ..Default::default()
            }],
            ..Default::default()
        };
        let scene = Scene::build(&desc).unwrap();
        let r = (2.0f64 * 4.0 * 4.0).sqrt() / 2.0; // half the bounding box's diagonal
        let phi = scene.lights[0].power().x as f64;
        assert!((phi / (e_irr as f64 * PI * r * r) - 1.0).abs() < 1e-5, "Φ = {phi}");
        let inside = |p: Vec3| p.y.abs() < 1e-4 && p.x.abs() < 0.5 && p.z.abs() < 0.5;
        let (m, err) = mean_and_error(&trace_fluxes(&scene, 4_000_000, 5, inside));
        check(&format!("directional {dir}: irradiance"), m, err, e_irr as f64 * factor, 0.015);
    }
    // A directional light is invisible and starts no surface vertex.
    let bad = SceneDescription {
        materials: vec![black()],
        meshes: vec![plane],
        directional_lights: vec![DirectionalLightDesc {
            name: "sun".into(),
            direction: Vec3::ZERO,
            ..Default::default()
        }],
        ..Default::default()
    };
    assert!(Scene::build(&bad).unwrap_err().to_string().contains("direction"));
}

/// Impossible parameters are errors that name the light.
#[test]
fn impossible_light_parameters_are_errors() {
    let base = SceneDescription {
        materials: vec![black()],
        meshes: vec![inward_icosphere(1.0, 0)],
        ..Default::default()
    };
    let with = |l: PointLightDesc| {
        let mut d = base.clone();
        d.point_lights.push(PointLightDesc { name: "bad".into(), ..l });
        Scene::build(&d).map(|_| ()).unwrap_err().to_string()
    };
    let e = with(PointLightDesc { power: Some(Rgb::splat(-1.0)), ..Default::default() });
    assert!(e.contains("'bad'") && e.contains("power"), "{e}");
    let e = with(PointLightDesc { power: Some(Rgb::splat(f32::NAN)), ..Default::default() });
    assert!(e.contains("power"), "{e}");
    let e = with(PointLightDesc {
        profile: Some(EmissionProfile::Spot { cutoff_angle: 0.0, beam_width: 0.0 }),
        ..Default::default()
    });
    assert!(e.contains("cutoff"), "{e}");
    let e = with(PointLightDesc {
        profile: Some(EmissionProfile::CosinePower { exponent: -2.0 }),
        ..Default::default()
    });
    assert!(e.contains("exponent"), "{e}");
    let e = with(PointLightDesc { intensity: Rgb::splat(f32::NAN), ..Default::default() });
    assert!(e.contains("emission"), "{e}");
    let e = with(PointLightDesc {
        orientation: Some(Frame { s: Vec3::X, t: Vec3::X, n: Vec3::Z }),
        ..Default::default()
    });
    assert!(e.contains("orthonormal"), "{e}");
}

/// Malformed IES files on disk: the error names the file and the line.
#[test]
fn malformed_ies_files_name_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("missing-tilt.ies", "IESNA:LM-63-2002\n[TEST] x\n1 1000 1 3 1 1 2 0 0 0\n", ":3: no TILT= line"),
        (
            "truncated.ies",
            "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 90",
            ":5: the file ends before the vertical angle 3",
        ),
        (
            "negative.ies",
            "TILT=NONE\n1 1000 1 2 1 1 2 0 0 0\n1 1 10\n0 90\n0\n5\n-1\n",
            ":7: candela value 2 of horizontal angle 1 is negative",
        ),
        ("words.ies", "TILT=NONE\n1 lots 1 2 1 1 2 0 0 0\n", ":2: lumens per lamp: \"lots\" is not a number"),
        (
            "counts.ies",
            "TILT=NONE\n1 1000 1 -3 1 1 2 0 0 0\n",
            ":2: number of vertical angles must be a whole number",
        ),
        (
            "few.ies",
            "TILT=NONE\n1 1000 1 2 2 1 2 0 0 0\n1 1 10\n0 90\n0 180\n1 1 1\n",
            "the file ends before the candela value 2 of horizontal angle 2",
        ),
    ];
    for (name, text, want) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let e = load_ies(&path).unwrap_err().to_string();
        assert!(e.contains(name) && e.contains(want), "{name}: {e}\nwant: {want}");
    }
    let e = load_ies(&dir.path().join("nope.ies")).unwrap_err().to_string();
    assert!(e.contains("nope.ies") && e.contains("cannot read"), "{e}");
}

/// Writes `xml` to `path` and loads it.
fn load_xml(path: &Path, xml: &str) -> Result<opticks_io::LoadedScene, opticks_io::SceneFileError> {
    std::fs::write(path, xml).unwrap();
    opticks_io::load_scene(path)
}

/// The Mitsuba extensions: spot, directional, ies (file relative to the XML) and the area
/// emitter's `exponent`.
#[test]
fn mitsuba_light_extensions() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(testdata("ies/symmetric-3.ies"), dir.path().join("lamp.ies")).unwrap();
    let xml = r#"<scene version="3.0.0">
  <emitter type="spot" id="spot">
    <transform name="to_world"><lookat origin="0, 2, 0" target="0, 0, 0" up="0, 0, 1"/></transform>
    <rgb name="intensity" value="2"/><float name="cutoff_angle" value="30"/><float name="beam_width" value="20"/>
  </emitter>
  <emitter type="directional" id="sun"><vector name="direction" x="0" y="-1" z="0"/><rgb name="irradiance" value="3"/></emitter>
  <emitter type="ies" id="lamp">
    <string name="filename" value="lamp.ies"/>
    <transform name="to_world"><lookat origin="1, 2, 0" target="1, 0, 0" up="0, 0, 1"/></transform>
    <float name="lumens" value="683"/>
  </emitter>
  <shape type="rectangle" id="panel">
    <emitter type="area"><rgb name="radiance" value="1"/><float name="exponent" value="4"/></emitter>
  </shape>
</scene>"#;
    let path = dir.path().join("scene.xml");
    let loaded = load_xml(&path, xml).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let d = &loaded.description;
    assert_eq!(d.point_lights.len(), 2);
    assert_eq!(d.directional_lights.len(), 1);
    assert_eq!(
        d.meshes[0].emission.as_ref().unwrap().profile,
        Some(EmissionProfile::CosinePower { exponent: 4.0 })
    );
    let scene = Scene::build(d).unwrap();
    let spot = &scene.lights[scene.light_index("spot").unwrap()];
    let Light::Point(p) = spot else { panic!() };
    assert!(
        (p.frame.n - -Vec3::Y).length() < 1e-6 && (p.position - Vec3::new(0.0, 2.0, 0.0)).length() < 1e-6
    );
    let (g, b) = (30f64.to_radians(), 20f64.to_radians());
    let want = 2.0 * 2.0 * PI * (1.0 - (g.sin() - b.sin()) / (g - b));
    assert!((spot.power().x as f64 / want - 1.0).abs() < 1e-5);
    let lamp = &scene.lights[scene.light_index("lamp").unwrap()];
    assert!((lamp.power() - Rgb::ONE).abs().max_element() < 1e-5, "683 lm white = 1 W: {}", lamp.power());
    let panel = &scene.lights[scene.light_index("panel").unwrap()];
    assert!((panel.power().x as f64 / (4.0 * 2.0 * PI / 5.0) - 1.0).abs() < 1e-5, "{}", panel.power());

    for (body, want) in [
        (
            r#"<emitter type="spot"><float name="cutoff_angle" value="0"/></emitter>"#,
            "spot cutoff angle 0° must be in",
        ),
        (
            r#"<emitter type="spot"><float name="cutoff_angle" value="10"/><float name="beam_width" value="20"/></emitter>"#,
            "beam width 20° must be in",
        ),
        (
            r#"<emitter type="ies"><string name="filename" value="missing.ies"/></emitter>"#,
            "cannot read the IES file",
        ),
        (
            r#"<emitter type="ies"><string name="filename" value="lamp.ies"/><rgb name="power" value="-1"/></emitter>"#,
            "power [-1.0, -1.0, -1.0] W must be finite and non-negative",
        ),
        (
            r#"<emitter type="directional"><vector name="direction" x="0" y="0" z="0"/></emitter>"#,
            "<vector name=\"direction\">: direction [0.0, 0.0, 0.0] is zero or not finite",
        ),
        (
            r#"<shape type="rectangle"><emitter type="area"><float name="exponent" value="-1"/></emitter></shape>"#,
            "exponent -1 must be in",
        ),
        (r#"<emitter type="spot"><float name="cutoff_angle" value="nan"/></emitter>"#, "not a finite number"),
    ] {
        let e =
            load_xml(&path, &format!("<scene version=\"3.0.0\">\n{body}\n</scene>")).unwrap_err().to_string();
        assert!(e.contains("scene.xml:2") && e.contains(want), "{body}: {e}\nwant: {want}");
    }
}

/// The Mitsuba area emitter's extensions: an IES `filename` (Φ = the file's front-hemisphere
/// flux by default, a warning when that differs from the file's rated lumens), a `tangent`, and
/// `power` or `lumens`; bad values are errors naming the line.
#[test]
fn mitsuba_area_light_ies_tangent_power() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(testdata("ies/symmetric-3.ies"), dir.path().join("lamp.ies")).unwrap();
    std::fs::copy(testdata("ies/asymmetric-wallwasher.ies"), dir.path().join("ww.ies")).unwrap();
    let xml = r#"<scene version="3.0.0">
  <shape type="rectangle" id="lamp">
    <emitter type="area"><string name="filename" value="lamp.ies"/></emitter>
  </shape>
  <shape type="rectangle" id="washer">
    <transform name="to_world"><translate y="3"/></transform>
    <emitter type="area">
      <string name="filename" value="ww.ies"/><vector name="tangent" x="0" y="2" z="0"/>
      <rgb name="radiance" value="1, 0.5, 0.25"/><float name="scale" value="3"/><float name="lumens" value="683"/>
    </emitter>
  </shape>
  <shape type="rectangle" id="plain">
    <transform name="to_world"><translate y="6"/></transform>
    <emitter type="area"><rgb name="power" value="3"/></emitter>
  </shape>
  <shape type="rectangle" id="focused">
    <transform name="to_world"><translate y="9"/></transform>
    <emitter type="area"><float name="exponent" value="4"/><float name="lumens" value="1366"/></emitter>
  </shape>
</scene>"#;
    let path = dir.path().join("scene.xml");
    let loaded = load_xml(&path, xml).unwrap();
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    assert!(loaded.warnings[0].to_string().contains("front hemisphere"), "{:?}", loaded.warnings);
    let scene = Scene::build(&loaded.description).unwrap();
    let light = |name: &str| &scene.lights[scene.light_index(name).unwrap()];
    let lamp = light("lamp").power();
    let want = ((400.0 * PI - 400.0) / LUMENS_PER_WATT as f64) as f32;
    assert!((lamp - Rgb::splat(want)).abs().max_element() < 1e-5 * want, "{lamp} vs {want}");
    let Light::Area(washer) = light("washer") else { panic!() };
    assert_eq!(washer.tangent, Vec3::Y);
    let y = opticks_core::math::luminance(light("washer").power());
    assert!((y - 1.0).abs() < 1e-5, "683 lm = luminance 1 W: {}", light("washer").power());
    let p = light("washer").power();
    assert!((p.x / p.y - 2.0).abs() < 1e-5 && (p.y / p.z - 2.0).abs() < 1e-5, "keeps the colour: {p}");
    assert!((light("plain").power() - Rgb::splat(3.0)).abs().max_element() < 1e-5);
    assert!((light("focused").power() - Rgb::splat(2.0)).abs().max_element() < 1e-5);

    for (emitter, want) in [
        (
            r#"<vector name="tangent" x="0" y="0" z="0"/>"#,
            "tangent [0.0, 0.0, 0.0] must be finite and non-zero",
        ),
        (
            r#"<float name="exponent" value="2"/><string name="filename" value="lamp.ies"/>"#,
            "either `exponent` or `filename`",
        ),
        (r#"<rgb name="power" value="1"/><float name="lumens" value="1"/>"#, "either `power` or `lumens`"),
        (r#"<float name="lumens" value="-5"/>"#, "lumens -5 must be finite and non-negative"),
        (r#"<rgb name="power" value="-1"/>"#, "power [-1.0, -1.0, -1.0] W must be finite and non-negative"),
        (
            r#"<string name="filename" value="lamp.ies"/><float name="scale" value="-1"/>"#,
            "<float name=\"scale\">: emission [-1.0, -1.0, -1.0] must be finite and non-negative",
        ),
        (r#"<string name="filename" value="none.ies"/>"#, "cannot read the IES file"),
        (r#"<rgb name="radiance" value="0"/><float name="lumens" value="5"/>"#, "non-zero luminance"),
    ] {
        let body = format!("<shape type=\"rectangle\"><emitter type=\"area\">{emitter}</emitter></shape>");
        let e =
            load_xml(&path, &format!("<scene version=\"3.0.0\">\n{body}\n</scene>")).unwrap_err().to_string();
        assert!(e.contains("scene.xml:2") && e.contains(want), "{body}: {e}\nwant: {want}");
    }
}

/// The sensor's emission-vertex factor f_e(ω_c)/cos θ: a cosⁿ panel (n = 3) seen by a camera at
/// 60° from its normal has radiance e·cos²60° = e/4; a Lambertian one (no profile) e.
#[test]
fn camera_sees_profiled_emitter_radiance() {
    let (e, theta) = (2.0f32, 60f32.to_radians());
    let s = 0.2;
    let panel = quad(
        "panel",
        [Vec3::new(-s, -s, 0.0), Vec3::new(s, -s, 0.0), Vec3::new(s, s, 0.0), Vec3::new(-s, s, 0.0)],
        Some(Rgb::splat(e)),
    );
    for (profile, expected) in
        [(Some(EmissionProfile::CosinePower { exponent: 3.0 }), e as f64 * 0.25), (None, e as f64)]
    {
        let desc = SceneDescription {
            materials: vec![black()],
            meshes: vec![MeshDesc {
                emission: Some(AreaEmission {
                    profile: profile.clone(),
                    ..AreaEmission::lambertian(Rgb::splat(e))
                }),
                ..panel.clone()
            }],
            camera: Some(CameraDesc {
                eye: 2.0 * Vec3::new(theta.sin(), 0.0, theta.cos()),
                target: Vec3::ZERO,
                up: Vec3::Y,
                fov_x_degrees: 2.0,
                width: 8,
                height: 8,
                kind: CameraKind::Perspective,
                film: Default::default(),
            }),
            ..Default::default()
        };
        let scene = Scene::build(&desc).unwrap();
        let film = common::trace_and_render(&scene, &common::camera(&scene), 1_000_000, 21);
        let m = film.mean()[0];
        eprintln!("{profile:?}: mean radiance {m:.5}, expected {expected:.5}");
        assert!((m / expected - 1.0).abs() < 0.01, "{profile:?}: {m} vs {expected}");
    }
}

/// A light's shape hash covers its emission distribution (profile, orientation), not its power.
#[test]
fn light_shape_hash_covers_profile_not_power() {
    let shape = |l: PointLightDesc| {
        let desc = SceneDescription {
            materials: vec![black()],
            meshes: vec![inward_icosphere(1.0, 0)],
            point_lights: vec![PointLightDesc { name: "l".into(), ..l }],
            ..Default::default()
        };
        Scene::build(&desc).unwrap().light_shapes[0]
    };
    let spot = |g: f32, i: f32| PointLightDesc {
        intensity: Rgb::splat(i),
        profile: Some(EmissionProfile::Spot { cutoff_angle: g, beam_width: 0.5 * g }),
        ..Default::default()
    };
    assert_eq!(shape(spot(0.5, 1.0)), shape(spot(0.5, 7.0)), "power is not part of the shape");
    assert_eq!(shape(spot(0.5, 1.0)), shape(PointLightDesc { power: Some(Rgb::ONE), ..spot(0.5, 1.0) }));
    assert_ne!(shape(spot(0.5, 1.0)), shape(spot(0.6, 1.0)), "the cutoff is");
    assert_ne!(
        shape(spot(0.5, 1.0)),
        shape(PointLightDesc { orientation: Some(Frame::from_normal(Vec3::X)), ..spot(0.5, 1.0) }),
        "the orientation is"
    );
    assert_ne!(shape(spot(0.5, 1.0)), shape(PointLightDesc::default()), "spot vs isotropic");
}

/// An area light's shape hash covers its tangent when the profile depends on φ (IES), not its
/// power; a Lambertian one ignores the tangent (so existing datasets keep their hashes).
#[test]
fn area_light_shape_hash_covers_tangent_of_ies_only() {
    let ies = load_ies(&testdata("ies/asymmetric-wallwasher.ies")).unwrap();
    let shape = |profile: Option<EmissionProfile>, tangent: Option<Vec3>, power: Option<Rgb>| {
        let panel = MeshDesc {
            emission: Some(AreaEmission { profile, tangent, power, ..AreaEmission::lambertian(Rgb::ONE) }),
            ..quad("p", [Vec3::ZERO, Vec3::Z, Vec3::X + Vec3::Z, Vec3::X], None)
        };
        let desc = SceneDescription { materials: vec![black()], meshes: vec![panel], ..Default::default() };
        Scene::build(&desc).unwrap().light_shapes[0]
    };
    let ies = Some(EmissionProfile::Ies(ies.profile));
    assert_ne!(shape(ies.clone(), None, None), shape(ies.clone(), Some(Vec3::Z), None), "the tangent is");
    assert_eq!(shape(ies.clone(), None, None), shape(ies.clone(), Some(Vec3::X * 2.0), None), "unit");
    assert_eq!(shape(ies.clone(), None, None), shape(ies, None, Some(Rgb::splat(5.0))), "power is not");
    assert_eq!(shape(None, None, None), shape(None, Some(Vec3::Z), None), "Lambertian: no tangent");
}

/// The VRML writer writes spot and directional lights and cosⁿ emitters in the extension, and
/// refuses what it cannot express (an IES table) instead of dropping it.
#[test]
fn vrml_writer_round_trips_spots_suns_and_refuses_ies() {
    use opticks_io::scene_formats::vrml::{load_str, writer::write_vrml};
    let spot = EmissionProfile::Spot { cutoff_angle: 0.5, beam_width: 0.4 };
    let mut emitter = inward_icosphere(1.0, 0);
    emitter.emission = Some(AreaEmission {
        profile: Some(EmissionProfile::CosinePower { exponent: 7.5 }),
        ..AreaEmission::lambertian(Rgb::splat(2.0))
    });
    let mut desc = SceneDescription {
        materials: vec![black()],
        meshes: vec![emitter],
        point_lights: vec![
            PointLightDesc { name: "bulb".into(), power: Some(Rgb::splat(4.0)), ..Default::default() },
            PointLightDesc {
                name: "spot".into(),
                position: Vec3::new(0.0, 1.0, 0.0),
                power: Some(Rgb::new(1.0, 2.0, 3.0)),
                profile: Some(spot.clone()),
                orientation: Some(Frame::from_normal(Vec3::NEG_Y)),
                ..Default::default()
            },
        ],
        directional_lights: vec![DirectionalLightDesc {
            name: "sun".into(),
            direction: Vec3::new(0.6, -0.8, 0.0),
            irradiance: Rgb::new(5.0, 4.0, 3.0),
            ..Default::default()
        }],
        ..Default::default()
    };
    let mut out = Vec::new();
    write_vrml(&desc, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let i = (4.0 / (4.0 * std::f32::consts::PI)).to_string();
    assert!(text.contains(&format!("intensity {i} {i} {i}")), "power written as intensity Φ/4π");
    let back = load_str(&text, std::path::Path::new("w.wrl")).unwrap();
    assert!(back.warnings.is_empty(), "{:?}", back.warnings);
    let d = &back.description;
    assert_eq!(
        (d.point_lights[1].profile.as_ref(), d.point_lights[1].power),
        (Some(&spot), Some(Rgb::new(1.0, 2.0, 3.0)))
    );
    assert_eq!(d.point_lights[1].orientation.unwrap().n, Vec3::NEG_Y);
    assert_eq!(d.point_lights[1].position, Vec3::new(0.0, 1.0, 0.0));
    assert_eq!(d.directional_lights.len(), 1);
    assert_eq!(
        (d.directional_lights[0].direction, d.directional_lights[0].irradiance),
        (Vec3::new(0.6, -0.8, 0.0), Rgb::new(5.0, 4.0, 3.0))
    );
    let e = d.meshes[0].emission.as_ref().unwrap();
    assert_eq!(e.profile, Some(EmissionProfile::CosinePower { exponent: 7.5 }));
    assert_eq!(e.radiance, Rgb::splat(2.0));
    let ies = load_ies(&testdata("ies/symmetric-3.ies")).unwrap();
    desc.point_lights[1].profile = Some(EmissionProfile::Ies(ies.profile));
    let e = write_vrml(&desc, &mut Vec::new()).unwrap_err().to_string();
    assert!(e.contains("spot") && e.contains("profile"), "{e}");
}

/// A VRML97 `SpotLight` (color × intensity W/sr, beamWidth, cutOffAngle) emits the closed-form
/// power of the core's spot, measured on an enclosing sphere: the loader's parameters arrive.
#[test]
fn vrml_spot_light_power_matches_closed_form() {
    let (g, b) = (0.6f64, 0.3f64);
    let text = format!(
        "#VRML V2.0 utf8\nTransform {{ rotation 1 0 0 0.7 children SpotLight {{ location 0.1 0 0 direction 0 0 -1 \
         color 1 0.5 0.25 intensity 0.8 beamWidth {b} cutOffAngle {g} }} }}"
    );
    let loaded = opticks_io::scene_formats::vrml::load_str(&text, std::path::Path::new("s.wrl")).unwrap();
    let light = loaded.description.point_lights[0].clone();
    let expected = 0.8 * 2.0 * PI * (1.0 - (g.sin() - b.sin()) / (g - b));
    let (phi, m, e) = sphere_flux(light, 300_000, 9);
    assert!((phi / expected - 1.0).abs() < 1e-5, "Φ = {phi}, closed form {expected}");
    check("VRML SpotLight, sphere flux", m, e, expected, 0.005);
}
