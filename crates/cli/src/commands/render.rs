//! `opticks render`: a dataset, seen through a camera, into an EXR or PNG image. The dataset is
//! memory-mapped and streamed chunk by chunk; its scene must match (geometry fingerprint).

use super::{ThreadArgs, render_with_progress, write_film};
use crate::camera_args::CameraArgs;
use crate::scene_arg::load_scene;
use anyhow::{Context, Result, bail};
use opticks_core::sensor::SampleBatch;
use opticks_io::dataset_file::DatasetReader;
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
    let reader = DatasetReader::open(&a.dataset)?;
    let header = reader.header();
    let scene_spec = a.scene.clone().unwrap_or_else(|| header.label.clone());
    let scene = load_scene(&scene_spec).with_context(|| {
        format!("cannot load the dataset's scene (recorded as '{}'; pass --scene to name it)", header.label)
    })?;
    if scene.fingerprint.geometry != header.fingerprint.geometry {
        bail!(
            "{} was traced from a different scene than {scene_spec}: geometry/material fingerprint {} ≠ {}",
            a.dataset.display(),
            hex(&header.fingerprint.geometry),
            scene.fingerprint.geometry_hex()
        );
    }
    if scene.fingerprint.lights != header.fingerprint.lights
        || scene.lights.len() != header.table.lights.len()
    {
        bail!(
            "the lights of {scene_spec} differ from those {} was traced with; re-trace the scene",
            a.dataset.display()
        );
    }
    let camera = a.camera.resolve(scene.camera)?;
    let table = &header.table;
    let t0 = Instant::now();
    let film = render_with_progress(&scene, &camera, reader.chunk_count(), reader.total_samples(), |i| {
        let c = reader.chunk(i)?;
        Ok(SampleBatch { flux_per_path: table.flux_per_path(c.light as usize), samples: c.samples })
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

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}
