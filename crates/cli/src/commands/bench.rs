//! `opticks bench`: tracing and rendering speed on a scene, in memory (no disk in the timing).
//! Reports light paths/s, stored samples/s and render time; runs each phase `--repeat` times
//! and reports the best, so a one-off hiccup of the machine does not count.

use super::ThreadArgs;
use crate::camera_args::CameraArgs;
use crate::scene_arg::{BUILTIN_CORNELL, load_scene};
use crate::strategy_args::StrategyArgs;
use anyhow::Result;
use opticks_core::dataset::Chunk;
use opticks_core::film::Film;
use opticks_core::sensor::{SampleBatch, render};
use opticks_core::trace::trace;
use std::time::Instant;

/// Arguments of `opticks bench`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file or `builtin:cornell`.
    #[arg(default_value = BUILTIN_CORNELL)]
    scene: String,
    /// Light paths per run.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..), default_value_t = 4_194_304)]
    paths: u64,
    /// Random seed of the traced paths.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Runs per phase (the fastest is reported).
    #[arg(long, default_value_t = 3)]
    repeat: u32,
    /// Reference image (EXR) of the scene's camera: also report relative MSE and efficiency
    /// 1/(relMSE × seconds), the figure of merit of `docs/convergence.md`.
    #[arg(long)]
    reference: Option<std::path::PathBuf>,
    #[command(flatten)]
    strategy: StrategyArgs,
    #[command(flatten)]
    threads: ThreadArgs,
    #[command(flatten)]
    defines: crate::scene_arg::DefineArgs,
    #[command(flatten)]
    camera: CameraArgs,
}

/// Runs the benchmark and prints one JSON line after the human-readable report.
pub fn run(a: Args) -> Result<()> {
    a.threads.apply()?;
    let scene = load_scene(&a.scene, &a.defines)?;
    let camera = a.camera.resolve(scene.camera)?;
    let settings = a.strategy.settings(a.paths, a.seed);
    let mut best_trace = f64::INFINITY;
    let mut chunks: Vec<Chunk> = Vec::new();
    let mut table = Default::default();
    for _ in 0..a.repeat.max(1) {
        chunks.clear();
        let t = Instant::now();
        table = trace(
            &scene,
            &settings,
            |c| {
                chunks.push(c);
                Ok::<(), std::convert::Infallible>(())
            },
            |_| {},
        )?;
        best_trace = best_trace.min(t.elapsed().as_secs_f64());
    }
    let samples: usize = chunks.iter().map(|c| c.samples.len()).sum();
    let mut best_render = f64::INFINITY;
    let mut film = Film::new(1, 1);
    for _ in 0..a.repeat.max(1) {
        let t = Instant::now();
        film = render(
            &scene,
            &camera,
            chunks.len(),
            |i| {
                let c = &chunks[i];
                Ok::<_, std::convert::Infallible>(SampleBatch {
                    flux_per_path: table.flux_per_path(c.light as usize),
                    samples: &c.samples,
                })
            },
            |_| {},
        )?;
        best_render = best_render.min(t.elapsed().as_secs_f64());
    }
    let threads = rayon::current_num_threads();
    println!("scene          {} ({} triangles, {threads} threads)", a.scene, scene.triangles.len());
    println!(
        "trace          {} paths in {:.3} s: {:.3} M paths/s, {:.3} M samples/s ({:.2} samples/path)",
        a.paths,
        best_trace,
        a.paths as f64 / best_trace / 1e6,
        samples as f64 / best_trace / 1e6,
        samples as f64 / a.paths as f64
    );
    println!(
        "render         {}x{} from {} samples in {:.3} s: {:.3} M samples/s",
        camera.width(),
        camera.height(),
        samples,
        best_render,
        samples as f64 / best_render / 1e6
    );
    let m = film.mean();
    let mut quality = String::new();
    if let Some(path) = &a.reference {
        let (w, h, reference) = opticks_io::image_file::read_exr_rgb(path)?;
        if (w, h) != (camera.width(), camera.height()) {
            anyhow::bail!(
                "{}: {w}x{h} does not match the camera's {}x{}",
                path.display(),
                camera.width(),
                camera.height()
            );
        }
        let c = opticks_io::compare::compare(&film.to_rgb_f32(), &reference);
        let efficiency = 1.0 / (c.relmse * (best_trace + best_render));
        println!(
            "quality        relMSE {:.4e} vs {}; mean ratio {:.4} {:.4} {:.4}; efficiency 1/(relMSE·s) = {efficiency:.1}",
            c.relmse,
            path.display(),
            c.mean_ratio[0],
            c.mean_ratio[1],
            c.mean_ratio[2]
        );
        quality = format!(",\"relmse\":{:.6e},\"efficiency\":{efficiency:.3}", c.relmse);
    }
    println!(
        "{{\"scene\":\"{}\",\"paths\":{},\"threads\":{threads},\"trace_s\":{best_trace:.4},\"render_s\":{best_render:.4},\"samples\":{samples},\"mean_rgb\":[{:.6},{:.6},{:.6}]{quality}}}",
        a.scene, a.paths, m[0], m[1], m[2]
    );
    Ok(())
}
