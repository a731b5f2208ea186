//! Tests of [`super::Principled`], apart from it so that the BSDF's file stays readable: its
//! values against Mitsuba 3's own (the table of tools/mitsuba/principled_values.py), χ² of its
//! sampling against its pdf, reciprocity, the sample weights' consistency and energy, and the
//! parameter checks. The transmission lobe's (`spec_trans` > 0) are in `principled_trans_tests.rs`.

use super::*;
use crate::bsdf::Bsdf;
use crate::bsdf::TransportMode;
use crate::bsdf::chi2::{
    SphereGrid, assert_reciprocal_and_consistent, chi2_at_three_incidences, direction, directional_albedo,
    incident, mean_sample_weight, pilot,
};
use crate::bsdf::principled_mitsuba::MITSUBA;
use crate::sampling::RandomStream;
use rayon::prelude::*;

/// The cases of tools/mitsuba/principled_values.py, in its order.
fn mitsuba_cases() -> Vec<Principled> {
    let d = Principled::default();
    vec![
        d.clone(),
        Principled {
            base_color: Rgb::new(0.8, 0.4, 0.1),
            metallic: 0.7,
            roughness: 0.3,
            anisotropic: 0.5,
            spec_tint: 0.4,
            eta: eta_of_specular(0.6),
            ..d.clone()
        },
        Principled {
            base_color: Rgb::new(0.2, 0.5, 0.9),
            roughness: 0.8,
            sheen: 0.8,
            sheen_tint: 0.5,
            clearcoat: 0.7,
            clearcoat_gloss: 0.6,
            flatness: 0.4,
            ..d.clone()
        },
        Principled {
            base_color: Rgb::new(0.9, 0.7, 0.3),
            eta: 1.33,
            metallic: 1.0,
            roughness: 0.1,
            ..d.clone()
        },
        Principled {
            base_color: Rgb::new(0.6, 0.3, 0.3),
            eta: 0.8,
            spec_tint: 1.0,
            clearcoat: 1.0,
            clearcoat_gloss: 0.2,
            roughness: 0.4,
            metallic: 0.2,
            diffuse_rate: 0.5,
            specular_rate: 2.0,
            clearcoat_rate: 3.0,
            ..d.clone()
        },
        Principled { eta: eta_of_specular(0.0), metallic: 0.5, roughness: 0.2, sheen: 1.0, ..d },
    ]
    .into_iter()
    .map(|p| p.checked().unwrap())
    .collect()
}

/// Mitsuba's own eval (÷ cos θ_o) and pdf at fixed directions, both within 2·10⁻⁴ relative
/// (f32 rounding of the same formulas): the parameters' meanings, the defaults, the Fresnel
/// blend, the anisotropy's axes, the clearcoat's missing 1/(4 cos cos), the sampling rates.
#[test]
fn matches_mitsuba_values() {
    let cases = mitsuba_cases();
    assert_eq!(cases.len(), MITSUBA.len());
    for (b, (name, pairs)) in cases.iter().zip(MITSUBA) {
        for &(i, o, f, pdf) in pairs.iter() {
            let (wi, wo) = (direction(i), direction(o));
            let (ours, our_pdf) = (b.eval(wi, wo), b.pdf(wi, wo));
            for c in 0..3 {
                assert!(
                    (ours[c] - f[c]).abs() <= 2e-4 * f[c] + 1e-7,
                    "{name} wi={i:?} wo={o:?} channel {c}: f = {} vs Mitsuba's {}",
                    ours[c],
                    f[c]
                );
            }
            assert!(
                (our_pdf - pdf).abs() <= 2e-4 * pdf + 1e-7,
                "{name} wi={i:?} wo={o:?}: pdf {our_pdf} vs Mitsuba's {pdf}"
            );
            // One-sided: nothing from behind, nothing below.
            let below = Vec3::new(wo.x, wo.y, -wo.z);
            assert_eq!((b.eval(below, wi), b.eval(wi, below), b.pdf(wi, below)), (Rgb::ZERO, Rgb::ZERO, 0.0));
        }
    }
}

/// The cases the sampling, reciprocity and energy tests sweep: Mitsuba's, and a fully
/// anisotropic near-mirror metal with a glossy coat and no diffuse sampling.
fn cases() -> Vec<Principled> {
    let mut v = mitsuba_cases();
    v.push(
        Principled {
            base_color: Rgb::new(0.95, 0.9, 0.8),
            metallic: 0.9,
            roughness: 0.15,
            anisotropic: 1.0,
            clearcoat: 1.0,
            clearcoat_gloss: 0.9,
            diffuse_rate: 0.0,
            ..Principled::default()
        }
        .checked()
        .unwrap(),
    );
    v
}

/// χ² of the samples against `pdf` at normal, oblique and grazing incidence.
#[test]
fn chi2_sampling_matches_pdf() {
    let cases: Vec<Bsdf> = cases().into_iter().map(Bsdf::Principled).collect();
    chi2_at_three_incidences(&cases, 2100, "principled");
}

/// Reciprocity f(wi → wo) = f(wo → wi) (every lobe of Mitsuba's model is symmetric, so the
/// adjoint is f itself), and the weights agree with eval·cos/pdf.
#[test]
fn reciprocal_and_consistent() {
    let cases: Vec<Bsdf> = cases().into_iter().map(Bsdf::Principled).collect();
    assert_reciprocal_and_consistent(&cases, 2101);
}

/// Energy: the mean sample weight equals the quadrature of f·cos within 5σ, and stays below
/// [`Principled::max_albedo`]; a white metal reflects at most what it receives.
#[test]
fn furnace() {
    let metal = Principled { base_color: Rgb::ONE, metallic: 1.0, roughness: 0.4, ..Principled::default() };
    let all: Vec<(usize, Principled)> = cases().into_iter().chain([metal]).enumerate().collect();
    let last = all.len() - 1;
    all.into_par_iter().for_each(|(k, b)| {
        let mut rng = RandomStream::new(2102, &[k as u64]);
        for deg in [0.0, 45.0, 80.0] {
            let wi = incident(deg);
            let dirs =
                pilot(|ul, u| b.sample(wi, ul, u, TransportMode::Radiance).map(|s| (s.wo, s.pdf)), 20_000, 3);
            let grid = SphereGrid::adapted(Vec3::Z, &dirs, 16, 16);
            let want = directional_albedo(&grid, |wo| b.eval(wi, wo));
            let (mean, se) = mean_sample_weight(200_000, || {
                b.sample(wi, rng.next_f32(), rng.next_2d(), TransportMode::Radiance).map(|s| s.weight)
            });
            let bound = b.max_albedo();
            for c in 0..3 {
                assert!(
                    (mean[c] - want[c]).abs() <= 5.0 * se[c] + 1e-4,
                    "case {k} θ={deg} channel {c}: {} vs {} ± {}",
                    mean[c],
                    want[c],
                    se[c]
                );
                assert!(
                    want[c] <= bound[c] as f64,
                    "case {k} θ={deg}: albedo {} > bound {}",
                    want[c],
                    bound[c]
                );
                if k == last {
                    assert!(want[c] <= 1.0 && want[c] > 0.8, "white metal θ={deg}: albedo {}", want[c]);
                }
            }
            println!("case {k} θ={deg}: albedo {want}");
        }
    });
}

#[test]
fn parameters_are_validated() {
    use MaterialError::*;
    let d = Principled::default();
    assert_eq!(d.clone().checked(), Ok(d.clone()));
    assert!((d.eta - 1.5).abs() < 1e-6, "specular 0.5 is η 1.5");
    let bad = |p: Principled| p.checked().unwrap_err();
    assert_eq!(bad(Principled { base_color: Rgb::splat(1.2), ..d.clone() }), AboveOne("base_color"));
    assert_eq!(bad(Principled { metallic: 1.5, ..d.clone() }), OutOfUnitRange("metallic", 1.5));
    assert_eq!(bad(Principled { sheen: -0.1, ..d.clone() }), OutOfUnitRange("sheen", -0.1));
    assert_eq!(bad(Principled { roughness: f32::NAN, ..d.clone() }), NotFinite("roughness"));
    assert_eq!(bad(Principled { eta: 0.0, ..d.clone() }), NotPositive("eta"));
    assert_eq!(
        bad(Principled { specular_rate: 0.0, ..d.clone() }),
        NotPositive("main_specular_sampling_rate")
    );
    assert_eq!(bad(Principled { clearcoat_rate: -1.0, ..d }), Negative("clearcoat_sampling_rate"));
}

#[path = "principled_trans_tests.rs"]
mod trans;
