//! A blend of two BSDFs, Mitsuba 3's `blendbsdf`: f = (1 − w)·f₀ + w·f₁ for a weight w in
//! [0, 1], sampled as Mitsuba does — child 1 with probability w (u_lobe ≤ w, the lobe number
//! rescaled for the child), else child 0 — with the mixture density p = (1 − w)·p₀ + w·p₁ and
//! the weight f·cos θ_o/p (one-sample MIS of the two children's strategies).
//!
//! A delta event of a child k (its mirror, a plastic's coating) keeps the child's weight: the
//! blend's delta lobe is w_k times the child's, picked with w_k times its probability
//! ([`Bsdf::lobe_probability`] is the mixture of the children's). That is exact when only one
//! child has delta lobes, which the constructor requires (two deltas could coincide in
//! direction, and their sum would need both). Children only reflect (no dielectrics: their
//! frames are oriented, a reflector's follows the side the light comes from), and may be blends.
//! The two children live in one box, so the enum stays small; nothing is allocated when the
//! blend is evaluated or sampled.

use super::{Bsdf, BsdfSample, MaterialError, TransportMode};
use crate::math::{Rgb, Vec2, Vec3};

/// `blendbsdf` (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Blend {
    /// w: the share of `bsdfs[1]`.
    pub weight: f32,
    /// The two children f₀, f₁.
    pub bsdfs: Box<[Bsdf; 2]>,
}

impl Blend {
    /// A blend. Refuses a weight outside [0, 1] (or not finite), transmitting children, and two
    /// children that both have delta lobes.
    pub fn new(weight: f32, first: Bsdf, second: Bsdf) -> Result<Self, MaterialError> {
        if !weight.is_finite() {
            return Err(MaterialError::NotFinite("weight"));
        }
        if weight < 0.0 {
            return Err(MaterialError::Negative("weight"));
        }
        if weight > 1.0 {
            return Err(MaterialError::AboveOne("weight"));
        }
        if first.transmits() || second.transmits() {
            return Err(MaterialError::Unsupported(
                "a blend of a dielectric (its frame is oriented, a reflector's is not)",
            ));
        }
        if first.has_delta_lobe() && second.has_delta_lobe() {
            return Err(MaterialError::Unsupported("a blend of two BSDFs that both have delta lobes"));
        }
        Ok(Blend { weight, bsdfs: Box::new([first, second]) })
    }

    /// (1 − w)·f₀ + w·f₁.
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        let [a, b] = &*self.bsdfs;
        a.eval(wi, wo) * (1.0 - self.weight) + b.eval(wi, wo) * self.weight
    }

    /// (1 − w)·p₀ + w·p₁.
    #[inline]
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        let [a, b] = &*self.bsdfs;
        a.pdf(wi, wo) * (1.0 - self.weight) + b.pdf(wi, wo) * self.weight
    }

    /// The probability of the delta lobe leading to `wo` (that of the child that has one).
    #[inline]
    pub fn lobe_probability(&self, wi: Vec3, wo: Vec3) -> f32 {
        let [a, b] = &*self.bsdfs;
        a.lobe_probability(wi, wo) * (1.0 - self.weight) + b.lobe_probability(wi, wo) * self.weight
    }

    /// A child's sample (module docs): a delta event with the child's weight and w_k times its
    /// probability, else the mixture's weight and density at the sampled direction.
    #[inline]
    pub fn sample(&self, wi: Vec3, u_lobe: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let w = self.weight;
        let (k, share, u_child) =
            if u_lobe <= w && w > 0.0 { (1, w, u_lobe / w) } else { (0, 1.0 - w, (u_lobe - w) / (1.0 - w)) };
        let s = self.bsdfs[k].sample(wi, u_child.clamp(0.0, 1.0 - f32::EPSILON / 2.0), u, mode)?;
        if s.delta {
            return Some(BsdfSample { pdf: share * s.pdf, ..s });
        }
        let pdf = self.pdf(wi, s.wo);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight = self.eval(wi, s.wo) * (s.wo.z.abs() / pdf);
        weight.is_finite().then_some(BsdfSample { weight, pdf, ..s })
    }

    /// The mixture of the children's albedo bounds.
    pub fn max_albedo(&self) -> Rgb {
        let [a, b] = &*self.bsdfs;
        a.max_albedo() * (1.0 - self.weight) + b.max_albedo() * self.weight
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::{Chi2Test, SphereGrid, directional_albedo, incident, mean_sample_weight, pilot};
    use crate::bsdf::{Lambert, ModifiedPhong, Plastic, RoughConductor, RoughPlastic, SmoothConductor};
    use crate::sampling::microfacet::Distribution;
    use crate::sampling::{RandomStream, warp};
    use rayon::prelude::*;

    fn blends() -> Vec<Blend> {
        let lambert = || Bsdf::Lambert(Lambert::new(Rgb::new(0.8, 0.5, 0.2)).unwrap());
        let metal = || Bsdf::RoughConductor(RoughConductor::new(0.2, Rgb::new(0.9, 0.8, 0.7), None).unwrap());
        let phong =
            || Bsdf::ModifiedPhong(ModifiedPhong::new(Rgb::splat(0.3), Rgb::splat(0.5), 40.0).unwrap());
        let rough_plastic = || {
            Bsdf::RoughPlastic(
                RoughPlastic::new(Rgb::splat(0.4), Rgb::ONE, 1.5, 1.0, Distribution::Ggx, 0.3, true, false)
                    .unwrap(),
            )
        };
        let inner = Blend::new(0.5, phong(), rough_plastic()).unwrap();
        vec![
            Blend::new(0.3, lambert(), metal()).unwrap(),
            Blend::new(0.8, metal(), phong()).unwrap(),
            Blend::new(0.6, lambert(), Bsdf::Blend(inner)).unwrap(),
            Blend::new(0.0, lambert(), metal()).unwrap(),
            Blend::new(1.0, lambert(), metal()).unwrap(),
        ]
    }

    /// With delta lobes: a mirror, or a smooth plastic.
    fn delta_blends() -> Vec<Blend> {
        let lambert = || Bsdf::Lambert(Lambert::new(Rgb::new(0.8, 0.5, 0.2)).unwrap());
        let mirror = Bsdf::SmoothConductor(SmoothConductor::new(Rgb::splat(0.9), None).unwrap());
        let plastic = Bsdf::Plastic(Plastic::new(Rgb::splat(0.5), Rgb::ONE, 1.5, 1.0, false).unwrap());
        vec![Blend::new(0.4, mirror, lambert()).unwrap(), Blend::new(0.7, lambert(), plastic).unwrap()]
    }

    /// χ² of the (non-delta) samples against `pdf`; the harness checks ∫pdf against the
    /// fraction of accepted samples, so the delta events' share is checked too.
    #[test]
    fn chi2_sampling_matches_pdf() {
        let all: Vec<Blend> = blends().into_iter().chain(delta_blends()).collect();
        let items: Vec<(usize, f32)> =
            (0..all.len()).flat_map(|b| [0.0, 60.0, 85.0].map(move |d| (b, d))).collect();
        items.into_par_iter().enumerate().for_each(|(i, (k, deg))| {
            let all: Vec<Blend> = blends().into_iter().chain(delta_blends()).collect();
            let b = &all[k];
            let wi = incident(deg);
            Chi2Test::new(Vec3::Z, 2900 + i as u64)
                .run(
                    |ul, u| {
                        b.sample(wi, ul, u, TransportMode::Importance)
                            .filter(|s| !s.delta)
                            .map(|s| (s.wo, s.pdf))
                    },
                    |wo| b.pdf(wi, wo),
                )
                .assert_ok(&format!("blend {k} θi={deg}°"));
        });
    }

    /// eval and pdf are the mixtures; weights are eval·cos/pdf; delta events keep the child's
    /// weight and carry w_k times its probability.
    #[test]
    fn mixtures_and_weights_are_consistent() {
        let mut rng = RandomStream::new(2901, &[]);
        for b in blends().into_iter().chain(delta_blends()) {
            let [c0, c1] = &*b.bsdfs;
            for _ in 0..3_000 {
                let wi = warp::square_to_uniform_hemisphere(rng.next_2d());
                let wo = warp::square_to_uniform_hemisphere(rng.next_2d());
                let want = c0.eval(wi, wo) * (1.0 - b.weight) + c1.eval(wi, wo) * b.weight;
                assert!((b.eval(wi, wo) - want).abs().max_element() <= 1e-6 * want.max_element().max(1e-6));
                let Some(s) = b.sample(wi, rng.next_f32(), rng.next_2d(), TransportMode::Importance) else {
                    continue;
                };
                if s.delta {
                    let p = b.lobe_probability(wi, s.wo);
                    assert!((s.pdf - p).abs() <= 1e-6 * p, "{s:?} {p}");
                } else {
                    let w = b.eval(wi, s.wo) * s.wo.z / s.pdf;
                    assert!(
                        (s.weight - w).abs().max_element() <= 1e-5 * w.max_element() + 1e-30,
                        "{s:?} {w}"
                    );
                    assert_eq!(b.pdf(wi, s.wo), s.pdf);
                }
            }
        }
    }

    /// The mean sample weight (delta events included) equals (1 − w)·a₀ + w·a₁ of the children's
    /// albedos, each by quadrature plus its delta part, within 5σ.
    #[test]
    fn furnace() {
        let all: Vec<Blend> = blends().into_iter().chain(delta_blends()).collect();
        let mut rng = RandomStream::new(2902, &[]);
        for (k, b) in all.iter().enumerate() {
            for deg in [0.0, 50.0] {
                let wi = incident(deg);
                let mut want = glam::DVec3::ZERO;
                for (child, share) in b.bsdfs.iter().zip([1.0 - b.weight, b.weight]) {
                    let dirs = pilot(
                        |ul, u| {
                            child
                                .sample(wi, ul, u, TransportMode::Importance)
                                .filter(|s| !s.delta)
                                .map(|s| (s.wo, s.pdf))
                        },
                        20_000,
                        3,
                    );
                    let mut a = if dirs.is_empty() {
                        glam::DVec3::ZERO
                    } else {
                        directional_albedo(&SphereGrid::adapted(Vec3::Z, &dirs, 16, 16), |wo| {
                            child.eval(wi, wo)
                        })
                    };
                    // The delta part: the mean of the child's delta weights.
                    let n = 100_000;
                    let mut d = glam::DVec3::ZERO;
                    for _ in 0..n {
                        if let Some(s) =
                            child.sample(wi, rng.next_f32(), rng.next_2d(), TransportMode::Importance)
                            && s.delta
                        {
                            d += s.weight.as_dvec3();
                        }
                    }
                    a += d / n as f64;
                    want += a * share as f64;
                }
                let (mean, se) = mean_sample_weight(200_000, || {
                    b.sample(wi, rng.next_f32(), rng.next_2d(), TransportMode::Importance).map(|s| s.weight)
                });
                for c in 0..3 {
                    assert!(
                        (mean[c] - want[c]).abs() <= 6.0 * se[c] + 2e-3,
                        "blend {k} θ={deg} channel {c}: {} vs {} ± {}",
                        mean[c],
                        want[c],
                        se[c]
                    );
                }
            }
        }
    }

    #[test]
    fn parameters_are_validated() {
        use MaterialError::*;
        let l = || Bsdf::Lambert(Lambert::new(Rgb::ONE).unwrap());
        assert_eq!(Blend::new(1.5, l(), l()), Err(AboveOne("weight")));
        assert_eq!(Blend::new(-0.1, l(), l()), Err(Negative("weight")));
        assert_eq!(Blend::new(f32::NAN, l(), l()), Err(NotFinite("weight")));
        let glass =
            Bsdf::SmoothDielectric(crate::bsdf::SmoothDielectric::new(1.5, 1.0, Rgb::ONE, Rgb::ONE).unwrap());
        assert!(matches!(Blend::new(0.5, l(), glass), Err(Unsupported(_))));
        let mirror = || Bsdf::SmoothConductor(SmoothConductor::new(Rgb::ONE, None).unwrap());
        assert!(matches!(Blend::new(0.5, mirror(), mirror()), Err(Unsupported(_))));
    }
}
