//! `opticks walk`: a walkthrough — one dataset, many cameras. Keyframes from a JSON camera path
//! (see `opticks_io::camera_path_file`) are interpolated into frames, each rendered from the
//! same dataset (read chunk by chunk); the time per frame is reported next to what the trace cost.
//! With `ffmpeg` on the PATH the PNG frames of this run also become `walk.mp4`, written
//! atomically. The camera path is validated whole before the output folder is created: the
//! frame count (at least 1, at most 100000, computed without overflow) and every frame's camera
//! (an interpolated field of view can be invalid where no keyframe's is). Under `mpirun` (the
//! cluster build) the frames are split over the ranks, each writing its own
//! (`super::my_share`); they are the files a single process writes.

use super::estimator::{Estimator, EstimatorArgs};
use super::{DatasetArgs, ThreadArgs, warn_if_black, write_film};
use crate::camera_args::exposure_for;
use crate::output;
use crate::progress;
use anyhow::{Context, Result, bail};
use opticks_core::sensor::render;
use opticks_io::camera_path_file::read_camera_path;
use opticks_io::output_paths::{OutputKind, check_outputs, spares_what_was_read};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `opticks walk`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: DatasetArgs,
    /// Camera path (JSON keyframes).
    #[arg(long)]
    path: PathBuf,
    /// Output folder for the frames (created if missing).
    #[arg(short, long)]
    output: PathBuf,
    /// Render each frame from this fraction of the dataset's chunks (renormalised, so still
    /// unbiased): a cheaper, noisier preview of the walkthrough.
    #[arg(long, default_value_t = 1.0)]
    fraction: f64,
    /// Frame format: png or exr.
    #[arg(long, default_value = "png", value_parser = ["png", "exr"])]
    format: String,
    /// Exposure of PNG frames, in stops (refused with --format exr).
    #[arg(long, allow_hyphen_values = true)]
    exposure: Option<f32>,
    #[command(flatten)]
    threads: ThreadArgs,
    #[command(flatten)]
    estimator: EstimatorArgs,
}

/// Renders the walkthrough.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    let exposure = exposure_for(Path::new(&format!("frame.{}", a.format)), a.exposure)?;
    if a.output.exists() && !a.output.is_dir() {
        bail!("{}: exists and is not a folder (walk writes its frames into a folder)", a.output.display());
    }
    a.estimator.check()?;
    let mut data = a.input.open()?;
    data.keep_fraction(a.fraction)?;
    let (reader, scene) = (data.reader(), data.scene());
    let walk = read_camera_path(&a.path, scene.camera.map_or(45.0, |c| c.fov_x_degrees))?;
    let (w, h) = walk.size.or(scene.camera.map(|c| (c.width, c.height))).unwrap_or((512, 512));
    let cameras = walk.cameras((w, h)).with_context(|| a.path.display().to_string())?;
    let frames = cameras.len();
    super::check_film_fits("a frame", (w, h), super::IMAGE_OUTPUT_BYTES)?;
    std::fs::create_dir_all(&a.output).with_context(|| format!("cannot create {}", a.output.display()))?;
    // Every frame can be written, and none replaces a file the run read (a texture, say).
    let frame = |f: usize| a.output.join(format!("frame_{f:05}.{}", a.format));
    let mut inputs = a.input.inputs();
    inputs.push(&a.path);
    check_outputs(&[(&frame(0), OutputKind::Image)], &inputs)?;
    (0..frames).try_for_each(|f| spares_what_was_read(&frame(f)))?;
    if let (Estimator::Light, Some(first)) = (a.estimator.estimator, cameras.first()) {
        super::warn_light_estimator_blind_spots(scene, &(*first).into());
    }
    let _graceful = crate::interrupt::graceful();
    let (me, ranks) = super::my_share();
    let pb = progress::bar(frames.div_ceil(ranks) as u64, "frames", "frames");
    let start = Instant::now();
    for (f, camera) in cameras.into_iter().enumerate().filter(|(f, _)| f % ranks == me) {
        if crate::interrupt::requested() {
            bail!(
                "interrupted after {f} of {frames} frames: the frames finished are kept, each written whole"
            );
        }
        let film = match a.estimator.estimator {
            Estimator::Light => render(scene, &camera.into(), data.count(), |i| data.batch(i), |_| {})?,
            // Each frame its own camera streams (pass = frame number).
            Estimator::Bidirectional => {
                a.estimator.render(&data, &camera.into(), None, f as u64, false)?.film
            }
        };
        if f == 0 {
            warn_if_black(film.is_black(), data.samples(), "camera of frame 0", data.flux_per_path());
        }
        write_film(&film, &frame(f), exposure)?;
        pb.inc(1);
    }
    pb.finish_and_clear();
    if !super::shares_done()? {
        return Ok(()); // a worker rank: its frames are written, the master reports
    }
    let per_frame = start.elapsed().as_secs_f64() / frames as f64;
    let trace = reader.header().trace.seconds();
    output::result(&format!(
        "rendered {frames} frames of {w}x{h} in {:.2} s: {per_frame:.3} s per frame; the trace took {trace:.2} s \
         (a frame costs {:.1}% of it) → {}",
        per_frame * frames as f64,
        100.0 * per_frame / trace.max(1e-9),
        a.output.display()
    ));
    if a.format != "png" {
        output::result(&format!(
            "no video: ffmpeg is given PNG frames only (this run wrote {} frames)",
            a.format
        ));
    } else if opticks_io::video::ffmpeg_available() {
        let video = a.output.join("walk.mp4");
        opticks_io::video::encode_frames(&a.output, frames, walk.fps, &video)?;
        output::result(&format!("video → {}", video.display()));
    } else {
        output::result("no video: ffmpeg is not on the PATH");
    }
    Ok(())
}
