//! `opticks walk`: a walkthrough — one dataset, many cameras. Keyframes from a JSON camera path
//! (see `opticks_io::camera_path_file`) are interpolated into frames, each rendered from the
//! same dataset (read chunk by chunk); the time per frame is reported next to what the trace cost.
//! With `ffmpeg` on the PATH the PNG frames of this run also become `walk.mp4`, written
//! atomically; the camera path is validated before the output folder is created.

use super::{DatasetArgs, ThreadArgs, write_film};
use crate::progress;
use anyhow::{Context, Result, bail};
use opticks_core::sensor::{Pinhole, render};
use opticks_io::camera_path_file::read_camera_path;
use std::path::PathBuf;
use std::process::{Command, Stdio};
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
    /// Exposure for PNG frames, in stops.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    exposure: f32,
    #[command(flatten)]
    threads: ThreadArgs,
}

/// Renders the walkthrough.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    let mut data = a.input.open()?;
    data.keep_fraction(a.fraction)?;
    let (reader, scene) = (&data.reader, &data.scene);
    let walk = read_camera_path(&a.path, scene.camera.map_or(45.0, |c| c.fov_x_degrees))?;
    let (w, h) = walk.size.or(scene.camera.map(|c| (c.width, c.height))).unwrap_or((512, 512));
    let (t0, t1) = walk.path.span();
    let frames = ((t1 - t0) * walk.fps + 1e-4).floor() as usize + 1;
    if frames > 100_000 {
        bail!("{}: {frames} frames is more than this command renders (100000)", a.path.display());
    }
    super::check_film_fits("a frame", (w, h), super::IMAGE_OUTPUT_BYTES)?;
    std::fs::create_dir_all(&a.output).with_context(|| format!("cannot create {}", a.output.display()))?;
    let pb = progress::bar(frames as u64, "frames", "frames");
    let start = Instant::now();
    for f in 0..frames {
        if crate::interrupt::requested() {
            bail!("interrupted after {f} of {frames} frames");
        }
        let desc = walk.path.at(t0 + f as f32 / walk.fps, w, h);
        let camera = Pinhole::new(&desc).with_context(|| format!("frame {f}: invalid camera"))?;
        let film = render(scene, &camera.into(), data.count(), |i| data.batch(i), |_| {})?;
        write_film(&film, &a.output.join(format!("frame_{f:05}.{}", a.format)), a.exposure)?;
        pb.inc(1);
    }
    pb.finish_and_clear();
    let per_frame = start.elapsed().as_secs_f64() / frames as f64;
    let trace = reader.header().trace.seconds();
    println!(
        "rendered {frames} frames of {w}x{h} in {:.2} s: {per_frame:.3} s per frame; the trace took {trace:.2} s \
         (a frame costs {:.1}% of it) → {}",
        per_frame * frames as f64,
        100.0 * per_frame / trace.max(1e-9),
        a.output.display()
    );
    if a.format != "png" {
        println!("no video: ffmpeg is given PNG frames only (this run wrote {} frames)", a.format);
    } else if ffmpeg_available() {
        let video = a.output.join("walk.mp4");
        encode_video(&a.output, frames, walk.fps, &video)?;
        println!("video → {}", video.display());
    } else {
        println!("no video: ffmpeg is not on the PATH");
    }
    Ok(())
}

/// Encodes this run's `frames` PNG frames into `video`: exactly frames 0..frames (stale frames
/// of an earlier, longer run in the same folder are not read), into a temporary file renamed
/// into place only when ffmpeg succeeded.
fn encode_video(folder: &std::path::Path, frames: usize, fps: f32, video: &std::path::Path) -> Result<()> {
    let tmp = folder.join(format!(".walk.tmp-{}.mp4", std::process::id()));
    let status = Command::new("ffmpeg")
        .args(["-y", "-loglevel", "error", "-framerate", &fps.to_string(), "-start_number", "0", "-i"])
        .arg(folder.join("frame_%05d.png"))
        .args([
            "-frames:v",
            &frames.to_string(),
            "-pix_fmt",
            "yuv420p",
            "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
        ])
        .arg(&tmp)
        .status();
    let done = match status {
        Ok(s) if s.success() && tmp.exists() => std::fs::rename(&tmp, video)
            .with_context(|| format!("cannot move the video into place as {}", video.display())),
        Ok(s) => Err(anyhow::anyhow!("ffmpeg failed to encode {} ({s})", video.display())),
        Err(e) => Err(anyhow::anyhow!("cannot run ffmpeg: {e}")),
    };
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done
}

fn ffmpeg_available() -> bool {
    Command::new("ffmpeg")
        .arg("-version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}
