//! VRML97 `Viewpoint` (and the extension's `PhysicalViewpoint`) → the scene's camera: the first
//! Viewpoint, or the one `--camera` names by `description` or DEF name, placed by the transform
//! stack, its `fieldOfView` taken along the image's smaller side, and checked by the core's
//! camera rules. Kept apart from the walk in [`super::convert`], which only hands Viewpoints
//! over.

use super::convert::{Converter, DEFAULT_IMAGE_SIZE, Result, dv, rotation};
use super::tree::{FieldValue, Node};
use glam::{DMat4, DVec3};
use opticks_core::scene::{CameraDesc, CameraKind};
use opticks_core::sensor::Pinhole;

impl Converter {
    #[inline(never)] // keeps the recursive walk's stack frame small
    pub(super) fn viewpoint(&mut self, n: &Node, m: &DMat4) -> Result<()> {
        if let Some(wanted) = &self.wanted_viewpoint {
            // Chosen by `--camera`: its `description`, or its DEF name.
            let description = match n.get("description") {
                Some(FieldValue::Str(d)) => Some(d.as_str()),
                _ => None,
            };
            let names: Vec<&str> = description.into_iter().chain(n.def_name.as_deref()).collect();
            let picked = names.contains(&wanted.as_str()) && self.out.camera.is_none();
            if !picked {
                if let Some(name) = names.first() {
                    self.viewpoint_names.push(format!("{name:?}"));
                }
                return Ok(());
            }
        } else if self.out.camera.is_some() {
            self.extra_viewpoints += 1;
            return Ok(());
        }
        let (position, orientation, fov, width, height) = match self.extension(n, "PhysicalViewpoint") {
            Some(p) => {
                let int = |k: &str| match p.get(k) {
                    Some(FieldValue::Int(v)) => *v,
                    _ => DEFAULT_IMAGE_SIZE as i32,
                };
                (
                    p.get("position").and_then(FieldValue::as_vec3).unwrap_or([0.0, 0.0, 10.0]),
                    match p.get("orientation") {
                        Some(FieldValue::Rotation(r)) => *r,
                        _ => [0.0, 0.0, 1.0, 0.0],
                    },
                    p.get("fieldOfView")
                        .and_then(FieldValue::as_float)
                        .unwrap_or(std::f32::consts::FRAC_PI_4),
                    int("width"),
                    int("height"),
                )
            }
            None => (
                n.vec3("position", [0.0, 0.0, 10.0]),
                n.rotation("orientation", [0.0, 0.0, 1.0, 0.0]),
                n.float("fieldOfView", std::f32::consts::FRAC_PI_4),
                DEFAULT_IMAGE_SIZE as i32,
                DEFAULT_IMAGE_SIZE as i32,
            ),
        };
        let size = (u32::try_from(width), u32::try_from(height));
        let (Ok(width), Ok(height)) = size else {
            return Err(self.invalid(n, format!("image size {width}x{height} must be positive")));
        };
        // The core's one rule for image sizes, before anything is sized by them.
        opticks_core::sensor::check_image_size(width, height).map_err(|e| self.invalid(n, e.to_string()))?;
        let q = rotation(orientation);
        let eye = m.transform_point3(dv(position));
        let forward = m.transform_vector3(q * DVec3::NEG_Z).normalize_or_zero();
        let up = m.transform_vector3(q * DVec3::Y).normalize_or_zero();
        if m.determinant() < 0.0 {
            self.warn(n, "a mirroring transform: the image is not mirrored");
        }
        // fieldOfView is the angle along the smaller image side.
        let fov = f64::from(fov);
        let aspect = f64::from(width) / f64::from(height);
        let fov_x = if width <= height { fov } else { 2.0 * ((fov / 2.0).tan() * aspect).atan() };
        let camera = CameraDesc {
            eye: eye.as_vec3(),
            target: (eye + forward).as_vec3(),
            up: up.as_vec3(),
            fov_x_degrees: fov_x.to_degrees() as f32,
            width,
            height,
            kind: CameraKind::Perspective,
            film: Default::default(),
        };
        // The core's camera checks (image size, field of view, axes), reported at the node.
        Pinhole::new(&camera).map_err(|e| self.invalid(n, e.to_string()))?;
        self.out.camera = Some(camera);
        Ok(())
    }
}
