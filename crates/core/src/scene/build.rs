//! Scene (being written).
/// s
pub struct Scene;
/// e
#[derive(Debug, thiserror::Error)]
#[error("x")]
pub struct SceneError;
/// t
pub struct Triangle;
