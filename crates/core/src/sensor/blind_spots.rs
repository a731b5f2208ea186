//! What the light estimator cannot show. It connects every stored vertex to the sensor, and a
//! vertex on an ideal mirror or a smooth dielectric is never stored (its BSDF is a Dirac delta:
//! no connection can reach it), so such a surface seen directly renders black — together with
//! everything seen in it or through it — however many paths are traced. The bidirectional
//! estimator's camera paths see it. Front ends ask [`delta_fraction`] before a light-estimator
//! render and warn, as they do for an environment seen directly.

use super::Sensor;
use super::bidirectional::camera_ray;
use crate::geometry::Ray;
use crate::math::Vec2;
use crate::scene::Scene;

/// Grid side of the view sampled (at most this many pixel centres along each axis).
const GRID: u32 = 64;

/// The fraction of `sensor`'s view whose first surface is an ideal mirror or smooth dielectric
/// ([`crate::bsdf::Bsdf::is_delta`]), from the pixel centres of a grid of at most 64 × 64.
pub fn delta_fraction(scene: &Scene, sensor: &Sensor) -> f64 {
    let (w, h) = (sensor.width(), sensor.height());
    let (gx, gy) = (w.min(GRID), h.min(GRID));
    let centre = Vec2::splat(0.5);
    let mut delta = 0u32;
    for b in 0..gy {
        for a in 0..gx {
            let (i, j) = ((a as u64 * w as u64 / gx as u64) as u32, (b as u64 * h as u64 / gy as u64) as u32);
            let r = camera_ray(sensor, i, j, centre, centre);
            let ray = Ray { origin: r.origin, dir: r.dir, t_max: f32::INFINITY };
            if scene.intersect(&ray).is_some_and(|hit| scene.material(hit.prim).bsdf.is_delta()) {
                delta += 1;
            }
        }
    }
    delta as f64 / (gx * gy) as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::{Bsdf, SmoothConductor};
    use crate::math::Rgb;
    use crate::scene::cornell_box;

    #[test]
    fn mirrors_in_view_are_found_and_diffuse_walls_are_not() {
        let desc = cornell_box();
        let sensor = Sensor::new(desc.camera.as_ref().unwrap()).unwrap();
        assert_eq!(delta_fraction(&Scene::build(&desc).unwrap(), &sensor), 0.0);
        // The red wall (x = −1) a mirror: the left part of the view, about a seventh of it.
        let mut mirror = desc.clone();
        let red = mirror.materials.iter_mut().find(|m| m.name == "red").unwrap();
        red.bsdf = Bsdf::SmoothConductor(SmoothConductor::new(Rgb::ONE, None).unwrap());
        let f = delta_fraction(&Scene::build(&mirror).unwrap(), &sensor);
        assert!(f > 0.08 && f < 0.25, "{f}");
    }
}
