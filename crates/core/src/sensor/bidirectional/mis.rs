//! Multiple importance sampling for the bidirectional estimator: the recursive MIS quantities of
//! Georgiev's *Implementing Vertex Connection and Merging* (2012), restricted to vertex
//! connection (no merging) and adapted to a light vertex cache whose strategies are sampled at
//! different rates. The derivation, with every quantity defined, is `docs/bidirectional.md`;
//! this module is its code, with the notation used there.
//!
//! A full path x₀ … x_k runs from a light (x₀) to the camera (x_k). Strategy s takes s vertices
//! from the light side and t = k + 1 − s from the camera side. Per camera path and per light k
//! the strategies have the expected sample counts n_s (P = N_k/N, the light's share of the
//! dataset's paths, which is also NEE's light-pick probability):
//!
//! | strategy | s, t | n_s |
//! |---|---|---|
//! | emitter hit | s = 0 | 1 |
//! | next-event estimation (NEE) | s = 1, t ≥ 2 | P |
//! | cache connection | s ≥ 2, t ≥ 2 | `Counts::conn`·P = n_c·N_k/\|Y\| |
//! | light tracing (a stored sample's splat) | t = 1 | `Counts::light_trace`·P = N_k/M |
//!
//! and the weight of strategy s is w_s = (n_s p̃_s)^β / Σ_j (n_j p̃_j)^β over the strategies j
//! that can produce the path (p̃: the area-measure density of the strategy, *without* the
//! light-pick probability; β = 1 balance, 2 power heuristic).
//!
//! Each side carries a few numbers along its subpath ([`LightVertexMis`], [`CameraVertexMis`]),
//! updated by [`LightVertexMis::after_hit`]/[`LightVertexMis::after_scatter`] (and the camera
//! side's equivalents), so that a weight costs a few multiplications when the two sides meet
//! ([`weight_emitter_hit`], [`weight_nee`], [`weight_connection`], [`weight_light_trace`]).
//! The light side's numbers are computed at trace time and stored with each sample
//! ([`MisRecord`], 16 bytes): they depend neither on the camera nor on the counts, which enter
//! only at render time (only on how both tracers sample, which the dataset must record), so relighting, switching lights off, merged datasets and previews from a
//! subset of chunks keep weights that sum to one exactly. To make that possible the light side
//! keeps the terms of strategies with different counts apart: SmallVCM's single dVC becomes
//! three sums (emitter-hit, NEE and connection terms), and dVCM carries which strategy it
//! belongs to (NEE at the first hit y₁, a connection deeper, an emitter hit at y₀).
//!
//! Conventions for every function here:
//! * **Pdfs are the tracers' own**, solid angle unless said otherwise. "fwd" at a vertex is the
//!   density with which this side's tracer samples the direction it continues in; "rev" is the
//!   density with which the *other* side's tracer, arriving along the same path from the other
//!   direction, would sample this side's previous vertex. A light vertex's rev pdf is therefore
//!   the camera tracer's BSDF sampling density, and a camera vertex's rev pdf the light
//!   tracer's (with the dataset's direction strategy). For a delta (mirror, smooth glass) event
//!   both are the discrete probabilities of the chosen lobe.
//! * Cosines are absolute values against the **geometric** normal; distances are squared.
//! * Russian roulette and splitting do not enter (the docs say why that is unbiased).
//! * Inputs (pdfs, cosines, distances) and weights are f32, the renderer's precision; the
//!   recursion runs in f64, because its powered products span far more than f32's 10^±38 (a
//!   glossy lobe's density of 10⁵ against a grazing cosine of 10⁻⁴, squared by the power
//!   heuristic, over a few vertices), and an overflow there is not harmless: the product it
//!   belongs to can be of order one once the connection's own factors multiply it. Records
//!   store the β-th root of each sum in f32, which keeps their range that of the raw density
//!   ratios. Products in which one factor is exactly 0 are 0 even if the other is ∞, so a
//!   weight is never NaN: an impossible strategy has a zero pdf, and zero wins.

use bytemuck::{Pod, Zeroable};

/// The MIS heuristic: the exponent β of w_s = (n_s p_s)^β / Σ_j (n_j p_j)^β.
///
/// The light side's stored quantities are powered sums, so a dataset is traced for one
/// heuristic and rendered with it (the header records which, [`Heuristic::code`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Heuristic {
    /// β = 1 (Veach's balance heuristic).
    Balance,
    /// β = 2 (Veach's power heuristic).
    Power,
}

impl Heuristic {
    /// x^β.
    #[inline]
    pub fn mis(self, x: f64) -> f64 {
        match self {
            Heuristic::Balance => x,
            Heuristic::Power => x * x,
        }
    }

    /// x^(1/β), how a record stores a powered sum.
    #[inline]
    fn root(self, x: f64) -> f64 {
        match self {
            Heuristic::Balance => x,
            Heuristic::Power => x.sqrt(),
        }
    }

    /// The exponent β.
    pub fn exponent(self) -> u32 {
        match self {
            Heuristic::Balance => 1,
            Heuristic::Power => 2,
        }
    }

    /// The byte a dataset header stores for it: 0 balance, 1 power.
    pub fn code(self) -> u8 {
        match self {
            Heuristic::Balance => 0,
            Heuristic::Power => 1,
        }
    }

    /// The heuristic of a header byte ([`Heuristic::code`]); `None` for an unknown code.
    pub fn from_code(code: u8) -> Option<Self> {
        match code {
            0 => Some(Heuristic::Balance),
            1 => Some(Heuristic::Power),
            _ => None,
        }
    }
}

/// The render-time sample counts per camera path of the strategies whose rate is a render
/// option, relative to a light's share P = N_k/N (module docs). NEE and emitter hits count 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Counts {
    /// c_conn = n_c·N/|Y|: every non-delta camera vertex draws n_c of the |Y| stored
    /// non-emission vertices uniformly (N light paths in total).
    pub conn: f64,
    /// c_LT = N/M: N light paths are each splatted once into an image of M camera paths
    /// (W·H·spp of the whole render).
    pub light_trace: f64,
}

impl Counts {
    /// The counts of a render that connects each camera vertex to `connections` (n_c) cache
    /// vertices drawn from `cache_vertices` (|Y|, stored non-emission vertices of the lights
    /// rendered), with `light_paths` (N = Σ N_k of those lights) and `camera_paths` (M) camera
    /// paths in the whole image. A zero count (no connections, an empty cache) switches the
    /// strategy off; `camera_paths` = 0 gives c_LT = ∞ (light tracing only).
    pub fn new(connections: u32, light_paths: u64, cache_vertices: u64, camera_paths: u64) -> Self {
        let n = light_paths as f64;
        let conn = if cache_vertices == 0 { 0.0 } else { connections as f64 * n / cache_vertices as f64 };
        let light_trace = if camera_paths == 0 { f64::INFINITY } else { n / camera_paths as f64 };
        Counts { conn, light_trace }
    }
}

/// The four kinds of light, as MIS sees them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LightKind {
    /// A one-sided emitting surface: x₀ has an area density, its direction a solid-angle one;
    /// camera paths can hit it.
    Area,
    /// A delta position (camera paths never hit it).
    Point,
    /// A delta direction, emitted from a disk of area density outside the scene (an infinite
    /// light: its first segment has no 1/d², camera paths never hit it).
    Directional,
    /// An environment at infinity: x₀ is a direction of solid-angle density, emitted from a disk
    /// of area density outside the scene (an infinite light, as [`LightKind::Directional`]); a
    /// camera ray that leaves the scene hits it (its camera-side density of x₀ is the camera
    /// tracer's solid-angle density, no cosine and no 1/d²).
    Environment,
}

/// A light's own emission densities for one start point and direction, **without** the
/// light-pick probability: what the tracer drew x₀ and the first direction from, and what NEE
/// and emitter hits must evaluate for the same point and direction. NEE must draw x₀ with the
/// light's own emission-position sampling (`docs/bidirectional.md` §7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emitter {
    kind: LightKind,
    /// Density of x₀ in its own measure: area (area light), 1 (the delta position of a point
    /// light, the delta direction of a directional light), solid angle (an environment's
    /// direction).
    first: f64,
    /// The density that turns the first segment into an area density at x₁ (× |cos θ₁|, and
    /// ÷ d² for finite lights): the direction pdf (area, point), the disk pdf (directional,
    /// environment).
    second: f64,
}

impl Emitter {
    /// An area light: `pos_pdf` the area density of x₀ (1/A for uniform sampling), `dir_pdf`
    /// the solid-angle density of the emission direction (the profile's *sampling* pdf).
    #[inline]
    pub fn area(pos_pdf: f32, dir_pdf: f32) -> Self {
        Emitter { kind: LightKind::Area, first: pos_pdf as f64, second: dir_pdf as f64 }
    }

    /// A point light emitting with solid-angle density `dir_pdf`.
    #[inline]
    pub fn point(dir_pdf: f32) -> Self {
        Emitter { kind: LightKind::Point, first: 1.0, second: dir_pdf as f64 }
    }

    /// A directional light whose rays start with area density `disk_pdf` (1/(π r²)) on its disk.
    #[inline]
    pub fn directional(disk_pdf: f32) -> Self {
        Emitter { kind: LightKind::Directional, first: 1.0, second: disk_pdf as f64 }
    }

    /// An environment whose direction toward x₀'s side (where the light comes from) has
    /// solid-angle density `dir_pdf`, its rays starting with area density `disk_pdf` on a disk.
    #[inline]
    pub fn environment(dir_pdf: f32, disk_pdf: f32) -> Self {
        Emitter { kind: LightKind::Environment, first: dir_pdf as f64, second: disk_pdf as f64 }
    }

    /// Which kind of light.
    #[inline]
    pub fn kind(&self) -> LightKind {
        self.kind
    }

    /// The conversion of the first segment's density to an area density at its end (the
    /// factor with which the light samples x₁, up to |cos θ₁|).
    #[inline]
    fn segment(&self, dist2: f64) -> f64 {
        match self.kind {
            LightKind::Directional | LightKind::Environment => self.second,
            _ => self.second / dist2,
        }
    }
}

/// Which strategy the coefficient `vcm` of a light vertex y_i belongs to: the one that takes
/// y_i from the camera side and one vertex fewer from the light side.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VcmClass {
    /// y₀ on an area light: the emitter hit (count 1).
    Hit,
    /// y₁, the first hit: NEE (count P).
    Nee,
    /// y_i, i ≥ 2: a cache connection (count c_conn·P).
    Conn,
}

/// Returns a·b, or 0 when either is 0 (even if the other is ∞): a zero pdf means an impossible
/// strategy, whatever an overflowed factor says.
#[inline]
fn mul(a: f64, b: f64) -> f64 {
    if a == 0.0 || b == 0.0 { 0.0 } else { a * b }
}

/// Returns a/b, or 0 when a is 0 (even if b is 0 too): a zero density or cosine in the
/// numerator makes a strategy impossible, as in [`mul`]. (A light path emitted exactly along
/// its surface, where a cosine profile's density is 0 too, would otherwise make a NaN.)
#[inline]
fn div(a: f64, b: f64) -> f64 {
    if a == 0.0 { 0.0 } else { a / b }
}

/// 1/(1 + sum), the weight of a strategy whose other strategies' ratios sum to `sum`.
#[inline]
fn weight(sum: f64) -> f32 {
    let w = 1.0 / (1.0 + sum);
    if w.is_nan() { 0.0 } else { w as f32 }
}

/// The recursion both sides share (SmallVCM's dVCM and dVC, the dVC split into one sum per
/// count class). At a vertex: `vcm` is the term of the strategy that takes this vertex from the
/// *other* side (of class `class`), `vc[c]` the terms of class c of the strategies that take
/// this vertex and older ones from the other side, all powered by β and without the factors
/// known only where the sides meet. After a scatter `vcm` belongs to a connection, the last
/// class. On a segment the values lack the next hit's conversion.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Subpath<const N: usize> {
    vcm: f64,
    vc: [f64; N],
    class: usize,
    heuristic: Heuristic,
    /// On the first segment of a directional light (no 1/d² at its end).
    infinite_segment: bool,
}

impl<const N: usize> Subpath<N> {
    /// The class of a connection: the last.
    const CONN: usize = N - 1;

    /// At the vertex `dist2` away, arriving at |cos θ| = `cos_in`: the densities of the hit
    /// vertex become area densities.
    #[inline]
    fn after_hit(self, dist2: f32, cos_in: f32) -> Self {
        let (h, dist2, cos_in) = (self.heuristic, dist2 as f64, cos_in as f64);
        let g = if self.infinite_segment { 1.0 / cos_in } else { div(dist2, cos_in) };
        let inv_cos = h.mis(1.0 / cos_in);
        Subpath {
            vcm: mul(self.vcm, h.mis(g)),
            vc: self.vc.map(|v| mul(v, inv_cos)),
            infinite_segment: false,
            ..self
        }
    }

    /// Leaving the vertex with |cos θ| = `cos_out`, the direction drawn with `pdf_fwd_w` by
    /// this side's tracer; `pdf_rev_w` the other side's density of the reverse step.
    #[inline]
    fn after_scatter(self, cos_out: f32, pdf_fwd_w: f32, pdf_rev_w: f32, delta: bool) -> Self {
        let h = self.heuristic;
        let (cos_out, pdf_fwd_w, pdf_rev_w) = (cos_out as f64, pdf_fwd_w as f64, pdf_rev_w as f64);
        if delta {
            // No connection can end here: the strategies of `vcm` and of the next vertex are
            // impossible; the older ones pass through (their δ cancel against this side's).
            let g = h.mis(mul(div(cos_out, pdf_fwd_w), pdf_rev_w));
            return Subpath { vcm: 0.0, vc: self.vc.map(|v| mul(v, g)), class: Self::CONN, ..self };
        }
        let g = h.mis(div(cos_out, pdf_fwd_w));
        let r = h.mis(pdf_rev_w);
        let mut vc = self.vc.map(|v| mul(v, r));
        vc[self.class] += self.vcm;
        Subpath { vcm: h.mis(1.0 / pdf_fwd_w), vc: vc.map(|v| mul(g, v)), class: Self::CONN, ..self }
    }

    /// The sum over the strategies that take this vertex (and older ones) from the other side,
    /// for a strategy whose other side samples this vertex with area density `p_other` and
    /// would continue to this side's previous vertex with `pdf_rev_w`; `f[c]` = (n_c/n_s)^β.
    #[inline]
    fn sum(&self, p_other: f64, pdf_rev_w: f32, f: [f64; N]) -> f64 {
        let h = self.heuristic;
        let older = (0..N).map(|c| mul(f[c], self.vc[c])).sum();
        mul(h.mis(p_other), mul(f[self.class], self.vcm) + mul(h.mis(pdf_rev_w as f64), older))
    }
}

/// The light subpath's MIS state at a vertex y_i (after [`LightVertexMis::after_hit`]), or on
/// the segment leaving it (after [`LightVertexMis::at_emission`] or
/// [`LightVertexMis::after_scatter`]). All values are already raised to the power β.
///
/// At a vertex, with the camera-side area density p←(y_i) of y_i and the camera tracer's pdf r
/// of continuing from y_i to y_{i−1}, the light-side sum of the weight of the strategy s = i + 1
/// that connects y_i is (f_c = (n_c/n_s)^β):
///
/// ```text
/// p←(y_i)^β · [ f_class·vcm + r^β·(f_hit·vc_hit + f_nee·vc_nee + f_conn·vc_conn) ]
/// ```
///
/// where vcm holds the strategy j = i (its class [`VcmClass`]) and the three vc sums the
/// strategies j < i of each count class.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightVertexMis(Subpath<3>);

/// The light side's count classes, in `Subpath::vc` order.
const HIT: usize = 0;
const NEE: usize = 1;

impl LightVertexMis {
    /// The state of the first segment y₀ → y₁ of a light path: `emitter` holds the densities
    /// x₀ and the direction were drawn with, `cos_light` is |cos θ| at y₀ of the emission
    /// direction (area lights; ignored otherwise).
    #[inline]
    pub fn at_emission(emitter: Emitter, cos_light: f32, heuristic: Heuristic) -> Self {
        let h = heuristic;
        // NEE draws x₀ as the tracer does, so its density of x₀ cancels that of the light path:
        // the NEE term is 1/(density of x₁ given x₀), completed at the hit.
        let vcm = h.mis(1.0 / emitter.second);
        let vc_hit = match emitter.kind {
            // The emitter hit's camera-side density of x₀ is r·cos θ₀/d²: cos θ₀ now, the d²
            // cancels against the light's own 1/d², r comes at the connection.
            LightKind::Area => h.mis(div(cos_light as f64, emitter.first * emitter.second)),
            // The camera side's density of an environment's x₀ is r itself (solid angle), the
            // disk's cosine is 1.
            LightKind::Environment => h.mis(div(1.0, emitter.first * emitter.second)),
            LightKind::Point | LightKind::Directional => 0.0, // never hit by a camera path
        };
        LightVertexMis(Subpath {
            vcm,
            vc: [vc_hit, 0.0, 0.0],
            class: NEE,
            heuristic,
            infinite_segment: matches!(emitter.kind, LightKind::Directional | LightKind::Environment),
        })
    }

    /// The state of the emission vertex y₀ itself (area lights: the sample with the emission
    /// flag), whose only other strategy is the emitter hit.
    #[inline]
    pub fn emission_vertex(emitter: Emitter, heuristic: Heuristic) -> Self {
        debug_assert_eq!(emitter.kind, LightKind::Area, "only area lights store y₀");
        let vcm = heuristic.mis(1.0 / emitter.first);
        LightVertexMis(Subpath { vcm, vc: [0.0; 3], class: HIT, heuristic, infinite_segment: false })
    }

    /// The state at the vertex the current segment hits, `dist2` away, arriving at |cos θ| =
    /// `cos_in` (geometric normal).
    #[inline]
    #[must_use]
    pub fn after_hit(self, dist2: f32, cos_in: f32) -> Self {
        LightVertexMis(self.0.after_hit(dist2, cos_in))
    }

    /// The state of the segment leaving the current vertex: |cos θ| = `cos_out` of the new
    /// direction, sampled by the light tracer with `pdf_fwd_w`; `pdf_rev_w` is the camera
    /// tracer's density of the reverse step (from the new direction to the previous vertex).
    /// `delta`: a delta event (then both pdfs are the lobe's discrete probabilities).
    #[inline]
    #[must_use]
    pub fn after_scatter(self, cos_out: f32, pdf_fwd_w: f32, pdf_rev_w: f32, delta: bool) -> Self {
        LightVertexMis(self.0.after_scatter(cos_out, pdf_fwd_w, pdf_rev_w, delta))
    }

    /// The stored form of this vertex state (call it after [`LightVertexMis::after_hit`] or on
    /// [`LightVertexMis::emission_vertex`]).
    #[inline]
    pub fn record(&self) -> MisRecord {
        let s = &self.0;
        debug_assert!(!s.infinite_segment, "a record is taken at a vertex, not on a segment");
        let h = s.heuristic;
        let root = |x: f64, class_bit: bool| {
            f32::from_bits((h.root(x) as f32).to_bits() | if class_bit { SIGN } else { 0 })
        };
        MisRecord {
            vcm: root(s.vcm, s.class == NEE),
            vc_hit: root(s.vc[HIT], s.class == HIT),
            vc_nee: root(s.vc[NEE], false),
            vc_conn: root(s.vc[Subpath::<3>::CONN], false),
        }
    }

    /// The vertex state a record was taken from, for a dataset traced with `heuristic`.
    #[inline]
    pub fn from_record(record: MisRecord, heuristic: Heuristic) -> Self {
        let h = heuristic;
        let power = |x: f32| h.mis(f32::from_bits(x.to_bits() & !SIGN) as f64);
        let class = if record.vc_hit.is_sign_negative() {
            HIT
        } else if record.vcm.is_sign_negative() {
            NEE
        } else {
            Subpath::<3>::CONN
        };
        let vc = [power(record.vc_hit), power(record.vc_nee), power(record.vc_conn)];
        LightVertexMis(Subpath { vcm: power(record.vcm), vc, class, heuristic, infinite_segment: false })
    }

    /// Which strategy `vcm` belongs to.
    #[inline]
    pub fn class(&self) -> VcmClass {
        [VcmClass::Hit, VcmClass::Nee, VcmClass::Conn][self.0.class]
    }

    /// The heuristic the state is powered for.
    #[inline]
    pub fn heuristic(&self) -> Heuristic {
        self.0.heuristic
    }

    /// The light-side sum of a strategy that takes this vertex from the light side and whose
    /// camera side samples it with area density `p_camera` (then continues to the previous
    /// light vertex with `pdf_rev_w`), relative to that strategy's count (`f`).
    #[inline]
    fn sum(&self, p_camera: f64, pdf_rev_w: f32, f: &Factors) -> f64 {
        self.0.sum(p_camera, pdf_rev_w, [f.hit, f.nee, f.conn])
    }
}

/// The sign bit, which every MIS quantity (≥ 0) leaves free.
const SIGN: u32 = 1 << 31;

/// The 16 bytes a dataset stores per sample for the bidirectional estimator: a light vertex's
/// [`LightVertexMis`] as four f32 (little endian), each the β-th root of its powered sum
/// (x for the balance heuristic, √x for the power heuristic), and its [`VcmClass`] in two
/// sign bits (vcm's for NEE, vc_hit's for the emitter hit; neither for a connection).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct MisRecord {
    vcm: f32,
    vc_hit: f32,
    vc_nee: f32,
    vc_conn: f32,
}

const _: () = assert!(std::mem::size_of::<MisRecord>() == 16);

impl MisRecord {
    /// Whether every field is a number ≥ 0 or +∞ once the class bits are removed (what a reader
    /// checks, as it checks a sample's β).
    pub fn is_valid(&self) -> bool {
        let magnitude = |x: f32| f32::from_bits(x.to_bits() & !SIGN);
        [magnitude(self.vcm), magnitude(self.vc_hit), self.vc_nee, self.vc_conn].iter().all(|x| *x >= 0.0)
    }
}

/// How a camera draws its rays, image-wide: the camera-side density every strategy that takes
/// the first camera hit from the camera needs (`docs/bidirectional.md` §3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraPdf {
    /// Rays leave a point (the pinhole, a lens point, the 360° camera's centre) in a direction of
    /// this solid-angle density (pinhole 1/(A·cos³θ), A the image area at unit distance;
    /// equirectangular 1/(2π² sin θ)): the first hit x₁ has area density p·|cos θ₁|/d².
    Solid(f32),
    /// Rays leave the film plane in one direction from a point of this area density
    /// (orthographic: 1 over the film's area): x₁ has area density p·|cos θ₁|, no 1/d² — the
    /// camera vertex is a direction, as a directional light's x₀ is.
    Area(f32),
}

impl CameraPdf {
    /// The area density of a point at |cos θ| = `cos`, `dist2` from the camera point.
    #[inline]
    fn of_point(self, cos: f32, dist2: f32) -> f64 {
        match self {
            CameraPdf::Solid(p) => p as f64 * cos as f64 / dist2 as f64,
            CameraPdf::Area(p) => p as f64 * cos as f64,
        }
    }
}

/// The camera subpath's MIS state at a vertex z_m (after [`CameraVertexMis::after_hit`]) or on
/// the segment leaving it. Values are raised to the power β; they hold no counts, so one
/// camera path serves any [`Counts`]. Its `vcm` is 1/p←(z_m)^β, the strategy that takes z_m
/// from the light side (light tracing of z₁ at the first hit, a connection deeper); its sums
/// are those of light tracing (z₁ taken from the light side) and of the connections that end
/// the light side at z₂ … z_{m−1}.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraVertexMis(Subpath<2>);

/// The camera side's count classes, in `Subpath::vc` order.
const LIGHT_TRACE: usize = 0;

impl CameraVertexMis {
    /// The state of the segment leaving the camera, whose rays are drawn with the image-wide
    /// density `pdf` ([`CameraPdf`]). The lens position's own density (thin lens) is the same
    /// for every strategy and cancels.
    #[inline]
    pub fn at_camera(pdf: CameraPdf, heuristic: Heuristic) -> Self {
        let (p, infinite_segment) = match pdf {
            CameraPdf::Solid(p) => (p, false),
            CameraPdf::Area(p) => (p, true),
        };
        let vcm = heuristic.mis(1.0 / p as f64);
        CameraVertexMis(Subpath { vcm, vc: [0.0; 2], class: LIGHT_TRACE, heuristic, infinite_segment })
    }

    /// The state at the vertex the current segment hits (as [`LightVertexMis::after_hit`]).
    #[inline]
    #[must_use]
    pub fn after_hit(self, dist2: f32, cos_in: f32) -> Self {
        CameraVertexMis(self.0.after_hit(dist2, cos_in))
    }

    /// The state of the segment leaving the current vertex (as
    /// [`LightVertexMis::after_scatter`], sides swapped): `pdf_fwd_w` is the camera tracer's
    /// density of the new direction, `pdf_rev_w` the **light tracer's** density of continuing
    /// from the new direction to the previous camera vertex, with the dataset's strategy.
    #[inline]
    #[must_use]
    pub fn after_scatter(self, cos_out: f32, pdf_fwd_w: f32, pdf_rev_w: f32, delta: bool) -> Self {
        CameraVertexMis(self.0.after_scatter(cos_out, pdf_fwd_w, pdf_rev_w, delta))
    }

    /// The heuristic the state is powered for.
    #[inline]
    pub fn heuristic(&self) -> Heuristic {
        self.0.heuristic
    }

    /// Whether this is the first hit z₁ (or the segment leaving the camera).
    #[inline]
    fn first(&self) -> bool {
        self.0.class == LIGHT_TRACE
    }

    /// The camera-side sum of a strategy that takes this vertex from the camera side and whose
    /// light side would sample it with area density `p_light` (then continue to the previous
    /// camera vertex with `pdf_rev_w`), relative to that strategy's count (`f`).
    #[inline]
    fn sum(&self, p_light: f64, pdf_rev_w: f32, f: &Factors) -> f64 {
        self.0.sum(p_light, pdf_rev_w, [f.lt, f.conn])
    }
}

/// One end of a connection (or NEE's camera end, or a splat's light end): |cos θ| of the
/// connecting segment at this vertex, the density with which this side's tracer would sample
/// the connection direction (`pdf_fwd_w`), and the density with which the other side's tracer,
/// arriving along the connection, would continue to this vertex's predecessor (`pdf_rev_w`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConnectionEnd {
    /// |cos θ| at this vertex of the connecting segment (geometric normal).
    pub cos: f32,
    /// This side's tracer's solid-angle density of the direction to the other end.
    pub pdf_fwd_w: f32,
    /// The other side's tracer's solid-angle density of the direction from here to this
    /// side's previous vertex, given that it arrived from the other end.
    pub pdf_rev_w: f32,
}

/// The strategy whose weight is computed.
#[derive(Clone, Copy)]
enum Target {
    Hit,
    Nee,
    Conn,
    LightTrace,
}

/// (n_j/n_s)^β for each count class j, for the target strategy s (module docs: n = 1, P,
/// c_conn·P, c_LT·P). Written out per target so that P cancels exactly where it cancels.
struct Factors {
    hit: f64,
    nee: f64,
    conn: f64,
    lt: f64,
}

impl Factors {
    #[inline]
    fn new(target: Target, counts: Counts, pick: f32, h: Heuristic) -> Self {
        let (c, l, p) = (counts.conn, counts.light_trace, pick as f64);
        let m = |x: f64| h.mis(x);
        match target {
            Target::Hit => Factors { hit: 1.0, nee: m(p), conn: m(c * p), lt: m(l * p) },
            Target::Nee => Factors { hit: m(1.0 / p), nee: 1.0, conn: m(c), lt: m(l) },
            Target::Conn => Factors { hit: m(1.0 / (c * p)), nee: m(1.0 / c), conn: 1.0, lt: m(l / c) },
            Target::LightTrace => Factors { hit: m(1.0 / (l * p)), nee: m(1.0 / l), conn: m(c / l), lt: 1.0 },
        }
    }
}

/// The weight of an emitter hit (s = 0): the camera path, in state `camera` after its hit on
/// an area light (or, for an environment, on the segment that left the scene: no hit
/// conversion, the environment's x₀ has a solid-angle measure), found the emitter there;
/// `emitter` holds that light's densities of the hit point (an environment: of the direction
/// the segment left in) and of the direction back to the previous camera vertex. `pick` =
/// N_k/N of the light. Zero for lights camera paths cannot hit.
#[inline]
pub fn weight_emitter_hit(camera: &CameraVertexMis, emitter: Emitter, pick: f32, counts: Counts) -> f32 {
    if !matches!(emitter.kind, LightKind::Area | LightKind::Environment) {
        return 0.0;
    }
    let (c, h) = (&camera.0, camera.0.heuristic);
    let f = Factors::new(Target::Hit, counts, pick, h);
    // x₀ taken from the light side: NEE (deeper) or the splat of y₀ (seen directly), both
    // drawing x₀ with the light's own position density. Not `Subpath::sum`: here the class of
    // `vcm` is not that of the sum it joins deeper. An environment's y₀ is not stored (no
    // surface to splat from): seen directly, the hit is its only strategy.
    let own = match (camera.first(), emitter.kind) {
        (true, LightKind::Area) => f.lt,
        (true, _) => 0.0,
        (false, _) => f.nee,
    };
    let older = mul(f.lt, c.vc[LIGHT_TRACE]) + mul(f.conn, c.vc[Subpath::<2>::CONN]);
    weight(mul(h.mis(emitter.first), mul(own, c.vcm) + mul(h.mis(emitter.second), older)))
}

/// The weight of next-event estimation (s = 1) from camera vertex z (state `camera`, after its
/// hit) to a light point x₀ drawn with the light's own position sampling: `at_camera` is z's
/// end of the shadow segment (its `pdf_fwd_w` the camera tracer's density toward x₀, used for
/// area lights only), `emitter` the light's densities of x₀ and of the direction x₀ → z,
/// `cos_light` |cos θ| at x₀ (area lights), `dist2` = |x₀ − z|² (ignored for directional lights).
#[inline]
pub fn weight_nee(
    camera: &CameraVertexMis,
    at_camera: ConnectionEnd,
    emitter: Emitter,
    cos_light: f32,
    dist2: f32,
    pick: f32,
    counts: Counts,
) -> f32 {
    let h = camera.heuristic();
    let f = Factors::new(Target::Nee, counts, pick, h);
    let light = match emitter.kind {
        // The emitter hit: the camera tracer would have found x₀ with area density
        // pdf_fwd·cos θ₀/d², NEE drew it with the light's own density.
        LightKind::Area => {
            let p_hit = at_camera.pdf_fwd_w as f64 * cos_light as f64 / dist2 as f64;
            mul(f.hit, h.mis(p_hit / emitter.first))
        }
        // A camera ray leaving along the shadow ray's direction hits the environment: the
        // camera tracer's solid-angle density against NEE's.
        LightKind::Environment => mul(f.hit, h.mis(div(at_camera.pdf_fwd_w as f64, emitter.first))),
        LightKind::Point | LightKind::Directional => 0.0,
    };
    let p_light = emitter.segment(dist2 as f64) * at_camera.cos as f64;
    weight(light + camera.sum(p_light, at_camera.pdf_rev_w, &f))
}

/// The weight of a cache connection (s ≥ 2, t ≥ 2) of camera vertex z (state `camera`) to a
/// stored light vertex y (state `light`, from its [`MisRecord`]), `dist2` = |y − z|² apart.
#[inline]
pub fn weight_connection(
    camera: &CameraVertexMis,
    at_camera: ConnectionEnd,
    light: &LightVertexMis,
    at_light: ConnectionEnd,
    dist2: f32,
    pick: f32,
    counts: Counts,
) -> f32 {
    debug_assert_eq!(camera.heuristic(), light.heuristic(), "a dataset renders with its own heuristic");
    let f = Factors::new(Target::Conn, counts, pick, camera.heuristic());
    let dist2 = dist2 as f64;
    let p_camera = at_camera.pdf_fwd_w as f64 * at_light.cos as f64 / dist2; // the camera side samples y
    let p_light = at_light.pdf_fwd_w as f64 * at_camera.cos as f64 / dist2; // the light side samples z
    weight(light.sum(p_camera, at_light.pdf_rev_w, &f) + camera.sum(p_light, at_camera.pdf_rev_w, &f))
}

/// The weight of light tracing (t = 1): the stored vertex y (state `light`; y₀ of an area light
/// included) splatted to the camera, whose image-wide density of the ray camera → y is
/// `camera_pdf` ([`CameraVertexMis::at_camera`]), `dist2` away; `at_light.cos` is |cos θ| at y
/// of that direction, `at_light.pdf_rev_w` the camera tracer's density of continuing from y
/// (arriving from the camera) to y's predecessor; `at_light.pdf_fwd_w` is not used (the light
/// path hitting the lens is not a strategy).
#[inline]
pub fn weight_light_trace(
    light: &LightVertexMis,
    at_light: ConnectionEnd,
    camera_pdf: CameraPdf,
    dist2: f32,
    pick: f32,
    counts: Counts,
) -> f32 {
    let f = Factors::new(Target::LightTrace, counts, pick, light.heuristic());
    let p_camera = camera_pdf.of_point(at_light.cos, dist2);
    weight(light.sum(p_camera, at_light.pdf_rev_w, &f))
}

#[cfg(test)]
mod tests;
