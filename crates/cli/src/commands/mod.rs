//! One module per verb: each parses its arguments, calls the core (`opticks_core::dataset` for
//! every dataset operation) and io (`opticks_io::dataset_job` writes every dataset), and prints.
//! The shared steps — open a dataset against its scene, render with a progress bar, write the
//! image(s), word the library's errors the command line's way — live here so every verb does
//! them the same way.

pub mod add_light;
pub mod bench;
pub mod demo;
pub mod extend_args;
pub mod info;
pub mod light_args;
pub mod measure;
pub mod merge;
pub mod refine;
pub mod render;
pub mod resume;
pub mod trace;
pub mod walk;

use crate::progress;
use anyhow::{Context, Result, anyhow};
use opticks_core::dataset::{Chunk, LightTable, LightingError, check_scene, lighting, subset};
use opticks_core::film::Film;
use opticks_core::scene::{Scene, SceneDescription};
use opticks_core::sensor::{SampleBatch, Sensor, render};
use opticks_io::dataset_file::DatasetReader;
use opticks_io::dataset_job::{JobError, JobReport};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

/// `--threads`, shared by every verb that computes.
#[derive(clap::Args, Debug)]
pub struct ThreadArgs {
    /// Worker threads (0 = all cores).
    #[arg(long, default_value_t = 0)]
    threads: usize,
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
/// which load `scene` (the file the verb loaded its scene from) themselves.
pub fn write_job(
    scene: &str,
    output: &Path,
    header: opticks_core::dataset::DatasetHeader,
    sources: &[opticks_io::dataset_job::Source<'_>],
    new: Option<opticks_io::dataset_job::NewPaths<'_>>,
    progress: &dyn opticks_io::dataset_job::JobProgress,
) -> Result<JobReport, JobError> {
    #[cfg(feature = "mpi")]
    if crate::cluster::is_master() {
        let tracer = crate::cluster::trace::ClusterTracer::new(scene);
        return opticks_io::dataset_job::write_dataset_with(output, header, sources, new, progress, &tracer);
    }
    let _ = scene;
    opticks_io::dataset_job::write_dataset(output, header, sources, new, progress)
}

/// The outcome of a dataset job run with a time limit: the report, or `None` when the time was
/// up first — then the paths traced so far are saved as `NAME.partial.opds` (said here), which
/// `opticks resume` completes, and that is a success.
pub fn unless_time_up(
    result: Result<JobReport, JobError>,
    progress: &crate::progress::TraceProgress,
) -> Result<Option<JobReport>> {
    match result {
        Err(JobError::Interrupted { output, partial, paths }) if progress.time_was_up() => {
            println!(
                "time up after {paths} paths: saved {} (a valid dataset; `opticks resume {}` traces the rest \
                 into {})",
                partial.display(),
                partial.display(),
                output.display()
            );
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
        JobError::Interrupted { partial, .. } => anyhow!(
            "{e} (a valid dataset: render it, or `opticks resume {}` to finish the run)",
            partial.display()
        ),
        _ => e.into(),
    }
}

/// An error once Ctrl-C was pressed: reading and rendering stop at the next batch, and the
/// verb writes nothing (`render`, `walk`, `measure`, `merge`; traces save their work instead).
pub fn unless_interrupted() -> Result<()> {
    if crate::interrupt::requested() {
        anyhow::bail!("interrupted: stopped, nothing written");
    }
    Ok(())
}

/// Renders `count` sample batches through `camera` with a progress bar over `total_samples`;
/// stops with an error on Ctrl-C.
pub fn render_with_progress<'a>(
    scene: &Scene,
    camera: &Sensor,
    count: usize,
    total_samples: u64,
    batch: impl Fn(usize) -> Result<SampleBatch<'a>> + Sync,
) -> Result<Film> {
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
/// the ranks of a cluster job (`crate::cluster::render`): the film, or `None` on a worker rank,
/// whose part went to the master. The image is the same either way, bit for bit.
pub fn render_film<'a>(
    scene: &Scene,
    camera: &Sensor,
    count: usize,
    total_samples: u64,
    batch: impl Fn(usize) -> Result<SampleBatch<'a>> + Sync,
) -> Result<Option<Film>> {
    #[cfg(feature = "mpi")]
    if crate::cluster::active() {
        let pb = progress::bar(0, "rendering", "runs");
        let batch = |i| {
            unless_interrupted()?;
            batch(i)
        };
        let film = crate::cluster::render::render(scene, camera, count, batch, |done, runs| {
            pb.set_length(runs as u64);
            pb.set_position(done as u64);
        })?;
        pb.finish_and_clear();
        return Ok(film);
    }
    render_with_progress(scene, camera, count, total_samples, batch).map(Some)
}

/// The scene file a dataset is used with: `scene` if given, else the one recorded in it.
pub fn scene_spec<'a>(reader: &'a DatasetReader, scene: Option<&'a str>) -> &'a str {
    scene.unwrap_or(&reader.header().label)
}

/// Opens a dataset and the scene it is to be used with — `scene` if given, else the scene file
/// recorded in the dataset — and checks that the geometry and materials are those it was traced
/// in (`opticks_core::dataset::check_scene`; lights are checked one by one where they are used:
/// see `opticks_core::dataset::lighting`).
pub fn open_with_scene(
    dataset: &Path,
    scene: Option<&str>,
) -> Result<(DatasetReader, SceneDescription, Scene)> {
    let reader = DatasetReader::open(dataset)?;
    let label = &reader.header().label;
    let spec = scene_spec(&reader, scene);
    let context =
        || format!("cannot load the dataset's scene (recorded as '{label}'; pass --scene to name it)");
    let description = crate::scene_arg::load_description(spec).with_context(context)?;
    let scene = crate::scene_arg::build_scene(spec, &description)?;
    check_scene(reader.header(), &scene).map_err(|e| {
        anyhow!(
            "{} was traced from a different scene than {spec}: geometry/material fingerprint {} ≠ {}",
            dataset.display(),
            e.recorded.geometry_hex(),
            e.current.geometry_hex()
        )
    })?;
    Ok((reader, description, scene))
}

/// The dataset a view is rendered from, with its scene and relighting (`render`, `walk`,
/// `measure`).
#[derive(clap::Args, Debug)]
pub struct DatasetArgs {
    /// Dataset file written by `opticks trace`.
    dataset: std::path::PathBuf,
    /// Scene file the dataset was traced from (default: the path recorded in the dataset).
    #[arg(long)]
    scene: Option<String>,
    /// Relight: NAME_OR_INDEX=SCALE or NAME_OR_INDEX=R,G,B multiplies that light's power
    /// (0 switches it off); repeatable. No re-tracing: exact.
    #[arg(long = "light", value_parser = light_args::parse_light_scale, allow_hyphen_values = true)]
    light: Vec<opticks_core::dataset::LightScale>,
}

/// An opened dataset, its scene, and the flux each light's samples stand for — over all its
/// chunks, or over a subset ([`LitDataset::keep_fraction`]).
pub struct LitDataset {
    /// The memory-mapped dataset.
    pub reader: DatasetReader,
    /// The scene as loaded (meters find surfaces by name in it).
    pub description: SceneDescription,
    /// The validated scene.
    pub scene: Scene,
    lighting: opticks_core::dataset::Lighting,
    chunks: Vec<usize>,
}

impl DatasetArgs {
    /// Opens the dataset against its scene and works out the lighting; prints the notes.
    pub fn open(&self) -> Result<LitDataset> {
        let (reader, description, scene) = open_with_scene(&self.dataset, self.scene.as_deref())?;
        let lighting = lighting(&reader.header().table, &scene, &self.light).map_err(|e| match &e {
            LightingError::NotTraced(name) => {
                anyhow!("{e}: add it with `opticks add-light`, or switch it off with --light '{name}=0'")
            }
            LightingError::ShapeChanged(_) => anyhow!("{e} (re-trace the scene)"),
            _ => e.into(),
        })?;
        for note in &lighting.notes {
            eprintln!("note: {note}");
        }
        let chunks = (0..reader.chunk_count()).collect();
        Ok(LitDataset { reader, description, scene, lighting, chunks })
    }
}

impl LitDataset {
    /// Number of batches.
    pub fn count(&self) -> usize {
        self.chunks.len()
    }

    /// Samples in the batches.
    pub fn samples(&self) -> u64 {
        self.chunks.iter().filter_map(|&i| self.reader.chunk_summary(i)).map(|(_, _, n)| n as u64).sum()
    }

    /// Batch `i`: a chunk's samples with their light's (relit) flux per path.
    pub fn batch(&self, i: usize) -> Result<SampleBatch<'_>> {
        let c = self.reader.chunk(self.chunks[i])?;
        Ok(SampleBatch { flux_per_path: self.lighting.flux_per_path[c.light as usize], samples: c.samples })
    }

    /// Keeps about `fraction` of each light's chunks (evenly spread) and renormalises, by the
    /// preview-subset law (`opticks_core::dataset::subset`): the kept chunks' samples stand for
    /// Φ_k/N'_k each — an unbiased estimate from fewer paths, a cheaper, noisier preview.
    pub fn keep_fraction(&mut self, fraction: f64) -> Result<()> {
        let chunks: Vec<(u32, u64)> = (0..self.reader.chunk_count())
            .filter_map(|i| self.reader.chunk_summary(i))
            .map(|(light, paths, _)| (light, paths))
            .collect();
        let kept = subset(&chunks, self.lighting.flux_per_path.len(), fraction)?;
        for (flux, scale) in self.lighting.flux_per_path.iter_mut().zip(kept.flux_scale) {
            *flux *= scale;
        }
        self.chunks = kept.chunks;
        Ok(())
    }
}

/// Writes the film to `path` (format from the extension).
pub fn write_film(film: &Film, path: &Path, exposure: f32) -> Result<()> {
    opticks_io::image_file::write_image(path, film.width, film.height, &film.to_rgb_f32(), exposure)
        .with_context(|| format!("cannot write image {}", path.display()))
}

/// Renders in-memory chunks (as traced, with the table's Φ_k/N_k).
pub fn render_chunks(scene: &Scene, camera: &Sensor, table: &LightTable, chunks: &[Chunk]) -> Result<Film> {
    let total = chunks.iter().map(|c| c.samples.len() as u64).sum();
    render_with_progress(scene, camera, chunks.len(), total, |i| {
        let c = &chunks[i];
        Ok(SampleBatch { flux_per_path: table.flux_per_path(c.light as usize), samples: &c.samples })
    })
}
