//! The light side of the bidirectional estimator's multiple importance sampling, which the
//! tracer computes and the dataset stores: a light's own emission densities ([`Emitter`]), the
//! light subpath's state at each vertex ([`LightVertexMis`], the recursion of `recursion.rs`
//! walked from the light) and its stored form, the 16 bytes a dataset keeps per sample
//! ([`MisRecord`]) with the class of its first term ([`VcmClass`]).
//!
//! The light side's numbers are computed at trace time and stored with each sample: they
//! depend neither on the camera nor on the counts, which enter only at render time (only on
//! how both tracers sample, which the dataset must record), so relighting, switching lights
//! off, merged datasets and previews from a subset of chunks keep weights that sum to one
//! exactly. To make that possible the light side keeps the terms of strategies with different
//! counts apart: SmallVCM's single dVC becomes three sums (emitter-hit, NEE and connection
//! terms), and dVCM carries which strategy it belongs to (NEE at the first hit y₁, a connection
//! deeper, an emitter hit at y₀). The camera side, which weights a strategy from a record and
//! a camera subpath, is the bidirectional sensor's.

use super::recursion::{Heuristic, Subpath, div};
use bytemuck::{Pod, Zeroable};

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
    pub(crate) first: f64,
    /// The density that turns the first segment into an area density at x₁ (× |cos θ₁|, and
    /// ÷ d² for finite lights): the direction pdf (area, point), the disk pdf (directional,
    /// environment).
    pub(crate) second: f64,
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
    pub(crate) fn segment(&self, dist2: f64) -> f64 {
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
        let class = record.class_index();
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
    /// light vertex with `pdf_rev_w`), relative to that strategy's count: `f` holds
    /// (n_c/n_s)^β of the classes emitter hit, NEE and connection, in that order.
    #[inline]
    pub(crate) fn sum(&self, p_camera: f64, pdf_rev_w: f32, f: [f64; 3]) -> f64 {
        self.0.sum(p_camera, pdf_rev_w, f)
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
    /// The class of the record's `vcm` ([`LightVertexMis::class`] of the state it holds), read
    /// from the sign bits alone: it does not depend on the heuristic, and a writer checking
    /// every record of a chunk need not decode them.
    #[inline]
    pub fn class(&self) -> VcmClass {
        [VcmClass::Hit, VcmClass::Nee, VcmClass::Conn][self.class_index()]
    }

    /// [`MisRecord::class`] as the index of `Subpath::vc`.
    #[inline]
    fn class_index(&self) -> usize {
        if self.vc_hit.is_sign_negative() {
            HIT
        } else if self.vcm.is_sign_negative() {
            NEE
        } else {
            Subpath::<3>::CONN
        }
    }

    /// Whether every field is a number ≥ 0 or +∞ once the class bits are removed (what a reader
    /// checks, as it checks a sample's β).
    #[inline]
    pub fn is_valid(&self) -> bool {
        let magnitude = |x: f32| f32::from_bits(x.to_bits() & !SIGN);
        [magnitude(self.vcm), magnitude(self.vc_hit), self.vc_nee, self.vc_conn].iter().all(|x| *x >= 0.0)
    }
}

#[cfg(test)]
mod tests;
