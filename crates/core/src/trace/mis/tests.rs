//! The tracer's MIS records against a brute force: for random paths of a glossy Cornell box lit
//! by an area, a point and a directional light and an environment map, every record `trace_path` stores equals the
//! light-side sums of `docs/bidirectional.md` §4 computed from scratch from the path's vertices
//! (area densities of every strategy, multiplied out); records never change the samples; and
//! the densities of delta lobes are the ones the sampler draws with.

use super::*;
use crate::bsdf::{
    Lambert, ModifiedPhong, Plastic, RoughConductor, SmoothConductor, SmoothDielectric, ThinDielectric,
    TransportMode,
};
use crate::dataset::{Heuristic, LightVertexMis, MisRecord, Sample, Selection, TraceSettings, VcmClass};
use crate::math::{Rgb, Vec2};
use crate::sampling::RandomStream;
use crate::scene::{
    DirectionalLightDesc, EnvironmentLightDesc, EnvironmentRadiance, PointLightDesc, Scene, Source,
    cornell_box,
};
use crate::trace::{PathScratch, trace_block, trace_path};
use glam::DVec3;

/// The Cornell box with a Phong white, a GGX red wall, a point light, and a sun and an
/// environment map (a bright patch on a dim sky, rotated) shining in through the open front.
fn glossy_box() -> Scene {
    let mut d = cornell_box();
    d.materials[0].bsdf =
        Bsdf::ModifiedPhong(ModifiedPhong::new(Rgb::splat(0.4), Rgb::splat(0.45), 12.0).unwrap());
    d.materials[1].bsdf =
        Bsdf::RoughConductor(RoughConductor::new(0.3, Rgb::new(0.9, 0.5, 0.4), None).unwrap());
    d.materials[2].bsdf = Bsdf::Lambert(Lambert::new(Rgb::new(0.2, 0.8, 0.3)).unwrap());
    d.point_lights.push(PointLightDesc {
        name: "bulb".into(),
        position: Vec3::new(0.3, -0.2, 0.6),
        intensity: Rgb::splat(0.3),
        ..Default::default()
    });
    let sun = DVec3::new(0.3, -0.4, -1.0);
    d.directional_lights
        .push(DirectionalLightDesc::new("sun".into(), Source::default(), sun, Rgb::ONE).unwrap());
    let (width, height) = (8, 4);
    let mut texels = vec![Rgb::new(0.2, 0.3, 0.5); width * height];
    texels[width + 2] = Rgb::splat(20.0);
    d.environment_lights.push(EnvironmentLightDesc {
        name: "sky".into(),
        source: Source::default(),
        radiance: EnvironmentRadiance::Map { width, height, texels, scale: 1.0, file: None },
        to_world: glam::Mat3::from_axis_angle(Vec3::new(1.0, 0.5, 0.2).normalize(), 1.1),
        sky: None,
    });
    Scene::build(&d).unwrap()
}

/// The class bits removed: the four stored roots.
fn roots(r: MisRecord) -> [f64; 4] {
    let v: [u32; 4] = bytemuck::cast(r);
    v.map(|x| f32::from_bits(x & !(1 << 31)) as f64)
}

/// The record of vertex `i` of a chain of light vertices `x[0..=i]` (x₀ on the light, every
/// other vertex a stored, non-delta one with its triangle `prim[m]`), from scratch: the area
/// densities p→ and p← of every vertex, the terms of every strategy that takes vertices j..=i
/// from the camera side, summed by class (§4's invariant with the connection's factors a and
/// r set to 1), as roots.
fn brute_force(scene: &Scene, k: usize, x: &[Vec3], prim: &[u32], s: &TraceSettings) -> ([f64; 4], VcmClass) {
    let h = s.mis.unwrap();
    let light = &scene.lights[k];
    let i = x.len() - 1;
    let dir = |a: usize, b: usize| (x[b] - x[a]).normalize();
    let d2 = |a: usize, b: usize| (x[b] - x[a]).length_squared() as f64;
    let light_normal = match light {
        Light::Area(_) => scene.triangles[prim[0] as usize].normal(),
        _ => Vec3::ZERO,
    };
    // The direction light arrives at x_m from (x₁ of a sun: against the sun's direction).
    let incoming = |m: usize| match light {
        Light::Directional(l) if m == 1 => -l.direction,
        _ => dir(m, m - 1),
    };
    let infinite = matches!(light, Light::Directional(_) | Light::Environment(_));
    let environment = matches!(light, Light::Environment(_));
    let normal = |m: usize| if m == 0 { light_normal } else { scene.triangles[prim[m] as usize].normal() };
    let cos = |m: usize, w: Vec3| w.dot(normal(m)).abs() as f64;
    // An environment's x₀ is its direction (x[0] a point far along it).
    let (p0, _) = light.emission_pdfs(light_normal, if environment { -incoming(1) } else { Vec3::Z });
    let fwd = |m: usize| -> f64 {
        match m {
            0 => p0 as f64,
            1 => {
                let (_, second) = light.emission_pdfs(light_normal, -incoming(1));
                let g = if infinite { 1.0 } else { 1.0 / d2(0, 1) };
                second as f64 * cos(1, incoming(1)) * g
            }
            _ => {
                let v = m - 1;
                let n = scene.normals_at(prim[v], x[v]);
                let mat = scene.material(prim[v]);
                let p =
                    light_direction_pdf(mat, n, incoming(v), dir(v, m), s.directions, mat.bsdf.is_delta());
                p as f64 * cos(m, dir(m, v)) / d2(v, m)
            }
        }
    };
    // p←(x_m) for m < i − 1: the camera tracer at x_{m+1}, arriving from x_{m+2}; at i − 1 its
    // pdf r is left out, at i the whole density (a).
    let rev = |m: usize| -> f64 {
        if m == i {
            return 1.0;
        }
        // The camera side finds an environment's x₀ in solid angle: no conversion.
        let g = if m == 0 && environment { 1.0 } else { cos(m, dir(m, m + 1)) / d2(m, m + 1) };
        if m == i - 1 {
            return g;
        }
        let v = m + 1;
        let n = scene.normals_at(prim[v], x[v]);
        scene.material(prim[v]).pdf_world(n, dir(v, v + 1), dir(v, m)) as f64 * g
    };
    let term = |j: usize| h.mis((j..=i).map(|m| rev(m) / fwd(m)).product::<f64>());
    let class = |j: usize| match j {
        0 => VcmClass::Hit,
        1 => VcmClass::Nee,
        _ => VcmClass::Conn,
    };
    let first = if matches!(light, Light::Area(_) | Light::Environment(_)) { 0 } else { 1 };
    let mut vc = [0.0; 3];
    for j in first..i {
        vc[class(j) as usize] += term(j);
    }
    let root = |x: f64| if h == Heuristic::Power { x.sqrt() } else { x };
    ([root(term(i)), root(vc[0]), root(vc[1]), root(vc[2])], class(i))
}

#[test]
fn records_equal_the_brute_force_light_side_sums_of_every_stored_vertex() {
    let scene = glossy_box();
    let mut checked = [0usize; 3];
    let mut environment_records = 0;
    let mut worst = 0f64;
    let mut tight = 0;
    for (directions, heuristic) in [
        (Directions::Importance, Heuristic::Power),
        (Directions::Uniform, Heuristic::Power),
        (Directions::Importance, Heuristic::Balance),
    ] {
        let s = TraceSettings { directions, mis: Some(heuristic), rr_depth: 3, ..Default::default() };
        for k in 0..scene.lights.len() {
            let mut rng = RandomStream::new(11, &[k as u64, directions as u64, heuristic as u64]);
            let (mut out, mut records, mut stack) = (Vec::new(), Vec::new(), PathScratch::default());
            for _ in 0..300 {
                out.clear();
                records.clear();
                trace_path(&scene, k, &s, &mut rng, &mut out, &mut records, &mut stack);
                assert_eq!(records.len(), out.len());
                // x₀: the emission sample, the bulb; a sun's start point enters no density.
                let (mut x, mut prim) = match &scene.lights[k] {
                    Light::Area(_) => (vec![], vec![]),
                    Light::Point(l) => (vec![l.position], vec![0]),
                    Light::Directional(l) => (vec![l.centre], vec![0]),
                    // Far along the direction the first hit's light came from.
                    Light::Environment(_) => match out.first() {
                        Some(y1) => (vec![y1.position() + y1.from_dir() * 1e4], vec![0]),
                        None => continue,
                    },
                };
                for (sample, record) in out.iter().zip(&records) {
                    x.push(sample.position());
                    prim.push(sample.triangle());
                    let (want, class) = brute_force(&scene, k, &x, &prim, &s);
                    let got = roots(*record);
                    let state = LightVertexMis::from_record(*record, heuristic);
                    assert!(record.is_valid());
                    assert_eq!(state.class(), class, "light {k}, vertex {}", x.len() - 1);
                    let cosines: Vec<f32> = (1..x.len())
                        .flat_map(|m| {
                            let d = (x[m] - x[m - 1]).normalize();
                            let n = |v: usize| scene.triangles[prim[v] as usize].normal();
                            [
                                d.dot(n(m)).abs(),
                                if m > 1 || matches!(scene.lights[k], Light::Area(_)) {
                                    d.dot(n(m - 1)).abs()
                                } else {
                                    1.0
                                },
                            ]
                        })
                        .collect();
                    // The tracer's directions leave from offset ray origins (~2·10⁻⁵ m off the
                    // surface), the brute force's from the vertices: directions differ by about
                    // that over the segment's length, cosines by that relative to their size.
                    let min_cos = cosines.iter().fold(1f32, |a, &b| a.min(b)) as f64;
                    let min_d = (1..x.len()).map(|m| (x[m] - x[m - 1]).length()).fold(1f32, f32::min) as f64;
                    let tolerance = 1e-3 + 1e-4 / (min_cos * min_d);
                    tight += usize::from(tolerance < 2e-3);
                    for (g, w) in got.iter().zip(want) {
                        let err = (g - w).abs() / w.max(1e-30);
                        worst = worst.max(if w == 0.0 { *g } else { err / tolerance * 1e-3 });
                        assert!(
                            if w == 0.0 { *g == 0.0 } else { err < tolerance },
                            "light {k} ({directions:?}, {heuristic:?}), vertex {}: record {got:?}, brute force {want:?}",
                            x.len() - 1
                        );
                    }
                    checked[class as usize] += 1;
                    environment_records += usize::from(matches!(scene.lights[k], Light::Environment(_)));
                }
            }
        }
    }
    eprintln!(
        "records checked (y₀, y₁, deeper): {checked:?}; worst relative error {worst:.2e} (scaled to the tolerance at normal incidence, 1e-3)"
    );
    let total: usize = checked.iter().sum();
    eprintln!("{tight} of {total} within 2e-3");
    assert!(checked.iter().all(|&n| n > 100), "{checked:?}");
    assert!(environment_records > 100, "{environment_records} records of the environment's paths");
    assert!(tight * 4 > total * 3, "most vertices are compared within 2e-3: {tight} of {total}");
}

/// What a block stores does not depend on whether records are computed, for every strategy.
#[test]
fn records_change_no_sample_and_are_absent_without_mis() {
    let scene = glossy_box();
    for selection in [Selection::Single, Selection::Priority] {
        for directions in [Directions::Importance, Directions::Uniform] {
            let with = TraceSettings { selection, directions, ..Default::default() };
            let without = TraceSettings { mis: None, ..with };
            for k in 0..scene.lights.len() {
                let (a, b) = (
                    trace_block(&scene, &with, k, k as u32, 3, 500),
                    trace_block(&scene, &without, k, k as u32, 3, 500),
                );
                assert_eq!(a.samples, b.samples);
                assert_eq!((a.records.len(), b.records.len()), (a.samples.len(), 0));
                let emission = |c: &[Sample]| c.iter().filter(|s| s.is_emission()).count();
                let hit_class = a
                    .records
                    .iter()
                    .filter(|r| LightVertexMis::from_record(**r, Heuristic::Power).class() == VcmClass::Hit);
                assert_eq!(
                    hit_class.count(),
                    emission(&a.samples),
                    "the hit class marks exactly the emission samples"
                );
            }
        }
    }
}

/// The densities of delta lobes: `pdf_world_of` a delta event gives the probability
/// `sample_world` picked the lobe with, and for the reverse step the probability of the lobe
/// that leads back — for every BSDF with a delta lobe (smooth glass, mirror, thin sheet, and the
/// coating of a plastic, whose other lobe is diffuse). A BSDF whose delta lobe answered 0 here
/// gave the bidirectional estimator a zero reverse density, and its images came out 15–65% too
/// bright behind a thin pane (both strategies of such a path weighted 1).
#[test]
fn delta_lobe_probabilities_are_the_samplers_both_ways() {
    let glass = Material {
        name: "glass".into(),
        bsdf: Bsdf::SmoothDielectric(SmoothDielectric::new(1.5, 1.0, Rgb::ONE, Rgb::ONE).unwrap()),
        two_sided: false,
    };
    let mirror = Material {
        name: "mirror".into(),
        bsdf: Bsdf::SmoothConductor(SmoothConductor::new(Rgb::ONE, None).unwrap()),
        two_sided: true,
    };
    let thin = Material {
        name: "thin".into(),
        bsdf: Bsdf::ThinDielectric(ThinDielectric::new(2.4, 1.0, Rgb::ONE, Rgb::splat(0.7)).unwrap()),
        two_sided: true,
    };
    let plastic = Material {
        name: "plastic".into(),
        bsdf: Bsdf::Plastic(Plastic::new(Rgb::splat(0.4), Rgb::ONE, 1.5, 1.0, false).unwrap()),
        two_sided: true,
    };
    let n = SurfaceNormals::flat(Vec3::new(0.2, 1.0, -0.1).normalize());
    let mut rng = RandomStream::new(5, &[1]);
    let mut lobes = [0; 2];
    for _ in 0..2000 {
        let wi = crate::sampling::warp::square_to_uniform_sphere(rng.next_2d());
        for m in [&glass, &mirror, &thin, &plastic] {
            let Some(s) = m.sample_world(n, wi, rng.next_f32(), Vec2::ZERO, TransportMode::Importance) else {
                continue;
            };
            if !s.delta {
                assert!(matches!(m.bsdf, Bsdf::Plastic(_)), "{}: every lobe is a delta", m.name);
                continue;
            }
            assert!(s.pdf > 0.0, "{}: a delta event of probability 0", m.name);
            assert_eq!(m.pdf_world_of(n, wi, s.wo, true), s.pdf, "{}: forward", m.name);
            assert_eq!(
                light_direction_pdf(m, n, wi, s.wo, Directions::Uniform, s.delta),
                s.pdf,
                "delta: never uniform"
            );
            // The reverse: from s.wo, the lobe (reflection below F, refraction above) that
            // returns to wi, and the probability it is picked with.
            let back = [0.0, 1.0 - 1e-7]
                .into_iter()
                .filter_map(|u| m.sample_world(n, s.wo, u, Vec2::ZERO, TransportMode::Radiance))
                .find(|b| b.delta && b.wo.dot(wi) > 0.9999);
            let Some(back) = back else { panic!("{}: no lobe leads back from {} to {wi}", m.name, s.wo) };
            let rev = m.pdf_world_of(n, s.wo, wi, true);
            assert!(
                (rev - back.pdf).abs() <= 1e-5 * back.pdf.max(1e-3),
                "{}: reverse {rev} vs {}",
                m.name,
                back.pdf
            );
            lobes[(s.wo.dot(n.geometric) * wi.dot(n.geometric) < 0.0) as usize] += 1;
        }
    }
    assert!(lobes[0] > 100 && lobes[1] > 100, "reflections and refractions: {lobes:?}");
}

/// The uniform rule's density is 1/2π on the hemisphere light may leave into, zero below.
#[test]
fn uniform_directions_have_the_hemispheres_density() {
    let m =
        Material { name: "m".into(), bsdf: Bsdf::Lambert(Lambert::new(Rgb::ONE).unwrap()), two_sided: false };
    let n = SurfaceNormals::flat(Vec3::Y);
    let (wi, up, down) =
        (Vec3::new(0.3, 0.9, 0.1).normalize(), Vec3::new(-0.5, 0.5, 0.0).normalize(), -Vec3::Y);
    assert_eq!(
        light_direction_pdf(&m, n, wi, up, Directions::Uniform, false),
        crate::sampling::warp::UNIFORM_HEMISPHERE_PDF
    );
    assert_eq!(light_direction_pdf(&m, n, wi, down, Directions::Uniform, false), 0.0);
    assert_eq!(
        light_direction_pdf(&m, n, -wi, up, Directions::Uniform, false),
        0.0,
        "the back of a one-sided surface"
    );
    let cosine = light_direction_pdf(&m, n, wi, up, Directions::Importance, false);
    assert!((cosine - up.y * std::f32::consts::FRAC_1_PI).abs() < 1e-6);
}

/// A path emitted exactly along its light's surface (a cosine profile's density is 0 there)
/// still gets valid records: zero over zero is zero, never NaN.
#[test]
fn a_grazing_emission_gives_valid_records() {
    let scene = glossy_box();
    let light = &scene.lights[0];
    let Light::Area(area) = light else { panic!("the box's first light is its area light") };
    let normal = scene.triangles[area.triangles[0] as usize].normal();
    let along = normal.cross(Vec3::X).normalize();
    let emitter = emitter_densities(light, normal, along);
    for h in [Heuristic::Power, Heuristic::Balance] {
        let m = LightVertexMis::at_emission(emitter, along.dot(normal).abs(), h);
        for r in [m.after_hit(1.0, 0.5).record(), m.after_hit(0.0, 0.0).record()] {
            assert!(r.is_valid(), "{r:?}");
        }
    }
}
