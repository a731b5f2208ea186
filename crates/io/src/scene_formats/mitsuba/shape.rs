//! `<shape>` elements: triangle meshes with their normals, material, interior medium and area
//! emitter. [`SHAPE_TYPES`] maps each supported Mitsuba shape type to the function producing
//! its geometry in object space; adding a shape is an entry there and its function. The rest —
//! `to_world`, `face_normals`, `flip_normals`, the BSDF, the medium, the emitter — is the same for
//! every type and done once, in [`shape`].
//!
//! Normals follow Mitsuba: a mesh file's vertex normals are the shading normals (carried by the
//! inverse transpose of `to_world`); a mesh file without normals gets Mitsuba's generated smooth
//! normals, computed on the world positions ([`generated_vertex_normals`]) — OBJ, PLY and
//! serialized files alike; `rectangle`, `cube` and `disk` are faceted, `sphere` and `cylinder`
//! tessellated with their exact normals ([`crate::scene_formats::tessellate`]), and a mirroring `to_world`
//! reverses an analytic shape's winding so that its normal stays where Mitsuba's transformed
//! normal is.

use super::Result;
use super::bsdf;
use super::build::Builder;
use super::properties::Props;
use super::texture;
use super::xml::Element;
use super::{emitter, medium};
use crate::scene_formats::mesh_bytes::{MeshData, read_mesh_file};
use crate::scene_formats::obj::{generated_vertex_normals, read_obj};
use crate::scene_formats::tessellate;
use crate::scene_formats::{ply::parse_ply_with, serialized::parse_serialized_within};
use glam::{DMat3, DMat4};
use opticks_core::math::{Vec2, Vec3};
use opticks_core::scene::{AreaEmission, MeshAttribute, MeshDesc};
use opticks_core::texture::{ColourSlot, Texture};

/// A shape's geometry before `to_world`.
pub struct Geometry {
    /// Object-space vertex positions.
    pub positions: Vec<Vec3>,
    /// Counter-clockwise triangles.
    pub triangles: Vec<[u32; 3]>,
    /// Shading normals, one per position, or empty.
    pub normals: Vec<Vec3>,
    /// Texture coordinates, one per position (Mitsuba's parameterisation of an analytic shape,
    /// a mesh file's own), or empty (then the UV is the barycentrics, as in Mitsuba).
    pub uvs: Vec<Vec2>,
    /// The mesh file's attributes that the shape's textures read (PLY only).
    pub attributes: Vec<MeshAttribute>,
    /// A mesh file, which gets Mitsuba's generated smooth normals when it has none (unless
    /// `face_normals` is set).
    pub mesh_file: bool,
    /// An analytic shape, whose normals Mitsuba transforms as normals (a mirroring `to_world`
    /// reverses its winding to keep them).
    pub analytic: bool,
}

/// A geometry builder: the `<shape>` element and its properties.
type BuildGeometry = for<'d> fn(&mut Builder<'d>, &'d Element, &mut Props<'d>) -> Result<Geometry>;

/// The supported shape types, in the order the error message lists them.
const SHAPE_TYPES: &[(&str, BuildGeometry)] = &[
    ("obj", obj),
    ("ply", ply),
    ("serialized", serialized),
    ("rectangle", rectangle),
    ("cube", cube),
    ("sphere", sphere),
    ("disk", disk),
    ("cylinder", cylinder),
];

/// The mesh of a `<shape>`; `index` counts the scene's shapes (for the default name
/// `<type>_<index>`). Materials it introduces are added to the scene.
pub fn shape<'d>(b: &mut Builder<'d>, e: &'d Element, index: usize) -> Result<MeshDesc> {
    Ok(shape_and_kind(b, e, index)?.0)
}

/// [`shape`], and whether the shape is analytic (a sphere, disk…: its winding follows its
/// outward normal through a mirroring transform, as an instance's must too).
pub fn shape_and_kind<'d>(b: &mut Builder<'d>, e: &'d Element, index: usize) -> Result<(MeshDesc, bool)> {
    let ty = e.required("type")?;
    let name = e.attr("id")?.map_or_else(|| format!("{ty}_{index}"), str::to_string);
    let mut p = Props::of(e)?;
    let Some((_, geometry)) = SHAPE_TYPES.iter().find(|(n, _)| *n == ty) else {
        let names: Vec<&str> = SHAPE_TYPES.iter().map(|(n, _)| *n).collect();
        return Err(
            e.attr_err("type", format!("unsupported shape type \"{ty}\" (supported: {})", names.join(", ")))
        );
    };
    let Geometry { mut positions, mut triangles, mut normals, uvs, attributes, mesh_file, analytic } =
        geometry(b, e, &mut p)?;
    // Mitsuba's default (false) shades with the file's vertex normals when it has them, and
    // generates smooth ones (after `to_world`, below) when it has none.
    let face_normals = p.bool("face_normals")?.unwrap_or(false);
    if face_normals {
        normals.clear();
    }
    let flip = p.bool("flip_normals")?.unwrap_or(false);
    let mut mirrored = false;
    if let Some((t, tnode)) = p.transform("to_world")? {
        let m = t.matrix;
        mirrored = DMat3::from_mat4(m).determinant() < 0.0;
        if m != DMat4::IDENTITY
            && let Some(i) = transform_mesh(&m, &mut positions, &mut normals)
        {
            return Err(tnode.err(format!("to_world maps vertex {} to a non-finite point", i + 1)));
        }
    }
    if mesh_file && !face_normals && normals.is_empty() {
        let smooth = generated_vertex_normals(positions, triangles);
        (positions, triangles, normals) = (smooth.positions, smooth.triangles, smooth.normals);
    }
    if flip ^ (analytic && mirrored) {
        triangles.iter_mut().for_each(|t| t.swap(1, 2));
    }
    if flip {
        normals.iter_mut().for_each(|v| *v = -*v);
    }

    let mut chosen = None;
    let mut interior = None;
    let mut emission = None;
    for &c in p.objects() {
        // A <ref> to a top-level area emitter (Mitsuba accepts a reference wherever an object goes).
        if let Some(t) = c.target.map(|i| b.doc.top(i)).filter(|t| c.tag == "ref" && t.tag == "emitter") {
            if emission.is_some() {
                return Err(c.err("a shape can have only one emitter"));
            }
            b.used.insert(c.required("id")?.to_string());
            emission = Some(with_uvs(emitter::area_emitter(b, t)?, !uvs.is_empty(), &name, c)?);
            continue;
        }
        match (c.tag.as_str(), c.raw("name")) {
            ("ref" | "medium", Some("interior")) => {
                if interior.is_some() {
                    return Err(c.err("a shape can have only one interior medium"));
                }
                interior = Some(medium::interior_medium(b, c)?);
            }
            ("ref" | "medium", Some("exterior")) => {
                return Err(c.err("exterior media are not supported: the outside of every shape is vacuum"));
            }
            ("medium", _) => return Err(c.err("a <medium> inside a shape needs name=\"interior\"")),
            ("bsdf" | "ref", _) => {
                if chosen.is_some() {
                    return Err(c.err("a shape can have only one BSDF"));
                }
                let (parsed, ref_id) = if c.tag == "ref" {
                    let parsed = bsdf::bsdf_ref(b, c)?;
                    let id = parsed.name.clone();
                    (parsed, Some(id))
                } else {
                    let mut parsed = bsdf::bsdf(b, c)?;
                    if c.raw("id").is_none() {
                        parsed.name = format!("{name}.bsdf");
                    }
                    (parsed, None)
                };
                if uvs.is_empty() && parsed.textures.iter().any(|(s, _)| *s == ColourSlot::BumpMap) {
                    return Err(c.err(format!(
                        "shape '{name}' has no texture coordinates, which its bumpmap needs (the \
                         height's gradient is taken along u and v); give the mesh UVs (OBJ `vt`, \
                         PLY u/v) or use a shape that has them"
                    )));
                }
                chosen = Some((parsed, ref_id));
            }
            ("emitter", _) => {
                if emission.is_some() {
                    return Err(c.err("a shape can have only one emitter"));
                }
                emission = Some(with_uvs(emitter::area_emitter(b, c)?, !uvs.is_empty(), &name, c)?);
            }
            (other, _) => {
                return Err(c.err(format!(
                    "unsupported element <{other}> inside <shape> (supported: bsdf, ref, emitter, medium)"
                )));
            }
        }
    }
    let material = match (chosen, interior) {
        (Some((parsed, ref_id)), None) => bsdf::material_index(b, &parsed, ref_id.as_deref()),
        (Some((parsed, ref_id)), Some(medium)) => medium::absorbing_material(b, parsed, ref_id, medium)?,
        (None, Some(medium)) => {
            return Err(medium
                .node
                .err("an interior medium needs a dielectric BSDF on the shape (this shape has none)"));
        }
        (None, None) => bsdf::default_material(b, emission.is_some()),
    };
    b.finish(&p);
    let mut mesh = MeshDesc {
        name,
        source: Builder::source(e),
        positions,
        triangles,
        normals,
        uvs,
        attributes,
        material,
        ..Default::default()
    };
    emitter::set_area_emission(&mut mesh, emission);
    Ok((mesh, analytic))
}

/// Carries a mesh's `positions` (projectively, if `m` is) and shading `normals` (by the inverse
/// transpose; the core normalises them) through `m`. `Some(i)`: vertex i became non-finite.
pub fn transform_mesh(m: &DMat4, positions: &mut [Vec3], normals: &mut [Vec3]) -> Option<usize> {
    let mf = m.as_mat4();
    if m.row(3) == glam::DVec4::W {
        positions.iter_mut().for_each(|q| *q = mf.transform_point3(*q));
    } else {
        positions.iter_mut().for_each(|q| *q = mf.project_point3(*q));
    }
    let bad = positions.iter().position(|q| !q.is_finite());
    let nm = glam::Mat3::from_mat4(mf).inverse().transpose();
    normals.iter_mut().for_each(|v| *v = nm * *v);
    bad
}

/// `obj`: the triangles of a Wavefront OBJ file (`filename`, relative to the scene's folder).
fn obj<'d>(b: &mut Builder<'d>, e: &'d Element, p: &mut Props<'d>) -> Result<Geometry> {
    let (file, fnode) =
        p.string("filename")?.ok_or_else(|| e.err("missing <string name=\"filename\" value=\"...\"/>"))?;
    let path = b.doc.resolve(fnode, &file);
    // Mitsuba's OBJ reader flips v by default (most OBJ files count it from the bottom).
    let flip_v = p.bool("flip_tex_coords")?.unwrap_or(true);
    let mesh = b.mesh_files.get(&file, &path, "obj".to_string(), || {
        let m = read_obj(&path, Some((e.describe(), e.at.clone())))?;
        Ok(MeshData {
            positions: m.positions,
            triangles: m.triangles,
            normals: m.normals,
            uvs: m.uvs,
            ..MeshData::default()
        })
    })?;
    if mesh.triangles.is_empty() {
        b.warn(e, format!("{} has no faces", path.display()));
    }
    Ok(Geometry {
        positions: mesh.positions,
        triangles: mesh.triangles,
        normals: mesh.normals,
        uvs: flipped_v(mesh.uvs, flip_v),
        attributes: Vec::new(),
        mesh_file: true,
        analytic: false,
    })
}

/// `ply`: a PLY file's triangles, normals, texture coordinates and the attributes the shape's
/// `mesh_attribute` textures read (`filename`).
fn ply<'d>(b: &mut Builder<'d>, e: &'d Element, p: &mut Props<'d>) -> Result<Geometry> {
    let (file, fnode) = mesh_filename(e, p)?;
    let path = b.doc.resolve(fnode, &file);
    // Mitsuba's PLY reader keeps v as written by default.
    let flip_v = p.bool("flip_tex_coords")?.unwrap_or(false);
    let wanted = texture::attribute_names(b.doc, e);
    let mut mesh = b.mesh_files.get(&file, &path, format!("ply {wanted:?}"), || {
        read_mesh_file(&path, Some((e.describe(), e.at.clone())), |d| parse_ply_with(d, &wanted))
    })?;
    mesh.uvs = flipped_v(std::mem::take(&mut mesh.uvs), flip_v);
    Ok(mesh_geometry(b, e, &path, mesh))
}

/// `serialized`: mesh `shape_index` (default 0) of a Mitsuba serialized file (`filename`).
fn serialized<'d>(b: &mut Builder<'d>, e: &'d Element, p: &mut Props<'d>) -> Result<Geometry> {
    let (file, fnode) = mesh_filename(e, p)?;
    let index = match p.int("shape_index")? {
        Some((i, _)) if i >= 0 => i as u64,
        Some((i, node)) => return Err(node.err(format!("shape_index must be ≥ 0, not {i}"))),
        None => 0,
    };
    let path = b.doc.resolve(fnode, &file);
    let max_expansion = b.doc.limits.max_mesh_expansion;
    let mesh = b.mesh_files.get(&file, &path, format!("serialized {index} {max_expansion}"), || {
        read_mesh_file(&path, Some((e.describe(), e.at.clone())), |d| {
            parse_serialized_within(d, index, max_expansion)
        })
    })?;
    Ok(mesh_geometry(b, e, &path, mesh))
}

/// A mesh file's `filename` parameter.
fn mesh_filename<'d>(e: &'d Element, p: &mut Props<'d>) -> Result<(String, &'d Element)> {
    p.string("filename")?.ok_or_else(|| e.err("missing <string name=\"filename\" value=\"...\"/>"))
}

/// `emission`, unless it is textured by UV (not a mesh attribute) and the shape `name` has no
/// texture coordinates (`has_uvs` false): an error at its emitter element `at`.
fn with_uvs(emission: AreaEmission, has_uvs: bool, name: &str, at: &Element) -> Result<AreaEmission> {
    let by_uv = emission.texture.as_deref().is_some_and(|t| !matches!(t, Texture::MeshAttribute(_)));
    if by_uv && !has_uvs {
        return Err(at.err(format!(
            "shape '{name}' has no texture coordinates, which the texture on its emitter's \
             `radiance` needs; give the mesh UVs (OBJ `vt`, PLY u/v) or use a shape that has them"
        )));
    }
    Ok(emission)
}

/// `uvs` with v replaced by 1 − v if `flip`.
fn flipped_v(mut uvs: Vec<Vec2>, flip: bool) -> Vec<Vec2> {
    if flip {
        uvs.iter_mut().for_each(|t| t.y = 1.0 - t.y);
    }
    uvs
}

/// The geometry of a binary mesh file (its vertices are already Mitsuba's); warns when it has
/// no faces.
fn mesh_geometry(b: &mut Builder, e: &Element, path: &std::path::Path, mesh: MeshData) -> Geometry {
    if mesh.triangles.is_empty() {
        b.warn(e, format!("{} has no faces", path.display()));
    }
    Geometry {
        positions: mesh.positions,
        triangles: mesh.triangles,
        normals: mesh.normals,
        uvs: mesh.uvs,
        attributes: mesh.attributes,
        mesh_file: true,
        analytic: false,
    }
}

/// `sphere`: `center` (0), `radius` (1), tessellated with smooth normals.
fn sphere<'d>(_: &mut Builder<'d>, _: &'d Element, p: &mut Props<'d>) -> Result<Geometry> {
    let center = p.point("center")?.map_or(Vec3::ZERO, |(c, _)| c.as_vec3());
    let radius = positive(p, "radius", 1.0)?;
    let (positions, triangles, normals, uvs) = tessellate::sphere(center, radius as f32);
    Ok(analytic(positions, triangles, normals, uvs))
}

/// `disk`: the unit disk at z = 0, normal +z.
fn disk<'d>(_: &mut Builder<'d>, _: &'d Element, _: &mut Props<'d>) -> Result<Geometry> {
    let (positions, triangles, _, uvs) = tessellate::disk();
    Ok(analytic(positions, triangles, Vec::new(), uvs))
}

/// `cylinder`: `p0` (0, 0, 0) to `p1` (0, 0, 1), `radius` (1), open, smooth normals outward.
fn cylinder<'d>(_: &mut Builder<'d>, e: &'d Element, p: &mut Props<'d>) -> Result<Geometry> {
    let p0 = p.point("p0")?;
    let p1 = p.point("p1")?;
    let radius = positive(p, "radius", 1.0)?;
    let (a, b) = (p0.map_or(glam::DVec3::ZERO, |x| x.0), p1.map_or(glam::DVec3::Z, |x| x.0));
    let (positions, triangles, normals, uvs) = tessellate::cylinder(a, b, radius)
        .ok_or_else(|| p1.or(p0).map_or(e, |x| x.1).err("the cylinder's p0 and p1 are the same point"))?;
    Ok(analytic(positions, triangles, normals, uvs))
}

/// A float parameter that must be > 0 (`default` if absent).
fn positive<'d>(p: &mut Props<'d>, name: &str, default: f64) -> Result<f64> {
    let (v, node) = p.float_or(name, default)?;
    if v <= 0.0 {
        return Err(node.err(format!("{name} must be > 0, not {v}")));
    }
    Ok(v)
}

/// `rectangle`: [-1, 1]² at z = 0, normal +z, (u, v) = ((x + 1)/2, (y + 1)/2) as in Mitsuba.
fn rectangle<'d>(_: &mut Builder<'d>, _: &'d Element, _: &mut Props<'d>) -> Result<Geometry> {
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let positions = corners.map(|(x, y)| Vec3::new(x, y, 0.0));
    let uvs = corners.map(|(x, y)| Vec2::new((x + 1.0) / 2.0, (y + 1.0) / 2.0));
    Ok(analytic(positions.to_vec(), vec![[0, 1, 2], [2, 3, 0]], Vec::new(), uvs.to_vec()))
}

/// Mitsuba's `cube` texture coordinates: each face's corners (position, outward normal axis
/// and sign) with their (u, v), from Mitsuba 3's `cube.cpp` (every face maps onto [0, 1]²).
const CUBE_UVS: [([f32; 3], usize, f32, [f32; 2]); 24] = [
    ([1.0, -1.0, -1.0], 1, -1.0, [0.0, 1.0]),
    ([1.0, -1.0, 1.0], 1, -1.0, [1.0, 1.0]),
    ([-1.0, -1.0, 1.0], 1, -1.0, [1.0, 0.0]),
    ([-1.0, -1.0, -1.0], 1, -1.0, [0.0, 0.0]),
    ([1.0, 1.0, -1.0], 1, 1.0, [0.0, 1.0]),
    ([-1.0, 1.0, -1.0], 1, 1.0, [1.0, 1.0]),
    ([-1.0, 1.0, 1.0], 1, 1.0, [1.0, 0.0]),
    ([1.0, 1.0, 1.0], 1, 1.0, [0.0, 0.0]),
    ([1.0, -1.0, -1.0], 0, 1.0, [0.0, 1.0]),
    ([1.0, 1.0, -1.0], 0, 1.0, [1.0, 1.0]),
    ([1.0, 1.0, 1.0], 0, 1.0, [1.0, 0.0]),
    ([1.0, -1.0, 1.0], 0, 1.0, [0.0, 0.0]),
    ([1.0, -1.0, 1.0], 2, 1.0, [0.0, 1.0]),
    ([1.0, 1.0, 1.0], 2, 1.0, [1.0, 1.0]),
    ([-1.0, 1.0, 1.0], 2, 1.0, [1.0, 0.0]),
    ([-1.0, -1.0, 1.0], 2, 1.0, [0.0, 0.0]),
    ([-1.0, -1.0, 1.0], 0, -1.0, [0.0, 1.0]),
    ([-1.0, 1.0, 1.0], 0, -1.0, [1.0, 1.0]),
    ([-1.0, 1.0, -1.0], 0, -1.0, [1.0, 0.0]),
    ([-1.0, -1.0, -1.0], 0, -1.0, [0.0, 0.0]),
    ([1.0, 1.0, -1.0], 2, -1.0, [0.0, 1.0]),
    ([1.0, -1.0, -1.0], 2, -1.0, [1.0, 1.0]),
    ([-1.0, -1.0, -1.0], 2, -1.0, [1.0, 0.0]),
    ([-1.0, 1.0, -1.0], 2, -1.0, [0.0, 0.0]),
];

/// `cube`: Mitsuba's [-1, 1]³, four vertices per face, outward normals, counter-clockwise.
fn cube<'d>(_: &mut Builder<'d>, _: &'d Element, _: &mut Props<'d>) -> Result<Geometry> {
    let mut positions = Vec::with_capacity(24);
    let mut triangles = Vec::with_capacity(12);
    let mut uvs = Vec::with_capacity(24);
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            // Face at coordinate `axis` = sign; (u, v) span it with u × v = sign · e_axis.
            let n = Vec3::from_array(std::array::from_fn(|k| if k == axis { sign } else { 0.0 }));
            let u = Vec3::from_array(std::array::from_fn(|k| if k == (axis + 1) % 3 { 1.0 } else { 0.0 }));
            let v = n.cross(u);
            let base = positions.len() as u32;
            for (a, c) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let q = n + a * u + c * v;
                positions.push(q);
                let uv =
                    CUBE_UVS.iter().find(|(p, ax, s, _)| Vec3::from(*p) == q && *ax == axis && *s == sign);
                uvs.push(uv.map_or(Vec2::ZERO, |t| Vec2::from(t.3)));
            }
            triangles.push([base, base + 1, base + 2]);
            triangles.push([base, base + 2, base + 3]);
        }
    }
    Ok(analytic(positions, triangles, Vec::new(), uvs))
}

/// An analytic shape, tessellated: its triangles, its exact normals (none: faceted) and its
/// texture coordinates.
fn analytic(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>, normals: Vec<Vec3>, uvs: Vec<Vec2>) -> Geometry {
    Geometry { positions, triangles, normals, uvs, attributes: Vec::new(), mesh_file: false, analytic: true }
}
