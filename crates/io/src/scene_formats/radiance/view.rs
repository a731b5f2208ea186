//! The camera of a Radiance scene. A `.rad` file has no view (Radiance gives it to the renderer:
//! `rpict -vf view.vf` or `-vp … -vd …`), so the loader's `--camera` takes one: a view file, or
//! the view options themselves when the value starts with `-`. Options not given keep
//! Radiance's defaults (`-vtv -vp 0 0 0 -vd 0 1 0 -vu 0 0 1 -vh 45 -vv 45`). Without a view,
//! the camera looks at the scene's bounding box: from its centre toward north (+y) if the
//! centre is inside a room (surfaces all around facing it), else from outside, south-west and
//! above, as an overview ([`default_view`]).

use super::lexer::{NumberError, option_number};
use opticks_core::math::Vec3;
use opticks_core::scene::{CameraDesc, CameraKind, SceneDescription};

/// The image width of a Radiance view (its height follows `-vv`); `--size` overrides both.
pub const WIDTH: u32 = 512;

/// Why a Radiance view is not a camera Opticks has.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ViewError {
    /// An option's number is missing or not a number.
    #[error(transparent)]
    Number(#[from] NumberError),
    /// `-vo`, `-va`, `-vs` or `-vl` other than 0.
    #[error("{option} other than 0 (clipping planes, view shift and lift) is not supported")]
    NonZero {
        /// The option.
        option: String,
    },
    /// A view type other than `-vtv` and `-vtl`.
    #[error(
        "view type {option} is not supported (-vtv perspective and -vtl parallel are; fisheyes, cylindrical and planisphere views are not)"
    )]
    ViewType {
        /// The option (`-vth`, …).
        option: String,
    },
    /// An option this reader does not know.
    #[error("unsupported view option \"{option}\" (supported: -vtv, -vtl, -vp, -vd, -vu, -vh, -vv)")]
    Unsupported {
        /// The option.
        option: String,
    },
    /// `-vd` zero or along `-vu`.
    #[error("the view direction -vd must be non-zero and not along the up vector -vu")]
    Direction,
    /// A perspective view's angles outside (0, 180).
    #[error("a perspective view's -vh {vh} and -vv {vv} must be between 0 and 180 degrees")]
    Angles {
        /// `-vh`, degrees.
        vh: f64,
        /// `-vv`, degrees.
        vv: f64,
    },
    /// A parallel view's extents not positive.
    #[error("a parallel view's -vh {vh} and -vv {vv} (its width and height) must be positive")]
    Extents {
        /// `-vh`, the width.
        vh: f64,
        /// `-vv`, the height.
        vv: f64,
    },
}

/// A Radiance view (`-vt`, `-vp`, `-vd`, `-vu`, `-vh`, `-vv`; `-vo`, `-va`, `-vs`, `-vl` only
/// at 0) as a camera. The first word may be a program name (`rvu`, `rpict`), as in view files
/// Radiance writes; words may span lines.
pub fn parse_view(text: &str) -> Result<CameraDesc, ViewError> {
    let words: Vec<&str> = text.split_whitespace().collect();
    let mut i = usize::from(words.first().is_some_and(|w| !w.starts_with('-')));
    let (mut kind, mut vp, mut vd, mut vu) = ('v', [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    let (mut vh, mut vv) = (45.0, 45.0);
    let number = |i: usize, o: &str| option_number(&words, i, o);
    let vector = |i: usize, o: &str| -> Result<[f64; 3], NumberError> {
        Ok([number(i, o)?, number(i + 1, o)?, number(i + 2, o)?])
    };
    while i < words.len() {
        let o = words[i];
        match o {
            "-vp" | "-vd" | "-vu" => {
                let v = vector(i + 1, o)?;
                *match o {
                    "-vp" => &mut vp,
                    "-vd" => &mut vd,
                    _ => &mut vu,
                } = v;
                i += 4;
            }
            "-vh" | "-vv" => {
                *(if o == "-vh" { &mut vh } else { &mut vv }) = number(i + 1, o)?;
                i += 2;
            }
            "-vo" | "-va" | "-vs" | "-vl" => {
                if number(i + 1, o)? != 0.0 {
                    return Err(ViewError::NonZero { option: o.to_string() });
                }
                i += 2;
            }
            _ if o.starts_with("-vt") && o.len() == 4 => {
                kind = o.as_bytes()[3] as char;
                if kind != 'v' && kind != 'l' {
                    return Err(ViewError::ViewType { option: o.to_string() });
                }
                i += 1;
            }
            _ => {
                return Err(ViewError::Unsupported { option: o.to_string() });
            }
        }
    }
    let v = |a: [f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
    let (eye, dir, up) = (v(vp), v(vd), v(vu));
    if dir.length() == 0.0 || dir.cross(up).length() == 0.0 {
        return Err(ViewError::Direction);
    }
    let (height, kind, fov) = if kind == 'v' {
        if !(vh > 0.0 && vh < 180.0 && vv > 0.0 && vv < 180.0) {
            return Err(ViewError::Angles { vh, vv });
        }
        let ratio = (vv.to_radians() / 2.0).tan() / (vh.to_radians() / 2.0).tan();
        (WIDTH as f64 * ratio, CameraKind::Perspective, vh)
    } else {
        if !(vh > 0.0 && vv > 0.0) {
            return Err(ViewError::Extents { vh, vv });
        }
        let kind = CameraKind::Orthographic { half_width: (vh / 2.0) as f32, half_height: (vv / 2.0) as f32 };
        (WIDTH as f64 * vv / vh, kind, 45.0)
    };
    let height = height.round().clamp(1.0, 32768.0) as u32;
    Ok(CameraDesc {
        eye,
        target: eye + dir.normalize(),
        up,
        fov_x_degrees: fov as f32,
        width: WIDTH,
        height,
        kind,
        film: Default::default(),
    })
}

/// The camera of a scene without a view, +z up (Radiance's convention), 512 × 512. If the
/// centre of the bounding box is inside a room — along each of ±x, ±y, ±z the nearest surface
/// faces it with its front, as walls modelled facing into the room do — the eye is there, looking north (+y), 90° across. Otherwise it
/// is an overview: from the south-west (−x, −y, Radiance's north being +y), above, aimed at
/// the centre, 45° across, far enough for the bounding sphere to fit. `None` for a scene
/// without geometry.
pub fn default_view(desc: &SceneDescription) -> Option<CameraDesc> {
    let mut points = desc.meshes.iter().flat_map(|m| m.positions.iter().copied());
    let first = points.next()?;
    let (lo, hi) = points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
    let centre = (lo + hi) * 0.5;
    let camera = |eye: Vec3, target: Vec3, fov_x_degrees: f32| CameraDesc {
        eye,
        target,
        up: Vec3::Z,
        fov_x_degrees,
        width: WIDTH,
        height: WIDTH,
        kind: CameraKind::Perspective,
        film: Default::default(),
    };
    if enclosed(desc, centre) {
        return Some(camera(centre, centre + Vec3::Y, 90.0));
    }
    let radius = ((hi - lo).length() * 0.5).max(1e-3);
    let dir = Vec3::new(-1.0, -1.5, 1.0).normalize();
    let distance = radius / (22.5f32).to_radians().sin();
    Some(camera(centre + dir * distance, centre, 45.0))
}

/// Whether `p` is inside a room: along each of ±x, ±y and ±z, the nearest surface a ray from
/// `p` meets faces `p` with its front (one pass over the triangles).
fn enclosed(desc: &SceneDescription, p: Vec3) -> bool {
    let axes = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let mut nearest = [(f32::INFINITY, false); 6];
    for m in &desc.meshes {
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            for (d, n) in axes.iter().zip(&mut nearest) {
                if let Some(hit) = crossing(p, *d, a, b, c).filter(|h| h.0 < n.0) {
                    *n = hit;
                }
            }
        }
    }
    nearest.iter().all(|&(t, front)| t.is_finite() && front)
}

/// Where the ray p + t·d, t > 0, crosses the triangle (a, b, c) (Möller–Trumbore): t, and
/// whether the ray meets its front (counter-clockwise) side.
fn crossing(p: Vec3, d: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<(f32, bool)> {
    let (e1, e2) = (b - a, c - a);
    let q = d.cross(e2);
    let det = e1.dot(q);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = (p - a) / det;
    let u = s.dot(q);
    let r = s.cross(e1);
    let v = d.dot(r);
    let t = e2.dot(r);
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then(|| (t, e1.cross(e2).dot(d) < 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_options_and_defaults() {
        let c = parse_view("rvu -vtv -vp 1 2 1.5 -vd 0 1 0 -vu 0 0 1 -vh 60 -vv 40 -vo 0 -va 0").unwrap();
        assert_eq!((c.eye, c.target, c.up), (Vec3::new(1.0, 2.0, 1.5), Vec3::new(1.0, 3.0, 1.5), Vec3::Z));
        assert_eq!(c.fov_x_degrees, 60.0);
        let expected = 512.0 * (20f64.to_radians().tan() / 30f64.to_radians().tan());
        assert_eq!(c.height, expected.round() as u32);
        let d = parse_view("-vp 0 0 1").unwrap();
        assert_eq!((d.target, d.width, d.height), (Vec3::new(0.0, 1.0, 1.0), 512, 512));
        let l = parse_view("-vtl -vh 4 -vv 2").unwrap();
        assert_eq!(l.kind, CameraKind::Orthographic { half_width: 2.0, half_height: 1.0 });
        assert_eq!(l.height, 256);
        let e = |s: &str| parse_view(s).unwrap_err();
        assert!(e("-vta").to_string().starts_with("view type -vta is not supported"));
        assert_eq!(e("-vs 0.1"), ViewError::NonZero { option: "-vs".into() });
        assert!(e("-vf x.vf").to_string().starts_with("unsupported view option \"-vf\""));
        assert_eq!(e("-vd 0 0 1"), ViewError::Direction);
        assert!(e("-vd 0 0 1").to_string().contains("up vector"));
        assert_eq!(e("-vp 1 2").to_string(), "-vp needs a number");
        assert_eq!(e("-vh x").to_string(), "-vh: \"x\" is not a number");
        assert_eq!(e("-vh 180"), ViewError::Angles { vh: 180.0, vv: 45.0 });
    }
}
