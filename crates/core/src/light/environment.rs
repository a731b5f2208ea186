//! Environment lights: radiance L(ω) arriving from every direction at infinity — a constant
//! colour (Mitsuba's `constant`) or a latitude-longitude RGB map (Mitsuba's `envmap`). ω is the
//! direction from the scene toward the environment (where the light comes from).
//!
//! **Mitsuba's convention, exactly** (`src/emitters/envmap.cpp`, 3.9): a world direction ω is
//! taken to the map's frame by the inverse of `to_world` (here a rotation), d = R⁻¹·ω, then
//! u = atan2(d.x, −d.z)/2π (wrapped into [0, 1)), v = acos(d.y)/π: +y is the map's top row
//! (v = 0), and d = (sin φ sin θ, cos θ, −cos φ sin θ) for (φ, θ) = (2πu, πv). The lookup is
//! bilinear, texel-centred and periodic in u (column i at u = (i + ½)/W), corner-aligned and
//! clamped in v (row j at v = j/(H − 1)); a map narrower than 2 or lower than 3 texels is padded
//! by repeating its last column and row, as Mitsuba's `Bitmap::pad_to`.
//!
//! **Emission.** Like a directional light ([`super::directional`]), a path starts on a disk of
//! the scene's bounding radius r perpendicular to its direction, just outside the bounding
//! sphere: the direction −ω is drawn first, ω with solid-angle density p(ω), then the start
//! point uniformly on the disk (1/(πr²)). So Φ = πr²·∫L(ω) dω per channel and the start's
//! weight is L(ω)/(p(ω)·∫L dω) (exactly 1 for a constant environment, mean 1 per channel for a
//! map). ∫L dω is exact: the integral of the bilinear interpolant, cell by cell in closed form.
//!
//! **Direction sampling** (emission and the bidirectional estimator's NEE draw with the same
//! density): the sphere is cut into the interpolation cells of the map (W columns between
//! texel centres × H − 1 rows between texel rows); a cell is picked with probability ∝ its exact
//! ∫ luminance(L) dω (a row from the marginal, then a column in it) and ω uniformly in solid
//! angle inside it (φ uniform, cos θ uniform), so p(ω) = P(cell)/Ω(cell) — piecewise constant,
//! positive wherever L is, and the uniform sphere for a uniform map. A constant environment
//! samples the uniform sphere.

use super::check::check_emission;
use super::{Emission, LightError};
use crate::math::{Frame, Mat3, Rgb, Vec2, Vec3};
use crate::sampling::warp;
use std::f64::consts::PI as PI64;

/// What an environment emits.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvRadiance {
    /// The same radiance from every direction (W/(m²·sr) per channel).
    Constant(Rgb),
    /// A latitude-longitude map.
    Map(LatLong),
}

/// A latitude-longitude radiance map with its sampling distribution (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct LatLong {
    width: usize,
    height: usize,
    /// Texels as given (before `scale`), row-major from the top row, padded to ≥ 2 × 3.
    texels: Vec<Rgb>,
    scale: f32,
    /// Per cell (row-major, `width` × (`height` − 1)): its probability.
    cell_prob: Vec<f64>,
    /// Per row of cells: the cumulative probability of the rows up to it (last = 1).
    row_cdf: Vec<f64>,
    /// Per cell: the cumulative probability within its row (each row's last = 1).
    col_cdf: Vec<f64>,
    /// ∫ L(ω) dω per channel (scale included).
    integral: Rgb,
    /// cos θ_k of every texel row k (`height` of them: the bounds of the rows of cells), so
    /// that a density or a draw looks up what it took two `cos` calls to compute.
    row_cos: Vec<f64>,
}

/// Why a map cannot be an environment (the light's name and place are the caller's).
fn map_error(message: String) -> LightError {
    LightError::Map(message)
}

impl LatLong {
    /// The map of `width` × `height` texels (row-major from the top row; linear RGB, each
    /// finite and non-negative) scaled by `scale` (finite, ≥ 0). Its size is bounded only by
    /// the texels given (the file reader bounds them: `opticks_io`'s `LoadLimits::max_texels`,
    /// which the CLI's `--max-texels` raises); the map and its distribution take about 36
    /// bytes a texel.
    pub fn new(width: usize, height: usize, texels: &[Rgb], scale: f32) -> Result<Self, LightError> {
        if width == 0 || height == 0 {
            return Err(map_error(format!("the map is {width} × {height}: it has no texels")));
        }
        if width.checked_mul(height) != Some(texels.len()) {
            return Err(map_error(format!("the map is {width} × {height} but has {} texels", texels.len())));
        }
        if let Some(i) = texels.iter().position(|t| check_emission(*t).is_err()) {
            let t = texels[i];
            return Err(map_error(format!(
                "texel ({}, {}) is {:?}: texels must be finite and non-negative",
                i % width,
                i / width,
                t.to_array()
            )));
        }
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(map_error(format!("scale {scale} must be finite and non-negative")));
        }
        // Mitsuba's pad_to(2, 3): repeat the last column, then the last row.
        let (w, h) = (width.max(2), height.max(3));
        let mut padded = Vec::with_capacity(w * h);
        for j in 0..h {
            let row = j.min(height - 1) * width;
            padded.extend((0..w).map(|i| texels[row + i.min(width - 1)]));
        }
        let mut map = LatLong {
            width: w,
            height: h,
            texels: padded,
            scale,
            cell_prob: Vec::new(),
            row_cdf: Vec::new(),
            col_cdf: Vec::new(),
            integral: Rgb::ZERO,
            row_cos: Vec::new(),
        };
        // The same expressions as `row_angles` (k·Δθ), so the same bits as its cosines.
        let d = PI64 / (h - 1) as f64;
        map.row_cos = (0..h).map(|k| (k as f64 * d).cos()).collect();
        map.build_distribution();
        Ok(map)
    }

    /// Texel (i, j), before `scale`.
    #[inline]
    fn texel(&self, i: usize, j: usize) -> Rgb {
        self.texels[j * self.width + i]
    }

    /// The size after padding (columns, rows).
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The texels (before `scale`, padded) and the scale, what the light's shape hash covers.
    pub fn texels(&self) -> (&[Rgb], f32) {
        (&self.texels, self.scale)
    }

    /// The polar angles θ_j, θ_{j+1} bounding cell row j.
    #[inline]
    fn row_angles(&self, j: usize) -> (f64, f64) {
        let d = PI64 / (self.height - 1) as f64;
        (j as f64 * d, (j + 1) as f64 * d)
    }

    /// ∫ sin θ (1 − t) dθ and ∫ sin θ t dθ over a row of cells, t = (θ − θ₀)/(θ₁ − θ₀): the
    /// weights of its top and bottom texel rows in the exact integral of the interpolant.
    fn row_weights(&self, j: usize) -> (f64, f64) {
        let (t0, t1) = self.row_angles(j);
        let i1 = -t1.cos() + (t1.sin() - t0.sin()) / (t1 - t0);
        ((t0.cos() - t1.cos()) - i1, i1)
    }

    fn build_distribution(&mut self) {
        let (w, rows) = (self.width, self.height - 1);
        let dphi = 2.0 * PI64 / w as f64;
        let mut weights = Vec::with_capacity(w * rows);
        let mut integral = [0.0f64; 3];
        // A texel row's neighbour means, each computed once: the bottom of a row of cells is the
        // top of the next (half of this loop's work, the same values).
        let means = |j: usize, out: &mut Vec<glam::DVec3>| {
            out.clear();
            out.extend((0..w).map(|i| (self.texel(i, j) + self.texel((i + 1) % w, j)).as_dvec3() * 0.5));
        };
        let (mut top, mut bottom) = (Vec::with_capacity(w), Vec::with_capacity(w));
        means(0, &mut top);
        for j in 0..rows {
            let (a, b) = self.row_weights(j);
            means(j + 1, &mut bottom);
            for (&top, &bottom) in top.iter().zip(&bottom) {
                let cell = (top * a + bottom * b) * dphi;
                for (c, v) in integral.iter_mut().zip(cell.to_array()) {
                    *c += v;
                }
                weights.push(0.212_671 * cell.x + 0.715_160 * cell.y + 0.072_169 * cell.z);
            }
            std::mem::swap(&mut top, &mut bottom);
        }
        let total: f64 = weights.iter().sum();
        if !(total > 0.0) {
            // A black map: sample by solid angle (any density will do, nothing is emitted).
            weights = (0..rows)
                .flat_map(|j| {
                    let (t0, t1) = self.row_angles(j);
                    std::iter::repeat_n(dphi * (t0.cos() - t1.cos()), w)
                })
                .collect();
        }
        let total: f64 = weights.iter().sum();
        self.cell_prob = weights.iter().map(|x| x / total).collect();
        drop(weights); // before the column CDFs, which take as much again
        self.row_cdf.clear();
        self.col_cdf.clear();
        self.col_cdf.reserve_exact(self.cell_prob.len());
        let mut acc = 0.0;
        for row in self.cell_prob.chunks(w) {
            let sum: f64 = row.iter().sum();
            acc += sum;
            self.row_cdf.push(acc);
            let mut c = 0.0;
            for p in row {
                c += p;
                self.col_cdf.push(if sum > 0.0 { c / sum } else { 0.0 });
            }
            if sum > 0.0 {
                *self.col_cdf.last_mut().expect("a row has cells") = 1.0;
            }
        }
        *self.row_cdf.last_mut().expect("a map has a row of cells") = 1.0;
        self.integral = Rgb::new(integral[0] as f32, integral[1] as f32, integral[2] as f32) * self.scale;
    }

    /// ∫ L(ω) dω per channel.
    pub fn integral(&self) -> Rgb {
        self.integral
    }

    /// ∫ L(ω) cos θ dω over the map's upper hemisphere (θ < π/2 from its pole, +y) per channel:
    /// the irradiance of an unobstructed plane facing the pole. Exact for the bilinear
    /// interpolant, as [`LatLong::integral`]: per row of cells, the top and bottom texel rows
    /// weigh ∫ sin θ cos θ (1 − t) dθ and ∫ sin θ cos θ t dθ over the row's part above the
    /// horizon, in closed form.
    pub fn pole_irradiance(&self) -> Rgb {
        let (w, rows) = (self.width, self.height - 1);
        let dphi = 2.0 * PI64 / w as f64;
        let mut sum = glam::DVec3::ZERO;
        for j in 0..rows {
            let (t0, t1) = self.row_angles(j);
            let te = t1.min(0.5 * PI64);
            if te <= t0 {
                break;
            }
            // A = ∫ sin θ cos θ dθ, B = ∫ (θ − θ₀) sin θ cos θ dθ over [θ₀, θₑ].
            let a = ((2.0 * t0).cos() - (2.0 * te).cos()) / 4.0;
            let b = -(te - t0) * (2.0 * te).cos() / 4.0 + ((2.0 * te).sin() - (2.0 * t0).sin()) / 8.0;
            let bottom_w = b / (t1 - t0);
            let top_w = a - bottom_w;
            for i in 0..w {
                let i1 = (i + 1) % w;
                let top = (self.texel(i, j) + self.texel(i1, j)).as_dvec3() * 0.5;
                let bottom = (self.texel(i, j + 1) + self.texel(i1, j + 1)).as_dvec3() * 0.5;
                sum += (top * top_w + bottom * bottom_w) * dphi;
            }
        }
        Rgb::new(sum.x as f32, sum.y as f32, sum.z as f32) * self.scale
    }

    /// L at map coordinates (u, v): Mitsuba's bilinear lookup (module docs), scaled.
    pub fn eval_uv(&self, u: f32, v: f32) -> Rgb {
        let (w, h) = (self.width, self.height);
        let u = u - u.floor();
        let v = v.clamp(0.0, 1.0);
        let fx = u * w as f32 - 0.5;
        let fy = v * (h - 1) as f32;
        let (x0, y0) = (fx.floor(), fy.floor().min((h - 2) as f32));
        let (tx, ty) = (fx - x0, fy - y0);
        let i0 = (x0 as i64).rem_euclid(w as i64) as usize;
        let i1 = (i0 + 1) % w;
        let j0 = y0 as usize;
        let top = self.texel(i0, j0) * (1.0 - tx) + self.texel(i1, j0) * tx;
        let bottom = self.texel(i0, j0 + 1) * (1.0 - tx) + self.texel(i1, j0 + 1) * tx;
        (top * (1.0 - ty) + bottom * ty) * self.scale
    }

    /// The cell (column, row) containing map coordinates (u, v).
    #[inline]
    fn cell_of(&self, u: f32, v: f32) -> (usize, usize) {
        let fx = (u - u.floor()) * self.width as f32 - 0.5;
        let i = (fx.floor() as i64).rem_euclid(self.width as i64) as usize;
        let fy = v.clamp(0.0, 1.0) * (self.height - 1) as f32;
        (i, (fy as usize).min(self.height - 2))
    }

    /// Solid angle of a cell of row j.
    #[inline]
    fn cell_solid_angle(&self, j: usize) -> f64 {
        2.0 * PI64 / self.width as f64 * (self.row_cos[j] - self.row_cos[j + 1])
    }

    /// The solid-angle density of sampling the map-frame unit direction `d`.
    pub fn pdf(&self, d: Vec3) -> f32 {
        let (u, v) = direction_to_uv(d);
        let (i, j) = self.cell_of(u, v);
        (self.cell_prob[j * self.width + i] / self.cell_solid_angle(j)) as f32
    }

    /// A map-frame unit direction drawn from `u` ∈ [0,1)² with [`LatLong::pdf`], and its pdf.
    pub fn sample(&self, u: Vec2) -> (Vec3, f32) {
        let w = self.width;
        let pick = |cdf: &[f64], x: f64| cdf.partition_point(|&c| c <= x).min(cdf.len() - 1);
        let uy = u.y as f64;
        let j = pick(&self.row_cdf, uy);
        let row_lo = if j == 0 { 0.0 } else { self.row_cdf[j - 1] };
        let ry = ((uy - row_lo) / (self.row_cdf[j] - row_lo)).clamp(0.0, 1.0);
        let cols = &self.col_cdf[j * w..(j + 1) * w];
        let ux = u.x as f64;
        let i = pick(cols, ux);
        let col_lo = if i == 0 { 0.0 } else { cols[i - 1] };
        let rx = ((ux - col_lo) / (cols[i] - col_lo)).clamp(0.0, 1.0);
        let rx = if rx.is_finite() { rx } else { 0.5 };
        let ry = if ry.is_finite() { ry } else { 0.5 };
        let (cos0, cos1) = (self.row_cos[j], self.row_cos[j + 1]);
        let cos_theta = cos0 - (cos0 - cos1) * ry;
        let phi = 2.0 * PI64 * ((i as f64 + 0.5 + rx) / w as f64);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let d = Vec3::new((phi.sin() * sin_theta) as f32, cos_theta as f32, (-phi.cos() * sin_theta) as f32);
        // The density of the cell drawn (not re-derived from d, which rounding may move across
        // a cell border).
        (d, (self.cell_prob[j * w + i] / self.cell_solid_angle(j)) as f32)
    }
}

/// Mitsuba's map coordinates of a map-frame unit direction: (atan2(x, −z)/2π, acos(y)/π).
#[inline]
pub fn direction_to_uv(d: Vec3) -> (f32, f32) {
    let u = d.x.atan2(-d.z) * (0.5 / std::f32::consts::PI);
    (u - u.floor(), d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI)
}

/// Light arriving from every direction at infinity, covering the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentLight {
    /// Name from the scene.
    pub name: String,
    /// What it emits.
    pub radiance: EnvRadiance,
    /// The map's frame in the world (a rotation, possibly mirrored; world = R·map).
    pub to_world: Mat3,
    /// Centre of the scene's bounding sphere.
    pub centre: Vec3,
    /// The scene's bounding radius (the emission disk's radius).
    pub radius: f32,
}

impl EnvironmentLight {
    /// The environment `radiance` in the frame `to_world` (a rotation) around a scene whose
    /// bounding sphere has centre `centre` and radius `radius`.
    pub fn new(
        name: String,
        radiance: EnvRadiance,
        to_world: Mat3,
        (centre, radius): (Vec3, f32),
    ) -> Result<Self, LightError> {
        if let EnvRadiance::Constant(c) = radiance {
            check_emission(c)?;
        }
        check_rotation(to_world)?;
        Ok(EnvironmentLight { name, radiance, to_world, centre, radius })
    }

    /// ∫ L(ω) dω per channel.
    #[inline]
    pub fn integral(&self) -> Rgb {
        match &self.radiance {
            EnvRadiance::Constant(c) => *c * (4.0 * std::f32::consts::PI),
            EnvRadiance::Map(m) => m.integral(),
        }
    }

    /// The world direction of the map's pole, to_world·ŷ (a Radiance sky's zenith).
    #[inline]
    pub fn pole(&self) -> Vec3 {
        self.to_world * Vec3::Y
    }

    /// ∫ L(ω) (ω·z) dω over the hemisphere around the pole z = [`EnvironmentLight::pole`], per
    /// channel: the irradiance this environment alone gives an unobstructed plane facing its
    /// pole (for a sky, the horizontal irradiance in the open, no ground). Exact: π·L for a
    /// constant, [`LatLong::pole_irradiance`] for a map.
    pub fn pole_irradiance(&self) -> Rgb {
        match &self.radiance {
            EnvRadiance::Constant(c) => *c * std::f32::consts::PI,
            EnvRadiance::Map(m) => m.pole_irradiance(),
        }
    }

    /// Power Φ = π·r²·∫L dω per channel.
    #[inline]
    pub fn power(&self) -> Rgb {
        self.integral() * (std::f32::consts::PI * self.radius * self.radius)
    }

    /// L(ω) for the unit world direction `omega` toward the environment.
    #[inline]
    pub fn radiance(&self, omega: Vec3) -> Rgb {
        match &self.radiance {
            EnvRadiance::Constant(c) => *c,
            EnvRadiance::Map(m) => {
                let (u, v) = direction_to_uv(self.to_world.transpose() * omega);
                m.eval_uv(u, v)
            }
        }
    }

    /// The solid-angle density with which [`EnvironmentLight::sample_direction`] draws `omega`.
    #[inline]
    pub fn direction_pdf(&self, omega: Vec3) -> f32 {
        match &self.radiance {
            EnvRadiance::Constant(_) => 1.0 / (4.0 * std::f32::consts::PI),
            EnvRadiance::Map(m) => m.pdf(self.to_world.transpose() * omega),
        }
    }

    /// A unit world direction toward the environment, drawn from `u`, and its solid-angle pdf.
    #[inline]
    pub fn sample_direction(&self, u: Vec2) -> (Vec3, f32) {
        match &self.radiance {
            EnvRadiance::Constant(_) => {
                (warp::square_to_uniform_sphere(u), 1.0 / (4.0 * std::f32::consts::PI))
            }
            EnvRadiance::Map(m) => {
                let (d, pdf) = m.sample(u);
                ((self.to_world * d).normalize(), pdf)
            }
        }
    }

    /// The area density of a path's start point on the disk: 1/(π r²).
    #[inline]
    pub fn disk_pdf(&self) -> f32 {
        1.0 / (std::f32::consts::PI * self.radius * self.radius)
    }

    /// A path start: `u_dir` draws ω, the path travels along −ω from a point drawn by `u_pos`
    /// uniformly on the disk perpendicular to ω outside the bounding sphere. Weight
    /// L(ω)/(p(ω)·∫L dω) per channel (0 in a channel that emits nothing).
    #[inline]
    pub fn sample_emission(&self, u_pos: Vec2, u_dir: Vec2) -> Emission {
        let (omega, pdf) = self.sample_direction(u_dir);
        let frame = Frame::from_normal(omega);
        let d = self.radius * warp::square_to_concentric_disk(u_pos);
        let origin = self.centre + omega * (self.radius * 1.001 + 1e-4) + d.x * frame.s + d.y * frame.t;
        let integral = self.integral();
        let l = self.radiance(omega);
        let per = |l: f32, i: f32| if i > 0.0 && pdf > 0.0 { l / (pdf * i) } else { 0.0 };
        let weight = Rgb::new(per(l.x, integral.x), per(l.y, integral.y), per(l.z, integral.z));
        Emission { origin, surface: None, dir: -omega, weight, emitted: Rgb::ONE }
    }
}

/// A frame matrix that is a rotation, possibly mirrored (orthonormal columns within 10⁻⁴).
fn check_rotation(m: Mat3) -> Result<(), LightError> {
    let ok =
        m.is_finite() && (m.transpose() * m - Mat3::IDENTITY).to_cols_array().iter().all(|x| x.abs() < 1e-4);
    if ok { Ok(()) } else { Err(LightError::EnvironmentFrame(m.to_cols_array())) }
}

#[cfg(test)]
mod tests;
