//! `opticks measure`: an illuminance meter over a dataset — irradiance per cell of a plane
//! (a mesh by name, or a rectangle given by a corner and two edges, on a surface or in the
//! air) or at points read from a file, with a standard error per cell; written as CSV and, for
//! planes, optionally as a heat-map PNG.
//!
//! CSV columns, planes: `i,j` (cell along u and v), `x,y,z` (cell centre, m); points: `point`
//! (its index in the file, from 0), `x,y,z`, `nx,ny,nz` (the unit normal); then `E_R,E_G,E_B`
//! (irradiance, W/m² per RGB channel), `E_v_lux`, and their standard errors
//! `SE_R,SE_G,SE_B,SE_v_lux` (from the dataset's independent chunks; `NaN` where a light has a
//! single chunk). The photometric column uses E_v = 683 lm/W · (0.2126·E_R + 0.7152·E_G +
//! 0.0722·E_B) (`opticks_core::sensor::meter::lux`): the Rec. 709 luminance weights with the
//! 555 nm luminous efficacy, an approximation — exact only if the RGB channels were radiometric
//! quantities with the spectral shapes the weights assume. The PNG shows E_v.
//!
//! Estimators (`--estimator`): `connections` works anywhere — every stored sample connected to
//! `--connections` uniform points of the meter, plus the direct light of point and directional
//! lights gathered at `--direct-samples` points per cell; `samples` counts the samples that
//! landed on the meter and so only reads meters on scene geometry, where it is several times
//! cheaper and less noisy (measured in docs/guide.md, "Sensors"). `--surface` uses `samples`,
//! `--plane` and `--points` `connections`, unless `--estimator` says otherwise
//! (`opticks_core::sensor::meter`).
//!
//! Orientation: only light arriving from the meter's front is counted — the side its normal
//! n = u × v faces (for `--surface`, the side the mesh's triangles face; for points, their
//! normal). The summary line states the normal; a meter lit only from behind reads 0, with a
//! warning.
//!
//! The scene is resolved and checked against the dataset as `opticks render` does. Every output
//! and the points file are checked before the dataset is read; outputs are written all or none.

use super::{DatasetArgs, ThreadArgs};
use crate::camera_args::parse_vec3;
use crate::output;
use crate::progress;
use anyhow::{Context, Result, bail};
use opticks_core::film::Film;
use opticks_core::math::Vec3;
use opticks_core::sensor::IlluminanceMeter;
use opticks_core::sensor::meter::{self, ConnectedSettings, MeterLayout};
use opticks_io::output_paths::{OutputKind, check_outputs};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};

/// How `measure` estimates.
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
    /// its triangles face.
    #[arg(long, conflicts_with_all = ["plane", "points"], required_unless_present_any = ["plane", "points"])]
    surface: Option<String>,
    /// Measure on the rectangle "ox,oy,oz,ux,uy,uz,vx,vy,vz" (corner and two edges, m), on a
    /// surface or in the air. Only light arriving from its front, the side u × v points to, is
    /// counted: swap u and v to measure the other side.
    #[arg(long, allow_hyphen_values = true, conflicts_with = "points")]
    plane: Option<String>,
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
    /// Connections: points per cell at which the direct light of point and directional lights
    /// is gathered [default: 256].
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..=1_000_000))]
    direct_samples: Option<u32>,
    /// Connections: seed of the meter's random streams [default: 0].
    #[arg(long)]
    seed: Option<u64>,
    /// Output CSV file (.csv).
    #[arg(short, long)]
    output: PathBuf,
    /// Also write a heat-map PNG (.png) of the illuminance (lux); planes only.
    #[arg(long)]
    png: Option<PathBuf>,
    #[command(flatten)]
    threads: ThreadArgs,
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
    let estimator = a.estimator.unwrap_or(match a.surface {
        Some(_) => MeterEstimator::Samples,
        None => MeterEstimator::Connections,
    });
    if estimator == MeterEstimator::Samples {
        let given = [
            ("--connections", a.connections.is_some()),
            ("--direct-samples", a.direct_samples.is_some()),
            ("--seed", a.seed.is_some()),
        ];
        if let Some((name, _)) = given.iter().find(|g| g.1) {
            bail!(
                "{name} applies to --estimator connections; --estimator samples counts the stored samples as they are"
            );
        }
    }
    if a.points.is_some() {
        if a.cells.is_some() {
            bail!("--cells is for planes; with --points every point is one cell");
        }
        if a.png.is_some() {
            bail!("--png draws a plane's heat map; points have none (the CSV has every point)");
        }
        if estimator == MeterEstimator::Samples {
            bail!(
                "--estimator samples counts samples landing on a surface and cannot read points: use connections"
            );
        }
    }
    let mut outputs = vec![(a.output.as_path(), OutputKind::Csv)];
    outputs.extend(a.png.as_deref().map(|p| (p, OutputKind::Png)));
    let mut inputs = a.input.inputs();
    inputs.extend(a.points.as_deref());
    check_outputs(&outputs, &inputs)?;
    let points = match &a.points {
        Some(p) => Some(MeterLayout::points(opticks_io::meter_points::read_points(p)?)?),
        None => None,
    };
    let data = a.input.open()?;
    // Again, now that the files the scene names have been read (textures, environment maps).
    check_outputs(&outputs, &inputs)?;
    let desc = data.description();
    let (nx, ny) = a.cells.unwrap_or((10, 10));
    let layout = match (&a.surface, &a.plane, points) {
        (_, _, Some(points)) => points,
        (Some(name), _, _) => MeterLayout::Grid(IlluminanceMeter::on_mesh(desc, name, nx, ny)?),
        (None, Some(p), _) => {
            let (o, u, v) = parse_plane(p)?;
            MeterLayout::Grid(
                IlluminanceMeter::new(o, u, v, nx, ny).with_context(|| format!("--plane '{p}'"))?,
            )
        }
        (None, None, None) => {
            bail!("give --surface NAME, --plane ox,oy,oz,ux,uy,uz,vx,vy,vz or --points FILE")
        }
    };
    // Per cell: its lux value and its CSV line (about 120 characters).
    super::check_film_fits("a meter", (layout.len() as u32, 1), 8 + 128)?;
    // Counting the samples on a plane reads only where the plane lies on a surface.
    if let (MeterLayout::Grid(m), Some(p), MeterEstimator::Samples) = (&layout, &a.plane, estimator) {
        let (on, cells) = (m.cells_on_surfaces(data.scene()), layout.len());
        if on == 0 {
            bail!(
                "--plane '{p}' lies on no scene surface, and --estimator samples reads only the light landing \
                 on surfaces: measure the light crossing it with --estimator connections (a plane's default)"
            );
        }
        if on < cells {
            output::warning(&format!(
                "{} of the {cells} cells of --plane '{p}' lie on no scene surface: --estimator samples reads \
                 zero there (--estimator connections measures them)",
                cells - on
            ));
        }
    }
    let _graceful = crate::interrupt::graceful();
    let pb = progress::bar(data.samples(), "measuring", "samples");
    let done = AtomicU64::new(0);
    let progress = |n: usize| pb.set_position(done.fetch_add(n as u64, Ordering::Relaxed) + n as u64);
    let how = match estimator {
        MeterEstimator::Samples => meter::MeterEstimator::Samples,
        MeterEstimator::Connections => meter::MeterEstimator::Connections(ConnectedSettings {
            connections: a.connections.unwrap_or(1),
            direct_samples: a.direct_samples.unwrap_or(256),
            seed: a.seed.unwrap_or(0),
        }),
    };
    let reading = data.measure(&layout, how, progress, crate::interrupt::requested)?;
    pb.finish_and_clear();
    let side = match &layout {
        MeterLayout::Grid(m) => {
            let n = m.normal();
            format!("normal {:.3},{:.3},{:.3}; to measure the other side, swap u and v", n.x, n.y, n.z)
        }
        MeterLayout::Points(_) => "points' normals".into(),
    };
    let mut film = Film::new(layout.len() as u32, 1);
    for (p, v) in film.pixels.iter_mut().zip(&reading.value) {
        *p = [v[0], v[1], v[2]];
    }
    super::warn_if_black(&film, data.samples(), &format!("meter's front ({side})"), data.flux_per_path());

    let csv = opticks_io::meter_table::csv(&layout, &reading);
    let lux: Vec<f64> = reading.value.iter().map(|v| v[3]).collect();
    let heatmap = match (&a.png, &layout) {
        (Some(png), MeterLayout::Grid(m)) => Some(opticks_io::heatmap::encode_heatmap(
            png,
            &lux,
            nx,
            ny,
            m.u.length() as f64,
            m.v.length() as f64,
            "E (lux)",
        )?),
        _ => None,
    };
    let mut files = vec![(a.output.as_path(), csv.as_bytes())];
    if let (Some(png), Some(bytes)) = (&a.png, &heatmap) {
        files.push((png.as_path(), bytes.as_slice()));
    }
    let removed = opticks_io::image_file::write_files_atomically(&files).context("nothing was written")?;
    super::note_removed_stale(&removed);
    let mean = film.mean();
    let (min, max) = lux.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    let what = match &layout {
        MeterLayout::Grid(m) => {
            let n = m.normal();
            let area = (m.cell_area() as f64) * (nx * ny) as f64;
            format!(
                "{nx}x{ny} cells on {area:.4} m², front side (light arriving from normal {:.3},{:.3},{:.3})",
                n.x, n.y, n.z
            )
        }
        MeterLayout::Points(p) => format!("{} points, each facing its normal", p.len()),
    };
    output::result(&format!(
        "{what}: mean E = {:.5e},{:.5e},{:.5e} W/m², E_v {min:.4e}..{max:.4e} lux → {}{}",
        mean[0],
        mean[1],
        mean[2],
        a.output.display(),
        a.png.as_ref().map(|p| format!(" and {}", p.display())).unwrap_or_default()
    ));
    let (rel_max, rel_mean, lit) = reading.relative_error();
    if lit > 0 {
        output::result(&format!(
            "relative standard error of E_v over the {lit} lit {}: max {:.3} %, mean {:.3} % ({} estimator)",
            if layout.is_point() { "points" } else { "cells" },
            100.0 * rel_max,
            100.0 * rel_mean,
            match estimator {
                MeterEstimator::Connections => "connections",
                MeterEstimator::Samples => "samples",
            }
        ));
    }
    if rel_max.is_nan() {
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
