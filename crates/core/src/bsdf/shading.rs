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

use super::{Bsdf, BsdfSample, Material, TransportMode};
use crate::geometry::SurfaceNormals;
use crate::math::{Frame, Rgb, Vec2, Vec3};

/// The frame a BSDF is evaluated in at a surface point, oriented to the side light arrives on
/// ([`Material::frame_for`]).
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
        LocalFrame { frame: n.frame_of(ns), geometric: ng, flat }
    }
}

/// A surface point as every BSDF query there sees it: the material, its normals and the one
/// shading frame all queries share, built once ([`ShadingPoint::new`]) however many directions
/// are evaluated, sampled or weighed at the point (a camera vertex asks ~10 times: NEE, each
/// connection, their MIS densities, the next bounce). The `Material` methods (`eval_world`,
/// `pdf_world`, `sample_world`, …) are this type for a single query.
///
/// Directions are prepared once per point ([`ShadingPoint::direction`]: their coordinates in
/// the frame of the unflipped shading normal and their geometric cosine) and the side each
/// query is seen from is applied to them: the back of a two-sided surface is the frame of −n,
/// which [`Frame::from_normal`] builds as (s, −t, −n) *exactly* (every rounding of its
/// construction is odd in n; so does [`Frame::with_tangent`], the frame of an anisotropic
/// BSDF, [`SurfaceNormals::tangent`]), so a flipped direction is (x, −y, −z) and every result equals
/// that of a frame built for the query alone — bit for bit, but for the sign of an exactly zero
/// coordinate (+0 where the flipped frame gave −0: equal as numbers, and no BSDF here reads the
/// sign of a zero).
#[derive(Clone, Copy, Debug)]
pub struct ShadingPoint<'m> {
    /// How the surface scatters.
    pub material: &'m Material,
    /// Its normals at the point.
    pub normals: SurfaceNormals,
    /// The frame of the unflipped shading normal.
    frame: Frame,
    /// Whether the shading normal is the geometric one.
    flat: bool,
}

/// A unit world direction at a [`ShadingPoint`], prepared for its queries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Direction {
    /// The world direction.
    pub world: Vec3,
    /// Its coordinates in the point's unflipped shading frame.
    local: Vec3,
    /// n_g · world (signed; the unflipped geometric normal).
    cos_g: f32,
}

impl Direction {
    /// The local coordinates seen from the side `flip` says (the flipped frame is (s, −t, −n)).
    #[inline]
    fn oriented(&self, flip: bool) -> Vec3 {
        let l = self.local;
        if flip { Vec3::new(l.x, -l.y, -l.z) } else { l }
    }

    /// |n_g · world|: the geometric |cos θ| of the direction.
    #[inline]
    pub fn abs_cos(&self) -> f32 {
        self.cos_g.abs()
    }
}

impl<'m> ShadingPoint<'m> {
    /// The point of `material` with normals `n` (its shading frame built here, once).
    #[inline]
    pub fn new(material: &'m Material, n: SurfaceNormals) -> Self {
        ShadingPoint { material, normals: n, frame: n.frame(), flat: n.is_flat() }
    }

    /// The unit world direction `w`, prepared for this point's queries.
    #[inline]
    pub fn direction(&self, w: Vec3) -> Direction {
        Direction { world: w, local: self.frame.to_local(w), cos_g: self.normals.geometric.dot(w) }
    }

    /// The side light arriving from `wi` is scattered on: `Some(flip)` (the frame turned over
    /// for the back of a two-sided surface), `None` if that side does not scatter. The side is
    /// decided by the geometric normal; dielectrics always get the unflipped frame (their
    /// inside is behind it). A reflecting surface whose shading normal faces away from `wi`
    /// does not scatter either (the module docs).
    #[inline]
    pub fn side(&self, wi: &Direction) -> Option<bool> {
        let c = wi.cos_g;
        let transmits = self.material.bsdf.transmits();
        let flip = if transmits {
            if c == 0.0 {
                return None;
            }
            false
        } else if c > 0.0 {
            false
        } else if c < 0.0 && self.material.two_sided {
            true
        } else {
            return None;
        };
        if !self.flat && !transmits && !(wi.oriented(flip).z > 0.0) {
            return None;
        }
        Some(flip)
    }

    /// Whether light arriving from `wi` is scattered at all ([`ShadingPoint::side`]).
    #[inline]
    pub fn scatters_from(&self, wi: &Direction) -> bool {
        self.side(wi).is_some()
    }

    /// The light-leak guard: whether the shading frame and the geometric surface agree that the
    /// pair `wi`, `wo` (shading-frame cosines `a_z`, `b_z` on either side: the product does not
    /// depend on it) is a reflection, or agree that it is a transmission. Directions in either
    /// tangent plane never count.
    #[inline]
    fn agrees(gi: f32, go: f32, a_z: f32, b_z: f32) -> bool {
        let shading = a_z * b_z;
        let geometric = gi * go;
        shading != 0.0 && geometric != 0.0 && (shading > 0.0) == (geometric > 0.0)
    }

    /// f_eff / f_s = |ω_in·n_s| / |ω_in·n_g| for light arriving from `wi` (local `a`).
    #[inline]
    fn incident_factor(wi: &Direction, a: Vec3) -> f32 {
        a.z.abs() / wi.cos_g.abs()
    }

    /// f_r in light-flow order from `wi` to `wo`: the physical BSDF, or with shading normals
    /// the adjoint-consistent f_eff of the module docs ([`Material::eval_world`]).
    #[inline]
    pub fn eval(&self, wi: &Direction, wo: &Direction) -> Rgb {
        let Some(flip) = self.side(wi) else { return Rgb::ZERO };
        let (a, b) = (wi.oriented(flip), wo.oriented(flip));
        if self.flat {
            return self.material.bsdf.eval(a, b);
        }
        if !Self::agrees(wi.cos_g, wo.cos_g, a.z, b.z) {
            return Rgb::ZERO;
        }
        self.material.bsdf.eval(a, b) * Self::incident_factor(wi, a)
    }

    /// The density of sampling `wo` given `wi` for one kind of event ([`Material::pdf_world_of`]):
    /// with `delta` the probability of the delta lobe leading to `wo`, else the density of the
    /// other lobes; 0 where sampling never returns `wo`.
    #[inline]
    pub fn pdf_of(&self, wi: &Direction, wo: &Direction, delta: bool) -> f32 {
        let Some(flip) = self.side(wi) else { return 0.0 };
        let (a, b) = (wi.oriented(flip), wo.oriented(flip));
        if !self.flat && !Self::agrees(wi.cos_g, wo.cos_g, a.z, b.z) {
            return 0.0;
        }
        match &self.material.bsdf {
            // The most common surface answered here, inline: the dispatch of `Bsdf::pdf` is
            // too large to inline into the tracer's and the sensors' vertex loops.
            Bsdf::Lambert(l) if !delta => l.pdf(a, b),
            bsdf if delta => bsdf.lobe_probability(a, b),
            bsdf => bsdf.pdf(a, b),
        }
    }

    /// [`ShadingPoint::pdf_of`] for the material's own kind of event ([`Material::pdf_world`]).
    #[inline]
    pub fn pdf(&self, wi: &Direction, wo: &Direction) -> f32 {
        self.pdf_of(wi, wo, self.material.bsdf.is_delta())
    }

    /// The density of [`ShadingPoint::sample_uniform`] given `wi` returning `wo`
    /// ([`Material::pdf_uniform_world`]).
    #[inline]
    pub fn pdf_uniform(&self, wi: &Direction, wo: &Direction) -> f32 {
        let Some(flip) = self.side(wi) else { return 0.0 };
        let (a, b) = (wi.oriented(flip), wo.oriented(flip));
        if !(b.z > 0.0) || (!self.flat && !Self::agrees(wi.cos_g, wo.cos_g, a.z, b.z)) {
            return 0.0;
        }
        crate::sampling::warp::UNIFORM_HEMISPHERE_PDF
    }

    /// The weight of the straight-through delta lobe (ω_o = −ω_i) for light arriving from
    /// `wi`: [`super::Bsdf::straight_through`] at the shading-frame cosine, `None` for a material
    /// without that lobe. [`ShadingPoint::sample`] gives the lobe this weight times its
    /// probability in both modes: the pair (ω_i, −ω_i) is a transmission for both normals
    /// (the leak guard passes unless a cosine is 0) and the importance factor
    /// |ω_i·n_s|·|ω_o·n_g| / (|ω_i·n_g|·|ω_o·n_s|) is 1.
    #[inline]
    pub fn straight_through(&self, wi: &Direction) -> Option<Rgb> {
        let t = self.material.bsdf.straight_through(wi.local)?;
        Some(if wi.cos_g == 0.0 { Rgb::ZERO } else { t })
    }

    /// Samples a world direction given `wi` ([`Material::sample_world`]).
    #[inline(always)]
    pub fn sample(&self, wi: &Direction, u_lobe: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let flip = self.side(wi)?;
        let a = wi.oriented(flip);
        let s = match &self.material.bsdf {
            Bsdf::Lambert(l) => l.sample(a, u), // inline, as in `pdf_of`
            bsdf => bsdf.sample(a, u_lobe, u, mode),
        }?;
        self.finish(wi, flip, a, s, mode)
    }

    /// Samples a world direction uniformly over the scattering hemisphere
    /// ([`Material::sample_uniform_world`]).
    #[inline]
    pub fn sample_uniform(&self, wi: &Direction, u: Vec2) -> Option<BsdfSample> {
        let flip = self.side(wi)?;
        let a = wi.oriented(flip);
        let wo = crate::sampling::warp::square_to_uniform_hemisphere(u);
        let pdf = crate::sampling::warp::UNIFORM_HEMISPHERE_PDF;
        let weight = self.material.bsdf.eval(a, wo) * wo.z / pdf;
        self.finish(wi, flip, a, BsdfSample { wo, weight, pdf, delta: false }, TransportMode::Importance)
    }

    /// A sample `s` drawn in the local frame of side `flip` (from `wi`, local `a`) turned into
    /// world space, with the importance-mode correction and the leak guard (`None`: weight 0).
    #[inline]
    fn finish(
        &self,
        wi: &Direction,
        flip: bool,
        a: Vec3,
        s: BsdfSample,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        let l = s.wo;
        let wo = self.frame.to_world(if flip { Vec3::new(l.x, -l.y, -l.z) } else { l });
        if self.flat {
            return Some(BsdfSample { wo, ..s });
        }
        let go = wo.dot(self.normals.geometric);
        if !Self::agrees(wi.cos_g, go, a.z, s.wo.z) {
            return None;
        }
        let weight = match mode {
            TransportMode::Importance => s.weight * (Self::incident_factor(wi, a) * go.abs() / s.wo.z.abs()),
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
        let normals = SurfaceNormals {
            geometric: Vec3::Y,
            shading: Vec3::new(0.35, 1.0, -0.1).normalize(),
            tangent: None,
        };
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

    /// What lets one [`ShadingPoint`] serve both faces: the frame of −n is exactly (s, −t, −n)
    /// of the frame of n (every rounding of `Frame::from_normal` is odd in n; only an exact
    /// zero may come out as −0 one way and +0 the other, e.g. t.y for n = ±y), so flipped local
    /// coordinates are exactly (x, −y, −z) and a flipped local sample maps back to the same
    /// world direction. `==` compares numbers: bit for bit except the sign of a zero.
    #[test]
    fn the_frame_of_the_back_face_is_the_front_frame_turned_over_exactly() {
        let mut rng = RandomStream::new(11, &[3]);
        let mut normals: Vec<Vec3> =
            (0..20_000).map(|_| warp::square_to_uniform_sphere(rng.next_2d())).collect();
        normals.extend([
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(0.6, 0.8, 0.0),
            Vec3::new(0.6, 0.0, -0.8),
        ]);
        let flip = |v: Vec3| Vec3::new(v.x, -v.y, -v.z);
        for n in normals {
            let (f, b) = (Frame::from_normal(n), Frame::from_normal(-n));
            assert!(b.s == f.s && b.t == -f.t && b.n == -f.n, "n = {n}");
            for _ in 0..4 {
                let w = warp::square_to_uniform_sphere(rng.next_2d());
                let (l, lb) = (f.to_local(w), b.to_local(w));
                assert_eq!(lb, flip(l), "n = {n}, w = {w}");
                assert_eq!(b.to_world(lb), f.to_world(flip(lb)), "n = {n}, w = {w}");
            }
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
        let normals = SurfaceNormals { geometric: Vec3::Y, shading: Vec3::new(0.8, 0.6, 0.0), tangent: None };
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
