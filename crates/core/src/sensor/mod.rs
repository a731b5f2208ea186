//! Sensors: connecting stored samples to a measuring device (the thesis's "visualisation",
//! ch. 4 and §6.1.5). Every camera model lives here, one file each.
//!
//! A [`Sensor`] is an image-forming device: a [`Pinhole`] camera (`pinhole.rs`, which also
//! builds one from a scene file's [`crate::scene::CameraDesc`] and says why it cannot,
//! [`CameraError`]), a [`ThinLens`] camera with depth of field (`thin_lens.rs`), or an
//! [`Equirectangular`] 360° camera (`equirect.rs`). Each owns its image size (the sensor reads
//! it from the camera, [`Sensor::width`]). All of them are rendered by one splat loop
//! ([`splat`]); the only per-sensor part is [`Sensor::connect`], which links a surface
//! point x to the device and returns the pixel, the point c on the device's aperture, and the
//! factor W that holds the importance and every geometric term on the sensor's side. Each stored
//! vertex x of light k with weight β then adds
//!
//! ```text
//! Δpixel = (Φ_k/N_k) · β · f_r(x; ω_in → ω_c) · |cos θ_x| · V(x, c) · W
//! ```
//!
//! (a light tracer's t = 1 connection, Veach ch. 10, docs/estimator.md §5). θ_x is measured from the
//! geometric normal; on meshes with shading normals f_r is the adjoint f_eff of
//! [`crate::bsdf::shading`], evaluated at the normals interpolated at x. For the pinhole,
//! W = 1/(d²·a·cos³θ_c), so each pixel converges to the radiance at the pinhole averaged over its
//! square of the image plane (a box filter). Emission vertices use L_e·A_k/Φ_k = f_e(ω_c)/cos θ
//! ([`crate::light::Light::emitted_fraction`]; 1/π for a Lambertian emitter) in place of f_r,
//! and only their front side is visible. The per-sensor W are derived in each sensor's module.
//!
//! Sensors that pick a random point on their aperture (the thin lens) draw it from a hash of the
//! sample's own bits, so a render is reproducible and does not depend on how the dataset was
//! chunked or how many threads render it.
//!
//! The [`meter`] module holds the illuminance meter, which needs no connection: a stored sample
//! already *is* flux arriving at a surface.

pub mod bidirectional;
mod equirect;
pub mod meter;
mod pinhole;
mod runs;
mod thin_lens;

pub use equirect::Equirectangular;
pub use meter::{IlluminanceMeter, MeterError, measure};
pub use pinhole::{CameraError, Pinhole, check_fov};
pub use runs::{RunFold, batches_per_run, render_run, render_runs, run_count};
pub use thin_lens::{LensError, ThinLens};

use crate::dataset::Sample;
use crate::film::{Accumulator, Film, SplatTarget};
use crate::geometry::{Ray, offset_ray_origin};
use crate::math::{Rgb, Vec2, Vec3};
use crate::scene::Scene;

/// A run of samples from one light and the flux each unit of β stands for (Φ_k/N_k, after any
/// relighting). What a sensor consumes; the source can be memory or a mapped file.
#[derive(Clone, Copy, Debug)]
pub struct SampleBatch<'a> {
    /// Φ_k / N_k of the batch's light.
    pub flux_per_path: Rgb,
    /// The samples.
    pub samples: &'a [Sample],
}

/// The closed set of image-forming sensors. Each camera owns its image size ([`Sensor::width`],
/// [`Sensor::height`] read it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sensor {
    /// Ideal pinhole (perspective) camera.
    Pinhole(Pinhole),
    /// Thin-lens perspective camera (depth of field).
    ThinLens(ThinLens),
    /// Equirectangular (longitude/latitude) 360° camera.
    Equirectangular(Equirectangular),
}

/// How a surface point connects to a sensor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Connection {
    /// Row-major pixel index, row 0 on top.
    pub pixel: usize,
    /// The point on the sensor's aperture the point is connected to (the shadow ray's end).
    pub point: Vec3,
    /// Importance times the sensor-side geometry (everything in Δ except Φβ/N · f_r · |cos θ_x|
    /// · V), including the 1/d² of the connection.
    pub weight: f32,
}

impl From<Pinhole> for Sensor {
    fn from(p: Pinhole) -> Self {
        Sensor::Pinhole(p)
    }
}

impl From<ThinLens> for Sensor {
    fn from(t: ThinLens) -> Self {
        Sensor::ThinLens(t)
    }
}

impl From<Equirectangular> for Sensor {
    fn from(e: Equirectangular) -> Self {
        Sensor::Equirectangular(e)
    }
}

impl Sensor {
    /// Image width in pixels (the camera's).
    pub fn width(&self) -> u32 {
        match self {
            Sensor::Pinhole(p) => p.width,
            Sensor::ThinLens(t) => t.pinhole.width,
            Sensor::Equirectangular(e) => e.width,
        }
    }

    /// Image height in pixels (the camera's).
    pub fn height(&self) -> u32 {
        match self {
            Sensor::Pinhole(p) => p.height,
            Sensor::ThinLens(t) => t.pinhole.height,
            Sensor::Equirectangular(e) => e.height,
        }
    }

    /// Connects the surface point `x` to the sensor, using `u` ∈ [0,1)² if the sensor samples
    /// its aperture. `None` when x is outside the field of view (or behind the sensor).
    #[inline]
    pub fn connect(&self, x: Vec3, u: Vec2) -> Option<Connection> {
        match self {
            Sensor::Pinhole(p) => p.connect(x),
            Sensor::ThinLens(t) => t.connect(x, u),
            Sensor::Equirectangular(e) => e.connect(x),
        }
    }

    /// Whether [`Sensor::connect`] uses its random numbers.
    #[inline]
    fn samples_aperture(&self) -> bool {
        matches!(self, Sensor::ThinLens(t) if t.radius > 0.0)
    }
}

/// SplitMix64 finaliser.
#[inline]
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Two uniform numbers in [0,1)² derived from the bits of a sample alone (reproducible
/// whatever the chunking or thread count).
#[inline]
pub fn sample_hash_2d(s: &Sample) -> Vec2 {
    let p = s.position;
    let a = (p[0].to_bits() as u64) | ((p[1].to_bits() as u64) << 32);
    let b = (p[2].to_bits() as u64) | ((s.prim as u64) << 32);
    let c = (s.from_dir as u64) | ((s.beta[0].to_bits() as u64) << 32);
    let h = mix(mix(mix(a ^ 0x6f70_7469_6373_6c73) ^ b) ^ c);
    let to_unit = |v: u64| (v >> 40) as f32 * (1.0 / 16_777_216.0);
    Vec2::new(to_unit(h), to_unit(h << 24))
}

/// Adds the contribution of `batch` to `film` as seen by `sensor` — the one splat loop every
/// image-forming sensor shares.
pub fn splat(scene: &Scene, sensor: &Sensor, batch: SampleBatch<'_>, film: &mut impl SplatTarget) {
    if batch.flux_per_path == Rgb::ZERO {
        return;
    }
    let random = sensor.samples_aperture();
    for s in batch.samples {
        let x = s.position();
        let u = if random { sample_hash_2d(s) } else { Vec2::ZERO };
        let Some(conn) = sensor.connect(x, u) else { continue };
        let to_c = conn.point - x;
        let d = to_c.length();
        if !(d > 0.0) {
            continue;
        }
        let wc = to_c / d;
        let prim = s.triangle();
        let n = scene.normal(prim);
        // |cos θ_x| is the connection's geometry term: always the geometric normal's. Shading
        // normals enter only through f_r (the adjoint f_eff, see `crate::bsdf::shading`).
        let cos_x = n.dot(wc);
        let f = if s.is_emission() {
            if cos_x <= 0.0 {
                continue; // emitters are one-sided
            }
            Rgb::splat(scene.light_of(prim).map_or(0.0, |k| scene.lights[k].emitted_fraction(n, wc)))
        } else {
            let f = scene.material(prim).eval_world(scene.normals_at(prim, x), s.from_dir(), wc);
            if f == Rgb::ZERO {
                continue;
            }
            f
        };
        let origin = offset_ray_origin(x, n, wc);
        let to_c = conn.point - origin;
        let t = to_c.length();
        if scene.occluded(&Ray { origin, dir: to_c / t, t_max: t * (1.0 - 1e-5) }) {
            continue;
        }
        film.splat(conn.pixel, batch.flux_per_path * s.beta() * f * (cos_x.abs() * conn.weight));
    }
}

/// Accumulates `count` batches (fetched by index, possibly from a memory-mapped file) into a
/// `width`×`height` film on all cores, with `add` doing the per-batch work: in runs of
/// consecutive batches, each with one [`Accumulator`], summed in run order (`runs.rs`), so the
/// film is the same whatever the number of threads or processes.
pub(crate) fn accumulate<'a, E: Send>(
    size: (u32, u32),
    count: usize,
    batch: impl Fn(usize) -> Result<SampleBatch<'a>, E> + Sync,
    progress: impl Fn(usize) + Sync,
    add: impl Fn(SampleBatch<'a>, &mut Accumulator) + Sync,
) -> Result<Film, E> {
    runs::accumulate_runs(size, count, batch, progress, add)
}

/// Renders `count` batches (fetched by index, possibly from a memory-mapped file) through
/// `sensor` on all cores.
pub fn render<'a, E: Send>(
    scene: &Scene,
    sensor: &Sensor,
    count: usize,
    batch: impl Fn(usize) -> Result<SampleBatch<'a>, E> + Sync,
    progress: impl Fn(usize) + Sync,
) -> Result<Film, E> {
    accumulate((sensor.width(), sensor.height()), count, batch, progress, |b, film| {
        splat(scene, sensor, b, film)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_hash_is_uniform_enough_and_deterministic() {
        let mut sum = Vec2::ZERO;
        let n = 20_000;
        for i in 0..n {
            let s = Sample::scattered(Vec3::new(i as f32 * 0.001, 1.0, 2.0), Vec3::Z, 3, Rgb::ONE);
            let u = sample_hash_2d(&s);
            assert!(u.x >= 0.0 && u.x < 1.0 && u.y >= 0.0 && u.y < 1.0);
            assert_eq!(u, sample_hash_2d(&s));
            sum += u;
        }
        let m = sum / n as f32;
        assert!((m - Vec2::splat(0.5)).abs().max_element() < 0.01, "mean {m}");
    }
}
