//! Camera options shared by `render` and `demo`: `--eye`, `--target`, `--up`, `--fov`, `--size`
//! override (or, without a scene camera, define) the camera a dataset is rendered from.

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use opticks_core::math::Vec3;
use opticks_core::scene::{CameraDesc, Pinhole};

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
    /// Horizontal field of view, degrees.
    #[arg(long)]
    pub fov: Option<f32>,
    /// Image size "WxH" in pixels.
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
}

fn parse_vec3(s: &str) -> Result<Vec3> {
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

fn parse_size(s: &str) -> Result<(u32, u32)> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| anyhow!("'{s}' must look like 640x480"))?;
    let (w, h): (u32, u32) = (w.trim().parse()?, h.trim().parse()?);
    if w == 0 || h == 0 || w > 32768 || h > 32768 {
        bail!("image size {w}x{h} must be between 1x1 and 32768x32768");
    }
    Ok((w, h))
}

impl CameraArgs {
    /// The camera to render with: the scene's camera with any overrides applied.
    pub fn resolve(&self, scene_camera: Option<CameraDesc>) -> Result<Pinhole> {
        let base = scene_camera.or_else(|| {
            let (eye, target) = (self.eye?, self.target?);
            Some(CameraDesc { eye, target, up: Vec3::Y, fov_x_degrees: 45.0, width: 512, height: 512 })
        });
        let Some(mut c) = base else {
            bail!("the scene has no camera: give one with --eye X,Y,Z --target X,Y,Z (and --fov, --size)");
        };
        c.eye = self.eye.unwrap_or(c.eye);
        c.target = self.target.unwrap_or(c.target);
        c.up = self.up.unwrap_or(c.up);
        c.fov_x_degrees = self.fov.unwrap_or(c.fov_x_degrees);
        if let Some((w, h)) = self.size {
            (c.width, c.height) = (w, h);
        }
        Pinhole::new(&c).context("invalid camera")
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
}
