//! The scene: a plain [`SceneDescription`] that every file format loads into, and the validated,
//! ray-traceable [`Scene`] built from it (BVH, per-triangle data, light table, fingerprint).
//!
//! | file | what lives there |
//! |---|---|
//! | `description.rs` | [`SceneDescription`] and its parts: meshes ([`AreaEmission`] on an emissive one), point and directional lights, the file's [`CameraDesc`] |
//! | `build.rs` | [`Scene`] and [`Scene::build`], which runs the stages below in order |
//! | `meshes.rs` | stages 1–2: validate each mesh, flatten it into triangles with shading normals |
//! | `attributes.rs` | mesh attributes: their checks, and their values at the triangles' corners for `mesh_attribute` textures |
//! | `lights.rs` | stage 3: the lights, through the light kinds' constructors |
//! | `textures.rs` | stage 4: texture bindings checked per material; materials resolved at a point |
//! | `hashes.rs` | stage 5: the fingerprints of the built scene |
//! | `fingerprint.rs` | [`Fingerprint`] and the hashing primitives |
//! | `objects.rs` | per-mesh and per-material hashes ([`ObjectHash`]) and what differs between two lists of them |
//! | `panes.rs` | shadow rays through thin panes ([`Scene::shadow_transmittance`], the illuminance meter's) |
//! | `photometry.rs` | [`Photometry`]: how the scene's RGB becomes lux (its format's rule) |
//! | `error.rs` | [`SceneError`] |
//! | `camera_path.rs` | walkthrough camera paths |
//! | `demo.rs` | the built-in Cornell box |

mod attributes;
mod build;
mod camera_path;
mod demo;
mod description;
mod error;
mod fingerprint;
mod hashes;
mod lights;
mod meshes;
mod objects;
mod panes;
mod photometry;
mod textures;

pub use build::Scene;
pub use camera_path::{CameraKey, CameraPath, CameraPathError};
pub use demo::{CORNELL_LIGHT_RADIANCE, cornell_box};
pub use description::{
    AreaEmission, CameraDesc, CameraKind, DirectionalLightDesc, EnvironmentLightDesc, EnvironmentRadiance,
    MeshAttribute, MeshDesc, PointLightDesc, SceneDescription, SkyModel, Source,
};
pub use error::SceneError;
pub use fingerprint::Fingerprint;
pub use objects::{Change, ObjectChanges, ObjectHash, ObjectKind, object_changes};
pub use panes::MAX_PANES;
pub use photometry::Photometry;
