//! Camera options shared by `render`, `demo` and `bench`: `--eye`, `--target`, `--up`, `--fov`,
//! `--size` override (or, without a scene camera, define) the camera a dataset is rendered from;
//! `--projection`, `--lens-radius`, `--focus-distance` and `--ortho-width` choose the kind of
//! sensor (pinhole, thin lens, orthographic, equirectangular 360°; by default the scene
//! camera's kind). [`CameraArgs::resolve`] turns them into a [`Sensor`].
//! Also the number parsers the measuring verbs share (`parse_vec3`, `parse_size`).

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, ValueEnum};
use opticks_core::math::Vec3;
use opticks_core::scene::{CameraDesc, CameraKind};
use opticks_core::sensor::{Equirectangular, Orthographic, Pinhole, Sensor, ThinLens};

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
    /// Projection: perspective (default) or equirect (360° panorama around the eye).
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
    /// The option combinations refused before any work: `--fov` and a non-2:1 `--size` with the
    /// equirect projection (which always covers 360°×180°), the lens options with a projection
    /// other than perspective, `--fov` with orthographic, `--ortho-width` with another.
    pub fn check(&self) -> Result<()> {
        match self.projection {
            Some(p) => self.check_for(p),
            None if self.ortho_width.is_some() => self.check_for(Projection::Orthographic),
            None => Ok(()), // the scene camera's kind: checked by `resolve`
        }
    }

    /// [`CameraArgs::check`] for `projection`.
    fn check_for(&self, projection: Projection) -> Result<()> {
        let lens = self.lens_radius.is_some() || self.focus_distance.is_some();
        match projection {
            Projection::Perspective if self.ortho_width.is_some() => {
                bail!("--ortho-width applies to the orthographic projection, not perspective")
            }
            Projection::Perspective => Ok(()),
            Projection::Orthographic if lens => {
                bail!(
                    "--lens-radius and --focus-distance apply to the perspective projection, not orthographic"
                )
            }
            Projection::Orthographic => match self.fov {
                Some(fov) => bail!(
                    "--fov {fov}: an orthographic camera has no field of view; its film's width is --ortho-width"
                ),
                None => Ok(()),
            },
            Projection::Equirect => {
                if lens {
                    bail!(
                        "--lens-radius and --focus-distance apply to the perspective projection, not equirect"
                    );
                }
                if self.ortho_width.is_some() {
                    bail!("--ortho-width applies to the orthographic projection, not equirect");
                }
                if let Some(fov) = self.fov {
                    bail!(
                        "--fov {fov}: the equirect projection always covers 360°×180°; --fov applies to perspective"
                    );
                }
                if let Some((w, h)) = self.size.filter(|&(w, h)| w != 2 * h) {
                    bail!("--size {w}x{h}: an equirect image is twice as wide as high (e.g. {}x{h})", 2 * h);
                }
                Ok(())
            }
        }
    }

    /// The sensor to render with: the scene's camera with any overrides applied, of the kind
    /// `--projection` names or, without it, of the scene camera's kind (a thin lens keeps its
    /// aperture and focus unless overridden).
    pub fn resolve(&self, scene_camera: Option<CameraDesc>) -> Result<Sensor> {
        self.check()?;
        let mut desc = self.resolve_desc(scene_camera)?;
        let named = self.projection.or(self.ortho_width.map(|_| Projection::Orthographic));
        let projection = named.unwrap_or(match desc.kind {
            CameraKind::Orthographic { .. } => Projection::Orthographic,
            CameraKind::Perspective | CameraKind::ThinLens { .. } => Projection::Perspective,
        });
        if named.is_none() {
            self.check_for(projection).context("the scene's camera is orthographic")?;
        }
        match projection {
            Projection::Equirect => {
                if self.size.is_none() {
                    desc.height = (desc.width / 2).max(1);
                    desc.width = 2 * desc.height;
                }
                Ok(Equirectangular::new(&desc).context("invalid camera")?.into())
            }
            Projection::Orthographic => {
                let (half_width, half_height) = match (self.ortho_width, desc.kind) {
                    (Some(w), _) => (0.5 * w, 0.5 * w * desc.height as f32 / desc.width as f32),
                    (None, CameraKind::Orthographic { half_width, half_height }) => (half_width, half_height),
                    (None, _) => bail!(
                        "--projection orthographic needs --ortho-width (the film's width in metres): the scene's camera is not orthographic"
                    ),
                };
                Ok(Orthographic::new(&desc, half_width, half_height).context("invalid camera")?.into())
            }
            Projection::Perspective => {
                let pinhole = Pinhole::new(&desc).context("invalid camera")?;
                let (radius, focus) = match desc.kind {
                    CameraKind::ThinLens { aperture_radius, focus_distance } => {
                        (Some(aperture_radius), Some(focus_distance))
                    }
                    CameraKind::Perspective | CameraKind::Orthographic { .. } => (None, None),
                };
                let (radius, focus) = (self.lens_radius.or(radius), self.focus_distance.or(focus));
                if radius.is_none() && focus.is_none() {
                    return Ok(pinhole.into());
                }
                let focus = focus.unwrap_or_else(|| (desc.target - desc.eye).length());
                Ok(ThinLens::new(pinhole, radius.unwrap_or(0.0), focus).context("invalid thin lens")?.into())
            }
        }
    }

    /// The camera description: the scene's camera with any overrides applied.
    pub fn resolve_desc(&self, scene_camera: Option<CameraDesc>) -> Result<CameraDesc> {
        let base = scene_camera.or_else(|| {
            let (eye, target) = (self.eye?, self.target?);
            Some(CameraDesc {
                eye,
                target,
                up: Vec3::Y,
                fov_x_degrees: 45.0,
                width: 512,
                height: 512,
                kind: CameraKind::Perspective,
            })
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
        Ok(c)
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

    fn desc() -> CameraDesc {
        CameraDesc {
            eye: Vec3::Z,
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_x_degrees: 40.0,
            width: 8,
            height: 4,
            kind: CameraKind::Perspective,
        }
    }

    #[test]
    fn resolves_the_kind_of_sensor() {
        let plain = CameraArgs::default();
        assert!(matches!(plain.resolve(Some(desc())).unwrap(), Sensor::Pinhole(_)));
        let lens = CameraArgs { lens_radius: Some(0.1), ..Default::default() };
        let Sensor::ThinLens(t) = lens.resolve(Some(desc())).unwrap() else { panic!() };
        assert_eq!((t.radius, t.focus_distance), (0.1, 1.0));
        let pano = CameraArgs { projection: Some(Projection::Equirect), ..Default::default() };
        let s = pano.resolve(Some(desc())).unwrap();
        assert!(matches!(s, Sensor::Equirectangular(_)) && (s.width(), s.height()) == (8, 4));
        let square = CameraDesc { width: 9, height: 9, ..desc() };
        let s = pano.resolve(Some(square)).unwrap();
        assert_eq!((s.width(), s.height()), (8, 4), "the scene camera's width, 2:1");
        for refused in [
            CameraArgs { fov: Some(30.0), ..pano.clone() },
            CameraArgs { size: Some((64, 64)), ..pano.clone() },
        ] {
            assert!(refused.check().is_err() && refused.resolve(Some(desc())).is_err(), "{refused:?}");
        }
        assert!(CameraArgs { size: Some((64, 32)), ..pano.clone() }.check().is_ok());
        assert!(CameraArgs { lens_radius: Some(-1.0), ..Default::default() }.resolve(Some(desc())).is_err());
        assert!(
            CameraArgs { focus_distance: Some(0.0), ..Default::default() }.resolve(Some(desc())).is_err()
        );
        let both = CameraArgs { lens_radius: Some(0.1), ..pano };
        assert!(both.resolve(Some(desc())).is_err());
    }

    /// Without --projection the scene camera's kind is rendered, its parameters overridable.
    #[test]
    fn resolves_the_scene_cameras_kind() {
        let plain = CameraArgs::default();
        let lens = CameraDesc {
            kind: CameraKind::ThinLens { aperture_radius: 0.05, focus_distance: 2.0 },
            ..desc()
        };
        let Sensor::ThinLens(t) = plain.resolve(Some(lens)).unwrap() else { panic!() };
        assert_eq!((t.radius, t.focus_distance), (0.05, 2.0));
        let refocused = CameraArgs { focus_distance: Some(3.0), ..Default::default() };
        let Sensor::ThinLens(t) = refocused.resolve(Some(lens)).unwrap() else { panic!() };
        assert_eq!((t.radius, t.focus_distance), (0.05, 3.0));
        let ortho =
            CameraDesc { kind: CameraKind::Orthographic { half_width: 2.0, half_height: 1.0 }, ..desc() };
        let Sensor::Orthographic(o) = plain.resolve(Some(ortho)).unwrap() else { panic!() };
        assert_eq!((o.half_width, o.half_height), (2.0, 1.0));
        // --ortho-width alone makes any camera orthographic; the height follows the 8x4 image.
        let wide = CameraArgs { ortho_width: Some(6.0), ..Default::default() };
        let Sensor::Orthographic(o) = wide.resolve(Some(desc())).unwrap() else { panic!() };
        assert_eq!((o.half_width, o.half_height), (3.0, 1.5));
        // A perspective projection of the orthographic scene camera: its field of view.
        let persp = CameraArgs { projection: Some(Projection::Perspective), ..Default::default() };
        assert!(matches!(persp.resolve(Some(ortho)).unwrap(), Sensor::Pinhole(_)));
        for refused in [
            CameraArgs { fov: Some(30.0), ..Default::default() },
            CameraArgs { lens_radius: Some(0.1), ..Default::default() },
        ] {
            let err = refused.resolve(Some(ortho)).unwrap_err();
            assert!(format!("{err:#}").contains("orthographic"), "{err:#}");
        }
        let needs_width = CameraArgs { projection: Some(Projection::Orthographic), ..Default::default() };
        assert!(needs_width.resolve(Some(desc())).is_err());
        assert!(CameraArgs { ortho_width: Some(1.0), ..persp }.check().is_err());
        assert!(CameraArgs { ortho_width: Some(-1.0), ..Default::default() }.resolve(Some(desc())).is_err());
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
