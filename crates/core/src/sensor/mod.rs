//! Sensors: connecting stored samples to a measuring device (the thesis's "visualisation").
//!
//! The pinhole camera implements the measurement contract of DESIGN.md §2. Each stored vertex
//! x of light k with weight β adds to the pixel it projects into
//!
//! ```text
//! Δ = (Φ_k/N_k) · β · f_r(x; ω_in → ω_c) · |cos θ_x| · V(x, c) / (d² · a · cos³θ_c)
//! ```
//!
//! (a light tracer's t = 1 connection, Veach ch. 10), so each pixel converges to the radiance at
//! the pinhole averaged over its square of the image plane (a box filter). Emission vertices use
//! L_e·A_k/Φ_k = 1/π in place of f_r, and only their front side is visible.

use crate::dataset::Sample;
use crate::film::Film;
use crate::geometry::{Ray, offset_ray_origin};
use crate::math::Rgb;
use crate::scene::{Pinhole, Scene};
use rayon::prelude::*;
use std::f32::consts::FRAC_1_PI;

/// A run of samples from one light and the flux each unit of β stands for (Φ_k/N_k, after any
/// relighting). What a sensor consumes; the source can be memory or a mapped file.
#[derive(Clone, Copy, Debug)]
pub struct SampleBatch<'a> {
    /// Φ_k / N_k of the batch's light.
    pub flux_per_path: Rgb,
    /// The samples.
    pub samples: &'a [Sample],
}

/// Adds the contribution of `samples` to `film` as seen by `camera`.
pub fn splat_pinhole(scene: &Scene, camera: &Pinhole, batch: SampleBatch<'_>, film: &mut Film) {
    if batch.flux_per_path == Rgb::ZERO {
        return;
    }
    let inv_area = 1.0 / camera.pixel_area();
    for s in batch.samples {
        let x = s.position();
        let Some((pixel, cos_c)) = camera.project(x) else { continue };
        let to_eye = camera.eye - x;
        let d2 = to_eye.length_squared();
        let d = d2.sqrt();
        let wc = to_eye / d;
        let prim = s.triangle();
        let n = scene.normal(prim);
        let cos_x = n.dot(wc);
        let f = if s.is_emission() {
            if cos_x <= 0.0 {
                continue; // emitters are one-sided
            }
            Rgb::splat(FRAC_1_PI)
        } else {
            let f = scene.material(prim).eval_world(n, s.from_dir(), wc);
            if f == Rgb::ZERO {
                continue;
            }
            f
        };
        let origin = offset_ray_origin(x, n, wc);
        let to_eye = camera.eye - origin;
        let t = to_eye.length();
        if scene.occluded(&Ray { origin, dir: to_eye / t, t_max: t * (1.0 - 1e-5) }) {
            continue;
        }
        let g = cos_x.abs() * inv_area / (d2 * cos_c * cos_c * cos_c);
        film.splat(pixel, batch.flux_per_path * s.beta() * f * g);
    }
}

/// Renders `count` batches (fetched by index, possibly from a memory-mapped file) through a
/// pinhole camera on all cores.
pub fn render_pinhole<'a, E: Send>(
    scene: &Scene,
    camera: &Pinhole,
    count: usize,
    batch: impl Fn(usize) -> Result<SampleBatch<'a>, E> + Sync,
    progress: impl Fn(usize) + Sync,
) -> Result<Film, E> {
    (0..count)
        .into_par_iter()
        .try_fold(
            || Film::new(camera.width, camera.height),
            |mut film, i| {
                let b = batch(i)?;
                splat_pinhole(scene, camera, b, &mut film);
                progress(b.samples.len());
                Ok(film)
            },
        )
        .try_reduce(
            || Film::new(camera.width, camera.height),
            |mut a, b| {
                a.add(&b);
                Ok(a)
            },
        )
}
