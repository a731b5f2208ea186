//! What a camera-side vertex gathers from the light side: next-event estimation (s = 1,
//! [`nee`]) and connections to vertices drawn from the light vertex cache (s ≥ 2,
//! [`connect`]), each MIS-weighted with `mis.rs`.
//!
//! Both take a [`Receiver`] — a point, how it scatters there (its [`ShadingPoint`]: one shading
//! frame for every BSDF query of the vertex) and the direction back toward the camera side — and
//! the camera subpath's MIS state there, not a pixel: a camera vertex is one receiver, and a point sensor of cosine importance (an illuminance meter in the
//! air) is another that can reuse them once `Receiver` learns its scattering (today: a surface
//! material). They return the radiance toward the camera side per unit throughput, already
//! weighted; the caller multiplies by its throughput.

use super::cache::{CachedVertex, ConnectionSet, LightCache, PendingDraw};
use super::lights::{LightPoint, RenderLights};
use super::{CameraVertexMis, ConnectionEnd, Counts, weight_connection, weight_nee};
use crate::bsdf::{Direction, Material, ShadingPoint};
use crate::dataset::{Directions, Heuristic, LightVertexMis};
use crate::geometry::{Ray, SurfaceNormals, offset_ray_origin};
use crate::math::{Rgb, Vec3};
use crate::sampling::RandomStream;
use crate::scene::Scene;
use crate::trace::light_direction_pdf_at;

/// Everything a camera-side vertex needs to know about the render.
#[derive(Clone, Copy, Debug)]
pub struct Context<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The sensor's visibility buffer, if it has one (`crate::sensor::VisibilityBuffer`): a
    /// camera path's first hit where it knows it.
    pub visibility: Option<&'a crate::sensor::VisibilityBuffer>,
    /// The lights that are on.
    pub lights: &'a RenderLights,
    /// The light half.
    pub cache: &'a LightCache<'a>,
    /// Where connections draw their vertices: a `ConnectionSet` drawn from the cache (what a
    /// camera pass's band uses), or, if `None`, the cache itself.
    pub set: Option<&'a ConnectionSet>,
    /// Per table light: Φ'_k/N_k (relit, over the rendered chunks' N_k).
    pub flux_per_path: &'a [Rgb],
    /// The render's counts (in a camera pass: those of the pixel being rendered).
    pub counts: Counts,
    /// Per pixel c_LT(p), when the render allocates its camera paths pixel by pixel
    /// (`Allocation::PerPixel`); `None`: `counts` holds everywhere.
    pub pixel_light_trace: Option<&'a [f64]>,
    /// The dataset's heuristic.
    pub heuristic: Heuristic,
    /// The dataset's direction strategy (the light tracer's densities).
    pub directions: Directions,
    /// n_c, cache vertices drawn per receiver.
    pub connections: u32,
}

impl Context<'_> {
    /// The counts of a path that ends in pixel `p` (row-major): the render's, with the pixel's
    /// own c_LT when camera paths are allocated pixel by pixel.
    #[inline]
    pub fn counts_at(&self, p: usize) -> Counts {
        match self.pixel_light_trace {
            Some(lt) => Counts { light_trace: lt[p], ..self.counts },
            None => self.counts,
        }
    }
}

/// A camera-side vertex that gathers light: where it is, how it scatters, and where the
/// camera side came from.
#[derive(Clone, Copy, Debug)]
pub struct Receiver<'a> {
    /// The point.
    pub position: Vec3,
    /// How it scatters there: material, normals (the geometric one decides cosines and ray
    /// offsets) and the shading frame every query of this receiver shares.
    pub point: ShadingPoint<'a>,
    /// Unit direction toward the previous camera-side vertex, prepared at `point`.
    pub to_camera: Direction,
    /// The absorption coefficient of the medium the camera side arrived in.
    pub medium: Rgb,
}

impl<'a> Receiver<'a> {
    /// The receiver at `position` on a surface of `material` with normals `normals`, seen from
    /// the unit direction `to_camera` (its shading frame built here, once).
    #[inline]
    pub fn new(
        position: Vec3,
        material: &'a Material,
        normals: SurfaceNormals,
        to_camera: Vec3,
        medium: Rgb,
    ) -> Self {
        Self::at(position, material.at(normals), to_camera, medium)
    }

    /// The receiver at `position` of the shading point `point` (a camera vertex's, whose frame
    /// it shares), seen from `to_camera`.
    #[inline]
    pub fn at(position: Vec3, point: ShadingPoint<'a>, to_camera: Vec3, medium: Rgb) -> Self {
        Receiver { position, point, to_camera: point.direction(to_camera), medium }
    }

    /// The geometric normal.
    #[inline]
    fn geometric(&self) -> Vec3 {
        self.point.normals.geometric
    }

    /// f(to_light → to_camera) in light-flow order (the adjoint f_eff with shading normals).
    #[inline]
    fn eval(&self, to_light: &Direction) -> Rgb {
        self.point.eval(to_light, &self.to_camera)
    }

    /// The connection end at this receiver for the direction `to_light`: |cos θ| (geometric),
    /// the camera tracer's density of `to_light`, the light tracer's of continuing to the camera
    /// side.
    #[inline]
    pub fn end(&self, to_light: &Direction, directions: Directions) -> ConnectionEnd {
        ConnectionEnd {
            cos: to_light.abs_cos(),
            pdf_fwd_w: self.point.pdf(&self.to_camera, to_light),
            pdf_rev_w: light_direction_pdf_at(&self.point, to_light, &self.to_camera, directions, false),
        }
    }

    /// Absorption coefficient of a segment leaving here along `dir`: a dielectric's inside is
    /// behind its normal; other surfaces keep the medium (the tracer's rule).
    #[inline]
    fn medium_toward(&self, dir: Vec3) -> Rgb {
        segment_medium(self.point.material, self.geometric(), dir, self.medium)
    }
}

/// The absorption coefficient of the segment leaving a surface of `material` (geometric normal
/// `n`) along `dir`, having arrived in a medium of `current` (`crate::trace`'s rule).
#[inline]
pub(super) fn segment_medium(material: &Material, n: Vec3, dir: Vec3, current: Rgb) -> Rgb {
    match material.bsdf.transmits() {
        true if dir.dot(n) < 0.0 => material.bsdf.absorption(),
        true => Rgb::ZERO,
        false => current,
    }
}

/// exp(−σ·d), 1 when σ = 0 (also for d = ∞).
#[inline]
pub(super) fn transmittance(sigma: Rgb, d: f32) -> Rgb {
    if sigma == Rgb::ZERO { Rgb::ONE } else { (-sigma * d).exp() }
}

/// Whether the segment from `a` (geometric normal `na`) toward `b` along unit `dir`, `d` long,
/// is unblocked; `nb` is `b`'s normal if it lies on a surface.
#[inline]
pub(crate) fn visible(scene: &Scene, a: Vec3, na: Vec3, dir: Vec3, d: f32, b: Option<(Vec3, Vec3)>) -> bool {
    shadow_ray(a, na, dir, d, b).is_some_and(|ray| !scene.occluded(&ray))
}

/// The shadow ray of [`visible`]'s segment: from `a` offset off its surface, ending just short
/// of `b` (offset off its surface too if `b` is given with its normal), unbounded when `d` is
/// infinite; `None` for a segment of no length. Also the illuminance meter's, which asks
/// [`Scene::shadow_transmittance`] of it (`crate::sensor::meter`).
#[inline]
pub(crate) fn shadow_ray(a: Vec3, na: Vec3, dir: Vec3, d: f32, b: Option<(Vec3, Vec3)>) -> Option<Ray> {
    let origin = offset_ray_origin(a, na, dir);
    Some(match b {
        _ if d.is_infinite() => Ray { origin, dir, t_max: f32::INFINITY },
        Some((b, nb)) => {
            let end = offset_ray_origin(b, nb, -dir);
            let v = end - origin;
            let t = v.length();
            if !(t > 0.0) {
                return None;
            }
            Ray { origin, dir: v / t, t_max: t * (1.0 - 1e-5) }
        }
        None => Ray { origin, dir, t_max: d * (1.0 - 1e-5) },
    })
}

/// Next-event estimation (s = 1) at `r`, whose camera subpath is in state `camera`: one light
/// picked with P_k = N_k/N, its point drawn with its own position sampling; MIS-weighted.
#[inline]
pub fn nee(ctx: &Context, r: &Receiver, camera: &CameraVertexMis, rng: &mut RandomStream) -> Rgb {
    let (u_pick, u_pos) = (rng.next_f32(), rng.next_2d());
    let Some(lp) = ctx.lights.sample(ctx.scene, r.position, u_pick, u_pos) else { return Rgb::ZERO };
    let to_light = r.point.direction(lp.dir);
    let f = r.eval(&to_light);
    if f == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let end = r.end(&to_light, ctx.directions);
    let target = lp.normal.map(|n| (r.position + lp.dir * lp.distance, n));
    if !visible(ctx.scene, r.position, r.geometric(), lp.dir, lp.distance, target) {
        return Rgb::ZERO;
    }
    let w = weight_of_nee(ctx, camera, end, &lp);
    f * lp.radiance * (end.cos * w) * transmittance(r.medium_toward(lp.dir), lp.distance)
}

/// The MIS weight of NEE at `r` (camera state `camera`) to the light point `lp`.
#[inline]
pub fn nee_weight(ctx: &Context, r: &Receiver, camera: &CameraVertexMis, lp: &LightPoint) -> f32 {
    weight_of_nee(ctx, camera, r.end(&r.point.direction(lp.dir), ctx.directions), lp)
}

/// [`nee_weight`] with the receiver's end of the segment already known (what [`nee`] reuses).
#[inline]
fn weight_of_nee(ctx: &Context, camera: &CameraVertexMis, end: ConnectionEnd, lp: &LightPoint) -> f32 {
    let d2 = lp.distance * lp.distance;
    weight_nee(camera, end, lp.emitter, lp.cos_light, d2, lp.pick, ctx.counts)
}

/// The segment from a receiver to a cache vertex and the vertex's surface, found once for
/// both the connection's contribution and its weight: the vertex's shading point (one frame for
/// its three BSDF queries) and the two directions they take there.
struct Link<'s> {
    /// Squared length of the segment.
    d2: f32,
    /// The vertex's surface.
    point: ShadingPoint<'s>,
    /// The vertex's `from_dir`, where its light came from.
    from: Direction,
    /// From the vertex back toward the receiver (−dir).
    back: Direction,
}

impl<'s> Link<'s> {
    /// The direction and squared distance from `r` to `y` (NaN direction if they coincide).
    #[inline]
    fn segment(r: &Receiver, y: Vec3) -> (Vec3, f32) {
        let to_y = y - r.position;
        let d2 = to_y.length_squared();
        (to_y / d2.sqrt(), d2)
    }

    /// The link of the segment `dir`, `d2` to `v`'s surface (its material at the vertex, a
    /// textured one kept in `resolved`).
    #[inline]
    fn to(
        scene: &'s Scene,
        v: &CachedVertex,
        (dir, d2): (Vec3, f32),
        resolved: &'s mut Option<Material>,
    ) -> Self {
        let (y, prim) = (v.sample.position(), v.sample.triangle());
        let (material, normals) = scene.surface_at(prim, y, resolved);
        let point = material.at(normals);
        Link { d2, point, from: point.direction(v.sample.from_dir()), back: point.direction(-dir) }
    }
}

/// The MIS weight of connecting `r` (camera state `camera`) to the cache vertex `v`; 0 if its
/// light is off.
#[inline]
pub fn connection_weight(ctx: &Context, r: &Receiver, camera: &CameraVertexMis, v: &CachedVertex) -> f32 {
    let (dir, d2) = Link::segment(r, v.sample.position());
    let mut resolved = None;
    let link = Link::to(ctx.scene, v, (dir, d2), &mut resolved);
    weight_of_link(ctx, camera, r.end(&r.point.direction(dir), ctx.directions), v, &link)
}

/// [`connection_weight`] with the link and the receiver's end of it already known (what a
/// connection reuses).
#[inline]
fn weight_of_link(
    ctx: &Context,
    camera: &CameraVertexMis,
    end: ConnectionEnd,
    v: &CachedVertex,
    link: &Link,
) -> f32 {
    let Some(light) = ctx.lights.of_table(v.light as usize) else { return 0.0 };
    let (y, from, back) = (&link.point, &link.from, &link.back);
    let at_light = ConnectionEnd {
        cos: back.abs_cos(),
        pdf_fwd_w: light_direction_pdf_at(y, from, back, ctx.directions, false),
        pdf_rev_w: y.pdf(back, from),
    };
    let state = LightVertexMis::from_record(v.record, ctx.heuristic);
    weight_connection(camera, end, &state, at_light, link.d2, light.pick, ctx.counts)
}

/// Connections (s ≥ 2) of `r`, camera state `camera`, to n_c vertices drawn uniformly from the
/// cache, each weighted by |Y|/n_c and by MIS.
#[inline]
pub fn connect(ctx: &Context, r: &Receiver, camera: &CameraVertexMis, rng: &mut RandomStream) -> Rgb {
    connect_ahead(ctx, r, camera, rng, &mut DrawsAhead::default())
}

/// Most cache draws a camera path begins one vertex ahead ([`DrawsAhead`]); connections beyond
/// them draw when they connect.
const MAX_AHEAD: usize = 4;

/// The cache draws of a camera path's next connections, begun ahead of them
/// ([`LightCache::begin_draw`]), so that their memory reads overlap the work in between. Start a
/// path with [`DrawsAhead::begin`]; [`connect_ahead`] uses them and begins the next vertex's.
#[derive(Clone, Copy, Debug, Default)]
pub struct DrawsAhead {
    draws: [Option<PendingDraw>; MAX_AHEAD],
}

impl DrawsAhead {
    /// The first vertex's draws (min(n_c, 4) of them), begun now.
    #[inline]
    pub fn begin(ctx: &Context, rng: &mut RandomStream) -> Self {
        let mut d = DrawsAhead::default();
        d.refill(ctx, rng);
        d
    }

    #[inline]
    fn refill(&mut self, ctx: &Context, rng: &mut RandomStream) {
        if ctx.connections == 0 || ctx.counts.conn == 0.0 || ctx.set.is_some() {
            return;
        }
        let n = (ctx.connections as usize).min(MAX_AHEAD);
        for d in &mut self.draws[..n] {
            *d = ctx.cache.begin_draw(rng);
        }
    }
}

/// [`connect`] with the draws begun in `ahead` (a draw missing there is made now); begins the
/// draws of the next vertex's connections into `ahead`.
#[inline]
pub fn connect_ahead(
    ctx: &Context,
    r: &Receiver,
    camera: &CameraVertexMis,
    rng: &mut RandomStream,
    ahead: &mut DrawsAhead,
) -> Rgb {
    if ctx.connections == 0 || ctx.counts.conn == 0.0 {
        return Rgb::ZERO;
    }
    let mut total = Rgb::ZERO;
    if let Some(set) = ctx.set {
        for _ in 0..ctx.connections {
            let Some(v) = set.draw(rng) else { break };
            total += connect_one(ctx, r, camera, &v);
        }
        return total * (ctx.cache.vertices() as f32 / ctx.connections as f32);
    }
    for k in 0..ctx.connections as usize {
        let pending = match ahead.draws.get_mut(k).and_then(Option::take) {
            Some(p) => p,
            None => match ctx.cache.begin_draw(rng) {
                Some(p) => p,
                None => break,
            },
        };
        let v = ctx.cache.finish_draw(pending, rng);
        total += connect_one(ctx, r, camera, &v);
    }
    ahead.refill(ctx, rng);
    total * (ctx.cache.vertices() as f32 / ctx.connections as f32)
}

/// The MIS-weighted contribution of connecting `r` (camera state `camera`) to the cache vertex
/// `v`, before the |Y|/n_c of the draw.
#[inline]
fn connect_one(ctx: &Context, r: &Receiver, camera: &CameraVertexMis, v: &CachedVertex) -> Rgb {
    let y = v.sample.position();
    let (dir, d2) = Link::segment(r, y);
    if !(d2 > 0.0) {
        return Rgb::ZERO;
    }
    let d = d2.sqrt();
    let to_y = r.point.direction(dir);
    let f_z = r.eval(&to_y);
    if f_z == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let mut resolved = None;
    let link = Link::to(ctx.scene, v, (dir, d2), &mut resolved);
    let f_y = link.point.eval(&link.from, &link.back);
    if f_y == Rgb::ZERO {
        return Rgb::ZERO;
    }
    if !visible(ctx.scene, r.position, r.geometric(), dir, d, Some((y, link.point.normals.geometric))) {
        return Rgb::ZERO;
    }
    let w = weight_of_link(ctx, camera, r.end(&to_y, ctx.directions), v, &link);
    let g = to_y.abs_cos() * link.back.abs_cos() / d2;
    f_z * f_y
        * ctx.flux_per_path[v.light as usize]
        * v.sample.beta()
        * (g * w)
        * transmittance(r.medium_toward(dir), d)
}
