//! Camera options shared by `render`, `demo` and `bench`: `--eye`, `--target`, `--up`, `--fov`,
//! `--size` override (or, without a scene camera, define) the camera a dataset is rendered from;
//! `--projection`, `--lens-radius`, `--focus-distance` and `--ortho-width` choose the kind of
//! sensor (pinhole, thin lens, orthographic, equirectangular 360°; by default the scene
//! camera's kind). The library's [`View`] checks and resolves them into a [`Sensor`].
//! Also the number parsers the measuring verbs share (`parse_vec3`, `parse_size`).

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, ValueEnum};
use opticks_core::math::Vec3;
use opticks_core::scene::CameraDesc;
use opticks_core::sensor::Sensor;
use opticks_core::sensor::view::{self, View};

/// How the camera projects the world onto its image.
#[derive(ValueEnum, Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Projection {
    /// Perspective (pinhole, or thin lens with --lens-radius).
    #[default]
    Perspective,
    /// Orthographic: parallel rays along the view from a film centred on the eye (its width
    /// --ortho-width, or the scene camera's).
    Orthographic,
    /// Equirectangular 360°×180° (longitude across, latitude down; a 2:1 --size, by default
    /// the scene camera's width by half of it).
    Equirect,
}

/// Camera overrides.
#[derive(Args, Debug, Clone, Default)]
pub struct CameraArgs {
    /// Camera position "x,y,z" (metres).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub eye: Option<Vec3>,
    /// Point looked at "x,y,z".
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub target: Option<Vec3>,
    /// Up direction "x,y,z" (default 0,1,0).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub up: Option<Vec3>,
    /// Horizontal field of view, degrees (perspective only).
    #[arg(long)]
    pub fov: Option<f32>,
    /// Image size "WxH" in pixels.
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Projection: perspective (default), orthographic (parallel rays; --ortho-width) or
    /// equirect (360° panorama around the eye).
    #[arg(long, value_enum)]
    pub projection: Option<Projection>,
    /// Thin-lens aperture radius in metres (depth of field; 0 = pinhole).
    #[arg(long, allow_hyphen_values = true)]
    pub lens_radius: Option<f32>,
    /// Distance in metres from the lens to the plane in focus (default: the scene camera's, else
    /// eye to target).
    #[arg(long, allow_hyphen_values = true)]
    pub focus_distance: Option<f32>,
    /// Width in metres of an orthographic camera's film (its height follows the image's
    /// aspect; default: the scene camera's film).
    #[arg(long, allow_hyphen_values = true)]
    pub ortho_width: Option<f32>,
}

/// Parses "x,y,z".
pub fn parse_vec3(s: &str) -> Result<Vec3> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>().with_context(|| format!("'{x}' is not a number")))
        .collect::<Result<_>>()?;
    match v.as_slice() {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Vec3::new(*x, *y, *z)),
        [_, _, _] => bail!("'{s}' has a non-finite component"),
        _ => bail!("'{s}' must be three comma-separated numbers, e.g. 0,1,2.5"),
    }
}

/// Parses "WxH" (each 1..=32768).
pub fn parse_size(s: &str) -> Result<(u32, u32)> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| anyhow!("'{s}' must look like 640x480"))?;
    let (w, h): (u32, u32) = (w.trim().parse()?, h.trim().parse()?);
    opticks_core::sensor::check_image_size(w, h)?;
    Ok((w, h))
}

/// The exposure of an image written to `path`: `--exposure` applies to PNG output only (an EXR
/// holds radiance as it is, so an exposure there is refused rather than ignored), and must be
/// finite. Checked before any work.
pub fn exposure_for(path: &std::path::Path, exposure: Option<f32>) -> Result<f32> {
    let exr = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    match exposure {
        Some(e) if !e.is_finite() => bail!("--exposure {e}: must be a finite number of stops"),
        Some(_) if exr => bail!(
            "--exposure applies to PNG output; {} is an EXR, which holds the radiance as it is",
            path.display()
        ),
        e => Ok(e.unwrap_or(0.0)),
    }
}

impl CameraArgs {
    /// The overrides as the library takes them.
    pub fn view(&self) -> View {
        View {
            eye: self.eye,
            target: self.target,
            up: self.up,
            fov: self.fov,
            size: self.size,
            projection: self.projection.map(|p| match p {
                Projection::Perspective => view::Projection::Perspective,
                Projection::Orthographic => view::Projection::Orthographic,
                Projection::Equirect => view::Projection::Equirect,
            }),
            lens_radius: self.lens_radius,
            focus_distance: self.focus_distance,
            ortho_width: self.ortho_width,
        }
    }

    /// Refuses contradictory options before any work ([`View::check`]).
    pub fn check(&self) -> Result<()> {
        Ok(self.view().check()?)
    }

    /// The sensor to render with ([`View::resolve`]).
    pub fn resolve(&self, scene_camera: Option<CameraDesc>) -> Result<Sensor, view::ViewError> {
        self.view().resolve(scene_camera)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_vectors_and_sizes() {
        assert_eq!(parse_vec3("1, -2,3.5").unwrap(), Vec3::new(1.0, -2.0, 3.5));
        assert!(parse_vec3("1,2").is_err());
        assert!(parse_vec3("1,nan,2").is_err());
        assert_eq!(parse_size("640x480").unwrap(), (640, 480));
        assert!(parse_size("0x10").is_err());
        assert!(parse_size("640").is_err());
    }

    #[test]
    fn exposure_is_for_png_only_and_finite() {
        use std::path::Path;
        assert_eq!(exposure_for(Path::new("a.png"), Some(1.5)).unwrap(), 1.5);
        assert_eq!(exposure_for(Path::new("a.exr"), None).unwrap(), 0.0);
        assert!(exposure_for(Path::new("a.EXR"), Some(0.0)).is_err());
        assert!(exposure_for(Path::new("a.png"), Some(f32::NAN)).is_err());
    }
}
