//! What a dataset holds (`opticks info`), as one typed value a front end prints or serialises:
//! every chunk's checksum verified, the scene as the dataset records it and where it was found,
//! each pass with the options that repeat it, whether the bidirectional estimator can weight
//! it, and each light's Φ_k and N_k.
//!
//! [`DatasetInfo`] serialises (serde) to the JSON object `opticks info --json` prints, and
//! [`DatasetInfo::lines`] gives the readable summary; both come from the same fields, so the two
//! never disagree.

use crate::dataset_file::DatasetReader;
use crate::memory::readable_bytes;
use crate::opened::{OpenError, OpenedDataset};
use crate::scene_ref::{self, RecordedScene};
use opticks_core::dataset::{Choice, DatasetHeader, MisUnavailable, mis_compatibility};
use opticks_core::scene::{ObjectHash, ObjectKind};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The scene a dataset records.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum SceneInfo {
    /// A built-in scene.
    Builtin {
        /// Its name.
        builtin: String,
    },
    /// A scene file, relative to the dataset's folder and absolute.
    File {
        /// Relative to the dataset's folder.
        relative: PathBuf,
        /// Absolute.
        absolute: PathBuf,
    },
    /// A path recorded by a dataset format before both were kept.
    Recorded {
        /// As recorded.
        recorded: String,
    },
}

/// One trace pass.
#[derive(Clone, Debug, Serialize)]
pub struct PassInfo {
    /// Its seed.
    pub seed: u64,
    /// Its random stream.
    pub stream: u64,
    /// Paths traced.
    pub paths: u64,
    /// Paths planned.
    pub planned_paths: u64,
    /// Whether every planned path was traced.
    pub complete: bool,
    /// Whether `opticks resume` can finish it (unfinished, and the last pass).
    pub resumable: bool,
    /// Wall-clock seconds it took.
    pub seconds: f32,
    /// Russian roulette (`--roulette`).
    pub roulette: &'static str,
    /// Depth from which roulette applies (`--rr-depth`).
    pub rr_depth: u32,
    /// Emission directions (`--directions`).
    pub directions: &'static str,
    /// Light selection (`--selection`).
    pub selection: &'static str,
    /// MIS records' heuristic (`--mis-records`).
    pub mis_records: &'static str,
    /// The sampling signature the MIS records were computed with.
    pub sampling_signature: Option<u32>,
}

impl PassInfo {
    /// The options that would repeat this pass: `--roulette energy --rr-depth 5 …`.
    pub fn options(&self) -> String {
        format!(
            "--roulette {} --rr-depth {} --directions {} --selection {} --mis-records {}{}",
            self.roulette,
            self.rr_depth,
            self.directions,
            self.selection,
            self.mis_records,
            self.sampling_signature.map_or(String::new(), |s| format!(" (sampling signature {s})"))
        )
    }

    /// What is to be said of it if it is unfinished: only the last pass can be resumed.
    pub fn state(&self) -> Option<String> {
        match (self.complete, self.resumable) {
            (true, _) => None,
            (false, true) => Some(format!(
                "interrupted: {} of {} planned paths (`opticks resume` finishes it)",
                self.paths, self.planned_paths
            )),
            (false, false) => Some(format!(
                "interrupted: {} of {} planned paths (passes were added after it, so it cannot be resumed)",
                self.paths, self.planned_paths
            )),
        }
    }
}

/// One light of the dataset's table.
#[derive(Clone, Debug, Serialize)]
pub struct LightInfo {
    /// Its name.
    pub name: String,
    /// Paths traced from it (N_k).
    pub paths: u64,
    /// Its power Φ_k, W per RGB channel.
    pub power_w: [f32; 3],
}

/// A mesh or material whose hash the dataset records.
#[derive(Clone, Debug, Serialize)]
pub struct ObjectInfo {
    /// `mesh` or `material`.
    pub kind: &'static str,
    /// Its name.
    pub name: String,
}

impl From<&ObjectHash> for ObjectInfo {
    fn from(o: &ObjectHash) -> Self {
        ObjectInfo { kind: o.kind.word(), name: o.name.clone() }
    }
}

/// What a dataset holds.
#[derive(Clone, Debug, Serialize)]
pub struct DatasetInfo {
    /// The dataset file.
    pub dataset: PathBuf,
    /// How far its samples were checked: against the scene's triangles, or why not.
    pub checked: String,
    /// The scene it records: its first file, when it was read from several (`scene_files`).
    pub scene: SceneInfo,
    /// Every file of the scene, in the order they were read (several Radiance `.rad` files are
    /// one scene); one entry otherwise.
    pub scene_files: Vec<SceneInfo>,
    /// The scene files found for it, one per line, if every one was found.
    pub scene_found: Option<String>,
    /// Hash of the scene's geometry.
    pub geometry_fingerprint: String,
    /// Hash of the scene's lights.
    pub lights_fingerprint: String,
    /// The meshes and materials hashed one by one.
    pub objects: Vec<ObjectInfo>,
    /// Its trace passes, in order.
    pub passes: Vec<PassInfo>,
    /// Whether the bidirectional estimator can weight it.
    pub bidirectional: bool,
    /// Paths traced, all lights.
    pub paths: u64,
    /// Samples stored.
    pub samples: u64,
    /// Chunks stored.
    pub chunks: usize,
    /// File size, bytes.
    pub bytes: u64,
    /// The lights.
    pub lights: Vec<LightInfo>,
    /// Why the bidirectional estimator cannot weight it, if it cannot; else its MIS heuristic.
    #[serde(skip)]
    pub mis: Result<&'static str, MisUnavailable>,
    /// Where the scene is recorded and which copy is found (readable lines).
    #[serde(skip)]
    pub scene_lines: Vec<String>,
    /// What loading its scene did not reproduce exactly.
    #[serde(skip)]
    pub warnings: Vec<String>,
}

impl DatasetInfo {
    /// Reads `dataset`, checks its samples against its scene's triangles when the scene loads,
    /// and verifies every chunk's checksum: `info` is also the integrity check.
    #[allow(clippy::result_large_err)] // once per run, as `OpenedDataset::open`
    pub fn read(dataset: &Path) -> Result<DatasetInfo, OpenError> {
        crate::output_paths::check_input_file(dataset, "a dataset").map_err(OpenError::Unreadable)?;
        // Opened against its scene, the dataset's reader checks every sample's triangle; if the
        // scene cannot be had, a reader of the file alone still checks the rest.
        let (reader, checked, warnings) = match OpenedDataset::open(dataset, None, &Default::default()) {
            Ok(opened) => {
                let triangles = opened.scene.triangles.len();
                let checked = format!("every sample checked against its scene's {triangles} triangles");
                (opened.reader, checked, opened.warnings)
            }
            Err(e) => {
                let checked = format!("samples not checked against the scene: {}", crate::error_chain(&e));
                (DatasetReader::open(dataset)?, checked, Vec::new())
            }
        };
        reader.verify()?;
        Ok(Self::of(dataset, &reader, checked, warnings))
    }

    fn of(dataset: &Path, reader: &DatasetReader, checked: String, warnings: Vec<String>) -> DatasetInfo {
        let h: &DatasetHeader = reader.header();
        let n = h.trace.passes.len();
        let scene = match scene_ref::parse(&h.label) {
            RecordedScene::Builtin(builtin) => SceneInfo::Builtin { builtin },
            RecordedScene::File { relative, absolute } => SceneInfo::File { relative, absolute },
            RecordedScene::Legacy(recorded) => SceneInfo::Recorded { recorded },
        };
        let scene_files = match &scene {
            SceneInfo::File { relative, absolute } => std::iter::once((relative.clone(), absolute.clone()))
                .chain(scene_ref::further_files(&h.label))
                .map(|(relative, absolute)| SceneInfo::File { relative, absolute })
                .collect(),
            other => vec![other.clone()],
        };
        let passes = (h.trace.passes.iter().enumerate())
            .map(|(i, p)| PassInfo {
                seed: p.seed,
                stream: p.stream,
                paths: p.paths,
                planned_paths: p.planned_paths(),
                complete: p.is_complete(),
                resumable: !p.is_complete() && i + 1 == n,
                seconds: p.seconds,
                roulette: p.roulette.name(),
                rr_depth: p.rr_depth,
                directions: p.directions.name(),
                selection: p.selection.name(),
                mis_records: p.mis.map(|m| m.heuristic).name(),
                sampling_signature: p.mis.map(|m| m.signature),
            })
            .collect();
        let lights = (h.table.lights.iter())
            .map(|l| LightInfo { name: l.name.clone(), paths: l.paths, power_w: l.power.to_array() })
            .collect();
        let objects = h.objects.iter().map(ObjectInfo::from).collect();
        let mis = mis_compatibility(h).map(|m| Some(m.heuristic).name());
        DatasetInfo {
            dataset: dataset.to_owned(),
            checked,
            scene,
            scene_files,
            scene_found: scene_ref::resolve(&h.label, dataset).ok(),
            geometry_fingerprint: h.fingerprint.geometry_hex(),
            lights_fingerprint: h.fingerprint.lights_hex(),
            objects,
            passes,
            bidirectional: mis.is_ok(),
            paths: h.table.total_paths(),
            samples: reader.total_samples(),
            chunks: reader.chunk_count(),
            bytes: reader.file_len(),
            lights,
            mis,
            scene_lines: scene_ref::describe(&h.label, dataset),
            warnings,
        }
    }

    /// The readable summary, a line each.
    pub fn lines(&self) -> Vec<String> {
        let mut out = vec![format!("dataset   {}", self.dataset.display())];
        for (i, line) in self.scene_lines.iter().enumerate() {
            out.push(format!("{}{line}", if i == 0 { "scene     " } else { "          " }));
        }
        out.push(format!("checked   {}", self.checked));
        out.push(format!("geometry  {}", self.geometry_fingerprint));
        out.push(format!("lights    {}", self.lights_fingerprint));
        out.push(format!("objects   {}", objects_summary(&self.objects)));
        for p in &self.passes {
            let state = p.state().map(|s| format!(" — {s}")).unwrap_or_default();
            out.push(format!(
                "pass      seed {}, stream {}: {} paths in {:.2} s; {}{state}",
                p.seed,
                p.stream,
                p.paths,
                p.seconds,
                p.options()
            ));
        }
        out.push(match &self.mis {
            Ok(heuristic) => {
                format!("mis       the bidirectional estimator can weight it ({heuristic} heuristic)")
            }
            Err(e) => format!("mis       not usable by the bidirectional estimator: {e}"),
        });
        out.push(format!("paths     {}", self.paths));
        out.push(format!(
            "samples   {} ({:.2} per path)",
            self.samples,
            self.samples as f64 / self.paths.max(1) as f64
        ));
        out.push(format!("chunks    {}", self.chunks));
        out.push(format!(
            "size      {} ({} bytes, {:.1} bytes/sample)",
            readable_bytes(self.bytes),
            self.bytes,
            self.bytes as f64 / self.samples.max(1) as f64
        ));
        out.push(format!("{:>5}  {:<24} {:>14}  power Φ (W, RGB)", "light", "name", "paths N_k"));
        for (k, l) in self.lights.iter().enumerate() {
            out.push(format!(
                "{k:>5}  {:<24} {:>14}  {:.6} {:.6} {:.6}",
                l.name, l.paths, l.power_w[0], l.power_w[1], l.power_w[2]
            ));
        }
        out
    }
}

/// `12 meshes and 6 materials hashed (a refusal names which changed)`, or that an older
/// dataset records none.
fn objects_summary(objects: &[ObjectInfo]) -> String {
    if objects.is_empty() {
        return "not recorded (dataset format < 4: a refusal cannot name which mesh or material changed)"
            .into();
    }
    let meshes = objects.iter().filter(|o| o.kind == ObjectKind::Mesh.word()).count();
    let count = |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    format!(
        "{} and {} hashed (a refusal names which changed)",
        count(meshes, "mesh", "meshes"),
        count(objects.len() - meshes, "material", "materials")
    )
}
