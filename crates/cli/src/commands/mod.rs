//! One module per verb: each parses its arguments, calls the core (`opticks_core::dataset` for
//! every dataset operation) and io (`opticks_io::dataset_job` writes every dataset), and prints.
//! The shared steps — open a dataset against its scene, render with a progress bar, write the
//! image(s), word the library's errors the command line's way — live here so every verb does
//! them the same way.

pub mod add_light;
pub mod bench;
pub mod demo;
pub mod estimator;
pub mod extend_args;
pub mod info;
pub mod light_args;
pub mod measure;
pub mod merge;
pub mod refine;
pub mod render;
pub mod resume;
pub mod trace;
pub mod upgrade;
pub mod walk;

use crate::progress;
use crate::scene_arg::DefineArgs;
use anyhow::{Context, Result, anyhow};
use opticks_core::dataset::{Chunk, LightTable, LightingError};
use opticks_core::film::Film;
use opticks_core::scene::Scene;
use opticks_core::sensor::{AsBatch, SampleBatch, Sensor, render};
use opticks_io::dataset_job::{JobError, JobReport};
use opticks_io::dataset_lock::{WriteIntent, WriteLock, WriteRefused, begin_write, same_file};
use opticks_io::opened::{LitDataset, OpenError, OpenedDataset};
use opticks_io::output_paths::{OutputKind, check_outputs_in_place};
use opticks_io::scene_source::SceneRef;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

/// `--threads`, shared by every verb that computes.
#[derive(clap::Args, Debug)]
pub struct ThreadArgs {
    /// Worker threads (0 = all cores; at most 4 × the cores).
    #[arg(long, default_value_t = 0, value_parser = parse_threads)]
    threads: usize,
}

/// Most worker threads per core `--threads` accepts: more only costs (each thread's stack and
/// its share of the film batches), and tens of thousands of threads took minutes to start.
pub const MAX_THREADS_PER_CORE: usize = 4;

/// Parses `--threads`: 0 (all cores) up to [`MAX_THREADS_PER_CORE`] × the cores available.
fn parse_threads(s: &str) -> Result<usize> {
    let n: usize = s.trim().parse().map_err(|_| anyhow!("'{s}' is not a thread count (0 = all cores)"))?;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let max = MAX_THREADS_PER_CORE * cores;
    if n > max {
        anyhow::bail!(
            "at most {max} threads on this machine ({MAX_THREADS_PER_CORE} × its {cores} cores); 0 uses all cores"
        );
    }
    Ok(n)
}

impl ThreadArgs {
    /// The thread count asked for (0: all cores).
    pub fn count(&self) -> usize {
        self.threads
    }

    /// Sizes rayon's global pool.
    pub fn apply(&self) -> Result<()> {
        if self.threads > 0 {
            rayon::ThreadPoolBuilder::new()
                .num_threads(self.threads)
                .build_global()
                .context("cannot set --threads")?;
        }
        Ok(())
    }
}

/// Writes a dataset (`opticks_io::dataset_job::write_dataset`), its new paths traced in this
/// process or — in the cluster build, on the master of an `mpirun` job — by the worker ranks,
/// which load `scene` (the file the verb loaded its scene from, with its `-D` parameters)
/// themselves.
pub fn write_job(
    scene: (&SceneRef, &opticks_io::scene_formats::LoadOptions),
    output: &Path,
    header: opticks_core::dataset::DatasetHeader,
    sources: &[opticks_io::dataset_job::Source<'_>],
    new: Option<opticks_io::dataset_job::NewPaths<'_>>,
    progress: &dyn opticks_io::dataset_job::JobProgress,
) -> Result<JobReport, JobError> {
    #[cfg(feature = "mpi")]
    if opticks_cluster::is_master() {
        let tracer = opticks_cluster::ClusterTracer::new(scene.0, scene.1, crate::cluster::HOOKS);
        return opticks_io::dataset_job::write_dataset_with(output, header, sources, new, progress, &tracer);
    }
    let _ = scene;
    opticks_io::dataset_job::write_dataset(output, header, sources, new, progress)
}

/// The outcome of a dataset job run with a time limit: the report (a run whose time was up is
/// complete with the paths it traced), or `None` when the time was up before every light had a
/// path — then the paths traced so far are saved as `NAME.partial.opds` (said here), which
/// `opticks resume` completes, and that is a success.
pub fn unless_time_up(
    result: Result<JobReport, JobError>,
    progress: &crate::progress::TraceProgress,
) -> Result<Option<JobReport>> {
    match result {
        Err(JobError::Interrupted { output, partial, paths }) if progress.time_was_up() => {
            crate::output::result(&format!(
                "time up after {paths} paths, before every light had a path: saved {} (`opticks resume {}` \
                 traces the rest into {})",
                partial.display(),
                partial.display(),
                output.display()
            ));
            Ok(None)
        }
        r => r.map(Some).map_err(job_error),
    }
}

/// A positive, finite number of seconds (`--time`).
pub fn parse_seconds(text: &str) -> Result<std::time::Duration, String> {
    match text.parse::<f64>() {
        Ok(s) if s.is_finite() && s > 0.0 && s < 1e12 => Ok(std::time::Duration::from_secs_f64(s)),
        _ => Err(format!("'{text}' is not a positive number of seconds")),
    }
}

/// A failed dataset job as the command line says it: an interrupted run names the verb that
/// finishes it.
pub fn job_error(e: JobError) -> anyhow::Error {
    match &e {
        JobError::Interrupted { partial, .. } | JobError::WriteFailed { partial: Some(partial), .. } => {
            anyhow!(
                "{e} (a valid dataset: render it, or `opticks resume {}` to finish the run)",
                partial.display()
            )
        }
        _ => e.into(),
    }
}

/// What a dataset verb does before anything else: checks its output path (`.opds`, not an
/// input), then takes the output's write lock (`opticks_io::dataset_lock`), reporting the
/// stale temporary files of killed runs it removed, and words a refusal the command line's way.
pub fn begin_dataset_write(output: &Path, intent: WriteIntent<'_>) -> Result<WriteLock> {
    let mut inputs = intent.inputs.to_vec();
    if let Some(p) = intent.resuming {
        inputs.push(p);
    }
    // A dataset may replace its own input in place (refine, add-light): the lock's rules.
    let (in_place, others): (Vec<&Path>, Vec<&Path>) =
        inputs.iter().copied().partition(|i| same_file(i, output));
    check_outputs_in_place(&[(output, OutputKind::Dataset)], &others, &in_place)?;
    let lock = begin_write(output, intent).map_err(|e| match &e {
        WriteRefused::Exists { .. } => anyhow!("{e}: give --overwrite to replace it"),
        WriteRefused::PendingPartial { partial, .. } => {
            anyhow!("{e} (`opticks resume {}` finishes it)", partial.display())
        }
        _ => e.into(),
    })?;
    note_removed_stale(&lock.removed_stale);
    if let Some((partial, paths)) = &lock.extended_partial {
        crate::output::note(&format!(
            "an earlier resumption of {} was killed; the blocks it had written were added to it ({paths} paths now)",
            partial.display()
        ));
    }
    Ok(lock)
}

/// Reports the temporary files of killed runs that a write removed (datasets and images alike).
pub fn note_removed_stale(removed: &[(std::path::PathBuf, u64)]) {
    for (path, bytes) in removed {
        crate::output::note(&format!(
            "removed {} ({}), the temporary file of an earlier run that was killed",
            path.display(),
            crate::output::bytes(*bytes)
        ));
    }
}

/// Refuses to extend a dataset whose last pass was interrupted (refine, add-light, merge).
pub fn check_finished(path: &Path, header: &opticks_core::dataset::DatasetHeader) -> Result<()> {
    opticks_core::dataset::check_finished(header)
        .map_err(|e| anyhow!("{}: {e} (`opticks resume {}`)", path.display(), path.display()))
}

/// Before a long trace ([`opticks_io::dataset_job::preflight`]): refuses a pass beyond the most
/// paths a dataset may hold, and warns when the dataset may not fit on its disk.
pub fn check_before_trace(
    output: &Path,
    table: &LightTable,
    pass: &opticks_core::dataset::PassPlan,
    estimate: u64,
) -> Result<()> {
    let shortfall = opticks_io::dataset_job::preflight(table, pass, output, estimate)
        .map_err(|e| anyhow!("cannot trace into {}: {e}", output.display()))?;
    if let Some(s) = shortfall {
        crate::output::warning(&format!(
            "{} will need about {} but its file system has {} free; if it fills up, the paths \
             written so far are kept in {}",
            output.display(),
            crate::output::bytes(s.needed),
            crate::output::bytes(s.free),
            opticks_io::dataset_job::partial_path(output).display()
        ));
    }
    Ok(())
}

/// Warns of what the light estimator cannot show through `sensor`: an environment seen directly,
/// and mirrors or smooth glass seen directly (`opticks_core::sensor::delta_fraction`), which it
/// renders black with all that is seen in or through them.
pub fn warn_light_estimator_blind_spots(scene: &opticks_core::scene::Scene, sensor: &Sensor) {
    if let Some(sky) = scene.lights.iter().find(|l| matches!(l, opticks_core::light::Light::Environment(_))) {
        crate::output::warning(&format!(
            "the light estimator does not show the environment '{}' itself (only what it lights): \
             render with --estimator bidirectional to see the sky",
            sky.name()
        ));
    }
    let delta = opticks_core::sensor::delta_fraction(scene, sensor);
    if delta > 0.0 {
        crate::output::warning(&format!(
            "{:.0}% of the view is a mirror or smooth glass seen directly, which the light estimator shows \
             black (with all that is seen in or through it): render with --estimator bidirectional",
            (100.0 * delta).max(1.0)
        ));
    }
}

/// Warns when an image or a measurement received nothing at all (`black`; `what` names the sensor):
/// because `--light` switched every light off (`flux_per_path` all zero), or else because of
/// where the sensor is.
pub fn warn_if_black(black: bool, samples: u64, what: &str, flux_per_path: &[opticks_core::math::Rgb]) {
    if !black {
        return;
    }
    if flux_per_path.iter().all(|f| *f == opticks_core::math::Rgb::ZERO) {
        crate::output::warning(&format!(
            "the {what} received nothing: --light switched every light of the dataset off"
        ));
    } else {
        crate::output::warning(&format!(
            "0 of {samples} samples reached the {what}: the image is black (is it inside a wall, facing \
             away from the light, or the lit side of a one-sided surface seen from behind?)"
        ));
    }
}

/// An error once a signal asked the work to stop: reading and rendering stop at the next batch,
/// and the verb writes nothing (`render`, `walk`, `measure`, `merge`; traces save their work
/// instead).
pub fn unless_interrupted() -> Result<()> {
    if crate::interrupt::requested() {
        anyhow::bail!("interrupted: stopped, nothing written");
    }
    Ok(())
}

/// Refuses, before any work, a film that does not fit in memory
/// ([`opticks_io::memory::check_film_fits`], with this process's rayon threads).
pub fn check_film_fits(what: &str, size: (u32, u32), output_bytes: u64) -> Result<()> {
    Ok(opticks_io::memory::check_film_fits(what, size, output_bytes, rayon::current_num_threads())?)
}

/// Bytes a pixel of an image output needs while it is written.
pub const IMAGE_OUTPUT_BYTES: u64 = opticks_io::memory::IMAGE_OUTPUT_BYTES;

/// Renders `count` sample batches through `camera` with a progress bar over `total_samples`;
/// stops with an error on Ctrl-C. The film is checked to fit in memory first
/// ([`check_film_fits`]).
pub fn render_with_progress<B: AsBatch>(
    scene: &Scene,
    camera: &Sensor,
    count: usize,
    total_samples: u64,
    batch: impl Fn(usize) -> Result<B> + Sync,
) -> Result<Film> {
    check_film_fits("an image", (camera.width(), camera.height()), IMAGE_OUTPUT_BYTES)?;
    let pb = progress::bar(total_samples, "rendering", "samples");
    let done = AtomicU64::new(0);
    let batch = |i| {
        unless_interrupted()?;
        batch(i)
    };
    let film = render(scene, camera, count, batch, |n| {
        let d = done.fetch_add(n as u64, Ordering::Relaxed) + n as u64;
        pb.set_position(d);
    })?;
    pb.finish_and_clear();
    Ok(film)
}

/// Renders `count` sample batches through `camera` like [`render_with_progress`], or split over
/// the ranks of a cluster job (`opticks_cluster::render`): the film, or `None` on a worker rank,
/// whose part went to the master. The image is the same either way, bit for bit.
pub fn render_film<B: AsBatch>(
    scene: &Scene,
    camera: &Sensor,
    count: usize,
    total_samples: u64,
    batch: impl Fn(usize) -> Result<B> + Sync,
) -> Result<Option<Film>> {
    #[cfg(feature = "mpi")]
    if opticks_cluster::active() {
        check_film_fits("an image", (camera.width(), camera.height()), IMAGE_OUTPUT_BYTES)?;
        let pb = progress::bar(0, "rendering", "runs");
        let batch = |i| {
            unless_interrupted()?;
            batch(i)
        };
        let progress = |done, runs| {
            pb.set_length(runs as u64);
            pb.set_position(done as u64);
        };
        let film =
            opticks_cluster::render(scene, camera, count, batch, progress, crate::interrupt::requested)?;
        pb.finish_and_clear();
        return Ok(film);
    }
    render_with_progress(scene, camera, count, total_samples, batch).map(Some)
}

/// This process's share of independent items (walk's frames): item i is this process's when
/// i mod `.1` = `.0` — (rank, ranks) under `mpirun` with more than one rank, else (0, 1).
pub fn my_share() -> (usize, usize) {
    #[cfg(feature = "mpi")]
    if opticks_cluster::active() {
        return opticks_cluster::rank_and_size();
    }
    (0, 1)
}

/// After this process's share ([`my_share`]): under `mpirun`, a worker reports it done and the
/// master waits for every worker's; whether this process goes on to finish the verb (the
/// master, or a process alone).
pub fn shares_done() -> Result<bool> {
    #[cfg(feature = "mpi")]
    if opticks_cluster::active() {
        opticks_cluster::share_done(crate::interrupt::requested)?;
        return Ok(opticks_cluster::is_master());
    }
    Ok(true)
}

/// Refuses `what` under `mpirun` with more than one rank (the cluster build): work that is not
/// split over the ranks is run as one process, never once per rank.
pub fn single_process_only(what: &str) -> Result<()> {
    #[cfg(feature = "mpi")]
    if opticks_cluster::active() {
        anyhow::bail!(
            "{what} does not run under mpirun yet (its camera passes are not split over the ranks): run it as \
             one process, `opticks render …` without mpirun (docs/cluster.md)"
        );
    }
    let _ = what;
    Ok(())
}

/// Opens a dataset against its scene (`opticks_io::opened`): `scene` if given, else the scene
/// file the dataset records; prints the loader's warnings and words the library's refusals
/// with the command line's way out.
pub fn open_with_scene(dataset: &Path, scene: Option<&SceneRef>, defines: &DefineArgs) -> Result<Opened> {
    let opened = OpenedDataset::open(dataset, scene, &defines.options()).map_err(open_error)?;
    for w in &opened.warnings {
        crate::output::warning(w);
    }
    Ok(opened)
}

/// A dataset opened against its scene.
pub type Opened = OpenedDataset;

/// A refusal of `opticks_io::opened` with the flag or verb that gets past it.
fn open_error(e: OpenError) -> anyhow::Error {
    match &e {
        OpenError::SceneNotFound { .. } => anyhow!("{e}: pass --scene to name it"),
        OpenError::Lighting(LightingError::NotTraced(name)) => {
            anyhow!("{e}: add it with `opticks add-light`, or switch it off with --light '{name}=0'")
        }
        OpenError::Lighting(LightingError::ShapeChanged(_)) => anyhow!("{e} (re-trace the scene)"),
        _ => e.into(),
    }
}

/// The dataset a view is rendered from, with its scene and relighting (`render`, `walk`,
/// `measure`).
#[derive(clap::Args, Debug)]
pub struct DatasetArgs {
    /// Dataset file written by `opticks trace`.
    dataset: std::path::PathBuf,
    /// Scene file the dataset was traced from (default: the path recorded in the dataset);
    /// repeated for a scene of several Radiance .rad files, in the order traced.
    #[arg(long, value_parser = crate::scene_arg::parse_scene)]
    scene: Vec<SceneRef>,
    /// Relight: NAME_OR_INDEX=SCALE or NAME_OR_INDEX=R,G,B multiplies that light's power
    /// (0 switches it off); repeatable. No re-tracing: exact.
    #[arg(long = "light", value_parser = light_args::parse_light_scale, allow_hyphen_values = true)]
    light: Vec<opticks_core::dataset::LightScale>,
    #[command(flatten)]
    defines: DefineArgs,
}

impl DatasetArgs {
    /// The command's input files (the dataset, the scene if given), which no output may replace.
    pub fn inputs(&self) -> Vec<&Path> {
        let mut inputs = vec![self.dataset.as_path()];
        inputs.extend(self.scene.iter().flat_map(SceneRef::files));
        inputs
    }

    /// The scene given with `--scene`, if any.
    pub fn scene(&self) -> Result<Option<SceneRef>> {
        crate::scene_arg::joined(&self.scene)
    }

    /// Opens the dataset against its scene and works out the lighting; prints the notes.
    pub fn open(&self) -> Result<LitDataset> {
        let opened = open_with_scene(&self.dataset, self.scene()?.as_ref(), &self.defines)?;
        let data = opened.lit(&self.light).map_err(open_error)?;
        for note in data.notes() {
            crate::output::note(note);
        }
        Ok(data)
    }
}

/// Writes the film to `path` (format from the extension).
pub fn write_film(film: &Film, path: &Path, exposure: f32) -> Result<()> {
    let removed =
        opticks_io::image_file::write_image(path, film.width, film.height, &film.to_rgb_f32(), exposure)
            .with_context(|| format!("cannot write image {}", path.display()))?;
    note_removed_stale(&removed);
    Ok(())
}

/// Renders in-memory chunks (as traced, with the table's Φ_k/N_k).
pub fn render_chunks(scene: &Scene, camera: &Sensor, table: &LightTable, chunks: &[Chunk]) -> Result<Film> {
    let total = chunks.iter().map(|c| c.samples.len() as u64).sum();
    render_with_progress(scene, camera, chunks.len(), total, |i| {
        let c = &chunks[i];
        Ok(SampleBatch { flux_per_path: table.flux_per_path(c.light as usize), samples: &c.samples })
    })
}
