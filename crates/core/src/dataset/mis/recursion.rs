//! The multiple-importance-sampling recursion of the bidirectional estimator, which both of its
//! sides carry along their subpaths: the light side at trace time (its state stored with every
//! sample, `record.rs`), the camera side at render time (in the bidirectional sensor). These
//! are the recursive MIS quantities of Georgiev's *Implementing Vertex Connection and Merging*
//! (2012), restricted to vertex connection (no merging) and adapted to a light vertex cache
//! whose strategies are sampled at different rates; the derivation, with every quantity
//! defined, is `docs/bidirectional.md`, and this is its code, with the notation used there.
//! It lives with the dataset because the records are computed from it: the tracer and the file
//! format need it, and the sensor uses what the dataset stores, never the other way round.
//!
//! A full path x₀ … x_k runs from a light (x₀) to the camera (x_k). Strategy s takes s vertices
//! from the light side and t = k + 1 − s from the camera side, with an expected sample count
//! n_s per camera path, and its weight is w_s = (n_s p̃_s)^β / Σ_j (n_j p̃_j)^β over the
//! strategies j that can produce the path (p̃: the area-measure density of the strategy,
//! *without* the light-pick probability; β = 1 balance, 2 power heuristic, [`Heuristic`]).
//!
//! Conventions for every function here and for the camera side's:
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
    pub(crate) fn root(self, x: f64) -> f64 {
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

/// Returns a·b, or 0 when either is 0 (even if the other is ∞): a zero pdf means an impossible
/// strategy, whatever an overflowed factor says.
#[inline]
pub(crate) fn mul(a: f64, b: f64) -> f64 {
    if a == 0.0 || b == 0.0 { 0.0 } else { a * b }
}

/// Returns a/b, or 0 when a is 0 (even if b is 0 too): a zero density or cosine in the
/// numerator makes a strategy impossible, as in [`mul`]. (A light path emitted exactly along
/// its surface, where a cosine profile's density is 0 too, would otherwise make a NaN.)
#[inline]
pub(crate) fn div(a: f64, b: f64) -> f64 {
    if a == 0.0 { 0.0 } else { a / b }
}

/// `vc` with every element v replaced by [`mul`]`(v, g)`: a plain loop, which the compiler
/// unrolls, where `[f64; N]::map` left a counted loop with a drop guard in the tracer's hot
/// path (the same products, in the same order).
#[inline(always)]
fn scaled<const N: usize>(mut vc: [f64; N], g: f64) -> [f64; N] {
    for v in &mut vc {
        *v = mul(*v, g);
    }
    vc
}

/// The recursion both sides share (SmallVCM's dVCM and dVC, the dVC split into one sum per
/// count class). At a vertex: `vcm` is the term of the strategy that takes this vertex from the
/// *other* side (of class `class`), `vc[c]` the terms of class c of the strategies that take
/// this vertex and older ones from the other side, all powered by β and without the factors
/// known only where the sides meet. After a scatter `vcm` belongs to a connection, the last
/// class. On a segment the values lack the next hit's conversion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Subpath<const N: usize> {
    pub(crate) vcm: f64,
    pub(crate) vc: [f64; N],
    pub(crate) class: usize,
    pub(crate) heuristic: Heuristic,
    /// On the first segment of a directional light (no 1/d² at its end).
    pub(crate) infinite_segment: bool,
}

impl<const N: usize> Subpath<N> {
    /// The class of a connection: the last.
    pub(crate) const CONN: usize = N - 1;

    /// At the vertex `dist2` away, arriving at |cos θ| = `cos_in`: the densities of the hit
    /// vertex become area densities.
    #[inline]
    pub(crate) fn after_hit(self, dist2: f32, cos_in: f32) -> Self {
        let (h, dist2, cos_in) = (self.heuristic, dist2 as f64, cos_in as f64);
        let g = if self.infinite_segment { 1.0 / cos_in } else { div(dist2, cos_in) };
        let inv_cos = h.mis(1.0 / cos_in);
        Subpath {
            vcm: mul(self.vcm, h.mis(g)),
            vc: scaled(self.vc, inv_cos),
            infinite_segment: false,
            ..self
        }
    }

    /// Leaving the vertex with |cos θ| = `cos_out`, the direction drawn with `pdf_fwd_w` by
    /// this side's tracer; `pdf_rev_w` the other side's density of the reverse step.
    #[inline]
    pub(crate) fn after_scatter(self, cos_out: f32, pdf_fwd_w: f32, pdf_rev_w: f32, delta: bool) -> Self {
        let h = self.heuristic;
        let (cos_out, pdf_fwd_w, pdf_rev_w) = (cos_out as f64, pdf_fwd_w as f64, pdf_rev_w as f64);
        if delta {
            // No connection can end here: the strategies of `vcm` and of the next vertex are
            // impossible; the older ones pass through (their δ cancel against this side's).
            let g = h.mis(mul(div(cos_out, pdf_fwd_w), pdf_rev_w));
            return Subpath { vcm: 0.0, vc: scaled(self.vc, g), class: Self::CONN, ..self };
        }
        let g = h.mis(div(cos_out, pdf_fwd_w));
        let r = h.mis(pdf_rev_w);
        let mut vc = scaled(self.vc, r);
        vc[self.class] += self.vcm;
        for v in &mut vc {
            *v = mul(g, *v);
        }
        Subpath { vcm: h.mis(1.0 / pdf_fwd_w), vc, class: Self::CONN, ..self }
    }

    /// The sum over the strategies that take this vertex (and older ones) from the other side,
    /// for a strategy whose other side samples this vertex with area density `p_other` and
    /// would continue to this side's previous vertex with `pdf_rev_w`; `f[c]` = (n_c/n_s)^β.
    #[inline]
    pub(crate) fn sum(&self, p_other: f64, pdf_rev_w: f32, f: [f64; N]) -> f64 {
        let h = self.heuristic;
        let older = (0..N).map(|c| mul(f[c], self.vc[c])).sum();
        mul(h.mis(p_other), mul(f[self.class], self.vcm) + mul(h.mis(pdf_rev_w as f64), older))
    }
}
