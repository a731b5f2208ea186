//! Tests of the transmission lobe of [`Principled`] (`spec_trans` > 0, `principled_trans.rs`):
//! Mitsuba's own values in both transport modes, with directions on both sides; χ² of the
//! sampling over the whole sphere from outside and from inside; reciprocity of the reflection,
//! generalized reciprocity of the refraction and the sample weights of both modes.

use super::super::*;
use crate::bsdf::Bsdf;
use crate::bsdf::chi2::{
    assert_rgb_close_to_mitsuba, chi2_from_directions, close_to_mitsuba, direction, incident,
};
use crate::bsdf::principled_mitsuba::MITSUBA_TRANS;
use crate::sampling::{RandomStream, warp};

const IMP: TransportMode = TransportMode::Importance;
const RAD: TransportMode = TransportMode::Radiance;

/// (x, y, −z).
fn flip(v: Vec3) -> Vec3 {
    Vec3::new(v.x, v.y, -v.z)
}

/// The transmitting cases of tools/mitsuba/principled_values.py (`TRANS_CASES`), in its order.
fn mitsuba_trans_cases() -> Vec<Principled> {
    let d = Principled { has_spec_trans: true, ..Principled::default() };
    vec![
        Principled { base_color: Rgb::new(0.9, 0.8, 0.6), spec_trans: 1.0, roughness: 0.2, ..d.clone() },
        Principled {
            base_color: Rgb::new(0.2, 0.5, 0.9),
            spec_trans: 0.3,
            roughness: 0.6,
            metallic: 0.2,
            sheen: 0.5,
            clearcoat: 0.5,
            ..d.clone()
        },
        Principled {
            base_color: Rgb::new(0.7, 0.9, 0.5),
            spec_trans: 1.0,
            roughness: 0.6,
            anisotropic: 0.7,
            eta: 1.33,
            spec_tint: 0.5,
            ..d.clone()
        },
        Principled {
            base_color: Rgb::new(0.5, 0.5, 0.8),
            spec_trans: 0.3,
            roughness: 0.2,
            diffuse_rate: 0.5,
            specular_rate: 2.0,
            ..d.clone()
        },
        Principled { spec_trans: 0.7, roughness: 0.4, eta: 0.8, ..d.clone() },
        // Mitsuba raises specular 0 to 10⁻³ with transmission (the loader does).
        Principled { spec_trans: 1.0, roughness: 0.2, eta: eta_of_specular(1e-3), ..d },
    ]
    .into_iter()
    .map(|p| p.checked().unwrap())
    .collect()
}

/// Mitsuba's eval (÷ |cos θ_o|) in importance mode is our eval(wi, wo), in radiance mode our
/// eval(wo, wi) (the adjoint: refraction differs by 1/η_p²), and its pdf ours, all within
/// 2·10⁻⁴ relative: the transmission's η_p², √base_color, (1 − m)·t weights, the back side's
/// bare dielectric reflection, the lobe probabilities from both sides.
#[test]
fn matches_mitsuba_transmission_values() {
    let cases = mitsuba_trans_cases();
    assert_eq!(cases.len(), MITSUBA_TRANS.len());
    let mut across = 0;
    for (b, (name, pairs)) in cases.iter().zip(MITSUBA_TRANS) {
        for &(i, o, f_imp, f_rad, pdf) in pairs.iter() {
            let (wi, wo) = (direction(i), direction(o));
            let (imp, rad, our_pdf) = (b.eval(wi, wo), b.eval(wo, wi), b.pdf(wi, wo));
            assert_rgb_close_to_mitsuba(imp, f_imp, &format!("{name} {i:?}->{o:?} f"));
            assert_rgb_close_to_mitsuba(rad, f_rad, &format!("{name} {i:?}->{o:?} adjoint"));
            assert!(close_to_mitsuba(our_pdf, pdf), "{name} {i:?}->{o:?}: pdf {our_pdf} vs Mitsuba's {pdf}");
            across += (wi.z * wo.z < 0.0 && f_imp[0] > 0.0) as usize;
        }
    }
    assert!(across >= 40, "{across} refracted pairs with a value");
}

/// The cases the sampling and reciprocity tests sweep: Mitsuba's and a metal-free coated one.
fn cases() -> Vec<Principled> {
    let mut v = mitsuba_trans_cases();
    v.push(
        Principled {
            base_color: Rgb::new(0.95, 0.6, 0.3),
            spec_trans: 0.5,
            roughness: 0.3,
            anisotropic: 1.0,
            clearcoat: 1.0,
            clearcoat_gloss: 0.9,
            has_spec_trans: true,
            ..Principled::default()
        }
        .checked()
        .unwrap(),
    );
    v
}

/// χ² of the samples against `pdf` over the whole sphere (reflection and refraction), from
/// outside at normal, oblique and grazing incidence and from inside (below and beyond the
/// critical angle).
#[test]
fn chi2_sampling_matches_pdf_on_both_sides() {
    let cases: Vec<Bsdf> = cases().into_iter().map(Bsdf::Principled).collect();
    let wis = [incident(0.0), incident(50.0), incident(85.0), flip(incident(20.0)), flip(incident(60.0))];
    chi2_from_directions(&cases, &wis, 3100, "principled transmission");
}

/// Reflection is reciprocal, f(a→b) = f(b→a), on both sides; refraction obeys generalized
/// reciprocity f(a→b)/η_b² = f(b→a)/η_a² (absolute indices, 1 outside, η inside): the adjoint
/// the light tracer needs. Every sample's importance weight is f(wi→wo)|cos θ_o|/pdf and its
/// radiance weight f(wo→wi)|cos θ_o|/pdf, with the density `pdf` gives.
#[test]
fn reciprocity_adjoint_and_weights() {
    let mut rng = RandomStream::new(3201, &[]);
    for b in cases() {
        let index = |v: Vec3| if v.z > 0.0 { 1.0f32 } else { b.eta };
        let (mut refracted, mut reflected) = (0, 0);
        for _ in 0..20_000 {
            let wa = warp::square_to_uniform_sphere(rng.next_2d());
            let sampled = b.sample(wa, rng.next_f32(), rng.next_2d(), IMP);
            let wb = match sampled {
                Some(s) if rng.next_f32() < 0.7 => s.wo,
                _ => warp::square_to_uniform_sphere(rng.next_2d()),
            };
            let (ab, ba) = (b.eval(wa, wb), b.eval(wb, wa));
            let (lhs, rhs) = if wa.z * wb.z < 0.0 {
                refracted += (ab.x > 0.0) as usize;
                (ab / index(wb).powi(2), ba / index(wa).powi(2))
            } else {
                reflected += (ab.x > 0.0) as usize;
                (ab, ba)
            };
            assert!(lhs.is_finite() && rhs.is_finite() && lhs.min_element() >= 0.0, "{b:?} {wa} {wb}");
            // 1 − F is taken from wi's side, as Mitsuba does, which at grazing angles rounds
            // differently from the other side's (the same in exact arithmetic, Stokes).
            let rel = if wa.z * wb.z < 0.0 { 5e-3 } else { 1e-3 };
            let tol = rel * lhs.max_element().max(rhs.max_element()) + 1e-6;
            assert!((lhs - rhs).abs().max_element() <= tol, "{b:?} {wa} {wb}: {lhs} vs {rhs}");

            let (ul, u) = (rng.next_f32(), rng.next_2d());
            let (Some(si), Some(sr)) = (b.sample(wa, ul, u, IMP), b.sample(wa, ul, u, RAD)) else { continue };
            assert_eq!((si.wo, si.pdf), (sr.wo, sr.pdf));
            assert_eq!(si.pdf, b.pdf(wa, si.wo));
            assert!(!si.delta);
            let w_imp = b.eval(wa, si.wo) * si.wo.z.abs() / si.pdf;
            let w_rad = b.eval(si.wo, wa) * si.wo.z.abs() / si.pdf;
            let close = |a: Rgb, e: Rgb| (a - e).abs().max_element() <= 2e-3 * e.max_element() + 1e-6;
            assert!(close(si.weight, w_imp), "importance {si:?} vs {w_imp}");
            assert!(
                close(sr.weight, w_rad),
                "radiance {sr:?} vs {w_rad} wa={wa} imp={si:?} ab={} ba={}",
                b.eval(wa, si.wo),
                b.eval(si.wo, wa)
            );
        }
        assert!(
            refracted > 2_000 && reflected > 2_000,
            "{b:?}: {refracted} refracted, {reflected} reflected"
        );
    }
}

/// Energy from outside in importance mode (flux): the mean sample weight over the sphere stays
/// below 1 per channel for a white, fully transmitting, smooth-ish glass, and a white glass
/// seen from inside sends out at most what arrives.
#[test]
fn white_glass_conserves_flux() {
    let glass = Principled {
        base_color: Rgb::ONE,
        spec_trans: 1.0,
        roughness: 0.3,
        has_spec_trans: true,
        ..Principled::default()
    };
    let mut rng = RandomStream::new(3301, &[]);
    for wi in [incident(0.0), incident(60.0), flip(incident(10.0)), flip(incident(60.0))] {
        let n = 200_000;
        let (mut sum, mut through) = (Rgb::ZERO, 0);
        for _ in 0..n {
            if let Some(s) = glass.sample(wi, rng.next_f32(), rng.next_2d(), IMP) {
                sum += s.weight;
                through += (s.wo.z * wi.z < 0.0) as usize;
            }
        }
        let mean = sum / n as f32;
        assert!(mean.max_element() <= 1.0 + 3e-3 && mean.min_element() > 0.7, "wi={wi}: {mean}");
        assert!(through > 0, "wi={wi}");
    }
}

/// Without the lobe (`has_spec_trans` false) nothing changes: one-sided, black from behind,
/// even with a `spec_trans` weight set (as Mitsuba, whose flag decides).
#[test]
fn without_the_flag_the_bsdf_is_one_sided() {
    let b = Principled { spec_trans: 0.0, ..Principled::default() };
    let (wi, wo) = (incident(30.0), -incident(20.0));
    assert_eq!((b.eval(wi, wo), b.pdf(wi, wo)), (Rgb::ZERO, 0.0));
    assert!(b.sample(flip(wi), 0.5, Vec2::splat(0.5), IMP).is_none());
    assert!(!Bsdf::Principled(b).transmits());
    let t = Principled { has_spec_trans: true, spec_trans: 1.0, ..Principled::default() };
    assert!(Bsdf::Principled(t.clone()).transmits());
    assert!(t.eval(wi, wo).x > 0.0 && t.eval(wo, wi).x > 0.0);
}
