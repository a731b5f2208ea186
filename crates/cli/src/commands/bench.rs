//! `opticks bench`: tracing and rendering speed on a scene, in memory (no disk in the timing).
//! Reports light paths/s, stored samples/s and render time; runs each phase `--repeat` times
//! and reports the best, so a one-off hiccup of the machine does not count.

use super::ThreadArgs;
use crate::camera_args::CameraArgs;
use crate::output;
use crate::scene_arg::load_scene;
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
    #[arg(default_value = "builtin:cornell", value_parser = crate::scene_arg::parse_scene)]
    scene: opticks_io::scene_source::SceneRef,
    /// Light paths per run; e.g. 4194304, 4M, 4e6.
    #[arg(long, value_parser = crate::count_arg::parse_count, default_value_t = 4_194_304)]
    paths: u64,
    /// Random seed of the traced paths (the same default as `trace`).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Runs per phase, at least 1 (the fastest is reported).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
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
    // The reference is read and its size checked before the expensive runs.
    let reference = match &a.reference {
        Some(path) => {
            let (w, h, rgb) = opticks_io::image_file::read_exr_rgb(path)?;
            if (w, h) != (camera.width(), camera.height()) {
                anyhow::bail!(
                    "{}: {w}x{h} does not match the camera's {}x{}",
                    path.display(),
                    camera.width(),
                    camera.height()
                );
            }
            Some((path, rgb))
        }
        None => None,
    };
    super::check_film_fits("an image", (camera.width(), camera.height()), 0)?;
    let settings = a.strategy.settings(a.paths, a.seed);
    let mut best_trace = f64::INFINITY;
    let mut chunks: Vec<Chunk> = Vec::new();
    let mut table = Default::default();
    for _ in 0..a.repeat {
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
    for _ in 0..a.repeat {
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
    output::result(&format!(
        "scene          {} ({} triangles, {threads} threads)",
        a.scene,
        scene.triangles.len()
    ));
    output::result(&format!(
        "trace          {} paths in {:.3} s: {:.3} M paths/s, {:.3} M samples/s ({:.2} samples/path)",
        a.paths,
        best_trace,
        a.paths as f64 / best_trace / 1e6,
        samples as f64 / best_trace / 1e6,
        samples as f64 / a.paths as f64
    ));
    output::result(&format!(
        "render         {}x{} from {} samples in {:.3} s: {:.3} M samples/s",
        camera.width(),
        camera.height(),
        samples,
        best_render,
        samples as f64 / best_render / 1e6
    ));
    let m = film.mean();
    let mut quality = String::new();
    if let Some((path, reference)) = &reference {
        let c = opticks_io::compare::compare(&film.to_rgb_f32(), reference);
        let efficiency = 1.0 / (c.relmse * (best_trace + best_render));
        output::result(&format!(
            "quality        relMSE {:.4e} vs {}; mean ratio {:.4} {:.4} {:.4}; efficiency 1/(relMSE·s) = {efficiency:.1}",
            c.relmse,
            path.display(),
            c.mean_ratio[0],
            c.mean_ratio[1],
            c.mean_ratio[2]
        ));
        quality = format!(
            ",\"relmse\":{},\"efficiency\":{}",
            json_number(c.relmse, 6, true),
            json_number(efficiency, 3, false)
        );
    }
    let mean = m.map(|x| json_number(x, 6, false)).join(",");
    output::data(&format!(
        "{{\"scene\":{},\"paths\":{},\"threads\":{threads},\"trace_s\":{},\"render_s\":{},\"samples\":{samples},\"mean_rgb\":[{mean}]{quality}}}",
        json_string(&a.scene.label()),
        a.paths,
        json_number(best_trace, 4, false),
        json_number(best_render, 4, false)
    ));
    Ok(())
}

/// `x` as a JSON number with `digits` decimals (in exponent form if `exp`), or `null` when it
/// is not finite: JSON has no infinity or NaN, and the line must parse whatever was rendered.
fn json_number(x: f64, digits: usize, exp: bool) -> String {
    match (x.is_finite(), exp) {
        (false, _) => "null".into(),
        (true, true) => format!("{x:.digits$e}"),
        (true, false) => format!("{x:.digits$}"),
    }
}

/// `s` as a JSON string (quotes, backslashes and control characters escaped).
fn json_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 10, item 20: `bench` printed `"mean_rgb":[inf,inf,inf]`, which no JSON parser reads.
    #[test]
    fn the_json_line_has_only_json_numbers_and_strings() {
        assert_eq!(json_number(f64::INFINITY, 6, false), "null");
        assert_eq!(json_number(f64::NAN, 6, true), "null");
        assert_eq!(json_number(0.5, 3, false), "0.500");
        assert_eq!(json_number(4.069e-3, 3, true), "4.069e-3");
        assert_eq!(json_string("a\"b\\c\n"), "\"a\\\"b\\\\c\\u000a\"");
    }
}
