//! Shading normals and the adjoint BSDF they require (Veach's thesis §5.3, pbrt-v4's
//! `TransportMode::Importance`).
//!
//! A mesh with vertex normals has two normals at each point: the geometric n_g of the triangle
//! and the interpolated shading normal n_s. The BSDF f_s is evaluated in the frame of n_s, and a
//! **camera** path tracer computes, at a point seen along ω_c,
//!
//! ```text
//! L(x, ω_c) = ∫ f_s(ω_l → ω_c) · L_i(x, ω_l) · |ω_l·n_s| dω_l        (the definition of shading normals)
//!           = ∫ f_eff(ω_l → ω_c) · L_i(x, ω_l) · |ω_l·n_g| dω_l
//! with  f_eff(ω_in → ω_out) = f_s(ω_in → ω_out) · |ω_in·n_s| / |ω_in·n_g|.
//! ```
//!
//! The second line is an ordinary rendering equation with the geometric cosine, so the light
//! tracer — whose measure is area and whose geometry terms carry the *geometric* cosines — solves
//! the same equation if it uses f_eff in light-flow order at every vertex. f_eff is not
//! symmetric (that is the "non-symmetric BSDF" of Veach §5.3), which is why the correction
//! falls on the incident side ω_in, the direction light came from:
//!
//! * **trace** (β update at a vertex, ω_in = where the light came from, ω_out sampled from f_s
//!   in the shading frame with pdf p): β ← β · f_eff(ω_in→ω_out)·|ω_out·n_g|/p
//!   = β · [f_s·|ω_out·n_s|/p] · |ω_in·n_s|·|ω_out·n_g| / (|ω_in·n_g|·|ω_out·n_s|),
//!   pbrt's `CorrectShadingNormal` in importance mode.
//! * **sensor** (docs/estimator.md §5, Δ ∝ f_r(ω_in → ω_c)·|cos θ_x|): f_r is f_eff(ω_in → ω_c) and
//!   θ_x stays the **geometric** angle between ω_c and n_g — it is the cosine of the connection's
//!   geometry term, not of the BSDF. This is pbrt-v3's BDPT t = 1 connection:
//!   f_s·|ω_in·n_s|·|ω_c·n_g|/|ω_in·n_g|.
//! * camera paths ([`TransportMode::Radiance`], ω given = toward the camera, ω sampled = toward
//!   the light) need no correction: their weight f_s(sampled→given)·|sampled·n_s|/p is already
//!   what the first line integrates.
//!
//! **Light leaks.** A direction can be above the shading hemisphere and below the geometric
//! one (or the reverse). As pbrt decides reflection versus transmission with the geometric
//! normal, a pair (ω_in, ω_out) contributes only if n_s and n_g agree on whether it is a
//! reflection (both on one side) or a transmission; otherwise f_eff = 0, and a sampled direction
//! that fails the test is discarded (its weight is 0). Evaluation and sampling apply the same
//! rule, so the estimator stays consistent. For reflecting BSDFs light arriving below the
//! shading hemisphere (ω_in·n_s ≤ 0 on the lit side) is absorbed.
//!
//! Where the shading normal equals the geometric one ([`SurfaceNormals::is_flat`]) none of this
//! runs: results are bit-identical to a mesh without normals.

use super::{BsdfSample, TransportMode};
use crate::geometry::SurfaceNormals;
use crate::math::{Frame, Vec3};

/// The frame a BSDF is evaluated in at a surface point, oriented to the side light arrives on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalFrame {
    /// The shading frame (z = the shading normal, flipped with the geometric one for the back of
    /// two-sided surfaces).
    pub frame: Frame,
    /// The geometric normal, flipped like `frame`.
    pub geometric: Vec3,
    /// Whether the shading normal is the geometric one.
    pub flat: bool,
}

impl LocalFrame {
    /// The frame of `n`, turned over if `flip`.
    #[inline]
    pub fn new(n: SurfaceNormals, flip: bool) -> Self {
        let flat = n.is_flat();
        let (ns, ng) = if flip { (-n.shading, -n.geometric) } else { (n.shading, n.geometric) };
        LocalFrame { frame: Frame::from_normal(ns), geometric: ng, flat }
    }

    /// The light-leak guard: whether the shading frame and the geometric surface agree that the
    /// pair of world directions `wi`, `wo` (local `a`, `b`) is a reflection, or agree that it is
    /// a transmission. Directions in either tangent plane never count.
    #[inline]
    pub fn agrees(&self, wi: Vec3, wo: Vec3, a: Vec3, b: Vec3) -> bool {
        let (gi, go) = (wi.dot(self.geometric), wo.dot(self.geometric));
        let shading = a.z * b.z;
        let geometric = gi * go;
        shading != 0.0 && geometric != 0.0 && (shading > 0.0) == (geometric > 0.0)
    }

    /// f_eff / f_s = |ω_in·n_s| / |ω_in·n_g| for light arriving from world `wi` (local `a`).
    #[inline]
    pub fn incident_factor(&self, wi: Vec3, a: Vec3) -> f32 {
        a.z.abs() / wi.dot(self.geometric).abs()
    }

    /// A sample `s` drawn in the local frame (from world `wi`, local `a`) turned into world
    /// space, with the importance-mode correction and the leak guard (`None`: weight 0).
    #[inline]
    pub fn finish(&self, wi: Vec3, a: Vec3, s: BsdfSample, mode: TransportMode) -> Option<BsdfSample> {
        let wo = self.frame.to_world(s.wo);
        if self.flat {
            return Some(BsdfSample { wo, ..s });
        }
        if !self.agrees(wi, wo, a, s.wo) {
            return None;
        }
        let weight = match mode {
            TransportMode::Importance => {
                s.weight * (self.incident_factor(wi, a) * wo.dot(self.geometric).abs() / s.wo.z.abs())
            }
            TransportMode::Radiance => s.weight,
        };
        Some(BsdfSample { wo, weight, ..s })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::{Bsdf, Lambert, Material, ModifiedPhong};
    use crate::math::Rgb;
    use crate::sampling::{RandomStream, warp};

    /// Mean and standard error of `n` draws of `f`.
    fn estimate(n: usize, mut f: impl FnMut() -> f64) -> (f64, f64) {
        let (mut s, mut s2) = (0.0, 0.0);
        for _ in 0..n {
            let x = f();
            s += x;
            s2 += x * x;
        }
        let m = s / n as f64;
        (m, ((s2 / n as f64 - m * m) / n as f64).sqrt())
    }

    /// The trace's β update must be f_eff·|ω_o·n_g|/p: importance-mode sampling averages
    /// ∫ f_eff(ω_i→ω)·g(ω)·|ω·n_g| dω, as integrated by uniform sphere sampling of `eval_world`
    /// (the sensor's f_r). Radiance-mode weights, which lack the correction, must not.
    #[test]
    fn importance_sampling_agrees_with_eval_and_differs_from_radiance_mode() {
        let normals = SurfaceNormals { geometric: Vec3::Y, shading: Vec3::new(0.35, 1.0, -0.1).normalize() };
        let wi = Vec3::new(-0.5, 0.6, 0.2).normalize();
        let g = |w: Vec3| 1.0 + 0.8 * w.x as f64 + 0.3 * w.z as f64;
        let phong = ModifiedPhong::new(Rgb::splat(0.4), Rgb::splat(0.3), 12.0).unwrap();
        for bsdf in [Bsdf::Lambert(Lambert::new(Rgb::splat(0.7)).unwrap()), Bsdf::ModifiedPhong(phong)] {
            let m = Material { name: "m".into(), bsdf, two_sided: true };
            let n = 400_000;
            let mut rng = RandomStream::new(7, &[1]);
            let mut sampled = |mode| {
                estimate(n, || {
                    let (ul, u) = (rng.next_f32(), rng.next_2d());
                    m.sample_world(normals, wi, ul, u, mode).map_or(0.0, |s| s.weight.x as f64 * g(s.wo))
                })
            };
            let (imp, imp_e) = sampled(TransportMode::Importance);
            let (rad, rad_e) = sampled(TransportMode::Radiance);
            let (ev, ev_e) = estimate(n, || {
                let w = warp::square_to_uniform_sphere(rng.next_2d());
                m.eval_world(normals, wi, w).x as f64 * w.y.abs() as f64 * g(w) * 4.0 * std::f64::consts::PI
            });
            let sigma = (imp_e * imp_e + ev_e * ev_e).sqrt();
            eprintln!(
                "{:?}: importance {imp:.4}±{imp_e:.4}, eval {ev:.4}±{ev_e:.4}, radiance {rad:.4}±{rad_e:.4}",
                m.bsdf
            );
            assert!((imp - ev).abs() < 4.0 * sigma, "importance {imp} vs eval {ev} (σ {sigma})");
            assert!(
                (rad - ev).abs() > 10.0 * (rad_e * rad_e + ev_e * ev_e).sqrt(),
                "radiance mode {rad} vs {ev}"
            );
        }
    }

    /// A direction above the shading hemisphere but below the geometric surface is discarded
    /// by sampling and evaluates to zero (the light-leak guard).
    #[test]
    fn leaking_directions_are_zero_both_ways() {
        let m = Material {
            name: "m".into(),
            bsdf: Bsdf::Lambert(Lambert::new(Rgb::ONE).unwrap()),
            two_sided: false,
        };
        let normals = SurfaceNormals { geometric: Vec3::Y, shading: Vec3::new(0.8, 0.6, 0.0) };
        let wi = Vec3::new(0.6, 0.8, 0.0);
        let below = Vec3::new(0.9, -0.1, 0.0).normalize(); // above n_s, below n_g
        assert!(below.dot(normals.shading) > 0.0);
        assert_eq!(m.eval_world(normals, wi, below), Rgb::ZERO);
        let mut rng = RandomStream::new(1, &[2]);
        let mut discarded = 0;
        for _ in 0..10_000 {
            match m.sample_world(normals, wi, rng.next_f32(), rng.next_2d(), TransportMode::Importance) {
                Some(s) => assert!(s.wo.y > 0.0 && m.eval_world(normals, wi, s.wo).x > 0.0),
                None => discarded += 1,
            }
        }
        assert!(discarded > 0, "some cosine samples fall below the geometric surface");
    }
}
