//! IES photometric tables as emission profiles: the plain [`IesProfile`] a reader produces
//! (`opticks_io::ies`), its checks ([`IesProfile::validate`], the one place an IES grid's
//! constraints are written), and the refined [`Table`] that
//! [`BuiltProfile::Table`](super::BuiltProfile::Table) evaluates and samples.
//!
//! An [`IesProfile`] gives candela on a grid of vertical angles θ (0° = the light's axis, the
//! nadir of a downlight; photometric type C) and horizontal angles φ (0° = local +x, 90° =
//! local +y) with LM-63's symmetries (one horizontal angle: rotationally symmetric; 0–90:
//! quadrant symmetric; 0–180: bilateral; 0–360: full). The intensity between grid points is the
//! **bilinear interpolation in (θ, φ)** of the candela values, and zero outside the vertical
//! range of the file. The flux of that interpolant is integrated in closed form cell by cell
//! (the integrand is bilinear in θ, φ times sin θ), so Φ (lumens) is exact for the distribution
//! that is actually emitted. For sampling, the grid is refined (cells at most 2° × 5°; a
//! bilinear function stays bilinear on sub-cells), each cell gets the probability ∝ (largest
//! corner value) × (solid angle), and a direction is drawn uniformly in solid angle inside the
//! chosen cell. On an area light the table is cut at 90°.

use crate::math::Vec3;
use std::f32::consts::TAU;

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

/// Which angles of an IES grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IesAxis {
    /// The vertical angles θ.
    Vertical,
    /// The horizontal angles φ.
    Horizontal,
}

impl std::fmt::Display for IesAxis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            IesAxis::Vertical => "vertical",
            IesAxis::Horizontal => "horizontal",
        })
    }
}

/// Why an IES grid is not a usable profile. Indices are 0-based (the messages count from 1), so
/// a reader can point at the value's line.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum IesTableError {
    /// Fewer than 2 vertical or 1 horizontal angles.
    #[error(
        "at least 2 vertical angles and 1 horizontal angle are needed, found {vertical} and {horizontal}"
    )]
    TooFewAngles {
        /// Vertical angle count.
        vertical: usize,
        /// Horizontal angle count.
        horizontal: usize,
    },
    /// Angle `index` does not exceed the one before it.
    #[error("{axis} angles must increase: {next} follows {previous}")]
    NotIncreasing {
        /// Which angles.
        axis: IesAxis,
        /// Index of the offending (later) angle.
        index: usize,
        /// The angle before it.
        previous: f32,
        /// The offending angle.
        next: f32,
    },
    /// The vertical angles leave [0°, 180°].
    #[error("vertical angles must lie in [0, 180] for type C, found {first}..{last}")]
    VerticalRange {
        /// First vertical angle.
        first: f32,
        /// Last vertical angle.
        last: f32,
    },
    /// The horizontal angles do not start at 0° or end at 0°, 90°, 180° or 360°.
    #[error("horizontal angles {first}..{last}: supported are 0 (symmetric), 0–90, 0–180 and 0–360")]
    HorizontalRange {
        /// First horizontal angle.
        first: f32,
        /// Last horizontal angle.
        last: f32,
    },
    /// The candela list does not match the grid.
    #[error("{vertical} vertical and {horizontal} horizontal angles need {} candela values, found {found}", vertical * horizontal)]
    CandelaCount {
        /// Vertical angle count.
        vertical: usize,
        /// Horizontal angle count.
        horizontal: usize,
        /// Candela values given.
        found: usize,
    },
    /// A candela value is negative or not finite.
    #[error("candela value {} of horizontal angle {} is {}", .vertical + 1, .horizontal + 1, what_is_wrong(*.value))]
    BadCandela {
        /// Horizontal angle index.
        horizontal: usize,
        /// Vertical angle index.
        vertical: usize,
        /// The value.
        value: f32,
    },
    /// Every candela value is zero.
    #[error("the IES profile emits nothing (all candela values are zero)")]
    EmitsNothing,
}

fn what_is_wrong(value: f32) -> String {
    if value.is_finite() { format!("negative ({value})") } else { format!("not finite ({value})") }
}

impl IesProfile {
    /// Checks an angle grid: at least 2 vertical and 1 horizontal angles, each list strictly
    /// increasing, vertical angles within [0°, 180°], horizontal ones from 0° to 0°, 90°, 180° or
    /// 360° (the LM-63 type C symmetries).
    pub fn check_angles(vertical: &[f32], horizontal: &[f32]) -> Result<(), IesTableError> {
        let (nv, nh) = (vertical.len(), horizontal.len());
        if nv < 2 || nh < 1 {
            return Err(IesTableError::TooFewAngles { vertical: nv, horizontal: nh });
        }
        for (axis, angles) in [(IesAxis::Vertical, vertical), (IesAxis::Horizontal, horizontal)] {
            if let Some(index) = (1..angles.len()).find(|&i| !(angles[i] > angles[i - 1])) {
                return Err(IesTableError::NotIncreasing {
                    axis,
                    index,
                    previous: angles[index - 1],
                    next: angles[index],
                });
            }
        }
        let (first, last) = (vertical[0], vertical[nv - 1]);
        if !(first >= 0.0 && last <= 180.0) {
            return Err(IesTableError::VerticalRange { first, last });
        }
        let (first, last) = (horizontal[0], horizontal[nh - 1]);
        if first != 0.0 || !(nh == 1 || last == 90.0 || last == 180.0 || last == 360.0) {
            return Err(IesTableError::HorizontalRange { first, last });
        }
        Ok(())
    }

    /// Checks the candela value of horizontal angle `horizontal` and vertical angle `vertical`:
    /// finite and non-negative.
    pub fn check_candela(horizontal: usize, vertical: usize, value: f32) -> Result<(), IesTableError> {
        if value.is_finite() && value >= 0.0 {
            Ok(())
        } else {
            Err(IesTableError::BadCandela { horizontal, vertical, value })
        }
    }

    /// Checks the whole profile: the angles ([`Self::check_angles`]), one candela value per grid
    /// point, each valid ([`Self::check_candela`]). (Whether it emits at all is known once the
    /// table is built.)
    pub fn validate(&self) -> Result<(), IesTableError> {
        Self::check_angles(&self.vertical_angles, &self.horizontal_angles)?;
        let (nv, nh) = (self.vertical_angles.len(), self.horizontal_angles.len());
        if self.candela.len() != nv * nh {
            return Err(IesTableError::CandelaCount {
                vertical: nv,
                horizontal: nh,
                found: self.candela.len(),
            });
        }
        self.candela.iter().enumerate().try_for_each(|(k, &c)| Self::check_candela(k / nv, k % nv, c))
    }
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
    /// Validates `ies` ([`IesProfile::validate`]) and refines it for sampling; cut at 90° if
    /// `hemisphere` (an area light's profile).
    pub(super) fn build(ies: &IesProfile, hemisphere: bool) -> Result<Table, IesTableError> {
        ies.validate()?;
        let (nv, nh) = (ies.vertical_angles.len(), ies.horizontal_angles.len());
        let va: Vec<f64> = ies.vertical_angles.iter().map(|&a| a as f64).collect();
        let ha: Vec<f64> = ies.horizontal_angles.iter().map(|&a| a as f64).collect();
        let last = *ha.last().unwrap();
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
            return Err(IesTableError::EmitsNothing);
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

    /// Density of the directions the table's sampling draws ([`super::BuiltProfile::sample`]).
    pub fn pdf(&self, v: Vec3) -> f32 {
        let Some((i, j, _, _)) = self.cell(v) else { return 0.0 };
        self.cell_p[i * (self.phis.len() - 1) + j] / self.solid_angle(i, j)
    }

    /// Draws a local direction from `u` with the weight f_e/p (see [`super::BuiltProfile::sample`]).
    pub(super) fn sample(&self, u: crate::math::Vec2) -> (Vec3, f32) {
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

    /// The refined grid: θ nodes and φ nodes (radians) and the candela at the nodes (θ-major),
    /// which define the distribution (what a light's shape hash covers).
    pub(crate) fn grid(&self) -> (&[f32], &[f32], &[f32]) {
        (&self.thetas, &self.phis, &self.values)
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::super::{BuiltProfile, EmissionProfile, LUMENS_PER_WATT};
    use super::*;
    use std::f64::consts::PI as PI64;

    /// A bilateral (0–180°) table whose lobe leans towards φ = 0.
    pub(in crate::light) fn asymmetric() -> IesProfile {
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
    }

    /// Each constraint is reported as what it is, with the index a reader maps to its line.
    #[test]
    fn validation_names_the_offending_value() {
        let e = |v: &[f32], h: &[f32]| IesProfile::check_angles(v, h).unwrap_err();
        assert_eq!(e(&[0.0], &[0.0]), IesTableError::TooFewAngles { vertical: 1, horizontal: 1 });
        assert_eq!(
            e(&[0.0, 10.0, 10.0], &[0.0]),
            IesTableError::NotIncreasing { axis: IesAxis::Vertical, index: 2, previous: 10.0, next: 10.0 }
        );
        assert_eq!(
            e(&[0.0, 90.0], &[0.0, 90.0, 45.0]).to_string(),
            "horizontal angles must increase: 45 follows 90"
        );
        assert_eq!(e(&[-5.0, 90.0], &[0.0]), IesTableError::VerticalRange { first: -5.0, last: 90.0 });
        assert_eq!(e(&[0.0, 90.0], &[0.0, 45.0]), IesTableError::HorizontalRange { first: 0.0, last: 45.0 });
        assert_eq!(e(&[0.0, 90.0], &[5.0]), IesTableError::HorizontalRange { first: 5.0, last: 5.0 });
        assert_eq!(
            IesProfile::check_candela(0, 1, -1.0).unwrap_err().to_string(),
            "candela value 2 of horizontal angle 1 is negative (-1)"
        );
        assert!(IesProfile::check_candela(0, 0, f32::NAN).unwrap_err().to_string().contains("not finite"));
        let short =
            IesProfile { vertical_angles: vec![0.0, 90.0], horizontal_angles: vec![0.0], candela: vec![1.0] };
        assert_eq!(
            short.validate(),
            Err(IesTableError::CandelaCount { vertical: 2, horizontal: 1, found: 1 })
        );
        let dark = IesProfile { candela: vec![0.0, 0.0], ..short };
        assert_eq!(dark.validate(), Ok(()));
        assert_eq!(
            BuiltProfile::build(&EmissionProfile::Ies(dark), false),
            Err(IesTableError::EmitsNothing.into())
        );
    }
}
