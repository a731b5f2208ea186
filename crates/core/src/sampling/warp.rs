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
//! The GGX functions ([`ggx_d`], [`ggx_lambda`], [`square_to_ggx_visible_normal`],
//! [`ggx_visible_normal_pdf`]) serve the microfacet BSDFs: the isotropic Trowbridge–Reitz (GGX)
//! normal distribution of roughness α and Heitz 2018's exact sampling of the normals *visible*
//! from a direction ("Sampling the GGX Distribution of Visible Normals", JCGT 7(4)).

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

/// Isotropic GGX normal distribution D(m) = α² / (π·((α² − 1)·cos²θ_m + 1)²) for `m.z > 0`
/// (unit `m`), 0 below. ∫ D(m)·cos θ_m dω_m = 1.
#[inline]
pub fn ggx_d(m: Vec3, alpha: f32) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    // (m.x² + m.y²)/α² + m.z², scaled by α²: exact for unit m, no cancellation.
    let t = m.x * m.x + m.y * m.y + a2 * m.z * m.z;
    a2 / (PI * t * t)
}

/// Smith's Λ for GGX: (−1 + √(1 + α²·tan²θ))/2 for the direction `w` (any hemisphere: |cos θ|
/// is used). G₁(w) = 1/(1 + Λ(w)); the height-correlated G₂(wi, wo) = 1/(1 + Λ(wi) + Λ(wo)).
#[inline]
pub fn ggx_lambda(w: Vec3, alpha: f32) -> f32 {
    let z2 = w.z * w.z;
    if z2 <= 0.0 {
        return f32::INFINITY;
    }
    let a2tan2 = alpha * alpha * (w.x * w.x + w.y * w.y) / z2;
    // (√(1 + x) − 1)/2 = x / (2(√(1 + x) + 1)): no cancellation for small x.
    a2tan2 / (2.0 * ((1.0 + a2tan2).sqrt() + 1.0))
}

/// A microfacet normal m distributed by the GGX distribution of normals visible from `wi`
/// (which must have `wi.z > 0`): density D_wi(m) = G₁(wi)·max(0, wi·m)·D(m)/cos θ_i
/// ([`ggx_visible_normal_pdf`]). Heitz 2018, listing 1: stretch `wi` to the α = 1 configuration,
/// sample the projected hemisphere, unstretch.
#[inline]
pub fn square_to_ggx_visible_normal(wi: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    let vh = Vec3::new(alpha * wi.x, alpha * wi.y, wi.z).normalize();
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = if lensq > 0.0 { Vec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt() } else { Vec3::X };
    let t2 = vh.cross(t1);
    let r = u.x.sqrt();
    let phi = TAU * u.y;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
    let nh = t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    Vec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(1e-7)).normalize()
}

/// Density of [`square_to_ggx_visible_normal`] w.r.t. solid angle of m: G₁(wi)·max(0, wi·m)·
/// D(m)/cos θ_i, for `wi.z > 0`.
#[inline]
pub fn ggx_visible_normal_pdf(wi: Vec3, m: Vec3, alpha: f32) -> f32 {
    let wm = wi.dot(m);
    if wi.z <= 0.0 || wm <= 0.0 {
        return 0.0;
    }
    ggx_d(m, alpha) * wm / (wi.z * (1.0 + ggx_lambda(wi, alpha)))
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

    #[test]
    fn ggx_is_normalised_and_visible_normals_integrate_to_one() {
        // ∫ D(m) cos θ_m dω = 1 and ∫ D_wi(m) dω = 1, by the midpoint rule in (cos θ, φ).
        for alpha in [0.05f32, 0.3, 1.0] {
            for wi in [Vec3::Z, Vec3::new(0.6, 0.2, 0.5).normalize(), Vec3::new(0.99, 0.0, 0.05).normalize()]
            {
                let (nt, np) = (4000, 64);
                let (mut d, mut v) = (0.0f64, 0.0f64);
                for i in 0..nt {
                    // cos θ = 1 − x², x uniform: dense near the pole where narrow lobes live.
                    let x = (i as f64 + 0.5) / nt as f64;
                    let ct = 1.0 - x * x;
                    let st = (1.0 - ct * ct).max(0.0).sqrt();
                    for j in 0..np {
                        let phi = std::f64::consts::TAU * (j as f64 + 0.5) / np as f64;
                        let m = Vec3::new((st * phi.cos()) as f32, (st * phi.sin()) as f32, ct as f32);
                        let dw = 2.0 * x / nt as f64 * std::f64::consts::TAU / np as f64;
                        d += ggx_d(m, alpha) as f64 * ct * dw;
                        v += ggx_visible_normal_pdf(wi, m, alpha) as f64 * dw;
                    }
                }
                assert!((d - 1.0).abs() < 2e-3, "α={alpha}: ∫D cos = {d}");
                assert!((v - 1.0).abs() < 2e-3, "α={alpha} wi={wi}: ∫D_wi = {v}");
            }
        }
    }

    #[test]
    fn ggx_visible_normals_face_the_viewer() {
        let mut s = RandomStream::new(7, &[]);
        for alpha in [1e-3f32, 0.2, 1.0] {
            for wi in [Vec3::Z, Vec3::new(1.0, 0.0, 1e-4).normalize(), Vec3::new(0.3, -0.4, 0.8).normalize()]
            {
                for _ in 0..10_000 {
                    let m = square_to_ggx_visible_normal(wi, alpha, s.next_2d());
                    assert!(m.is_finite() && m.z > 0.0 && (m.length() - 1.0).abs() < 1e-5, "{m}");
                    assert!(wi.dot(m) > -1e-5, "α={alpha} wi={wi} m={m}");
                }
            }
        }
    }
}
