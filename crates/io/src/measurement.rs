//! A measurement as a front end asks for it (`opticks measure`, a binding): where — a mesh, a
//! rectangle on a surface or in the air, or points; several meshes or several rectangles at once
//! — in how many cells, with which estimator and its settings. [`Request::check`] refuses, before any work, the combinations that cannot mean
//! anything; [`Request::layout`] places the meter in an opened dataset's scene; the reading
//! ([`crate::opened::LitDataset::measure`]) then comes back as a [`Measured`], which gives the
//! CSV table ([`crate::meter_table`]), the heat map ([`crate::heatmap`]) and the summary a front
//! end prints.
//!
//! Defaults are the command line's: 10×10 cells; the `samples` estimator on a mesh (on scene
//! geometry it is several times cheaper and less noisy) and `connections` elsewhere, with one
//! connection per stored sample, 256 direct-light points per cell for point and directional
//! lights, an environment's direct light by its guided sampler and the area lights' by
//! stratified points on them, each to an SE of 0.5 % (`direct_samples` `None`;
//! `opticks_core::sensor::meter`'s `sky.rs` and `area.rs`) and seed 0.
//!
//! **Several meters.** A request may place several meters of one kind (meshes, or rectangles),
//! read in one pass over the dataset ([`crate::opened::LitDataset::measure_many`]), each reading
//! the same bit for bit as that meter measured alone. Each is named ([`Request::meter_name`]: a
//! mesh by its name, a rectangle `plane1`, `plane2`, … in order) and the CSV of several
//! ([`meters_csv`]) has that name first, in a `meter` column; one meter's CSV is the single
//! meter's table, unchanged. A heat map is refused with several meters (one PNG is one meter's).
//!
//! **Daylight factor.** Whenever the lights on are a CIE overcast sky alone
//! ([`crate::daylight`]), [`Request::daylight`] gives the basis and the reading comes with the
//! daylight factor per target (CSV columns `DF_percent`, `SE_DF_percent`, appended) and its
//! range in the summary; otherwise none, with a note when the scene has such a sky but other
//! lights are on. [`Request::daylight_factor`] makes the DF a requirement: a dataset that
//! cannot give one is then refused before any work, saying why.

use crate::daylight::{DaylightBasis, DaylightError, daylight_basis};
use crate::heatmap::{HeatmapError, encode_heatmap};
use crate::opened::LitDataset;
use opticks_core::math::Vec3;
use opticks_core::scene::Photometry;
use opticks_core::sensor::IlluminanceMeter;
use opticks_core::sensor::meter::{self, ConnectedSettings, MeterError, MeterLayout, MeterPoint, Reading};
use std::path::Path;

/// Where the meter is.
#[derive(Clone, Debug)]
pub enum Place {
    /// On the planar mesh of this name (its bounding rectangle in its plane), on the side its
    /// triangles face.
    Surface(String),
    /// On the rectangle with this corner and edges (m); its front is the side u × v faces.
    Plane {
        /// A corner.
        origin: Vec3,
        /// The first edge (cells along it are `i`).
        u: Vec3,
        /// The second edge (`j`).
        v: Vec3,
    },
    /// At these points, each facing its normal.
    Points(Vec<MeterPoint>),
}

/// How a meter estimates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Estimator {
    /// Connect every stored sample to the meter (+ direct light of point and directional
    /// lights): anywhere, in the air too.
    Connections,
    /// Count the samples that landed on the meter: only for meters on scene geometry.
    Samples,
}

impl Estimator {
    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Estimator::Connections => "connections",
            Estimator::Samples => "samples",
        }
    }
}

/// A measurement asked for; unset settings take the defaults in the module docs.
#[derive(Clone, Debug)]
pub struct Request {
    /// Where: one meter per place, all read in one pass; at least one, and several only of
    /// meshes or of rectangles ([`Request::check`]).
    pub places: Vec<Place>,
    /// Cells along u and v (planes).
    pub cells: Option<(u32, u32)>,
    /// The estimator.
    pub estimator: Option<Estimator>,
    /// Connections: meter points each stored sample is connected to.
    pub connections: Option<u32>,
    /// Connections: points per cell gathering the direct light of point and directional lights,
    /// and directions per target for environments; `None` (not given) or
    /// [`DirectSamples::Auto`]: the defaults (256 points; as many directions as the sky's pilot
    /// asks for). Given at all, even as `Auto`, it is refused with the samples estimator.
    pub direct_samples: Option<DirectSamples>,
    /// Connections: seed of the meter's random streams.
    pub seed: Option<u64>,
    /// Whether a heat map is wanted (planes only).
    pub heatmap: bool,
    /// Whether the daylight factor is required (an error if the dataset cannot give one; it
    /// is reported anyway whenever it can).
    pub daylight_factor: bool,
}

/// `--direct-samples` as given: `auto` (the defaults, by name) or a count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectSamples {
    /// The defaults.
    Auto,
    /// This many points per cell and sky directions per target.
    Count(u32),
}

impl DirectSamples {
    /// The count, `None` for the defaults.
    pub fn count(self) -> Option<u32> {
        match self {
            DirectSamples::Auto => None,
            DirectSamples::Count(n) => Some(n),
        }
    }
}

/// A measurement that cannot be made as asked.
#[derive(Debug, thiserror::Error)]
pub enum RequestError {
    /// A setting of the connections estimator given to the samples estimator.
    #[error(
        "{0} applies to --estimator connections; --estimator samples counts the stored samples as they are"
    )]
    ConnectionsOnly(&'static str),
    /// Cells asked of points.
    #[error("--cells is for planes; with --points every point is one cell")]
    CellsAtPoints,
    /// No place given.
    #[error("no meter: give --surface, --plane or --points")]
    NoMeter,
    /// Several places of different kinds, or points among several.
    #[error("several meters must be all --surface or all --plane (one --points file holds every point)")]
    MixedMeters,
    /// The same mesh named twice.
    #[error("--surface {0} is given twice")]
    SurfaceTwice(String),
    /// A heat map asked of several meters.
    #[error(
        "--png draws one meter's heat map, and {0} meters were given: measure one --surface or --plane per \
         run for its map (the CSV has every meter)"
    )]
    HeatmapOfSeveral(usize),
    /// A heat map asked of points.
    #[error("--png draws a plane's heat map; points have none (the CSV has every point)")]
    HeatmapOfPoints,
    /// The samples estimator asked to read points.
    #[error(
        "--estimator samples counts samples landing on a surface and cannot read points: use connections"
    )]
    SamplesAtPoints,
    /// The samples estimator asked to read a plane on no surface.
    #[error(
        "the plane lies on no scene surface, and --estimator samples reads only the light landing on surfaces: \
         measure the light crossing it with --estimator connections (a plane's default)"
    )]
    PlaneOffSurfaces,
    /// The meter cannot be placed.
    #[error(transparent)]
    Meter(#[from] MeterError),
    /// The daylight factor was required and the dataset, as lit, gives none.
    #[error(transparent)]
    Daylight(#[from] DaylightError),
}

impl Request {
    /// Refuses the combinations that mean nothing; the estimator to use.
    pub fn check(&self) -> Result<Estimator, RequestError> {
        let first = self.places.first().ok_or(RequestError::NoMeter)?;
        let kind = std::mem::discriminant(first);
        if self.places.len() > 1 {
            if matches!(first, Place::Points(_))
                || self.places.iter().any(|p| std::mem::discriminant(p) != kind)
            {
                return Err(RequestError::MixedMeters);
            }
            for (k, place) in self.places.iter().enumerate() {
                if let Place::Surface(name) = place
                    && self.places[..k].iter().any(|p| matches!(p, Place::Surface(n) if n == name))
                {
                    return Err(RequestError::SurfaceTwice(name.clone()));
                }
            }
            if self.heatmap {
                return Err(RequestError::HeatmapOfSeveral(self.places.len()));
            }
        }
        let points = matches!(first, Place::Points(_));
        let estimator = self.estimator.unwrap_or(match first {
            Place::Surface(_) => Estimator::Samples,
            _ => Estimator::Connections,
        });
        if estimator == Estimator::Samples {
            let given = [
                ("--connections", self.connections.is_some()),
                ("--direct-samples", self.direct_samples.is_some()),
                ("--seed", self.seed.is_some()),
            ];
            if let Some((name, _)) = given.iter().find(|g| g.1) {
                return Err(RequestError::ConnectionsOnly(name));
            }
        }
        match (points, self.cells.is_some(), self.heatmap, estimator) {
            (true, true, _, _) => Err(RequestError::CellsAtPoints),
            (true, _, true, _) => Err(RequestError::HeatmapOfPoints),
            (true, _, _, Estimator::Samples) => Err(RequestError::SamplesAtPoints),
            _ => Ok(estimator),
        }
    }

    /// Cells along u and v (10×10 unless given).
    pub fn cells(&self) -> (u32, u32) {
        self.cells.unwrap_or((10, 10))
    }

    /// The name of meter `k` (of [`Request::places`]): a mesh's name, `plane1`, `plane2`, … for
    /// rectangles (counted from 1), `points` for points.
    pub fn meter_name(&self, k: usize) -> String {
        match &self.places[k] {
            Place::Surface(name) => name.clone(),
            Place::Plane { .. } => format!("plane{}", k + 1),
            Place::Points(_) => "points".into(),
        }
    }

    /// Meter `k` (of [`Request::places`]) placed in `data`'s scene, and a warning when the
    /// samples estimator reads a plane only partly on scene surfaces (zero elsewhere), naming
    /// the meter when there are several.
    pub fn layout(&self, k: usize, data: &LitDataset) -> Result<(MeterLayout, Option<String>), RequestError> {
        let estimator = self.check()?;
        let (nx, ny) = self.cells();
        let place = &self.places[k];
        let layout = match place {
            Place::Points(points) => MeterLayout::points(points.clone())?,
            Place::Surface(name) => {
                MeterLayout::Grid(IlluminanceMeter::on_mesh(data.description(), name, nx, ny)?)
            }
            Place::Plane { origin, u, v } => {
                MeterLayout::Grid(IlluminanceMeter::new(*origin, *u, *v, nx, ny)?)
            }
        };
        let mut warning = None;
        if let (MeterLayout::Grid(m), Place::Plane { .. }, Estimator::Samples) = (&layout, place, estimator) {
            let (on, cells) = (m.cells_on_surfaces(data.scene()), layout.len());
            if on == 0 {
                return Err(RequestError::PlaneOffSurfaces);
            }
            if on < cells {
                let of =
                    if self.places.len() > 1 { format!(" ({})", self.meter_name(k)) } else { String::new() };
                warning = Some(format!(
                    "{} of the {cells} cells of the plane{of} lie on no scene surface: --estimator samples \
                     reads zero there (--estimator connections measures them)",
                    cells - on
                ));
            }
        }
        Ok((layout, warning))
    }

    /// The daylight factor's basis, if the dataset as lit gives one ([`crate::daylight`]), and
    /// a note when it gives none though its scene has a CIE overcast sky (other lights on).
    /// Refused ([`RequestError::Daylight`]) when [`Request::daylight_factor`] requires one.
    pub fn daylight(
        &self,
        data: &LitDataset,
    ) -> Result<(Option<DaylightBasis>, Option<String>), RequestError> {
        match daylight_basis(data) {
            Ok(basis) => Ok((Some(basis), None)),
            Err(e) if self.daylight_factor => Err(e.into()),
            Err(e) if e.worth_a_note() => Ok((None, Some(format!("{e} (no DF columns)")))),
            Err(_) => Ok((None, None)),
        }
    }

    /// The estimator with its settings, for [`crate::opened::LitDataset::measure`].
    pub fn settings(&self) -> Result<meter::MeterEstimator, RequestError> {
        Ok(match self.check()? {
            Estimator::Samples => meter::MeterEstimator::Samples,
            Estimator::Connections => meter::MeterEstimator::Connections(ConnectedSettings {
                connections: self.connections.unwrap_or(1),
                direct_samples: self.direct_samples.and_then(DirectSamples::count),
                seed: self.seed.unwrap_or(0),
            }),
        })
    }
}

/// A reading with its meter: what a front end writes and says of it.
pub struct Measured<'a> {
    /// The meter.
    pub layout: &'a MeterLayout,
    /// Its reading.
    pub reading: &'a Reading,
    /// The estimator it was read with.
    pub estimator: Estimator,
    /// The daylight factor's basis, if reported ([`Request::daylight`]).
    pub daylight: Option<&'a DaylightBasis>,
    /// The rule the E_v values were read by: the scene's (`opticks_core::scene::Scene::photometry`).
    pub photometry: Photometry,
}

impl Measured<'_> {
    /// The CSV table ([`crate::meter_table::csv`]); several meters' is [`meters_csv`].
    pub fn csv(&self) -> String {
        crate::meter_table::csv(self.layout, self.reading, self.daylight.map(|d| d.horizontal_lux))
    }

    /// The PNG heat map of the illuminance (lux) for `path`, if the meter is a plane.
    pub fn heatmap(&self, path: &Path) -> Result<Option<Vec<u8>>, HeatmapError> {
        let MeterLayout::Grid(m) = self.layout else { return Ok(None) };
        let lux: Vec<f64> = self.reading.value.iter().map(|v| v[3]).collect();
        let (u, v) = (m.u.length() as f64, m.v.length() as f64);
        encode_heatmap(path, &lux, m.nx, m.ny, u, v, &heatmap_title(self.photometry)).map(Some)
    }

    /// Whether nothing reached the meter's front.
    pub fn is_black(&self) -> bool {
        self.reading.value.iter().all(|v| v[..3].iter().all(|&x| x == 0.0))
    }

    /// Which side is measured, said so the user can measure the other.
    pub fn side(&self) -> String {
        match self.layout {
            MeterLayout::Grid(m) => {
                let n = m.normal();
                format!("normal {:.3},{:.3},{:.3}; to measure the other side, swap u and v", n.x, n.y, n.z)
            }
            MeterLayout::Points(_) => "points' normals".into(),
        }
    }

    /// The summary: what was measured, mean irradiance and the range of illuminance, then the
    /// relative standard errors if any target was lit, and the daylight factor's range if
    /// reported. `written` names the outputs.
    pub fn summary(&self, written: &str) -> Vec<String> {
        let n = self.reading.value.len().max(1) as f64;
        let mut mean = [0.0f64; 3];
        for v in &self.reading.value {
            for c in 0..3 {
                mean[c] += v[c];
            }
        }
        let mean = mean.map(|m| m / n);
        let lux = self.reading.value.iter().map(|v| v[3]);
        let (min, max) = lux.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        let what = match self.layout {
            MeterLayout::Grid(m) => {
                let n = m.normal();
                let area = (m.cell_area() as f64) * (m.nx * m.ny) as f64;
                format!(
                    "{}x{} cells on {area:.4} m², front side (light arriving from normal {:.3},{:.3},{:.3})",
                    m.nx, m.ny, n.x, n.y, n.z
                )
            }
            MeterLayout::Points(p) => format!("{} points, each facing its normal", p.len()),
        };
        let mut lines = vec![format!(
            "{what}: mean E = {:.5e},{:.5e},{:.5e} W/m², E_v {min:.4e}..{max:.4e} lux ({}) → {written}",
            mean[0], mean[1], mean[2], self.photometry.name
        )];
        let (rel_max, rel_mean, lit) = self.reading.relative_error();
        if lit > 0 {
            lines.push(format!(
                "relative standard error of E_v over the {lit} lit {}: max {:.3} %, mean {:.3} % ({} estimator)",
                if self.layout.is_point() { "points" } else { "cells" },
                100.0 * rel_max,
                100.0 * rel_mean,
                self.estimator.name()
            ));
        }
        if let Some(d) = self.daylight {
            let df: Vec<f64> = self.reading.value.iter().map(|v| d.percent(v[3])).collect();
            let (lo, hi) =
                df.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
            let mean = df.iter().sum::<f64>() / df.len().max(1) as f64;
            lines.push(format!(
                "daylight factor under the CIE overcast sky ({}; E_v,h = {:.4e} lux in the open): DF min {lo:.3} %, \
                 mean {mean:.3} %, max {hi:.3} %",
                d.skies.join(", "),
                d.horizontal_lux
            ));
        }
        lines
    }

    /// Whether some standard errors are unknown (a light with a single chunk of paths).
    pub fn errors_unknown(&self) -> bool {
        self.reading.relative_error().0.is_nan()
    }
}

/// The CSV table of several meters read together, each given with its name
/// ([`Request::meter_name`]): one meter's is its own table ([`Measured::csv`], unchanged), several
/// meters' the same columns after a first `meter` column naming each line's meter
/// ([`crate::meter_table::csv_of_meters`]).
pub fn meters_csv(meters: &[(String, Measured<'_>)]) -> String {
    match meters {
        [(_, one)] => one.csv(),
        _ => {
            let daylight = meters.first().and_then(|(_, m)| m.daylight).map(|d| d.horizontal_lux);
            let tables: Vec<_> =
                meters.iter().map(|(name, m)| (name.as_str(), m.layout, m.reading)).collect();
            crate::meter_table::csv_of_meters(&tables, daylight)
        }
    }
}

/// The summary of several meters read together ([`meters_csv`]'s): one meter's is its own
/// ([`Measured::summary`]); several meters' are each meter's lines, its first line led by its
/// name.
pub fn meters_summary(meters: &[(String, Measured<'_>)], written: &str) -> Vec<String> {
    match meters {
        [(_, one)] => one.summary(written),
        _ => meters
            .iter()
            .flat_map(|(name, m)| {
                let mut lines = m.summary(written);
                lines[0] = format!("{name}: {}", lines[0]);
                lines
            })
            .collect(),
    }
}

/// The heat map's title: "E (lux)" by the default rule, with the efficacy after it by another
/// ("E (lux) 179 lm/W" for a Radiance scene; the map's font has no comma).
fn heatmap_title(photometry: Photometry) -> String {
    if photometry == Photometry::REC709_683 {
        "E (lux)".into()
    } else {
        format!("E (lux) {} lm/W", photometry.efficacy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_heat_map_title_names_a_rule_other_than_the_default() {
        assert_eq!(heatmap_title(Photometry::REC709_683), "E (lux)");
        assert_eq!(heatmap_title(Photometry::RADIANCE), "E (lux) 179 lm/W");
    }

    /// Several meters are of one kind, each mesh once, with no heat map; one meter keeps every
    /// request it had (a heat map of a plane included).
    #[test]
    fn several_meters_are_checked_before_any_work() {
        let plane = Place::Plane { origin: Vec3::ZERO, u: Vec3::X, v: Vec3::Y };
        let surface = |n: &str| Place::Surface(n.into());
        let request = |places: Vec<Place>, heatmap: bool| Request {
            places,
            cells: None,
            estimator: None,
            connections: None,
            direct_samples: None,
            seed: None,
            heatmap,
            daylight_factor: false,
        };
        let err = |places, heatmap| request(places, heatmap).check().unwrap_err().to_string();
        assert!(err(vec![], false).contains("no meter"));
        assert!(err(vec![surface("a"), plane.clone()], false).contains("all --surface or all --plane"));
        assert!(err(vec![Place::Points(vec![]), Place::Points(vec![])], false).contains("one --points file"));
        assert!(
            err(vec![surface("a"), surface("b"), surface("a")], false).contains("--surface a is given twice")
        );
        assert!(err(vec![plane.clone(), plane.clone()], true).contains("2 meters were given"));
        assert_eq!(request(vec![surface("a"), surface("b")], false).check().unwrap(), Estimator::Samples);
        assert_eq!(
            request(vec![plane.clone(), plane.clone()], false).check().unwrap(),
            Estimator::Connections
        );
        assert_eq!(request(vec![plane], true).check().unwrap(), Estimator::Connections);
        let names = request(vec![Place::Plane { origin: Vec3::ZERO, u: Vec3::X, v: Vec3::Y }; 2], false);
        assert_eq!((names.meter_name(0), names.meter_name(1)), ("plane1".into(), "plane2".into()));
    }
}
