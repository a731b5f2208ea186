//! `opticks measure`: an illuminance meter over a dataset — irradiance per cell on a planar
//! scene surface (a mesh by name, or a rectangle given by a corner and two edges), written as
//! CSV and optionally as a heat-map PNG.
//!
//! CSV columns: `i,j` (cell along u and v), `x,y,z` (cell centre, m), `E_R,E_G,E_B` (irradiance,
//! W/m² per RGB channel) and `E_v_lux`. The photometric column uses the convention
//! E_v = 683 lm/W · (0.2126·E_R + 0.7152·E_G + 0.0722·E_B): the Rec. 709 luminance weights with
//! the 555 nm luminous efficacy. It is an approximation — exact only if the RGB channels were
//! radiometric quantities with the spectral shapes the weights assume; renderers' RGB light is
//! not a spectrum. The PNG shows E_v.
//!
//! Orientation: only light arriving from the meter's front is counted — the side its normal
//! n = u × v faces (for `--surface`, the side the mesh's triangles face). The summary line
//! states that normal; a plane lit only from behind reads 0, with a warning saying to swap u
//! and v to measure the other side.
//!
//! The scene is resolved and checked against the dataset as `opticks render` does. Both outputs
//! are checked before the dataset is read and written all or none.

use super::{DatasetArgs, ThreadArgs};
use crate::camera_args::parse_vec3;
use crate::output;
use crate::progress;
use anyhow::{Context, Result, bail};
use opticks_core::light::LUMENS_PER_WATT;
use opticks_core::math::Vec3;
use opticks_core::sensor::{IlluminanceMeter, measure_both_sides};
use opticks_io::output_paths::{OutputKind, check_outputs};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};

/// Arguments of `opticks measure`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: DatasetArgs,
    /// Measure on the planar mesh of this name (its bounding rectangle in its plane), on the side
    /// its triangles face.
    #[arg(long, conflicts_with = "plane", required_unless_present = "plane")]
    surface: Option<String>,
    /// Measure on the rectangle "ox,oy,oz,ux,uy,uz,vx,vy,vz" (corner and two edges, m); it must
    /// lie on scene geometry. Only light arriving from its front, the side u × v points to, is
    /// counted: swap u and v to measure the other side.
    #[arg(long, allow_hyphen_values = true)]
    plane: Option<String>,
    /// Cells "NXxNY" along u and v.
    #[arg(long, default_value = "10x10", value_parser = parse_cells)]
    cells: (u32, u32),
    /// Output CSV file (.csv).
    #[arg(short, long)]
    output: PathBuf,
    /// Also write a heat-map PNG (.png) of the illuminance (lux).
    #[arg(long)]
    png: Option<PathBuf>,
    #[command(flatten)]
    threads: ThreadArgs,
}

/// Parses "NXxNY" cell counts (1..=65536 each).
fn parse_cells(s: &str) -> Result<(u32, u32)> {
    let (x, y) = s.split_once(['x', 'X']).with_context(|| format!("'{s}' must look like 10x8"))?;
    let (x, y): (u32, u32) = (
        x.trim().parse().with_context(|| format!("'{s}': '{x}' is not a cell count"))?,
        y.trim().parse().with_context(|| format!("'{s}': '{y}' is not a cell count"))?,
    );
    if x == 0 || y == 0 || x > 65536 || y > 65536 {
        bail!("{x}x{y} cells: each count must be between 1 and 65536");
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
    let mut outputs = vec![(a.output.as_path(), OutputKind::Csv)];
    outputs.extend(a.png.as_deref().map(|p| (p, OutputKind::Png)));
    check_outputs(&outputs, &a.input.inputs())?;
    let data = a.input.open()?;
    let desc = &data.description;
    let (nx, ny) = a.cells;
    let meter = match (&a.surface, &a.plane) {
        (Some(name), _) => IlluminanceMeter::on_mesh(desc, name, nx, ny)?,
        (None, Some(p)) => {
            let (o, u, v) = parse_plane(p)?;
            IlluminanceMeter::new(o, u, v, nx, ny).with_context(|| format!("--plane '{p}'"))?
        }
        (None, None) => bail!("give --surface NAME or --plane ox,oy,oz,ux,uy,uz,vx,vy,vz"),
    };
    let _graceful = crate::interrupt::graceful();
    // Per cell: its lux value and its CSV line (about 120 characters).
    super::check_film_fits("a meter", (nx, ny), 8 + 128)?;
    let pb = progress::bar(data.samples(), "measuring", "samples");
    let done = AtomicU64::new(0);
    let (film, behind) = measure_both_sides(
        &meter,
        data.count(),
        |i| {
            super::unless_interrupted()?;
            data.batch(i)
        },
        |n| pb.set_position(done.fetch_add(n as u64, Ordering::Relaxed) + n as u64),
    )?;
    pb.finish_and_clear();
    let n = meter.normal();
    let (front_mean, back_mean) = (film.mean(), behind.mean());
    let (front_sum, back_sum) = (front_mean.iter().sum::<f64>(), back_mean.iter().sum::<f64>());
    if back_sum > front_sum {
        output::warning(&format!(
            "more light reaches this plane from behind (mean E {:.4e} W/m² summed over RGB) than from its \
             front (normal {:.3},{:.3},{:.3}: {:.4e} W/m²); to measure the other side, swap u and v",
            back_sum, n.x, n.y, n.z, front_sum
        ));
    } else {
        super::warn_if_black(&film, data.samples(), "meter's front");
    }

    let lux: Vec<f64> = film
        .pixels
        .iter()
        .map(|e| f64::from(LUMENS_PER_WATT) * (0.2126 * e[0] + 0.7152 * e[1] + 0.0722 * e[2]))
        .collect();
    let mut csv = String::from("i,j,x,y,z,E_R,E_G,E_B,E_v_lux\n");
    for j in 0..ny {
        for i in 0..nx {
            let k = (j * nx + i) as usize;
            let c = meter.cell_centre(i, j);
            let e = film.pixels[k];
            let _ = writeln!(
                csv,
                "{i},{j},{},{},{},{:e},{:e},{:e},{:e}",
                c.x, c.y, c.z, e[0], e[1], e[2], lux[k]
            );
        }
    }
    let heatmap = match &a.png {
        Some(png) => Some(opticks_io::heatmap::encode_heatmap(
            png,
            &lux,
            nx,
            ny,
            meter.u.length() as f64,
            meter.v.length() as f64,
            "E (lux)",
        )?),
        None => None,
    };
    let mut files = vec![(a.output.as_path(), csv.as_bytes())];
    if let (Some(png), Some(bytes)) = (&a.png, &heatmap) {
        files.push((png.as_path(), bytes.as_slice()));
    }
    let removed = opticks_io::image_file::write_files_atomically(&files).context("nothing was written")?;
    super::note_removed_stale(&removed);
    let area = (meter.cell_area() as f64) * (nx * ny) as f64;
    let mean = front_mean;
    let (min, max) = lux.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    output::result(&format!(
        "{nx}x{ny} cells on {area:.4} m², front side (light arriving from normal {:.3},{:.3},{:.3}): mean E = \
         {:.5e},{:.5e},{:.5e} W/m², E_v {min:.4e}..{max:.4e} lux → {}{}",
        n.x,
        n.y,
        n.z,
        mean[0],
        mean[1],
        mean[2],
        a.output.display(),
        a.png.as_ref().map(|p| format!(" and {}", p.display())).unwrap_or_default()
    ));
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
