//! `<emitter>` elements: the area emitter of a shape, and the top-level point, spot, IES,
//! directional and environment (`constant`, `envmap`; the Radiance skies `gensky`, `gendaylit`
//! and the CIE general skies `ciesky` in `sky.rs`) lights. [`TOP_EMITTERS`] maps each supported top-level type to its builder (which
//! adds the light to the scene) and [`SHAPE_EMITTERS`] names the ones a shape holds; adding an
//! emitter type is an entry there and its function.
//!
//! Three rules keep the core's light model in one place here:
//! * a mesh's emission fields are filled by [`set_area_emission`] only;
//! * every physical check of a value read is the core's (`light::check`, the profiles'
//!   constructors, [`DirectionalLightDesc::new`], [`axis_frame`]), its error placed at the
//!   element that gave the value;
//! * `filename`/`scale` (an IES file) and `power`/`lumens` are read by one function each
//!   ([`ies_file`], [`power_or_lumens`]) for the area and the `ies` emitters.

use super::Result;
use super::build::Builder;
use super::properties::Props;
use super::transform::Transform;
use super::xml::Element;
use crate::scene_formats::lights;
use crate::texture_file::read_texture_within;
use glam::{DMat3, DVec3};
use opticks_core::light::check::{check_emission, check_power, unit_tangent};
use opticks_core::light::{
    EmissionProfile, IesProfile, LatLong, LightError, ProfileError, axis_frame, lumens_to_watts,
};
use opticks_core::math::{Frame, Mat3, Rgb, Vec3};
use opticks_core::scene::{
    AreaEmission, DirectionalLightDesc, EnvironmentLightDesc, EnvironmentRadiance, MeshDesc, PointLightDesc,
};
use std::path::PathBuf;

/// A top-level emitter builder: the element, its type and its name (its `id`, else
/// `<type>_<index>`); adds the light to `Builder::desc`.
type BuildEmitter = for<'d> fn(&mut Builder<'d>, &'d Element, &str, String) -> Result<()>;

/// The emitter types supported at the top level, in the order the error message lists them.
const TOP_EMITTERS: &[(&str, BuildEmitter)] = &[
    ("point", point),
    ("spot", spot),
    ("directional", directional),
    ("ies", ies),
    ("constant", constant),
    ("envmap", envmap),
    ("gensky", super::sky::gensky),
    ("gendaylit", super::sky::gendaylit),
    ("ciesky", super::sky::ciesky),
];

/// The top-level emitters that light the scene from infinity (named in the error of one
/// nested in a shape).
const INFINITE_EMITTERS: &[&str] = &["constant", "envmap", "directional", "gensky", "gendaylit", "ciesky"];

/// The emitter types supported inside a `<shape>`.
const SHAPE_EMITTERS: &[&str] = &["area"];

/// Makes `mesh` the area light `emission` describes (or no light): the one place a mesh's
/// emission is set.
pub fn set_area_emission(mesh: &mut MeshDesc, emission: Option<AreaEmission>) {
    mesh.emission = emission;
}

/// A top-level `<emitter>`, added to the scene; `index` counts the top-level emitters (for the
/// default name).
pub fn top_emitter<'d>(b: &mut Builder<'d>, e: &'d Element, index: usize) -> Result<()> {
    let ty = e.required("type")?;
    if let Some((_, build)) = TOP_EMITTERS.iter().find(|(n, _)| *n == ty) {
        let name = e.attr("id")?.map_or_else(|| format!("{ty}_{index}"), str::to_string);
        return build(b, e, ty, name);
    }
    if SHAPE_EMITTERS.contains(&ty) {
        if e.attr("id")?.is_some() {
            return Ok(()); // built where a shape refers to it
        }
        return Err(e.err(format!(
            "an {ty} emitter must be nested inside a <shape> (or have an id a shape refers to)"
        )));
    }
    let top: Vec<&str> = TOP_EMITTERS.iter().map(|(n, _)| *n).collect();
    Err(e.attr_err(
        "type",
        format!(
            "unsupported emitter type \"{ty}\" (supported: {} at the top level, {} inside a shape)",
            top.join(", "),
            SHAPE_EMITTERS.join(", ")
        ),
    ))
}

/// A shape's `<emitter type="area">`: `radiance`, and the Opticks extensions `exponent` (a cosⁿ
/// emitter, `radiance` along the normal), `filename` (an IES profile, `radiance` a colour
/// scale), `tangent` (the profile's horizontal 0°) and `power`/`lumens`.
pub fn area_emitter<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<AreaEmission> {
    let ty = e.required("type")?;
    if INFINITE_EMITTERS.contains(&ty) {
        return Err(e.attr_err(
            "type",
            format!(
                "a {ty} emitter lights the scene from infinity and cannot be nested inside a shape: \
                 declare it at the top level"
            ),
        ));
    }
    if !SHAPE_EMITTERS.contains(&ty) {
        return Err(e.attr_err(
            "type",
            format!(
                "unsupported emitter type \"{ty}\" inside a shape (supported: {})",
                SHAPE_EMITTERS.join(", ")
            ),
        ));
    }
    let mut p = Props::of(e)?;
    // A texture as the radiance (the light's sampling and power follow it: the core's
    // `light::area` module docs); the shape must have texture coordinates (the scene checks).
    let texture = match p.take_object("radiance") {
        Some(t) => Some(super::texture::emitter_radiance(b, &mut p, t)?),
        None => None,
    };
    if let Some(c) = p.objects().first() {
        return Err(
            c.err("unsupported element inside an area emitter (its `radiance` is an <rgb> or a <texture>)")
        );
    }
    let radiance = match texture {
        Some(_) => Rgb::ONE, // the texture's values are the radiance
        None => {
            let (radiance, node) = p.color_or("radiance", Rgb::ONE)?;
            check_emission(radiance).map_err(|e| node.err(e.to_string()))?;
            radiance
        }
    };
    let exponent = p.float("exponent")?;
    let ies = ies_file(b, &mut p, true)?;
    let (profile, colour, default_power) = match (exponent, ies) {
        (Some(_), Some((_, _, fnode))) => {
            return Err(fnode.err("give either `exponent` or `filename`, not both"));
        }
        (Some((x, enode)), None) => {
            let profile = EmissionProfile::cosine_power(x as f32).map_err(|e| enode.err(e.to_string()))?;
            (Some(profile), radiance, None)
        }
        (None, Some((ies, scale, _))) => {
            let colour = radiance * scale;
            (Some(EmissionProfile::Ies(ies.profile)), colour, Some(colour * ies.watts))
        }
        (None, None) => (None, radiance, None),
    };
    let tangent = match p.point("tangent")? {
        Some((t, tnode)) => {
            unit_tangent(t.as_vec3()).map_err(|e| tnode.err(e.to_string()))?;
            Some(t.as_vec3())
        }
        None => None,
    };
    let power = power_or_lumens(&mut p, colour, "radiance")?.or(default_power);
    b.finish(&p);
    Ok(AreaEmission { radiance: colour, profile, tangent, power, texture })
}

/// `point`: `position` (or the translation of `to_world`) and `intensity`.
fn point<'d>(b: &mut Builder<'d>, e: &'d Element, ty: &str, name: String) -> Result<()> {
    let mut p = Props::of(e)?;
    no_objects(&p, ty)?;
    let position = match point_or_to_world(&mut p, "position")? {
        Placement::Given(pos, _) => pos,
        Placement::ToWorld(t, _) => t.matrix.transform_point3(DVec3::ZERO),
        Placement::Default => DVec3::ZERO,
    };
    let (intensity, inode) = p.color_or("intensity", Rgb::ONE)?;
    check_emission(intensity).map_err(|e| inode.err(e.to_string()))?;
    b.finish(&p);
    let light = PointLightDesc {
        name,
        source: Builder::source(e),
        position: position.as_vec3(),
        intensity,
        ..Default::default()
    };
    b.desc.point_lights.push(light);
    Ok(())
}

/// `spot`: an oriented point light with Mitsuba's linear falloff in angle between `beam_width`
/// and `cutoff_angle`, optionally projecting a `texture` (the core's `light::spot_texture`; its
/// `cutoff_angle` must be below 90°, its `to_world` a rotation and uniform scale).
fn spot<'d>(b: &mut Builder<'d>, e: &'d Element, ty: &str, name: String) -> Result<()> {
    let mut p = Props::of(e)?;
    let texture = match p.take_object("texture") {
        Some(t) => Some((super::texture::spot_texture(b, &mut p, t)?, t)),
        None => None,
    };
    let (mut light, similar) = oriented_point_light(e, ty, name, &mut p)?;
    let (cutoff, cnode) = p.float_or("cutoff_angle", 20.0)?;
    if let Some((t, tnode)) = texture {
        if cutoff >= 90.0 {
            return Err(cnode
                .err(format!("a spot projecting a texture needs a cutoff_angle below 90° (got {cutoff}°)")));
        }
        if !similar {
            return Err(tnode.err(
                "a spot projecting a texture needs a to_world that is a rotation (and a uniform \
                 scale): no mirror, shear or non-uniform scale",
            ));
        }
        light.texture = Some(t);
    }
    let (beam, bnode) = p.float_or("beam_width", cutoff * 0.75)?;
    let cone = EmissionProfile::spot(cutoff.to_radians() as f32, beam.to_radians() as f32);
    light.profile = Some(cone.map_err(|e| match e {
        ProfileError::Beam { .. } => bnode.err(e.to_string()),
        _ => cnode.err(e.to_string()),
    })?);
    b.finish(&p);
    b.desc.point_lights.push(light);
    Ok(())
}

/// `ies` (Opticks extension): an oriented point light with an IES file's candela distribution.
fn ies<'d>(b: &mut Builder<'d>, e: &'d Element, ty: &str, name: String) -> Result<()> {
    let mut p = Props::of(e)?;
    let (mut light, _) = oriented_point_light(e, ty, name, &mut p)?;
    let (ies, scale, _) =
        ies_file(b, &mut p, false)?.ok_or_else(|| e.err("an ies emitter needs a `filename`"))?;
    light.intensity *= scale;
    light.power = power_or_lumens(&mut p, light.intensity, "intensity")?;
    light.profile = Some(EmissionProfile::Ies(ies.profile));
    light.ies_file = Some(ies.path);
    b.finish(&p);
    b.desc.point_lights.push(light);
    Ok(())
}

/// What `spot` and `ies` share: a point light at M·(0,0,0) of `to_world` with its frame, and
/// `intensity`; and whether M's 3 × 3 part is a rotation times a uniform scale (what a
/// projected texture needs for its frame to be M's).
fn oriented_point_light<'d>(
    e: &'d Element,
    ty: &str,
    name: String,
    p: &mut Props<'d>,
) -> Result<(PointLightDesc, bool)> {
    no_objects(p, ty)?;
    let ((frame, position), similar) = match p.transform("to_world")? {
        Some((t, tnode)) => {
            let m = DMat3::from_mat4(t.matrix);
            let k = m.determinant().cbrt();
            let mtm = m.transpose() * m / (k * k);
            let similar = k > 0.0 && (mtm - DMat3::IDENTITY).to_cols_array().iter().all(|x| x.abs() < 1e-4);
            (emitter_frame(&t, tnode)?, similar)
        }
        None => ((Frame { s: Vec3::X, t: Vec3::Y, n: Vec3::Z }, DVec3::ZERO), true),
    };
    let (intensity, inode) = p.color_or("intensity", Rgb::ONE)?;
    check_emission(intensity).map_err(|e| inode.err(e.to_string()))?;
    let light = PointLightDesc {
        name,
        source: Builder::source(e),
        position: position.as_vec3(),
        intensity,
        orientation: Some(frame),
        ..Default::default()
    };
    Ok((light, similar))
}

/// `directional`: `irradiance` along `direction` (or M·(0,0,1) of `to_world`).
fn directional<'d>(b: &mut Builder<'d>, e: &'d Element, ty: &str, name: String) -> Result<()> {
    let mut p = Props::of(e)?;
    no_objects(&p, ty)?;
    let (direction, dnode) = match point_or_to_world(&mut p, "direction")? {
        Placement::Given(d, dnode) => (d, Some(dnode)),
        Placement::ToWorld(t, tnode) => (emitter_frame(&t, tnode)?.0.n.as_dvec3(), None),
        Placement::Default => (DVec3::Z, None),
    };
    let (irradiance, inode) = p.color_or("irradiance", Rgb::ONE)?;
    b.finish(&p);
    let light =
        DirectionalLightDesc::new(name, Builder::source(e), direction, irradiance).map_err(|e| {
            match (&e, dnode) {
                (LightError::Direction(_), Some(dnode)) => dnode.err(e.to_string()),
                _ => inode.err(e.to_string()),
            }
        })?;
    b.desc.directional_lights.push(light);
    Ok(())
}

/// `constant`: `radiance` (a colour or spectrum, default 1) from every direction.
fn constant<'d>(b: &mut Builder<'d>, e: &'d Element, ty: &str, name: String) -> Result<()> {
    let mut p = Props::of(e)?;
    no_objects(&p, ty)?;
    let (radiance, node) = p.color_or("radiance", Rgb::ONE)?;
    check_emission(radiance).map_err(|e| node.err(e.to_string()))?;
    b.finish(&p);
    b.desc.environment_lights.push(EnvironmentLightDesc {
        name,
        source: Builder::source(e),
        radiance: EnvironmentRadiance::Constant(radiance),
        to_world: Mat3::IDENTITY,
        sky: None,
    });
    Ok(())
}

/// `envmap`: the lat-long image `filename` (EXR, HDR, PNG, JPEG; relative to the XML file's
/// folder; 8-bit formats sRGB-decoded as Mitsuba does), times `scale`, in the frame of
/// `to_world` (a rotation, possibly mirrored; its translation is irrelevant). Mitsuba's
/// `mis_compensation` changes only its sampling and is accepted and ignored.
fn envmap<'d>(b: &mut Builder<'d>, e: &'d Element, ty: &str, name: String) -> Result<()> {
    let mut p = Props::of(e)?;
    no_objects(&p, ty)?;
    let (file, fnode) = p.string("filename")?.ok_or_else(|| e.err("an envmap emitter needs a `filename`"))?;
    let (scale, snode) = p.float_or("scale", 1.0)?;
    check_emission(Rgb::splat(scale as f32))
        .map_err(|_| snode.err(format!("`scale` {scale} must be finite and non-negative")))?;
    let to_world = match p.transform("to_world")? {
        Some((t, tnode)) => environment_frame(&t, tnode)?,
        None => Mat3::IDENTITY,
    };
    p.bool("mis_compensation")?;
    let path = b.doc.resolve(fnode, &file);
    let image = read_texture_within(&path, false, b.doc.limits.max_texels)
        .map_err(|m| fnode.attr_err("value", format!("{}: {m}", path.display())))?;
    // The core's check of the texels, reported at the file (e.g. a negative EXR value).
    LatLong::new(image.width, image.height, &image.texels, scale as f32)
        .map_err(|m| fnode.attr_err("value", format!("{}: {m}", path.display())))?;
    b.finish(&p);
    b.desc.environment_lights.push(EnvironmentLightDesc {
        name,
        source: Builder::source(e),
        radiance: EnvironmentRadiance::Map {
            width: image.width,
            height: image.height,
            texels: image.texels,
            scale: scale as f32,
            file: Some(path.canonicalize().unwrap_or(path)),
        },
        to_world,
        sky: None,
    });
    Ok(())
}

/// The rotation of an environment's `to_world` (its 3 × 3 part must be orthonormal: Mitsuba's
/// lookup of a scaled or sheared frame is not a map of directions; a `<rotate>` with an axis
/// that is not unit length is one, since Mitsuba does not normalise it).
pub(super) fn environment_frame(t: &Transform, tnode: &Element) -> Result<Mat3> {
    let m = DMat3::from_mat4(t.matrix);
    let orthonormal = (m.transpose() * m - DMat3::IDENTITY).to_cols_array().iter().all(|x| x.abs() < 1e-4);
    if !orthonormal {
        return Err(tnode.err(
            "the to_world of an environment must be a rotation (no scale or shear; \
             a <rotate> axis must have unit length)",
        ));
    }
    Ok(m.as_mat3())
}

/// Where a point or directional light is: given by a point/vector property, by `to_world`, or
/// neither (the default); each with the element it came from.
enum Placement<'d> {
    Given(DVec3, &'d Element),
    ToWorld(Transform, &'d Element),
    Default,
}

/// The point/vector property `name` or `to_world`, at most one of them.
fn point_or_to_world<'d>(p: &mut Props<'d>, name: &str) -> Result<Placement<'d>> {
    let given = p.point(name)?;
    let to_world = p.transform("to_world")?;
    match (given, to_world) {
        (Some(_), Some((_, tnode))) => {
            Err(tnode.err(format!("give either `{name}` or `to_world`, not both")))
        }
        (Some((v, vnode)), None) => Ok(Placement::Given(v, vnode)),
        (None, Some((t, tnode))) => Ok(Placement::ToWorld(t, tnode)),
        (None, None) => Ok(Placement::Default),
    }
}

/// An error unless the emitter of type `ty` has no nested elements.
pub(super) fn no_objects(p: &Props, ty: &str) -> Result<()> {
    match p.objects().first() {
        Some(c) => Err(c.err(format!("unsupported element inside a {ty} emitter"))),
        None => Ok(()),
    }
}

/// An IES file's photometric grid and the flux it carries, W per unit colour.
struct Ies {
    profile: IesProfile,
    watts: f32,
    /// The file it was read from (kept on point lights, for writers).
    path: PathBuf,
}

/// An IES emitter's `filename` (relative to the XML file's folder) and `scale`, if a
/// `filename` is given: the file, checked (as an area light's profile, cut at 90°, if
/// `hemisphere`), with the flux its candela distribution carries (in W: lumens/683), the scale
/// and the `filename` element. Warns when the file's rated lumens differ from that flux.
fn ies_file<'d>(
    b: &mut Builder<'d>,
    p: &mut Props<'d>,
    hemisphere: bool,
) -> Result<Option<(Ies, f32, &'d Element)>> {
    let Some((file, fnode)) = p.string("filename")? else { return Ok(None) };
    let path = b.doc.resolve(fnode, &file);
    let ies = lights::ies_luminaire(&path, hemisphere).map_err(|e| fnode.err(e.to_string()))?;
    if let Some(w) = ies.warning {
        b.warn(fnode, w);
    }
    let scale = match p.float("scale")? {
        Some((scale, snode)) => {
            check_emission(Rgb::splat(scale as f32)).map_err(|e| snode.err(e.to_string()))?;
            scale as f32
        }
        None => 1.0,
    };
    let path = path.canonicalize().unwrap_or(path); // absolute, for writers
    Ok(Some((Ies { profile: ies.profile, watts: ies.watts, path }, scale, fnode)))
}

/// An emitter's `power` (W per channel) or `lumens` (converted keeping the colour `colour`,
/// the value of the parameter `colour_name`), at most one of them; `None` if neither.
fn power_or_lumens(p: &mut Props, colour: Rgb, colour_name: &str) -> Result<Option<Rgb>> {
    let power = p.color("power")?;
    let lumens = p.float("lumens")?;
    match (power, lumens) {
        (Some(_), Some((_, lnode))) => Err(lnode.err("give either `power` or `lumens`, not both")),
        (Some((w, pnode)), None) => {
            check_power(w).map_err(|e| pnode.err(e.to_string()))?;
            Ok(Some(w))
        }
        (None, Some((lm, lnode))) => lumens_to_watts(lm as f32, colour).map(Some).map_err(|e| match e {
            LightError::NoLuminance(_) => {
                lnode.err(format!("`lumens` needs the `{colour_name}` colour to have non-zero luminance"))
            }
            e => lnode.err(e.to_string()),
        }),
        (None, None) => Ok(None),
    }
}

/// The frame of an emitter's `to_world`: z = M·(0,0,1) (the axis), x = M·(1,0,0) made
/// perpendicular; and the position M·(0,0,0). A zero axis is an error at `tnode`.
fn emitter_frame(t: &Transform, tnode: &Element) -> Result<(Frame, DVec3)> {
    let m = t.matrix;
    let frame = axis_frame(m.transform_vector3(DVec3::Z), m.transform_vector3(DVec3::X))
        .map_err(|_| tnode.err("to_world maps the emitter's axis (0, 0, 1) to zero"))?;
    Ok((frame, m.transform_point3(DVec3::ZERO)))
}
