//! Where camera subpaths start: a ray through a pixel of each sensor, with the image-wide
//! solid-angle density of its direction (`docs/bidirectional.md` §3) and its starting
//! throughput W_e·cos/p, and the same density for a given direction, which the light-tracing
//! splat's MIS weight needs ([`image_pdf`]).
//!
//! Every camera samples its film point uniformly over the pixel's square of (s_x, s_y) (the box
//! filter of docs/estimator.md §6) or, with another reconstruction filter, from the normalised
//! filter f̂ around the pixel's centre (`crate::sensor::raster`): the pixel's importance and
//! the ray's density then both carry f̂, so the throughput below is unchanged and the density is
//! the one below times f̂ (the density of the pixel's rays; the splat's MIS weight takes the same
//! factor for each pixel it reaches). The crop window only moves the pixels on the full film,
//! whose projection stays the camera's. The thin lens its lens point uniformly on the aperture
//! as its splat does (`ThinLens::connect` with a hashed point), so the lens density cancels in
//! every weight. The image-wide density is the per-pixel density divided by W·H:
//!
//! * pinhole and thin lens: 1/(A·cos³θ), A = 4·tan(fov_x/2)·tan(fov_y/2) the image's area at
//!   unit distance, θ between the ray and the axis (from the lens point: the film maps to the
//!   plane of focus, dω = cos³θ·dA from every lens point, `thin_lens.rs`). The starting
//!   throughput is 1: a pixel reads the radiance averaged over its film square.
//! * equirectangular: film (s_x, s_y) uniform is (longitude, latitude) uniform over
//!   2π × π, so 1/(2π²·sin θ) with θ the polar angle from `up`; the pixel reads the radiance
//!   averaged over its solid angle Ω_j (`equirect.rs`), so the throughput is
//!   W_e·cos/p = (2π²/(W·H))·sin θ/Ω_j, which averages to 1 over the pixel.
//! * orthographic: the ray's origin is uniform over the film, area density 1/(4h_x·h_y), its
//!   direction fixed ([`CameraPdf::Area`]); a pixel reads the radiance averaged over its film
//!   rectangle, so the throughput is 1.

use super::super::Sensor;
use super::CameraPdf;
use crate::math::{Vec2, Vec3};
use std::f32::consts::PI;

/// The start of a camera subpath.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraRay {
    /// The point on the sensor (eye, or lens point).
    pub origin: Vec3,
    /// Unit direction into the scene.
    pub dir: Vec3,
    /// The image-wide density of the ray ([`image_pdf`]).
    pub pdf: CameraPdf,
    /// W_e·cos/p: the factor on the radiance arriving along the ray.
    pub throughput: f32,
}

/// The ray of image pixel (`i`, `j`) (of the crop window) through its film point `u_film` ∈
/// [0,1)² (relative to the pixel's corner for the box, the filter's sample otherwise), from the
/// lens point `u_lens` ∈ [0,1)² (thin lens only).
#[inline]
pub fn camera_ray(sensor: &Sensor, i: u32, j: u32, u_film: Vec2, u_lens: Vec2) -> CameraRay {
    let raster = sensor.raster();
    let (w, h) = (raster.full_width as f32, raster.full_height as f32);
    let (sx, sy, filter) = if raster.is_box() {
        let (x, y) = (raster.window.x + i, raster.window.y + j);
        ((x as f32 + u_film.x) / w, (y as f32 + u_film.y) / h, 1.0)
    } else {
        let d = raster.filter.sample(u_film);
        let (sx, sy) = raster.film_point(i, j, d);
        (sx, sy, raster.weight(d))
    };
    let image_pdf = |dir| image_pdf(sensor, dir).scaled(filter);
    match sensor {
        Sensor::Pinhole(p) => {
            let dir = p.direction(sx, sy);
            CameraRay { origin: p.eye, dir, pdf: image_pdf(dir), throughput: 1.0 }
        }
        Sensor::ThinLens(t) => {
            let p = &t.pinhole;
            let towards = p.direction(sx, sy);
            if t.radius == 0.0 {
                return CameraRay { origin: p.eye, dir: towards, pdf: image_pdf(towards), throughput: 1.0 };
            }
            let focus = p.eye + towards * (t.focus_distance / towards.dot(p.forward));
            let origin = t.lens_point(u_lens);
            let dir = (focus - origin).normalize();
            CameraRay { origin, dir, pdf: image_pdf(dir), throughput: 1.0 }
        }
        Sensor::Orthographic(o) => {
            let dir = o.forward;
            CameraRay { origin: o.film_point(sx, sy), dir, pdf: image_pdf(dir), throughput: 1.0 }
        }
        Sensor::Equirectangular(e) => {
            // Box only (`Equirectangular::new`): the pixel's full-film row gives Ω_j.
            let dir = e.direction(sx, sy);
            let pdf = image_pdf(dir);
            let omega = e.pixel_solid_angle(raster.window.y + j);
            let CameraPdf::Solid(pdf_w) = pdf else { unreachable!("a point camera") };
            let throughput = 1.0 / (pdf_w * w * h * omega);
            CameraRay { origin: e.eye, dir, pdf, throughput }
        }
    }
}

/// The image-wide density with which the camera's rays take the unit direction `dir`: a
/// solid-angle density from the eye or, for the thin lens, from whichever lens point the ray
/// leaves; for the orthographic camera (whose rays all take its one direction) the area
/// density of the ray's origin on the film. The camera-side density of light tracing's t = 1
/// strategy. 0 outside the field of view is not checked (callers only ask for directions that
/// project into the image).
#[inline]
pub fn image_pdf(sensor: &Sensor, dir: Vec3) -> CameraPdf {
    let perspective = |p: &super::super::Pinhole| {
        let cos = dir.dot(p.forward);
        CameraPdf::Solid(1.0 / (4.0 * p.tan_x * p.tan_y * cos * cos * cos))
    };
    match sensor {
        Sensor::Pinhole(p) => perspective(p),
        Sensor::ThinLens(t) => perspective(&t.pinhole),
        Sensor::Orthographic(o) => CameraPdf::Area(1.0 / (4.0 * o.half_width * o.half_height)),
        Sensor::Equirectangular(e) => {
            // sin θ as |dir × up|: accurate near the poles, where 1 − cos² is not.
            let sin = dir.cross(e.up).length();
            CameraPdf::Solid(1.0 / (2.0 * PI * PI * sin))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::RandomStream;
    use crate::scene::{CameraDesc, CameraKind};
    use crate::sensor::{Equirectangular, Orthographic, Pinhole, ThinLens};

    fn desc() -> CameraDesc {
        CameraDesc {
            eye: Vec3::new(0.2, 0.1, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_x_degrees: 50.0,
            width: 24,
            height: 16,
            kind: CameraKind::Perspective,
            film: Default::default(),
        }
    }

    /// A camera ray lands in its own pixel through the sensor's connection, and the camera's
    /// importance integrates to one per pixel: E[throughput] = 1, and E[1/(pdf·W·H)] over the
    /// pixel's rays is the pixel's solid angle (the density is normalised).
    #[test]
    fn rays_land_in_their_pixel_and_densities_are_normalised() {
        let p = Pinhole::new(&desc()).unwrap();
        let sensors = [
            Sensor::Pinhole(p),
            Sensor::ThinLens(ThinLens::new(p, 0.1, 2.5).unwrap()),
            Sensor::Equirectangular(Equirectangular::new(&desc()).unwrap()),
            Sensor::Orthographic(Orthographic::new(&desc(), 1.2, 0.8).unwrap()),
        ];
        let mut rng = RandomStream::new(5, &[]);
        for s in sensors {
            let (w, h) = (s.width(), s.height());
            let (mut total_solid_angle, mut throughput, n) = (0.0f64, 0.0f64, 200_000);
            for k in 0..n {
                let (i, j) = (k % w, (k / w) % h);
                let r = camera_ray(&s, i, j, rng.next_2d(), rng.next_2d());
                // The pixel check keeps off the pixel's border (where rounding may pick the
                // neighbour).
                let inner = camera_ray(&s, i, j, Vec2::splat(0.01) + 0.98 * rng.next_2d(), Vec2::ZERO);
                let x = inner.origin + 1.7 * inner.dir;
                // The splat's connection from x picks the same pixel (any lens point would do
                // in focus; here x is off the focus plane, so use the ray's own lens point).
                let lens_u = match s {
                    Sensor::ThinLens(_) => None,
                    _ => Some(Vec2::ZERO),
                };
                if let Some(u) = lens_u {
                    let c = s.connect(x, u).unwrap();
                    assert_eq!(c.pixel, (j * w + i) as usize, "{s:?}");
                }
                let (CameraPdf::Solid(p) | CameraPdf::Area(p)) = r.pdf;
                assert_eq!(image_pdf(&s, r.dir), r.pdf, "{s:?}");
                total_solid_angle += 1.0 / p as f64;
                throughput += r.throughput as f64;
            }
            let mean_throughput = throughput / n as f64;
            assert!((mean_throughput - 1.0).abs() < 0.01, "{s:?}: {mean_throughput}");
            let omega = total_solid_angle / n as f64;
            let expected = match s {
                Sensor::Equirectangular(_) => 4.0 * std::f64::consts::PI,
                // The film's area (the density is one of area).
                Sensor::Orthographic(o) => 4.0 * (o.half_width * o.half_height) as f64,
                // The image rectangle [−t_x, t_x] × [−t_y, t_y] at unit distance subtends
                // 4·atan(t_x·t_y/√(1 + t_x² + t_y²)) (the thin lens nearly the same from r ≪ F).
                Sensor::Pinhole(p) | Sensor::ThinLens(ThinLens { pinhole: p, .. }) => {
                    let (tx, ty) = (p.tan_x as f64, p.tan_y as f64);
                    4.0 * (tx * ty / (1.0 + tx * tx + ty * ty).sqrt()).atan()
                }
            };
            assert!((omega / expected - 1.0).abs() < 0.01, "{s:?}: {omega} vs {expected}");
        }
    }
}
