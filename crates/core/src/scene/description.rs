//! The plain scene description: what every loader (Mitsuba XML, OBJ, VRML, glTF, the built-in
//! demo) produces. World-space triangles, materials, lights and an optional camera; no
//! acceleration structures, nothing validated yet. [`crate::scene::Scene::build`] validates it.

use crate::bsdf::Material;
use crate::math::{Rgb, Vec3};
use crate::scene::CameraDesc;

/// Where a scene element came from, for error messages ("scene.xml:42").
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Source {
    /// File path as given by the user (empty for built-in scenes).
    pub file: String,
    /// 1-based line, 0 if unknown.
    pub line: u32,
}

impl std::fmt::Display for Source {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.file.is_empty(), self.line) {
            (true, _) => write!(f, "<built-in>"),
            (false, 0) => write!(f, "{}", self.file),
            (false, l) => write!(f, "{}:{}", self.file, l),
        }
    }
}

/// A triangle mesh in world space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshDesc {
    /// Name (shape id) for messages.
    pub name: String,
    /// Where it was declared.
    pub source: Source,
    /// World-space vertex positions.
    pub positions: Vec<Vec3>,
    /// Counter-clockwise triangles (front face normal = (v1-v0)×(v2-v0)).
    pub triangles: Vec<[u32; 3]>,
    /// Index into [`SceneDescription::materials`].
    pub material: usize,
    /// If set, the mesh is a one-sided Lambertian area light of this radiance, W/(m²·sr).
    pub emission: Option<Rgb>,
}

/// An isotropic point light.
#[derive(Clone, Debug, PartialEq)]
pub struct PointLightDesc {
    /// Name for messages and relighting.
    pub name: String,
    /// Where it was declared.
    pub source: Source,
    /// Position, world space.
    pub position: Vec3,
    /// Radiant intensity, W/sr (power Φ = 4π·I).
    pub intensity: Rgb,
}

/// Everything a loader produces.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneDescription {
    /// Materials referenced by meshes.
    pub materials: Vec<Material>,
    /// Triangle meshes (area lights are meshes with `emission`).
    pub meshes: Vec<MeshDesc>,
    /// Point lights.
    pub point_lights: Vec<PointLightDesc>,
    /// The scene file's own camera, if it has one.
    pub camera: Option<CameraDesc>,
}
