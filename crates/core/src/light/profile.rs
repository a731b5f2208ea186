//! Emission functions as probability densities (the thesis's f_e, §6.1.3).
//!
//! A light of power Φ emits, in the direction ω of its local frame (z = the light's axis, or an
//! area light's surface normal), the intensity (point light) or the intensity per unit area
//! (area light) `Φ·f_e(ω)`, where f_e is a probability density over directions (per unit solid
//! angle, integrating to 1). Every profile here is written as an unnormalised **shape**
//! s(ω) (1 on the axis for the analytic ones) and its integral S = ∫ s dω, so f_e = s/S and a
//! light of *strength* c (W/sr on the axis; radiance along the normal for an area light) has
//! Φ = c·S per unit (area):
//!
//! | profile | s(ω) | S | sampled by |
//! |---|---|---|---|
//! | [`EmissionProfile::Uniform`] | 1 | 4π (2π on an area light: front hemisphere only) | uniform sphere / hemisphere, exact |
//! | [`EmissionProfile::Cosine`] | cos θ | π | cosine hemisphere, exact |
//! | [`EmissionProfile::CosinePower`] | cosⁿθ | 2π/(n+1) | Phong-lobe inversion, exact |
//! | [`EmissionProfile::Spot`] | 1 inside `beam_width`, (γ−θ)/(γ−β) to 0 at `cutoff_angle` γ (Mitsuba 3's `spot`) | 2π·(1 − (sin γ − sin β)/(γ − β)) (closed form) | uniform in the cone θ < γ, weighted |
//! | [`EmissionProfile::Ies`] | candela(θ, φ)/683, bilinear in (θ, φ) | exact integral of the bilinear interpolant | 2D piecewise-constant table, weighted |
//!
//! When sampling is only proportional to an approximation of s (spot, IES), the sampled
//! direction carries the weight f_e(ω)/p(ω), with p the exact density of what was sampled, so
//! the estimator stays exact; its mean over directions is exactly 1.
//!
//! ## IES tables
//! An [`IesProfile`] (plain data, parsed by `opticks_io::ies`) gives candela on a grid of
//! vertical angles θ (0° = the light's axis, the nadir of a downlight; photometric type C) and
//! horizontal angles φ (0° = local +x, 90° = local +y) with LM-63's symmetries (one horizontal
//! angle: rotationally symmetric; 0–90: quadrant symmetric; 0–180: bilateral; 0–360: full). The
//! intensity between grid points is the **bilinear interpolation in (θ, φ)** of the candela
//! values, and zero outside the vertical range of the file. The flux of that interpolant is
//! integrated in closed form cell by cell (the integrand is bilinear in θ, φ times sin θ), so
//! Φ (lumens) is exact for the distribution that is actually emitted. For sampling, the grid is
//! refined (cells at most 2° × 5°; a bilinear function stays bilinear on sub-cells), each cell
//! gets the probability ∝ (largest corner value) × (solid angle), and a direction is drawn
//! uniformly in solid angle inside the chosen cell. On an area light the table is cut at 90°.

use crate::math::Vec3;
use crate::sampling::warp;
use std::f32::consts::{FRAC_1_PI, PI, TAU};
use std::f64::consts::PI as PI64;
use std::sync::Arc;

/// Luminous efficacy used to convert lumens and candela to watts: 683 lm/W (555 nm).
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Watts per channel of an RGB light of `colour` and luminous flux `lumens`: the colour is scaled
/// so that 683·luminance(Φ) = lumens, with luminance = 0.2126 R + 0.7152 G + 0.0722 B. A white
/// (1, 1, 1) light of 683 lm has Φ = 1 W per channel. `None` if the colour has no luminance.
pub fn lumens_to_watts(lumens: f32, colour: Vec3) -> Option<Vec3> {
    let y = crate::math::luminance(colour);
    (y > 0.0 && y.is_finite()).then(|| colour * (lumens / (LUMENS_PER_WATT * y)))
}

/// Photometric data of an IES (LM-63) file, type C: plain numbers, no IO.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IesProfile {
    /// Vertical angles θ in degrees, strictly increasing, within [0, 180].
    pub vertical_angles: Vec<f32>,
    /// Horizontal angles φ in degrees, strictly increasing, starting at 0 and ending at 0, 90,
    /// 180 or 360.
    pub horizontal_angles: Vec<f32>,
    /// Candela (all multipliers applied), `candela[h * vertical_angles.len() + v]`: for each
    /// horizontal angle, the values along the vertical angles (the file's order).
    pub candela: Vec<f32>,
}

/// How a light's emission is distributed over directions (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub enum EmissionProfile {
    /// Uniform over the sphere (the front hemisphere on an area light).
    Uniform,
    /// Lambertian: f_e = cos θ/π over the front hemisphere.
    Cosine,
    /// Focused: f_e = (n+1)/(2π)·cosⁿθ over the front hemisphere, n ≥ 0.
    CosinePower {
        /// The exponent n.
        exponent: f32,
    },
    /// Mitsuba's spot: full intensity within `beam_width` of the axis, falling linearly in angle
    /// to zero at `cutoff_angle` (both in radians, 0 < beam_width ≤ cutoff_angle ≤ π).
    Spot {
        /// γ, radians.
        cutoff_angle: f32,
        /// β, radians.
        beam_width: f32,
    },
    /// Measured photometric data.
    Ies(IesProfile),
}

/// Why a profile cannot be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct ProfileError(pub String);

/// A profile ready for sampling (built once per light by [`BuiltProfile::build`]).
#[derive(Clone, Debug, PartialEq)]
pub enum BuiltProfile {
    /// Uniform sphere (or hemisphere if `hemisphere`).
    Uniform {
        /// Restricted to z > 0.
        hemisphere: bool,
    },
    /// cos θ/π.
    Cosine,
    /// (n+1)/(2π)·cosⁿθ.
    CosinePower {
        /// n.
        exponent: f32,
    },
    /// Mitsuba spot.
    Spot {
        /// γ.
        cutoff: f32,
        /// β.
        beam: f32,
        /// cos γ.
        cos_cutoff: f32,
        /// cos β.
        cos_beam: f32,
        /// ∫ s dω.
        integral: f32,
    },
    /// Tabulated (IES).
    Table(Arc<Table>),
}

/// The refined (θ, φ) grid of an IES profile with its sampling tables.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// θ nodes, radians, increasing.
    thetas: Vec<f32>,
    /// cos of the θ nodes.
    cos_thetas: Vec<f32>,
    /// φ nodes, radians, from 0 to 2π.
    phis: Vec<f32>,
    /// Candela at the nodes, `values[i * phis.len() + j]`.
    values: Vec<f32>,
    /// Cumulative row probabilities (one per θ interval), last = 1.
    row_cdf: Vec<f32>,
    /// Per row, cumulative cell probabilities within the row (last of each row = 1).
    cell_cdf: Vec<f32>,
    /// Probability of each cell (absolute).
    cell_p: Vec<f32>,
    /// ∫ candela dω, lumens (exact for the bilinear interpolant).
    flux_lm: f64,
}

fn bad(msg: impl Into<String>) -> ProfileError {
    ProfileError(msg.into())
}

impl BuiltProfile {
    /// Validates `p` and precomputes what sampling needs. `hemisphere`: the profile belongs to
    /// a one-sided area light, which emits only into z > 0.
    pub fn build(p: &EmissionProfile, hemisphere: bool) -> Result<BuiltProfile, ProfileError> {
        Ok(match p {
            EmissionProfile::Uniform => BuiltProfile::Uniform { hemisphere },
            EmissionProfile::Cosine => BuiltProfile::Cosine,
            &EmissionProfile::CosinePower { exponent } => {
                if !(0.0..=1e6).contains(&exponent) {
                    return Err(bad(format!("the cosine-power exponent {exponent} must be in [0, 10⁶]")));
                }
                BuiltProfile::CosinePower { exponent }
            }
            &EmissionProfile::Spot { cutoff_angle, beam_width } => {
                let max = if hemisphere { 0.5 * PI } else { PI };
                if !(cutoff_angle > 0.0 && cutoff_angle <= max) {
                    return Err(bad(format!(
                        "the spot cutoff angle {}° must be in (0°, {}°]",
                        cutoff_angle.to_degrees(),
                        max.to_degrees()
                    )));
                }
                if !(beam_width > 0.0 && beam_width <= cutoff_angle) {
                    return Err(bad(format!(
                        "the spot beam width {}° must be in (0°, cutoff angle = {}°]",
                        beam_width.to_degrees(),
                        cutoff_angle.to_degrees()
                    )));
                }
                BuiltProfile::Spot {
                    cutoff: cutoff_angle,
                    beam: beam_width,
                    cos_cutoff: cutoff_angle.cos(),
                    cos_beam: beam_width.cos(),
                    integral: spot_integral(cutoff_angle as f64, beam_width as f64) as f32,
                }
            }
            EmissionProfile::Ies(ies) => BuiltProfile::Table(Arc::new(Table::build(ies, hemisphere)?)),
        })
    }

    /// The unnormalised shape s(ω) of a local unit direction (z = axis); W/sr per unit strength
    /// (candela/683 for IES).
    #[inline]
    pub fn shape(&self, v: Vec3) -> f32 {
        match self {
            BuiltProfile::Uniform { hemisphere } => {
                if !hemisphere || v.z > 0.0 {
                    1.0
                } else {
                    0.0
                }
            }
            BuiltProfile::Cosine => v.z.max(0.0),
            BuiltProfile::CosinePower { exponent } => {
                if v.z > 0.0 {
                    warp::pow_cos_from_versine(1.0 - v.z, *exponent)
                } else {
                    0.0
                }
            }
            &BuiltProfile::Spot { cutoff, beam, cos_cutoff, cos_beam, .. } => {
                if v.z >= cos_beam {
                    1.0
                } else if v.z > cos_cutoff {
                    ((cutoff - v.z.clamp(-1.0, 1.0).acos()) / (cutoff - beam)).clamp(0.0, 1.0)
                } else {
                    0.0
                }
            }
            BuiltProfile::Table(t) => t.candela(v) / LUMENS_PER_WATT,
        }
    }

    /// S = ∫ s(ω) dω.
    pub fn integral(&self) -> f32 {
        match self {
            BuiltProfile::Uniform { hemisphere: false } => 4.0 * PI,
            BuiltProfile::Uniform { hemisphere: true } => TAU,
            BuiltProfile::Cosine => PI,
            BuiltProfile::CosinePower { exponent } => TAU / (exponent + 1.0),
            BuiltProfile::Spot { integral, .. } => *integral,
            BuiltProfile::Table(t) => (t.flux_lm / LUMENS_PER_WATT as f64) as f32,
        }
    }

    /// The emission density f_e(ω) = s(ω)/S of a local unit direction.
    #[inline]
    pub fn eval(&self, v: Vec3) -> f32 {
        match self {
            BuiltProfile::Cosine => v.z.max(0.0) * FRAC_1_PI,
            BuiltProfile::CosinePower { exponent } if v.z > 0.0 => {
                warp::phong_lobe_pdf_from_versine(1.0 - v.z, *exponent)
            }
            _ => self.shape(v) / self.integral(),
        }
    }

    /// f_e(ω)/cos θ: L_e·A/Φ for an area light (1/π for a Lambertian one); 0 behind it.
    #[inline]
    pub fn emitted_fraction(&self, v: Vec3) -> f32 {
        match self {
            BuiltProfile::Cosine => FRAC_1_PI,
            _ if v.z > 0.0 => self.eval(v) / v.z,
            _ => 0.0,
        }
    }

    /// The density of the directions [`BuiltProfile::sample`] draws (equal to [`Self::eval`]
    /// for the exactly sampled profiles).
    pub fn sampling_pdf(&self, v: Vec3) -> f32 {
        match self {
            &BuiltProfile::Spot { cos_cutoff, .. } => {
                if v.z > cos_cutoff {
                    1.0 / (TAU * (1.0 - cos_cutoff))
                } else {
                    0.0
                }
            }
            BuiltProfile::Table(t) => t.pdf(v),
            BuiltProfile::Uniform { hemisphere: true } => {
                if v.z > 0.0 {
                    warp::UNIFORM_HEMISPHERE_PDF
                } else {
                    0.0
                }
            }
            _ => self.eval(v),
        }
    }

    /// Draws a local direction from `u` ∈ [0,1)²; returns it with the weight f_e(ω)/p(ω)
    /// (1 for exactly sampled profiles, mean 1 always).
    #[inline]
    pub fn sample(&self, u: crate::math::Vec2) -> (Vec3, f32) {
        match self {
            BuiltProfile::Uniform { hemisphere: false } => (warp::square_to_uniform_sphere(u), 1.0),
            BuiltProfile::Uniform { hemisphere: true } => (warp::square_to_uniform_hemisphere(u), 1.0),
            BuiltProfile::Cosine => (warp::square_to_cosine_hemisphere(u), 1.0),
            BuiltProfile::CosinePower { exponent } => {
                // u.x = 0 would give the horizon exactly; keep it strictly inside.
                let ux = 1.0 - u.x; // (0, 1]
                (warp::square_to_phong_lobe(crate::math::Vec2::new(ux, u.y), *exponent), 1.0)
            }
            &BuiltProfile::Spot { cos_cutoff, integral, .. } => {
                let z = 1.0 - u.x * (1.0 - cos_cutoff);
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = TAU * u.y;
                let v = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                let w = self.shape(v) * TAU * (1.0 - cos_cutoff) / integral;
                (v, w)
            }
            BuiltProfile::Table(t) => t.sample(u),
        }
    }

    /// Whether the distribution depends on the azimuth φ (IES tables). A profile that does not
    /// is invariant under rotations about its axis, so any frame with that axis evaluates and
    /// samples it alike; one that does needs a defined φ = 0 direction.
    #[inline]
    pub fn depends_on_azimuth(&self) -> bool {
        matches!(self, BuiltProfile::Table(_))
    }

    /// Feeds what defines the distribution (not its scale) to a hash.
    pub(crate) fn hash_into(&self, h: &mut blake3::Hasher) {
        match self {
            BuiltProfile::Uniform { hemisphere } => {
                h.update(if *hemisphere { b"uniform hemisphere" } else { b"uniform sphere...." });
            }
            BuiltProfile::Cosine => {
                h.update(b"cosine");
            }
            BuiltProfile::CosinePower { exponent } => {
                h.update(b"cosine power");
                h.update(&exponent.to_le_bytes());
            }
            BuiltProfile::Spot { cutoff, beam, .. } => {
                h.update(b"spot");
                h.update(&cutoff.to_le_bytes());
                h.update(&beam.to_le_bytes());
            }
            BuiltProfile::Table(t) => {
                h.update(b"table");
                for v in t.thetas.iter().chain(&t.phis).chain(&t.values) {
                    h.update(&v.to_le_bytes());
                }
            }
        }
    }
}

/// ∫ s dω of Mitsuba's spot (linear falloff in angle from β to γ), in closed form:
/// 2π·[1 − (sin γ − sin β)/(γ − β)], and 2π(1 − cos γ) when β = γ.
pub fn spot_integral(cutoff: f64, beam: f64) -> f64 {
    let d = cutoff - beam;
    if d <= 1e-9 {
        return 2.0 * PI64 * (1.0 - cutoff.cos());
    }
    2.0 * PI64 * (1.0 - (cutoff.sin() - beam.sin()) / d)
}

/// ∫_{θa}^{θb} (1 − s)·sin θ dθ and ∫ s·sin θ dθ with s = (θ − θa)/(θb − θa).
fn theta_weights(a: f64, b: f64) -> (f64, f64) {
    let d = b - a;
    let w1 = (b.sin() - a.sin()) / d - b.cos();
    let w0 = (a.cos() - b.cos()) - w1;
    (w0, w1)
}

/// Piecewise-linear interpolation of `ys` at `x` over increasing `xs`.
fn lerp_at(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    if xs.len() == 1 {
        return ys[0];
    }
    let i = xs.partition_point(|&t| t <= x).clamp(1, xs.len() - 1);
    let t = ((x - xs[i - 1]) / (xs[i] - xs[i - 1])).clamp(0.0, 1.0);
    ys[i - 1] * (1.0 - t) + ys[i] * t
}

/// Picks an index from a cumulative table (last = 1) and returns it with the rescaled remainder.
#[inline]
fn pick(cdf: &[f32], u: f32) -> (usize, f32) {
    let i = cdf.partition_point(|&c| c <= u).min(cdf.len() - 1);
    let lo = if i == 0 { 0.0 } else { cdf[i - 1] };
    let w = cdf[i] - lo;
    let r = if w > 0.0 { ((u - lo) / w).clamp(0.0, 1.0 - f32::EPSILON / 2.0) } else { 0.5 };
    (i, r)
}

impl Table {
    fn build(ies: &IesProfile, hemisphere: bool) -> Result<Table, ProfileError> {
        let (nv, nh) = (ies.vertical_angles.len(), ies.horizontal_angles.len());
        if nv < 2 {
            return Err(bad(format!("an IES profile needs at least 2 vertical angles, found {nv}")));
        }
        if nh < 1 || ies.candela.len() != nv * nh {
            return Err(bad(format!(
                "an IES profile with {nv} vertical and {nh} horizontal angles needs {} candela values, found {}",
                nv * nh,
                ies.candela.len()
            )));
        }
        let va: Vec<f64> = ies.vertical_angles.iter().map(|&a| a as f64).collect();
        let ha: Vec<f64> = ies.horizontal_angles.iter().map(|&a| a as f64).collect();
        if !va.iter().all(|a| a.is_finite() && (0.0..=180.0).contains(a))
            || !va.windows(2).all(|w| w[0] < w[1])
        {
            return Err(bad("IES vertical angles must increase strictly within [0°, 180°]"));
        }
        if !ha.windows(2).all(|w| w[0] < w[1]) || ha[0] != 0.0 {
            return Err(bad("IES horizontal angles must start at 0° and increase strictly"));
        }
        let last = *ha.last().unwrap();
        if !(nh == 1 || last == 90.0 || last == 180.0 || last == 360.0) {
            return Err(bad(format!(
                "IES horizontal angles end at {last}°: supported are 0° (symmetric), 90°, 180° and 360°"
            )));
        }
        if let Some(c) = ies.candela.iter().find(|c| !(c.is_finite() && **c >= 0.0)) {
            return Err(bad(format!("IES candela value {c} must be finite and non-negative")));
        }
        // Fold a horizontal angle (degrees, [0, 360]) into the file's range.
        let fold = |phi: f64| -> f64 {
            let mut p = phi;
            if nh == 1 {
                return 0.0;
            }
            if last <= 180.0 && p > 180.0 {
                p = 360.0 - p;
            }
            if last <= 90.0 && p > 90.0 {
                p = 180.0 - p;
            }
            p
        };
        // Candela of the file at (θ°, φ°): bilinear on the file grid after folding.
        let column = |h: usize| -> Vec<f64> { (0..nv).map(|v| ies.candela[h * nv + v] as f64).collect() };
        let columns: Vec<Vec<f64>> = (0..nh).map(column).collect();
        let file_value = |theta: f64, phi: f64| -> f64 {
            if theta < va[0] - 1e-9 || theta > va[nv - 1] + 1e-9 {
                return 0.0;
            }
            let at: Vec<f64> = columns.iter().map(|c| lerp_at(&va, c, theta)).collect();
            lerp_at(&ha, &at, fold(phi))
        };
        // Coarse nodes: file angles (and their mirror images), then refined.
        let mut tnodes: Vec<f64> = vec![0.0, 180.0];
        tnodes.extend(&va);
        if hemisphere {
            tnodes.push(90.0);
        }
        let mut pnodes: Vec<f64> = vec![0.0, 360.0];
        for &h in &ha {
            pnodes.extend([h, 360.0 - h]);
            if last <= 90.0 {
                pnodes.extend([180.0 - h, 180.0 + h]);
            }
        }
        let refine = |mut nodes: Vec<f64>, max_step: f64, hi: f64| -> Vec<f64> {
            nodes.retain(|x| (0.0..=hi).contains(x));
            nodes.sort_by(f64::total_cmp);
            nodes.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
            let mut out = vec![nodes[0]];
            for w in nodes.windows(2) {
                let k = ((w[1] - w[0]) / max_step).ceil().max(1.0) as usize;
                for s in 1..=k {
                    out.push(w[0] + (w[1] - w[0]) * s as f64 / k as f64);
                }
            }
            out
        };
        let thetas = refine(tnodes, 2.0, if hemisphere { 90.0 } else { 180.0 });
        let phis = refine(pnodes, 5.0, 360.0);
        let np = phis.len();
        let mut values = Vec::with_capacity(thetas.len() * np);
        for &t in &thetas {
            for &p in &phis {
                values.push(file_value(t, p));
            }
        }
        // A node on the boundary of the file's vertical range belongs to it; a cell straddling
        // beyond it would interpolate towards 0 only if the file's range ends at a node (it does).
        let (tr, pr): (Vec<f64>, Vec<f64>) =
            (thetas.iter().map(|t| t.to_radians()).collect(), phis.iter().map(|p| p.to_radians()).collect());
        let mut flux = 0.0f64;
        let mut mass = Vec::with_capacity((tr.len() - 1) * (np - 1));
        for i in 0..tr.len() - 1 {
            let (w0, w1) = theta_weights(tr[i], tr[i + 1]);
            let solid = tr[i].cos() - tr[i + 1].cos();
            for j in 0..np - 1 {
                let dphi = pr[j + 1] - pr[j];
                let v = |a: usize, b: usize| values[(i + a) * np + j + b];
                let (a0, a1, b0, b1) = (v(0, 0), v(0, 1), v(1, 0), v(1, 1));
                // Outside the file's vertical range the intensity is 0 even between nodes.
                let mid = 0.5 * (thetas[i] + thetas[i + 1]);
                let inside = mid >= va[0] && mid <= va[nv - 1];
                if !inside {
                    mass.push(0.0);
                    continue;
                }
                flux += dphi * (w0 * 0.5 * (a0 + a1) + w1 * 0.5 * (b0 + b1));
                mass.push(a0.max(a1).max(b0).max(b1) * solid * dphi);
            }
        }
        let total: f64 = mass.iter().sum();
        if !(total > 0.0) || !(flux > 0.0) {
            return Err(bad("the IES profile emits nothing (all candela values are zero)"));
        }
        let mut row_cdf = Vec::new();
        let mut cell_cdf = Vec::with_capacity(mass.len());
        let mut acc = 0.0;
        for row in mass.chunks(np - 1) {
            let rsum: f64 = row.iter().sum();
            acc += rsum;
            row_cdf.push((acc / total) as f32);
            let mut c = 0.0;
            for m in row {
                c += m;
                cell_cdf.push(if rsum > 0.0 { (c / rsum) as f32 } else { 1.0 });
            }
        }
        *row_cdf.last_mut().unwrap() = 1.0;
        let cell_p = mass.iter().map(|m| (m / total) as f32).collect();
        Ok(Table {
            cos_thetas: tr.iter().map(|t| t.cos() as f32).collect(),
            thetas: tr.iter().map(|&t| t as f32).collect(),
            phis: pr.iter().map(|&p| p as f32).collect(),
            values: values.iter().map(|&v| v as f32).collect(),
            row_cdf,
            cell_cdf,
            cell_p,
            flux_lm: flux,
        })
    }

    /// Luminous flux of the (interpolated) distribution, lumens.
    pub fn flux_lumens(&self) -> f64 {
        self.flux_lm
    }

    /// The cell of a local unit direction, or `None` outside the table.
    #[inline]
    fn cell(&self, v: Vec3) -> Option<(usize, usize, f32, f32)> {
        let theta = v.z.clamp(-1.0, 1.0).acos();
        let mut phi = v.y.atan2(v.x);
        if phi < 0.0 {
            phi += TAU;
        }
        let nt = self.thetas.len();
        if theta > self.thetas[nt - 1] {
            return None;
        }
        let i = self.thetas.partition_point(|&t| t <= theta).clamp(1, nt - 1) - 1;
        let j = self.phis.partition_point(|&p| p <= phi).clamp(1, self.phis.len() - 1) - 1;
        Some((i, j, theta, phi))
    }

    /// Candela in a local direction (bilinear in θ, φ).
    #[inline]
    pub fn candela(&self, v: Vec3) -> f32 {
        let Some((i, j, theta, phi)) = self.cell(v) else { return 0.0 };
        let np = self.phis.len();
        if self.cell_p[i * (np - 1) + j] == 0.0 {
            return 0.0;
        }
        let s = ((theta - self.thetas[i]) / (self.thetas[i + 1] - self.thetas[i])).clamp(0.0, 1.0);
        let t = ((phi - self.phis[j]) / (self.phis[j + 1] - self.phis[j])).clamp(0.0, 1.0);
        let val = |a: usize, b: usize| self.values[(i + a) * np + j + b];
        let lo = val(0, 0) * (1.0 - t) + val(0, 1) * t;
        let hi = val(1, 0) * (1.0 - t) + val(1, 1) * t;
        lo * (1.0 - s) + hi * s
    }

    fn solid_angle(&self, i: usize, j: usize) -> f32 {
        (self.cos_thetas[i] - self.cos_thetas[i + 1]) * (self.phis[j + 1] - self.phis[j])
    }

    /// Density of `Table::sample`'s directions.
    pub fn pdf(&self, v: Vec3) -> f32 {
        let Some((i, j, _, _)) = self.cell(v) else { return 0.0 };
        self.cell_p[i * (self.phis.len() - 1) + j] / self.solid_angle(i, j)
    }

    fn sample(&self, u: crate::math::Vec2) -> (Vec3, f32) {
        let np1 = self.phis.len() - 1;
        let (i, rx) = pick(&self.row_cdf, u.x);
        let (j, ry) = pick(&self.cell_cdf[i * np1..(i + 1) * np1], u.y);
        let z = self.cos_thetas[i] + rx * (self.cos_thetas[i + 1] - self.cos_thetas[i]);
        let phi = self.phis[j] + ry * (self.phis[j + 1] - self.phis[j]);
        let r = (1.0 - z * z).max(0.0).sqrt();
        let v = Vec3::new(r * phi.cos(), r * phi.sin(), z);
        // Weight from the direction itself, so that it agrees with `pdf` and `candela` even
        // when rounding puts v on a neighbouring cell's edge.
        let p = self.pdf(v);
        let w = if p > 0.0 { (self.candela(v) as f64 / (self.flux_lm * p as f64)) as f32 } else { 0.0 };
        (v, w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::Chi2Test;
    use crate::math::Vec2;
    use crate::sampling::RandomStream;

    fn asymmetric() -> IesProfile {
        IesProfile {
            vertical_angles: vec![0.0, 30.0, 60.0, 90.0, 120.0, 180.0],
            horizontal_angles: vec![0.0, 90.0, 180.0],
            candela: vec![
                500.0, 450.0, 300.0, 100.0, 20.0, 0.0, // φ = 0
                500.0, 400.0, 200.0, 50.0, 10.0, 0.0, // φ = 90
                500.0, 300.0, 100.0, 10.0, 0.0, 0.0, // φ = 180
            ],
        }
    }

    fn profiles() -> Vec<(EmissionProfile, bool)> {
        vec![
            (EmissionProfile::Uniform, false),
            (EmissionProfile::Uniform, true),
            (EmissionProfile::Cosine, true),
            (EmissionProfile::CosinePower { exponent: 12.0 }, true),
            (EmissionProfile::Spot { cutoff_angle: 0.6, beam_width: 0.3 }, false),
            (EmissionProfile::Spot { cutoff_angle: 2.5, beam_width: 2.5 }, false),
            (EmissionProfile::Ies(asymmetric()), false),
            (EmissionProfile::Ies(asymmetric()), true),
        ]
    }

    /// ∫ f_e dω = 1 by brute-force quadrature over the sphere, for every profile.
    #[test]
    fn densities_integrate_to_one() {
        let (nt, np) = (1440, 720);
        for (p, hemi) in profiles() {
            let b = BuiltProfile::build(&p, hemi).unwrap();
            let mut sum = 0.0f64;
            for i in 0..nt {
                let th = (i as f64 + 0.5) / nt as f64 * PI64;
                for j in 0..np {
                    let ph = (j as f64 + 0.5) / np as f64 * 2.0 * PI64;
                    let v = Vec3::new(
                        (th.sin() * ph.cos()) as f32,
                        (th.sin() * ph.sin()) as f32,
                        th.cos() as f32,
                    );
                    sum += b.eval(v) as f64 * th.sin();
                }
            }
            sum *= (PI64 / nt as f64) * (2.0 * PI64 / np as f64);
            assert!((sum - 1.0).abs() < 2e-3, "{p:?} hemisphere={hemi}: ∫f_e = {sum}");
        }
    }

    /// Sampling matches the sampling pdf (χ²), and the weights are f_e/p.
    #[test]
    fn chi2_profile_sampling() {
        for (k, (p, hemi)) in profiles().into_iter().enumerate() {
            let b = BuiltProfile::build(&p, hemi).unwrap();
            Chi2Test::new(Vec3::Z, 900 + k as u64)
                .run(
                    |_, u| {
                        let (v, w) = b.sample(u);
                        let pdf = b.sampling_pdf(v);
                        let expect = b.eval(v) / pdf;
                        assert!(
                            (w - expect).abs() <= 1e-3 * expect.max(1.0),
                            "{p:?}: weight {w} vs {expect}"
                        );
                        Some((v, pdf))
                    },
                    |v| b.sampling_pdf(v),
                )
                .assert_ok(&format!("{p:?} hemisphere={hemi}"));
        }
    }

    /// The mean weight of sampled directions is 1 (the estimator of Φ is exact).
    #[test]
    fn mean_weight_is_one() {
        for (p, hemi) in profiles() {
            let b = BuiltProfile::build(&p, hemi).unwrap();
            let mut rng = RandomStream::new(77, &[]);
            let n = 400_000;
            let (mut s, mut s2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let w = b.sample(rng.next_2d()).1 as f64;
                s += w;
                s2 += w * w;
            }
            let m = s / n as f64;
            let se = ((s2 / n as f64 - m * m).max(0.0) / n as f64).sqrt();
            assert!((m - 1.0).abs() <= 4.0 * se + 1e-4, "{p:?}: mean weight {m} ± {se}");
        }
    }

    #[test]
    fn spot_integral_matches_quadrature() {
        for (g, b) in [(0.6f64, 0.3f64), (1.2, 0.2), (0.35, 0.35), (3.0, 1.0)] {
            let n = 200_000;
            let mut s = 0.0;
            for i in 0..n {
                let th = (i as f64 + 0.5) / n as f64 * PI64;
                let f = if th <= b {
                    1.0
                } else if th < g {
                    (g - th) / (g - b)
                } else {
                    0.0
                };
                s += f * th.sin();
            }
            s *= 2.0 * PI64 * PI64 / n as f64;
            assert!(
                (s / spot_integral(g, b) - 1.0).abs() < 1e-4,
                "γ={g} β={b}: {s} vs {}",
                spot_integral(g, b)
            );
        }
    }

    /// Flux of a table against a hand computation: 200 cd at 0°, 100 at 90°, 0 at 180°,
    /// bilinear → exactly 400π lm (the same as a uniform 100 cd).
    #[test]
    fn table_flux_is_exact() {
        let ies = IesProfile {
            vertical_angles: vec![0.0, 90.0, 180.0],
            horizontal_angles: vec![0.0],
            candela: vec![200.0, 100.0, 0.0],
        };
        let b = BuiltProfile::build(&EmissionProfile::Ies(ies), false).unwrap();
        let BuiltProfile::Table(t) = &b else { unreachable!() };
        assert!((t.flux_lumens() / (400.0 * PI64) - 1.0).abs() < 1e-9, "{}", t.flux_lumens());
        // Symmetry: quadrant-symmetric file evaluated in all four quadrants.
        let q = IesProfile {
            vertical_angles: vec![0.0, 90.0],
            horizontal_angles: vec![0.0, 90.0],
            candela: vec![10.0, 10.0, 10.0, 0.0],
        };
        let b = BuiltProfile::build(&EmissionProfile::Ies(q), false).unwrap();
        let th = 89.9f32.to_radians(); // just inside the file's range [0°, 90°]
        let at = |phi: f32| {
            b.shape(Vec3::new(th.sin() * phi.cos(), th.sin() * phi.sin(), th.cos())) * LUMENS_PER_WATT
        };
        for (phi, cd) in [(0.0, 10.0), (90.0, 0.0), (180.0, 10.0), (270.0, 0.0), (45.0, 5.0), (315.0, 5.0)] {
            assert!((at(f32::to_radians(phi)) - cd).abs() < 0.02, "φ={phi}: {}", at(f32::to_radians(phi)));
        }
        assert_eq!(b.shape(Vec3::new(0.0, 0.0, -1.0)), 0.0, "beyond the file's vertical range");
        let _ = Vec2::ZERO;
    }

    #[test]
    fn impossible_parameters_are_errors() {
        for p in [
            EmissionProfile::CosinePower { exponent: -1.0 },
            EmissionProfile::CosinePower { exponent: f32::NAN },
            EmissionProfile::Spot { cutoff_angle: 0.0, beam_width: 0.0 },
            EmissionProfile::Spot { cutoff_angle: -0.5, beam_width: 0.1 },
            EmissionProfile::Spot { cutoff_angle: 0.5, beam_width: 0.6 },
            EmissionProfile::Spot { cutoff_angle: f32::NAN, beam_width: 0.1 },
            EmissionProfile::Ies(IesProfile {
                vertical_angles: vec![0.0],
                horizontal_angles: vec![0.0],
                candela: vec![1.0],
            }),
            EmissionProfile::Ies(IesProfile {
                vertical_angles: vec![0.0, 90.0],
                horizontal_angles: vec![0.0],
                candela: vec![1.0],
            }),
            EmissionProfile::Ies(IesProfile {
                vertical_angles: vec![0.0, 90.0],
                horizontal_angles: vec![0.0],
                candela: vec![1.0, -1.0],
            }),
            EmissionProfile::Ies(IesProfile {
                vertical_angles: vec![0.0, 90.0],
                horizontal_angles: vec![0.0],
                candela: vec![0.0, 0.0],
            }),
            EmissionProfile::Ies(IesProfile {
                vertical_angles: vec![90.0, 0.0],
                horizontal_angles: vec![0.0],
                candela: vec![1.0, 1.0],
            }),
            EmissionProfile::Ies(IesProfile {
                vertical_angles: vec![0.0, 90.0],
                horizontal_angles: vec![0.0, 45.0],
                candela: vec![1.0; 4],
            }),
        ] {
            assert!(BuiltProfile::build(&p, false).is_err(), "{p:?}");
        }
        assert!(
            BuiltProfile::build(&EmissionProfile::Spot { cutoff_angle: 2.0, beam_width: 1.0 }, true).is_err()
        );
    }
}
