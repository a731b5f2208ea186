//! The illuminance meter: irradiance E (W/m²) per cell of a grid, or at points (the thesis
//! §6.1.5's measuring devices), with a standard error per target. Two estimators:
//!
//! * **Connected** (`connect.rs`, [`read_connected`]): anywhere — on a plane in the air, at a
//!   list of points ([`MeterPoint`]), or on a surface. Every stored scattered vertex is
//!   connected to a uniform point of the meter, the light tracer's t = 1 strategy with the
//!   meter as a sensor of cosine importance; every light's direct light is estimated at the
//!   meter, per target: point and directional lights at points of the cell, environments by a
//!   visibility-guided sampler (`sky.rs`), area lights by stratified points on them (`area.rs`,
//!   which is why their stored emission points are not connected: nothing counts twice).
//! * **Stored samples** ([`read_samples`], and [`measure`] without the errors): only for a meter
//!   lying *on* scene geometry. No connection is needed: a stored sample on a surface *is* the
//!   flux Φ_k·β/N_k arriving there (docs/estimator.md §2), so
//!
//! ```text
//! E_cell = Σ_{samples x in the cell, arriving from the front} (Φ_k/N_k) · β  /  A_cell
//! ```
//!
//!   — unbiased for the cell's mean irradiance, whatever the light paths did before; a plane in
//!   the air receives no samples and reads 0; emission vertices are not incident light and are
//!   skipped.
//!
//! Both count only light arriving from the side the meter's normal faces (n = u × v; a
//! sample's `from_dir` · n > 0 here), so a meter on a wall reads that wall's front irradiance.
//! Their standard errors come from the dataset's chunks, which are independent (`tally.rs`).
//!
//! A grid meter is a parallelogram (origin, edge vectors u and v) divided into nx × ny cells; a
//! sample belongs to it when it lies within a small tolerance of that plane.
//! [`IlluminanceMeter::on_mesh`] builds one covering a planar mesh's bounding rectangle in its
//! own plane. Entry `j * nx + i` of a reading is cell i along u and j along v (row 0 at the
//! origin's side — not an image's top row).

mod area;
mod budget;
mod connect;
mod layout;
mod sky;
mod tally;

pub use connect::{
    ConnectedSettings, DEFAULT_DIRECT_POINTS, DIRECT_STOP_DRAWS, read_connected, read_connected_many,
};
pub use layout::{MeterDraw, MeterLayout, MeterPoint};
pub use tally::{Group, Reading};

/// Test helper of the direct terms' closed-form tests (`sky.rs`, `area/tests.rs`): reading
/// `v ± se` of seed `seed` at point `(x, z)` against its closed form `exact` — a positive SE of
/// at most 1 %, within max(4 SE, 1 %) — printed; returns `(v, se²)` for the seeds' mean.
#[cfg(test)]
pub(super) fn check_reading(
    what: &str,
    seed: u64,
    (x, z): (f32, f32),
    (v, se): (f64, f64),
    exact: f64,
) -> (f64, f64) {
    eprintln!(
        "{what} seed {seed} ({x}, {z}): {:+.3} % ± {:.3} %",
        100.0 * (v / exact - 1.0),
        100.0 * se / exact
    );
    assert!(se > 0.0 && se <= 0.01 * exact, "{what} ({x}, {z}) seed {seed}: {v} ± {se}");
    assert!((v - exact).abs() <= (4.0 * se).max(0.01 * exact), "{what} ({x}, {z}): {v} ± {se} vs {exact}");
    (v, se * se)
}

/// Test helper of the direct terms' closed-form tests: a scene of `meshes` whose surfaces are all
/// black (one one-sided black Lambert material), so that a reading is the direct light alone.
#[cfg(test)]
pub(super) fn black_room(meshes: Vec<crate::scene::MeshDesc>) -> SceneDescription {
    use crate::bsdf::{Bsdf, Lambert, Material};
    let black = Bsdf::Lambert(Lambert::new(crate::math::Rgb::ZERO).unwrap());
    SceneDescription {
        materials: vec![Material { name: "black".into(), bsdf: black, two_sided: false }],
        meshes,
        ..Default::default()
    }
}

/// How a meter reads a dataset (module docs): every stored sample connected to points of the
/// meter, which reads anywhere, or the samples that landed on it, which reads only a grid on
/// the scene's surfaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeterEstimator {
    /// [`read_connected`] with these settings.
    Connections(ConnectedSettings),
    /// [`read_samples`].
    Samples,
}

use super::{SampleBatch, Splatter, accumulate};
use crate::dataset::Sample;
use crate::film::{Film, SplatTarget};
use crate::geometry::Ray;
use crate::math::Vec3;
use crate::scene::{Scene, SceneDescription};

/// cos of the largest angle (0.8°) between a sample's surface and the meter for the sample to be
/// the meter's ([`IlluminanceMeter::splat_on`]).
const PARALLEL_COS: f32 = 0.9999;

/// Why a meter cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeterError {
    /// nx or ny is zero, or there are more than [`MAX_TARGETS`] cells.
    #[error("a meter needs at least 1x1 cells and at most 65536 in all, got {0}x{1}")]
    Cells(u32, u32),
    /// Non-finite numbers, or u and v parallel or zero.
    #[error(
        "the meter's plane is degenerate (origin, u and v must be finite, u and v non-zero and not parallel)"
    )]
    Degenerate,
    /// No mesh has that name.
    #[error("no mesh named '{name}' in the scene (meshes: {known})")]
    UnknownSurface {
        /// The name asked for.
        name: String,
        /// The scene's mesh names, comma separated.
        known: String,
    },
    /// The mesh is not flat.
    #[error(
        "mesh '{name}' is not planar (a vertex lies {deviation} m off its plane); meters need planar surfaces"
    )]
    NotPlanar {
        /// Mesh name.
        name: String,
        /// Largest distance of a vertex from the mean plane.
        deviation: f32,
    },
    /// The mesh has no (non-degenerate) triangles.
    #[error("mesh '{0}' has no area to measure")]
    EmptySurface(String),
    /// The mesh has area, but its triangles face every way (a closed or curved surface: a
    /// cylinder, a box), so that no plane is the surface's.
    #[error(
        "mesh '{0}' is not planar (a closed or curved surface: its triangles face every way); meters need planar surfaces (measure points on it with --points)"
    )]
    Curved(String),
    /// A meter point's position or normal is not finite, or its normal is zero.
    #[error("a meter point needs a finite position and a finite, non-zero normal")]
    BadPoint,
    /// No points, or more than [`MAX_TARGETS`].
    #[error("a meter needs between 1 and 65536 points, got {0}")]
    PointCount(usize),
}

/// The most cells or points one meter reads (its statistics take ~100 bytes per target and
/// light on each thread).
pub const MAX_TARGETS: usize = 65536;

/// A grid of nx × ny irradiance cells on the parallelogram origin + a·u + b·v, a, b ∈ [0,1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IlluminanceMeter {
    /// Corner of cell (0, 0).
    pub origin: Vec3,
    /// First edge (cells i = 0..nx along it).
    pub u: Vec3,
    /// Second edge (cells j = 0..ny along it).
    pub v: Vec3,
    /// Cells along u.
    pub nx: u32,
    /// Cells along v.
    pub ny: u32,
    /// Largest distance from the plane at which a sample still counts, metres.
    pub tolerance: f32,
    normal: Vec3,
    inv_det: f32,
}

impl IlluminanceMeter {
    /// A meter on the parallelogram (origin, u, v) with nx × ny cells. Its front (the side whose
    /// incident light it measures) is n = u × v.
    pub fn new(origin: Vec3, u: Vec3, v: Vec3, nx: u32, ny: u32) -> Result<Self, MeterError> {
        if nx == 0 || ny == 0 || nx as u64 * ny as u64 > MAX_TARGETS as u64 {
            return Err(MeterError::Cells(nx, ny));
        }
        let c = u.cross(v);
        let det = c.length();
        let finite = origin.is_finite() && u.is_finite() && v.is_finite() && det.is_finite();
        if !finite || det <= 1e-6 * u.length() * v.length() {
            return Err(MeterError::Degenerate);
        }
        let tolerance = 1e-4 * (u.length() + v.length()) + 1e-6 * origin.length();
        Ok(IlluminanceMeter { origin, u, v, nx, ny, tolerance, normal: c / det, inv_det: 1.0 / det })
    }

    /// A meter covering the bounding rectangle of the planar mesh(es) called `name`, in their
    /// plane, facing the way their triangles face (area-weighted mean normal n). Its v edge
    /// points up the surface (world +y projected on it; −z for floors and ceilings) and u = v × n,
    /// so the heat map looks like the surface seen from its front (a floor: x right, −z up).
    pub fn on_mesh(desc: &SceneDescription, name: &str, nx: u32, ny: u32) -> Result<Self, MeterError> {
        let meshes: Vec<_> = desc.meshes.iter().filter(|m| m.name == name).collect();
        if meshes.is_empty() {
            let known: Vec<&str> = desc.meshes.iter().map(|m| m.name.as_str()).collect();
            return Err(MeterError::UnknownSurface { name: name.into(), known: known.join(", ") });
        }
        let mut points = Vec::new();
        let (mut area_normal, mut area) = (Vec3::ZERO, 0.0f32);
        for m in &meshes {
            for t in &m.triangles {
                let [Some(a), Some(b), Some(c)] = t.map(|i| m.positions.get(i as usize).copied()) else {
                    continue; // the scene builder reports bad indices
                };
                let cross = (b - a).cross(c - a);
                area_normal += cross;
                area += cross.length();
                points.extend([a, b, c]);
            }
        }
        let Some(&p0) = points.first() else { return Err(MeterError::EmptySurface(name.into())) };
        let extent = points.iter().map(|p| (*p - p0).length()).fold(0.0f32, f32::max);
        let len = area_normal.length();
        if !(len > 1e-12 * extent * extent) || !area_normal.is_finite() {
            return Err(if area > 1e-12 * extent * extent && area.is_finite() {
                MeterError::Curved(name.into())
            } else {
                MeterError::EmptySurface(name.into())
            });
        }
        let n = area_normal / len;
        let deviation = points.iter().map(|p| (*p - p0).dot(n).abs()).fold(0.0f32, f32::max);
        if deviation > 1e-4 * extent {
            return Err(MeterError::NotPlanar { name: name.into(), deviation });
        }
        // v points up the surface (world +y projected), or, on floors and ceilings, toward −z;
        // u = v × n is then to the right of someone facing the surface's front.
        let up = if n.y.abs() < 0.9 { Vec3::Y } else { Vec3::NEG_Z };
        let vd = (up - up.dot(n) * n).normalize();
        let ud = vd.cross(n);
        let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
        for p in &points {
            let q = [(*p - p0).dot(ud), (*p - p0).dot(vd)];
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        let origin = p0 + lo[0] * ud + lo[1] * vd;
        let mut meter = IlluminanceMeter::new(origin, (hi[0] - lo[0]) * ud, (hi[1] - lo[1]) * vd, nx, ny)?;
        // The surface's samples lie as far from its plane as its vertices do (plus rounding):
        // a wider band would also take the samples of a neighbouring wall that meets it at an
        // edge, counting them twice (a closed box read 0.02 % high, CIE 171 case 5.4).
        let scale = meter.u.length() + meter.v.length() + origin.length();
        meter.tolerance = meter.tolerance.min(deviation + 1e-6 * scale);
        Ok(meter)
    }

    /// The unit normal u × v / |u × v| (the measured side).
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// Area of one cell, m².
    pub fn cell_area(&self) -> f32 {
        1.0 / (self.inv_det * self.nx as f32 * self.ny as f32)
    }

    /// World position of the centre of cell (i, j).
    pub fn cell_centre(&self, i: u32, j: u32) -> Vec3 {
        self.origin + (i as f32 + 0.5) / self.nx as f32 * self.u + (j as f32 + 0.5) / self.ny as f32 * self.v
    }

    /// How many cells have a scene surface at their centre (within twice the tolerance of the
    /// plane there). The samples estimator reads the light that lands on surfaces: a cell in the
    /// air reads zero with it whatever the light there, so a front end refuses a meter with no
    /// cell on a surface and warns of one with some.
    pub fn cells_on_surfaces(&self, scene: &Scene) -> usize {
        let reach = 2.0 * self.tolerance;
        let on_surface = |(i, j)| {
            let centre = self.cell_centre(i, j);
            scene.occluded(&Ray {
                origin: centre + reach * self.normal,
                dir: -self.normal,
                t_max: 2.0 * reach,
            })
        };
        (0..self.ny).flat_map(|j| (0..self.nx).map(move |i| (i, j))).filter(|&c| on_surface(c)).count()
    }

    /// The cell (index `j * nx + i`) holding the point, if it is on the meter.
    #[inline]
    pub fn locate(&self, x: Vec3) -> Option<usize> {
        let p = x - self.origin;
        if p.dot(self.normal).abs() > self.tolerance {
            return None;
        }
        let a = p.cross(self.v).dot(self.normal) * self.inv_det;
        let b = self.u.cross(p).dot(self.normal) * self.inv_det;
        if !(0.0..1.0).contains(&a) || !(0.0..1.0).contains(&b) {
            return None;
        }
        let i = ((a * self.nx as f32) as u32).min(self.nx - 1);
        let j = ((b * self.ny as f32) as u32).min(self.ny - 1);
        Some(j as usize * self.nx as usize + i as usize)
    }

    /// Adds the irradiance of a batch's samples to `film` (nx × ny).
    pub fn splat(&self, batch: SampleBatch<'_>, film: &mut impl SplatTarget) {
        self.splat_where(batch, film, |_| true)
    }

    /// [`IlluminanceMeter::splat`] counting only the samples whose triangle of `scene` lies
    /// parallel to the meter (within 0.8°): a sample of a surface meeting the meter's plane at
    /// an angle — a wall at a floor's edge, inside or outside — lies within the meter's band
    /// near the shared edge but is not the meter's light (it read +11 % in a corner cell of a
    /// floor under the sky, the outside of the walls counted).
    pub fn splat_on(&self, scene: &Scene, batch: SampleBatch<'_>, film: &mut impl SplatTarget) {
        self.splat_where(batch, film, |s| scene.normal(s.triangle()).dot(self.normal).abs() > PARALLEL_COS)
    }

    /// The splat loop, counting only the samples `keep` keeps.
    fn splat_where(
        &self,
        batch: SampleBatch<'_>,
        film: &mut impl SplatTarget,
        keep: impl Fn(&Sample) -> bool,
    ) {
        let scale = batch.flux_per_path / self.cell_area();
        for s in batch.samples {
            if s.is_emission() {
                continue;
            }
            let Some(cell) = self.locate(s.position()) else { continue };
            if !keep(s) {
                continue;
            }
            if s.from_dir().dot(self.normal) <= 0.0 {
                continue;
            }
            film.splat(cell, scale * s.beta());
        }
    }
}

/// The stored-samples estimator with standard errors: irradiance per cell of a meter on scene
/// geometry from `groups.len()` batches (batch i is chunk i, of light and paths `groups[i]`),
/// counting the samples of `scene`'s surfaces parallel to the meter
/// ([`IlluminanceMeter::splat_on`]), E_v by the scene's photometry
/// ([`crate::scene::Scene::photometry`]).
pub fn read_samples<B: super::AsBatch, E: Send>(
    meter: &IlluminanceMeter,
    scene: &Scene,
    groups: &[Group],
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
) -> Result<Reading, E> {
    let mut readings = read_samples_many(&[meter], scene, groups, batch, progress)?;
    Ok(readings.remove(0))
}

/// [`read_samples`] for several meters in one pass over the batches (each batch fetched once):
/// one reading per meter, in their order, each the same bit for bit as that meter read alone
/// (a target's sums see the same contributions in the same order; only the row is longer).
pub fn read_samples_many<B: super::AsBatch, E: Send>(
    meters: &[&IlluminanceMeter],
    scene: &Scene,
    groups: &[Group],
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
) -> Result<Vec<Reading>, E> {
    let lens: Vec<usize> = meters.iter().map(|m| m.nx as usize * m.ny as usize).collect();
    let (offsets, total) = tally::offsets(&lens);
    let reading = tally::tally_groups(
        total,
        scene.photometry,
        groups,
        batch,
        progress,
        |_, samples, flux_per_path, scratch| {
            for (meter, &offset) in meters.iter().zip(&offsets) {
                let row = &mut tally::Offset { row: &mut *scratch, offset };
                meter.splat_on(scene, SampleBatch { flux_per_path, samples }, row)
            }
        },
    )?;
    Ok(reading.split(&lens))
}

/// Irradiance per cell (W/m², RGB) from `count` batches, on all cores (the stored-samples
/// estimator without errors), counting the samples of `scene`'s surfaces parallel to the meter
/// as [`read_samples`] does ([`IlluminanceMeter::splat_on`]).
pub fn measure<B: super::AsBatch, E: Send>(
    meter: &IlluminanceMeter,
    scene: &Scene,
    count: usize,
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize) + Sync,
) -> Result<Film, E> {
    accumulate((meter.nx, meter.ny), count, batch, progress, &OnScene { meter, scene })
}

/// A meter counting the samples of a scene's surfaces parallel to it, as [`accumulate`] runs it.
struct OnScene<'a> {
    meter: &'a IlluminanceMeter,
    scene: &'a Scene,
}

impl Splatter for OnScene<'_> {
    #[inline]
    fn splat_batch<T: SplatTarget>(&self, batch: SampleBatch<'_>, film: &mut T) {
        self.meter.splat_on(self.scene, batch, film)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::Sample;
    use crate::math::Rgb;
    use crate::scene::MeshDesc;

    #[test]
    fn cells_are_located_and_sides_respected() {
        let m = IlluminanceMeter::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), Vec3::new(4.0, 0.0, 0.0), 2, 4)
            .unwrap();
        assert!((m.normal() - Vec3::Y).length() < 1e-6);
        assert!((m.cell_area() - 1.0).abs() < 1e-6);
        assert_eq!(m.locate(Vec3::new(3.5, 0.0, 0.5)), Some(3 * 2));
        assert_eq!(m.locate(Vec3::new(0.5, 0.0, 1.5)), Some(1));
        assert_eq!(m.locate(Vec3::new(0.5, 0.01, 1.5)), None);
        assert_eq!(m.locate(Vec3::new(-0.1, 0.0, 1.5)), None);
        let from_above = Sample::scattered(Vec3::new(0.5, 0.0, 0.5), Vec3::Y, 0, Rgb::ONE);
        let from_below = Sample::scattered(Vec3::new(0.5, 0.0, 0.5), Vec3::NEG_Y, 0, Rgb::ONE);
        let mut film = Film::new(2, 4);
        m.splat(
            SampleBatch { flux_per_path: Rgb::splat(2.0), samples: &[from_above, from_below] },
            &mut film,
        );
        assert_eq!(film.pixels[0], [2.0; 3]);
        assert_eq!(film.pixels.iter().map(|p| p[0]).sum::<f64>(), 2.0);
    }

    /// A surface meter takes the samples of its own surface only: on a floor meeting a wall at
    /// an edge, a sample on the wall 0.2 mm above the edge (within the plane meter's band of
    /// 10⁻⁴ of the edges, 0.4 mm here) is not the floor's, while the floor's own samples,
    /// rounded off its plane, still are.
    #[test]
    fn a_surface_meter_does_not_take_a_neighbouring_walls_samples() {
        let desc = SceneDescription {
            meshes: vec![MeshDesc {
                name: "floor".into(),
                positions: vec![
                    Vec3::ZERO,
                    Vec3::new(2.0, 0.0, 0.0),
                    Vec3::new(2.0, 0.0, -2.0),
                    Vec3::new(0.0, 0.0, -2.0),
                ],
                triangles: vec![[0, 1, 2], [0, 2, 3]],
                ..Default::default()
            }],
            ..Default::default()
        };
        let floor = IlluminanceMeter::on_mesh(&desc, "floor", 1, 1).unwrap();
        assert!((floor.normal() - Vec3::Y).length() < 1e-6);
        let plane = IlluminanceMeter::new(floor.origin, floor.u, floor.v, 1, 1).unwrap();
        let on_wall = Vec3::new(0.0, 2e-4, -1.0); // the wall x = 0, just above the floor
        assert_eq!(plane.locate(on_wall), Some(0), "the plane meter's band takes it");
        assert_eq!(floor.locate(on_wall), None);
        let rounded = Vec3::new(1.0, f32::EPSILON * 2.0, -1.0);
        assert_eq!(floor.locate(rounded), Some(0));
    }

    /// With the scene, a meter counts only the samples of surfaces parallel to it: on the
    /// Cornell floor, a sample of the left wall 0.1 mm above the floor's edge (inside the
    /// plane meter's band) is the wall's, not the floor's; a floor sample is the floor's.
    #[test]
    fn with_the_scene_a_meter_counts_its_own_surfaces_samples_only() {
        let scene = Scene::build(&crate::scene::cornell_box()).unwrap();
        let tri =
            |n: Vec3| (0..scene.triangles.len() as u32).find(|&t| scene.normal(t).dot(n) > 0.999).unwrap();
        let (floor_tri, wall_tri) = (tri(Vec3::Y), tri(Vec3::X));
        // The floor is y = −1 over x, z ∈ [−1, 1]; the left wall x = −1 faces +x.
        let m =
            IlluminanceMeter::new(Vec3::new(-1.0, -1.0, 1.0), 2.0 * Vec3::X, -2.0 * Vec3::Z, 1, 1).unwrap();
        let on_floor = Sample::scattered(Vec3::new(0.0, -1.0, 0.0), Vec3::Y, floor_tri, Rgb::ONE);
        let on_wall = Sample::scattered(
            Vec3::new(-1.0, -1.0 + 1e-4, 0.0),
            Vec3::new(1.0, 1.0, 0.0).normalize(),
            wall_tri,
            Rgb::ONE,
        );
        let count = |on: bool, samples: &[Sample]| {
            let mut film = Film::new(1, 1);
            let batch = SampleBatch { flux_per_path: Rgb::ONE, samples };
            if on {
                m.splat_on(&scene, batch, &mut film)
            } else {
                m.splat(batch, &mut film)
            }
            film.pixels[0][0] * m.cell_area() as f64
        };
        assert_eq!(count(false, &[on_floor, on_wall]), 2.0, "the band alone takes both");
        assert_eq!(count(true, &[on_floor, on_wall]), 1.0);
        assert_eq!(count(true, &[on_wall]), 0.0);
    }

    #[test]
    fn cells_on_surfaces_are_told_from_cells_in_the_air() {
        let scene = Scene::build(&crate::scene::cornell_box()).unwrap();
        // The floor is y = −1 over x, z ∈ [−1, 1]; this plane holds it and reaches beyond x = 1.
        let floor =
            IlluminanceMeter::new(Vec3::new(-0.9, -1.0, 0.9), Vec3::new(2.8, 0.0, 0.0), -1.8 * Vec3::Z, 4, 2);
        assert_eq!(floor.unwrap().cells_on_surfaces(&scene), 6, "three columns of four on the floor");
        let air = IlluminanceMeter::new(Vec3::new(-0.5, 0.0, 0.5), Vec3::X, -Vec3::Z, 3, 3).unwrap();
        assert_eq!(air.cells_on_surfaces(&scene), 0);
    }

    #[test]
    fn bad_meters_are_refused() {
        let (o, u, v) = (Vec3::ZERO, Vec3::X, Vec3::Z);
        assert_eq!(IlluminanceMeter::new(o, u, v, 0, 3), Err(MeterError::Cells(0, 3)));
        assert_eq!(IlluminanceMeter::new(o, u, 2.0 * u, 3, 3), Err(MeterError::Degenerate));
        assert_eq!(IlluminanceMeter::new(Vec3::splat(f32::NAN), u, v, 3, 3), Err(MeterError::Degenerate));
        let desc = SceneDescription {
            meshes: vec![MeshDesc {
                name: "bent".into(),
                positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.5)],
                triangles: vec![[0, 1, 2], [1, 3, 2]],
                ..Default::default()
            }],
            ..Default::default()
        };
        assert!(matches!(
            IlluminanceMeter::on_mesh(&desc, "nope", 2, 2),
            Err(MeterError::UnknownSurface { .. })
        ));
        assert!(matches!(IlluminanceMeter::on_mesh(&desc, "bent", 2, 2), Err(MeterError::NotPlanar { .. })));
        // A closed surface (a tetrahedron) has area, but its triangles' facing cancels: it is
        // called curved, not empty (it used to read "has no area to measure").
        let closed = SceneDescription {
            meshes: vec![MeshDesc {
                name: "tetra".into(),
                positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
                triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
                ..Default::default()
            }],
            ..Default::default()
        };
        let e = IlluminanceMeter::on_mesh(&closed, "tetra", 2, 2).unwrap_err();
        assert_eq!(e, MeterError::Curved("tetra".into()), "{e}");
        assert!(e.to_string().contains("not planar"), "{e}");
    }

    #[test]
    fn a_mesh_meter_covers_the_mesh_rectangle() {
        let desc = SceneDescription {
            meshes: vec![MeshDesc {
                name: "floor".into(),
                positions: vec![
                    Vec3::new(-1.0, 0.5, -2.0),
                    Vec3::new(-1.0, 0.5, 2.0),
                    Vec3::new(3.0, 0.5, 2.0),
                    Vec3::new(3.0, 0.5, -2.0),
                ],
                triangles: vec![[0, 1, 2], [0, 2, 3]],
                ..Default::default()
            }],
            ..Default::default()
        };
        let m = IlluminanceMeter::on_mesh(&desc, "floor", 4, 4).unwrap();
        assert!((m.normal() - Vec3::Y).length() < 1e-6);
        assert!((m.cell_area() - 1.0).abs() < 1e-5);
        assert!((m.u - Vec3::new(4.0, 0.0, 0.0)).length() < 1e-5);
        assert!(
            m.locate(Vec3::new(2.9, 0.5, 1.9)).is_some() && m.locate(Vec3::new(-0.9, 0.5, -1.9)).is_some()
        );
    }
}
