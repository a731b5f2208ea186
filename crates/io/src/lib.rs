//! # opticks-io
//!
//! File formats for Opticks, everything that touches the disk:
//!
//! * [`scene_formats`]: scene files (Mitsuba 3 XML, OBJ) → `opticks_core::scene::SceneDescription`;
//! * [`dataset_file`]: the persistent dataset (`.opds`): atomic writer, reader by explicit reads;
//! * [`dataset_job`]: writing a dataset — copying chunks, tracing into it, finishing it
//!   atomically, saving an interrupted run as `NAME.partial.opds`;
//! * [`dataset_lock`]: what a dataset writer checks first — the lock against a second writer,
//!   stale temporary files of killed runs, a pending partial run, an existing target;
//! * [`output_paths`]: the rules every output path obeys (its extension, its directory, never an
//!   input of the command), checked before any work;
//! * [`scene_source`]: the scene a front end works on (built-in or a file), loaded and built;
//! * [`opened`]: a dataset opened against its scene, checked and relit — what every use of a
//!   dataset starts with, whatever the front end;
//! * [`scene_ref`]: the scene file a dataset records (relative to the dataset, and absolute);
//! * [`image_file`]: OpenEXR and PNG output (atomic writes), EXR input;
//! * [`texture_file`]: texture images (PNG, JPEG, HDR, EXR) as linear RGB, sizes checked first;
//! * [`camera_path_file`]: camera paths (JSON keyframes) for walkthroughs, and their frames' cameras;
//! * [`video`]: a walkthrough's frames as an MP4 video through ffmpeg;
//! * [`ies`]: IES LM-63 photometric files → `opticks_core::light::IesProfile`;
//! * [`heatmap`]: heat-map PNGs of meter readings (colour bar, numbered axes);
//! * [`meter_table`]: a meter's reading as the CSV table `measure` writes;
//! * [`daylight`]: the daylight factor under a CIE overcast sky (what it is relative to, when);
//! * [`meter_points`]: the points an illuminance meter reads at (`x,y,z,nx,ny,nz` lines);
//! * [`light_cache`]: the bidirectional estimator's light vertex cache over a dataset file;
//! * [`compare`]: the image comparison the project is judged by (relative MSE, mean ratios);
//! * [`input_file`]: how every reader opens its files (regular files only, bounded by their size);
//! * [`memory`]: the memory available, checked before a large film is allocated;
//! * [`count_text`]: counts as people write them (`4M`, `1e6`, `4,000,000`), exactly;
//! * [`cluster_wire`]: the messages of a cluster (MPI) job as bytes — jobs, blocks, chunks.

pub mod batch_pool;
pub mod camera_path_file;
pub mod cluster_wire;
pub mod compare;
pub mod count_text;
pub mod dataset_file;
pub mod dataset_info;
pub mod dataset_job;
pub mod dataset_lock;
pub mod daylight;
pub mod heatmap;
pub mod ies;
pub mod image_file;
pub mod input_file;
pub mod light_cache;
pub mod measurement;
pub mod memory;
pub mod meter_points;
pub mod meter_table;
pub mod opened;
pub mod output_paths;
pub mod scene_formats;
pub mod scene_ref;
pub mod scene_source;
pub mod texture_file;
pub mod video;

pub use scene_formats::{
    FileLocation, LoadLimits, LoadOptions, LoadedScene, SceneFileError, load_scene, load_scene_with,
};

/// An error and its causes joined by ": ", leaving out a cause whose text the message before it
/// already ends with (errors that show their source in their own message, as most `thiserror`
/// types here do, would otherwise say it twice): how a front end words a library error.
pub fn error_chain(e: &(dyn std::error::Error + 'static)) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(cause) = source {
        let part = cause.to_string();
        if !text.ends_with(&part) {
            text.push_str(": ");
            text.push_str(&part);
        }
        source = cause.source();
    }
    text
}
