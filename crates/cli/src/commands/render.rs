//! `opticks render`: a dataset, seen through a camera, into an EXR or PNG image, optionally
//! relit (`--light`). The dataset is memory-mapped and streamed chunk by chunk; its scene must
//! match (geometry fingerprint; each light's shape).

use super::light_args::parse_light_scale;
use super::{ThreadArgs, open_with_scene, render_with_progress, write_film};
use crate::camera_args::CameraArgs;
use anyhow::Result;
use opticks_core::dataset::{LightScale, lighting};
use opticks_core::sensor::SampleBatch;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `opticks render`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Dataset file written by `opticks trace`.
    dataset: PathBuf,
    /// Scene file the dataset was traced from (default: the path recorded in the dataset).
    #[arg(long)]
    scene: Option<String>,
    /// Output image: .exr (linear radiance) or .png (sRGB).
    #[arg(short, long)]
    output: PathBuf,
    /// Relight: NAME_OR_INDEX=SCALE or NAME_OR_INDEX=R,G,B multiplies that light's power
    /// (0 switches it off); repeatable. No re-tracing: exact.
    #[arg(long = "light", value_parser = parse_light_scale, allow_hyphen_values = true)]
    light: Vec<LightScale>,
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
    let (reader, _, scene) = open_with_scene(&a.dataset, a.scene.as_deref())?;
    let lit = lighting(&reader.header().table, &scene, &a.light)?;
    for note in &lit.notes {
        eprintln!("note: {note}");
    }
    let camera = a.camera.resolve(scene.camera)?;
    let t0 = Instant::now();
    let film = render_with_progress(&scene, &camera, reader.chunk_count(), reader.total_samples(), |i| {
        let c = reader.chunk(i)?;
        Ok(SampleBatch { flux_per_path: lit.flux_per_path[c.light as usize], samples: c.samples })
    })?;
    let secs = t0.elapsed().as_secs_f64();
    write_film(&film, &a.output, a.exposure)?;
    println!(
        "rendered {} samples at {}x{} in {:.2} s → {}",
        reader.total_samples(),
        camera.width,
        camera.height,
        secs,
        a.output.display()
    );
    Ok(())
}
