//! `opticks demo`: the built-in Cornell box, traced and rendered in one go — no files needed.
//! By default the images go into the folder `opticks-demo/` (created; git-ignored in the
//! repository), never among the user's own files.

use super::{ThreadArgs, render_chunks, warn_if_black};
use crate::camera_args::CameraArgs;
use crate::output;
use crate::progress::TraceProgress;
use crate::scene_arg::load_scene;
use anyhow::{Context, Result};
use opticks_core::dataset::TraceSettings;
use opticks_io::dataset_job::trace_in_memory;
use opticks_io::output_paths::{OutputKind, check_output, check_outputs};
use opticks_io::scene_source::SceneRef;
use std::path::{Path, PathBuf};

/// Where the demo writes by default: a folder of its own.
const DEFAULT_OUTPUT: &str = "opticks-demo/cornell.png";
use std::time::Instant;

/// Arguments of `opticks demo`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output image; the other format (.png ↔ .exr) is written beside it. The default's folder
    /// is created if missing.
    #[arg(short, long, default_value = DEFAULT_OUTPUT)]
    output: PathBuf,
    /// Light paths to trace; e.g. 4000000, 4M, 4e6.
    #[arg(long, allow_hyphen_values = true, value_parser = opticks_io::count_text::parse_count, default_value = "4M")]
    paths: u64,
    /// Random seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Exposure of the PNG, in stops (the EXR holds the radiance as it is).
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
        check_output(path, OutputKind::Vrml, &[])?;
        let scene = opticks_core::scene::cornell_box();
        opticks_io::scene_formats::vrml::write_vrml_file(&scene, path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        output::result(&format!("wrote the built-in scene to {}", path.display()));
        return Ok(());
    }
    a.threads.apply()?;
    if !a.exposure.is_finite() {
        anyhow::bail!("--exposure {}: must be a finite number of stops", a.exposure);
    }
    if a.output == Path::new(DEFAULT_OUTPUT) {
        let dir = a.output.parent().expect("the default has a folder");
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    let other =
        a.output.with_extension(if a.output.extension().is_some_and(|e| e == "exr") { "png" } else { "exr" });
    check_outputs(&[(&a.output, OutputKind::Image), (&other, OutputKind::Image)], &[])?;
    let scene = load_scene(&SceneRef::cornell(), &Default::default())?;
    let camera = a.camera.resolve(scene.camera)?;
    let settings = TraceSettings { paths: a.paths, seed: a.seed, ..Default::default() };
    let t0 = Instant::now();
    let _graceful = crate::interrupt::graceful();
    let traced = trace_in_memory(&scene, &SceneRef::cornell().label(), settings, &TraceProgress::default())?;
    let Some((header, chunks)) = traced else { anyhow::bail!("interrupted: stopped, nothing written") };
    let t1 = Instant::now();
    let film = render_chunks(&scene, &camera, &header.table, &chunks)?;
    let t2 = Instant::now();
    let samples: usize = chunks.iter().map(|c| c.samples.len()).sum();
    warn_if_black(film.is_black(), samples as u64, "camera", &[opticks_core::math::Rgb::ONE]);
    // Both images or neither.
    let encode = |path: &Path| {
        opticks_io::image_file::encode_image(path, film.width, film.height, &film.to_rgb_f32(), a.exposure)
    };
    let (first, second) = (encode(&a.output)?, encode(&other)?);
    let removed = opticks_io::image_file::write_files_atomically(&[(&a.output, &first), (&other, &second)])
        .context("nothing was written")?;
    super::note_removed_stale(&removed);
    output::result(&format!(
        "traced {} paths ({} samples) in {:.2} s, rendered {}x{} in {:.2} s → {} and {}",
        a.paths,
        samples,
        (t1 - t0).as_secs_f64(),
        camera.width(),
        camera.height(),
        (t2 - t1).as_secs_f64(),
        a.output.display(),
        other.display()
    ));
    Ok(())
}
