//! # opticks-io
//!
//! File formats for Opticks: scene loaders ([`scene_formats`]).

pub mod scene_formats;

pub use scene_formats::{
    FileLocation, LoadOptions, LoadedScene, SceneFileError, load_scene, load_scene_with,
};
