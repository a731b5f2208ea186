//! The connected illuminance meter: irradiance anywhere — on a plane in the air, at points, or
//! on a surface — by connecting the stored samples to the meter (the light tracer's t = 1
//! strategy, with the meter as a sensor of cosine importance), plus the direct light of the
//! lights that store no emission vertex (docs/estimator.md §5).
//!
//! **Stored samples** (scattered vertices and the emission points y₀ of area lights). The
//! irradiance of target T (a cell of area A_T, or a point) is E_T = (1/A_T)∫_T ∫ L_i(p, ω)
//! cos θ_p dω dA_p. Each stored vertex x of light k with weight β is connected to n_c points p
//! drawn uniformly over the whole layout (uniform on the grid's area, so uniform within the
//! cell it lands in; for points, a uniform pick), and adds to p's target
//!
//! ```text
//! ΔE_T = (Φ_k/N_k) · β · f(x; ω_in → ω_p) · |cos θ_x| · cos θ_p / d² · V(x, p) · T / n_c
//! ```
//!
//! with T the number of targets: p lands in a given cell with probability 1/T, at density
//! 1/A_T there, so E[ΔE_T] is the cell's mean irradiance from x; for a point, δ(p) with
//! probability 1/T. f is the BSDF in light-flow order, or for an emission vertex the emission
//! factor f_e(ω_p)/cos θ (one-sided) — exactly the camera's [`crate::sensor::connect_to`].
//! θ_p is measured from the meter's normal; light from behind (cos θ_p ≤ 0) is not counted.
//! A vertex on a surface lying in the meter's own plane (a meter on a floor, the floor's
//! samples) contributes exactly 0 (both cosines vanish) and is skipped, which also keeps
//! rounding from producing fireflies there.
//!
//! **Direct light of point, directional and environment lights.** They store no emission
//! vertex (a delta position or direction, or a direction at infinity), so it is estimated at
//! the meter: per target, `direct_samples` uniform points of the cell (one for a point when
//! no environment is on: it is exact), each gathering from every such light that is on
//! I(ω)·cos θ_p/d²·V (point), E·cos θ_p·V (directional) or L(ω)·cos θ_p·V/p(ω) for one
//! direction ω drawn with the environment's own sampling (unbiased for ∫L cos θ_p V dω), relit.
//! Their standard error is the points' spread. Area lights need no such term: their emission
//! vertices above carry their direct light, with the emission distribution — the same
//! density per connection as sampling the light from the meter (both draw the pair (p, y₀)
//! uniformly over meter × light).
//!
//! Both parts are unbiased; every contribution scales with its light's Φ_k/N_k, so relighting,
//! switching lights off, merged and extended datasets stay exact. Random numbers come from
//! streams named by (seed, chunk) and (seed, target): a reading does not depend on the thread
//! count.

use super::layout::{MeterDraw, MeterLayout};
use super::tally::{Group, Reading, Scratch, tally_groups};
use crate::dataset::Sample;
use crate::film::SplatTarget;
use crate::light::Light;
use crate::math::{Rgb, Vec3};
use crate::sampling::RandomStream;
use crate::scene::Scene;
use crate::sensor::bidirectional::{RenderLights, visible};
use crate::sensor::{AsBatch, Connection, connect_to};
use rayon::prelude::*;

/// Stream keys of the two parts (the seed's other streams are the tracer's and the renderer's).
const SPLAT_STREAM: u64 = 0x6d65_7465_7273_706c;
const DIRECT_STREAM: u64 = 0x6d65_7465_7264_6972;

/// How the connected meter samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ConnectedSettings {
    /// n_c, meter points each stored sample connects to (≥ 1).
    pub connections: u32,
    /// Points per cell for the direct light of point and directional lights (≥ 2; points use
    /// one, which is exact).
    pub direct_samples: u32,
    /// Names the random streams.
    pub seed: u64,
}

impl Default for ConnectedSettings {
    fn default() -> Self {
        ConnectedSettings { connections: 1, direct_samples: 256, seed: 0 }
    }
}

/// Reads the meter `layout` from `groups.len()` batches (batch i is chunk i of the dataset, of
/// light and path count `groups[i]`) on all cores: the connected stored samples plus the direct
/// light of the point and directional `lights` that are on. The value per target is in W/m²
/// (and lux, by the scene's rule, [`Scene::photometry`]), with its standard error. `Ok(None)`
/// once `stop` said so: the batches check it themselves (the caller's `batch`); the direct
/// light asks it every [`DIRECT_STOP_DRAWS`] points of a target, so `direct_samples` never
/// delays an interrupt.
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
    let mut reading = tally_groups(
        layout.len(),
        scene.photometry,
        groups,
        batch,
        progress,
        |i, samples, flux, scratch| {
            splat_connected(scene, layout, settings, i as u64, samples, flux, scratch)
        },
    )?;
    let Some(direct) = direct_light(scene, lights, layout, settings, stop) else { return Ok(None) };
    reading.add_independent(&direct);
    Ok(Some(reading))
}

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
    out: &mut Scratch,
) {
    if flux == Rgb::ZERO || settings.connections == 0 {
        return;
    }
    let mut rng = RandomStream::new(settings.seed, &[SPLAT_STREAM, chunk]);
    let scale = layout.len() as f32 / settings.connections as f32;
    for s in samples {
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

/// β·f·|cos θ_x|·cos θ_p/d²·V of sample `s` (at `x`, geometric normal `n_x`) toward the drawn
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
    let c = connect_to::<false>(scene, s, Connection { pixel: d.target, point: d.position, weight: 0.0 })?;
    let cos_p = h / c.dist2.sqrt();
    Some(s.beta() * c.f * (c.cos_x.abs() * cos_p / c.dist2))
}

/// The direct light of the point, directional and environment lights that are on, per target.
fn direct_light(
    scene: &Scene,
    lights: &RenderLights,
    layout: &MeterLayout,
    settings: ConnectedSettings,
    stop: impl Fn() -> bool + Sync,
) -> Option<Reading> {
    let delta: Vec<usize> = (0..lights.lights().len())
        .filter(|&i| !matches!(scene.lights[lights.lights()[i].scene_index], Light::Area(_)))
        .collect();
    if delta.is_empty() {
        return Some(Reading::zero(layout.len()));
    }
    let environment =
        delta.iter().any(|&i| matches!(scene.lights[lights.lights()[i].scene_index], Light::Environment(_)));
    let m = if layout.is_point() && !environment { 1 } else { settings.direct_samples.max(2) };
    let per_target: Vec<([f64; 4], [f64; 4])> = (0..layout.len())
        .into_par_iter()
        .map(|t| {
            let mut rng = RandomStream::new(settings.seed, &[DIRECT_STREAM, t as u64]);
            let (mut sum, mut sq) = ([0.0f64; 4], [0.0f64; 4]);
            for k in 0..m {
                if k % DIRECT_STOP_DRAWS == 0 && stop() {
                    return None;
                }
                let d = layout.draw_in(t, rng.next_2d());
                let e = delta.iter().fold(Rgb::ZERO, |e, &i| e + direct_from(scene, lights, i, &d, &mut rng));
                let e = [e.x as f64, e.y as f64, e.z as f64];
                let x = [e[0], e[1], e[2], scene.photometry.lux(e)];
                for c in 0..4 {
                    sum[c] += x[c];
                    sq[c] += x[c] * x[c];
                }
            }
            let mf = m as f64;
            let mean = sum.map(|s| s / mf);
            let mut se = [0.0; 4];
            if m > 1 {
                for c in 0..4 {
                    se[c] = ((sq[c] - mf * mean[c] * mean[c]).max(0.0) / (mf - 1.0) / mf).sqrt();
                }
            }
            Some((mean, se))
        })
        .collect::<Option<_>>()?;
    let (value, std_error) = per_target.into_iter().unzip();
    Some(Reading { value, std_error })
}

/// The irradiance at `d` from light `i` of `lights` (a point, directional or environment
/// light; an environment's direction drawn from `rng`): what it sends (relit) times cos θ_p,
/// if unblocked.
#[inline]
fn direct_from(scene: &Scene, lights: &RenderLights, i: usize, d: &MeterDraw, rng: &mut RandomStream) -> Rgb {
    let lp = match &scene.lights[lights.lights()[i].scene_index] {
        Light::Environment(env) => {
            let (omega, pdf) = env.sample_direction(rng.next_2d());
            lights.from_environment(scene, i, omega, pdf)
        }
        _ => lights.toward(scene, i, Vec3::ZERO, None, d.position),
    };
    let Some(lp) = lp else { return Rgb::ZERO };
    let cos = d.normal.dot(lp.dir);
    if !(cos > 0.0) || !visible(scene, d.position, d.normal, lp.dir, lp.distance, None) {
        return Rgb::ZERO;
    }
    // `radiance` is divided by NEE's pick probability; here every light is gathered.
    lp.radiance * (lp.pick * cos)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::{Bsdf, Lambert, Material};
    use crate::scene::{MeshDesc, PointLightDesc, SceneDescription};
    use crate::sensor::IlluminanceMeter;
    use crate::sensor::meter::MeterPoint;

    /// A black floor at y = 0 and a point light "bulb" of intensity 3 at height 1.
    fn bulb_over_floor() -> Scene {
        let desc = SceneDescription {
            materials: vec![Material {
                name: "black".into(),
                bsdf: Bsdf::Lambert(Lambert::new(Rgb::ZERO).unwrap()),
                two_sided: false,
            }],
            meshes: vec![MeshDesc {
                name: "floor".into(),
                positions: vec![
                    Vec3::new(-5.0, 0.0, -5.0),
                    Vec3::new(-5.0, 0.0, 5.0),
                    Vec3::new(5.0, 0.0, 5.0),
                    Vec3::new(5.0, 0.0, -5.0),
                ],
                triangles: vec![[0, 1, 2], [0, 2, 3]],
                ..Default::default()
            }],
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
            ConnectedSettings { direct_samples: 256, ..Default::default() },
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
        let settings = ConnectedSettings { direct_samples: 1 << 20, ..Default::default() };
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
