//! Camera subpaths: from a pixel of the sensor through the scene, importance-sampling each BSDF
//! in radiance mode (through mirrors and glass, absorbing glass as the tracer does it), and at
//! every vertex the camera strategies of `docs/bidirectional.md` §1: the emitter hit (s = 0)
//! where the path finds an area light or leaves the scene toward an environment, and at non-delta vertices NEE and cache connections
//! (`vertex.rs`). The MIS state ([`CameraVertexMis`]) is carried along with the densities both
//! tracers would use (`Material::pdf_world`, `crate::trace::light_direction_pdf`); Russian roulette and the delta-run survival divide the
//! throughput and stay out of the weights (§2).

use super::camera::camera_ray;
use super::vertex::{Context, DrawsAhead, Receiver, connect_ahead, nee, segment_medium, transmittance};
use super::{CameraVertexMis, weight_emitter_hit};
use crate::bsdf::{Direction, Material, ShadingPoint, TransportMode};
use crate::dataset::Directions;
use crate::geometry::SurfaceNormals;
use crate::geometry::{Ray, offset_ray_origin};
use crate::math::Rgb;
use crate::math::Vec3;
use crate::sampling::RandomStream;
use crate::sensor::Sensor;
use crate::trace::light_direction_pdf_at;

/// Camera vertices from which Russian roulette may end a path (at non-delta vertices, survival
/// q = min(0.95, 2·max T) with T the throughput, as the tracer's energy-driven rule).
const RR_DEPTH: u32 = 3;

/// After this many delta bounces in a row, each further one survives with
/// [`DELTA_RUN_SURVIVAL`] (divided out): light trapped by total internal reflection still ends,
/// and nothing is truncated (the tracer's `MAX_DELTA_RUN`).
const MAX_DELTA_RUN: u32 = 1024;

/// Survival probability of a delta bounce beyond [`MAX_DELTA_RUN`].
const DELTA_RUN_SURVIVAL: f32 = 0.95;

/// The radiance estimate of one camera path through pixel (`i`, `j`): every camera strategy,
/// MIS-weighted (the light-tracing splat of the same pixel is added separately).
#[inline]
pub fn camera_path(ctx: &Context, sensor: &Sensor, i: u32, j: u32, rng: &mut RandomStream) -> Rgb {
    camera_path_rays(ctx, sensor, i, j, rng).0
}

/// [`camera_path`], and the rays it asked for: one per segment traced, plus, at each non-delta
/// vertex, NEE's shadow ray and n_c connections' (asked for, whether or not a draw needed its ray)
/// — the cost measure of the allocation pilot (`pilot.rs`), which must not depend on a clock.
pub(super) fn camera_path_rays(
    ctx: &Context,
    sensor: &Sensor,
    i: u32,
    j: u32,
    rng: &mut RandomStream,
) -> (Rgb, u32) {
    let gather_rays = 1 + ctx.connections;
    let mut rays = 0u32;
    let (u_film, u_lens) = (rng.next_2d(), rng.next_2d());
    let start = camera_ray(sensor, i, j, u_film, u_lens);
    let scene = ctx.scene;
    let mut mis = CameraVertexMis::at_camera(start.pdf, ctx.heuristic);
    let mut throughput = Rgb::splat(start.throughput);
    let mut ray = Ray { origin: start.origin, dir: start.dir, t_max: f32::INFINITY };
    let mut medium = Rgb::ZERO;
    let (mut depth, mut delta_run) = (0u32, 0u32);
    let mut radiance = Rgb::ZERO;
    // The first connections' cache reads start now, each later vertex's at the one before.
    let mut ahead = DrawsAhead::begin(ctx, rng);
    // The first hit from the eye is the visibility buffer's front triangle where it knows one.
    let mut front = ctx.visibility.and_then(|v| v.front(ray.origin, ray.dir));
    loop {
        rays = rays.saturating_add(1);
        let hit = match front.take() {
            Some(t) => scene.intersect_front(&ray, t),
            None => scene.intersect(&ray),
        };
        let Some(hit) = hit else {
            // Left the scene: the environments' emitter hit (s = 0), weighted on the segment's
            // state (an environment's x₀ is a direction: no hit conversion).
            if ctx.lights.has_environment() {
                radiance += throughput * escaped(medium) * environment_hit(ctx, &mis, ray.dir);
            }
            break;
        };
        depth += 1;
        throughput *= transmittance(medium, hit.t);
        let to_camera = -ray.dir;
        let cos_in = hit.normal.dot(to_camera).abs();
        if !(cos_in > 0.0) {
            break;
        }
        mis = mis.after_hit(hit.t * hit.t, cos_in);
        if let Some((emitted, emitter, pick)) =
            ctx.lights.hit(scene, hit.prim, hit.position, hit.normal, to_camera)
        {
            let w = weight_emitter_hit(&mis, emitter, pick, ctx.counts);
            radiance += throughput * emitted * w;
        }
        let mut resolved = None;
        let (material, normals) = scene.surface_at(hit.prim, hit.position, &mut resolved);
        // One shading frame for every BSDF query at this vertex (NEE, the connections, their
        // weights, the next bounce and its MIS densities).
        let r = Receiver::at(hit.position, material.at(normals), to_camera, medium);
        if !r.point.scatters_from(&r.to_camera) {
            break; // the back of a one-sided surface
        }
        let delta = material.bsdf.is_delta();
        if !delta {
            rays = rays.saturating_add(gather_rays);
            let gathered = nee(ctx, &r, &mis, rng) + connect_ahead(ctx, &r, &mis, rng, &mut ahead);
            radiance += throughput * gathered;
        }
        let (u_lobe, u) = (rng.next_f32(), rng.next_2d());
        let Some(s) = r.point.sample(&r.to_camera, u_lobe, u, TransportMode::Radiance) else {
            break;
        };
        throughput *= s.weight;
        if s.delta {
            delta_run += 1;
            if delta_run > MAX_DELTA_RUN {
                if !(rng.next_f32() < DELTA_RUN_SURVIVAL) {
                    break;
                }
                throughput /= DELTA_RUN_SURVIVAL;
            }
        } else {
            delta_run = 0;
            if depth >= RR_DEPTH {
                let q = (2.0 * throughput.max_element()).min(0.95);
                if !(rng.next_f32() < q) {
                    break;
                }
                throughput /= q;
            }
        }
        if !(throughput.max_element() > 0.0) {
            break;
        }
        mis = scatter_mis_at(mis, ctx.directions, &r.point, &r.to_camera, s.wo, s.pdf, s.delta);
        medium = segment_medium(material, hit.normal, s.wo, medium);
        ray = Ray {
            origin: offset_ray_origin(hit.position, hit.normal, s.wo),
            dir: s.wo,
            t_max: f32::INFINITY,
        };
    }
    (radiance, rays)
}

/// What the environments that are on send back along a camera ray leaving the scene along
/// `dir` (the camera subpath in state `mis` on that segment), MIS-weighted.
#[inline]
pub(super) fn environment_hit(ctx: &Context, mis: &CameraVertexMis, dir: Vec3) -> Rgb {
    ctx.lights.escaped(ctx.scene, dir).fold(Rgb::ZERO, |sum, (emitted, emitter, pick)| {
        sum + emitted * weight_emitter_hit(mis, emitter, pick, ctx.counts)
    })
}

/// The transmittance of an infinite segment through a medium absorbing `sigma`: 1 in the
/// channels it does not absorb, 0 in the others.
#[inline]
fn escaped(sigma: Rgb) -> Rgb {
    sigma.map(|s| if s > 0.0 { 0.0 } else { 1.0 })
}

/// The camera subpath's MIS state after scattering at a surface of `material` (`normals`) from
/// `to_camera` into `wo`, sampled with density (or, `delta`, lobe probability) `pdf_fwd`: the
/// reverse density is the light tracer's with the dataset's `directions`.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn scatter_mis(
    mis: CameraVertexMis,
    directions: Directions,
    material: &Material,
    normals: SurfaceNormals,
    to_camera: Vec3,
    wo: Vec3,
    pdf_fwd: f32,
    delta: bool,
) -> CameraVertexMis {
    let p = material.at(normals);
    scatter_mis_at(mis, directions, &p, &p.direction(to_camera), wo, pdf_fwd, delta)
}

/// [`scatter_mis`] at a camera vertex's shading point `p`, whose frame the vertex's other
/// queries share (`to_camera` prepared there).
#[inline]
pub(super) fn scatter_mis_at(
    mis: CameraVertexMis,
    directions: Directions,
    p: &ShadingPoint,
    to_camera: &Direction,
    wo: Vec3,
    pdf_fwd: f32,
    delta: bool,
) -> CameraVertexMis {
    let wo = p.direction(wo);
    // The light tracer arriving along `wo` and continuing to `to_camera` (for a delta event
    // the probability of that lobe, the same for both tracers; a plastic has both kinds).
    let pdf_rev = light_direction_pdf_at(p, &wo, to_camera, directions, delta);
    mis.after_scatter(wo.abs_cos(), pdf_fwd, pdf_rev, delta)
}
