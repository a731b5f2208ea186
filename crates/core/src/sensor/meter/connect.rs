//! The connected illuminance meter: irradiance anywhere — on a plane in the air, at points, or
//! on a surface — by connecting the stored scattered samples to the meter (the light tracer's
//! t = 1 strategy, with the meter as a sensor of cosine importance), plus every light's direct
//! light, estimated at the meter (docs/estimator.md §5).
//!
//! **Stored samples** (scattered vertices; not the emission points y₀ of area lights, below).
//! The irradiance of target T (a cell of area A_T, or a point) is
//! E_T = (1/A_T)∫_T ∫ L_i(p, ω) cos θ_p dω dA_p. Each stored scattered vertex x of light k with
//! weight β is connected to n_c points p drawn uniformly over the whole layout (uniform on the
//! grid's area, so uniform within the cell it lands in; for points, a uniform pick), and adds
//! to p's target
//!
//! ```text
//! ΔE_T = (Φ_k/N_k) · β · f(x; ω_in → ω_p) · |cos θ_x| · cos θ_p / d² · τ(x, p) · T / n_c
//! ```
//!
//! with T the number of targets: p lands in a given cell with probability 1/T, at density
//! 1/A_T there, so E[ΔE_T] is the cell's mean irradiance from x; for a point, δ(p) with
//! probability 1/T. f is the BSDF in light-flow order — exactly the camera's connection
//! (`connect_seen`'s). τ is the segment's transmittance (below: 1 or 0, but for window panes).
//! θ_p is measured from the meter's normal; light from behind (cos θ_p ≤ 0) is not counted.
//! A vertex on a surface lying in the meter's own plane (a meter on a floor, the floor's
//! samples) contributes exactly 0 (both cosines vanish) and is skipped, which also keeps
//! rounding from producing fireflies there.
//!
//! **Direct light, estimated at the meter, per target.** Point and directional lights store no
//! emission vertex (a delta position or direction), nor do environments (a direction at
//! infinity); area lights do, but connecting y₀ gives an error that falls only as
//! 1/√(light paths), where sampling the light from the target needs a few hundred shadow rays.
//! So every light's direct light is this term's. Point and directional lights:
//! `direct_samples` uniform points of the cell (256 by default; one for a point, which is
//! exact), each gathering from every such light that is on I(ω)·cos θ_p/d²·τ (point) or
//! E·cos θ_p·τ (directional), relit; their standard error is the points' spread. Environments
//! (a sky): a pilot learns where from the target the sky is seen and the fresh directions are
//! drawn from a defensive mixture of that guide and the environment's own sampling, as many as
//! a standard error of 0.5 % needs by default (`sky.rs`, which also shows why this is unbiased)
//! — through a small opening, directions drawn from the whole sky rarely pass. Area lights:
//! stratified points on the lights, drawn with their own position sampling, as many as a
//! standard error of 0.5 % needs by default (`area.rs`); the two sampled terms share their
//! sample budget (`budget.rs`). The estimates are independent and add, their errors in
//! quadrature with the connections'.
//!
//! **Invariant: stored emission vertices are not connected.** The area lights' direct term
//! counts every light path whose only segment toward the meter leaves the light straight
//! (y₀ → p, through panes or not); a connection from y₀ would count the same paths again.
//! Skipping y₀ leaves each path arriving at p to exactly one strategy — its direct segment to
//! the direct term, every longer path to the connection of its last scattered vertex — each
//! with weight 1, so the sum stays unbiased (no MIS is involved). The emission vertices still
//! count as the paths they start: a light's N_k and its chunks' statistics are unchanged.
//!
//! **Shadow rays through glazing.** τ is [`Scene::shadow_transmittance`]: 0 where a surface
//! blocks the segment, else the product of the straight-through transmittance T(θ) of the thin
//! dielectric panes it crosses (`ThinDielectric`: Radiance's `glass`, Mitsuba's
//! `thindielectric`; per channel, with the pane's internal reflections), so a meter behind a
//! window reads the sky, the sun and the outside surfaces through it. Past
//! [`crate::scene::MAX_PANES`] panes on one segment it counts as blocked (a bound on the work,
//! documented there). Mirrors, refracting dielectrics, opaque and masked surfaces keep the
//! ordinary visibility. Why this is unbiased and counts nothing twice: a pane does not deflect
//! what it transmits (its transmission is a Dirac delta at ω_o = −ω_i), so a light path whose
//! last segments cross panes on their way to p is the straight segment x → p itself, with the
//! panes' delta transmissions as its throughput — the very path the connection (or the direct
//! term) already samples, at the same density; τ is its missing factor, where a blocking V
//! scored such paths 0. No other part of the meter produces paths whose last segment crosses
//! a pane toward the meter: the light tracer stores no vertex on a delta surface (a path
//! passing a pane is stored at its next non-delta vertex, never at the pane), and the meter
//! gathers nothing but these connections and the direct term. Each path is therefore counted
//! by exactly one strategy, with weight 1 — no MIS is involved. (The cameras' estimators keep
//! the blocking V: their bidirectional weights assume it.)
//!
//! Both parts are unbiased; every contribution scales with its light's Φ_k/N_k, so relighting,
//! switching lights off, merged and extended datasets stay exact. Random numbers come from
//! streams named by (seed, chunk) and (seed, target): a reading does not depend on the thread
//! count.

use super::area::AreaLights;
use super::budget::{self, Moments};
use super::layout::{MeterDraw, MeterLayout};
use super::sky::Sky;
use super::tally::{self, Group, Reading, tally_groups};
use crate::dataset::Sample;
use crate::film::SplatTarget;
use crate::light::Light;
use crate::math::{Rgb, Vec3};
use crate::sampling::RandomStream;
use crate::scene::Scene;
use crate::sensor::bidirectional::{RenderLights, shadow_ray};
use crate::sensor::{AsBatch, Connection, connect_through_panes};
use rayon::prelude::*;

/// Stream keys of the two parts (the seed's other streams are the tracer's and the renderer's).
const SPLAT_STREAM: u64 = 0x6d65_7465_7273_706c;
const DIRECT_STREAM: u64 = 0x6d65_7465_7264_6972;

/// How the connected meter samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ConnectedSettings {
    /// n_c, meter points each stored sample connects to (≥ 1).
    pub connections: u32,
    /// `None` (the default): the direct light of point and directional lights from
    /// [`DEFAULT_DIRECT_POINTS`] points per cell, the environments' from as many guided
    /// directions as their pilot asks for (`sky.rs`), the area lights' from as many points on
    /// them as theirs asks for (`area.rs`). `Some(n)`: n points per cell (≥ 2; points use one,
    /// which is exact), exactly n guided directions per target for environments and n points on
    /// the area lights (n/2 strata of two).
    pub direct_samples: Option<u32>,
    /// Names the random streams.
    pub seed: u64,
}

impl Default for ConnectedSettings {
    fn default() -> Self {
        ConnectedSettings { connections: 1, direct_samples: None, seed: 0 }
    }
}

/// Reads the meter `layout` from `groups.len()` batches (batch i is chunk i of the dataset, of
/// light and path count `groups[i]`) on all cores: the connected stored scattered samples plus
/// the direct light of the `lights` that are on. The value per target is in W/m²
/// (and lux, by the scene's rule, [`Scene::photometry`]), with its standard error. `Ok(None)`
/// once `stop` said so: the batches check it themselves (the caller's `batch`); the direct
/// light asks it every [`DIRECT_STOP_DRAWS`] points or sky directions of a target (pilot
/// included), so no sample count delays an interrupt.
#[allow(clippy::too_many_arguments)]
pub fn read_connected<B: AsBatch, E: Send>(
    scene: &Scene,
    lights: &RenderLights,
    layout: &MeterLayout,
    settings: ConnectedSettings,
    groups: &[Group],
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
    stop: impl Fn() -> bool + Sync,
) -> Result<Option<Reading>, E> {
    let readings = read_connected_many(scene, lights, &[layout], settings, groups, batch, progress, stop)?;
    Ok(readings.map(|mut r| r.remove(0)))
}

/// [`read_connected`] for several meters in one pass over the batches (each batch fetched
/// once): one reading per layout, in their order, each the same bit for bit as that layout read
/// alone with the same settings — a chunk's connections to a layout draw from the stream of
/// (seed, chunk) whatever the other layouts, and each layout's direct light is its own.
#[allow(clippy::too_many_arguments)]
pub fn read_connected_many<B: AsBatch, E: Send>(
    scene: &Scene,
    lights: &RenderLights,
    layouts: &[&MeterLayout],
    settings: ConnectedSettings,
    groups: &[Group],
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
    stop: impl Fn() -> bool + Sync,
) -> Result<Option<Vec<Reading>>, E> {
    let lens: Vec<usize> = layouts.iter().map(|l| l.len()).collect();
    let (offsets, total) = tally::offsets(&lens);
    let reading =
        tally_groups(total, scene.photometry, groups, batch, progress, |i, samples, flux, scratch| {
            for (layout, &offset) in layouts.iter().zip(&offsets) {
                let row = &mut tally::Offset { row: &mut *scratch, offset };
                splat_connected(scene, layout, settings, i as u64, samples, flux, row)
            }
        })?;
    let mut readings = reading.split(&lens);
    for (reading, layout) in readings.iter_mut().zip(layouts) {
        let Some(direct) = direct_light(scene, lights, layout, settings, &stop) else { return Ok(None) };
        reading.add_independent(&direct);
    }
    Ok(Some(readings))
}

/// Points per cell for the direct light of point and directional lights by default.
pub const DEFAULT_DIRECT_POINTS: u32 = 256;

/// Direct-light points drawn between two questions to `stop` (a millisecond or so of one core).
pub const DIRECT_STOP_DRAWS: u32 = 1 << 10;

/// The connections of one chunk's samples (its light's flux per path `flux`) to the layout.
fn splat_connected(
    scene: &Scene,
    layout: &MeterLayout,
    settings: ConnectedSettings,
    chunk: u64,
    samples: &[Sample],
    flux: Rgb,
    out: &mut impl SplatTarget,
) {
    if flux == Rgb::ZERO || settings.connections == 0 {
        return;
    }
    let mut rng = RandomStream::new(settings.seed, &[SPLAT_STREAM, chunk]);
    let scale = layout.len() as f32 / settings.connections as f32;
    for s in samples {
        if s.is_emission() {
            continue; // an area light's direct light is the direct term's (`area.rs`)
        }
        let x = s.position();
        let n_x = scene.normal(s.triangle());
        for _ in 0..settings.connections {
            let d = layout.draw(rng.next_2d());
            if let Some(e) = connect_one(scene, layout, s, x, n_x, &d) {
                out.splat(d.target, flux * e * scale);
            }
        }
    }
}

/// β·f·|cos θ_x|·cos θ_p/d²·τ of sample `s` (at `x`, geometric normal `n_x`) toward the drawn
/// meter point `d`; `None` when it adds nothing.
#[inline]
fn connect_one(
    scene: &Scene,
    layout: &MeterLayout,
    s: &Sample,
    x: Vec3,
    n_x: Vec3,
    d: &MeterDraw,
) -> Option<Rgb> {
    let h = (x - d.position).dot(d.normal);
    if !(h > 0.0) {
        return None; // behind the measured side
    }
    if h <= layout.tolerance(d) && n_x.dot(d.normal).abs() > 1.0 - 1e-6 {
        return None; // on a surface in the meter's plane: both cosines are 0
    }
    let c = connect_through_panes(scene, s, Connection { pixel: d.target, point: d.position, weight: 0.0 })?;
    let cos_p = h / c.dist2.sqrt();
    Some(s.beta() * c.f * (c.cos_x.abs() * cos_p / c.dist2))
}

/// The direct light of the lights that are on, per target: the point and directional lights'
/// from `direct_samples` points of a cell (256 by default; one at a point, which is exact), the
/// environments' from their guided sampler (`sky.rs`), the area lights' from stratified points
/// on them (`area.rs`), the independent estimates added.
fn direct_light(
    scene: &Scene,
    lights: &RenderLights,
    layout: &MeterLayout,
    settings: ConnectedSettings,
    stop: impl Fn() -> bool + Sync,
) -> Option<Reading> {
    let delta: Vec<usize> = (0..lights.lights().len())
        .filter(|&i| {
            !matches!(scene.lights[lights.lights()[i].scene_index], Light::Area(_) | Light::Environment(_))
        })
        .collect();
    let sky = Sky::new(scene, lights);
    let area = AreaLights::new(scene, lights);
    if delta.is_empty() && sky.is_none() && area.is_none() {
        return Some(Reading::zero(layout.len()));
    }
    let m =
        if layout.is_point() { 1 } else { settings.direct_samples.unwrap_or(DEFAULT_DIRECT_POINTS).max(2) };
    let cap = budget::sample_cap(layout.len());
    let stop: &(dyn Fn() -> bool + Sync) = &stop;
    let per_target: Vec<([f64; 4], [f64; 4])> = (0..layout.len())
        .into_par_iter()
        .map(|t| {
            let (mut mean, mut se) = ([0.0f64; 4], [0.0f64; 4]);
            if !delta.is_empty() {
                let mut rng = RandomStream::new(settings.seed, &[DIRECT_STREAM, t as u64]);
                let mut moments = Moments::default();
                for k in 0..m {
                    if k % DIRECT_STOP_DRAWS == 0 && stop() {
                        return None;
                    }
                    let d = layout.draw_in(t, rng.next_2d());
                    let e = delta.iter().fold(Rgb::ZERO, |e, &i| e + direct_from(scene, lights, i, &d));
                    moments.add(e, &scene.photometry);
                }
                (mean, se) = moments.finish();
            }
            let mut add = |(v, s): ([f64; 4], [f64; 4])| {
                for c in 0..4 {
                    mean[c] += v[c];
                    se[c] = se[c].hypot(s[c]);
                }
            };
            if let Some(sky) = &sky {
                add(sky.target(layout, t, settings.direct_samples, cap, settings.seed, stop)?);
            }
            if let Some(area) = &area {
                add(area.target(layout, t, settings.direct_samples, cap, settings.seed, stop)?);
            }
            Some((mean, se))
        })
        .collect::<Option<_>>()?;
    let (value, std_error) = per_target.into_iter().unzip();
    Some(Reading { value, std_error })
}

/// The irradiance at `d` from light `i` of `lights` (a point or directional light): what it
/// sends (relit) times cos θ_p and the panes' transmittance τ, 0 if blocked.
#[inline]
fn direct_from(scene: &Scene, lights: &RenderLights, i: usize, d: &MeterDraw) -> Rgb {
    let Some(lp) = lights.toward(scene, i, Vec3::ZERO, None, d.position) else { return Rgb::ZERO };
    let cos = d.normal.dot(lp.dir);
    if !(cos > 0.0) {
        return Rgb::ZERO;
    }
    let ray = shadow_ray(d.position, d.normal, lp.dir, lp.distance, None);
    let Some(tau) = ray.and_then(|ray| scene.shadow_transmittance(&ray)) else { return Rgb::ZERO };
    // `radiance` is divided by NEE's pick probability; here every light is gathered.
    lp.radiance * tau * (lp.pick * cos)
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::bsdf::{Bsdf, Lambert, Material, SmoothConductor, ThinDielectric};
    use crate::scene::{MeshDesc, PointLightDesc, SceneDescription};
    use crate::sensor::IlluminanceMeter;
    use crate::sensor::meter::MeterPoint;

    /// A black floor at y = 0 and a point light "bulb" of intensity 3 at height 1.
    fn bulb_over_floor() -> Scene {
        bulb_over_floor_and(&[])
    }

    /// A horizontal 10 m square at height `y` of material `material`, centred on the y axis.
    fn square(y: f32, material: usize) -> MeshDesc {
        MeshDesc::square_at(format!("square at {y}"), y, material)
    }

    /// The pane materials of [`bulb_over_floor_and`]: 1 clear glass (n = 1.52), 2 tinted glass.
    fn pane(material: usize) -> ThinDielectric {
        let tint = if material == 2 { Rgb::new(0.9, 0.6, 0.3) } else { Rgb::ONE };
        ThinDielectric::new(1.52, 1.0, Rgb::ONE, tint).unwrap()
    }

    /// [`bulb_over_floor`] with horizontal squares at the heights and of the materials
    /// `sheets` gives: 0 black, 1 clear glass, 2 tinted glass, 3 a mirror.
    fn bulb_over_floor_and(sheets: &[(f32, usize)]) -> Scene {
        let m = |name: &str, bsdf| Material { name: name.into(), bsdf, two_sided: false };
        let mut meshes = vec![square(0.0, 0)];
        meshes.extend(sheets.iter().map(|&(y, material)| square(y, material)));
        let desc = SceneDescription {
            materials: vec![
                m("black", Bsdf::Lambert(Lambert::new(Rgb::ZERO).unwrap())),
                m("clear", Bsdf::ThinDielectric(pane(1))),
                m("tinted", Bsdf::ThinDielectric(pane(2))),
                m("mirror", Bsdf::SmoothConductor(SmoothConductor::new(Rgb::ONE, None).unwrap())),
            ],
            meshes,
            point_lights: vec![PointLightDesc {
                name: "bulb".into(),
                position: Vec3::new(0.0, 1.0, 0.0),
                intensity: Rgb::splat(3.0),
                ..Default::default()
            }],
            ..Default::default()
        };
        Scene::build(&desc).unwrap()
    }

    /// A black floor at y = 0 and a point light of intensity `i` at height 1: the samples carry
    /// nothing, so the reading is the direct light alone, I·cos θ/d², exact at points.
    #[test]
    fn point_light_direct_term_is_the_inverse_square_law() {
        let scene = bulb_over_floor();
        let power = Rgb::splat(3.0 * 4.0 * std::f32::consts::PI);
        let lights = RenderLights::new(&scene, &["bulb"], &[power / 100.0], &[100]);
        let points = MeterLayout::points(vec![
            MeterPoint::new(Vec3::new(0.5, 0.5, 0.0), Vec3::Y).unwrap(),
            MeterPoint::new(Vec3::new(0.5, 0.5, 0.0), Vec3::NEG_Y).unwrap(),
            MeterPoint::new(Vec3::new(0.0, 0.0, 0.0), Vec3::Y).unwrap(), // on the floor
        ])
        .unwrap();
        let groups = [Group { light: 0, paths: 100 }];
        let r = read_connected(
            &scene,
            &lights,
            &points,
            ConnectedSettings::default(),
            &groups,
            |_| Ok::<_, ()>(crate::sensor::OwnedBatch::default()),
            |_| {},
            || false,
        )
        .unwrap()
        .unwrap();
        let d2 = 0.5f64 * 0.5 + 0.5 * 0.5;
        let expected = 3.0 * (0.5 / d2.sqrt()) / d2;
        assert!((r.value[0][0] / expected - 1.0).abs() < 1e-5, "{} vs {expected}", r.value[0][0]);
        assert_eq!(r.value[1][0], 0.0, "light from behind the measured side");
        assert!((r.value[2][1] / 3.0 - 1.0).abs() < 1e-5, "on the floor, straight below: {}", r.value[2][1]);
        assert_eq!(r.std_error[0], [0.0; 4]);
        // A cell of a grid: its mean over the cell, with a spread-based error.
        let grid = MeterLayout::Grid(
            IlluminanceMeter::new(Vec3::new(-0.1, 0.5, -0.1), Vec3::Z * 0.2, Vec3::X * 0.2, 1, 1).unwrap(),
        );
        let g = read_connected(
            &scene,
            &lights,
            &grid,
            ConnectedSettings { direct_samples: Some(256), ..Default::default() },
            &groups,
            |_| Ok::<_, ()>(crate::sensor::OwnedBatch::default()),
            |_| {},
            || false,
        )
        .unwrap()
        .unwrap();
        // The cell's mean of I·h/d³ (h = 0.5), by a 200 × 200 midpoint rule.
        let k = 200;
        let mean = (0..k * k)
            .map(|n| {
                let (x, z) = (
                    -0.1 + 0.2 * ((n % k) as f64 + 0.5) / k as f64,
                    -0.1 + 0.2 * ((n / k) as f64 + 0.5) / k as f64,
                );
                let d2 = x * x + z * z + 0.25;
                3.0 * 0.5 / (d2 * d2.sqrt())
            })
            .sum::<f64>()
            / (k * k) as f64;
        let (v, se) = (g.value[0][0], g.std_error[0][0]);
        assert!(se > 0.0 && se < 0.01 * v, "{v} ± {se}");
        assert!((v - mean).abs() < 4.0 * se, "{v} ± {se} vs {mean}");
    }

    /// Reads meter `points` in `scene` lit by its bulb alone (no stored samples).
    fn read_bulb(scene: &Scene, points: &MeterLayout) -> Reading {
        let power = Rgb::splat(3.0 * 4.0 * std::f32::consts::PI);
        let lights = RenderLights::new(scene, &["bulb"], &[power / 100.0], &[100]);
        read_direct_only(scene, &lights, points, ConnectedSettings::default())
    }

    /// Reads `layout` in `scene` with `settings`: the direct light of `lights` alone (one light
    /// of 100 paths, no stored samples).
    pub(in crate::sensor::meter) fn read_direct_only(
        scene: &Scene,
        lights: &RenderLights,
        layout: &MeterLayout,
        settings: ConnectedSettings,
    ) -> Reading {
        read_connected(
            scene,
            lights,
            layout,
            settings,
            &[Group { light: 0, paths: 100 }],
            |_| Ok::<_, ()>(crate::sensor::OwnedBatch::default()),
            |_| {},
            || false,
        )
        .unwrap()
        .unwrap()
    }

    /// The bulb seen through horizontal panes between it (height 1) and meter points at height
    /// 0.5: each point reads I·cos θ/d² times the panes' straight-through T at θ (they are
    /// parallel to the meter, so θ is the meter's angle too), per channel, exactly (SE 0).
    /// Two panes multiply, a mirror blocks, MAX_PANES panes pass and one more blocks.
    #[test]
    fn the_point_light_is_seen_through_panes() {
        let xs = [0.0f32, 0.3, 0.5, 1.2];
        let points = MeterLayout::points(
            xs.iter().map(|&x| MeterPoint::new(Vec3::new(x, 0.5, 0.13), Vec3::Y).unwrap()).collect(),
        )
        .unwrap();
        // (I·cos θ/d², cos θ) at each point.
        let bare: Vec<(f32, f32)> = xs
            .iter()
            .map(|&x| {
                let d2 = x * x + 0.25 + 0.13 * 0.13;
                let cos = 0.5 / d2.sqrt();
                (3.0 * cos / d2, cos)
            })
            .collect();
        let expect = |what: &str, r: &Reading, through: &dyn Fn(f32) -> Rgb| {
            for (t, &(e, cos)) in bare.iter().enumerate() {
                let want = through(cos) * e;
                for c in 0..3 {
                    let got = r.value[t][c];
                    assert!(
                        (got - want[c] as f64).abs() <= 1e-5 * e as f64,
                        "{what} {t}.{c}: {got} vs {}",
                        want[c]
                    );
                }
                assert_eq!(r.std_error[t], [0.0; 4], "{what}");
            }
        };
        expect("no pane", &read_bulb(&bulb_over_floor(), &points), &|_| Rgb::ONE);
        let clear = read_bulb(&bulb_over_floor_and(&[(0.75, 1)]), &points);
        expect("clear", &clear, &|cos| pane(1).transmittance(cos));
        let ratio = clear.value[0][0] / bare[0].0 as f64;
        assert!(ratio > 0.91 && ratio < 0.92, "clear glass near normal incidence passes ≈ 0.918: {ratio}");
        expect("tinted", &read_bulb(&bulb_over_floor_and(&[(0.75, 2)]), &points), &|cos| {
            pane(2).transmittance(cos)
        });
        expect("two", &read_bulb(&bulb_over_floor_and(&[(0.6, 1), (0.8, 2)]), &points), &|cos| {
            pane(1).transmittance(cos) * pane(2).transmittance(cos)
        });
        for sheets in [&[(0.75, 3)][..], &[(0.6, 1), (0.8, 3)], &[(0.6, 3), (0.8, 1)], &[(0.6, 0), (0.8, 1)]]
        {
            let r = read_bulb(&bulb_over_floor_and(sheets), &points);
            assert!(r.value.iter().all(|v| *v == [0.0; 4]), "{sheets:?}: {:?}", r.value);
        }
        let stack = |n: usize| (0..n).map(|k| (0.55 + 0.4 * k as f32 / n as f32, 1)).collect::<Vec<_>>();
        let most = read_bulb(&bulb_over_floor_and(&stack(crate::scene::MAX_PANES)), &points);
        expect("MAX_PANES", &most, &|cos| pane(1).transmittance(cos).powf(crate::scene::MAX_PANES as f32));
        let more = read_bulb(&bulb_over_floor_and(&stack(crate::scene::MAX_PANES + 1)), &points);
        assert!(more.value.iter().all(|v| *v == [0.0; 4]), "past MAX_PANES: {:?}", more.value);
    }

    /// The direct light asks whether to stop every DIRECT_STOP_DRAWS points of a target, so a
    /// stop is seen whatever the points per cell are: asked for after the first question, it
    /// ends the reading with `None` at the second, DIRECT_STOP_DRAWS draws in, not 2^20.
    #[test]
    fn the_direct_light_sees_a_stop_within_a_target() {
        let scene = bulb_over_floor();
        let power = Rgb::splat(3.0 * 4.0 * std::f32::consts::PI);
        let lights = RenderLights::new(&scene, &["bulb"], &[power / 100.0], &[100]);
        let grid = MeterLayout::Grid(
            IlluminanceMeter::new(Vec3::new(-0.1, 0.5, -0.1), Vec3::Z * 0.2, Vec3::X * 0.2, 1, 1).unwrap(),
        );
        let asked = std::sync::atomic::AtomicU64::new(0);
        let stop = || asked.fetch_add(1, std::sync::atomic::Ordering::Relaxed) >= 1;
        let settings = ConnectedSettings { direct_samples: Some(1 << 20), ..Default::default() };
        let r = read_connected(
            &scene,
            &lights,
            &grid,
            settings,
            &[Group { light: 0, paths: 100 }],
            |_| Ok::<_, ()>(crate::sensor::OwnedBatch::default()),
            |_| {},
            stop,
        )
        .unwrap();
        assert!(r.is_none());
        assert_eq!(asked.into_inner(), 2);
    }
}
