//! A step of the glTF pipeline: a node's `KHR_lights_punctual` light converted to a point, spot
//! or directional light of the scene (see the table in the module docs of [`super`]).

use super::Report;
use super::nodes::node_element;
use crate::scene_formats::SceneFileError;
use ::gltf::khr_lights_punctual::Kind;
use opticks_core::light::check::check_emission;
use opticks_core::light::{LUMENS_PER_WATT, LightError};
use opticks_core::math::{Mat4, Rgb, Vec3};
use opticks_core::scene::{DirectionalLightDesc, PointLightDesc, SceneDescription};

/// The narrowest full-intensity cone of a glTF spot, as a fraction of its outer cone (the core's
/// spot needs a positive beam; glTF allows `innerConeAngle` 0).
pub const SPOT_MIN_BEAM: f64 = 1e-3;

/// Adds the light of `node` (placed by `m`), if it has one, to `desc`. A value the core refuses
/// is an error in the core's words, at the light.
pub(super) fn add_node_light(
    node: &::gltf::Node<'_>,
    m: Mat4,
    desc: &mut SceneDescription,
    report: &Report,
) -> Result<(), SceneFileError> {
    let Some(light) = node.light() else { return Ok(()) };
    let lname = light.name().map_or_else(|| format!("light {}", light.index()), str::to_string);
    let bad = |e: LightError| report.invalid(format!("{}: {lname}", node_element(node)), e.to_string());
    let source = report.source();
    // glTF gives candela (point, spot) or lux (directional): ÷ 683 is W/sr or W/m².
    let [r, g, b] = light.color();
    let amount = Rgb::new(r, g, b) * (light.intensity() / LUMENS_PER_WATT);
    let (position, axis) = (m.transform_point3(Vec3::ZERO), m.transform_vector3(Vec3::NEG_Z));
    match light.kind() {
        Kind::Point => {
            desc.point_lights.push(PointLightDesc {
                name: lname.clone(),
                source,
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
                source,
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
                DirectionalLightDesc::new(lname.clone(), source, axis.as_dvec3(), amount).map_err(bad)?;
            desc.directional_lights.push(sun);
        }
    }
    Ok(())
}
