//! Why a [`super::SceneDescription`] is not a valid scene: [`SceneError`], which names the
//! element and where it was declared.

use super::Source;
use crate::light::LightError;

/// Why a scene description is not a valid scene.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// A vertex coordinate is NaN or infinite.
    #[error("{at}: mesh '{mesh}': vertex {vertex} is not finite ({value:?})")]
    NonFiniteVertex {
        /// Where the mesh was declared.
        at: Source,
        /// Mesh name.
        mesh: String,
        /// Vertex index.
        vertex: usize,
        /// The bad value.
        value: [f32; 3],
    },
    /// A triangle refers to a vertex that does not exist.
    #[error(
        "{at}: mesh '{mesh}': triangle {triangle} refers to vertex {index}, but the mesh has {count} vertices"
    )]
    IndexOutOfRange {
        /// Where the mesh was declared.
        at: Source,
        /// Mesh name.
        mesh: String,
        /// Triangle index.
        triangle: usize,
        /// The bad vertex index.
        index: u32,
        /// Vertex count.
        count: usize,
    },
    /// A mesh's vertex normals do not match its vertices, or one is zero or not finite.
    #[error("{at}: mesh '{mesh}': {message}")]
    BadNormals {
        /// Where the mesh was declared.
        at: Source,
        /// Mesh name.
        mesh: String,
        /// What is wrong.
        message: String,
    },
    /// A mesh attribute is malformed (its name, channels, count or values).
    #[error("{at}: mesh '{mesh}': attribute \"{attribute}\": {message}")]
    BadAttribute {
        /// Where the mesh was declared.
        at: Source,
        /// Mesh name.
        mesh: String,
        /// The attribute's name.
        attribute: String,
        /// What is wrong.
        message: String,
    },
    /// A mesh refers to a material that does not exist.
    #[error("{at}: mesh '{mesh}' refers to material {material}, but the scene has {count}")]
    MissingMaterial {
        /// Where the mesh was declared.
        at: Source,
        /// Mesh name.
        mesh: String,
        /// The bad material index.
        material: usize,
        /// Material count.
        count: usize,
    },
    /// A light's parameters are impossible (negative or non-finite emission or power, a bad
    /// position, axis, tangent or orientation, an impossible profile).
    #[error("{at}: light '{light}': {source}")]
    Light {
        /// Where the light was declared.
        at: Source,
        /// Light name.
        light: String,
        /// The light's constraint that fails.
        #[source]
        source: LightError,
    },
    /// An emissive mesh has no area.
    #[error("{at}: area light '{light}' has no triangle of non-zero area")]
    EmptyAreaLight {
        /// Where the light was declared.
        at: Source,
        /// Light name.
        light: String,
    },
    /// A texture binding is impossible: no such material, a colour the material does not
    /// have, or values the parameter cannot take.
    #[error("material '{material}': texture on {slot}: {message}")]
    BadTexture {
        /// Material name (or index, if it does not exist).
        material: String,
        /// The parameter's name.
        slot: &'static str,
        /// What is wrong.
        message: String,
    },
    /// Nothing to render.
    #[error("the scene has no triangles: light paths would have nothing to hit")]
    NoGeometry,
    /// Two lights share a name (lights are matched by name when relighting).
    #[error("two lights are named '{0}': light names must be unique")]
    DuplicateLightName(String),
    /// Nothing emits.
    #[error("the scene has no light source (an area emitter or a point light)")]
    NoLight,
    /// The lights' powers are each finite but their sum is not (quotas are shared out by it).
    #[error("the lights' total power is not a finite number of watts: their emission is too large")]
    TotalPowerNotFinite,
}
