//! The light-tracing strategy (t = 1) of the bidirectional estimator: every stored sample of a
//! light that is on is splatted to the camera exactly as the light estimator does it
//! (`crate::sensor::splat`'s connection and walk, `splat_projected`) and weighted by
//! [`weight_light_trace`] with its stored record ([`light_trace_weight`]). The camera-side
//! density of the splat is the image-wide density of the camera's own rays ([`image_pdf`]); the
//! camera tracer's density of continuing from the sample to its predecessor is that of the
//! camera subpaths.

use super::camera::image_pdf;
use super::vertex::Context;
use super::{ConnectionEnd, Counts, cache::CacheChunk, weight_light_trace};
use crate::dataset::{LightVertexMis, MisRecord, Sample};
use crate::film::SplatTarget;
use crate::math::Vec3;
use crate::sensor::{Sensor, VisibilityBuffer, connect_filtered, connect_seen, splat_projected};

/// Adds the MIS-weighted splats of `chunk`'s samples to `film` (with the sensor's `visibility`
/// buffer, if it has one: `Sensor::visibility`).
pub fn splat_chunk(
    ctx: &Context,
    sensor: &Sensor,
    visibility: Option<&VisibilityBuffer>,
    chunk: &CacheChunk<'_>,
    film: &mut impl SplatTarget,
) {
    if !sensor.raster().is_box() {
        return splat_chunk_filtered(ctx, sensor, visibility, chunk, film);
    }
    let k = chunk.light as usize;
    let Some(light) = ctx.lights.of_table(k) else { return };
    let flux = ctx.flux_per_path[k];
    splat_projected(sensor, visibility, chunk.samples, film, |film, i, conn, seen| {
        let (s, record) = (&chunk.samples[i], chunk.records[i]);
        // One shading point at the sample for f and the reverse density.
        let Some(c) = connect_seen::<true>(ctx.scene, seen, s, conn) else { return };
        let end = ConnectionEnd { cos: c.cos_x.abs(), pdf_fwd_w: 0.0, pdf_rev_w: c.pdf_rev };
        let dist2 = (c.conn.point - s.position()).length_squared();
        let counts = ctx.counts_at(c.conn.pixel);
        let w = weight_at_sensor(ctx, sensor, light.pick, counts, record, end, c.to_sensor, dist2, 1.0);
        film.splat(c.conn.pixel, flux * s.beta() * c.f * (c.cos_x.abs() * c.conn.weight * w));
    });
}

/// [`splat_chunk`] through a filter: one connection, then each pixel p within the filter's
/// radius gets the splat times f̂(s − c_p), MIS-weighted with the density of p's camera rays
/// (the image-wide density times the same f̂) and p's counts.
fn splat_chunk_filtered(
    ctx: &Context,
    sensor: &Sensor,
    visibility: Option<&VisibilityBuffer>,
    chunk: &CacheChunk<'_>,
    film: &mut impl SplatTarget,
) {
    let k = chunk.light as usize;
    let Some(light) = ctx.lights.of_table(k) else { return };
    let flux = ctx.flux_per_path[k];
    let random = sensor.samples_aperture();
    for (s, record) in chunk.samples.iter().zip(chunk.records) {
        let Some((c, footprint)) = connect_filtered::<true>(ctx.scene, sensor, visibility, s, random) else {
            continue;
        };
        let end = ConnectionEnd { cos: c.cos_x.abs(), pdf_fwd_w: 0.0, pdf_rev_w: c.pdf_rev };
        let dist2 = (c.conn.point - s.position()).length_squared();
        let v = flux * s.beta() * c.f * (c.cos_x.abs() * c.conn.weight);
        footprint.for_each(|pixel, f| {
            let counts = ctx.counts_at(pixel);
            let w = weight_at_sensor(ctx, sensor, light.pick, counts, *record, end, c.to_sensor, dist2, f);
            film.splat(pixel, v * (f * w));
        });
    }
}

/// The MIS weight of a splat with `counts` (those of the pixel it lands in), the sample's end of
/// the connection being `at_light`, `to_sensor` and `dist2` the connection's direction and
/// squared length, `filter` the pixel's normalised filter f̂ at the splat (1 for the box).
#[allow(clippy::too_many_arguments)]
#[inline]
fn weight_at_sensor(
    ctx: &Context,
    sensor: &Sensor,
    pick: f32,
    counts: Counts,
    record: MisRecord,
    at_light: ConnectionEnd,
    to_sensor: Vec3,
    dist2: f32,
    filter: f32,
) -> f32 {
    if counts.light_trace == f64::INFINITY {
        return 1.0; // a pixel without camera paths: the splat is its only strategy
    }
    let state = LightVertexMis::from_record(record, ctx.heuristic);
    weight_light_trace(&state, at_light, image_pdf(sensor, -to_sensor).scaled(filter), dist2, pick, counts)
}

/// The MIS weight of splatting the stored sample `s` of table light `light` (record `record`)
/// to the sensor point `c` (the eye, or the lens point its connection chose), with the render's
/// counts; 0 if the light is off. `filter` is f̂ of the pixel the weight is for at the splat's
/// film point (1 for the box filter; `crate::sensor::raster`). The splat pass computes the same
/// weight from its connection ([`splat_chunk`]: the reverse density from the shading point that
/// gave f).
#[inline]
pub fn light_trace_weight(
    ctx: &Context,
    sensor: &Sensor,
    light: u32,
    s: &Sample,
    record: MisRecord,
    c: Vec3,
    filter: f32,
) -> f32 {
    let Some(light) = ctx.lights.of_table(light as usize) else { return 0.0 };
    let x = s.position();
    let v = c - x;
    let dist2 = v.length_squared();
    let to_sensor = v / dist2.sqrt();
    let prim = s.triangle();
    let pdf_rev_w = if s.is_emission() {
        0.0 // y₀ has no predecessor
    } else {
        let mut resolved = None;
        let (m, n) = ctx.scene.surface_at(prim, x, &mut resolved);
        m.pdf_world(n, to_sensor, s.from_dir())
    };
    let cos = ctx.scene.normal(prim).dot(to_sensor).abs();
    let at_light = ConnectionEnd { cos, pdf_fwd_w: 0.0, pdf_rev_w };
    weight_at_sensor(ctx, sensor, light.pick, ctx.counts, record, at_light, to_sensor, dist2, filter)
}
