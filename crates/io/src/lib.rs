//! # opticks-io
//!
//! File formats for Opticks, everything that touches the disk:
//!
//! * [`scene_formats`]: scene files (Mitsuba 3 XML, OBJ) → `opticks_core::scene::SceneDescription`;
//! * [`dataset_file`]: the persistent dataset (`.opds`): atomic writer, memory-mapped reader;
//! * [`dataset_job`]: writing a dataset — copying chunks, tracing into it, finishing it
//!   atomically, saving an interrupted run as `NAME.partial.opds`;
//! * [`image_file`]: OpenEXR and PNG output (atomic writes), EXR input;
//! * [`camera_path_file`]: camera paths (JSON keyframes) for walkthroughs;
//! * [`ies`]: IES LM-63 photometric files → `opticks_core::light::IesProfile`;
//! * [`heatmap`]: heat-map PNGs of meter readings (colour bar, numbered axes);
//! * [`compare`]: the image comparison the project is judged by (relative MSE, mean ratios);
//! * [`cluster_wire`]: the messages of a cluster (MPI) job as bytes — jobs, blocks, chunks.

pub mod camera_path_file;
pub mod cluster_wire;
pub mod compare;
pub mod dataset_file;
pub mod dataset_job;
pub mod heatmap;
pub mod ies;
pub mod image_file;
pub mod scene_formats;

pub use scene_formats::{
    FileLocation, LoadOptions, LoadedScene, SceneFileError, load_scene, load_scene_with,
};
