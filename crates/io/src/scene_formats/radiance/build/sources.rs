//! The sky generators' lines and the `source` primitive: Radiance's lights at infinity.

use super::{Builder, DIRECTIONAL_SOURCE_DEGREES, Frame, Modifier};
use crate::scene_formats::radiance::err;
use crate::scene_formats::radiance::lexer::Primitive;
use crate::scene_formats::radiance::sky;
use crate::scene_formats::{FileLocation, SceneFileError};
use glam::DVec3;
use opticks_core::bsdf::{Bsdf, Lambert, Material};
use opticks_core::math::Rgb;
use opticks_core::scene::{DirectionalLightDesc, EnvironmentLightDesc, Source};
use std::path::Path;

impl Builder {
    /// `!gensky …` or `!gendaylit …`, interpreted (never run; `sky/`): defines `skyfunc` (for
    /// the `glow` of the sky and ground `source`s that follow, as in Radiance), and with a sun
    /// the `solar` light and its `source sun`, a directional light (gensky's 0.5° disc,
    /// gendaylit's 0.533°).
    pub(super) fn sky(
        &mut self,
        path: &Path,
        generator: sky::Generator,
        words: &[String],
        text: &str,
        here: &FileLocation,
        frame: &Frame,
    ) -> Result<(), SceneFileError> {
        let element = format!("!{}", generator.name());
        let bad = |e: sky::SkyArgsError| err(here, &element, format!("{e}: \"!{text}\""));
        let g = sky::generate(generator, &words[1..]).map_err(bad)?;
        for w in &g.warnings {
            self.warnings.push(format!("{here}: {element}: {w}"));
        }
        if let Some(sun) = g.sun {
            let rgb = Rgb::splat(sun.radiance as f32);
            let black = Bsdf::Lambert(Lambert::new(Rgb::ZERO).expect("black is a reflectance"));
            let material = Material { name: "solar".into(), bsdf: black, two_sided: false };
            self.modifiers.push(Modifier::Material { material, emission: Some(rgb), index: None });
            self.names.insert("solar".into(), self.modifiers.len() - 1);
            if sun.radiance > 0.0 {
                self.add_sun(path, here, frame, "sun", sun.toward, rgb, sun.diameter_degrees)?;
            }
        }
        self.modifiers.push(Modifier::Sky(Box::new(g.func)));
        self.names.insert("skyfunc".into(), self.modifiers.len() - 1);
        Ok(())
    }

    /// A directional light `name` toward `toward` (Radiance's source direction) of a disc of
    /// `angle` degrees and radiance `rgb`: irradiance `rgb` × the disc's solid angle.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn add_sun(
        &mut self,
        path: &Path,
        here: &FileLocation,
        frame: &Frame,
        name: &str,
        toward: DVec3,
        rgb: Rgb,
        angle: f64,
    ) -> Result<(), SceneFileError> {
        let name = self.light_name(frame, name);
        let omega = sky::disc_solid_angle(angle);
        let d = DirectionalLightDesc::new(
            name.clone(),
            Source { file: path.display().to_string(), line: here.line },
            -frame.transform.vector(toward),
            rgb * omega as f32,
        )
        .map_err(|e| err(here, &format!("source {name}"), e.to_string()))?;
        self.desc.directional_lights.push(d);
        Ok(())
    }

    pub(super) fn light_name(&self, frame: &Frame, ident: &str) -> String {
        match &frame.prefix {
            Some(prefix) => format!("{prefix}.{ident}"),
            None => ident.to_string(),
        }
    }

    /// `mod source id 0 0 4 dx dy dz angle`: a light at infinity in the cone of full `angle`
    /// degrees around the direction. Modified by a glow of gensky's `skyfunc`, an environment
    /// light of the sky's brightness × the glow's colour in the cone (the sky dome, the ground
    /// dome); by a `light` or `glow` of constant radiance, a directional light when narrower
    /// than [`DIRECTIONAL_SOURCE_DEGREES`] (the sun), else an environment light of the cone.
    pub(super) fn source(
        &mut self,
        path: &Path,
        p: &Primitive,
        here: &FileLocation,
        frame: &Frame,
    ) -> Result<(), SceneFileError> {
        let element = p.describe();
        let bad = |m: String| err(here, &element, m);
        if !p.strings.is_empty() || !p.ints.is_empty() || p.reals.len() != 4 {
            return Err(bad("source takes 0 string, 0 integer and 4 real arguments".into()));
        }
        let r = &p.reals;
        let axis = frame.transform.vector(DVec3::new(r[0], r[1], r[2]));
        let angle = r[3];
        if axis.length() == 0.0 || !axis.is_finite() || !(angle > 0.0 && angle <= 360.0) {
            return Err(bad(format!("needs a non-zero direction and an angle in (0, 360], not {angle}")));
        }
        let axis = axis.normalize();
        let modifier = frame.modifier.as_deref().unwrap_or(&p.modifier.text);
        let Some(i) = self.lookup(modifier, here, &element)? else {
            self.void_surfaces += 1;
            return Ok(());
        };
        let (sky, rgb) = match &self.modifiers[i] {
            Modifier::SkyGlow(g, rgb) => (Some(g.clone()), *rgb),
            Modifier::Material { emission: Some(rgb), .. } => (None, *rgb),
            Modifier::Invisible => {
                self.void_surfaces += 1;
                return Ok(());
            }
            Modifier::Material { emission: None, .. } => {
                return Err(bad(format!(
                    "modifier \"{modifier}\" emits nothing: a source takes a light or glow (or a glow of gensky's skyfunc)"
                )));
            }
            Modifier::Sky(_) => {
                return Err(bad(format!(
                    "modifier \"{modifier}\" is gensky's skyfunc, a pattern: a source takes a glow of it (skyfunc glow sky_glow 0 0 4 1 1 1 0)"
                )));
            }
            Modifier::Same(_) => unreachable!("Same is never stored"),
        };
        if sky.is_none() && angle < DIRECTIONAL_SOURCE_DEGREES {
            return self.add_sun(
                path,
                here,
                &Frame::default(),
                &self.light_name(frame, &p.ident.text),
                axis,
                rgb,
                angle,
            );
        }
        let half = (0.5 * angle).to_radians();
        let radiance = sky::sky_map(axis, half, rgb, |d| match &sky {
            Some(g) => g.brightness(d),
            None => 1.0,
        });
        self.desc.environment_lights.push(EnvironmentLightDesc {
            name: self.light_name(frame, &p.ident.text),
            source: Source { file: path.display().to_string(), line: p.modifier.line },
            radiance,
            to_world: sky::MAP_TO_WORLD,
            sky: sky.as_ref().map(|g| g.model()),
        });
        Ok(())
    }
}
