//! The first stages of [`super::Scene::build`]: each mesh is validated ([`validate`]: material,
//! vertices, vertex normals, emitted radiance, indices) and then flattened into the scene's
//! triangle arrays ([`Flat::push_mesh`]), with its shading normals, texture coordinates and
//! attributes. Degenerate (zero-area) triangles are dropped there, since they can neither be
//! hit nor emit; so are finite triangles too large for single precision (their area or normal
//! overflows `f32`: nothing about them can be computed), counted apart so that the warning
//! says which it was.

use super::attributes::{self, AttributeTable};
use super::{MeshDesc, SceneError};
use crate::geometry::Triangle;
use crate::light::check::check_emission;
use crate::math::{Vec2, Vec3};

/// A triangle's vertex normals are ignored (the triangle is faceted) when each is within this
/// distance of its geometric normal: they could only change results by rounding.
const FLAT_TOLERANCE: f32 = 1e-5;

/// No shading normals on a triangle.
pub(super) const NO_SHADING: u32 = u32::MAX;

/// No texture coordinates on a triangle.
pub(super) const NO_UV: u32 = u32::MAX;

/// No light index.
pub(super) const NO_LIGHT: u32 = u32::MAX;

/// Checks `mesh` against a scene of `materials` materials, in this order: its material exists,
/// its vertices are finite, its vertex normals are usable, its emitted radiance is possible,
/// its triangles' indices are in range. Returns its unit vertex normals (empty when faceted).
pub(super) fn validate(mesh: &MeshDesc, materials: usize) -> Result<Vec<Vec3>, SceneError> {
    if mesh.material >= materials {
        return Err(SceneError::MissingMaterial {
            at: mesh.source.clone(),
            mesh: mesh.name.clone(),
            material: mesh.material,
            count: materials,
        });
    }
    if let Some((vertex, p)) = mesh.positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(SceneError::NonFiniteVertex {
            at: mesh.source.clone(),
            mesh: mesh.name.clone(),
            vertex,
            value: p.to_array(),
        });
    }
    let normals = unit_normals(mesh)?;
    check_uvs(mesh)?;
    attributes::check(mesh)?;
    if let Some(e) = &mesh.emission {
        check_emission(e.radiance).map_err(|source| SceneError::Light {
            at: mesh.source.clone(),
            light: mesh.name.clone(),
            source,
        })?;
    }
    for (triangle, t) in mesh.triangles.iter().enumerate() {
        if let Some(&index) = t.iter().find(|&&i| i as usize >= mesh.positions.len()) {
            return Err(SceneError::IndexOutOfRange {
                at: mesh.source.clone(),
                mesh: mesh.name.clone(),
                triangle,
                index,
                count: mesh.positions.len(),
            });
        }
    }
    Ok(normals)
}

/// The mesh's texture coordinates: none, or one finite pair per vertex.
fn check_uvs(mesh: &MeshDesc) -> Result<(), SceneError> {
    let bad = |message: String| SceneError::BadNormals {
        at: mesh.source.clone(),
        mesh: mesh.name.clone(),
        message,
    };
    if !mesh.uvs.is_empty() && mesh.uvs.len() != mesh.positions.len() {
        return Err(bad(format!(
            "{} texture coordinates for {} vertices (there must be one per vertex)",
            mesh.uvs.len(),
            mesh.positions.len()
        )));
    }
    match mesh.uvs.iter().position(|uv| !uv.is_finite()) {
        Some(i) => Err(bad(format!("texture coordinate {i} {} is not finite", mesh.uvs[i]))),
        None => Ok(()),
    }
}

/// The mesh's vertex normals, normalised and checked (one per vertex, finite, non-zero); empty
/// for a faceted mesh.
fn unit_normals(mesh: &MeshDesc) -> Result<Vec<Vec3>, SceneError> {
    let bad = |message: String| SceneError::BadNormals {
        at: mesh.source.clone(),
        mesh: mesh.name.clone(),
        message,
    };
    if mesh.normals.is_empty() {
        return Ok(Vec::new());
    }
    if mesh.normals.len() != mesh.positions.len() {
        return Err(bad(format!(
            "{} vertex normals for {} vertices (there must be one per vertex)",
            mesh.normals.len(),
            mesh.positions.len()
        )));
    }
    mesh.normals
        .iter()
        .enumerate()
        .map(|(i, n)| {
            let u = n.normalize_or_zero();
            if n.is_finite() && u != Vec3::ZERO && u.is_finite() {
                Ok(u)
            } else {
                Err(bad(format!("vertex normal {i} {n} is zero or not finite")))
            }
        })
        .collect()
}

/// The scene's triangles, flattened from its meshes in scene order (sample records refer to
/// these indices), with what each triangle needs: corners, material, light, shading normals.
#[derive(Debug, Default)]
pub(super) struct Flat {
    /// Triangles (v0 and edges).
    pub triangles: Vec<Triangle>,
    /// The same triangles' corners (for the BVH, the bounds and the fingerprints).
    pub vertices: Vec<[Vec3; 3]>,
    /// Per triangle: index into the scene's materials.
    pub material_of: Vec<u32>,
    /// Per triangle: index of the light it belongs to, or [`NO_LIGHT`].
    pub light_of: Vec<u32>,
    /// Per triangle: index into `shading_normals`, or [`NO_SHADING`].
    pub shading_of: Vec<u32>,
    /// Unit vertex normals of the triangles that have them.
    pub shading_normals: Vec<[Vec3; 3]>,
    /// Per triangle: index into `uvs`, or [`NO_UV`] (then the UV is the barycentrics).
    pub uv_of: Vec<u32>,
    /// Vertex texture coordinates of the triangles that have them.
    pub uvs: Vec<[Vec2; 3]>,
    /// The meshes' attributes, one table per name.
    pub attributes: Vec<AttributeTable>,
    /// Zero-area triangles dropped.
    pub dropped: usize,
    /// Finite triangles dropped because their area overflows `f32`.
    pub oversized: usize,
}

/// Whether the triangle `t` of `positions`, which `f32` arithmetic finds unusable (area zero or
/// not finite, or normal not finite), has in fact a positive area (computed in `f64`, where
/// finite `f32` coordinates cannot overflow) that `f32` cannot hold: too large, not degenerate.
fn overflows_f32(positions: &[Vec3], t: [u32; 3]) -> bool {
    let [a, b, c] = t.map(|i| positions[i as usize].as_dvec3());
    let area = 0.5 * (b - a).cross(c - a).length();
    area > 0.0 && (area > f32::MAX as f64 || !(Triangle::from_indices(positions, t).area().is_finite()))
}

/// The triangles an emissive mesh contributes, with their cumulative areas (for picking one
/// ∝ area).
#[derive(Debug, Default)]
pub(super) struct Emitter {
    /// Scene triangle indices.
    pub triangles: Vec<u32>,
    /// Running sum of their areas (accumulated in double precision); last = total area.
    pub cumulative_area: Vec<f32>,
}

impl Flat {
    /// Appends the triangles of `mesh` (already [`validate`]d, with its unit vertex `normals`),
    /// as part of light `light` ([`NO_LIGHT`] if it does not emit), and returns them as an
    /// emitter (empty if the mesh does not emit). Triangles whose vertex normals all point to
    /// their back are rewound (the front is where the normals point, as pbrt and Mitsuba
    /// orient the geometric normal by the shading one); vertex normals within
    /// [`FLAT_TOLERANCE`] of the geometric normal are dropped (the triangle is faceted).
    pub fn push_mesh(&mut self, mesh: &MeshDesc, normals: &[Vec3], light: u32) -> Emitter {
        let mut emitter = Emitter::default();
        let mut area_sum = 0.0f64;
        for (face, t) in mesh.triangles.iter().enumerate() {
            let mut t = *t;
            let mut tri = Triangle::from_indices(&mesh.positions, t);
            let area = tri.area();
            let usable = area > 0.0 && area.is_finite() && tri.normal().is_finite();
            if !usable {
                if overflows_f32(&mesh.positions, t) {
                    self.oversized += 1;
                } else {
                    self.dropped += 1;
                }
                continue;
            }
            let mut shading = NO_SHADING;
            if !normals.is_empty() {
                let mut ns = t.map(|i| normals[i as usize]);
                if (ns[0] + ns[1] + ns[2]).dot(tri.normal()) < 0.0 {
                    t.swap(1, 2);
                    ns.swap(1, 2);
                    tri = Triangle::from_indices(&mesh.positions, t);
                }
                let ng = tri.normal();
                if ns.iter().any(|n| (*n - ng).length() > FLAT_TOLERANCE) {
                    shading = self.shading_normals.len() as u32;
                    self.shading_normals.push(ns);
                }
            }
            let index = self.triangles.len() as u32;
            self.shading_of.push(shading);
            if mesh.uvs.is_empty() {
                self.uv_of.push(NO_UV);
            } else {
                self.uv_of.push(self.uvs.len() as u32);
                self.uvs.push(t.map(|i| mesh.uvs[i as usize]));
            }
            for a in &mesh.attributes {
                let k = self.attributes.iter().position(|x| x.name == a.name).unwrap_or_else(|| {
                    self.attributes.push(AttributeTable::new(a.name.clone()));
                    self.attributes.len() - 1
                });
                self.attributes[k].push(index as usize, attributes::corner_values(a, face, t));
            }
            if light != NO_LIGHT {
                emitter.triangles.push(index);
                area_sum += area as f64;
                emitter.cumulative_area.push(area_sum as f32);
            }
            self.triangles.push(tri);
            self.vertices.push(t.map(|i| mesh.positions[i as usize]));
            self.material_of.push(mesh.material as u32);
            self.light_of.push(light);
        }
        emitter
    }
}
