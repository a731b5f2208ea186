//! The view a dataset is rendered from: the scene's camera with overrides (eye, target, up,
//! field of view, size) and the kind of sensor (pinhole, thin lens, orthographic,
//! equirectangular 360°; by default the scene camera's kind) — what every front end asks for
//! before it renders. [`View::check`] refuses contradictory options before any work (each is
//! either used or refused, never ignored); [`View::resolve`] turns them into a [`Sensor`].
//! The messages name the options as the command line spells them (`--fov`, `--ortho-width`),
//! which the bindings take as keywords of the same names.

use super::{CameraError, Equirectangular, LensError, Orthographic, Pinhole, Sensor, ThinLens};
use crate::math::Vec3;
use crate::scene::{CameraDesc, CameraKind};

/// How the camera projects the world onto its image.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Projection {
    /// Perspective (pinhole, or thin lens with a lens radius).
    #[default]
    Perspective,
    /// Orthographic: parallel rays along the view from a film centred on the eye.
    Orthographic,
    /// Equirectangular 360°×180° (longitude across, latitude down; a 2:1 image).
    Equirect,
}

/// Overrides of the scene's camera; `None` keeps the scene camera's value.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct View {
    /// Camera position (metres).
    pub eye: Option<Vec3>,
    /// Point looked at.
    pub target: Option<Vec3>,
    /// Up direction.
    pub up: Option<Vec3>,
    /// Horizontal field of view, degrees (perspective only).
    pub fov: Option<f32>,
    /// Image size in pixels.
    pub size: Option<(u32, u32)>,
    /// The projection (default: the scene camera's kind).
    pub projection: Option<Projection>,
    /// Thin-lens aperture radius in metres.
    pub lens_radius: Option<f32>,
    /// Distance in metres from the lens to the plane in focus.
    pub focus_distance: Option<f32>,
    /// Width in metres of an orthographic camera's film.
    pub ortho_width: Option<f32>,
}

/// Why a view cannot be rendered.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ViewError {
    /// Options that contradict each other or the projection.
    #[error("{0}")]
    Options(String),
    /// Neither the scene nor the options give a camera.
    #[error("the scene has no camera: give one with --eye X,Y,Z --target X,Y,Z (and --fov, --size)")]
    NoCamera,
    /// An option contradicts the scene camera's kind (orthographic).
    #[error("the scene's camera is orthographic")]
    SceneCamera(#[source] Box<ViewError>),
    /// The camera is invalid (size, field of view, film).
    #[error("invalid camera")]
    Camera(#[source] CameraError),
    /// The thin lens is invalid (radius, focus distance).
    #[error("invalid thin lens")]
    Lens(#[source] LensError),
}

macro_rules! refuse {
    ($($t:tt)*) => { return Err(ViewError::Options(format!($($t)*))) };
}

impl View {
    /// The option values and combinations refused before any work: a field of view out of its
    /// range (blamed on `--fov`, not on the scene's camera), `--fov` and a non-2:1 `--size` with the
    /// equirect projection (which always covers 360°×180°), the lens options with a projection
    /// other than perspective, `--fov` with orthographic, `--ortho-width` with another.
    pub fn check(&self) -> Result<(), ViewError> {
        if let Some(fov) = self.fov {
            super::check_fov(fov).map_err(|e| ViewError::Options(format!("--fov {fov}: {e}")))?;
        }
        match self.projection {
            Some(p) => self.check_for(p),
            None if self.ortho_width.is_some() => self.check_for(Projection::Orthographic),
            None => Ok(()), // the scene camera's kind: checked by `resolve`
        }
    }

    /// [`CameraArgs::check`] for `projection`.
    fn check_for(&self, projection: Projection) -> Result<(), ViewError> {
        let lens = self.lens_radius.is_some() || self.focus_distance.is_some();
        match projection {
            Projection::Perspective if self.ortho_width.is_some() => {
                refuse!("--ortho-width applies to the orthographic projection, not perspective")
            }
            Projection::Perspective => Ok(()),
            Projection::Orthographic if lens => {
                refuse!(
                    "--lens-radius and --focus-distance apply to the perspective projection, not orthographic"
                )
            }
            Projection::Orthographic => match self.fov {
                Some(fov) => refuse!(
                    "--fov {fov}: an orthographic camera has no field of view; its film's width is --ortho-width"
                ),
                None => Ok(()),
            },
            Projection::Equirect => {
                if lens {
                    refuse!(
                        "--lens-radius and --focus-distance apply to the perspective projection, not equirect"
                    );
                }
                if self.ortho_width.is_some() {
                    refuse!("--ortho-width applies to the orthographic projection, not equirect");
                }
                if let Some(fov) = self.fov {
                    refuse!(
                        "--fov {fov}: the equirect projection always covers 360°×180°; --fov applies to perspective"
                    );
                }
                if let Some((w, h)) = self.size.filter(|&(w, h)| w != 2 * h) {
                    refuse!(
                        "--size {w}x{h}: an equirect image is twice as wide as high (e.g. {}x{h})",
                        2 * h
                    );
                }
                Ok(())
            }
        }
    }

    /// The sensor to render with: the scene's camera with any overrides applied, of the kind
    /// `--projection` names or, without it, of the scene camera's kind (a thin lens keeps its
    /// aperture and focus unless overridden).
    pub fn resolve(&self, scene_camera: Option<CameraDesc>) -> Result<Sensor, ViewError> {
        self.check()?;
        let mut desc = self.resolve_desc(scene_camera)?;
        let named = self.projection.or(self.ortho_width.map(|_| Projection::Orthographic));
        let projection = named.unwrap_or(match desc.kind {
            CameraKind::Orthographic { .. } => Projection::Orthographic,
            CameraKind::Perspective | CameraKind::ThinLens { .. } => Projection::Perspective,
        });
        if named.is_none() {
            self.check_for(projection).map_err(|e| ViewError::SceneCamera(Box::new(e)))?;
        }
        match projection {
            Projection::Equirect => {
                if self.size.is_none() && desc.width != 2 * desc.height {
                    desc.height = (desc.width / 2).max(1);
                    desc.width = 2 * desc.height;
                    desc.film.crop = None; // a new film (`resolve_desc`)
                }
                Ok(Equirectangular::new(&desc).map_err(ViewError::Camera)?.into())
            }
            Projection::Orthographic => {
                let (half_width, half_height) = match (self.ortho_width, desc.kind) {
                    (Some(w), _) => (0.5 * w, 0.5 * w * desc.height as f32 / desc.width as f32),
                    (None, CameraKind::Orthographic { half_width, half_height }) => (half_width, half_height),
                    (None, _) => refuse!(
                        "--projection orthographic needs --ortho-width (the film's width in metres): the scene's camera is not orthographic"
                    ),
                };
                Ok(Orthographic::new(&desc, half_width, half_height).map_err(ViewError::Camera)?.into())
            }
            Projection::Perspective => {
                let pinhole = Pinhole::new(&desc).map_err(ViewError::Camera)?;
                let (radius, focus) = match desc.kind {
                    CameraKind::ThinLens { aperture_radius, focus_distance } => {
                        (Some(aperture_radius), Some(focus_distance))
                    }
                    CameraKind::Perspective | CameraKind::Orthographic { .. } => (None, None),
                };
                let (radius, focus) = (self.lens_radius.or(radius), self.focus_distance.or(focus));
                if let Some(f) = self.focus_distance.filter(|_| radius.unwrap_or(0.0) == 0.0) {
                    refuse!(
                        "--focus-distance {f} does nothing without a lens: give --lens-radius (the camera is a pinhole)"
                    );
                }
                if radius.is_none() && focus.is_none() {
                    return Ok(pinhole.into());
                }
                let focus = focus.unwrap_or_else(|| (desc.target - desc.eye).length());
                Ok(ThinLens::new(pinhole, radius.unwrap_or(0.0), focus).map_err(ViewError::Lens)?.into())
            }
        }
    }

    /// The camera description: the scene's camera with any overrides applied (a new `--size`
    /// drops the file's crop window, given in pixels of the file's film).
    pub fn resolve_desc(&self, scene_camera: Option<CameraDesc>) -> Result<CameraDesc, ViewError> {
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
                film: Default::default(),
            })
        });
        let Some(mut c) = base else { return Err(ViewError::NoCamera) };
        c.eye = self.eye.unwrap_or(c.eye);
        c.target = self.target.unwrap_or(c.target);
        c.up = self.up.unwrap_or(c.up);
        c.fov_x_degrees = self.fov.unwrap_or(c.fov_x_degrees);
        if let Some((w, h)) = self.size.filter(|&s| s != (c.width, c.height)) {
            // A new film: the file's crop window was in pixels of its own.
            (c.width, c.height) = (w, h);
            c.film.crop = None;
        }
        Ok(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn desc() -> CameraDesc {
        CameraDesc {
            eye: Vec3::Z,
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_x_degrees: 40.0,
            width: 8,
            height: 4,
            kind: CameraKind::Perspective,
            film: Default::default(),
        }
    }

    #[test]
    fn resolves_the_kind_of_sensor() {
        let plain = View::default();
        assert!(matches!(plain.resolve(Some(desc())).unwrap(), Sensor::Pinhole(_)));
        let lens = View { lens_radius: Some(0.1), ..Default::default() };
        let Sensor::ThinLens(t) = lens.resolve(Some(desc())).unwrap() else { panic!() };
        assert_eq!((t.radius, t.focus_distance), (0.1, 1.0));
        let pano = View { projection: Some(Projection::Equirect), ..Default::default() };
        let s = pano.resolve(Some(desc())).unwrap();
        assert!(matches!(s, Sensor::Equirectangular(_)) && (s.width(), s.height()) == (8, 4));
        let square = CameraDesc { width: 9, height: 9, ..desc() };
        let s = pano.resolve(Some(square)).unwrap();
        assert_eq!((s.width(), s.height()), (8, 4), "the scene camera's width, 2:1");
        for refused in [View { fov: Some(30.0), ..pano }, View { size: Some((64, 64)), ..pano }] {
            assert!(refused.check().is_err() && refused.resolve(Some(desc())).is_err(), "{refused:?}");
        }
        assert!(View { size: Some((64, 32)), ..pano }.check().is_ok());
        assert!(View { lens_radius: Some(-1.0), ..Default::default() }.resolve(Some(desc())).is_err());
        assert!(View { focus_distance: Some(0.0), ..Default::default() }.resolve(Some(desc())).is_err());
        // A focus distance without a lens would do nothing: refused, not ignored.
        let focus_alone = View { focus_distance: Some(2.0), ..Default::default() };
        assert!(
            matches!(focus_alone.resolve(Some(desc())), Err(ViewError::Options(m)) if m.contains("--lens-radius"))
        );
        let no_lens = View { lens_radius: Some(0.0), ..focus_alone };
        assert!(no_lens.resolve(Some(desc())).is_err());
        let both = View { lens_radius: Some(0.1), ..pano };
        assert!(both.resolve(Some(desc())).is_err());
    }

    /// Without --projection the scene camera's kind is rendered, its parameters overridable.
    #[test]
    fn resolves_the_scene_cameras_kind() {
        let plain = View::default();
        let lens = CameraDesc {
            kind: CameraKind::ThinLens { aperture_radius: 0.05, focus_distance: 2.0 },
            ..desc()
        };
        let Sensor::ThinLens(t) = plain.resolve(Some(lens)).unwrap() else { panic!() };
        assert_eq!((t.radius, t.focus_distance), (0.05, 2.0));
        let refocused = View { focus_distance: Some(3.0), ..Default::default() };
        let Sensor::ThinLens(t) = refocused.resolve(Some(lens)).unwrap() else { panic!() };
        assert_eq!((t.radius, t.focus_distance), (0.05, 3.0));
        let ortho =
            CameraDesc { kind: CameraKind::Orthographic { half_width: 2.0, half_height: 1.0 }, ..desc() };
        let Sensor::Orthographic(o) = plain.resolve(Some(ortho)).unwrap() else { panic!() };
        assert_eq!((o.half_width, o.half_height), (2.0, 1.0));
        // --ortho-width alone makes any camera orthographic; the height follows the 8x4 image.
        let wide = View { ortho_width: Some(6.0), ..Default::default() };
        let Sensor::Orthographic(o) = wide.resolve(Some(desc())).unwrap() else { panic!() };
        assert_eq!((o.half_width, o.half_height), (3.0, 1.5));
        // A perspective projection of the orthographic scene camera: its field of view.
        let persp = View { projection: Some(Projection::Perspective), ..Default::default() };
        assert!(matches!(persp.resolve(Some(ortho)).unwrap(), Sensor::Pinhole(_)));
        for refused in [
            View { fov: Some(30.0), ..Default::default() },
            View { lens_radius: Some(0.1), ..Default::default() },
        ] {
            let err = refused.resolve(Some(ortho)).unwrap_err();
            assert!(
                {
                    let mut s = err.to_string();
                    let mut e: &dyn std::error::Error = &err;
                    while let Some(x) = e.source() {
                        s += &x.to_string();
                        e = x;
                    }
                    s
                }
                .contains("orthographic"),
                "{err:#}"
            );
        }
        let needs_width = View { projection: Some(Projection::Orthographic), ..Default::default() };
        assert!(needs_width.resolve(Some(desc())).is_err());
        assert!(View { ortho_width: Some(1.0), ..persp }.check().is_err());
        assert!(View { ortho_width: Some(-1.0), ..Default::default() }.resolve(Some(desc())).is_err());
    }
}
