//! `opticks bench`: tracing and rendering speed on a scene, in memory (no disk in the timing).
//! Reports light paths/s, stored samples/s and render time; runs each phase `--repeat` times
//! and reports the best, so a one-off hiccup of the machine does not count. Everything traced is
//! held in memory, so a `--paths` the machine cannot hold is refused before the runs (its bytes
//! measured on a pilot trace, `opticks_core::bench::memory_estimate`).

use super::ThreadArgs;
use crate::camera_args::CameraArgs;
use crate::output;
use crate::scene_arg::load_scene;
use crate::strategy_args::StrategyArgs;
use anyhow::Result;

/// Arguments of `opticks bench`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file or `builtin:cornell`; several Radiance .rad files are one scene, as for `trace`.
    #[arg(default_value = "builtin:cornell", value_parser = crate::scene_arg::parse_scene, num_args = 1..)]
    scene: Vec<opticks_io::scene_source::SceneRef>,
    /// Light paths per run; e.g. 4194304, 4M, 4e6.
    #[arg(long, allow_hyphen_values = true, value_parser = opticks_io::count_text::parse_count, default_value_t = 4_194_304)]
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
    let scene_ref = crate::scene_arg::joined(&a.scene)?.expect("a default scene");
    let scene = load_scene(&scene_ref, &a.defines)?;
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
    // Every traced sample is held in memory: refuse a count the machine cannot hold.
    let need = opticks_core::bench::memory_estimate(&scene, &settings);
    opticks_io::memory::check_fits(
        &format!("--paths {} (its traced samples, held in memory)", a.paths),
        need,
    )
    .map_err(|e| anyhow::anyhow!("{e}: choose fewer --paths"))?;
    let report = opticks_core::bench::bench(&scene, &camera, &settings, a.repeat);
    let (best_trace, best_render, samples, film) =
        (report.trace_seconds, report.render_seconds, report.samples, report.film);
    let threads = rayon::current_num_threads();
    output::result(&format!(
        "scene          {} ({} triangles, {threads} threads)",
        scene_ref,
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
    let mut line = serde_json::json!({
        "scene": scene_ref.label(),
        "paths": a.paths,
        "threads": threads,
        "trace_s": round(best_trace, 4),
        "render_s": round(best_render, 4),
        "samples": samples,
        "mean_rgb": m.map(|x| round(x, 6)),
    });
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
        line["relmse"] = significant(c.relmse, 7).into();
        line["efficiency"] = round(efficiency, 3).into();
    }
    output::data(&line.to_string());
    Ok(())
}

/// `x` as a JSON number with `digits` decimals (in exponent form if `exp`), or `null` when it
/// is not finite: JSON has no infinity or NaN, and the line must parse whatever was rendered.
/// `x` rounded to `digits` decimals (JSON has no NaN or infinity: those are `null`).
fn round(x: f64, digits: i32) -> Option<f64> {
    let scale = 10f64.powi(digits);
    x.is_finite().then(|| (x * scale).round() / scale)
}

/// `x` to `digits` significant digits (`null` if not finite).
fn significant(x: f64, digits: usize) -> Option<f64> {
    x.is_finite().then(|| format!("{x:.*e}", digits - 1).parse().unwrap_or(x))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_rounded_and_non_finite_ones_are_null() {
        assert_eq!(round(f64::INFINITY, 6), None);
        assert_eq!(significant(f64::NAN, 7), None);
        assert_eq!(round(0.123456, 3), Some(0.123));
        assert_eq!(significant(4.0691234e-3, 4), Some(4.069e-3));
    }
}
