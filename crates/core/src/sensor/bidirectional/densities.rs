//! The two tracers' sampling densities at a surface, evaluated for given directions: what the
//! MIS weights of `docs/bidirectional.md` §4 and §7 need besides the densities a tracer gets
//! back when it samples. Both must be exactly the densities of the procedures that sample:
//!
//! * the **camera tracer** (this renderer's camera subpaths) samples with
//!   [`Material::sample_world`] in radiance mode: [`Bsdf::pdf`] in the shading frame chosen by
//!   the direction toward the camera side;
//! * the **light tracer** (`crate::trace::trace_path`) samples with [`Material::sample_world`] in
//!   importance mode, or uniformly over the shading hemisphere on non-delta, non-transmitting
//!   surfaces under [`Directions::Uniform`].
//!
//! [`Bsdf::pdf`] is the same in both transport modes, so the one function [`pdf`] serves both,
//! told whose rule applies. For a delta event the "density" is the chosen lobe's discrete
//! probability ([`delta_reverse`] gives the reverse one).

use crate::bsdf::{Bsdf, Material, fresnel};
use crate::dataset::Directions;
use crate::geometry::SurfaceNormals;
use crate::math::Vec3;
use crate::sampling::warp::UNIFORM_HEMISPHERE_PDF;

/// Whose sampling rule a density is asked of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tracer {
    /// The camera tracer: always the BSDF's importance sampling.
    Camera,
    /// The light tracer with the dataset's direction strategy.
    Light(Directions),
}

/// The solid-angle density with which `tracer`, at a surface of `material` and `normals` having
/// arrived along world direction `given` (pointing away from the surface, toward the previous
/// vertex of its own subpath), samples the world direction `sampled`. Zero where the side of
/// `given` does not scatter and for delta BSDFs.
#[inline]
pub fn pdf(tracer: Tracer, material: &Material, normals: SurfaceNormals, given: Vec3, sampled: Vec3) -> f32 {
    let Some(frame) = material.frame_for(normals, given) else { return 0.0 };
    let b = frame.frame.to_local(sampled);
    let uniform = tracer == Tracer::Light(Directions::Uniform);
    if uniform && !material.bsdf.is_delta() && !material.bsdf.transmits() {
        return if b.z > 0.0 { UNIFORM_HEMISPHERE_PDF } else { 0.0 };
    }
    material.bsdf.pdf(frame.frame.to_local(given), b)
}

/// The discrete probability with which either tracer, arriving at a delta surface along world
/// direction `sampled`, picks the lobe that leads to `given` — the reverse of a delta event
/// that went from `given` to `sampled` (both tracers sample delta BSDFs alike). 1 for a mirror;
/// F or 1 − F of the reverse direction for smooth glass; 0 for non-delta BSDFs.
#[inline]
pub fn delta_reverse(material: &Material, normals: SurfaceNormals, given: Vec3, sampled: Vec3) -> f32 {
    let Some(frame) = material.frame_for(normals, given) else { return 0.0 };
    match &material.bsdf {
        Bsdf::SmoothConductor(_) => 1.0,
        Bsdf::SmoothDielectric(d) => {
            let (a, b) = (frame.frame.to_local(given), frame.frame.to_local(sampled));
            let eta = if b.z < 0.0 { 1.0 / d.eta } else { d.eta };
            let (f, _) = fresnel::dielectric(b.z.abs(), eta);
            if a.z * b.z > 0.0 { f } else { 1.0 - f }
        }
        _ => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::{Lambert, SmoothDielectric, TransportMode};
    use crate::math::{Rgb, Vec2};
    use crate::sampling::RandomStream;

    /// A delta sample's reverse probability is the forward one of the reverse event: sample
    /// back from the sampled direction and read the lobe probability the BSDF reports.
    #[test]
    fn delta_reverse_is_the_reverse_sample_probability() {
        let glass = Material {
            name: "g".into(),
            bsdf: Bsdf::SmoothDielectric(SmoothDielectric::new(1.5, 1.0, Rgb::ONE, Rgb::ONE).unwrap()),
            two_sided: false,
        };
        let n = SurfaceNormals::flat(Vec3::Y);
        let mut rng = RandomStream::new(3, &[]);
        for _ in 0..2000 {
            let mut given = crate::sampling::warp::square_to_uniform_sphere(rng.next_2d());
            if given.y.abs() < 1e-3 {
                given.y = 0.5;
            }
            let given = given.normalize();
            let s =
                glass.sample_world(n, given, rng.next_f32(), Vec2::ZERO, TransportMode::Radiance).unwrap();
            let reverse = delta_reverse(&glass, n, given, s.wo);
            // The reverse sample reaches `given` with the lobe of the same kind.
            let reflect = given.y * s.wo.y > 0.0;
            let back = (0..2)
                .filter_map(|k| {
                    glass.sample_world(
                        n,
                        s.wo,
                        if k == 0 { 0.0 } else { 0.999_999 },
                        Vec2::ZERO,
                        TransportMode::Importance,
                    )
                })
                .find(|b| (b.wo.y * s.wo.y > 0.0) == reflect)
                .map_or(0.0, |b| b.pdf);
            assert!((reverse - back).abs() < 1e-4, "{reverse} vs {back}");
        }
    }

    #[test]
    fn uniform_directions_apply_only_to_the_light_tracer_on_opaque_surfaces() {
        let m = Material {
            name: "w".into(),
            bsdf: Bsdf::Lambert(Lambert::new(Rgb::ONE).unwrap()),
            two_sided: false,
        };
        let n = SurfaceNormals::flat(Vec3::Y);
        let (a, b) = (Vec3::new(0.3, 0.9, 0.1).normalize(), Vec3::new(-0.2, 0.5, 0.4).normalize());
        assert_eq!(pdf(Tracer::Light(Directions::Uniform), &m, n, a, b), UNIFORM_HEMISPHERE_PDF);
        let cosine = b.y / std::f32::consts::PI;
        assert!((pdf(Tracer::Camera, &m, n, a, b) - cosine).abs() < 1e-6);
        assert_eq!(pdf(Tracer::Light(Directions::Importance), &m, n, a, b), pdf(Tracer::Camera, &m, n, a, b));
        assert_eq!(pdf(Tracer::Camera, &m, n, -a, b), 0.0, "the back of a one-sided surface");
    }
}
