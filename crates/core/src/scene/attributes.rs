//! Mesh attributes in the built scene: per attribute name, the values at each triangle's
//! corners ([`AttributeTable`]), flattened with the triangles (`super::meshes::Flat`) and read
//! by `mesh_attribute` textures at a point's triangle and barycentrics
//! ([`super::Scene::material_at`]). A loader keeps only the attributes a texture uses, so
//! untextured scenes carry none.

use super::{MeshAttribute, MeshDesc, SceneError};
use crate::math::Rgb;

/// No value of this attribute on a triangle (its mesh does not have it).
const NONE: u32 = u32::MAX;

/// One attribute name's values over the scene's triangles.
#[derive(Clone, Debug, Default)]
pub(super) struct AttributeTable {
    /// The attribute's name (`vertex_…` or `face_…`).
    pub name: String,
    /// Per scene triangle (those before the first mesh with the attribute and after the last
    /// one are missing): index into `corners`, or [`NONE`].
    of: Vec<u32>,
    /// The values at the corners of the triangles that have the attribute (a face attribute's
    /// value three times).
    corners: Vec<[Rgb; 3]>,
}

impl AttributeTable {
    /// An empty table of attribute `name`.
    pub fn new(name: String) -> Self {
        AttributeTable { name, of: Vec::new(), corners: Vec::new() }
    }

    /// Records the corner values of scene triangle `triangle`.
    pub fn push(&mut self, triangle: usize, corners: [Rgb; 3]) {
        self.of.resize(triangle, NONE);
        self.of.push(self.corners.len() as u32);
        self.corners.push(corners);
    }

    /// The corner values of scene triangle `prim`, if its mesh has the attribute.
    #[inline]
    pub fn corners(&self, prim: u32) -> Option<&[Rgb; 3]> {
        let k = *self.of.get(prim as usize)?;
        self.corners.get(k as usize)
    }

    /// The attribute at barycentrics (b1, b2) of triangle `prim`: its corners blended (Mitsuba's
    /// `interpolate_attribute`; a face attribute's corners are equal), zero where the mesh has
    /// none (the scene refuses textures on such meshes).
    #[inline]
    pub fn at(&self, prim: u32, b1: f32, b2: f32) -> Rgb {
        match self.corners(prim) {
            Some([a, b, c]) => (1.0 - b1 - b2) * *a + b1 * *b + b2 * *c,
            None => Rgb::ZERO,
        }
    }
}

/// Checks the attributes of `mesh`: named `vertex_…` or `face_…`, each name once, one or three
/// channels, one finite value per vertex or per triangle.
pub(super) fn check(mesh: &MeshDesc) -> Result<(), SceneError> {
    for (i, a) in mesh.attributes.iter().enumerate() {
        let bad = |message: String| SceneError::BadAttribute {
            at: mesh.source.clone(),
            mesh: mesh.name.clone(),
            attribute: a.name.clone(),
            message,
        };
        let (count, what) = if a.per_vertex() {
            (mesh.positions.len(), "vertices")
        } else if a.name.starts_with("face_") {
            (mesh.triangles.len(), "triangles")
        } else {
            return Err(bad("the name must start with \"vertex_\" or \"face_\"".into()));
        };
        if mesh.attributes[..i].iter().any(|b| b.name == a.name) {
            return Err(bad("given twice".into()));
        }
        if !matches!(a.channels, 1 | 3) {
            return Err(bad(format!("{} channels (1 or 3 are supported)", a.channels)));
        }
        if a.values.len() != count {
            return Err(bad(format!("{} values for {count} {what} (one each)", a.values.len())));
        }
        if let Some(k) = a.values.iter().position(|v| !v.is_finite()) {
            return Err(bad(format!("value {k} {} is not finite", a.values[k])));
        }
    }
    Ok(())
}

/// The corner values of a mesh's triangle `triangle` (of vertex indices `t`, as flattened).
#[inline]
pub(super) fn corner_values(a: &MeshAttribute, triangle: usize, t: [u32; 3]) -> [Rgb; 3] {
    if a.per_vertex() { t.map(|i| a.values[i as usize]) } else { [a.values[triangle]; 3] }
}
