//! `opticks render`: a dataset, seen through a camera, into an EXR or PNG image, optionally
//! relit (`--light`). The dataset is memory-mapped and streamed chunk by chunk; its scene must
//! match (geometry fingerprint; each light's shape).

use super::{DatasetArgs, ThreadArgs, render_film, write_film};
use crate::camera_args::CameraArgs;
use anyhow::Result;
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
}

/// Runs the render.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    opticks_io::image_file::check_output_path(&a.output)?;
    let data = a.input.open()?;
    let scene = &data.scene;
    let camera = a.camera.resolve(scene.camera)?;
    let t0 = Instant::now();
    let Some(film) = render_film(scene, &camera, data.count(), data.samples(), |i| data.batch(i))? else {
        return Ok(()); // a worker rank of a cluster job: its part went to the master
    };
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
