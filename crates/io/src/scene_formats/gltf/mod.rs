//! glTF 2.0 scenes (`.gltf` with embedded base64 or external `.bin` buffers, and binary `.glb`):
//! [`load_gltf_scene`]. The JSON is parsed and validated by the `gltf` crate; buffers and
//! accessors are read here, with bounds checks ([`buffers`]).
//!
//! | glTF | Opticks |
//! |---|---|
//! | scene | the one [`LoadOptions::gltf_scene`] names (by name or index; the CLI's `--gltf-scene`), else the default `scene`, else the first; with no scene at all, every root node (warning) |
//! | node transforms | `matrix` or TRS (`T·R·S`), multiplied down the tree; vertices are baked to world space; a negative determinant flips the winding so front faces stay front faces |
//! | mesh primitives, mode `TRIANGLES` | one [`MeshDesc`] per primitive instance, named after the node (else the mesh), `.k` appended for primitive k of several; indexed (`u8`/`u16`/`u32`) and non-indexed; positions must be `VEC3`/`FLOAT` |
//! | `NORMAL` | per-vertex shading normals (`VEC3`/`FLOAT`, one per position), taken to world space by the inverse transpose of the node transform; without it the primitive is faceted (glTF's flat normals) |
//! | other primitive modes (points, lines, strips, fans) | warning, skipped |
//! | materials (metallic-roughness) | Lambert or Modified Phong, see [`materials`]; no material → glTF's default (white metal, roughness 1) |
//! | `baseColorTexture`, `metallicRoughnessTexture`, samplers, `KHR_texture_transform` | bitmap textures on kd and ks, baked per texel ([`materials`], [`textures`]); the primitive's `TEXCOORD_n` (`FLOAT`, or normalized `UNSIGNED_BYTE`/`UNSIGNED_SHORT`) become the mesh's UVs |
//! | `KHR_materials_transmission`, `KHR_materials_volume` | thin-walled or refracting glass ([`materials`]) |
//! | `emissiveFactor` × `KHR_materials_emissive_strength` | area light of that radiance in W/(m²·sr) (see [`materials`]) |
//! | `KHR_lights_punctual` point | [`PointLightDesc`] of intensity `color × intensity / 683` W/sr (glTF gives candela = lm/sr; 683 lm/W is the luminous efficacy at 555 nm, the convention glTF exporters such as Blender's use); `range` is ignored (physical inverse-square falloff) |
//! | `KHR_lights_punctual` spot | a spot [`PointLightDesc`] on the node's −Z, `color × intensity / 683` W/sr on the axis, full within `innerConeAngle` (at least [`SPOT_MIN_BEAM`] × outer) and falling **linearly in angle** to zero at `outerConeAngle` (glTF leaves the fall-off curve to the renderer); `range` ignored |
//! | `KHR_lights_punctual` directional | a [`DirectionalLightDesc`] along the node's −Z of irradiance `color × intensity / 683` W/m² (glTF gives lux), a sun covering the scene |
//! | cameras | the camera [`LoadOptions::camera`] names (its node's name or its own; the CLI's `--camera`), else the camera of the lowest-index node in the scene (orthographic ones with the film's half extents `xmag` × `ymag`, 512 pixels high); it looks down its local −Z with +Y up; `yfov` is vertical: `fov_x = 2·atan(tan(yfov/2)·W/H)`; the image is 512 pixels high and `round(512·aspectRatio)` wide (512×512 without `aspectRatio`) |
//! | skins, morph targets, animations, normal, occlusion and emissive textures | ignored (warnings for the ones that change what is seen) |
//!
//! glTF's units and axes (metres, right-handed, +Y up) are Opticks's, so nothing is converted.
//!
//! Errors name the file, and the JSON line and column for malformed JSON: unreadable file,
//! malformed JSON or GLB, a document the `gltf` crate's validation rejects (the JSON path is
//! given), a buffer whose file is missing (its path is given) or too short, an accessor outside
//! its buffer, an index past the vertex count, a non-finite transform, an invalid material value,
//! a light or camera the core's constructors refuse (in the core's words, at the element).
//! No input makes the loader panic.

pub mod buffers;
pub mod materials;
pub mod textures;

use super::{FileLocation, LoadOptions, LoadedScene, SceneFileError};
use ::gltf::camera::Projection;
use ::gltf::khr_lights_punctual::Kind;
use ::gltf::mesh::Mode;
use opticks_core::light::check::check_emission;
use opticks_core::light::{LUMENS_PER_WATT, LightError};
use opticks_core::math::{Mat4, Rgb, Vec2, Vec3};
use opticks_core::scene::{
    AreaEmission, CameraDesc, CameraKind, DirectionalLightDesc, MeshDesc, PointLightDesc, SceneDescription,
    Source,
};
use opticks_core::sensor::Sensor;
use opticks_core::texture::TextureBinding;
use std::path::Path;

/// The narrowest full-intensity cone of a glTF spot, as a fraction of its outer cone (the core's
/// spot needs a positive beam; glTF allows `innerConeAngle` 0).
pub const SPOT_MIN_BEAM: f64 = 1e-3;

/// Image height (and width without `aspectRatio`) of a glTF camera, pixels.
pub const DEFAULT_IMAGE_HEIGHT: u32 = 512;

/// A converted material as its primitives use it: its index in the description's materials,
/// its emitted radiance, the `TEXCOORD_n` set its textures read.
type MaterialUse = (usize, Option<Rgb>, Option<u32>);

/// The first mesh primitive whose POSITION attribute names a missing accessor: (mesh,
/// primitive, accessor index).
fn bad_position_accessor(json: &::gltf::json::Root) -> Option<(usize, usize, usize)> {
    use ::gltf::json::validation::Checked;
    let position = Checked::Valid(::gltf::json::mesh::Semantic::Positions);
    json.meshes.iter().enumerate().find_map(|(m, mesh)| {
        mesh.primitives.iter().enumerate().find_map(|(p, prim)| {
            let index = prim.attributes.get(&position)?.value();
            (index >= json.accessors.len()).then_some((m, p, index))
        })
    })
}

/// What is wrong with the declared length of a GLB file (`data` starting with the `glTF`
/// magic): it must cover the 12-byte header and not exceed the file.
fn bad_glb_length(data: &[u8]) -> Option<String> {
    if !data.starts_with(b"glTF") || data.len() < 12 {
        return None;
    }
    let length = u32::from_le_bytes([data[8], data[9], data[10], data[11]]) as usize;
    (length < 12 || length > data.len()).then(|| {
        format!(
            "malformed binary glTF: the header declares {length} bytes, the file has {} (at least 12)",
            data.len()
        )
    })
}

/// Loads a `.gltf` or `.glb` file as a scene (see the module docs): its default scene and camera.
pub fn load_gltf_scene(path: &Path) -> Result<LoadedScene, SceneFileError> {
    load_gltf_scene_with(path, &LoadOptions::default())
}

/// Loads a `.gltf` or `.glb` file as a scene, the scene and camera chosen by `options`
/// ([`LoadOptions::gltf_scene`], [`LoadOptions::camera`]; see the module docs).
pub fn load_gltf_scene_with(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneFileError> {
    let data = crate::input_file::read(path)
        .map_err(|source| SceneFileError::Read { path: path.to_path_buf(), source })?;
    let loc = |line: u32, column: u32| FileLocation { file: path.to_path_buf(), line, column };
    let invalid =
        |element: String, message: String| SceneFileError::Invalid { at: loc(0, 0), element, message };

    // gltf 1.4.1 subtracts the 12-byte header from a GLB's declared length unchecked (an
    // overflow panic on a length below 12, found by fuzzing): the header is checked here first.
    if let Some(message) = bad_glb_length(&data) {
        return Err(invalid("GLB container".into(), message));
    }
    // Parsed without validation first: gltf-json 1.4.1's validation indexes the POSITION
    // accessor without a bounds check (a panic, found by fuzzing), so that index is checked
    // here before the crate's validation runs.
    let gltf = ::gltf::Gltf::from_slice_without_validation(&data).and_then(|g| {
        let json = g.document.into_json();
        if let Some((m, p, index)) = bad_position_accessor(&json) {
            let message = format!(
                "meshes[{m}].primitives[{p}].attributes.POSITION: accessor {index} does not exist (the file has {})",
                json.accessors.len()
            );
            return Ok(Err(invalid("glTF document".into(), format!("invalid glTF: {message}"))));
        }
        Ok(Ok(::gltf::Gltf { document: ::gltf::Document::from_json(json)?, blob: g.blob }))
    });
    let gltf = gltf.map_err(|e| match e {
        ::gltf::Error::Deserialize(j) => {
            // serde_json's message ends with the position, which the location already gives.
            let text = j.to_string();
            let suffix = format!(" at line {} column {}", j.line(), j.column());
            SceneFileError::Invalid {
                at: loc(u32::try_from(j.line()).unwrap_or(0), u32::try_from(j.column()).unwrap_or(0)),
                element: "glTF JSON".into(),
                message: format!("malformed JSON: {}", text.strip_suffix(&suffix).unwrap_or(&text)),
            }
        }
        ::gltf::Error::Validation(errors) => {
            let list: Vec<String> = errors.iter().take(5).map(|(p, e)| format!("{p}: {e}")).collect();
            let more =
                if errors.len() > 5 { format!(" (and {} more)", errors.len() - 5) } else { String::new() };
            invalid("glTF document".into(), format!("invalid glTF: {}{more}", list.join("; ")))
        }
        ::gltf::Error::Binary(b) => invalid("GLB container".into(), format!("malformed binary glTF: {b}")),
        other => invalid("glTF".into(), other.to_string()),
    })??;
    let doc = &gltf.document;
    let folder = path.parent().unwrap_or(Path::new(""));
    let buffers = buffers::load_buffers(doc, gltf.blob.as_deref(), folder).map_err(|(i, e)| {
        let element = format!("buffer {i}");
        match e {
            buffers::BufferError::File { path: file, source } => {
                invalid(element, format!("cannot read buffer file {}: {source}", file.display()))
            }
            buffers::BufferError::Other(m) => invalid(element, m),
        }
    })?;

    let mut warnings = Vec::new();
    let file_name = path.display().to_string();
    let warn = |warnings: &mut Vec<String>, element: &str, msg: String| {
        warnings.push(format!("{file_name}: {element}: {msg}"));
    };
    for ext in doc.extensions_required() {
        if !matches!(
            ext,
            "KHR_lights_punctual"
                | "KHR_materials_emissive_strength"
                | "KHR_materials_specular"
                | "KHR_materials_ior"
                | "KHR_materials_transmission"
                | "KHR_materials_volume"
                | "KHR_texture_transform"
        ) {
            warn(
                &mut warnings,
                "extensionsRequired",
                format!("{ext} is not supported; the scene may look wrong"),
            );
        }
    }

    // Roots of the scene to load.
    let chosen = match &options.gltf_scene {
        None => doc.default_scene().or_else(|| doc.scenes().next()),
        Some(wanted) => {
            Some(choose_scene(doc, wanted).map_err(|m| invalid(format!("--gltf-scene {wanted:?}"), m))?)
        }
    };
    let roots: Vec<::gltf::Node<'_>> = match chosen {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    if let Some(x) = is_child.get_mut(c.index()) {
                        *x = true;
                    }
                }
            }
            if doc.nodes().len() > 0 {
                warn(&mut warnings, "scenes", "the file has no scene; every root node is loaded".into());
            }
            doc.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };

    // Depth-first traversal with world matrices; a node reached twice means the hierarchy is not
    // a tree (the glTF spec forbids that; it would loop forever or duplicate geometry).
    let mut world: Vec<Option<Mat4>> = vec![None; doc.nodes().len()];
    let mut order: Vec<::gltf::Node<'_>> = Vec::new();
    let mut stack: Vec<(::gltf::Node<'_>, Mat4)> =
        roots.into_iter().rev().map(|n| (n, Mat4::IDENTITY)).collect();
    while let Some((node, parent)) = stack.pop() {
        let element = node_element(&node);
        let slot = world
            .get_mut(node.index())
            .ok_or_else(|| invalid(element.clone(), "index out of range".into()))?;
        if slot.is_some() {
            return Err(invalid(element, "node is reached twice: the node hierarchy is not a tree".into()));
        }
        let m = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if !m.is_finite() {
            return Err(invalid(element, "transform is not finite".into()));
        }
        *slot = Some(m);
        order.push(node.clone());
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c, m));
        }
    }
    order.sort_by_key(|n| n.index());

    let mut desc = SceneDescription::default();
    // glTF material index (None = default) → (index in desc.materials, emission, UV set read).
    let mut material_of: Vec<Option<MaterialUse>> = vec![None; doc.materials().len() + 1];
    let mut images = textures::Images::new(doc, &buffers, folder);
    let source = Source { file: file_name.clone(), line: 0 };
    // The scene's cameras, in node order (one is chosen after the traversal).
    let mut cameras: Vec<(::gltf::Node<'_>, ::gltf::Camera<'_>, Mat4)> = Vec::new();

    for node in &order {
        let m = world[node.index()].unwrap_or(Mat4::IDENTITY);
        let element = node_element(node);
        if node.skin().is_some() || node.weights().is_some() {
            warn(
                &mut warnings,
                &element,
                "skins and morph targets are not supported; the rest pose is used".into(),
            );
        }
        if let Some(mesh) = node.mesh() {
            let prims: Vec<_> = mesh.primitives().collect();
            let base =
                node.name().or(mesh.name()).map_or_else(|| format!("node {}", node.index()), str::to_string);
            let flip = m.determinant() < 0.0;
            for (k, prim) in prims.iter().enumerate() {
                let pel = format!("{element}: mesh {} primitive {k}", mesh.index());
                if prim.mode() != Mode::Triangles {
                    warn(
                        &mut warnings,
                        &pel,
                        format!("mode {:?} is not supported (only TRIANGLES); skipped", prim.mode()),
                    );
                    continue;
                }
                let Some(pos_acc) = prim.get(&::gltf::Semantic::Positions) else {
                    warn(&mut warnings, &pel, "has no POSITION attribute; skipped".into());
                    continue;
                };
                let local = buffers::read_vec3(&pos_acc, &buffers).map_err(|e| invalid(pel.clone(), e))?;
                let n = local.len();
                let mut idx = match prim.indices() {
                    Some(a) => buffers::read_indices(&a, &buffers).map_err(|e| invalid(pel.clone(), e))?,
                    None => (0..u32::try_from(n).unwrap_or(u32::MAX)).collect(),
                };
                if let Some(&bad) = idx.iter().find(|&&i| i as usize >= n) {
                    return Err(invalid(
                        pel,
                        format!("index {bad} is past the {n} vertices of the primitive"),
                    ));
                }
                if idx.len() % 3 != 0 {
                    warn(
                        &mut warnings,
                        &pel,
                        format!(
                            "{} indices are not a multiple of 3; the last {} are ignored",
                            idx.len(),
                            idx.len() % 3
                        ),
                    );
                    idx.truncate(idx.len() - idx.len() % 3);
                }
                let triangles: Vec<[u32; 3]> = idx
                    .chunks_exact(3)
                    .map(|t| if flip { [t[0], t[2], t[1]] } else { [t[0], t[1], t[2]] })
                    .collect();
                let positions: Vec<Vec3> =
                    local.iter().map(|p| m.transform_point3(Vec3::from_array(*p))).collect();
                // NORMAL: shading normals, carried to world space by the inverse transpose.
                let normals = match prim.get(&::gltf::Semantic::Normals) {
                    None => Vec::new(),
                    Some(acc) => {
                        let local =
                            buffers::read_vec3(&acc, &buffers).map_err(|e| invalid(pel.clone(), e))?;
                        if local.len() != n {
                            return Err(invalid(
                                pel,
                                format!("NORMAL has {} entries for {n} positions", local.len()),
                            ));
                        }
                        let nm = glam::Mat3::from_mat4(m).inverse().transpose();
                        local.iter().map(|v| nm * Vec3::from_array(*v)).collect()
                    }
                };

                let key = prim.material().index().map_or(0, |i| i + 1);
                let (material, emission, tex_coord) = match material_of.get(key).copied().flatten() {
                    Some(r) => r,
                    None => {
                        let gm = prim.material();
                        let (name, c) = match gm.index() {
                            None => ("default".to_string(), materials::default_material()),
                            Some(i) => {
                                let name = gm.name().map_or_else(|| format!("material {i}"), str::to_string);
                                let c = materials::convert(&gm, &name, &mut images)
                                    .map_err(|e| invalid(format!("material {i} ({name})"), e))?;
                                (name, c)
                            }
                        };
                        for note in &c.notes {
                            warn(&mut warnings, &format!("material {name:?}"), note.clone());
                        }
                        desc.materials.push(c.material);
                        let index = desc.materials.len() - 1;
                        for (slot, texture) in c.textures {
                            desc.textures.push(TextureBinding { material: index, slot, texture });
                        }
                        let r = (index, c.emission, c.tex_coord);
                        if let Some(s) = material_of.get_mut(key) {
                            *s = Some(r);
                        }
                        r
                    }
                };
                // The texture coordinates the material's textures read.
                let uvs = match tex_coord {
                    None => Vec::new(),
                    Some(set) => {
                        let Some(acc) = prim.get(&::gltf::Semantic::TexCoords(set)) else {
                            return Err(invalid(
                                pel,
                                format!(
                                    "its material is textured through TEXCOORD_{set}, which the primitive does not have"
                                ),
                            ));
                        };
                        let uv = buffers::read_vec2(&acc, &buffers).map_err(|e| invalid(pel.clone(), e))?;
                        if uv.len() != n {
                            return Err(invalid(
                                pel,
                                format!("TEXCOORD_{set} has {} entries for {n} positions", uv.len()),
                            ));
                        }
                        if uv.iter().flatten().any(|c| !c.is_finite()) {
                            return Err(invalid(pel, format!("TEXCOORD_{set} has a non-finite value")));
                        }
                        uv.into_iter().map(Vec2::from_array).collect()
                    }
                };
                let name = if prims.len() > 1 { format!("{base}.{k}") } else { base.clone() };
                desc.meshes.push(MeshDesc {
                    name,
                    source: source.clone(),
                    positions,
                    triangles,
                    normals,
                    material,
                    emission: emission.map(AreaEmission::lambertian),
                    uvs,
                    attributes: Vec::new(),
                });
            }
        }
        if let Some(light) = node.light() {
            let lname = light.name().map_or_else(|| format!("light {}", light.index()), str::to_string);
            // A value the core refuses, in the core's words, at the light.
            let bad = |e: LightError| invalid(format!("{element}: {lname}"), e.to_string());
            // glTF gives candela (point, spot) or lux (directional): ÷ 683 is W/sr or W/m².
            let [r, g, b] = light.color();
            let amount = Rgb::new(r, g, b) * (light.intensity() / LUMENS_PER_WATT);
            let (position, axis) = (m.transform_point3(Vec3::ZERO), m.transform_vector3(Vec3::NEG_Z));
            match light.kind() {
                Kind::Point => {
                    desc.point_lights.push(PointLightDesc {
                        name: lname.clone(),
                        source: source.clone(),
                        position,
                        intensity: check_emission(amount).map_err(bad)?,
                        ..Default::default()
                    });
                }
                Kind::Spot { inner_cone_angle, outer_cone_angle } => {
                    let (outer, inner) = (f64::from(outer_cone_angle), f64::from(inner_cone_angle));
                    // The core's spot needs a positive beam: an inner cone of 0 falls off from
                    // (almost) the axis.
                    let beam = inner.clamp(outer * SPOT_MIN_BEAM, outer);
                    let spot = PointLightDesc::spot(
                        lname.clone(),
                        source.clone(),
                        position,
                        axis.as_dvec3(),
                        amount,
                        outer as f32,
                        beam as f32,
                    )
                    .map_err(bad)?;
                    desc.point_lights.push(spot);
                }
                Kind::Directional => {
                    let sun =
                        DirectionalLightDesc::new(lname.clone(), source.clone(), axis.as_dvec3(), amount)
                            .map_err(bad)?;
                    desc.directional_lights.push(sun);
                }
            }
        }
        if let Some(cam) = node.camera() {
            cameras.push((node.clone(), cam, m));
        }
    }
    // The camera: the one named by the options, else the lowest-index node's.
    let pick = match &options.camera {
        Some(wanted) => {
            let named = |(n, c, _): &&(::gltf::Node<'_>, ::gltf::Camera<'_>, Mat4)| {
                n.name() == Some(wanted.as_str()) || c.name() == Some(wanted.as_str())
            };
            let Some(found) = cameras.iter().find(named) else {
                let names: Vec<String> = cameras.iter().map(|(n, c, _)| camera_names(n, c)).collect();
                let has = if names.is_empty() {
                    "the scene has no camera".to_string()
                } else {
                    format!("the scene's cameras: {}", names.join(", "))
                };
                return Err(invalid(
                    format!("--camera {wanted:?}"),
                    format!("no camera of that name ({has})"),
                ));
            };
            Some(found)
        }
        None => cameras.first(),
    };
    for entry in &cameras {
        let (node, cam, m) = entry;
        let cel = format!("{}: camera {}", node_element(node), cam.index());
        if !pick.is_some_and(|p| std::ptr::eq(p, entry)) {
            let why = if options.camera.is_some() {
                "not the one --camera names"
            } else {
                "another camera comes first (lowest node index; --camera NAME chooses another)"
            };
            warn(&mut warnings, &cel, format!("{why}; ignored"));
            continue;
        }
        // The image is DEFAULT_IMAGE_HEIGHT pixels high; the projection gives its width.
        let height = DEFAULT_IMAGE_HEIGHT;
        let (width, fov_x_degrees, kind) = match cam.projection() {
            Projection::Perspective(p) => {
                let aspect = p.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0);
                let width = aspect.map_or(height, |a| ((height as f32 * a).round() as u32).max(1));
                let fov_x = 2.0 * ((p.yfov() * 0.5).tan() * width as f32 / height as f32).atan();
                (width, fov_x.to_degrees(), CameraKind::Perspective)
            }
            Projection::Orthographic(o) => {
                // xmag, ymag: half the view's width and height.
                let (xmag, ymag) = (o.xmag().abs(), o.ymag().abs());
                if !(xmag.is_finite() && ymag.is_finite() && xmag > 0.0 && ymag > 0.0) {
                    return Err(invalid(
                        cel,
                        format!("orthographic xmag {xmag} and ymag {ymag} must be positive"),
                    ));
                }
                let width = ((height as f32 * xmag / ymag).round() as u32).max(1);
                (width, 45.0, CameraKind::Orthographic { half_width: xmag, half_height: ymag })
            }
        };
        let eye = m.transform_point3(Vec3::ZERO);
        let forward = m.transform_vector3(-Vec3::Z).normalize_or_zero();
        let up = m.transform_vector3(Vec3::Y).normalize_or_zero();
        let camera = CameraDesc { eye, target: eye + forward, up, fov_x_degrees, width, height, kind };
        // The core's camera checks (field of view, axes, extent), reported at the camera.
        Sensor::new(&camera).map_err(|e| invalid(cel, e.to_string()))?;
        desc.camera = Some(camera);
    }
    if doc.animations().len() > 0 {
        warn(&mut warnings, "animations", "animations are ignored; the static pose is loaded".into());
    }
    if desc.meshes.is_empty() {
        warn(&mut warnings, "scene", "no triangle mesh was loaded".into());
    }
    Ok(LoadedScene { description: desc, warnings })
}

/// The scene `wanted` names: a scene's `name`, else its index. The error lists the scenes.
fn choose_scene<'a>(doc: &'a ::gltf::Document, wanted: &str) -> Result<::gltf::Scene<'a>, String> {
    if let Some(s) = doc.scenes().find(|s| s.name() == Some(wanted)) {
        return Ok(s);
    }
    if let Some(s) = wanted.parse::<usize>().ok().and_then(|i| doc.scenes().nth(i)) {
        return Ok(s);
    }
    let list: Vec<String> = doc
        .scenes()
        .map(|s| match s.name() {
            Some(n) => format!("{} ({n:?})", s.index()),
            None => s.index().to_string(),
        })
        .collect();
    Err(if list.is_empty() {
        "no scene of that name or index: the file has no scenes".to_string()
    } else {
        format!("no scene of that name or index (the file's scenes: {})", list.join(", "))
    })
}

/// How a camera can be named: its node's name and the camera's own name, quoted.
fn camera_names(node: &::gltf::Node<'_>, cam: &::gltf::Camera<'_>) -> String {
    match (node.name(), cam.name()) {
        (Some(n), Some(c)) if n != c => format!("{n:?} (camera {c:?})"),
        (Some(n), _) => format!("{n:?}"),
        (None, Some(c)) => format!("{c:?}"),
        (None, None) => format!("node {} (unnamed)", node.index()),
    }
}

fn node_element(node: &::gltf::Node<'_>) -> String {
    match node.name() {
        Some(n) => format!("node {} ({n:?})", node.index()),
        None => format!("node {}", node.index()),
    }
}
