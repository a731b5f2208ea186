//! A step of the glTF pipeline: the camera chosen among the scene's cameras (by name, else the
//! lowest node index; the others are warnings) and converted to a [`CameraDesc`].

use super::Report;
use super::nodes::node_element;
use crate::scene_formats::SceneFileError;
use ::gltf::camera::Projection;
use opticks_core::math::{Mat4, Vec3};
use opticks_core::scene::{CameraDesc, CameraKind};
use opticks_core::sensor::{CameraError, Sensor};

/// Image height (and width without `aspectRatio`) of a glTF camera, pixels.
pub const DEFAULT_IMAGE_HEIGHT: u32 = 512;

/// A camera of the scene: its node, the camera, the node's world matrix.
pub struct Placed<'a> {
    /// The node the camera hangs on.
    pub node: ::gltf::Node<'a>,
    /// The camera.
    pub camera: ::gltf::Camera<'a>,
    /// The node's world matrix.
    pub world: Mat4,
}

/// The camera of the scene, among `cameras` (in node order): the one `wanted` names (its node's
/// name or its own; an error listing the cameras if none is), else the first. Every other
/// camera is a warning; `None` without cameras.
pub(super) fn choose_camera(
    cameras: &[Placed<'_>],
    wanted: Option<&str>,
    report: &mut Report,
) -> Result<Option<CameraDesc>, SceneFileError> {
    let pick = match wanted {
        Some(wanted) => {
            let named = |p: &&Placed<'_>| p.node.name() == Some(wanted) || p.camera.name() == Some(wanted);
            let Some(found) = cameras.iter().find(named) else {
                let names: Vec<String> = cameras.iter().map(|p| camera_names(&p.node, &p.camera)).collect();
                let has = if names.is_empty() {
                    "the scene has no camera".to_string()
                } else {
                    format!("the scene's cameras: {}", names.join(", "))
                };
                return Err(
                    report.invalid(format!("--camera {wanted:?}"), format!("no camera of that name ({has})"))
                );
            };
            Some(found)
        }
        None => cameras.first(),
    };
    let mut chosen = None;
    for entry in cameras {
        let cel = format!("{}: camera {}", node_element(&entry.node), entry.camera.index());
        if !pick.is_some_and(|p| std::ptr::eq(p, entry)) {
            let why = if wanted.is_some() {
                "not the one --camera names"
            } else {
                "another camera comes first (lowest node index; --camera NAME chooses another)"
            };
            report.warn(&cel, format!("{why}; ignored"));
            continue;
        }
        chosen = Some(convert(&entry.camera, entry.world).map_err(|m| report.invalid(cel, m))?);
    }
    Ok(chosen)
}

/// Why a glTF camera is not one Opticks can render through.
#[derive(Debug, thiserror::Error)]
enum ConvertError {
    /// An orthographic camera's half extents are not positive.
    #[error("orthographic xmag {xmag} and ymag {ymag} must be positive")]
    Orthographic { xmag: f32, ymag: f32 },
    /// The core's camera checks refuse the camera.
    #[error(transparent)]
    Camera(#[from] CameraError),
}

/// The camera `cam` at the world matrix `m`: it looks down its local −Z with +Y up; the image is
/// [`DEFAULT_IMAGE_HEIGHT`] pixels high and the projection gives its width. The core's camera
/// checks (field of view, axes, extent) apply.
fn convert(cam: &::gltf::Camera<'_>, m: Mat4) -> Result<CameraDesc, ConvertError> {
    let height = DEFAULT_IMAGE_HEIGHT;
    let (width, fov_x_degrees, kind) = match cam.projection() {
        Projection::Perspective(p) => {
            let aspect = p.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0);
            let width = aspect.map_or(height, |a| ((height as f32 * a).round() as u32).max(1));
            let fov_x = 2.0 * ((p.yfov() * 0.5).tan() * width as f32 / height as f32).atan();
            (width, fov_x.to_degrees(), CameraKind::Perspective)
        }
        Projection::Orthographic(o) => {
            // xmag, ymag: half the view's width and height.
            let (xmag, ymag) = (o.xmag().abs(), o.ymag().abs());
            if !(xmag.is_finite() && ymag.is_finite() && xmag > 0.0 && ymag > 0.0) {
                return Err(ConvertError::Orthographic { xmag, ymag });
            }
            let width = ((height as f32 * xmag / ymag).round() as u32).max(1);
            (width, 45.0, CameraKind::Orthographic { half_width: xmag, half_height: ymag })
        }
    };
    let eye = m.transform_point3(Vec3::ZERO);
    let forward = m.transform_vector3(-Vec3::Z).normalize_or_zero();
    let up = m.transform_vector3(Vec3::Y).normalize_or_zero();
    let camera = CameraDesc {
        eye,
        target: eye + forward,
        up,
        fov_x_degrees,
        width,
        height,
        kind,
        film: Default::default(),
    };
    Sensor::new(&camera)?;
    Ok(camera)
}

/// How a camera can be named: its node's name and the camera's own name, quoted.
fn camera_names(node: &::gltf::Node<'_>, cam: &::gltf::Camera<'_>) -> String {
    match (node.name(), cam.name()) {
        (Some(n), Some(c)) if n != c => format!("{n:?} (camera {c:?})"),
        (Some(n), _) => format!("{n:?}"),
        (None, Some(c)) => format!("{c:?}"),
        (None, None) => format!("node {} (unnamed)", node.index()),
    }
}
