//! Warps from the unit square [0,1)² to directions and points, each with its density.
//! Directions are in a local frame whose z axis is the surface normal.

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
}
