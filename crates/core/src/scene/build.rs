//! Validation and assembly: [`SceneDescription`] → [`Scene`].
//!
//! Everything a file can get wrong is caught here and reported with the element's source:
//! non-finite coordinates, indices out of range, missing materials, impossible emission, a
//! scene with no light. Degenerate (zero-area) triangles are dropped, since they can neither be
//! hit nor emit; their count is reported in [`Scene::dropped_triangles`].

use super::fingerprint::{Hasher, light_shape, material_hash, material_v2};
use super::{CameraDesc, Fingerprint, MeshDesc, SceneDescription, Source};
use crate::accel::Accel;
use crate::bsdf::Material;
use crate::geometry::{Hit, Ray, SurfaceNormals};
use crate::light::{AreaLight, BuiltProfile, DirectionalLight, EmissionProfile, Light, PointLight};
use crate::math::{Frame, Rgb, Vec3};

/// A triangle as stored for sampling and shading: v0 and two edges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// First vertex.
    pub v0: Vec3,
    /// v1 − v0.
    pub e1: Vec3,
    /// v2 − v0.
    pub e2: Vec3,
}

impl Triangle {
    /// Point at barycentrics (b1, b2).
    #[inline]
    pub fn point(&self, b1: f32, b2: f32) -> Vec3 {
        self.v0 + b1 * self.e1 + b2 * self.e2
    }
    /// Unit geometric normal (e1 × e2, counter-clockwise front).
    #[inline]
    pub fn normal(&self) -> Vec3 {
        self.e1.cross(self.e2).normalize()
    }
    /// Area.
    #[inline]
    pub fn area(&self) -> f32 {
        0.5 * self.e1.cross(self.e2).length()
    }
    /// Barycentrics (b1, b2) of the point of the triangle's plane nearest to `p` (so a stored
    /// position, which does not record where on its triangle it lies, gives them back).
    #[inline]
    pub fn barycentrics(&self, p: Vec3) -> (f32, f32) {
        let d = p - self.v0;
        let (d00, d01, d11) = (self.e1.dot(self.e1), self.e1.dot(self.e2), self.e2.dot(self.e2));
        let (d20, d21) = (d.dot(self.e1), d.dot(self.e2));
        let inv = 1.0 / (d00 * d11 - d01 * d01);
        ((d11 * d20 - d01 * d21) * inv, (d00 * d21 - d01 * d20) * inv)
    }
}

/// A triangle's vertex normals are ignored (the triangle is faceted) when each is within this
/// distance of its geometric normal: they could only change results by rounding.
const FLAT_TOLERANCE: f32 = 1e-5;

/// No shading normals on a triangle.
const NO_SHADING: u32 = u32::MAX;

/// No light index.
const NO_LIGHT: u32 = u32::MAX;

/// A validated, ray-traceable scene.
#[derive(Debug)]
pub struct Scene {
    /// Triangles (scene order; sample records refer to these indices).
    pub triangles: Vec<Triangle>,
    normals: Vec<Vec3>,
    /// Per triangle: index into `shading_normals`, or [`NO_SHADING`].
    shading_of: Vec<u32>,
    /// Unit vertex normals of the triangles that have them.
    shading_normals: Vec<[Vec3; 3]>,
    material_of: Vec<u32>,
    light_of: Vec<u32>,
    /// Materials.
    pub materials: Vec<Material>,
    /// Lights, in scene order.
    pub lights: Vec<Light>,
    /// Per light: hash of where and how it emits (geometry and emission distribution), not of
    /// its power. Samples stay valid for a light as long as this is unchanged; power and colour
    /// may change freely (relighting).
    pub light_shapes: Vec<[u8; 16]>,
    /// The scene file's camera, if any.
    pub camera: Option<CameraDesc>,
    /// Content hashes.
    pub fingerprint: Fingerprint,
    /// The geometry hash as format-version-1 datasets recorded it (which also covered which
    /// triangles emit): such a dataset matches this scene if its hash equals this one.
    pub geometry_v1: [u8; 16],
    /// Zero-area triangles that were dropped.
    pub dropped_triangles: usize,
    accel: Accel,
}

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
    /// Emitted radiance or intensity is negative or not finite.
    #[error("{at}: light '{light}': emission {value:?} must be finite and non-negative")]
    BadEmission {
        /// Where the light was declared.
        at: Source,
        /// Light name.
        light: String,
        /// The bad value.
        value: [f32; 3],
    },
    /// A point light's position is not finite.
    #[error("{at}: light '{light}': position {value:?} is not finite")]
    BadPosition {
        /// Where the light was declared.
        at: Source,
        /// Light name.
        light: String,
        /// The bad value.
        value: [f32; 3],
    },
    /// An emission profile is impossible (a negative exponent, a cutoff ≤ 0, a bad IES table).
    #[error("{at}: light '{light}': {message}")]
    BadProfile {
        /// Where the light was declared.
        at: Source,
        /// Light name.
        light: String,
        /// What is wrong.
        message: String,
    },
    /// A light's orientation or direction is zero, not finite or not orthonormal.
    #[error("{at}: light '{light}': {message}")]
    BadOrientation {
        /// Where the light was declared.
        at: Source,
        /// Light name.
        light: String,
        /// What is wrong.
        message: String,
    },
    /// An emissive mesh has no area.
    #[error("{at}: area light '{light}' has no triangle of non-zero area")]
    EmptyAreaLight {
        /// Where the light was declared.
        at: Source,
        /// Light name.
        light: String,
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
}

/// The triangle of `positions` with vertex indices `t`.
fn triangle(positions: &[Vec3], t: [u32; 3]) -> Triangle {
    let [a, b, c] = t.map(|i| positions[i as usize]);
    Triangle { v0: a, e1: b - a, e2: c - a }
}

/// The mesh's vertex normals, normalised and checked (one per vertex, finite, non-zero); empty
/// for a faceted mesh.
fn unit_normals(mesh: &super::MeshDesc) -> Result<Vec<Vec3>, SceneError> {
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
                Err(bad(format!("vertex normal {i} {:?} is zero or not finite", n.to_array())))
            }
        })
        .collect()
}

/// The area light of an emissive `mesh` (emission `radiance`) made of the scene triangles
/// `triangles` with their cumulative areas: builds the profile, checks the tangent and derives
/// the radiance from `emission_power` when one is given.
fn area_light(
    mesh: &MeshDesc,
    radiance: Rgb,
    triangles: Vec<u32>,
    cumulative_area: Vec<f32>,
) -> Result<AreaLight, SceneError> {
    let bad_profile = |message: String| SceneError::BadProfile {
        at: mesh.source.clone(),
        light: mesh.name.clone(),
        message,
    };
    let profile = mesh.emission_profile.as_ref().unwrap_or(&EmissionProfile::Cosine);
    let profile = BuiltProfile::build(profile, true).map_err(|e| bad_profile(e.0))?;
    let tangent = match mesh.emission_tangent {
        None => Vec3::X,
        Some(t) if t.is_finite() && t.length() > 0.0 => t.normalize(),
        Some(t) => {
            return Err(SceneError::BadOrientation {
                at: mesh.source.clone(),
                light: mesh.name.clone(),
                message: format!("emission tangent {:?} must be finite and non-zero", t.to_array()),
            });
        }
    };
    let area = cumulative_area.last().copied().unwrap_or(0.0);
    let radiance = match mesh.emission_power {
        None => radiance,
        Some(phi) if !(phi.is_finite() && phi.min_element() >= 0.0) => {
            return Err(bad_profile(format!("power {:?} W must be finite and non-negative", phi.to_array())));
        }
        Some(phi) if !(area > 0.0) && phi.max_element() > 0.0 => {
            return Err(bad_profile(format!("power {:?} W on an emitter of zero area", phi.to_array())));
        }
        Some(phi) => {
            let per_radiance = profile.integral() * area;
            if !(per_radiance > 0.0) && phi.max_element() > 0.0 {
                return Err(bad_profile(format!(
                    "power {:?} W cannot be reached: the emission profile carries no flux into the front \
                     hemisphere",
                    phi.to_array()
                )));
            }
            if per_radiance > 0.0 { phi / per_radiance } else { Rgb::ZERO }
        }
    };
    Ok(AreaLight { name: mesh.name.clone(), radiance, profile, tangent, triangles, cumulative_area })
}

/// `f` re-orthonormalised (Gram–Schmidt from its z axis), if it is finite and close to
/// orthonormal (within 10⁻³).
fn orthonormal(f: Frame) -> Option<Frame> {
    let ok = [f.s, f.t, f.n].iter().all(|v| v.is_finite() && (v.length() - 1.0).abs() < 1e-3)
        && f.s.dot(f.t).abs() < 1e-3
        && f.s.dot(f.n).abs() < 1e-3
        && f.t.dot(f.n).abs() < 1e-3;
    if !ok {
        return None;
    }
    let n = f.n.normalize();
    let s = (f.s - n * f.s.dot(n)).normalize();
    Some(Frame { s, t: n.cross(s), n })
}

impl Scene {
    /// Validates `desc` and builds the BVH, light table and fingerprint.
    pub fn build(desc: &SceneDescription) -> Result<Scene, SceneError> {
        let mut triangles = Vec::new();
        let mut vertices = Vec::new();
        let mut material_of = Vec::new();
        let mut light_of = Vec::new();
        let mut shading_of = Vec::new();
        let mut shading_normals = Vec::new();
        let mut lights = Vec::new();
        let mut dropped = 0usize;
        // The geometry fingerprint covers each triangle's corners and material, not whether it
        // emits: emission is the lights' business (each light has its own shape hash), so a
        // surface may become a light without invalidating the samples of the others.
        let mut geo = Hasher::new("opticks geometry v2");
        let material_hashes: Vec<[u8; 16]> = desc.materials.iter().map(material_hash).collect();
        // The hash datasets of format version 1 recorded (it also covered emitter assignment).
        let mut geo_v1 = Hasher::new("opticks geometry v1");

        for mesh in &desc.meshes {
            if mesh.material >= desc.materials.len() {
                return Err(SceneError::MissingMaterial {
                    at: mesh.source.clone(),
                    mesh: mesh.name.clone(),
                    material: mesh.material,
                    count: desc.materials.len(),
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
            let light_index = match mesh.emission {
                Some(l) if !(l.is_finite() && l.min_element() >= 0.0) => {
                    return Err(SceneError::BadEmission {
                        at: mesh.source.clone(),
                        light: mesh.name.clone(),
                        value: l.to_array(),
                    });
                }
                Some(_) => lights.len() as u32,
                None => NO_LIGHT,
            };
            let mut emitter_tris = Vec::new();
            let mut cumulative = Vec::new();
            let mut area_sum = 0.0f64;
            for (ti, t) in mesh.triangles.iter().enumerate() {
                if let Some(&index) = t.iter().find(|&&i| i as usize >= mesh.positions.len()) {
                    return Err(SceneError::IndexOutOfRange {
                        at: mesh.source.clone(),
                        mesh: mesh.name.clone(),
                        triangle: ti,
                        index,
                        count: mesh.positions.len(),
                    });
                }
                let mut t = *t;
                let mut tri = triangle(&mesh.positions, t);
                let area = tri.area();
                if !(area > 0.0) || !tri.normal().is_finite() {
                    dropped += 1;
                    continue;
                }
                let mut shading = NO_SHADING;
                if !normals.is_empty() {
                    let mut ns = t.map(|i| normals[i as usize]);
                    if (ns[0] + ns[1] + ns[2]).dot(tri.normal()) < 0.0 {
                        // The front is where the vertex normals point (as pbrt and Mitsuba
                        // orient the geometric normal by the shading one): rewind.
                        t.swap(1, 2);
                        ns.swap(1, 2);
                        tri = triangle(&mesh.positions, t);
                    }
                    let ng = tri.normal();
                    if ns.iter().any(|n| (*n - ng).length() > FLAT_TOLERANCE) {
                        shading = shading_normals.len() as u32;
                        shading_normals.push(ns);
                    }
                }
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                let index = triangles.len() as u32;
                let corners = [a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z];
                geo.f32s(&corners);
                geo.0.update(&material_hashes[mesh.material]);
                geo_v1.f32s(&corners);
                geo_v1.u32s(&[mesh.material as u32, light_index]);
                if shading != NO_SHADING {
                    // Shading normals change what every stored vertex reflects; a version-1
                    // dataset (traced before they were honoured) must not match such a scene.
                    let normals = shading_normals[shading as usize].map(|n| n.to_array()).concat();
                    geo.f32s(&normals);
                    geo_v1.f32s(&normals);
                }
                shading_of.push(shading);
                if light_index != NO_LIGHT {
                    emitter_tris.push(index);
                    area_sum += area as f64;
                    cumulative.push(area_sum as f32);
                }
                triangles.push(tri);
                vertices.push([a, b, c]);
                material_of.push(mesh.material as u32);
                light_of.push(light_index);
            }
            if let Some(radiance) = mesh.emission {
                if emitter_tris.is_empty() {
                    return Err(SceneError::EmptyAreaLight {
                        at: mesh.source.clone(),
                        light: mesh.name.clone(),
                    });
                }
                lights.push(Light::Area(area_light(mesh, radiance, emitter_tris, cumulative)?));
            }
        }
        for p in &desc.point_lights {
            if !(p.intensity.is_finite() && p.intensity.min_element() >= 0.0) {
                return Err(SceneError::BadEmission {
                    at: p.source.clone(),
                    light: p.name.clone(),
                    value: p.intensity.to_array(),
                });
            }
            if !p.position.is_finite() {
                return Err(SceneError::BadPosition {
                    at: p.source.clone(),
                    light: p.name.clone(),
                    value: p.position.to_array(),
                });
            }
            let bad_profile = |message: String| SceneError::BadProfile {
                at: p.source.clone(),
                light: p.name.clone(),
                message,
            };
            let profile = BuiltProfile::build(p.profile.as_ref().unwrap_or(&EmissionProfile::Uniform), false)
                .map_err(|e| bad_profile(e.0))?;
            let frame = match p.orientation {
                None => Frame { s: Vec3::X, t: Vec3::Y, n: Vec3::Z },
                Some(f) => orthonormal(f).ok_or_else(|| SceneError::BadOrientation {
                    at: p.source.clone(),
                    light: p.name.clone(),
                    message: format!("orientation {f:?} is not a finite orthonormal frame"),
                })?,
            };
            let integral = profile.integral();
            let (intensity, power) = match p.power {
                Some(phi) => {
                    if !(phi.is_finite() && phi.min_element() >= 0.0) {
                        return Err(bad_profile(format!(
                            "power {:?} W must be finite and non-negative",
                            phi.to_array()
                        )));
                    }
                    (phi / integral, phi)
                }
                None => (p.intensity, integral * p.intensity),
            };
            lights.push(Light::Point(PointLight {
                name: p.name.clone(),
                position: p.position,
                intensity,
                power,
                profile,
                frame,
            }));
        }
        if !desc.directional_lights.is_empty() && !vertices.is_empty() {
            // Bounding sphere of the scene's triangles (centre of the box, half its diagonal).
            let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
            for v in vertices.iter().flatten() {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
            let centre = 0.5 * (lo + hi);
            let radius = 0.5 * (hi - lo).length();
            for d in &desc.directional_lights {
                if !(d.irradiance.is_finite() && d.irradiance.min_element() >= 0.0) {
                    return Err(SceneError::BadEmission {
                        at: d.source.clone(),
                        light: d.name.clone(),
                        value: d.irradiance.to_array(),
                    });
                }
                let dir = d.direction.normalize_or_zero();
                if !(dir.is_finite() && dir != Vec3::ZERO) {
                    return Err(SceneError::BadOrientation {
                        at: d.source.clone(),
                        light: d.name.clone(),
                        message: format!("direction {:?} is zero or not finite", d.direction.to_array()),
                    });
                }
                lights.push(Light::Directional(DirectionalLight {
                    name: d.name.clone(),
                    direction: dir,
                    irradiance: d.irradiance,
                    centre: centre - dir * (radius * 1.001 + 1e-4),
                    radius,
                    frame: Frame::from_normal(dir),
                }));
            }
        }
        if triangles.is_empty() {
            return Err(SceneError::NoGeometry);
        }
        if lights.is_empty() {
            return Err(SceneError::NoLight);
        }
        for m in &desc.materials {
            geo_v1.0.update(material_v2(m).as_bytes());
        }
        let mut names = std::collections::HashSet::new();
        if let Some(dup) = lights.iter().map(Light::name).find(|n| !names.insert(*n)) {
            return Err(SceneError::DuplicateLightName(dup.to_string()));
        }
        let light_shapes: Vec<[u8; 16]> = lights.iter().map(|l| light_shape(l, &triangles)).collect();
        let mut lit = Hasher::new("opticks lights v1");
        for (l, shape) in lights.iter().zip(&light_shapes) {
            lit.0.update(l.name().as_bytes());
            lit.0.update(shape);
        }
        let normals = triangles.iter().map(Triangle::normal).collect();
        let accel = Accel::build(&vertices);
        Ok(Scene {
            triangles,
            normals,
            shading_of,
            shading_normals,
            material_of,
            light_of,
            materials: desc.materials.clone(),
            lights,
            light_shapes,
            camera: desc.camera,
            fingerprint: Fingerprint { geometry: geo.finish(), lights: lit.finish() },
            geometry_v1: geo_v1.finish(),
            dropped_triangles: dropped,
            accel,
        })
    }

    /// Closest surface hit along `ray`.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let (t, prim) = self.accel.intersect(ray)?;
        Some(Hit { t, prim, position: ray.origin + t * ray.dir, normal: self.normals[prim as usize] })
    }

    /// Whether the segment from `ray.origin` of length `ray.t_max` is blocked.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.accel.occluded(ray)
    }

    /// Unit geometric normal of triangle `prim`.
    #[inline]
    pub fn normal(&self, prim: u32) -> Vec3 {
        self.normals[prim as usize]
    }

    /// The normals of triangle `prim` at the point `p` on it: the geometric normal and the
    /// vertex normals interpolated at p's barycentrics (recomputed from p, so a stored sample
    /// needs no more than its position and triangle).
    #[inline]
    pub fn normals_at(&self, prim: u32, p: Vec3) -> SurfaceNormals {
        let ng = self.normals[prim as usize];
        let k = self.shading_of[prim as usize];
        if k == NO_SHADING {
            return SurfaceNormals::flat(ng);
        }
        let [n0, n1, n2] = self.shading_normals[k as usize];
        let (b1, b2) = self.triangles[prim as usize].barycentrics(p);
        let ns = ((1.0 - b1 - b2) * n0 + b1 * n1 + b2 * n2).normalize_or_zero();
        // Interpolated normals can cancel (opposite vertex normals) or, at a crease, lean
        // through the surface: keep the shading normal on the geometric side.
        if ns.dot(ng) > 0.0 {
            SurfaceNormals { geometric: ng, shading: ns }
        } else {
            SurfaceNormals::flat(ng)
        }
    }

    /// Whether any triangle has shading normals.
    pub fn has_shading_normals(&self) -> bool {
        !self.shading_normals.is_empty()
    }

    /// Material of triangle `prim`.
    #[inline]
    pub fn material(&self, prim: u32) -> &Material {
        &self.materials[self.material_of[prim as usize] as usize]
    }

    /// The light whose emitter triangle `prim` is, if any.
    #[inline]
    pub fn light_of(&self, prim: u32) -> Option<usize> {
        let l = self.light_of[prim as usize];
        (l != NO_LIGHT).then_some(l as usize)
    }

    /// Index of the light named `name`.
    pub fn light_index(&self, name: &str) -> Option<usize> {
        self.lights.iter().position(|l| l.name() == name)
    }

    /// Powers Φ_k of all lights, in scene order.
    pub fn light_powers(&self) -> Vec<Rgb> {
        self.lights.iter().map(Light::power).collect()
    }
}
