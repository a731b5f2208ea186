//! `opticks render`: a dataset, seen through a camera, into an EXR or PNG image, optionally
//! relit (`--light`), with the light estimator (the default) or the bidirectional one
//! (`--estimator bidirectional`, `--spp`, `--connections`, `--time`). The dataset is
//! memory-mapped and streamed chunk by chunk; its scene must match (geometry fingerprint; each
//! light's shape).

use super::estimator::{Estimator, EstimatorArgs};
use super::{DatasetArgs, ThreadArgs, render_with_progress, write_film};
use crate::camera_args::CameraArgs;
use anyhow::{Result, bail};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `opticks render`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: DatasetArgs,
    /// Output image: .exr (linear radiance) or .png (sRGB).
    #[arg(short, long)]
    output: PathBuf,
    /// Exposure for PNG output, in stops.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    exposure: f32,
    #[command(flatten)]
    threads: ThreadArgs,
    #[command(flatten)]
    camera: CameraArgs,
    #[command(flatten)]
    estimator: EstimatorArgs,
    /// Bidirectional: add camera passes (of --spp paths per pixel each) over the same dataset
    /// until SECONDS have passed, with a progress bar and a running error estimate.
    #[arg(long, value_name = "SECONDS")]
    time: Option<f64>,
}

/// Runs the render.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    opticks_io::image_file::check_output_path(&a.output)?;
    let data = a.input.open()?;
    let scene = &data.scene;
    let camera = a.camera.resolve(scene.camera)?;
    a.estimator.check()?;
    if let Some(t) = a.time {
        if a.estimator.estimator != Estimator::Bidirectional {
            bail!(
                "--time applies to --estimator bidirectional (the light estimator renders the dataset once)"
            );
        }
        if !(t.is_finite() && t > 0.0) {
            bail!("--time {t} must be a positive number of seconds");
        }
    }
    let t0 = Instant::now();
    if a.estimator.estimator == Estimator::Bidirectional {
        let run = a.estimator.render(&data, &camera, a.time, 0, true)?;
        let secs = t0.elapsed().as_secs_f64();
        write_film(&run.film, &a.output, a.exposure)?;
        let error =
            run.error.map_or(String::new(), |e| format!(", estimated relative error {:.2}%", 100.0 * e));
        println!(
            "rendered bidirectionally: {} samples and {} camera paths per pixel ({} passes, {} connections) at {}x{} in {:.2} s{error} → {}",
            data.samples(),
            run.spp,
            run.passes,
            a.estimator.connections,
            camera.width(),
            camera.height(),
            secs,
            a.output.display()
        );
        return Ok(());
    }
    let film = render_with_progress(scene, &camera, data.count(), data.samples(), |i| data.batch(i))?;
    let secs = t0.elapsed().as_secs_f64();
    write_film(&film, &a.output, a.exposure)?;
    println!(
        "rendered {} samples at {}x{} in {:.2} s → {}",
        data.samples(),
        camera.width(),
        camera.height(),
        secs,
        a.output.display()
    );
    Ok(())
}
