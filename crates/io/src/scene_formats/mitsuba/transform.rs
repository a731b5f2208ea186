//! `<transform>` properties: the composed matrix of `<translate>`, `<scale>`, `<rotate>`,
//! `<lookat>` and `<matrix>` elements, each applied after the ones before it (M ← T·M), as in
//! Mitsuba. Shapes, the sensor and the emitters read their `to_world` through
//! [`super::properties::Props::transform`].

use super::Result;
use super::xml::Element;
use glam::{DMat3, DMat4, DVec3};

/// A composed `<transform>`: the matrix and the distance to the last `<lookat>`'s target.
#[derive(Clone, Copy, Debug)]
pub struct Transform {
    /// Object-to-world.
    pub matrix: DMat4,
    /// |target − origin| of the last `<lookat>`, if any (a camera's focus distance).
    pub focus: Option<f64>,
}

impl Transform {
    /// The identity (no `to_world`).
    pub const IDENTITY: Transform = Transform { matrix: DMat4::IDENTITY, focus: None };
}

/// Mitsuba's `<rotate>` matrix: Rodrigues' formula c·I + (1 − c)·a·aᵀ + s·[a]× with the axis
/// `a` **as given** — Mitsuba 3 does not normalise it (`Transform4f::rotate`), so an axis such
/// as `y="1" z="1"` also scales and shears, and a scene written for Mitsuba means that matrix
/// (its `scenes/hello.xml` does it; normalising the axis moved its teapot).
fn rotation(a: DVec3, radians: f64) -> DMat4 {
    let (s, c) = radians.sin_cos();
    let outer = DMat3::from_cols(a * a.x, a * a.y, a * a.z);
    let cross =
        DMat3::from_cols(DVec3::new(0.0, a.z, -a.y), DVec3::new(-a.z, 0.0, a.x), DVec3::new(a.y, -a.x, 0.0));
    DMat4::from_mat3(DMat3::IDENTITY * c + outer * (1.0 - c) + cross * s)
}

/// The transform described by the children of the `<transform>` element `e`.
pub fn read(e: &Element) -> Result<Transform> {
    let mut m = DMat4::IDENTITY;
    let mut focus = None;
    for c in &e.children {
        let t = match c.tag.as_str() {
            "translate" => DMat4::from_translation(c.xyz(0.0, false)?),
            "scale" => DMat4::from_scale(c.xyz(1.0, true)?),
            "rotate" => {
                let axis = match c.vec3_attr("value")? {
                    Some(a) => a,
                    None => c.xyz(0.0, false)?,
                };
                let angle = c.float_attr("angle")?.ok_or_else(|| c.err("missing attribute `angle`"))?;
                if axis.length_squared() == 0.0 {
                    return Err(c.err("the rotation axis is zero (give x, y, z or value=\"x, y, z\")"));
                }
                rotation(axis, angle.to_radians())
            }
            "lookat" => {
                let (matrix, distance) = lookat(c)?;
                focus = Some(distance);
                matrix
            }
            "matrix" => {
                let s = c.required("value")?;
                let v = c.numbers("value", s)?;
                match v.len() {
                    16 => DMat4::from_cols_slice(&v).transpose(),
                    9 => DMat4::from_mat3(DMat3::from_cols_slice(&v).transpose()),
                    k => {
                        return Err(c.attr_err(
                            "value",
                            format!("a matrix needs 16 numbers (row-major 4×4) or 9 (3×3), found {k}"),
                        ));
                    }
                }
            }
            other => {
                return Err(c.err(format!(
                    "unsupported transform element <{other}> (supported: translate, scale, rotate, lookat, matrix)"
                )));
            }
        };
        m = t * m;
        if !m.is_finite() {
            return Err(c.err("the transform overflows (non-finite matrix)"));
        }
    }
    Ok(Transform { matrix: m, focus })
}

/// `<lookat origin target up>`: Mitsuba's camera frame (local +z toward the target, +y up,
/// +x = up × direction, the image left) and the distance to the target.
fn lookat(c: &Element) -> Result<(DMat4, f64)> {
    let origin = c.vec3_attr("origin")?.ok_or_else(|| c.err("missing attribute `origin`"))?;
    let target = c.vec3_attr("target")?.ok_or_else(|| c.err("missing attribute `target`"))?;
    let up = c.vec3_attr("up")?;
    let d = target - origin;
    if d.length() == 0.0 {
        return Err(c.err("origin and target are the same point"));
    }
    let dir = d.normalize();
    let up = up.unwrap_or_else(|| coordinate_system(dir).1);
    let left = up.cross(dir);
    if left.length() <= 1e-9 * up.length() {
        return Err(c.err("`up` is zero or parallel to the view direction"));
    }
    let left = left.normalize();
    let new_up = dir.cross(left);
    let m = DMat4::from_cols(left.extend(0.0), new_up.extend(0.0), dir.extend(0.0), origin.extend(1.0));
    Ok((m, d.length()))
}

/// Mitsuba's `coordinate_system` (Duff et al. 2017): two unit vectors completing `n` to an
/// orthonormal basis; `<lookat>` without `up` uses the second.
fn coordinate_system(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), DVec3::new(b, sign + n.y * n.y * a, -n.y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_unit_axis_rotates_and_a_longer_one_is_taken_as_mitsuba_takes_it() {
        let axis = DVec3::new(0.3, -0.5, 0.8).normalize();
        let m = rotation(axis, 0.7);
        assert!(m.abs_diff_eq(DMat4::from_axis_angle(axis, 0.7), 1e-12), "{m}");
        // Mitsuba 3.9.1: `ScalarTransform4f().rotate([0, 1, 1], 15).matrix`, row by row.
        let mitsuba =
            [[0.965926, -0.258819, 0.258819], [0.258819, 1.0, 0.0340742], [-0.258819, 0.0340742, 1.0]];
        let m = rotation(DVec3::new(0.0, 1.0, 1.0), 15f64.to_radians());
        for (r, row) in mitsuba.iter().enumerate() {
            for (c, want) in row.iter().enumerate() {
                assert!((m.col(c)[r] - want).abs() < 1e-6, "({r}, {c}): {} ≠ {want}", m.col(c)[r]);
            }
        }
    }
}
