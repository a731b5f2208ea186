//! The scene: a plain [`SceneDescription`] that every file format loads into, and the validated,
//! ray-traceable [`Scene`] built from it (BVH, per-triangle data, light table, fingerprint).

mod build;
mod camera_path;
mod demo;
mod description;
mod fingerprint;

pub use build::{Scene, SceneError};
pub use camera_path::{CameraKey, CameraPath, CameraPathError};
pub use demo::{CORNELL_LIGHT_RADIANCE, cornell_box};
pub use description::{CameraDesc, DirectionalLightDesc, MeshDesc, PointLightDesc, SceneDescription, Source};
pub use fingerprint::Fingerprint;
