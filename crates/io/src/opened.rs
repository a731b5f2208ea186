//! A dataset opened against its scene: the step every use of a dataset starts with — render,
//! walk, measure, refine, add a light, resume, upgrade — whatever the front end (the command
//! line, a binding, a server).
//!
//! [`OpenedDataset::open`] reads the dataset's header, finds the scene it records
//! ([`crate::scene_ref`]: relative to the dataset, then absolute) unless one is given, loads and
//! builds it, and checks that its geometry and materials are those the dataset was traced in
//! (`opticks_core::dataset::check_scene`); lights are checked one by one where they are used.
//! [`OpenedDataset::lit`] then works out the flux each light's samples stand for, relit by the
//! caller's scales ([`LitDataset`]), which a renderer reads batch by batch. Errors are typed
//! ([`OpenError`]) so a front end can add its own way out (a flag to name the scene, a verb that
//! fixes it); what the user should know but is no error comes back as warnings and notes.

use crate::batch_pool::{BatchPool, PooledBatch};
use crate::dataset_file::{DatasetError, DatasetReader};
use crate::scene_formats::LoadOptions;
use crate::scene_source::{self, SceneRef, SceneSourceError};
use opticks_core::dataset::{
    ChangesText, LightScale, LightTable, Lighting, LightingError, MisUnavailable, check_scene,
    mis_compatibility, subset,
};
use opticks_core::math::Rgb;
use opticks_core::scene::{Scene, SceneDescription, SceneError};
use opticks_core::sensor::bidirectional::CacheChunk;
use opticks_core::sensor::bidirectional::run::{self, Coverage, Run, RunEvent, RunPlan};
use opticks_core::sensor::bidirectional::{RenderLights, Settings};
use opticks_core::sensor::bidirectional::{cameras_needed, pilot};
use opticks_core::sensor::meter::{
    Group, MeterEstimator, MeterLayout, Reading, read_connected_many, read_samples_many,
};
use opticks_core::sensor::{Sensor, VisibilityBuffer, render_with_buffer};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Why a dataset cannot be opened against a scene.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// The dataset file cannot be opened as one (missing, a directory, unreadable).
    #[error(transparent)]
    Unreadable(std::io::Error),
    /// The dataset file is damaged or not a dataset.
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    /// No scene was given and the one the dataset records is in none of the places tried.
    #[error("{}: cannot find the scene it was traced from (looked for {})", dataset.display(), list(tried))]
    SceneNotFound {
        /// The dataset.
        dataset: PathBuf,
        /// Where the scene was looked for.
        tried: Vec<PathBuf>,
    },
    /// The scene (given, or the one the dataset records) cannot be loaded.
    #[error("{}", if *given { "cannot load the scene given with --scene".to_string() } else { format!("cannot load the scene {} records", dataset.display()) })]
    Scene {
        /// The dataset.
        dataset: PathBuf,
        /// Whether the caller named the scene (else the dataset's record was used).
        given: bool,
        /// Why.
        #[source]
        source: Box<SceneSourceError>,
    },
    /// The scene has no light, so it cannot be the one a dataset (which needs one) was traced in.
    #[error(
        "{} was traced from a different scene than {scene}: {scene} has no light source, the dataset's lights are {}",
        dataset.display(), lights.join(", ")
    )]
    NoLight {
        /// The dataset.
        dataset: PathBuf,
        /// The scene.
        scene: SceneRef,
        /// The dataset's light names.
        lights: Vec<String>,
    },
    /// The scene's geometry or materials are not those the dataset was traced in.
    #[error(
        "{} was traced from a different scene than {scene}: {changes} (fingerprint {recorded} ≠ {current}; a scene \
         traced with -D parameters or --gltf-scene needs the same ones, which a dataset records from now on){lights}",
        dataset.display()
    )]
    DifferentScene {
        /// The dataset.
        dataset: PathBuf,
        /// The scene.
        scene: SceneRef,
        /// What changed, in words.
        changes: String,
        /// The dataset's geometry fingerprint (hex).
        recorded: String,
        /// The scene's (hex).
        current: String,
        /// "; lights …" naming lights only one of them has (empty if none).
        lights: String,
    },
    /// The lighting asked for is impossible (an unknown light, one not traced, one moved).
    #[error(transparent)]
    Lighting(#[from] LightingError),
}

fn list(paths: &[PathBuf]) -> String {
    let paths: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    paths.join(" and ")
}

/// Why the bidirectional estimator cannot render a dataset ([`LitDataset::render_bidirectional`]).
#[derive(Debug, thiserror::Error)]
pub enum BidirectionalError {
    /// The dataset's MIS records cannot weight the estimator (none, or inexact).
    #[error("{}: {source}", path.display())]
    Mis {
        /// The dataset.
        path: PathBuf,
        /// Why.
        source: MisUnavailable,
    },
    /// A chunk of a pass with MIS records has none.
    #[error("{}: a chunk of a pass with MIS records has none", .0.display())]
    MissingRecords(PathBuf),
    /// Reading the dataset failed.
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    /// `stop` asked the render to end.
    #[error("interrupted: stopped, nothing written")]
    Interrupted,
}

/// Why a measurement ([`LitDataset::measure`]) failed.
#[derive(Debug, thiserror::Error)]
pub enum MeasureError {
    /// The samples estimator was asked to read points.
    #[error(
        "the samples estimator counts samples landing on a surface and cannot read points: use connections"
    )]
    SamplesAtPoints,
    /// Reading the dataset failed.
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    /// `stop` asked the measurement to end.
    #[error("interrupted: stopped, nothing written")]
    Interrupted,
}

/// A dataset opened against its scene.
pub struct OpenedDataset {
    /// The dataset, its samples checked against the scene's triangles as they are read.
    pub reader: DatasetReader,
    /// The scene as loaded.
    pub description: SceneDescription,
    /// The validated scene.
    pub scene: Scene,
    /// The scene used: what a dataset written from this one records.
    pub scene_ref: SceneRef,
    /// The options the scene was loaded with: those given, or, when none that change the scene
    /// were given (`-D`, `--gltf-scene`), those the dataset records
    /// ([`crate::scene_ref::recorded_options`]); the memory limits are always those given. What
    /// a dataset written from this one records.
    pub options: LoadOptions,
    /// What loading the scene did not reproduce exactly (`file:line:column: …`, one a line).
    pub warnings: Vec<String>,
}

impl OpenedDataset {
    /// Opens `dataset` against `scene` — given, or else the scene file the dataset records —
    /// loaded with `options` (or, if they set no `-D` parameter and no glTF scene, with those
    /// the dataset records), and checks that it is the scene the dataset was traced in.
    #[allow(clippy::result_large_err)] // once per run, and the error carries what the user needs
    pub fn open(dataset: &Path, scene: Option<&SceneRef>, options: &LoadOptions) -> Result<Self, OpenError> {
        crate::output_paths::check_input_file(dataset, "a dataset").map_err(OpenError::Unreadable)?;
        let mut reader = DatasetReader::open(dataset)?;
        let options = if options.defines.is_empty() && options.gltf_scene.is_none() {
            LoadOptions {
                camera: options.camera.clone(),
                limits: options.limits,
                ..crate::scene_ref::recorded_options(&reader.header().label)
            }
        } else {
            options.clone()
        };
        let options = &options;
        let scene_ref = match scene {
            Some(s) => s.clone(),
            None => {
                let label = &reader.header().label;
                let spec = crate::scene_ref::resolve(label, dataset)
                    .map_err(|tried| OpenError::SceneNotFound { dataset: dataset.to_path_buf(), tried })?;
                SceneRef::parse(&spec).map_err(|source| OpenError::Scene {
                    dataset: dataset.to_path_buf(),
                    given: false,
                    source: Box::new(source),
                })?
            }
        };
        let scene_error = |source| OpenError::Scene {
            dataset: dataset.to_path_buf(),
            given: scene.is_some(),
            source: Box::new(source),
        };
        let loaded = scene_source::load(&scene_ref, options).map_err(scene_error)?;
        let mut warnings = loaded.warnings;
        let built = scene_source::build(&scene_ref, &loaded.description).map_err(|e| match e {
            // A scene without lights cannot be the one a dataset was traced in (a trace needs a
            // light): say so, rather than only that the scene is unusable.
            SceneSourceError::Invalid { source, .. } if matches!(*source, SceneError::NoLight) => {
                OpenError::NoLight {
                    dataset: dataset.to_path_buf(),
                    scene: scene_ref.clone(),
                    lights: reader.header().table.lights.iter().map(|l| l.name.clone()).collect(),
                }
            }
            e => scene_error(e),
        })?;
        warnings.extend(built.warning);
        let scene = built.scene;
        check_scene(reader.header(), &scene).map_err(|e| OpenError::DifferentScene {
            dataset: dataset.to_path_buf(),
            scene: scene_ref.clone(),
            changes: ChangesText(e.changes.as_ref()).to_string(),
            recorded: e.recorded.geometry_hex(),
            current: e.current.geometry_hex(),
            lights: lights_changed(&reader.header().table, &scene),
        })?;
        reader.check_triangles(scene.triangles.len());
        Ok(OpenedDataset {
            reader,
            description: loaded.description,
            scene,
            scene_ref,
            options: options.clone(),
            warnings,
        })
    }

    /// The flux each light's samples stand for, relit by `scales` (each multiplies one light's
    /// power, by name or index; 0 switches it off): the dataset ready to render or measure.
    #[allow(clippy::result_large_err)] // once per run
    pub fn lit(self, scales: &[LightScale]) -> Result<LitDataset, OpenError> {
        let lighting = opticks_core::dataset::lighting(&self.reader.header().table, &self.scene, scales)?;
        let chunks = (0..self.reader.chunk_count()).collect();
        Ok(LitDataset {
            opened: self,
            lighting,
            chunks,
            cache: OnceLock::new(),
            buffers: BatchPool::default(),
        })
    }
}

/// "; lights …" naming the dataset's lights the scene lacks and the scene's the dataset lacks.
fn lights_changed(table: &LightTable, scene: &Scene) -> String {
    let traced: Vec<&str> = table.lights.iter().map(|l| l.name.as_str()).collect();
    let current: Vec<&str> = scene.lights.iter().map(|l| l.name()).collect();
    let gone: Vec<&str> = traced.iter().copied().filter(|n| !current.contains(n)).collect();
    let new: Vec<&str> = current.iter().copied().filter(|n| !traced.contains(n)).collect();
    let mut out = String::new();
    if !gone.is_empty() {
        out += &format!("; lights of the dataset missing from the scene: {}", gone.join(", "));
    }
    if !new.is_empty() {
        out += &format!("; lights of the scene not in the dataset: {}", new.join(", "));
    }
    out
}

/// An opened dataset, its scene, and the flux each light's samples stand for — over all its
/// chunks, or over a subset ([`LitDataset::keep_fraction`]).
pub struct LitDataset {
    opened: OpenedDataset,
    lighting: Lighting,
    chunks: Vec<usize>,
    /// The kept chunks in memory, once the bidirectional estimator has asked for them.
    cache: OnceLock<Vec<opticks_core::dataset::Chunk>>,
    /// The buffers of batches read and done with, for the next reads.
    buffers: BatchPool,
}

impl LitDataset {
    /// The dataset file.
    pub fn reader(&self) -> &DatasetReader {
        &self.opened.reader
    }

    /// The validated scene.
    pub fn scene(&self) -> &Scene {
        &self.opened.scene
    }

    /// The scene as loaded (meters find surfaces by name in it).
    pub fn description(&self) -> &SceneDescription {
        &self.opened.description
    }

    /// What loading the scene did not reproduce exactly.
    pub fn warnings(&self) -> &[String] {
        &self.opened.warnings
    }

    /// What relighting the user should know (a light relit by the scene file, one gone).
    pub fn notes(&self) -> &[String] {
        &self.lighting.notes
    }

    /// Number of batches.
    pub fn count(&self) -> usize {
        self.chunks.len()
    }

    /// Samples in the batches.
    pub fn samples(&self) -> u64 {
        self.chunks.iter().filter_map(|&i| self.reader().chunk_summary(i)).map(|(_, _, n)| n as u64).sum()
    }

    /// Batch `i`: a chunk's samples, read from the file (each checked to name one of the
    /// scene's triangles), with their light's (relit) flux per path.
    pub fn batch(&self, i: usize) -> Result<PooledBatch<'_>, DatasetError> {
        let mut samples = self.buffers.take();
        let (light, _) = self.reader().read_chunk(self.chunks[i], &mut samples)?;
        Ok(self.buffers.batch(self.lighting.flux_per_path[light as usize], samples))
    }

    /// The kept chunks as independent groups of paths (light, paths), in batch order: what a
    /// meter's standard error is estimated from.
    pub fn groups(&self) -> Vec<Group> {
        self.chunks
            .iter()
            .map(|&i| {
                let (light, paths, _) = self.reader().chunk_summary(i).unwrap_or_default();
                Group { light, paths }
            })
            .collect()
    }

    /// The dataset's light names, in table order.
    pub fn light_names(&self) -> Vec<&str> {
        self.reader().header().table.lights.iter().map(|l| l.name.as_str()).collect()
    }

    /// Per table light, the flux Φ'_k/N_k its samples stand for (relit; over the kept chunks).
    pub fn flux_per_path(&self) -> &[Rgb] {
        &self.lighting.flux_per_path
    }

    /// Per table light, the factor `--light` scales multiplied its scene power by (1 unless
    /// scaled): what a quantity computed from the scene's light itself must be multiplied by.
    pub fn light_factors(&self) -> &[Rgb] {
        &self.lighting.factors
    }

    /// The kept chunks as the bidirectional estimator's light vertex cache (each verified),
    /// read into memory on the first call and kept for the next ones (a walkthrough's frames).
    pub fn cache_chunks(&self) -> Result<Vec<CacheChunk<'_>>, DatasetError> {
        let chunks = match self.cache.get() {
            Some(c) => c,
            None => {
                let read = crate::light_cache::read_cache(self.reader(), &self.chunks)?;
                self.cache.get_or_init(|| read)
            }
        };
        crate::light_cache::cache_views(self.reader(), chunks)
    }

    /// Keeps about `fraction` of each light's chunks (evenly spread) and renormalises, by the
    /// preview-subset law (`opticks_core::dataset::subset`): the kept chunks' samples stand for
    /// Φ_k/N'_k each — an unbiased estimate from fewer paths, a cheaper, noisier preview.
    pub fn keep_fraction(&mut self, fraction: f64) -> Result<(), opticks_core::dataset::BadFraction> {
        let chunks: Vec<(u32, u64)> = (0..self.reader().chunk_count())
            .filter_map(|i| self.reader().chunk_summary(i))
            .map(|(light, paths, _)| (light, paths))
            .collect();
        let kept = subset(&chunks, self.lighting.flux_per_path.len(), fraction)?;
        self.cache = OnceLock::new();
        for (flux, scale) in self.lighting.flux_per_path.iter_mut().zip(kept.flux_scale) {
            *flux *= scale;
        }
        self.chunks = kept.chunks;
        Ok(())
    }

    /// Reads a meter over the kept chunks: irradiance per target with its standard error, E_v
    /// by the scene's photometric rule (`opticks_core::scene::Photometry`).
    /// `progress(n)` counts samples read; `stop` is asked between batches and ends the reading
    /// with [`MeasureError::Interrupted`].
    pub fn measure(
        &self,
        layout: &MeterLayout,
        estimator: MeterEstimator,
        progress: impl Fn(usize) + Sync,
        stop: impl Fn() -> bool + Sync,
    ) -> Result<Reading, MeasureError> {
        Ok(self.measure_many(&[layout], estimator, progress, stop)?.remove(0))
    }

    /// [`LitDataset::measure`] for several meters with the same estimator in one pass over the
    /// kept chunks (each read once): a reading per layout, in their order, each the same bit for
    /// bit as that layout measured alone (`opticks_core::sensor::meter::read_samples_many`,
    /// `read_connected_many`). `progress` counts each sample read once, whatever the meters.
    pub fn measure_many(
        &self,
        layouts: &[&MeterLayout],
        estimator: MeterEstimator,
        progress: impl Fn(usize) + Sync,
        stop: impl Fn() -> bool + Sync,
    ) -> Result<Vec<Reading>, MeasureError> {
        let groups = self.groups();
        let batch = self.stoppable_batch(&stop, || MeasureError::Interrupted);
        let readings = match estimator {
            MeterEstimator::Samples => {
                let grids = layouts
                    .iter()
                    .map(|l| match l {
                        MeterLayout::Grid(meter) => Ok(meter),
                        MeterLayout::Points(_) => Err(MeasureError::SamplesAtPoints),
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                read_samples_many(&grids, self.scene(), &groups, batch, progress)?
            }
            MeterEstimator::Connections(settings) => {
                let paths = Group::paths_per_light(&groups, self.flux_per_path().len());
                let lights =
                    RenderLights::new(self.scene(), &self.light_names(), self.flux_per_path(), &paths);
                read_connected_many(
                    self.scene(),
                    &lights,
                    layouts,
                    settings,
                    &groups,
                    batch,
                    progress,
                    &stop,
                )?
                .ok_or(MeasureError::Interrupted)?
            }
        };
        if stop() {
            return Err(MeasureError::Interrupted);
        }
        Ok(readings)
    }

    /// Renders through `camera` with the bidirectional estimator (`opticks_core::sensor::
    /// bidirectional::run`): the kept chunks as its light vertex cache, weighted with the
    /// heuristic and direction rule the dataset's records were traced for; `connections` (n_c)
    /// cache vertices per camera vertex, camera streams named by `seed`, passes as `plan` says,
    /// camera paths in the pixels `coverage` chooses (with none, the light estimator's image,
    /// streamed without reading the cache).
    /// `event` follows the run; `stop` ends it ([`BidirectionalError::Interrupted`]).
    #[allow(clippy::too_many_arguments)]
    pub fn render_bidirectional(
        &self,
        camera: Sensor,
        connections: u32,
        seed: u64,
        plan: RunPlan,
        coverage: Coverage,
        event: impl Fn(RunEvent) + Sync,
        stop: impl Fn() -> bool + Sync,
    ) -> Result<Run, BidirectionalError> {
        let path = || self.reader().path().to_path_buf();
        let mis = mis_compatibility(self.reader().header())
            .map_err(|source| BidirectionalError::Mis { path: path(), source })?;
        let settings = Settings { connections, seed, heuristic: mis.heuristic, directions: mis.directions };
        let names = self.light_names();
        // Built once: it chooses the pixels that need camera paths (unless they all get them)
        // and then serves the render's splats and first hits.
        let buffer = camera.visibility(self.scene());
        let needed = match coverage {
            Coverage::Everywhere => None,
            Coverage::WhereNeeded | Coverage::Auto => {
                buffer.as_ref().and_then(|b| cameras_needed(self.scene(), &camera, b))
            }
        };
        let cameras = match (coverage, needed) {
            // No pixel needs camera paths: the light estimator's image first, which is also the
            // pilot's light half (kept as the render when the pilot chooses no camera paths).
            (Coverage::Auto, Some(needed)) if !needed.contains(&true) => {
                let samples = self.samples();
                let pilot_plan = pilot::Plan { spp: plan.spp, connections, samples };
                event(RunEvent::SplatStart(samples));
                let first = pilot::light_first(
                    self.scene(),
                    &camera,
                    buffer.as_ref(),
                    &self.groups(),
                    self.stoppable_batch(&stop, || BidirectionalError::Interrupted),
                    |n| event(RunEvent::Splatted(n)),
                    &names,
                    self.flux_per_path(),
                    settings,
                    pilot_plan,
                    &stop,
                )?;
                match first.ok_or(BidirectionalError::Interrupted)? {
                    pilot::LightFirst::Image(film) => return Ok(Run::splats_alone(film)),
                    pilot::LightFirst::Cameras(c) => Some(c),
                }
            }
            (Coverage::Auto, Some(needed)) => {
                let groups = self.groups();
                let pilot_plan = pilot::Plan { spp: plan.spp, connections, samples: self.samples() };
                let chosen = pilot::choose(
                    self.scene(),
                    &camera,
                    buffer.as_ref(),
                    &needed,
                    &groups,
                    |i| self.batch(i),
                    &names,
                    self.flux_per_path(),
                    settings,
                    pilot_plan,
                    &stop,
                )?;
                Some(chosen.ok_or(BidirectionalError::Interrupted)?)
            }
            (_, needed) => needed,
        };
        if cameras.as_ref().is_some_and(|c| !c.contains(&true)) {
            return self.render_splats_alone(camera, buffer, event, stop);
        }
        let chunks = self.cache_chunks()?;
        if !chunks.iter().all(|c| c.records.len() == c.samples.len()) {
            return Err(BidirectionalError::MissingRecords(path()));
        }
        let flux = self.flux_per_path();
        run::render(
            self.scene(),
            camera,
            buffer,
            chunks,
            &names,
            flux,
            settings,
            plan,
            cameras.as_deref(),
            event,
            stop,
        )
        .ok_or(BidirectionalError::Interrupted)
    }

    /// The bidirectional render when no pixel needs camera paths ([`cameras_needed`]): every
    /// splat then weighs 1, so the image is the light estimator's, and it is rendered as that
    /// one is — streamed chunk by chunk, without the light vertex cache (the same estimate the
    /// cache would give, without reading the whole dataset into memory first). `buffer` is the
    /// camera's visibility buffer, already built to choose the pixels.
    fn render_splats_alone(
        &self,
        camera: Sensor,
        buffer: Option<VisibilityBuffer>,
        event: impl Fn(RunEvent) + Sync,
        stop: impl Fn() -> bool + Sync,
    ) -> Result<Run, BidirectionalError> {
        event(RunEvent::SplatStart(self.samples()));
        let batch = self.stoppable_batch(&stop, || BidirectionalError::Interrupted);
        let splatted = |n| event(RunEvent::Splatted(n));
        let film = render_with_buffer(self.scene(), &camera, buffer, self.count(), batch, splatted)?;
        Ok(Run::splats_alone(film))
    }

    /// [`LitDataset::batch`] that fails with `interrupted()` once `stop()` says so, before
    /// reading (what a measurement and a render ask for their batches).
    fn stoppable_batch<'s, E: From<DatasetError> + 's>(
        &'s self,
        stop: &'s (impl Fn() -> bool + Sync),
        interrupted: fn() -> E,
    ) -> impl Fn(usize) -> Result<PooledBatch<'s>, E> + Sync + 's {
        move |i| {
            if stop() {
                return Err(interrupted());
            }
            Ok(self.batch(i)?)
        }
    }
}
