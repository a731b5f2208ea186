//! `<sensor>` and its `<film>`: the camera. [`SENSOR_TYPES`] maps each supported Mitsuba
//! sensor type to its builder; adding one is an entry there and its function.
//!
//! Mitsuba's camera looks along local +z with +y up and local +x to the image left; a
//! [`CameraDesc`] has an eye, a target and an up vector. For the perspective cameras
//! (`perspective`, `thinlens`) `to_world` must be a rotation (a mirror is refused, scale or
//! shear warned about) and the target is taken at the last `<lookat>`'s distance; the field of
//! view is converted to the horizontal angle the core wants with Mitsuba's own `fov_axis` rules
//! ([`fov_to_x`]). The `orthographic` camera's film is [-1, 1] × [-1/aspect, 1/aspect] of local
//! x and y at its near plane (aspect = width/height), mapped by `to_world`, whose scale
//! therefore sizes the film ([`orthographic_film`]).
//!
//! The `<film>` gives the image size, a crop window and the reconstruction filter
//! ([`FilmSpec`]); every projection is the full film's, the image the crop window's, as in
//! Mitsuba. A film without `<rfilter>` keeps Opticks's box filter (with a warning; Mitsuba's
//! default is the gaussian): the box is the exact pixel average and the fast path, and
//! every image rendered from such files so far stays the same.

use super::Result;
use super::build::Builder;
use super::properties::Props;
use super::transform::Transform;
use super::xml::Element;
use glam::{DMat3, DVec3};
use opticks_core::scene::{CameraDesc, CameraKind};
use opticks_core::sensor::{
    Crop, FilmSpec, Filter, MAX_IMAGE_SIDE, Raster, check_fov, check_image_size, check_lens,
};

/// A sensor builder: the `<sensor>` element and its properties.
type BuildSensor = for<'d> fn(&mut Builder<'d>, &'d Element, Props<'d>) -> Result<CameraDesc>;

/// The supported sensor types.
const SENSOR_TYPES: &[(&str, BuildSensor)] =
    &[("perspective", perspective), ("thinlens", thinlens), ("orthographic", orthographic)];

/// Mitsuba's default film size.
const DEFAULT_FILM: (u32, u32) = (768, 576);

/// Mitsuba's default clip planes (`near_clip`, `far_clip`), in camera-space units.
const DEFAULT_CLIP: (f64, f64) = (1e-2, 1e4);

/// The camera of a `<sensor>`.
pub fn sensor<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<CameraDesc> {
    let ty = e.required("type")?;
    let Some((_, build)) = SENSOR_TYPES.iter().find(|(name, _)| *name == ty) else {
        let names: Vec<&str> = SENSOR_TYPES.iter().map(|(name, _)| *name).collect();
        return Err(e.err(format!("unsupported sensor type \"{ty}\" (supported: {})", names.join(", "))));
    };
    build(b, e, Props::of(e)?)
}

/// The sensor's nested objects: its `<film>` (the image size, crop and filter) and samplers,
/// inline or by `<ref>`.
fn film_of<'d>(b: &mut Builder<'d>, p: &Props<'d>) -> Result<(u32, u32, FilmSpec)> {
    let (mut width, mut height) = DEFAULT_FILM;
    let mut spec = FilmSpec::default();
    for &c in p.objects() {
        match c.tag.as_str() {
            "film" => (width, height, spec) = film(b, c)?,
            "sampler" => {}
            // A reference to a top-level sampler (Mitsuba accepts a <ref> wherever an object
            // goes); films are read inline only.
            "ref" => match c.target.map(|i| b.doc.top(i)) {
                Some(t) if t.tag == "sampler" => {
                    b.used.insert(c.required("id")?.to_string());
                }
                Some(t) => {
                    return Err(c.err(format!(
                        "a <ref> inside <sensor> may name a <sampler>; this one names a <{}> (at {})",
                        t.tag, t.at
                    )));
                }
                None => {
                    return Err(
                        c.attr_err("id", format!("reference to unknown id \"{}\"", c.required("id")?))
                    );
                }
            },
            other => {
                return Err(c.err(format!(
                    "unsupported element <{other}> inside <sensor> (supported: film, sampler, ref to a sampler)"
                )));
            }
        }
    }
    Ok((width, height, spec))
}

fn perspective<'d>(b: &mut Builder<'d>, e: &'d Element, p: Props<'d>) -> Result<CameraDesc> {
    projective(b, e, p, false)
}

/// `thinlens`: a perspective camera with `aperture_radius` (required, as in Mitsuba; 0 is a
/// pinhole, where Mitsuba takes a radius of machine epsilon) and `focus_distance` (default
/// `far_clip`, Mitsuba's), the distance from the lens to the plane in focus along the axis.
fn thinlens<'d>(b: &mut Builder<'d>, e: &'d Element, p: Props<'d>) -> Result<CameraDesc> {
    projective(b, e, p, true)
}

/// The perspective cameras: the field of view (`fov` with `fov_axis`, or `focal_length`),
/// `to_world`, and for the thin lens its aperture and focus.
fn projective<'d>(b: &mut Builder<'d>, e: &'d Element, mut p: Props<'d>, lens: bool) -> Result<CameraDesc> {
    let (width, height, film) = film_of(b, &p)?;
    let fov = p.float("fov")?;
    let focal = p.string("focal_length")?;
    let axis = p.string("fov_axis")?;
    let (fov, axis_name, fov_node) = match (fov, focal) {
        (Some(_), Some((_, fnode))) => {
            return Err(fnode.err("give either `fov` or `focal_length`, not both"));
        }
        (Some((f, node)), None) => {
            let axis = axis.as_ref().map_or("x".to_string(), |(a, _)| a.to_ascii_lowercase());
            (f, axis, node)
        }
        (None, focal) => {
            let (s, node) = focal.map_or(("50mm".to_string(), e), |(s, node)| (s, node));
            let mm = node.number("value", s.trim().trim_end_matches("mm"))?;
            if mm <= 0.0 {
                return Err(node.err(format!("focal length {s} must be positive")));
            }
            // 35 mm film: 36×24 mm; Mitsuba measures this fov along the diagonal.
            let f = 2.0 * (36f64.hypot(24.0) / (2.0 * mm)).atan().to_degrees();
            (f, "diagonal".to_string(), node)
        }
    };
    check_fov(fov as f32).map_err(|err| fov_node.err(err.to_string()))?;
    let fov_x = fov_to_x(fov, &axis_name, width, height).ok_or_else(|| {
        let node = axis.as_ref().map_or(e, |(_, node)| *node);
        node.err(format!("unsupported fov_axis \"{axis_name}\" (supported: x, y, smaller, larger, diagonal)"))
    })?;
    let kind = if lens {
        let (radius, rnode) = p.float("aperture_radius")?.ok_or_else(|| {
            e.err("a thinlens sensor needs `aperture_radius` (Mitsuba has no default for it)")
        })?;
        let far = p.float("far_clip")?.map_or(DEFAULT_CLIP.1, |(f, _)| f);
        let (focus, fnode) = p.float_or("focus_distance", far)?;
        check_lens(radius as f32, 1.0).map_err(|err| rnode.err(format!("aperture_radius: {err}")))?;
        check_lens(0.0, focus as f32).map_err(|err| fnode.err(format!("focus_distance: {err}")))?;
        CameraKind::ThinLens { aperture_radius: radius as f32, focus_distance: focus as f32 }
    } else {
        CameraKind::Perspective
    };
    p.ignore(&["near_clip", "far_clip", "shutter_open", "shutter_close"]);
    let (t, tnode) = p.transform("to_world")?.unwrap_or((Transform::IDENTITY, e));
    check_camera_frame(b, &t, tnode)?;
    let m = t.matrix;
    let eye = m.transform_point3(DVec3::ZERO);
    let target = m.transform_point3(DVec3::new(0.0, 0.0, t.focus.unwrap_or(1.0)));
    let up = m.transform_vector3(DVec3::Y);
    b.finish(&p);
    Ok(CameraDesc {
        eye: eye.as_vec3(),
        target: target.as_vec3(),
        up: up.as_vec3(),
        fov_x_degrees: fov_x as f32,
        width,
        height,
        kind,
        film,
    })
}

/// `orthographic`: parallel rays along `to_world`'s local +z from its film
/// ([`orthographic_film`]), which starts at the near plane as Mitsuba's rays do.
fn orthographic<'d>(b: &mut Builder<'d>, e: &'d Element, mut p: Props<'d>) -> Result<CameraDesc> {
    let (width, height, film) = film_of(b, &p)?;
    let (near, nnode) = p.float_or("near_clip", DEFAULT_CLIP.0)?;
    if !(near.is_finite() && near > 0.0) {
        return Err(nnode.err(format!("near_clip {near} must be a finite number > 0 (as in Mitsuba)")));
    }
    p.ignore(&["far_clip", "shutter_open", "shutter_close"]);
    let (t, tnode) = p.transform("to_world")?.unwrap_or((Transform::IDENTITY, e));
    let (eye, forward, up, half_width, half_height) = orthographic_film(&t, near, width, height, tnode)?;
    b.finish(&p);
    Ok(CameraDesc {
        eye: eye.as_vec3(),
        target: (eye + forward * t.focus.unwrap_or(1.0)).as_vec3(),
        up: up.as_vec3(),
        // Not used by the orthographic camera; a perspective view of it (`--projection
        // perspective`) starts from the default of a camera given on the command line.
        fov_x_degrees: 45.0,
        width,
        height,
        kind: CameraKind::Orthographic { half_width: half_width as f32, half_height: half_height as f32 },
        film,
    })
}

/// The orthographic camera's film in the world for a `width`×`height` image: its centre (on
/// the near plane, local z = `near`), the unit view direction, the unit up direction and the
/// half width and height. Local x ∈ [-1, 1] and y ∈ [-1/aspect, 1/aspect] (Mitsuba's
/// `orthographic_projection`) are mapped by `to_world`, which must be affine, not a mirror, and
/// keep the three axes perpendicular (a rotation with scale; a shear would make the film a
/// parallelogram or slant the rays to it, which Opticks's camera cannot do).
pub fn orthographic_film(
    t: &Transform,
    near: f64,
    width: u32,
    height: u32,
    tnode: &Element,
) -> Result<(DVec3, DVec3, DVec3, f64, f64)> {
    let m = t.matrix;
    if m.row(3) != glam::DVec4::W {
        return Err(tnode.err("a camera's to_world must be affine (last matrix row 0, 0, 0, 1)"));
    }
    let lin = DMat3::from_mat4(m);
    let det = lin.determinant();
    if !(det.is_finite() && det != 0.0) {
        return Err(tnode.err("the camera's to_world is singular"));
    }
    if det < 0.0 {
        return Err(tnode.err(
            "the camera's to_world mirrors space (negative determinant): the image would be flipped, \
             which Opticks cameras cannot do",
        ));
    }
    let (x, y, z) = (lin.x_axis, lin.y_axis, lin.z_axis);
    let cos = |a: DVec3, b: DVec3| a.dot(b) / (a.length() * b.length());
    if [cos(x, y), cos(x, z), cos(y, z)].iter().any(|c| c.abs() > 1e-4) {
        return Err(tnode.err(
            "an orthographic camera's to_world must keep its axes perpendicular (a rotation with \
             scale): this one shears, which Opticks's orthographic camera cannot do",
        ));
    }
    let aspect = width as f64 / height as f64;
    let eye = m.transform_point3(DVec3::new(0.0, 0.0, near));
    Ok((eye, z.normalize(), y.normalize(), x.length(), y.length() / aspect))
}

/// Physical check of a camera's `to_world` (at `tnode`): affine, not singular, not a mirror
/// (which would flip the image left-right); scale or shear is a warning (only directions are
/// used).
fn check_camera_frame(b: &mut Builder, t: &Transform, tnode: &Element) -> Result<()> {
    let m = t.matrix;
    let lin = DMat3::from_mat4(m);
    let det = lin.determinant();
    if m.row(3) != glam::DVec4::W {
        return Err(tnode.err("a camera's to_world must be affine (last matrix row 0, 0, 0, 1)"));
    }
    if det == 0.0 {
        return Err(tnode.err("the camera's to_world is singular"));
    }
    if det < 0.0 {
        return Err(tnode.err(
            "the camera's to_world mirrors space (negative determinant): the image would be flipped \
             left-right, which Opticks cameras cannot do; use a <lookat> or a rotation",
        ));
    }
    let ortho = (lin.transpose() * lin - DMat3::IDENTITY).to_cols_array().iter().all(|e| e.abs() < 1e-4);
    if !ortho {
        b.warn(
            tnode,
            "the camera's to_world contains scale or shear (Mitsuba refuses this); only its directions are used",
        );
    }
    Ok(())
}

/// `<film type="hdrfilm">`: the image size, the crop window (`crop_offset_x`, `crop_offset_y`,
/// `crop_width`, `crop_height`: pixels of the full film; the size defaults to the film's, and the
/// window must lie within it, as in Mitsuba) and the `<rfilter>` ([`rfilter`]).
fn film<'d>(b: &mut Builder<'d>, e: &'d Element) -> Result<(u32, u32, FilmSpec)> {
    let ty = e.required("type")?;
    if ty != "hdrfilm" {
        return Err(e.err(format!("unsupported film type \"{ty}\" (supported: hdrfilm)")));
    }
    let mut p = Props::of(e)?;
    let mut size = [DEFAULT_FILM.0, DEFAULT_FILM.1];
    for (s, name) in size.iter_mut().zip(["width", "height"]) {
        if let Some((v, node)) = p.int(name)? {
            // The core's one rule for image sizes, checked here where the file gives them.
            *s = u32::try_from(v).ok().filter(|&v| check_image_size(v, 1).is_ok()).ok_or_else(|| {
                node.err(format!("{name} {v} must be an integer from 1 to {MAX_IMAGE_SIDE}"))
            })?;
        }
    }
    let mut crop = [0, 0, size[0], size[1]];
    let mut crop_node = None;
    for (k, name) in ["crop_offset_x", "crop_offset_y", "crop_width", "crop_height"].iter().enumerate() {
        if let Some((v, node)) = p.int(name)? {
            crop[k] = u32::try_from(v)
                .map_err(|_| node.err(format!("{name} {v} must be a non-negative integer (pixels)")))?;
            crop_node = Some(node);
        }
    }
    p.ignore(&[
        "pixel_format",
        "component_format",
        "file_format",
        "banner",
        "high_quality_edges",
        "sample_border",
    ]);
    let mut filter = None;
    for &c in p.objects() {
        match c.tag.as_str() {
            "rfilter" if filter.is_some() => return Err(c.err("a <film> takes one <rfilter>")),
            "rfilter" => filter = Some(rfilter(b, c)?),
            other => {
                return Err(
                    c.err(format!("unsupported element <{other}> inside <film> (supported: rfilter)"))
                );
            }
        }
    }
    if filter.is_none() {
        b.warn(
            e,
            "no <rfilter>: Opticks uses the box filter (Mitsuba's default is \"gaussian\"; \
             add <rfilter type=\"gaussian\"/> for Mitsuba's image)",
        );
    }
    let crop = crop_node.map(|_| Crop { x: crop[0], y: crop[1], width: crop[2], height: crop[3] });
    let spec = FilmSpec { crop, filter: filter.unwrap_or_default() };
    // The core's rule for the window, checked here where the file gives it.
    Raster::new(size[0], size[1], spec).map_err(|err| crop_node.unwrap_or(e).err(err.to_string()))?;
    b.finish(&p);
    Ok((size[0], size[1], spec))
}

/// `<rfilter>`: `box`, `tent` (`radius`, default 1 pixel) or `gaussian` (`stddev`, default ½
/// pixel), Mitsuba's filters and defaults; others are refused.
fn rfilter<'d>(b: &mut Builder<'d>, c: &'d Element) -> Result<Filter> {
    let ty = c.required("type")?;
    let mut p = Props::of(c)?;
    let (filter, node) = match ty {
        "box" => (Filter::Box, c),
        "tent" => {
            let (radius, node) = p.float_or("radius", 1.0)?;
            (Filter::Tent { radius: radius as f32 }, node)
        }
        "gaussian" => {
            let (stddev, node) = p.float_or("stddev", 0.5)?;
            (Filter::Gaussian { stddev: stddev as f32 }, node)
        }
        other => {
            return Err(c.attr_err(
                "type",
                format!("unsupported reconstruction filter \"{other}\" (supported: box, tent, gaussian)"),
            ));
        }
    };
    filter.check().map_err(|err| node.err(err.to_string()))?;
    b.finish(&p);
    Ok(filter)
}

/// The horizontal full angle (degrees) for a full angle `fov` along `axis`, as Mitsuba's
/// `parse_fov` computes it. `None` for an unknown axis.
pub fn fov_to_x(fov: f64, axis: &str, width: u32, height: u32) -> Option<f64> {
    let aspect = width as f64 / height as f64;
    let axis = match axis {
        "smaller" => {
            if aspect > 1.0 {
                "y"
            } else {
                "x"
            }
        }
        "larger" => {
            if aspect > 1.0 {
                "x"
            } else {
                "y"
            }
        }
        a => a,
    };
    let half = (0.5 * fov).to_radians();
    match axis {
        "x" => Some(fov),
        "y" => Some(2.0 * (half.tan() * aspect).atan().to_degrees()),
        "diagonal" => {
            let diagonal = 2.0 * half.tan();
            let w = diagonal / (1.0 + 1.0 / (aspect * aspect)).sqrt();
            Some(2.0 * (0.5 * w).atan().to_degrees())
        }
        _ => None,
    }
}
