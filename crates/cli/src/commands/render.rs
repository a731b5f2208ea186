//! `opticks render`: a dataset, seen through a camera, into an EXR or PNG image, optionally
//! relit (`--light`). The dataset is memory-mapped and streamed chunk by chunk; its scene must
//! match (geometry fingerprint; each light's shape). Every argument and the output location are
//! checked before the dataset is read.

use super::{DatasetArgs, ThreadArgs, render_with_progress, warn_if_black, write_film};
use crate::camera_args::{CameraArgs, exposure_for};
use crate::output;
use anyhow::{Context, Result};
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
}

/// Runs the render.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    check_output(&a.output, OutputKind::Image, &a.input.inputs())?;
    let exposure = exposure_for(&a.output, a.exposure)?;
    a.camera.check()?;
    let data = a.input.open()?;
    let scene = &data.scene;
    let camera = a.camera.resolve(scene.camera).with_context(|| match a.input.scene() {
        Some(spec) => format!("the scene given with --scene ({spec})"),
        None => "the dataset's scene".to_string(),
    })?;
    let t0 = Instant::now();
    let _graceful = crate::interrupt::graceful();
    let film = render_with_progress(scene, &camera, data.count(), data.samples(), |i| data.batch(i))?;
    let secs = t0.elapsed().as_secs_f64();
    warn_if_black(&film, data.samples(), "camera");
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
