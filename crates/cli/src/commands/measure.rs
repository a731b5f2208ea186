//! `opticks measure`: an illuminance meter over a dataset — irradiance per cell of a plane
//! (a mesh by name, or a rectangle given by a corner and two edges, on a surface or in the
//! air) or at points read from a file, with a standard error per cell; written as CSV and, for
//! one plane, optionally as a heat-map PNG. `--surface` and `--plane` repeat: several meters
//! read in one pass over the dataset, one CSV with a `meter` column naming each line's meter.
//!
//! What is measured and how — the places, the two estimators and their defaults, the daylight
//! factor under a CIE overcast sky — is `opticks_io::measurement`'s (and `opticks_io::daylight`);
//! the CSV's columns and the photometric rule are `opticks_io::meter_table`'s. Only light
//! arriving from the meter's front is counted, the side its normal n = u × v faces (a mesh's
//! triangles' side; points' normals): the summary states it, and a meter lit only from behind
//! reads 0, with a warning. This verb parses the options, checks every output and the points
//! file before the dataset is read, shows progress, writes the outputs all or none and prints
//! the summary.

use super::{DatasetArgs, ThreadArgs};
use crate::camera_args::parse_vec3;
use crate::output;
use crate::progress;
use anyhow::{Context, Result, bail};
use opticks_core::math::Vec3;
use opticks_io::measurement::{
    DirectSamples, Estimator, Measured, Place, Request, meters_csv, meters_summary,
};
use opticks_io::output_paths::{OutputKind, check_outputs};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};

/// How `measure` estimates (`opticks_io::measurement::Estimator`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeterEstimator {
    /// Connect every stored sample to the meter (+ direct light of point and directional
    /// lights): anywhere, in the air too.
    Connections,
    /// Count the samples that landed on the meter: only for meters on scene geometry.
    Samples,
}

/// Arguments of `opticks measure`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: DatasetArgs,
    /// Measure on the planar mesh of this name (its bounding rectangle in its plane), on the side
    /// its triangles face. Repeat it to measure several meshes in one pass over the dataset: the
    /// CSV then starts with a `meter` column holding each line's mesh name (one mesh: no such
    /// column), and --png is refused.
    #[arg(long, conflicts_with_all = ["plane", "points"], required_unless_present_any = ["plane", "points"])]
    surface: Vec<String>,
    /// Measure on the rectangle "ox,oy,oz,ux,uy,uz,vx,vy,vz" (corner and two edges, m), on a
    /// surface or in the air. Only light arriving from its front, the side u × v points to, is
    /// counted: swap u and v to measure the other side. Repeat it for several rectangles in one
    /// pass, named plane1, plane2, … in order in the CSV's `meter` column.
    #[arg(long, allow_hyphen_values = true, conflicts_with = "points")]
    plane: Vec<String>,
    /// Measure at the points of this file: one "x,y,z,nx,ny,nz" per line (position and the
    /// normal of the measured side; commas or spaces; '#' comments and an x,y,z,nx,ny,nz header
    /// allowed).
    #[arg(long)]
    points: Option<PathBuf>,
    /// Cells "NXxNY" along u and v (planes; default 10x10).
    #[arg(long, value_parser = parse_cells)]
    cells: Option<(u32, u32)>,
    /// How to estimate: `connections` works anywhere; `samples` only on scene geometry, where it
    /// is cheaper and less noisy. Default: `samples` for --surface, `connections` otherwise.
    #[arg(long, value_enum)]
    estimator: Option<MeterEstimator>,
    /// Connections: meter points each stored sample is connected to [default: 1].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    connections: Option<u32>,
    /// Connections: how the lights' direct light is gathered. `auto` (the default): point and
    /// directional lights at 256 points per cell; an environment (sky) from directions its own
    /// pilot learns to aim where the sky is seen (through openings), and area lights from
    /// stratified points on them, each as many as give its light a standard error of 0.5 % (256
    /// to 2^20 a point or cell). N (2 to 1000000): N points per cell, N sky directions and N
    /// points on the area lights each.
    #[arg(long, value_name = "auto|N", value_parser = parse_direct_samples)]
    direct_samples: Option<DirectSamples>,
    /// Connections: seed of the meter's random streams [default: 0].
    #[arg(long)]
    seed: Option<u64>,
    /// Output CSV file (.csv).
    #[arg(short, long)]
    output: PathBuf,
    /// Also write a heat-map PNG (.png) of the illuminance (lux); one plane or surface only.
    #[arg(long)]
    png: Option<PathBuf>,
    /// Require the daylight factor: refuse a dataset whose lights on are not a CIE overcast
    /// sky (`!gensky … -c`) alone. Without it, DF_percent and SE_DF_percent columns (DF = 100 ×
    /// E_v / E_v,h, E_v,h the sky's horizontal illuminance in the open, no ground) are added
    /// whenever that holds; a sun or other light on (switch it off with --light NAME=0) means
    /// none.
    #[arg(long)]
    daylight_factor: bool,
    #[command(flatten)]
    threads: ThreadArgs,
}

/// Parses `--direct-samples auto|N` (N from 2 to 1000000).
fn parse_direct_samples(s: &str) -> Result<DirectSamples> {
    if s.trim().eq_ignore_ascii_case("auto") {
        return Ok(DirectSamples::Auto);
    }
    match s.trim().parse::<u32>() {
        Ok(n) if (2..=1_000_000).contains(&n) => Ok(DirectSamples::Count(n)),
        _ => bail!("'{s}' must be auto or a count from 2 to 1000000"),
    }
}

/// Parses "NXxNY" cell counts (1..=65536 in all).
fn parse_cells(s: &str) -> Result<(u32, u32)> {
    let (x, y) = s.split_once(['x', 'X']).with_context(|| format!("'{s}' must look like 10x8"))?;
    let (x, y): (u32, u32) = (
        x.trim().parse().with_context(|| format!("'{s}': '{x}' is not a cell count"))?,
        y.trim().parse().with_context(|| format!("'{s}': '{y}' is not a cell count"))?,
    );
    let max = opticks_core::sensor::meter::MAX_TARGETS as u64;
    if x == 0 || y == 0 || x as u64 * y as u64 > max {
        bail!("{x}x{y} cells: each count must be between 1 and 65536, and at most {max} cells in all");
    }
    Ok((x, y))
}

/// Parses "ox,oy,oz,ux,uy,uz,vx,vy,vz" into (origin, u, v).
fn parse_plane(s: &str) -> Result<(Vec3, Vec3, Vec3)> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 9 {
        bail!("--plane '{s}' must be nine comma-separated numbers: corner x,y,z, edge u x,y,z, edge v x,y,z");
    }
    let v =
        |k: usize| parse_vec3(&parts[3 * k..3 * k + 3].join(",")).with_context(|| format!("--plane '{s}'"));
    Ok((v(0)?, v(1)?, v(2)?))
}

/// Runs the measurement.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    let mut places: Vec<Place> = a.surface.iter().map(|name| Place::Surface(name.clone())).collect();
    for p in &a.plane {
        let (origin, u, v) = parse_plane(p)?;
        places.push(Place::Plane { origin, u, v });
    }
    if a.points.is_some() {
        places.push(Place::Points(Vec::new()));
    }
    let mut request = Request {
        places,
        cells: a.cells,
        estimator: a.estimator.map(|e| match e {
            MeterEstimator::Connections => Estimator::Connections,
            MeterEstimator::Samples => Estimator::Samples,
        }),
        connections: a.connections,
        direct_samples: a.direct_samples,
        seed: a.seed,
        heatmap: a.png.is_some(),
        daylight_factor: a.daylight_factor,
    };
    let estimator = request.check()?;
    let mut outputs = vec![(a.output.as_path(), OutputKind::Csv)];
    outputs.extend(a.png.as_deref().map(|p| (p, OutputKind::Png)));
    let mut inputs = a.input.inputs();
    inputs.extend(a.points.as_deref());
    check_outputs(&outputs, &inputs)?;
    if let Some(p) = &a.points {
        request.places = vec![Place::Points(opticks_io::meter_points::read_points(p)?)];
    }
    let data = a.input.open()?;
    // Again, now that the files the scene names have been read (textures, environment maps).
    check_outputs(&outputs, &inputs)?;
    let mut layouts = Vec::with_capacity(request.places.len());
    for k in 0..request.places.len() {
        let plane = |e: opticks_io::measurement::RequestError| match request.places[k] {
            Place::Plane { .. } => anyhow::Error::from(e).context(format!("--plane '{}'", a.plane[k])),
            _ => e.into(),
        };
        let (layout, warning) = request.layout(k, &data).map_err(plane)?;
        warning.iter().for_each(|w| output::warning(w));
        layouts.push(layout);
    }
    let (daylight, note) = request.daylight(&data).context("--daylight-factor")?;
    note.iter().for_each(|n| output::note(n));
    // Per cell: its lux value and its CSV line (about 120 characters, 150 with DF).
    let line = if daylight.is_some() { 160 } else { 128 };
    let targets: usize = layouts.iter().map(|l| l.len()).sum();
    super::check_film_fits("a meter", (targets as u32, 1), 8 + line)?;
    let _graceful = crate::interrupt::graceful();
    let pb = progress::bar(data.samples(), "measuring", "samples");
    let done = AtomicU64::new(0);
    let progress = |n: usize| pb.set_position(done.fetch_add(n as u64, Ordering::Relaxed) + n as u64);
    let layout_refs: Vec<_> = layouts.iter().collect();
    let settings = request.settings()?;
    let readings = data.measure_many(&layout_refs, settings, progress, crate::interrupt::requested)?;
    pb.finish_and_clear();
    let meters: Vec<(String, Measured)> = layouts
        .iter()
        .zip(&readings)
        .enumerate()
        .map(|(k, (layout, reading))| {
            let measured = Measured {
                layout,
                reading,
                estimator,
                daylight: daylight.as_ref(),
                photometry: data.scene().photometry,
            };
            (request.meter_name(k), measured)
        })
        .collect();
    for (name, measured) in &meters {
        let front = match meters.len() {
            1 => format!("meter's front ({})", measured.side()),
            _ => format!("front of meter {name} ({})", measured.side()),
        };
        super::warn_if_black(measured.is_black(), data.samples(), &front, data.flux_per_path());
    }

    let csv = meters_csv(&meters);
    let heatmap = match (&a.png, meters.as_slice()) {
        (Some(png), [(_, measured)]) => measured.heatmap(png)?,
        _ => None,
    };
    let mut files = vec![(a.output.as_path(), csv.as_bytes())];
    if let (Some(png), Some(bytes)) = (&a.png, &heatmap) {
        files.push((png.as_path(), bytes.as_slice()));
    }
    let removed = opticks_io::image_file::write_files_atomically(&files).context("nothing was written")?;
    super::note_removed_stale(&removed);
    let png = a.png.as_ref().map(|p| format!(" and {}", p.display())).unwrap_or_default();
    for line in meters_summary(&meters, &format!("{}{png}", a.output.display())) {
        output::result(&line);
    }
    if meters.iter().any(|(_, m)| m.errors_unknown()) {
        output::warning(
            "some standard errors are unknown (NaN): a light with a single chunk of paths gives no \
             spread to estimate them from; trace more paths",
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planes_parse_or_explain() {
        let (o, u, v) = parse_plane("0,1,2, 3,0,0, 0,0,-4").unwrap();
        assert_eq!((o, u, v), (Vec3::new(0.0, 1.0, 2.0), Vec3::X * 3.0, Vec3::Z * -4.0));
        assert!(parse_plane("0,1,2").is_err());
        assert!(parse_plane("0,1,2,3,0,0,0,0,x").is_err());
        assert!(parse_plane("0,1,2,3,0,0,0,0,inf").is_err());
        assert_eq!(parse_cells("12x3").unwrap(), (12, 3));
        assert!(parse_cells("0x3").is_err() && parse_cells("3").is_err() && parse_cells("ax3").is_err());
    }
}
