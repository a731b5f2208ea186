//! Light conversions shared by the scene loaders (Mitsuba, VRML97, glTF): a spot light's profile
//! and frame, an IES luminaire file, and a directional light, built and checked once so every format maps its fields to
//! the same core lights. Each loader turns a [`LightError`] into its own located message (with
//! its own field names and units).

use glam::DVec3;
use opticks_core::light::EmissionProfile;
use opticks_core::math::{Frame, Rgb};
use opticks_core::scene::{DirectionalLightDesc, PointLightDesc, Source};

/// What is wrong with a light's parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightError {
    /// The cutoff angle is not in (0, π].
    Cutoff,
    /// The beam width is not in (0, cutoff].
    Beam,
    /// The axis or direction is zero or not finite.
    Axis,
    /// The intensity or irradiance is negative or not finite.
    Negative,
}

/// An IES (LM-63) file read and checked as a light's profile: its candela grid, the flux that
/// distribution carries (W per unit colour: lumens/683) and, when the file's rated lumens
/// differ from that flux by more than 5 %, a warning saying so.
pub struct IesLuminaire {
    /// The photometric grid.
    pub profile: opticks_core::light::IesProfile,
    /// Flux of the candela distribution, W (into the front hemisphere if built so).
    pub watts: f32,
    /// The rated-lumens mismatch, if any, as a message for the loader to place.
    pub warning: Option<String>,
}

/// Reads the IES file at `path` and builds it as a point light's profile, or an area light's
/// (cut at 90°) if `hemisphere`. The error message names the IES file (and its line).
pub fn ies_luminaire(path: &std::path::Path, hemisphere: bool) -> Result<IesLuminaire, String> {
    let ies = crate::ies::load_ies(path).map_err(|e| e.to_string())?;
    let built =
        opticks_core::light::BuiltProfile::build(&EmissionProfile::Ies(ies.profile.clone()), hemisphere)
            .map_err(|e| format!("{}: {e}", path.display()))?;
    let watts = built.integral();
    let warning = ies.rated_lumens().and_then(|rated| {
        let actual = watts * opticks_core::light::LUMENS_PER_WATT;
        let part = if hemisphere { " into the front hemisphere (an area light is one-sided)" } else { "" };
        ((actual / rated - 1.0).abs() > 0.05).then(|| {
            format!(
                "the file rates {rated} lm but its candela distribution carries {actual:.1} lm{part}; \
                 the distribution's flux is used"
            )
        })
    });
    Ok(IesLuminaire { profile: ies.profile, watts, warning })
}

/// The core's spot profile: full intensity within `beam` of the axis, falling linearly in angle
/// to zero at `cutoff` (radians, 0 < beam ≤ cutoff ≤ π) — Mitsuba's `spot` and VRML97's
/// `SpotLight` alike.
pub fn spot_profile(cutoff: f64, beam: f64) -> Result<EmissionProfile, LightError> {
    if !(cutoff > 0.0 && cutoff <= std::f64::consts::PI) {
        return Err(LightError::Cutoff);
    }
    if !(beam > 0.0 && beam <= cutoff) {
        return Err(LightError::Beam);
    }
    Ok(EmissionProfile::Spot { cutoff_angle: cutoff as f32, beam_width: beam as f32 })
}

/// The frame of a light whose axis is `axis` (z), with x as close to `x` as possible
/// (perpendicular to the axis; any perpendicular if `x` is parallel to it).
pub fn axis_frame(axis: DVec3, x: DVec3) -> Result<Frame, LightError> {
    if !axis.is_finite() || axis.length() <= 0.0 {
        return Err(LightError::Axis);
    }
    let n = axis.normalize();
    let s = x - n * x.dot(n);
    let s = if s.is_finite() && s.length() > 1e-9 * x.length().max(1e-300) {
        s.normalize()
    } else {
        Frame::from_normal(n.as_vec3()).s.as_dvec3()
    };
    Ok(Frame { s: s.as_vec3(), t: n.cross(s).as_vec3(), n: n.as_vec3() })
}

/// A spot light at `position` shining along `axis` with `intensity` W/sr on the axis.
pub fn spot_light(
    name: String,
    source: Source,
    position: DVec3,
    axis: DVec3,
    intensity: Rgb,
    cutoff: f64,
    beam: f64,
) -> Result<PointLightDesc, LightError> {
    check_colour(intensity)?;
    Ok(PointLightDesc {
        name,
        source,
        position: position.as_vec3(),
        intensity,
        profile: Some(spot_profile(cutoff, beam)?),
        orientation: Some(axis_frame(axis, DVec3::X)?),
        power: None,
        ies_file: None,
    })
}

/// A directional (sun) light travelling along `direction` with `irradiance` W/m² on a plane
/// perpendicular to it.
pub fn directional_light(
    name: String,
    source: Source,
    direction: DVec3,
    irradiance: Rgb,
) -> Result<DirectionalLightDesc, LightError> {
    check_colour(irradiance)?;
    if !direction.is_finite() || direction.length() <= 0.0 {
        return Err(LightError::Axis);
    }
    Ok(DirectionalLightDesc { name, source, direction: direction.normalize().as_vec3(), irradiance })
}

fn check_colour(c: Rgb) -> Result<(), LightError> {
    if c.is_finite() && c.min_element() >= 0.0 { Ok(()) } else { Err(LightError::Negative) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spot_checks_its_angles_and_frames_its_axis() {
        assert!(spot_profile(0.5, 0.5).is_ok());
        assert_eq!(spot_profile(0.0, 0.0), Err(LightError::Cutoff));
        assert_eq!(spot_profile(4.0, 1.0), Err(LightError::Cutoff));
        assert_eq!(spot_profile(0.5, 0.6), Err(LightError::Beam));
        assert_eq!(spot_profile(f64::NAN, 0.1), Err(LightError::Cutoff));
        let f = axis_frame(DVec3::new(0.0, 0.0, -2.0), DVec3::X).unwrap();
        assert_eq!(f.n, glam::Vec3::NEG_Z);
        assert_eq!(f.s, glam::Vec3::X);
        let f = axis_frame(DVec3::X, DVec3::X).unwrap();
        assert!(f.s.dot(f.n).abs() < 1e-6 && (f.s.length() - 1.0).abs() < 1e-6);
        assert_eq!(axis_frame(DVec3::ZERO, DVec3::X), Err(LightError::Axis));
        let s = Source::default();
        assert_eq!(
            spot_light("s".into(), s.clone(), DVec3::ZERO, DVec3::Z, Rgb::splat(-1.0), 0.5, 0.5),
            Err(LightError::Negative)
        );
        let d = directional_light("d".into(), s, DVec3::new(0.0, -3.0, 0.0), Rgb::ONE).unwrap();
        assert_eq!(d.direction, glam::Vec3::NEG_Y);
    }
}
