//! VRML97 lights → the core's lights: `PointLight`, `SpotLight` and `DirectionalLight`, and the
//! extension's `PhysicalPointLight`, `PhysicalSpotLight` and `PhysicalDirectionalLight` (in
//! W/sr, W or W/m²; a `PhysicalPointLight` may carry an IES LM-63 file, `iesUrl`, read by the
//! loaders' shared [`lights::ies_luminaire`], and give its power in lumens). The spot and
//! directional lights are the core's constructors ([`PointLightDesc::spot`],
//! [`DirectionalLightDesc::new`]), so they mean what Mitsuba's `spot` and `directional` mean;
//! a value the core refuses is reported at the node with the core's message.
//!
//! VRML97 semantics kept: `location`, `direction`, `color` × `intensity`, `on`; a spot is full
//! within `beamWidth` of its axis and falls linearly in angle to zero at `cutOffAngle` (VRML97
//! §6.45; a `beamWidth` at or above `cutOffAngle` means no fall-off). Not kept, with a warning:
//! `attenuation` other than 1/r² (physically only inverse-square is right), `radius` (light
//! has no range), `ambientIntensity` (there is no ambient term), a standard `SpotLight`'s
//! `cutOffAngle` beyond VRML97's π/2 (clamped: VTK's exporter writes degrees), and a
//! `DirectionalLight`'s scoping to its group: it becomes a sun lighting the whole scene. Lights
//! that emit nothing (black colour or intensity 0) are left out.

use super::convert::{Converter, dv, rgb};
use super::tree::{FieldValue, Node, ProtoInstance};
use crate::scene_formats::SceneFileError;
use crate::scene_formats::lights;
use glam::{DMat4, DVec3};
use opticks_core::light::check::check_power;
use opticks_core::light::{EmissionProfile, LightError, axis_frame, lumens_to_watts};
use opticks_core::math::Rgb;
use opticks_core::scene::{DirectionalLightDesc, PointLightDesc};
use std::f64::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};

/// Radiant intensity of a standard PointLight or SpotLight of `intensity` 1 and white `color`,
/// W/sr.
pub const POINT_LIGHT_INTENSITY: f32 = 1.0;
/// Irradiance of a standard DirectionalLight of `intensity` 1 and white `color`, W/m².
pub const DIRECTIONAL_IRRADIANCE: f32 = 1.0;

type Result<T> = std::result::Result<T, SceneFileError>;

fn colour(p: &ProtoInstance, k: &str) -> Rgb {
    rgb(p.get(k).and_then(FieldValue::as_vec3).unwrap_or([0.0; 3]))
}

fn vec3(p: &ProtoInstance, k: &str, default: [f32; 3]) -> DVec3 {
    dv(p.get(k).and_then(FieldValue::as_vec3).unwrap_or(default))
}

fn float(p: &ProtoInstance, k: &str, default: f32) -> f64 {
    f64::from(p.get(k).and_then(FieldValue::as_float).unwrap_or(default))
}

fn on(p: &ProtoInstance) -> bool {
    !matches!(p.get("on"), Some(FieldValue::Bool(false)))
}

fn name(n: &Node) -> String {
    n.def_name.clone().unwrap_or_else(|| format!("{}_{}_{}", n.type_name, n.pos.line, n.pos.col))
}

impl Converter {
    /// A light's value the core refuses, at the node `n`, in the core's words.
    fn light_error(&self, n: &Node, e: LightError) -> SceneFileError {
        self.invalid(n, e.to_string())
    }

    /// Warnings for the standard fields a physical light cannot honour.
    fn standard_light_notes(&mut self, n: &Node) {
        let a = n.vec3("attenuation", [1.0, 0.0, 0.0]);
        if a != [1.0, 0.0, 0.0] && a != [0.0, 0.0, 1.0] {
            self.warn_once(n, "attenuation", "attenuation ignored: light falls off with 1/r² physically");
        }
        if n.get("radius").is_some() {
            self.warn_once(n, "radius", "radius ignored: light has no range (it falls off with 1/r²)");
        }
        if n.float("ambientIntensity", 0.0) != 0.0 {
            self.warn_once(n, "ambient", "ambientIntensity ignored: there is no ambient light physically");
        }
    }

    /// The standard `color` × `intensity`, scaled to physical units.
    fn standard_colour(&mut self, n: &Node, unit: f32) -> Rgb {
        rgb(n.vec3("color", [1.0; 3])) * (n.float("intensity", 1.0) * unit)
    }

    pub(super) fn point_light(&mut self, n: &Node, m: &DMat4) -> Result<()> {
        let Some(p) = self.extension(n, "PhysicalPointLight") else {
            self.standard_light_notes(n);
            let intensity = self.standard_colour(n, POINT_LIGHT_INTENSITY);
            if n.bool("on", true) {
                let position = m.transform_point3(dv(n.vec3("location", [0.0; 3])));
                self.out.point_lights.push(PointLightDesc {
                    name: name(n),
                    source: self.source(n),
                    position: position.as_vec3(),
                    intensity,
                    ..Default::default()
                });
            }
            return Ok(());
        };
        if !on(p) {
            return Ok(());
        }
        let (i, phi, lumens) = (colour(p, "intensity"), colour(p, "power"), float(p, "lumens", 0.0));
        let mut light = PointLightDesc {
            name: name(n),
            source: self.source(n),
            position: m.transform_point3(vec3(p, "location", [0.0; 3])).as_vec3(),
            intensity: if i != Rgb::ZERO { i } else { phi / (4.0 * std::f32::consts::PI) },
            ..Default::default()
        };
        if let Some((path, ies)) = self.ies_url(n, p)? {
            // The file's candela, scaled per channel by `intensity` (white if not given).
            light.intensity = if i != Rgb::ZERO { i } else { Rgb::ONE };
            light.power = (phi != Rgb::ZERO).then_some(phi);
            let axis = m.transform_vector3(vec3(p, "direction", [0.0, -1.0, 0.0]));
            let horizontal = m.transform_vector3(vec3(p, "horizontal", [1.0, 0.0, 0.0]));
            light.orientation = Some(axis_frame(axis, horizontal).map_err(|e| self.light_error(n, e))?);
            light.profile = Some(EmissionProfile::Ies(ies.profile));
            if let Some(w) = ies.warning {
                self.warn(n, format!("{}: {w}", path.display()));
            }
            light.ies_file = Some(path);
        }
        if lumens != 0.0 {
            if phi != Rgb::ZERO {
                return Err(self.invalid(n, "give either power or lumens, not both"));
            }
            // The colour is the intensity's (white if not given); lumens set the flux.
            light.intensity = if i != Rgb::ZERO { i } else { Rgb::ONE };
            light.power =
                Some(lumens_to_watts(lumens as f32, light.intensity).map_err(|e| self.light_error(n, e))?);
        }
        self.out.point_lights.push(light);
        Ok(())
    }

    /// A `PhysicalPointLight`'s `iesUrl`: the first URL naming a local file (relative to the
    /// file being read, as for `Inline`), read and checked; `None` if no URL is given. A URL
    /// list naming no readable file, or a malformed file, is an error at the node.
    fn ies_url(&self, n: &Node, p: &ProtoInstance) -> Result<Option<(PathBuf, lights::IesLuminaire)>> {
        let urls = match p.get("iesUrl") {
            Some(FieldValue::Strs(v)) if !v.is_empty() => v,
            _ => return Ok(None),
        };
        let dir = self.file().parent().map(Path::to_path_buf).unwrap_or_default();
        let Some(path) = urls.iter().find_map(|u| super::local_url(&dir, u).map(|(p, _)| p)) else {
            return Err(
                self.invalid(n, format!("iesUrl: none of the URLs {urls:?} is a readable local file"))
            );
        };
        // Absolute, so a writer can refer to it from anywhere.
        let path = path.canonicalize().unwrap_or(path);
        let ies = lights::ies_luminaire(&path, false).map_err(|e| self.invalid(n, format!("iesUrl: {e}")))?;
        Ok(Some((path, ies)))
    }

    pub(super) fn spot_light(&mut self, n: &Node, m: &DMat4) -> Result<()> {
        let (location, direction, intensity, power, beam, cutoff, on) =
            match self.extension(n, "PhysicalSpotLight") {
                Some(p) => {
                    let (i, phi) = (colour(p, "intensity"), colour(p, "power"));
                    let power = (i == Rgb::ZERO && phi != Rgb::ZERO).then_some(phi);
                    (
                        vec3(p, "location", [0.0; 3]),
                        vec3(p, "direction", [0.0, 0.0, -1.0]),
                        i,
                        power,
                        float(p, "beamWidth", std::f32::consts::FRAC_PI_2),
                        float(p, "cutOffAngle", std::f32::consts::FRAC_PI_4),
                        on(p),
                    )
                }
                None => {
                    self.standard_light_notes(n);
                    (
                        dv(n.vec3("location", [0.0; 3])),
                        dv(n.vec3("direction", [0.0, 0.0, -1.0])),
                        self.standard_colour(n, POINT_LIGHT_INTENSITY),
                        None,
                        f64::from(n.float("beamWidth", std::f32::consts::FRAC_PI_2)),
                        f64::from(n.float("cutOffAngle", std::f32::consts::FRAC_PI_4)),
                        n.bool("on", true),
                    )
                }
            };
        if !on || intensity == Rgb::ZERO && power.is_none() {
            return Ok(()); // emits nothing
        }
        let cutoff = if cutoff > FRAC_PI_2 && n.proto.is_none() {
            // VTK's exporter, for one, writes degrees.
            self.warn_once(
                n,
                "cutoff",
                format!("cutOffAngle {cutoff} is beyond VRML97's range [0, π/2] radians: π/2 used"),
            );
            FRAC_PI_2
        } else {
            cutoff
        };
        if cutoff == 0.0 {
            self.warn_once(n, "cutoff", "cutOffAngle 0: the spot emits nothing: ignored");
            return Ok(());
        }
        let mut light = PointLightDesc::spot(
            name(n),
            self.source(n),
            m.transform_point3(location).as_vec3(),
            m.transform_vector3(direction),
            intensity,
            cutoff as f32,
            // VRML97: a beamWidth wider than the cutOffAngle means no fall-off.
            beam.min(cutoff) as f32,
        )
        .map_err(|e| self.light_error(n, e))?;
        if let Some(phi) = power {
            light.power = Some(check_power(phi).map_err(|e| self.light_error(n, e))?);
        }
        self.out.point_lights.push(light);
        Ok(())
    }

    pub(super) fn directional_light(&mut self, n: &Node, m: &DMat4, depth: usize) -> Result<()> {
        let (direction, irradiance, on) = match self.extension(n, "PhysicalDirectionalLight") {
            Some(p) => (vec3(p, "direction", [0.0, 0.0, -1.0]), colour(p, "irradiance"), on(p)),
            None => {
                self.standard_light_notes(n);
                let e = self.standard_colour(n, DIRECTIONAL_IRRADIANCE);
                (dv(n.vec3("direction", [0.0, 0.0, -1.0])), e, n.bool("on", true))
            }
        };
        if !on || irradiance == Rgb::ZERO {
            return Ok(()); // emits nothing (VTK writes its ambient light so)
        }
        if depth > 0 {
            self.warn_once(
                n,
                "scope",
                "lights the whole scene (a sun), not only the nodes of its group as VRML97 scopes it",
            );
        }
        let light =
            DirectionalLightDesc::new(name(n), self.source(n), m.transform_vector3(direction), irradiance)
                .map_err(|e| self.light_error(n, e))?;
        self.out.directional_lights.push(light);
        Ok(())
    }
}
