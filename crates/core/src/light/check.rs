//! The physical constraints on a light's parameters, each written once: what
//! [`crate::scene::Scene::build`] checks every light with, and what loaders call to report a bad
//! value at its place in the file ([`LightError`] says what is wrong; the loader adds where).
//! Also the photometric conversion lumens → watts, which has constraints of its own.

use super::ProfileError;
use crate::math::{Frame, Rgb, Vec3};
use glam::DVec3;

/// Luminous efficacy used to convert lumens and candela to watts: 683 lm/W (555 nm).
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Why a light's parameters are impossible (the light's name and place are the caller's).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LightError {
    /// An emitted radiance, intensity or irradiance is negative or not finite.
    #[error("emission {0:?} must be finite and non-negative")]
    Emission([f32; 3]),
    /// A power is negative or not finite.
    #[error("power {0:?} W must be finite and non-negative")]
    Power([f32; 3]),
    /// A luminous flux is negative or not finite.
    #[error("lumens {0} must be finite and non-negative")]
    Lumens(f32),
    /// Lumens were given for a colour without luminance (black, or not finite).
    #[error("lumens need a colour of non-zero luminance, not {0:?}")]
    NoLuminance([f32; 3]),
    /// A position is not finite.
    #[error("position {0:?} is not finite")]
    Position([f32; 3]),
    /// A direction or axis is zero or not finite.
    #[error("direction {0:?} is zero or not finite")]
    Direction([f32; 3]),
    /// An area light's tangent is zero or not finite.
    #[error("emission tangent {0:?} must be finite and non-zero")]
    Tangent([f32; 3]),
    /// A point light's orientation is not (close to) an orthonormal frame.
    #[error("orientation {0:?} is not a finite orthonormal frame")]
    Orientation(Frame),
    /// An impossible emission profile.
    #[error(transparent)]
    Profile(#[from] ProfileError),
    /// A light's power (from its emission and its size) is not a finite number of watts, or
    /// the sum of its channels is not: its paths would carry infinite flux.
    #[error(
        "its power {0:?} W (from its emission and size) is not a finite number: the emission or the emitter is too large"
    )]
    PowerNotFinite([f32; 3]),
    /// A power given for an area light without area.
    #[error("power {0:?} W on an emitter of zero area")]
    PowerWithoutArea([f32; 3]),
    /// A power given for an area light whose profile emits nothing into its front hemisphere.
    #[error(
        "power {0:?} W cannot be reached: the emission profile carries no flux into the front hemisphere"
    )]
    PowerUnreachable([f32; 3]),
    /// An environment map that cannot emit: no texels, a texel negative or not finite, a bad
    /// scale (the message says which).
    #[error("environment map: {0}")]
    Map(String),
    /// A textured area light's triangles cover more cells of its texture than its power may
    /// be integrated over.
    #[error(
        "its radiance texture repeats too often over the emitter (more than {0} texture cells) for its power to be computed"
    )]
    TextureTooFine(u64),
    /// A `mesh_attribute` radiance on a mesh without that attribute.
    #[error("its radiance is the mesh attribute \"{0}\", which the shape does not have")]
    TextureAttribute(String),
    /// A textured area light on a mesh without texture coordinates.
    #[error("its radiance is a texture, but the shape has no texture coordinates (UVs)")]
    TextureWithoutUvs,
    /// A texture on a point light that cannot project it (the message says why).
    #[error("{0}")]
    SpotTexture(&'static str),
    /// An environment's frame is not a rotation.
    #[error("the environment's frame {0:?} (columns) is not a rotation")]
    EnvironmentFrame([f32; 9]),
}

fn finite_non_negative(c: Rgb) -> bool {
    c.is_finite() && c.min_element() >= 0.0
}

/// An emitted radiance (W/(m²·sr)), intensity (W/sr) or irradiance (W/m²): finite and
/// non-negative.
pub fn check_emission(value: Rgb) -> Result<Rgb, LightError> {
    if finite_non_negative(value) { Ok(value) } else { Err(LightError::Emission(value.to_array())) }
}

/// A power Φ (W per channel): finite and non-negative.
pub fn check_power(value: Rgb) -> Result<Rgb, LightError> {
    if finite_non_negative(value) { Ok(value) } else { Err(LightError::Power(value.to_array())) }
}

/// A light's position: finite.
pub fn check_position(p: Vec3) -> Result<Vec3, LightError> {
    if p.is_finite() { Ok(p) } else { Err(LightError::Position(p.to_array())) }
}

/// The unit direction of `d` (single precision, as a scene description holds it): an error if
/// it is zero or not finite.
pub fn unit_direction(d: Vec3) -> Result<Vec3, LightError> {
    let u = d.normalize_or_zero();
    if u.is_finite() && u != Vec3::ZERO { Ok(u) } else { Err(LightError::Direction(d.to_array())) }
}

/// The unit axis of `d` in double precision (how loaders carry transformed axes): an error if
/// it is zero or not finite.
pub fn unit_axis(d: DVec3) -> Result<DVec3, LightError> {
    if d.is_finite() && d.length() > 0.0 {
        Ok(d.normalize())
    } else {
        Err(LightError::Direction(d.as_vec3().to_array()))
    }
}

/// An area light's tangent, normalised: an error if it is zero or not finite.
pub fn unit_tangent(t: Vec3) -> Result<Vec3, LightError> {
    if t.is_finite() && t.length() > 0.0 { Ok(t.normalize()) } else { Err(LightError::Tangent(t.to_array())) }
}

/// `f` re-orthonormalised (Gram–Schmidt from its z axis), if it is finite and close to
/// orthonormal (within 10⁻³).
pub fn check_orientation(f: Frame) -> Result<Frame, LightError> {
    let ok = [f.s, f.t, f.n].iter().all(|v| v.is_finite() && (v.length() - 1.0).abs() < 1e-3)
        && f.s.dot(f.t).abs() < 1e-3
        && f.s.dot(f.n).abs() < 1e-3
        && f.t.dot(f.n).abs() < 1e-3;
    if !ok {
        return Err(LightError::Orientation(f));
    }
    let n = f.n.normalize();
    let s = (f.s - n * f.s.dot(n)).normalize();
    Ok(Frame { s, t: n.cross(s), n })
}

/// Watts per channel of an RGB light of `colour` and luminous flux `lumens`: the colour is scaled
/// so that 683·luminance(Φ) = lumens, with luminance = 0.2126 R + 0.7152 G + 0.0722 B. A white
/// (1, 1, 1) light of 683 lm has Φ = 1 W per channel. An error if `lumens` is negative or not
/// finite, or the colour has no luminance.
pub fn lumens_to_watts(lumens: f32, colour: Vec3) -> Result<Vec3, LightError> {
    if !(lumens.is_finite() && lumens >= 0.0) {
        return Err(LightError::Lumens(lumens));
    }
    let y = crate::math::luminance(colour);
    if y > 0.0 && y.is_finite() {
        Ok(colour * (lumens / (LUMENS_PER_WATT * y)))
    } else {
        Err(LightError::NoLuminance(colour.to_array()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_constraint_names_the_bad_value() {
        assert_eq!(check_emission(Rgb::new(1.0, -1.0, 0.0)), Err(LightError::Emission([1.0, -1.0, 0.0])));
        assert!(check_emission(Rgb::splat(f32::NAN)).is_err() && check_emission(Rgb::ZERO).is_ok());
        assert!(check_power(Rgb::splat(f32::INFINITY)).unwrap_err().to_string().starts_with("power [inf"));
        assert!(check_position(Vec3::new(0.0, f32::NAN, 0.0)).is_err());
        assert_eq!(unit_direction(Vec3::new(0.0, -3.0, 0.0)), Ok(Vec3::NEG_Y));
        assert_eq!(unit_direction(Vec3::ZERO), Err(LightError::Direction([0.0; 3])));
        assert_eq!(unit_axis(DVec3::new(0.0, -3.0, 0.0)), Ok(DVec3::NEG_Y));
        assert!(unit_axis(DVec3::splat(f64::NAN)).is_err());
        assert_eq!(unit_tangent(Vec3::new(0.0, 2.0, 0.0)), Ok(Vec3::Y));
        assert!(unit_tangent(Vec3::ZERO).unwrap_err().to_string().contains("tangent"));
        let skew = Frame { s: Vec3::X, t: Vec3::X, n: Vec3::Z };
        assert!(check_orientation(skew).unwrap_err().to_string().contains("orthonormal"));
        assert_eq!(lumens_to_watts(683.0, Vec3::ONE), Ok(Vec3::ONE));
        assert_eq!(lumens_to_watts(-1.0, Vec3::ONE), Err(LightError::Lumens(-1.0)));
        assert_eq!(lumens_to_watts(1.0, Vec3::ZERO), Err(LightError::NoLuminance([0.0; 3])));
    }
}
