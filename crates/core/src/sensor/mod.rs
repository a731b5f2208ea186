//! Sensors: connecting stored samples to a measuring device (the thesis's "visualisation",
//! ch. 4 and §6.1.5). Every camera model lives here, one file each.
//!
//! A [`Sensor`] is an image-forming device: a [`Pinhole`] camera (`pinhole.rs`, which also
//! builds one from a scene file's [`crate::scene::CameraDesc`] and says why it cannot,
//! [`CameraError`]), a [`ThinLens`] camera with depth of field (`thin_lens.rs`), an
//! [`Orthographic`] camera of parallel rays (`orthographic.rs`), or an [`Equirectangular`] 360°
//! camera (`equirect.rs`). Each owns its image size (the sensor reads it from the camera,
//! [`Sensor::width`]); [`Sensor::new`] builds the one a scene file's [`CameraDesc`] states. All of them are rendered by one splat loop
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
//! The [`meter`] module holds the illuminance meter: on scene geometry it needs no connection
//! (a stored sample already *is* flux arriving at a surface); anywhere else it connects the
//! samples to itself through the cameras' connection, whose shadow ray there crosses thin
//! window panes (`connect_through_panes`).
//!
//! [`view`] turns the scene camera and a front end's overrides into the sensor a view is
//! rendered through.

pub mod bidirectional;
mod blind_spots;
mod equirect;
pub mod meter;
mod orthographic;
mod pinhole;
pub mod raster;
mod runs;
mod thin_lens;
pub mod view;
mod visibility;

pub use blind_spots::delta_fraction;
pub use equirect::Equirectangular;
pub use meter::{IlluminanceMeter, MeterError, measure};
pub use orthographic::Orthographic;
pub use pinhole::{CameraError, MAX_IMAGE_SIDE, Pinhole, check_fov, check_image_size};
pub use raster::{Crop, FilmSpec, Filter, Raster};
pub use runs::{RunFold, batches_per_run, render, render_runs, render_with_buffer, run_count};
pub use thin_lens::{LensError, ThinLens, check_lens};
pub use visibility::{Seen, VisibilityBuffer};

use crate::dataset::Sample;
use crate::film::{Film, SharedFilm, SplatTarget, private_films};
use crate::geometry::{Ray, offset_ray_origin};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::{mix, unit_from_hash};
use crate::scene::{CameraDesc, CameraKind, Scene};
use raster::NO_PIXEL;
use rayon::prelude::*;

/// A run of samples from one light and the flux each unit of β stands for (Φ_k/N_k, after any
/// relighting). What a sensor consumes; the source can be memory or a file ([`OwnedBatch`]).
#[derive(Clone, Copy, Debug)]
pub struct SampleBatch<'a> {
    /// Φ_k / N_k of the batch's light.
    pub flux_per_path: Rgb,
    /// The samples.
    pub samples: &'a [Sample],
}

/// A batch as `render` and `measure` take it: borrowed ([`SampleBatch`], from memory) or owning
/// its samples ([`OwnedBatch`], read from a file into a buffer).
pub trait AsBatch {
    /// The batch.
    fn as_batch(&self) -> SampleBatch<'_>;
}

impl AsBatch for SampleBatch<'_> {
    #[inline]
    fn as_batch(&self) -> SampleBatch<'_> {
        *self
    }
}

/// A batch that owns its samples (e.g. a chunk read from a dataset file).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OwnedBatch {
    /// Φ_k / N_k of the batch's light.
    pub flux_per_path: Rgb,
    /// The samples.
    pub samples: Vec<Sample>,
}

impl AsBatch for OwnedBatch {
    #[inline]
    fn as_batch(&self) -> SampleBatch<'_> {
        SampleBatch { flux_per_path: self.flux_per_path, samples: &self.samples }
    }
}

/// The closed set of image-forming sensors. Each camera owns its image size ([`Sensor::width`],
/// [`Sensor::height`] read it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sensor {
    /// Ideal pinhole (perspective) camera.
    Pinhole(Pinhole),
    /// Thin-lens perspective camera (depth of field).
    ThinLens(ThinLens),
    /// Orthographic camera (parallel rays).
    Orthographic(Orthographic),
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
    /// · V), including the 1/d² of the connection (none for the orthographic camera).
    pub weight: f32,
}

/// Where a point lands on a sensor's film for a filtered splat: full-film coordinates
/// (s_x, s_y), not clipped to the film (a filter reaches beyond it), the aperture point and W
/// (as in [`Connection`], for the pixel-sized box of the full film).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmHit {
    /// Full-film coordinates (s_x, s_y), \[0,1\]² on the film.
    pub film: (f32, f32),
    /// The point on the sensor's aperture.
    pub point: Vec3,
    /// W, as in [`Connection::weight`].
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

impl From<Orthographic> for Sensor {
    fn from(o: Orthographic) -> Self {
        Sensor::Orthographic(o)
    }
}

impl From<Equirectangular> for Sensor {
    fn from(e: Equirectangular) -> Self {
        Sensor::Equirectangular(e)
    }
}

impl Sensor {
    /// The sensor a camera description states: its [`CameraKind`]'s camera.
    pub fn new(d: &CameraDesc) -> Result<Self, CameraError> {
        Ok(match d.kind {
            CameraKind::Perspective => Pinhole::new(d)?.into(),
            CameraKind::ThinLens { aperture_radius, focus_distance } => {
                ThinLens::new(Pinhole::new(d)?, aperture_radius, focus_distance)?.into()
            }
            CameraKind::Orthographic { half_width, half_height } => {
                Orthographic::new(d, half_width, half_height)?.into()
            }
        })
    }

    /// The pixels the sensor writes (its crop window) and its reconstruction filter.
    #[inline]
    pub fn raster(&self) -> &Raster {
        match self {
            Sensor::Pinhole(p) => &p.raster,
            Sensor::ThinLens(t) => &t.pinhole.raster,
            Sensor::Orthographic(o) => &o.raster,
            Sensor::Equirectangular(e) => &e.raster,
        }
    }

    /// Image width in pixels (the crop window's; the whole film's without one).
    pub fn width(&self) -> u32 {
        self.raster().width()
    }

    /// Image height in pixels (the crop window's).
    pub fn height(&self) -> u32 {
        self.raster().height()
    }

    /// Connects the surface point `x` to the sensor, using `u` ∈ [0,1)² if the sensor samples
    /// its aperture. `None` when x is outside the field of view (or behind the sensor).
    #[inline]
    pub fn connect(&self, x: Vec3, u: Vec2) -> Option<Connection> {
        match self {
            Sensor::Pinhole(p) => p.connect(x),
            Sensor::ThinLens(t) => t.connect(x, u),
            Sensor::Orthographic(o) => o.connect(x),
            Sensor::Equirectangular(e) => e.connect(x),
        }
    }

    /// The [`VisibilityBuffer`] of this sensor in `scene`, for the sensors that have one (a
    /// pinhole: every connection ends at its eye).
    pub fn visibility(&self, scene: &Scene) -> Option<VisibilityBuffer> {
        match self {
            Sensor::Pinhole(p) => VisibilityBuffer::build(scene, p),
            _ => None,
        }
    }

    /// Where `x` lands on the full film, unclipped, for a filtered splat (`u` as in
    /// [`Sensor::connect`]); `None` behind the sensor. The equirectangular camera (box only)
    /// has none.
    #[inline]
    pub fn film_hit(&self, x: Vec3, u: Vec2) -> Option<FilmHit> {
        match self {
            Sensor::Pinhole(p) => p.film_hit(x),
            Sensor::ThinLens(t) => t.film_hit(x, u),
            Sensor::Orthographic(o) => o.film_hit(x),
            Sensor::Equirectangular(_) => None,
        }
    }

    /// Whether [`Sensor::connect`] uses its random numbers.
    #[inline]
    pub(crate) fn samples_aperture(&self) -> bool {
        matches!(self, Sensor::ThinLens(t) if t.radius > 0.0)
    }
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
    Vec2::new(unit_from_hash(h), unit_from_hash(h << 24))
}

/// A stored sample connected to a sensor: the pixel, the BSDF (or emission) factor f toward
/// the sensor, |cos θ_x| and the sensor's factor — Δpixel = (Φ_k/N_k)·β·f·(|cos θ_x|·W), the
/// visibility already tested.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SampleConnection {
    /// The sensor's connection (pixel, aperture point, W).
    pub conn: Connection,
    /// f_r(x; ω_in → ω_c), or L_e·A_k/Φ_k for an emission vertex.
    pub f: Rgb,
    /// cos θ_x (geometric normal; its absolute value enters Δ).
    pub cos_x: f32,
    /// Unit direction from x to the aperture point.
    pub to_sensor: Vec3,
    /// |x − c|².
    pub dist2: f32,
    /// With `connect_seen::<true>`: the density of the light tracer's BSDF sampling at x
    /// of continuing from the sensor's direction back to the sample's predecessor
    /// (`Material::pdf_world(n, to_sensor, from_dir)`, what the bidirectional splat's MIS weight
    /// needs), from the same shading point as `f`; 0 for an emission vertex or when not asked.
    pub pdf_rev: f32,
}

/// A stored sample's connection to the sensor point of `conn` (found by projecting the sample,
/// [`splat_projected`]), what the sensor's visibility buffer said of it being `seen`: `None`
/// when its f is 0 or the sensor cannot see it, the shadow ray traced only where the buffer did
/// not know ([`Seen::Unknown`]; the answers are the same). With `REVERSE`, also
/// [`SampleConnection::pdf_rev`], from the shading point that gives f (the bidirectional
/// splat's MIS weight needs both).
#[inline]
pub(crate) fn connect_seen<const REVERSE: bool>(
    scene: &Scene,
    seen: Seen,
    s: &Sample,
    conn: Connection,
) -> Option<SampleConnection> {
    let trace = match seen {
        Seen::Hidden => return None,
        Seen::Visible => false,
        Seen::Unknown => true,
    };
    let (c, [x, n]) = connection::<REVERSE>(scene, s, conn)?;
    (!trace || !scene.occluded(&shadow_ray(x, n, c.to_sensor, c.conn.point))).then_some(c)
}

/// A stored sample's connection to the sensor point `conn.point` (the rest of `conn` passed
/// through) — f toward it (or the emission factor), cos θ_x — whose shadow ray crosses thin
/// panes ([`Scene::shadow_transmittance`]): `f`
/// is then f times the panes' straight-through transmittance, per channel. The connected
/// illuminance meter's ([`meter`]; `meter/connect.rs` says why this is unbiased); the cameras
/// keep [`connect_seen`]'s shadow ray, as their bidirectional weights assume that a pane
/// blocks. `None` when f is 0, an emitter is seen from behind, or something else blocks.
#[inline]
pub(crate) fn connect_through_panes(scene: &Scene, s: &Sample, conn: Connection) -> Option<SampleConnection> {
    let (c, [x, n]) = connection::<false>(scene, s, conn)?;
    let t = scene.shadow_transmittance(&shadow_ray(x, n, c.to_sensor, c.conn.point))?;
    Some(SampleConnection { f: c.f * t, ..c })
}

/// A sample's connection to `conn.point` up to its shadow ray, with the sample's position and
/// geometric normal for that ray ([`shadow_ray`]), made only if it is traced (with `REVERSE`,
/// also the reverse density, [`SampleConnection::pdf_rev`]).
#[inline]
fn connection<const REVERSE: bool>(
    scene: &Scene,
    s: &Sample,
    conn: Connection,
) -> Option<(SampleConnection, [Vec3; 2])> {
    let x = s.position();
    let to_c = conn.point - x;
    let d = to_c.length();
    if !(d > 0.0) {
        return None;
    }
    let wc = to_c / d;
    let prim = s.triangle();
    let n = scene.normal(prim);
    // |cos θ_x| is the connection's geometry term: always the geometric normal's. Shading
    // normals enter only through f_r (the adjoint f_eff, see `crate::bsdf::shading`).
    let cos_x = n.dot(wc);
    let (f, pdf_rev) = if s.is_emission() {
        if cos_x <= 0.0 {
            return None; // emitters are one-sided
        }
        (Rgb::splat(scene.light_of(prim).map_or(0.0, |k| scene.lights[k].emitted_fraction(n, wc))), 0.0)
    } else {
        let from = s.from_dir();
        match scene.flat_lambert(prim) {
            Some(lambert) => flat_lambert_f::<REVERSE>(lambert, n.dot(from), cos_x)?,
            None => shaded_f::<REVERSE>(scene, prim, x, from, wc)?,
        }
    };
    Some((SampleConnection { conn, f, cos_x, to_sensor: wc, dist2: d * d, pdf_rev }, [x, n]))
}

/// f_r toward the sensor (and with `REVERSE` the reverse density, [`SampleConnection::pdf_rev`])
/// of a reflection vertex at `x` on triangle `prim`, light arriving from `from`, the sensor
/// along `wc`; `None` where f is 0. The general case: the material resolved at x, its normals
/// and one shading frame for both queries.
#[inline]
fn shaded_f<const REVERSE: bool>(
    scene: &Scene,
    prim: u32,
    x: Vec3,
    from: Vec3,
    wc: Vec3,
) -> Option<(Rgb, f32)> {
    let mut resolved = None;
    let (material, normals) = scene.surface_at(prim, x, &mut resolved);
    let p = material.at(normals);
    let (from, toward) = (p.direction(from), p.direction(wc));
    let f = p.eval(&from, &toward);
    (f != Rgb::ZERO).then(|| (f, if REVERSE { p.pdf(&toward, &from) } else { 0.0 }))
}

/// [`shaded_f`] on a flat, untextured Lambert reflector ([`Scene::flat_lambert`]: its ρ/π and
/// two-sidedness), from the geometric cosines of the arriving light (`cos_in`) and of the
/// sensor's direction (`cos_x`) alone — what `ShadingPoint::eval` and `pdf` reduce to there
/// without a frame: the lit side is the arriving light's (the back only if two-sided), f is
/// ρ/π if the sensor is on that side (`None` for a black one, as there), the reverse density
/// that cosine over π. The same numbers to the bit: each local z of the general case is the
/// same dot product (a test holds both to it).
#[inline]
fn flat_lambert_f<const REVERSE: bool>(
    (f, two_sided): (Rgb, bool),
    cos_in: f32,
    cos_x: f32,
) -> Option<(Rgb, f32)> {
    let lit = if cos_in > 0.0 { cos_x > 0.0 } else { cos_in < 0.0 && two_sided && cos_x < 0.0 };
    (lit && f != Rgb::ZERO)
        .then(|| (f, if REVERSE { cos_in.abs() * std::f32::consts::FRAC_1_PI } else { 0.0 }))
}

/// The shadow ray of a connection from surface point `x` (geometric normal `n`, unit direction
/// `wc` toward `point`) to `point`: from x pushed off its surface, ending just short of `point`.
#[inline]
fn shadow_ray(x: Vec3, n: Vec3, wc: Vec3, point: Vec3) -> Ray {
    let origin = offset_ray_origin(x, n, wc);
    let to_c = point - origin;
    let t = to_c.length();
    Ray { origin, dir: to_c / t, t_max: t * (1.0 - 1e-5) }
}

/// Whether nothing blocks a connection's shadow ray ([`shadow_ray`]'s arguments).
#[cfg(test)]
pub(crate) fn sees(scene: &Scene, x: Vec3, n: Vec3, wc: Vec3, point: Vec3) -> bool {
    !scene.occluded(&shadow_ray(x, n, wc, point))
}

/// Adds the contribution of `batch` to `film` as seen by `sensor` (with its `visibility`
/// buffer, [`Sensor::visibility`], if it has one) — the one splat loop every image-forming
/// sensor shares.
pub fn splat(
    scene: &Scene,
    sensor: &Sensor,
    visibility: Option<&VisibilityBuffer>,
    batch: SampleBatch<'_>,
    film: &mut impl SplatTarget,
) {
    if batch.flux_per_path == Rgb::ZERO {
        return;
    }
    if !sensor.raster().is_box() {
        return splat_filtered(scene, sensor, visibility, batch, film);
    }
    splat_projected(sensor, visibility, batch.samples, film, |film, i, conn, seen| {
        let s = &batch.samples[i];
        let Some(SampleConnection { conn, f, cos_x, .. }) = connect_seen::<false>(scene, seen, s, conn)
        else {
            return;
        };
        film.splat(conn.pixel, batch.flux_per_path * s.beta() * f * (cos_x.abs() * conn.weight));
    });
}

/// The box-filtered splat loop's walk over `samples`: `each(film, i, conn, seen)` for every
/// sample i that projects into `sensor`'s image, with its connection and what the `visibility`
/// buffer says of it. Software pipelining: a sample's pixel is
/// known as soon as it is projected, and its reads of the visibility buffer and of the film (a
/// megabyte together at 256², past L2) are random; each sample is projected [`SPLAT_AHEAD`]
/// samples early and those loads begun then, so they overlap the work of the samples between.
/// The same connections in the same order: images are unchanged to the bit. A pinhole's
/// samples are projected a block at a time instead ([`splat_projected_pinhole`]).
#[inline]
pub(crate) fn splat_projected<T: SplatTarget>(
    sensor: &Sensor,
    visibility: Option<&VisibilityBuffer>,
    samples: &[Sample],
    film: &mut T,
    mut each: impl FnMut(&mut T, usize, Connection, Seen),
) {
    if let Sensor::Pinhole(p) = sensor {
        return splat_projected_pinhole(p, visibility, samples, film, each);
    }
    let random = sensor.samples_aperture();
    let project =
        |s: &Sample| sensor.connect(s.position(), if random { sample_hash_2d(s) } else { Vec2::ZERO });
    let mut ahead = [None; SPLAT_AHEAD];
    for (slot, s) in ahead.iter_mut().zip(samples) {
        *slot = project(s);
    }
    for (i, s) in samples.iter().enumerate() {
        let slot = &mut ahead[i % SPLAT_AHEAD];
        let conn = *slot;
        if let Some(next) = samples.get(i + SPLAT_AHEAD) {
            *slot = project(next);
            if let Some(c) = slot {
                visibility.inspect(|v| v.prefetch(c.pixel));
                film.prefetch(c.pixel);
            }
        }
        if let Some(conn) = conn {
            let seen = visibility.map_or(Seen::Unknown, |v| v.seen_at(conn.pixel, s.triangle()));
            each(film, i, conn, seen);
        }
    }
}

/// How many samples ahead of its splat [`splat_projected`] projects a sample and starts the
/// loads of its pixel. 4, 8 and 16 measured alike (`docs/performance.md`).
const SPLAT_AHEAD: usize = 8;

/// [`splat_projected`] for the pinhole: the samples projected a block at a time
/// ([`Pinhole::connect_block`]), the next block's pixels loaded while this one's are splatted
/// (the same pipelining, [`BLOCK`] to 2·[`BLOCK`] samples ahead). The same connections in the
/// same order as the general walk.
#[inline]
fn splat_projected_pinhole<T: SplatTarget>(
    p: &Pinhole,
    visibility: Option<&VisibilityBuffer>,
    samples: &[Sample],
    film: &mut T,
    mut each: impl FnMut(&mut T, usize, Connection, Seen),
) {
    let project = |film: &T, blocks: &mut std::slice::Chunks<'_, Sample>, into: &mut ProjectedBlock| {
        let Some(block) = blocks.next() else { return into.len = 0 };
        p.connect_block(block, into);
        for &pixel in into.pixels().iter().filter(|&&q| q != NO_PIXEL) {
            visibility.inspect(|v| v.prefetch(pixel as usize));
            film.prefetch(pixel as usize);
        }
    };
    let mut blocks = samples.chunks(BLOCK);
    let (mut this, mut next) = (ProjectedBlock::default(), ProjectedBlock::default());
    project(film, &mut blocks, &mut this);
    let mut first = 0;
    while this.len > 0 {
        project(film, &mut blocks, &mut next);
        for (l, (&pixel, &weight)) in this.pixels().iter().zip(&this.weight).enumerate() {
            if pixel == NO_PIXEL {
                continue;
            }
            let (i, pixel) = (first + l, pixel as usize);
            let seen = visibility.map_or(Seen::Unknown, |v| v.seen_at(pixel, samples[i].triangle()));
            each(film, i, Connection { pixel, point: p.eye, weight }, seen);
        }
        first += this.len;
        std::mem::swap(&mut this, &mut next);
    }
}

/// Samples a pinhole projects at once ([`Pinhole::connect_block`]).
const BLOCK: usize = 16;

/// [`Pinhole::connect_block`]'s output: per sample its pixel (or [`NO_PIXEL`]) and its
/// connection's weight W.
#[derive(Clone, Copy, Debug)]
struct ProjectedBlock {
    pixel: [u32; BLOCK],
    weight: [f32; BLOCK],
    /// How many of the lanes hold samples.
    len: usize,
}

impl Default for ProjectedBlock {
    fn default() -> Self {
        ProjectedBlock { pixel: [NO_PIXEL; BLOCK], weight: [0.0; BLOCK], len: 0 }
    }
}

impl ProjectedBlock {
    /// The pixels of the lanes that hold samples.
    #[inline]
    fn pixels(&self) -> &[u32] {
        &self.pixel[..self.len]
    }
}

/// A sample connected to a filtered sensor: the connection (its `pixel` unused) and the pixels
/// it reaches with their filter weights; `None` as [`connect_seen`], or when no pixel of the
/// image is within the filter's radius (before the shadow ray).
#[inline]
pub(crate) fn connect_filtered<const REVERSE: bool>(
    scene: &Scene,
    sensor: &Sensor,
    visibility: Option<&VisibilityBuffer>,
    s: &Sample,
    random: bool,
) -> Option<(SampleConnection, raster::Footprint)> {
    let u = if random { sample_hash_2d(s) } else { Vec2::ZERO };
    let hit = sensor.film_hit(s.position(), u)?;
    let footprint = sensor.raster().footprint(hit.film.0, hit.film.1)?;
    let conn = Connection { pixel: 0, point: hit.point, weight: hit.weight };
    let seen = visibility.map_or(Seen::Unknown, |v| v.seen_on_film(hit.film, s.triangle()));
    Some((connect_seen::<REVERSE>(scene, seen, s, conn)?, footprint))
}

/// [`splat`] through a filter: one shadow ray, then the value times f̂(s − c_p) into each
/// pixel p within the filter's radius (`raster.rs`).
fn splat_filtered(
    scene: &Scene,
    sensor: &Sensor,
    visibility: Option<&VisibilityBuffer>,
    batch: SampleBatch<'_>,
    film: &mut impl SplatTarget,
) {
    let random = sensor.samples_aperture();
    for s in batch.samples {
        let Some((c, footprint)) = connect_filtered::<false>(scene, sensor, visibility, s, random) else {
            continue;
        };
        let v = batch.flux_per_path * s.beta() * c.f * (c.cos_x.abs() * c.conn.weight);
        footprint.for_each(|pixel, w| film.splat(pixel, v * w));
    }
}

/// The per-batch work of a render or a measurement: adds a batch's contributions to any splat
/// target (a run's [`crate::film::Accumulator`] or a [`SharedFilm`]). What [`accumulate`] runs on all cores.
pub(crate) trait Splatter: Sync {
    /// Adds `batch` to `film`.
    fn splat_batch<T: SplatTarget>(&self, batch: SampleBatch<'_>, film: &mut T);
}

/// Accumulates `count` batches (fetched by index, from memory or read from a file) into a
/// `width`×`height` film on all cores, with `splatter` doing the per-batch work. Films with
/// [`private_films`] (up to about 2.5 million pixels): in runs of consecutive batches, each
/// with one [`crate::film::Accumulator`], summed in run order (`runs.rs`), so the image is the same bit for
/// bit whatever the number of threads or processes. Larger films: one [`SharedFilm`] that all
/// threads add to atomically (equal within float rounding, its last bits varying from run to
/// run), fed by a few contiguous runs of batches per thread. Memory is therefore bounded by
/// [`crate::film::accumulation_bytes`], never threads × pixels.
pub(crate) fn accumulate<B: AsBatch, E: Send>(
    (width, height): (u32, u32),
    count: usize,
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
    splatter: &impl Splatter,
) -> Result<Film, E> {
    let in_runs = private_films(width, height);
    accumulate_in((width, height), count, batch, progress, splatter, in_runs)
}

/// [`accumulate`] in runs (`in_runs`) or into one shared film.
fn accumulate_in<B: AsBatch, E: Send>(
    (width, height): (u32, u32),
    count: usize,
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
    splatter: &impl Splatter,
    in_runs: bool,
) -> Result<Film, E> {
    if in_runs {
        return runs::accumulate_runs((width, height), count, batch, progress, splatter);
    }
    // A few contiguous runs of batches per thread, all into the one shared film.
    let runs = (rayon::current_num_threads() * 4).clamp(1, count.max(1));
    let run_len = count.div_ceil(runs).max(1);
    let shared = SharedFilm::new(width, height);
    (0..runs).into_par_iter().try_for_each(|r| {
        let mut target = &shared;
        for i in (r * run_len)..((r + 1) * run_len).min(count) {
            let b = batch(i)?;
            let b = b.as_batch();
            splatter.splat_batch(b, &mut target);
            progress(b.samples.len());
        }
        Ok(())
    })?;
    Ok(shared.into_film())
}

/// The splat loop of an image-forming sensor, as [`accumulate`] runs it.
pub(crate) struct SensorSplat<'a> {
    scene: &'a Scene,
    sensor: &'a Sensor,
    visibility: Option<VisibilityBuffer>,
}

impl<'a> SensorSplat<'a> {
    /// The splat loop of `sensor` in `scene`, with its visibility buffer.
    fn new(scene: &'a Scene, sensor: &'a Sensor) -> Self {
        SensorSplat { scene, sensor, visibility: sensor.visibility(scene) }
    }

    /// The same with `sensor`'s buffer already built ([`Sensor::visibility`]).
    pub(crate) fn with_buffer(
        scene: &'a Scene,
        sensor: &'a Sensor,
        visibility: Option<VisibilityBuffer>,
    ) -> Self {
        SensorSplat { scene, sensor, visibility }
    }
}

impl Splatter for SensorSplat<'_> {
    #[inline]
    fn splat_batch<T: SplatTarget>(&self, batch: SampleBatch<'_>, film: &mut T) {
        splat(self.scene, self.sensor, self.visibility.as_ref(), batch, film)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The splats' shortcut for flat Lambert reflectors ([`flat_lambert_f`]) gives what the
    /// general shading gives ([`shaded_f`]), f and the reverse density to the bit, on one- and
    /// two-sided walls, for light and sensor on every side; and it is taken only there.
    #[test]
    fn a_flat_lambert_connection_is_the_shaded_one_to_the_bit() {
        use crate::bsdf::{Bsdf, ModifiedPhong};
        use crate::sampling::{RandomStream, warp};
        let mut desc = crate::scene::cornell_box();
        for (i, m) in desc.materials.iter_mut().enumerate() {
            m.two_sided = i % 2 == 0;
        }
        // A black wall: no connection at all, as the general shading says (f = 0).
        desc.materials[1].bsdf = Bsdf::Lambert(crate::bsdf::Lambert::new(Rgb::ZERO).unwrap());
        let glossy = desc.materials.len();
        desc.materials.push(crate::bsdf::Material {
            name: "glossy".into(),
            bsdf: Bsdf::ModifiedPhong(ModifiedPhong::new(Rgb::splat(0.3), Rgb::splat(0.3), 20.0).unwrap()),
            two_sided: false,
        });
        desc.meshes[0].material = glossy;
        let scene = Scene::build(&desc).unwrap();
        let mut rng = RandomStream::new(5, &[]);
        let (mut lit, mut dark, mut general) = (0, 0, 0);
        for prim in 0..scene.triangles.len() as u32 {
            let Some(lambert) = scene.flat_lambert(prim) else {
                general += 1;
                let mut resolved = None;
                let p = scene.triangles[prim as usize].point(0.3, 0.3);
                assert_eq!(scene.material_at(prim, p, &mut resolved).name, "glossy");
                continue;
            };
            let t = &scene.triangles[prim as usize];
            for _ in 0..200 {
                let u = rng.next_2d();
                let x = t.point(u.x * (1.0 - u.y), u.y);
                let from = warp::square_to_uniform_sphere(rng.next_2d());
                let wc = warp::square_to_uniform_sphere(rng.next_2d());
                let n = scene.normal(prim);
                let fast = flat_lambert_f::<true>(lambert, n.dot(from), n.dot(wc));
                let shaded = shaded_f::<true>(&scene, prim, x, from, wc);
                let bits =
                    |r: Option<(Rgb, f32)>| r.map(|(f, p)| (f.to_array().map(f32::to_bits), p.to_bits()));
                assert_eq!(bits(fast), bits(shaded), "triangle {prim}, from {from}, to {wc}");
                if fast.is_some() { lit += 1 } else { dark += 1 }
            }
        }
        assert!(lit > 300 && dark > 300 && general > 0, "{lit} lit, {dark} dark, {general} general");
    }

    /// Issue 10, item 11: a 4096² render took 3.1 GB on two threads (one film per thread and
    /// run). Accumulation now never takes threads × pixels: small films are accumulated in runs
    /// within a fixed budget, large ones into one shared film; both give the same image.
    #[test]
    fn film_memory_is_bounded_and_both_accumulations_agree() {
        use crate::film::{FILM_BYTES_PER_PIXEL, PRIVATE_FILMS_BUDGET, accumulation_bytes};
        for threads in [1, 2, 64, 1024] {
            assert_eq!(accumulation_bytes(4096, 4096, threads), 4096 * 4096 * FILM_BYTES_PER_PIXEL);
            assert!(
                accumulation_bytes(256, 256, threads)
                    <= PRIVATE_FILMS_BUDGET + 256 * 256 * FILM_BYTES_PER_PIXEL
            );
        }
        assert!(private_films(256, 256) && !private_films(4096, 4096));
        let desc = crate::scene::cornell_box();
        let sensor: Sensor = Pinhole::new(&desc.camera.unwrap()).unwrap().into();
        let scene = Scene::build(&desc).unwrap();
        let mut chunks = Vec::new();
        let settings = crate::trace::TraceSettings { paths: 40_000, seed: 3, ..Default::default() };
        let table = crate::trace::trace(
            &scene,
            &settings,
            |c| {
                chunks.push(c);
                Ok::<_, ()>(())
            },
            |_| {},
        )
        .unwrap();
        let batch = |i: usize| {
            let c: &crate::dataset::Chunk = &chunks[i];
            Ok::<_, ()>(SampleBatch {
                flux_per_path: table.flux_per_path(c.light as usize),
                samples: &c.samples,
            })
        };
        let splatter = SensorSplat::new(&scene, &sensor);
        let dims = (sensor.width(), sensor.height());
        let private = accumulate_in(dims, chunks.len(), batch, |_| {}, &splatter, true).unwrap();
        let shared = accumulate_in(dims, chunks.len(), batch, |_| {}, &splatter, false).unwrap();
        let mean = private.mean();
        assert!(mean[0] > 0.0);
        for (a, b) in private.pixels.iter().zip(&shared.pixels) {
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() <= 1e-6 * (a[c].abs() + 1e-12), "{a:?} vs {b:?}");
            }
        }
    }

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
