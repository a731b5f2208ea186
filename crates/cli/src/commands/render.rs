//! `opticks render`: a dataset, seen through a camera, into an EXR or PNG image, optionally
//! relit (`--light`), with the light estimator (the default) or the bidirectional one
//! (`--estimator bidirectional`, `--spp`, `--connections`, `--time`). The dataset is streamed
//! chunk by chunk (the bidirectional estimator holds its light vertex cache in memory); its
//! scene must match (geometry fingerprint; each light's shape). Every argument and the output
//! location are checked before the dataset is read.

use super::estimator::{Estimator, EstimatorArgs};
use super::{DatasetArgs, ThreadArgs, render_film, warn_if_black, write_film};
use crate::camera_args::{CameraArgs, exposure_for};
use crate::output;
use anyhow::{Result, bail};
use opticks_core::sensor::view::ViewError;
use opticks_io::output_paths::{OutputKind, check_output};
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
    /// Exposure of PNG output, in stops (an EXR holds radiance as it is: refused there).
    #[arg(long, allow_hyphen_values = true)]
    exposure: Option<f32>,
    #[command(flatten)]
    threads: ThreadArgs,
    #[command(flatten)]
    camera: CameraArgs,
    #[command(flatten)]
    estimator: EstimatorArgs,
    /// Bidirectional: add camera passes (of --spp paths per pixel each) over the same dataset
    /// until SECONDS have passed, with a progress bar and a running error estimate.
    #[arg(long, value_name = "SECONDS", value_parser = super::parse_seconds)]
    time: Option<std::time::Duration>,
}

/// Runs the render.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    check_output(&a.output, OutputKind::Image, &a.input.inputs())?;
    let exposure = exposure_for(&a.output, a.exposure)?;
    a.camera.check()?;
    a.estimator.check()?;
    if a.time.is_some() && a.estimator.estimator != Estimator::Bidirectional {
        bail!("--time applies to --estimator bidirectional (the light estimator renders the dataset once)");
    }
    let data = a.input.open()?;
    // Again, now that the files the scene names have been read (textures, environment maps).
    check_output(&a.output, OutputKind::Image, &a.input.inputs())?;
    let scene = data.scene();
    // An option's own fault is blamed on the option; the rest (an invalid scene camera, or an
    // option the scene's camera cannot take) on the scene.
    let camera = a.camera.resolve(scene.camera).map_err(|e| match e {
        ViewError::Options(_) => anyhow::Error::new(e),
        e => anyhow::Error::new(e).context(match a.input.scene().ok().flatten() {
            Some(spec) => format!("the scene given with --scene ({spec})"),
            None => "the dataset's scene".to_string(),
        }),
    })?;
    output::detail(&format!(
        "dataset {}: {} samples of {} paths; {} triangles, {}; view {}x{}, estimator {:?}",
        data.reader().path().display(),
        data.samples(),
        data.reader().header().table.total_paths(),
        scene.triangles.len(),
        output::count(scene.lights.len() as u64, "light"),
        camera.width(),
        camera.height(),
        a.estimator.estimator
    ));
    let t0 = Instant::now();
    let _graceful = crate::interrupt::graceful();
    if a.estimator.estimator == Estimator::Bidirectional {
        super::single_process_only("render --estimator bidirectional")?;
        let run = a.estimator.render(&data, &camera, a.time, 0, true)?;
        let secs = t0.elapsed().as_secs_f64();
        warn_if_black(run.film.is_black(), data.samples(), "camera", data.flux_per_path());
        write_film(&run.film, &a.output, exposure)?;
        if run.interrupted {
            // Exit 128 + signal, as every interrupted verb, with the image of the passes done.
            bail!(
                "interrupted after {} passes ({} camera paths per pixel): their image is written to {}",
                run.passes,
                run.spp,
                a.output.display()
            );
        }
        let error =
            run.error.map_or(String::new(), |e| format!(", estimated relative error {:.2}%", 100.0 * e));
        output::result(&format!(
            "rendered bidirectionally: {} samples and {} camera paths per pixel in {:.1} % of the pixels ({} passes, {} connections) at {}x{} in {:.2} s{error} → {}",
            data.samples(),
            run.spp,
            100.0 * run.camera_pixels as f64 / (camera.width() as f64 * camera.height() as f64),
            run.passes,
            a.estimator.connections(),
            camera.width(),
            camera.height(),
            secs,
            a.output.display()
        ));
        return Ok(());
    }
    super::warn_light_estimator_blind_spots(scene, &camera);
    let Some(film) = render_film(scene, &camera, data.count(), data.samples(), |i| Ok(data.batch(i)?))?
    else {
        return Ok(()); // a worker rank of a cluster job: its part went to the master
    };
    let secs = t0.elapsed().as_secs_f64();
    warn_if_black(film.is_black(), data.samples(), "camera", data.flux_per_path());
    write_film(&film, &a.output, exposure)?;
    output::result(&format!(
        "rendered {} samples at {}x{} in {:.2} s → {}",
        data.samples(),
        camera.width(),
        camera.height(),
        secs,
        a.output.display()
    ));
    Ok(())
}
