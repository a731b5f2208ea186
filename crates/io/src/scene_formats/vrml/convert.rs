//! The node tree → a [`SceneDescription`]: walks the scene graph with the VRML transform stack
//! and turns shapes, materials, lights and the first viewpoint into Opticks' physical terms
//! (the conversions are documented in `docs/scene-formats.md`, section VRML97).
//!
//! Grouping: `Transform` (full VRML order T·C·R·SR·S·SR⁻¹·C⁻¹), `Group`, `Anchor`,
//! `Collision` (its proxy ignored), `Billboard` (not turned toward the viewer: a warning),
//! `Switch` (`whichChoice`), `LOD` (its first, most detailed level), `Inline` (relative URLs,
//! recursion guarded). Nodes that do not change the image (sensors, interpolators, `Script`,
//! `WorldInfo`, `NavigationInfo`, sound) are ignored silently; what would change it and is not
//! supported (`Background`, `Fog`, textures, transparency) gives a warning. Lights are converted
//! in [`super::lights`], appearances in [`super::appearance`], the camera in
//! [`super::viewpoint`]. Output is bounded ([`MAX_TRIANGLES`], [`MAX_VISITS`],
//! and the mesh bytes, positions counted as well as triangles, by [`MAX_MESH_BYTES`] and
//! max([`MIN_MESH_BUDGET`], [`MAX_AMPLIFICATION`] × the source)) because `DEF`/`USE` can
//! multiply geometry exponentially; a geometry node is triangulated once however often it is
//! `USE`d, and an Inlined file is parsed once however often it is included. The budgets are
//! checked by a first, counting walk that copies nothing, so a bomb is refused while memory
//! holds only the parsed file and its distinct meshes — not the copies that would exceed them.

use super::appearance::Emission;
use super::extension;
use super::geometry::{self, Geometry, LocalMesh};
use super::lexer::Pos;
use super::tree::{FieldValue, Node, NodeRef, ProtoInstance};
use crate::scene_formats::{FileLocation, LoadedScene, SceneFileError};
use glam::{DMat4, DQuat, DVec3};
use opticks_core::math::{Rgb, Vec3};
use opticks_core::scene::{AreaEmission, MeshDesc, SceneDescription, Source};
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// Most triangles a file (with its Inlines and instancing) may produce.
pub const MAX_TRIANGLES: usize = 50_000_000;
/// Most bytes of positions and triangles (12 bytes each) the instanced meshes may add up to.
pub const MAX_MESH_BYTES: usize = 2 << 30;
/// Mesh bytes any file may produce however small it is (see [`MAX_AMPLIFICATION`]).
pub const MIN_MESH_BUDGET: usize = 64 << 20;
/// Beyond [`MIN_MESH_BUDGET`], the mesh bytes may be at most this many times the source text
/// (the file and its Inlines): instancing that amplifies more is a bomb, refused early.
pub const MAX_AMPLIFICATION: usize = 1024;
/// Most nodes the walk may visit (counting every `USE` again).
pub const MAX_VISITS: usize = 10_000_000;
/// Deepest scene graph, Inlines included.
pub const MAX_WALK_DEPTH: usize = 400;
/// Deepest chain of Inlines.
pub const MAX_INLINE_DEPTH: usize = 16;
/// Radiance of a standard Material's `emissiveColor` of 1, W/(m²·sr).
pub const EMISSIVE_RADIANCE: f32 = 1.0;
/// Image size when the file has no `PhysicalViewpoint` saying otherwise.
pub const DEFAULT_IMAGE_SIZE: u32 = 512;

/// The converter's result: its errors are the loaders' [`SceneFileError`].
pub(super) type Result<T> = std::result::Result<T, SceneFileError>;

/// Converts the parsed top-level `nodes` of `file` (whose parser warnings are `warnings`).
pub fn convert(nodes: &[NodeRef], file: &Path, warnings: Vec<String>) -> Result<LoadedScene> {
    convert_sized(nodes, file, warnings, 0, None)
}

/// [`convert`] for a source text of `source_bytes` bytes (which sets the mesh budget).
pub fn convert_sized(
    nodes: &[NodeRef],
    file: &Path,
    warnings: Vec<String>,
    source_bytes: usize,
    camera: Option<&str>,
) -> Result<LoadedScene> {
    let mut c = Converter {
        source_bytes,
        mesh_bytes: 0,
        geometries: HashMap::new(),
        inlines: HashMap::new(),
        out: SceneDescription::default(),
        warnings,
        materials: HashMap::new(),
        warned: HashSet::new(),
        files: vec![file.to_path_buf()],
        visits: 0,
        triangles: 0,
        extra_viewpoints: 0,
        counting: true,
        wanted_viewpoint: camera.map(str::to_owned),
        viewpoint_names: Vec::new(),
    };
    // First count (every budget checked, nothing copied), then convert.
    for n in nodes {
        c.walk(n, &DMat4::IDENTITY, 0)?;
    }
    (c.counting, c.visits, c.triangles, c.mesh_bytes) = (false, 0, 0, 0);
    for n in nodes {
        c.walk(n, &DMat4::IDENTITY, 0)?;
    }
    if let Some(wanted) = camera
        && c.out.camera.is_none()
    {
        let has = if c.viewpoint_names.is_empty() {
            "the file has no Viewpoint with a description or DEF name".to_string()
        } else {
            format!("the file's Viewpoints: {}", c.viewpoint_names.join(", "))
        };
        return Err(SceneFileError::Invalid {
            at: FileLocation { file: file.to_path_buf(), line: 0, column: 0 },
            element: format!("--camera {wanted:?}"),
            message: format!("no Viewpoint has that description or DEF name ({has})"),
        });
    }
    if c.extra_viewpoints > 0 && camera.is_none() {
        let first = c.out.camera.is_some();
        if first {
            c.warnings.push(format!(
                "{}: {} more Viewpoints ignored: the first one is the camera",
                file.display(),
                c.extra_viewpoints
            ));
        }
    }
    Ok(LoadedScene { description: c.out, warnings: c.warnings })
}

pub(super) struct Converter {
    /// The Viewpoint `--camera` names (by `description` or DEF name), if one is chosen.
    pub(super) wanted_viewpoint: Option<String>,
    /// The names of the Viewpoints passed over (for the error when none is the wanted one).
    pub(super) viewpoint_names: Vec<String>,
    pub(super) out: SceneDescription,
    pub(super) warnings: Vec<String>,
    /// (material node, two-sided) → (material index, emission).
    pub(super) materials: HashMap<(usize, bool), (usize, Emission)>,
    /// Nodes already warned about (a USEd node warns once).
    warned: HashSet<(usize, &'static str)>,
    /// The Inline chain; the last one is the file being walked.
    files: Vec<PathBuf>,
    visits: usize,
    triangles: usize,
    /// Viewpoints after the first, ignored (a warning once the walk is done).
    pub(super) extra_viewpoints: usize,
    /// Bytes of source text read (the file and its Inlines), for the mesh budget.
    source_bytes: usize,
    /// Bytes of positions and triangles produced so far.
    mesh_bytes: usize,
    /// Each geometry node's triangulation, made once however often it is `USE`d (`None`:
    /// skipped). Keyed by node address: every tree stays alive for the whole conversion.
    geometries: HashMap<usize, Option<Rc<LocalMesh>>>,
    /// Each Inlined file (canonical path), read and parsed once however often it is included.
    inlines: HashMap<PathBuf, Rc<Vec<NodeRef>>>,
    /// The first walk: shapes are triangulated (once each) and counted against the budgets,
    /// nothing is copied into the output and no light or camera is made.
    counting: bool,
}

/// A node's address: the key of what is made once per node however often it is `USE`d.
pub(super) fn ptr(n: &Node) -> usize {
    n as *const Node as usize
}

pub(super) fn dv(v: [f32; 3]) -> DVec3 {
    DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
}

pub(super) fn rgb(v: [f32; 3]) -> Rgb {
    Rgb::from(v)
}

/// An SFRotation as a quaternion (a zero or non-finite axis is the identity).
pub(super) fn rotation(r: [f32; 4]) -> DQuat {
    let axis = dv([r[0], r[1], r[2]]);
    let len = axis.length();
    if len > 0.0 && len.is_finite() && r[3].is_finite() {
        DQuat::from_axis_angle(axis / len, f64::from(r[3]))
    } else {
        DQuat::IDENTITY
    }
}

/// The matrix of a Transform node: T · C · R · SR · S · SR⁻¹ · C⁻¹.
pub fn transform_matrix(n: &Node) -> DMat4 {
    let t = dv(n.vec3("translation", [0.0; 3]));
    let c = dv(n.vec3("center", [0.0; 3]));
    let r = rotation(n.rotation("rotation", [0.0, 0.0, 1.0, 0.0]));
    let s = dv(n.vec3("scale", [1.0; 3]));
    let sr = rotation(n.rotation("scaleOrientation", [0.0, 0.0, 1.0, 0.0]));
    DMat4::from_translation(t + c)
        * DMat4::from_quat(r)
        * DMat4::from_quat(sr)
        * DMat4::from_scale(s)
        * DMat4::from_quat(sr.inverse())
        * DMat4::from_translation(-c)
}

impl Converter {
    // ----- messages -----

    pub(super) fn file(&self) -> &Path {
        self.files.last().map(PathBuf::as_path).unwrap_or(Path::new(""))
    }

    pub(super) fn loc(&self, pos: Pos) -> FileLocation {
        FileLocation { file: self.file().to_path_buf(), line: pos.line, column: pos.col }
    }

    pub(super) fn warn(&mut self, n: &Node, message: impl std::fmt::Display) {
        let w = format!("{}: {}: {message}", self.loc(n.pos), n.type_name);
        self.warnings.push(w);
    }

    /// Warns once per node about `what`.
    pub(super) fn warn_once(&mut self, n: &Node, what: &'static str, message: impl std::fmt::Display) {
        if self.warned.insert((ptr(n), what)) {
            self.warn(n, message);
        }
    }

    pub(super) fn invalid(&self, n: &Node, message: impl Into<String>) -> SceneFileError {
        SceneFileError::Invalid { at: self.loc(n.pos), element: n.type_name.clone(), message: message.into() }
    }

    pub(super) fn source(&self, n: &Node) -> Source {
        Source { file: self.file().display().to_string(), line: n.pos.line }
    }

    /// The extension PROTO instance `name` this node is, if declared as documented.
    pub(super) fn extension<'n>(&mut self, n: &'n Node, name: &str) -> Option<&'n ProtoInstance> {
        let inst = n.proto.as_deref()?;
        if inst.proto.name != name {
            return None;
        }
        if extension::conforms(&inst.proto) {
            Some(inst)
        } else {
            if self.warned.insert((std::rc::Rc::as_ptr(&inst.proto) as usize, "interface")) {
                let at = self.loc(inst.proto.pos);
                self.warnings.push(format!(
                    "{at}: PROTO {name}: not the documented interface of the Opticks extension: used as plain VRML"
                ));
            }
            None
        }
    }

    // ----- the walk -----

    fn walk(&mut self, n: &NodeRef, m: &DMat4, depth: usize) -> Result<()> {
        if depth > MAX_WALK_DEPTH {
            return Err(self.invalid(n, format!("the scene graph is more than {MAX_WALK_DEPTH} levels deep")));
        }
        self.visits += 1;
        if self.visits > MAX_VISITS {
            return Err(self.invalid(
                n,
                format!(
                    "the scene graph has more than {MAX_VISITS} node instances (DEF/USE repeated too often)"
                ),
            ));
        }
        if n.unknown {
            return Ok(());
        }
        match n.type_name.as_str() {
            "Transform" => self.children(n.nodes("children"), &(*m * transform_matrix(n)), depth),
            "Group" | "Anchor" | "Collision" => self.children(n.nodes("children"), m, depth),
            "Billboard" => {
                self.warn_once(
                    n,
                    "billboard",
                    "not turned toward the viewer: its children are drawn as a Group",
                );
                self.children(n.nodes("children"), m, depth)
            }
            "Switch" => {
                let which = n.int("whichChoice", -1);
                match usize::try_from(which).ok().and_then(|i| n.nodes("choice").get(i)) {
                    Some(c) => self.walk(c, m, depth + 1),
                    None => Ok(()),
                }
            }
            "LOD" => match n.nodes("level").first() {
                Some(c) => self.walk(c, m, depth + 1),
                None => Ok(()),
            },
            "Shape" => self.shape(n, m),
            "Viewpoint" | "PointLight" | "SpotLight" | "DirectionalLight" if self.counting => Ok(()),
            "Viewpoint" => self.viewpoint(n, m),
            "PointLight" => self.point_light(n, m),
            "SpotLight" => self.spot_light(n, m),
            "DirectionalLight" => self.directional_light(n, m, depth),
            "Inline" => self.inline(n, m, depth),
            "Background" | "Fog" => {
                self.warn_once(
                    n,
                    "env",
                    "not supported (a VRML Background or Fog is not read: give environments in Mitsuba XML, \
                     and Opticks has no participating media): ignored",
                );
                Ok(())
            }
            "Appearance" | "Material" | "Box" | "Sphere" | "Cylinder" | "Cone" | "IndexedFaceSet"
            | "ElevationGrid" | "Coordinate" | "Normal" | "Color" => {
                self.warn_once(n, "place", "not allowed among children (only inside a Shape): ignored");
                Ok(())
            }
            _ => Ok(()),
        }
    }

    fn children(&mut self, kids: &[NodeRef], m: &DMat4, depth: usize) -> Result<()> {
        for c in kids {
            self.walk(c, m, depth + 1)?;
        }
        Ok(())
    }

    // ----- shapes -----

    #[inline(never)] // keeps the recursive walk's stack frame small
    fn shape(&mut self, n: &Node, m: &DMat4) -> Result<()> {
        let Some(g) = n.node("geometry") else { return Ok(()) };
        let local = match self.geometries.get(&ptr(g)) {
            Some(cached) => cached.clone(),
            None => {
                let mut notes = Vec::new();
                let local = match geometry::geometry(g, &mut notes) {
                    Err(e) => return Err(self.invalid(g, e.to_string())),
                    Ok(Geometry::Skipped(msg)) => {
                        self.warn_once(g, "geometry", msg);
                        None
                    }
                    Ok(Geometry::Mesh(mesh)) => Some(Rc::new(mesh)),
                };
                for note in notes {
                    self.warn_once(g, "geometry-note", note);
                }
                self.geometries.insert(ptr(g), local.clone());
                local
            }
        };
        let Some(local) = local else { return Ok(()) };
        // Budgets, checked before anything is copied: each USE costs its positions too.
        self.mesh_bytes += 12 * (local.positions.len() + local.triangles.len());
        let budget =
            MAX_MESH_BYTES.min(MIN_MESH_BUDGET.max(MAX_AMPLIFICATION.saturating_mul(self.source_bytes)));
        if self.mesh_bytes > budget {
            return Err(self.invalid(
                n,
                format!(
                    "the meshes take more than {} MB ({MAX_AMPLIFICATION} × the source text or {} MB, at most {} MB): DEF/USE or Inline multiplies geometry too much",
                    budget >> 20,
                    MIN_MESH_BUDGET >> 20,
                    MAX_MESH_BYTES >> 20
                ),
            ));
        }
        self.triangles += local.triangles.len();
        if self.triangles > MAX_TRIANGLES {
            return Err(self.invalid(
                n,
                format!("the scene has more than {MAX_TRIANGLES} triangles (DEF/USE or Inline multiplies geometry)"),
            ));
        }
        if self.counting {
            return Ok(());
        }
        let (material, emission) = self.material(n.node("appearance").map(|a| &**a), local.solid)?;
        let mut triangles = local.triangles.clone();
        let mut normals = local.normals.clone();
        let positions: Vec<Vec3> = if *m == DMat4::IDENTITY {
            local.positions.clone()
        } else {
            // Shading normals go by the inverse transpose (the core normalises them).
            let nm = glam::DMat3::from_mat4(*m).inverse().transpose();
            normals.iter_mut().for_each(|v| *v = (nm * v.as_dvec3()).as_vec3());
            if m.determinant() < 0.0 {
                // A mirror turns counter-clockwise into clockwise: keep VRML's front face.
                triangles.iter_mut().for_each(|t| t.swap(1, 2));
            }
            local.positions.iter().map(|p| m.transform_point3(p.as_dvec3()).as_vec3()).collect()
        };
        // A power is the core's to turn into radiance (Φ/(A·∫s dω), `AreaEmission::power`),
        // with the scene's own areas; the radiance given then only marks the Shape as a light.
        let emission = match emission {
            Emission::None => None,
            Emission::Radiance(radiance, profile) => {
                Some(AreaEmission { radiance, profile, ..Default::default() })
            }
            Emission::Power(phi, profile) => {
                Some(AreaEmission { radiance: phi, profile, power: Some(phi), ..Default::default() })
            }
        };
        let name = n.def_name.clone().unwrap_or_else(|| format!("Shape_{}_{}", n.pos.line, n.pos.col));
        // `..Default::default()` keeps this literal valid when MeshDesc gains fields.
        #[allow(clippy::needless_update)]
        self.out.meshes.push(MeshDesc {
            name,
            source: self.source(n),
            positions,
            triangles,
            normals,
            material,
            emission,
            ..Default::default()
        });
        Ok(())
    }

    // ----- Inline -----

    #[inline(never)] // keeps the recursive walk's stack frame small
    fn inline(&mut self, n: &Node, m: &DMat4, depth: usize) -> Result<()> {
        let urls: Vec<String> = match n.get("url") {
            Some(FieldValue::Strs(v)) => v.clone(),
            _ => Vec::new(),
        };
        let dir = self.file().parent().map(Path::to_path_buf).unwrap_or_default();
        let Some(path) = urls.iter().find_map(|u| super::local_url(&dir, u).map(|(p, _)| p)) else {
            self.warn_once(
                n,
                "inline",
                format!("none of the URLs {urls:?} is a readable local file: ignored"),
            );
            return Ok(());
        };
        let canonical = path.canonicalize().unwrap_or_else(|_| path.clone());
        if self.files.iter().any(|f| f.canonicalize().ok().as_ref() == Some(&canonical)) {
            self.warn_once(
                n,
                "recursion",
                format!("{} includes itself (Inline recursion): ignored", path.display()),
            );
            return Ok(());
        }
        if self.files.len() > MAX_INLINE_DEPTH {
            return Err(self.invalid(n, format!("Inlines nested more than {MAX_INLINE_DEPTH} deep")));
        }
        let nodes = match self.inlines.get(&canonical) {
            Some(nodes) => nodes.clone(),
            None => {
                let text = super::read_source(&path)?;
                self.source_bytes += text.len();
                let (nodes, warnings) = super::parse_text(&text, &path)?;
                self.warnings.extend(warnings);
                let nodes = Rc::new(nodes);
                self.inlines.insert(canonical, nodes.clone());
                nodes
            }
        };
        self.files.push(path);
        let result = self.children(&nodes, m, depth);
        self.files.pop();
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use opticks_core::bsdf::{Bsdf, Lambert};
    use opticks_core::light::EmissionProfile;
    use opticks_core::light::Light;
    use opticks_core::scene::Scene;
    use std::f64::consts::PI;

    /// The radiance of the area light that mesh `mesh` of `d` becomes in the built scene.
    fn built_radiance(d: &SceneDescription, mesh: usize) -> Rgb {
        let scene = Scene::build(d).unwrap();
        let k = scene.light_index(&d.meshes[mesh].name).unwrap();
        match &scene.lights[k] {
            Light::Area(a) => a.radiance,
            other => panic!("{other:?}"),
        }
    }

    fn load(body: &str) -> LoadedScene {
        let text = format!("#VRML V2.0 utf8\n{}\n{body}", extension::DECLARATIONS);
        let (nodes, warnings) = super::super::parse_text(&text, Path::new("t.wrl")).unwrap();
        convert(&nodes, Path::new("t.wrl"), warnings).unwrap()
    }

    /// The error converting `body` (after the extension's declarations), and the line of its
    /// last node.
    fn error(body: &str) -> (String, usize) {
        let text = format!("#VRML V2.0 utf8\n{}\n{body}", extension::DECLARATIONS);
        let (nodes, warnings) = super::super::parse_text(&text, Path::new("t.wrl")).unwrap();
        let e = convert(&nodes, Path::new("t.wrl"), warnings).map(|_| ()).unwrap_err().to_string();
        (e, text.lines().count())
    }

    #[test]
    fn transform_order_is_vrmls() {
        let s = load(
            "Transform { translation 1 0 0 rotation 0 0 1 1.5707963 center 0 1 0 scale 2 1 1 \
             scaleOrientation 0 0 1 0.7853982 children Shape { geometry IndexedFaceSet { \
             coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] } coordIndex [ 0 1 2 ] } } }",
        );
        let p = &s.description.meshes[0].positions;
        // By hand: P' = T·C·R·SR·S·SR⁻¹·C⁻¹·P.
        let m = |p: DVec3| {
            let p = p - DVec3::Y;
            let sr = DQuat::from_rotation_z(PI / 4.0);
            let p = sr * (DVec3::new(2.0, 1.0, 1.0) * (sr.inverse() * p));
            let p = DQuat::from_rotation_z(PI / 2.0) * p;
            p + DVec3::Y + DVec3::X
        };
        for (got, local) in p.iter().zip([DVec3::ZERO, DVec3::X, DVec3::Y]) {
            assert!((got.as_dvec3() - m(local)).length() < 1e-5, "{got:?} vs {:?}", m(local));
        }
    }

    #[test]
    fn materials_follow_vrml_lighting_and_the_extension() {
        let s = load(
            "Shape { appearance Appearance { material Material { diffuseColor 0.5 0.5 0.5 specularColor 0.8 0.2 0 shininess 0.5 } } geometry Box {} }\n\
             Shape { appearance Appearance { material DEF M PhysicalMaterial { diffuse 0.2 0.3 0.4 twoSided TRUE } } geometry Box {} }\n\
             Shape { appearance Appearance { material USE M } geometry Sphere {} }\n\
             Shape { appearance Appearance { material AreaLight { power 3 3 3 } } geometry Box { size 1 1 1 } }",
        );
        let d = &s.description;
        assert_eq!(d.materials.len(), 3, "{:?}", d.materials);
        match &d.materials[0].bsdf {
            Bsdf::ModifiedPhong(p) => {
                assert!((p.kd - Rgb::new(0.5 / 1.3, 0.5, 0.5)).abs().max_element() < 1e-6, "{:?}", p.kd);
                assert!((p.ks - Rgb::new(0.8 / 1.3, 0.2, 0.0)).abs().max_element() < 1e-6);
                assert_eq!(p.exponent, 64.0);
            }
            b => panic!("{b:?}"),
        }
        assert!(!d.materials[0].two_sided);
        assert!(s.warnings.iter().any(|w| w.contains("exceeds 1")), "{:?}", s.warnings);
        assert_eq!(d.materials[1].bsdf, Bsdf::Lambert(Lambert::new(Rgb::new(0.2, 0.3, 0.4)).unwrap()));
        assert!(d.materials[1].two_sided);
        assert_eq!(d.materials[1].name, "M");
        assert_eq!(d.meshes[2].material, 1);
        // Φ = π·L·A with A = 6 m² (the scene turns the given power into radiance).
        let l = built_radiance(d, 3);
        assert!((l * (std::f32::consts::PI * 6.0) - Rgb::splat(3.0)).abs().max_element() < 1e-5, "{l:?}");
    }

    /// The extension's explicit Modified Phong parameters are physical: kd + ks > 1 or a negative
    /// value is an error at the node (only legacy `Material` colours are rescaled).
    #[test]
    fn impossible_physical_materials_are_errors() {
        let cases = [
            ("PhysicalMaterial { diffuse 0.7 0.7 0.7 specular 0.5 0 0 exponent 10 }", "kd + ks"),
            ("PhysicalMaterial { diffuse 0.5 -0.1 0.5 }", "must not be negative"),
            ("AreaLight { power 1 1 1 diffuse 0.9 0.9 0.9 specular 0.2 0.2 0.2 }", "kd + ks"),
        ];
        for (material, want) in cases {
            let (e, line) = error(&format!(
                "Shape {{ appearance Appearance {{ material\n  {material} }} geometry Box {{}} }}"
            ));
            assert!(e.starts_with(&format!("t.wrl:{line}:3")) && e.contains(want), "{material}: {e}");
        }
    }

    #[test]
    fn viewpoint_fov_is_along_the_smaller_side() {
        let s = load(
            "Transform { translation 0 1 0 children PhysicalViewpoint { position 0 0 5 orientation 0 1 0 1.5707963 \
             fieldOfView 0.5 width 200 height 100 } }\nViewpoint {}",
        );
        let c = s.description.camera.unwrap();
        assert!((c.eye - Vec3::new(0.0, 1.0, 5.0)).length() < 1e-6);
        // -z turned by +90° about y looks along -x.
        assert!(((c.target - c.eye) - Vec3::NEG_X).length() < 1e-6, "{:?}", c.target - c.eye);
        assert_eq!((c.width, c.height), (200, 100));
        let expected = 2.0 * ((0.25f64).tan() * 2.0).atan();
        assert!((f64::from(c.fov_x_degrees) - expected.to_degrees()).abs() < 1e-4);
        assert!(s.warnings.iter().any(|w| w.contains("1 more Viewpoints")), "{:?}", s.warnings);
    }

    /// The Viewpoint is checked by the core's camera constructor, at the node.
    #[test]
    fn impossible_viewpoints_are_errors_at_the_node() {
        for (viewpoint, want) in [
            ("PhysicalViewpoint { width 0 height 4 }", "image size 0x4"),
            ("PhysicalViewpoint { width -2 height 4 }", "image size -2x4 must be positive"),
            ("Viewpoint { fieldOfView 3.5 }", "field of view"),
        ] {
            let (e, line) = error(viewpoint);
            assert!(e.starts_with(&format!("t.wrl:{line}:1")) && e.contains(want), "{viewpoint}: {e}");
        }
    }

    /// A light value the core refuses is an error at the light's node, in the core's words.
    #[test]
    fn impossible_lights_are_errors_at_the_node() {
        for (light, want) in [
            (
                "PhysicalSpotLight { power -1 1 1 }",
                "power [-1.0, 1.0, 1.0] W must be finite and non-negative",
            ),
            ("SpotLight { direction 0 0 0 }", "direction [0.0, 0.0, 0.0] is zero or not finite"),
            ("PhysicalSpotLight { intensity 1 1 1 beamWidth -1 }", "the spot beam width"),
            ("PhysicalDirectionalLight { irradiance -1 0 0 }", "emission [-1.0, 0.0, 0.0]"),
            ("PhysicalPointLight { lumens -5 }", "lumens -5 must be finite and non-negative"),
            (
                "PhysicalPointLight { intensity -1 0 0 lumens 5 }",
                "lumens need a colour of non-zero luminance",
            ),
        ] {
            let (e, line) = error(light);
            assert!(e.starts_with(&format!("t.wrl:{line}:1")) && e.contains(want), "{light}: {e}");
        }
    }

    #[test]
    fn lights_in_physical_units() {
        let s = load(
            "Transform { translation 1 2 3 children [ PointLight { intensity 0.5 color 1 0.5 0 location 1 0 0 } \
             PhysicalPointLight { power 12.566371 0 0 } PointLight { on FALSE } \
             SpotLight { location 0 1 0 direction 0 -2 0 beamWidth 0.2 cutOffAngle 0.5 intensity 0.5 attenuation 0 1 0 } \
             SpotLight { cutOffAngle 0.3 } PhysicalSpotLight { power 2 2 2 cutOffAngle 0.4 beamWidth 0.1 } \
             DirectionalLight { direction 1 0 0 intensity 0.25 color 1 1 0 } \
             PhysicalDirectionalLight { direction 0 0 -3 irradiance 100 50 25 } PhysicalDirectionalLight { on FALSE } ] }",
        );
        let l = &s.description.point_lights;
        assert_eq!(l.len(), 5, "{l:?}");
        assert_eq!(l[0].position, Vec3::new(2.0, 2.0, 3.0));
        assert_eq!(l[0].intensity, Rgb::new(0.5, 0.25, 0.0));
        assert!((l[1].intensity.x - 1.0).abs() < 1e-6);
        let spot = |c: f32, b: f32| {
            Some(opticks_core::light::EmissionProfile::Spot { cutoff_angle: c, beam_width: b })
        };
        assert_eq!(l[2].position, Vec3::new(1.0, 3.0, 3.0));
        assert_eq!(l[2].orientation.unwrap().n, Vec3::NEG_Y);
        assert_eq!(l[2].intensity, Rgb::splat(0.5));
        assert_eq!(l[2].profile, spot(0.5, 0.2));
        // VRML's default beamWidth (π/2) exceeds the cutoff: no fall-off.
        assert_eq!(l[3].profile, spot(0.3, 0.3));
        assert_eq!(l[3].orientation.unwrap().n, Vec3::NEG_Z);
        assert_eq!((l[4].power, l[4].profile.clone()), (Some(Rgb::splat(2.0)), spot(0.4, 0.1)));
        let d = &s.description.directional_lights;
        assert_eq!(d.len(), 2, "{d:?}");
        assert_eq!((d[0].direction, d[0].irradiance), (Vec3::X, Rgb::new(0.25, 0.25, 0.0)));
        assert_eq!((d[1].direction, d[1].irradiance), (Vec3::NEG_Z, Rgb::new(100.0, 50.0, 25.0)));
        let w = s.warnings.join("\n");
        assert!(w.contains("SpotLight: attenuation ignored"), "{w}");
        assert!(w.contains("DirectionalLight: lights the whole scene"), "{w}");
    }

    #[test]
    fn area_light_emission_functions() {
        let s = load(
            "Shape { appearance Appearance { material AreaLight { power 3 3 3 emission \"cosine 4\" } } geometry Box { size 1 1 1 } }\n\
             Shape { appearance Appearance { material AreaLight { radiance 1 1 1 emission \"uniform\" } } geometry Box {} }\n\
             Shape { appearance Appearance { material AreaLight { radiance 1 1 1 emission \"cosine -1\" } } geometry Box {} }",
        );
        let m = &s.description.meshes;
        assert_eq!(
            m[0].emission.as_ref().unwrap().profile,
            Some(EmissionProfile::CosinePower { exponent: 4.0 })
        );
        // Φ = L·A·2π/(n+1) with A = 6 m² (the scene turns the given power into radiance).
        let l = built_radiance(&s.description, 0).x as f64;
        assert!((l * 6.0 * 2.0 * PI / 5.0 - 3.0).abs() < 1e-5, "{l}");
        assert_eq!(m[1].emission.as_ref().unwrap().profile, Some(EmissionProfile::Uniform));
        assert_eq!(m[2].emission.as_ref().unwrap().profile, None);
        assert!(s.warnings.iter().any(|w| w.contains("\"cosine -1\" is not one of")), "{:?}", s.warnings);
    }

    /// An AreaLight given by its power is written back by its power, so the light keeps Φ.
    #[test]
    fn the_writer_keeps_an_area_light_given_by_power() {
        let s = load(
            "Shape { appearance Appearance { material AreaLight { power 3 2 1 emission \"cosine 4\" } } geometry Box { size 1 1 1 } }",
        );
        let mut text = Vec::new();
        super::super::writer::write_vrml(&s.description, &mut text).unwrap();
        let back = super::super::load_str(std::str::from_utf8(&text).unwrap(), Path::new("w.wrl")).unwrap();
        assert_eq!(
            back.description.meshes[0].emission.as_ref().unwrap().power,
            Some(Rgb::new(3.0, 2.0, 1.0))
        );
        assert_eq!(built_radiance(&back.description, 0), built_radiance(&s.description, 0));
    }

    #[test]
    fn switch_lod_and_mirrors() {
        let tri = "Shape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] } coordIndex [ 0 1 2 ] } }";
        let s = load(&format!(
            "Switch {{ whichChoice 1 choice [ {tri} Transform {{ scale -1 1 1 children {tri} }} ] }}\n\
             Switch {{ choice {tri} }}\nLOD {{ level [ {tri} {tri} ] }}"
        ));
        let d = &s.description;
        assert_eq!(d.meshes.len(), 2);
        let m = &d.meshes[0];
        let [a, b, c] = m.triangles[0].map(|i| m.positions[i as usize]);
        assert!((b - a).cross(c - a).z > 0.0, "a mirror keeps the front face");
    }
}
