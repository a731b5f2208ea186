//! Warps from the unit square [0,1)² to directions and points, each with its density.
//! Directions are in a local frame whose z axis is the surface normal (or, for the Phong lobe,
//! the lobe axis).
//!
//! The Phong-lobe functions ([`square_to_phong_lobe`], [`phong_lobe_pdf`],
//! [`phong_lobe_pdf_from_versine`], [`pow_cos_from_versine`]) are written for exponents from 0 to
//! 10⁶: they work with the versine 1 − cos α and `ln_1p`/`exp_m1` rather than `powf(cos α, n)`,
//! because near the axis of a narrow lobe cos α rounds to 1 in f32 and `powf` would lose all
//! precision (for n = 10⁵ one ulp of cos α changes cosⁿα by ~1 %).
//!
//! Microfacet normal distributions (GGX, Beckmann) live in [`super::microfacet`].

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI, TAU};

/// Cosine-weighted direction on the upper hemisphere (Malley's method on a concentric disk).
#[inline]
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = square_to_concentric_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Density of [`square_to_cosine_hemisphere`] w.r.t. solid angle.
#[inline]
pub fn cosine_hemisphere_pdf(v: Vec3) -> f32 {
    if v.z > 0.0 { v.z * FRAC_1_PI } else { 0.0 }
}

/// Shirley–Chiu concentric map of the square onto the unit disk.
#[inline]
pub fn square_to_concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, (PI / 4.0) * (o.y / o.x))
    } else {
        (o.y, PI / 2.0 - (PI / 4.0) * (o.x / o.y))
    };
    Vec2::new(r * theta.cos(), r * theta.sin())
}

/// Uniform direction on the upper hemisphere (z ≥ 0).
#[inline]
pub fn square_to_uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`square_to_uniform_hemisphere`] w.r.t. solid angle.
pub const UNIFORM_HEMISPHERE_PDF: f32 = 1.0 / (2.0 * PI);

/// Uniform direction on the unit sphere.
#[inline]
pub fn square_to_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`square_to_uniform_sphere`] w.r.t. solid angle.
pub const UNIFORM_SPHERE_PDF: f32 = 1.0 / (4.0 * PI);

/// Uniform barycentric coordinates (b1, b2) on a triangle; the point is
/// `(1 - b1 - b2)·v0 + b1·v1 + b2·v2`.
#[inline]
pub fn square_to_uniform_triangle(u: Vec2) -> Vec2 {
    let su = u.x.sqrt();
    Vec2::new(1.0 - su, u.y * su)
}

/// Direction in the Phong lobe of exponent `n` around the local z axis: density
/// `(n+1)/(2π)·cosⁿα` (α = angle to z) on the hemisphere z > 0, by inversion:
/// cos α = `u.x`^(1/(n+1)), φ = 2π·`u.y`. Accurate for `n` in [0, 10⁶]; `u.x = 0` gives α = 90°.
#[inline]
pub fn square_to_phong_lobe(u: Vec2, n: f32) -> Vec3 {
    // ln cos α = ln(u)/(n+1); sin²α = 1 − cos²α = −expm1(2 ln cos α), exact even for tiny α.
    let ln_cos = u.x.ln() / (n + 1.0);
    let cos_a = ln_cos.exp();
    let sin_a = (-(2.0 * ln_cos).exp_m1()).clamp(0.0, 1.0).sqrt();
    let phi = TAU * u.y;
    Vec3::new(sin_a * phi.cos(), sin_a * phi.sin(), cos_a)
}

/// cosⁿα computed from the versine `v` = 1 − cos α as exp(n·ln(1 − v)): keeps full relative
/// precision near the axis (where cos α would round to 1). Zero when cos α ≤ 0 or `v` is NaN;
/// 1 on the axis (also for n = 0).
#[inline]
pub fn pow_cos_from_versine(versine: f32, n: f32) -> f32 {
    if versine.is_nan() || versine >= 1.0 {
        0.0
    } else if versine <= 0.0 {
        1.0
    } else {
        (n * (-versine).ln_1p()).exp()
    }
}

/// Density of [`square_to_phong_lobe`] w.r.t. solid angle, from the versine 1 − cos α of the
/// direction's angle to the lobe axis (for unit vectors, `|v − axis|²/2`, the accurate form).
#[inline]
pub fn phong_lobe_pdf_from_versine(versine: f32, n: f32) -> f32 {
    (n + 1.0) * (0.5 * FRAC_1_PI) * pow_cos_from_versine(versine, n)
}

/// Density of [`square_to_phong_lobe`] w.r.t. solid angle: `(n+1)/(2π)·cosⁿα` for cos α > 0,
/// else 0.
#[inline]
pub fn phong_lobe_pdf(cos_alpha: f32, n: f32) -> f32 {
    // 1 − cos α is exact in f32 for cos α ∈ [0.5, 1] (Sterbenz).
    phong_lobe_pdf_from_versine(1.0 - cos_alpha, n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::RandomStream;

    #[test]
    fn cosine_hemisphere_moments() {
        // E[z] = 2/3 and E[z²] = 1/2 for a cosine-weighted hemisphere.
        let mut s = RandomStream::new(3, &[]);
        let n = 400_000;
        let (mut m1, mut m2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let v = square_to_cosine_hemisphere(s.next_2d());
            assert!(v.z >= 0.0 && (v.length() - 1.0).abs() < 1e-4);
            m1 += v.z as f64;
            m2 += (v.z * v.z) as f64;
        }
        assert!((m1 / n as f64 - 2.0 / 3.0).abs() < 2e-3);
        assert!((m2 / n as f64 - 0.5).abs() < 2e-3);
    }

    #[test]
    fn uniform_sphere_is_centred() {
        let mut s = RandomStream::new(4, &[]);
        let n = 400_000;
        let mut m = glam::DVec3::ZERO;
        for _ in 0..n {
            m += square_to_uniform_sphere(s.next_2d()).as_dvec3();
        }
        assert!((m / n as f64).length() < 5e-3);
    }

    #[test]
    fn triangle_barycentrics_are_uniform() {
        // Mean barycentric of a uniform triangle sample is (1/3, 1/3).
        let mut s = RandomStream::new(5, &[]);
        let n = 400_000;
        let mut m = glam::DVec2::ZERO;
        for _ in 0..n {
            let b = square_to_uniform_triangle(s.next_2d());
            assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
            m += b.as_dvec2();
        }
        let m = m / n as f64;
        assert!((m.x - 1.0 / 3.0).abs() < 2e-3 && (m.y - 1.0 / 3.0).abs() < 2e-3);
    }

    #[test]
    fn phong_lobe_moments_and_robustness() {
        // E[cos α] = (n+1)/(n+2) for the density (n+1)/(2π)·cosⁿα.
        for n in [0.0f32, 1.0, 10.0, 1e3, 1e5] {
            let mut s = RandomStream::new(6, &[n as u64]);
            let m = 200_000;
            let mut mean = 0.0f64;
            for _ in 0..m {
                let v = square_to_phong_lobe(s.next_2d(), n);
                assert!(v.is_finite() && v.z >= 0.0 && (v.length() - 1.0).abs() < 1e-5, "{v}");
                mean += v.z as f64;
            }
            let want = (n as f64 + 1.0) / (n as f64 + 2.0);
            // σ(cos α) ≤ 1 − E[cos α]; 5σ bound on the mean.
            let tol = 5.0 * (1.0 - want) / (m as f64).sqrt();
            assert!((mean / m as f64 - want).abs() < tol, "n={n}: {} vs {want}", mean / m as f64);
        }
        for n in [0.0f32, 1e6] {
            for u in [Vec2::ZERO, Vec2::new(1.0, 1.0), Vec2::new(f32::MIN_POSITIVE, 0.5)] {
                assert!(square_to_phong_lobe(u, n).is_finite());
            }
            for c in [-1.0f32, 0.0, 1e-30, 0.5, 1.0 - 1e-7, 1.0] {
                let p = phong_lobe_pdf(c, n);
                assert!(p.is_finite() && p >= 0.0, "pdf({c}, {n}) = {p}");
            }
        }
        assert_eq!(pow_cos_from_versine(f32::NAN, 3.0), 0.0);
        assert_eq!(pow_cos_from_versine(0.0, 0.0), 1.0);
        // Versine form agrees with powf where powf is accurate.
        assert!((pow_cos_from_versine(0.5, 3.0) - 0.125).abs() < 1e-6);
    }
}
