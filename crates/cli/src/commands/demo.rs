//! `opticks demo`: the built-in Cornell box, traced and rendered in one go — no files needed.

use super::{ThreadArgs, render_chunks, write_film};
use crate::camera_args::CameraArgs;
use crate::progress::TraceProgress;
use crate::scene_arg::{BUILTIN_CORNELL, load_scene};
use anyhow::{Context, Result};
use opticks_core::dataset::{TraceSettings, new_trace};
use opticks_io::dataset_job::trace_observed;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `opticks demo`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output image; the other format (.png ↔ .exr) is written beside it.
    #[arg(short, long, default_value = "cornell.png")]
    output: PathBuf,
    /// Light paths to trace.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..), default_value_t = 4_000_000)]
    paths: u64,
    /// Random seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Exposure for the PNG, in stops.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    exposure: f32,
    #[command(flatten)]
    threads: ThreadArgs,
    #[command(flatten)]
    camera: CameraArgs,
    /// Only write the built-in scene as a VRML97 file (with the Opticks extension) and exit.
    #[arg(long, value_name = "FILE.wrl")]
    export_scene: Option<PathBuf>,
}

/// Runs the demo.
pub fn run(a: Args) -> Result<()> {
    if let Some(path) = &a.export_scene {
        let scene = opticks_core::scene::cornell_box();
        opticks_io::scene_formats::vrml::write_vrml_file(&scene, path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote the built-in scene to {}", path.display());
        return Ok(());
    }
    a.threads.apply()?;
    opticks_io::image_file::check_output_path(&a.output)?;
    let scene = load_scene(BUILTIN_CORNELL, &Default::default())?;
    let camera = a.camera.resolve(scene.camera)?;
    let settings = TraceSettings { paths: a.paths, seed: a.seed, ..Default::default() };
    let t0 = Instant::now();
    let mut chunks = Vec::new();
    let (mut header, pass) = new_trace(&scene, BUILTIN_CORNELL, settings);
    let sink = |c| {
        chunks.push(c);
        Ok::<(), std::convert::Infallible>(())
    };
    let traced = trace_observed(&scene, &pass, sink, &TraceProgress::default())?;
    if crate::interrupt::requested() {
        anyhow::bail!("interrupted by the user");
    }
    header.record_traced(&pass.lights, &traced, 0.0)?;
    let t1 = Instant::now();
    let film = render_chunks(&scene, &camera, &header.table, &chunks)?;
    let t2 = Instant::now();
    let samples: usize = chunks.iter().map(|c| c.samples.len()).sum();
    let other =
        a.output.with_extension(if a.output.extension().is_some_and(|e| e == "exr") { "png" } else { "exr" });
    write_film(&film, &a.output, a.exposure)?;
    write_film(&film, &other, a.exposure)?;
    println!(
        "traced {} paths ({} samples) in {:.2} s, rendered {}x{} in {:.2} s → {} and {}",
        a.paths,
        samples,
        (t1 - t0).as_secs_f64(),
        camera.width(),
        camera.height(),
        (t2 - t1).as_secs_f64(),
        a.output.display(),
        other.display()
    );
    Ok(())
}
