//! Emission functions as probability densities (the thesis's f_e, §6.1.3).
//!
//! A light of power Φ emits, in the direction ω of its local frame (z = the light's axis, or an
//! area light's surface normal), the intensity (point light) or the intensity per unit area
//! (area light) `Φ·f_e(ω)`, where f_e is a probability density over directions (per unit solid
//! angle, integrating to 1). Every profile here is written as an unnormalised **shape**
//! s(ω) (1 on the axis for the analytic ones) and its integral S = ∫ s dω, so f_e = s/S and a
//! light of *strength* c (W/sr on the axis; radiance along the normal for an area light) has
//! Φ = c·S per unit (area):
//!
//! | profile | s(ω) | S | sampled by |
//! |---|---|---|---|
//! | [`EmissionProfile::Uniform`] | 1 | 4π (2π on an area light: front hemisphere only) | uniform sphere / hemisphere, exact |
//! | [`EmissionProfile::Cosine`] | cos θ | π | cosine hemisphere, exact |
//! | [`EmissionProfile::CosinePower`] | cosⁿθ | 2π/(n+1) | Phong-lobe inversion, exact |
//! | [`EmissionProfile::Spot`] | 1 inside `beam_width`, (γ−θ)/(γ−β) to 0 at `cutoff_angle` γ (Mitsuba 3's `spot`) | 2π·(1 − (sin γ − sin β)/(γ − β)) (closed form) | uniform in the cone θ < γ, weighted |
//! | [`EmissionProfile::Ies`] | candela(θ, φ)/683, bilinear in (θ, φ) | exact integral of the bilinear interpolant | 2D piecewise-constant table, weighted |
//!
//! When sampling is only proportional to an approximation of s (spot, IES), the sampled
//! direction carries the weight f_e(ω)/p(ω), with p the exact density of what was sampled, so
//! the estimator stays exact; its mean over directions is exactly 1.
//!
//! IES tables ([`IesProfile`], the [`Table`] built from it) are in [`super::ies`].

use super::check::LUMENS_PER_WATT;
use super::ies::{IesProfile, IesTableError, Table};
use crate::math::Vec3;
use crate::sampling::warp;
use std::f32::consts::{FRAC_1_PI, PI, TAU};
use std::f64::consts::PI as PI64;
use std::sync::Arc;

/// How a light's emission is distributed over directions (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub enum EmissionProfile {
    /// Uniform over the sphere (the front hemisphere on an area light).
    Uniform,
    /// Lambertian: f_e = cos θ/π over the front hemisphere.
    Cosine,
    /// Focused: f_e = (n+1)/(2π)·cosⁿθ over the front hemisphere, n ≥ 0.
    CosinePower {
        /// The exponent n.
        exponent: f32,
    },
    /// Mitsuba's spot: full intensity within `beam_width` of the axis, falling linearly in angle
    /// to zero at `cutoff_angle` (both in radians, 0 < beam_width ≤ cutoff_angle ≤ π).
    Spot {
        /// γ, radians.
        cutoff_angle: f32,
        /// β, radians.
        beam_width: f32,
    },
    /// Measured photometric data.
    Ies(IesProfile),
}

/// Why a profile cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileError {
    /// A cosⁿ exponent outside [0, 10⁶] (or NaN).
    #[error("the cosine-power exponent {0} must be in [0, 10⁶]")]
    Exponent(f32),
    /// A spot cutoff angle γ outside (0, `max`] (π; π/2 on a one-sided area light), radians.
    #[error("the spot cutoff angle {}° must be in (0°, {}°]", .cutoff.to_degrees(), .max.to_degrees())]
    Cutoff {
        /// γ.
        cutoff: f32,
        /// The largest cutoff allowed.
        max: f32,
    },
    /// A spot beam width β outside (0, γ], radians.
    #[error("the spot beam width {}° must be in (0°, cutoff angle = {}°]", .beam.to_degrees(), .cutoff.to_degrees())]
    Beam {
        /// β.
        beam: f32,
        /// γ.
        cutoff: f32,
    },
    /// An impossible IES table.
    #[error(transparent)]
    Ies(#[from] IesTableError),
}

impl EmissionProfile {
    /// A cosⁿ profile, n ∈ [0, 10⁶].
    pub fn cosine_power(exponent: f32) -> Result<Self, ProfileError> {
        check_exponent(exponent)?;
        Ok(EmissionProfile::CosinePower { exponent })
    }

    /// Mitsuba's spot of cutoff angle γ = `cutoff` and beam width β = `beam` (radians,
    /// 0 < β ≤ γ ≤ π; an area light's spot must also have γ ≤ π/2, checked when it is built).
    pub fn spot(cutoff: f32, beam: f32) -> Result<Self, ProfileError> {
        check_spot(cutoff, beam, PI)?;
        Ok(EmissionProfile::Spot { cutoff_angle: cutoff, beam_width: beam })
    }
}

/// n ∈ [0, 10⁶].
fn check_exponent(exponent: f32) -> Result<(), ProfileError> {
    if (0.0..=1e6).contains(&exponent) { Ok(()) } else { Err(ProfileError::Exponent(exponent)) }
}

/// 0 < β ≤ γ ≤ `max`.
fn check_spot(cutoff: f32, beam: f32, max: f32) -> Result<(), ProfileError> {
    if !(cutoff > 0.0 && cutoff <= max) {
        return Err(ProfileError::Cutoff { cutoff, max });
    }
    if !(beam > 0.0 && beam <= cutoff) {
        return Err(ProfileError::Beam { beam, cutoff });
    }
    Ok(())
}

/// A profile ready for sampling (built once per light by [`BuiltProfile::build`]).
#[derive(Clone, Debug, PartialEq)]
pub enum BuiltProfile {
    /// Uniform sphere (or hemisphere if `hemisphere`).
    Uniform {
        /// Restricted to z > 0.
        hemisphere: bool,
    },
    /// cos θ/π.
    Cosine,
    /// (n+1)/(2π)·cosⁿθ.
    CosinePower {
        /// n.
        exponent: f32,
    },
    /// Mitsuba spot.
    Spot {
        /// γ.
        cutoff: f32,
        /// β.
        beam: f32,
        /// cos γ.
        cos_cutoff: f32,
        /// cos β.
        cos_beam: f32,
        /// ∫ s dω.
        integral: f32,
    },
    /// Tabulated (IES).
    Table(Arc<Table>),
}

impl BuiltProfile {
    /// Validates `p` and precomputes what sampling needs. `hemisphere`: the profile belongs to
    /// a one-sided area light, which emits only into z > 0.
    pub fn build(p: &EmissionProfile, hemisphere: bool) -> Result<BuiltProfile, ProfileError> {
        Ok(match p {
            EmissionProfile::Uniform => BuiltProfile::Uniform { hemisphere },
            EmissionProfile::Cosine => BuiltProfile::Cosine,
            &EmissionProfile::CosinePower { exponent } => {
                check_exponent(exponent)?;
                BuiltProfile::CosinePower { exponent }
            }
            &EmissionProfile::Spot { cutoff_angle, beam_width } => {
                check_spot(cutoff_angle, beam_width, if hemisphere { 0.5 * PI } else { PI })?;
                BuiltProfile::Spot {
                    cutoff: cutoff_angle,
                    beam: beam_width,
                    cos_cutoff: cutoff_angle.cos(),
                    cos_beam: beam_width.cos(),
                    integral: spot_integral(cutoff_angle as f64, beam_width as f64) as f32,
                }
            }
            EmissionProfile::Ies(ies) => BuiltProfile::Table(Arc::new(Table::build(ies, hemisphere)?)),
        })
    }

    /// The unnormalised shape s(ω) of a local unit direction (z = axis); W/sr per unit strength
    /// (candela/683 for IES).
    #[inline]
    pub fn shape(&self, v: Vec3) -> f32 {
        match self {
            BuiltProfile::Uniform { hemisphere } => {
                if !hemisphere || v.z > 0.0 {
                    1.0
                } else {
                    0.0
                }
            }
            BuiltProfile::Cosine => v.z.max(0.0),
            BuiltProfile::CosinePower { exponent } => {
                if v.z > 0.0 {
                    warp::pow_cos_from_versine(1.0 - v.z, *exponent)
                } else {
                    0.0
                }
            }
            &BuiltProfile::Spot { cutoff, beam, cos_cutoff, cos_beam, .. } => {
                if v.z >= cos_beam {
                    1.0
                } else if v.z > cos_cutoff {
                    ((cutoff - v.z.clamp(-1.0, 1.0).acos()) / (cutoff - beam)).clamp(0.0, 1.0)
                } else {
                    0.0
                }
            }
            BuiltProfile::Table(t) => t.candela(v) / LUMENS_PER_WATT,
        }
    }

    /// S = ∫ s(ω) dω.
    pub fn integral(&self) -> f32 {
        match self {
            BuiltProfile::Uniform { hemisphere: false } => 4.0 * PI,
            BuiltProfile::Uniform { hemisphere: true } => TAU,
            BuiltProfile::Cosine => PI,
            BuiltProfile::CosinePower { exponent } => TAU / (exponent + 1.0),
            BuiltProfile::Spot { integral, .. } => *integral,
            BuiltProfile::Table(t) => (t.flux_lumens() / LUMENS_PER_WATT as f64) as f32,
        }
    }

    /// The emission density f_e(ω) = s(ω)/S of a local unit direction.
    #[inline]
    pub fn eval(&self, v: Vec3) -> f32 {
        match self {
            BuiltProfile::Cosine => v.z.max(0.0) * FRAC_1_PI,
            BuiltProfile::CosinePower { exponent } if v.z > 0.0 => {
                warp::phong_lobe_pdf_from_versine(1.0 - v.z, *exponent)
            }
            _ => self.shape(v) / self.integral(),
        }
    }

    /// f_e(ω)/cos θ: L_e·A/Φ for an area light (1/π for a Lambertian one); 0 behind it.
    #[inline]
    pub fn emitted_fraction(&self, v: Vec3) -> f32 {
        match self {
            BuiltProfile::Cosine => FRAC_1_PI,
            _ if v.z > 0.0 => self.eval(v) / v.z,
            _ => 0.0,
        }
    }

    /// The density of the directions [`BuiltProfile::sample`] draws (equal to [`Self::eval`]
    /// for the exactly sampled profiles).
    pub fn sampling_pdf(&self, v: Vec3) -> f32 {
        match self {
            &BuiltProfile::Spot { cos_cutoff, .. } => {
                if v.z > cos_cutoff {
                    1.0 / (TAU * (1.0 - cos_cutoff))
                } else {
                    0.0
                }
            }
            BuiltProfile::Table(t) => t.pdf(v),
            BuiltProfile::Uniform { hemisphere: true } => {
                if v.z > 0.0 {
                    warp::UNIFORM_HEMISPHERE_PDF
                } else {
                    0.0
                }
            }
            _ => self.eval(v),
        }
    }

    /// Draws a local direction from `u` ∈ [0,1)²; returns it with the weight f_e(ω)/p(ω)
    /// (1 for exactly sampled profiles, mean 1 always).
    #[inline]
    pub fn sample(&self, u: crate::math::Vec2) -> (Vec3, f32) {
        match self {
            BuiltProfile::Uniform { hemisphere: false } => (warp::square_to_uniform_sphere(u), 1.0),
            BuiltProfile::Uniform { hemisphere: true } => (warp::square_to_uniform_hemisphere(u), 1.0),
            BuiltProfile::Cosine => (warp::square_to_cosine_hemisphere(u), 1.0),
            BuiltProfile::CosinePower { exponent } => {
                // u.x = 0 would give the horizon exactly; keep it strictly inside.
                let ux = 1.0 - u.x; // (0, 1]
                (warp::square_to_phong_lobe(crate::math::Vec2::new(ux, u.y), *exponent), 1.0)
            }
            &BuiltProfile::Spot { cos_cutoff, integral, .. } => {
                let z = 1.0 - u.x * (1.0 - cos_cutoff);
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = TAU * u.y;
                let v = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                let w = self.shape(v) * TAU * (1.0 - cos_cutoff) / integral;
                (v, w)
            }
            BuiltProfile::Table(t) => t.sample(u),
        }
    }

    /// Whether the distribution depends on the azimuth φ (IES tables). A profile that does not
    /// is invariant under rotations about its axis, so any frame with that axis evaluates and
    /// samples it alike; one that does needs a defined φ = 0 direction.
    #[inline]
    pub fn depends_on_azimuth(&self) -> bool {
        matches!(self, BuiltProfile::Table(_))
    }
}

/// ∫ s dω of Mitsuba's spot (linear falloff in angle from β to γ), in closed form:
/// 2π·[1 − (sin γ − sin β)/(γ − β)], and 2π(1 − cos γ) when β = γ.
pub fn spot_integral(cutoff: f64, beam: f64) -> f64 {
    let d = cutoff - beam;
    if d <= 1e-9 {
        return 2.0 * PI64 * (1.0 - cutoff.cos());
    }
    2.0 * PI64 * (1.0 - (cutoff.sin() - beam.sin()) / d)
}

#[cfg(test)]
mod tests {
    use super::super::ies::tests::asymmetric;
    use super::*;
    use crate::bsdf::chi2::Chi2Test;
    use crate::sampling::RandomStream;

    fn profiles() -> Vec<(EmissionProfile, bool)> {
        vec![
            (EmissionProfile::Uniform, false),
            (EmissionProfile::Uniform, true),
            (EmissionProfile::Cosine, true),
            (EmissionProfile::CosinePower { exponent: 12.0 }, true),
            (EmissionProfile::Spot { cutoff_angle: 0.6, beam_width: 0.3 }, false),
            (EmissionProfile::Spot { cutoff_angle: 2.5, beam_width: 2.5 }, false),
            (EmissionProfile::Ies(asymmetric()), false),
            (EmissionProfile::Ies(asymmetric()), true),
        ]
    }

    /// ∫ f_e dω = 1 by brute-force quadrature over the sphere, for every profile.
    #[test]
    fn densities_integrate_to_one() {
        let (nt, np) = (1440, 720);
        for (p, hemi) in profiles() {
            let b = BuiltProfile::build(&p, hemi).unwrap();
            let mut sum = 0.0f64;
            for i in 0..nt {
                let th = (i as f64 + 0.5) / nt as f64 * PI64;
                for j in 0..np {
                    let ph = (j as f64 + 0.5) / np as f64 * 2.0 * PI64;
                    let v = Vec3::new(
                        (th.sin() * ph.cos()) as f32,
                        (th.sin() * ph.sin()) as f32,
                        th.cos() as f32,
                    );
                    sum += b.eval(v) as f64 * th.sin();
                }
            }
            sum *= (PI64 / nt as f64) * (2.0 * PI64 / np as f64);
            assert!((sum - 1.0).abs() < 2e-3, "{p:?} hemisphere={hemi}: ∫f_e = {sum}");
        }
    }

    /// Sampling matches the sampling pdf (χ²), and the weights are f_e/p.
    #[test]
    fn chi2_profile_sampling() {
        for (k, (p, hemi)) in profiles().into_iter().enumerate() {
            let b = BuiltProfile::build(&p, hemi).unwrap();
            Chi2Test::new(Vec3::Z, 900 + k as u64)
                .run(
                    |_, u| {
                        let (v, w) = b.sample(u);
                        let pdf = b.sampling_pdf(v);
                        let expect = b.eval(v) / pdf;
                        assert!(
                            (w - expect).abs() <= 1e-3 * expect.max(1.0),
                            "{p:?}: weight {w} vs {expect}"
                        );
                        Some((v, pdf))
                    },
                    |v| b.sampling_pdf(v),
                )
                .assert_ok(&format!("{p:?} hemisphere={hemi}"));
        }
    }

    /// The mean weight of sampled directions is 1 (the estimator of Φ is exact).
    #[test]
    fn mean_weight_is_one() {
        for (p, hemi) in profiles() {
            let b = BuiltProfile::build(&p, hemi).unwrap();
            let mut rng = RandomStream::new(77, &[]);
            let n = 400_000;
            let (mut s, mut s2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let w = b.sample(rng.next_2d()).1 as f64;
                s += w;
                s2 += w * w;
            }
            let m = s / n as f64;
            let se = ((s2 / n as f64 - m * m).max(0.0) / n as f64).sqrt();
            assert!((m - 1.0).abs() <= 4.0 * se + 1e-4, "{p:?}: mean weight {m} ± {se}");
        }
    }

    #[test]
    fn spot_integral_matches_quadrature() {
        for (g, b) in [(0.6f64, 0.3f64), (1.2, 0.2), (0.35, 0.35), (3.0, 1.0)] {
            let n = 200_000;
            let mut s = 0.0;
            for i in 0..n {
                let th = (i as f64 + 0.5) / n as f64 * PI64;
                let f = if th <= b {
                    1.0
                } else if th < g {
                    (g - th) / (g - b)
                } else {
                    0.0
                };
                s += f * th.sin();
            }
            s *= 2.0 * PI64 * PI64 / n as f64;
            assert!(
                (s / spot_integral(g, b) - 1.0).abs() < 1e-4,
                "γ={g} β={b}: {s} vs {}",
                spot_integral(g, b)
            );
        }
    }

    #[test]
    fn impossible_parameters_are_errors() {
        for p in [
            EmissionProfile::CosinePower { exponent: -1.0 },
            EmissionProfile::CosinePower { exponent: f32::NAN },
            EmissionProfile::Spot { cutoff_angle: 0.0, beam_width: 0.0 },
            EmissionProfile::Spot { cutoff_angle: -0.5, beam_width: 0.1 },
            EmissionProfile::Spot { cutoff_angle: 0.5, beam_width: 0.6 },
            EmissionProfile::Spot { cutoff_angle: f32::NAN, beam_width: 0.1 },
            EmissionProfile::Ies(IesProfile {
                vertical_angles: vec![0.0],
                horizontal_angles: vec![0.0],
                candela: vec![1.0],
            }),
            EmissionProfile::Ies(IesProfile {
                vertical_angles: vec![0.0, 90.0],
                horizontal_angles: vec![0.0],
                candela: vec![1.0],
            }),
            EmissionProfile::Ies(IesProfile {
                vertical_angles: vec![0.0, 90.0],
                horizontal_angles: vec![0.0],
                candela: vec![1.0, -1.0],
            }),
            EmissionProfile::Ies(IesProfile {
                vertical_angles: vec![0.0, 90.0],
                horizontal_angles: vec![0.0],
                candela: vec![0.0, 0.0],
            }),
            EmissionProfile::Ies(IesProfile {
                vertical_angles: vec![90.0, 0.0],
                horizontal_angles: vec![0.0],
                candela: vec![1.0, 1.0],
            }),
            EmissionProfile::Ies(IesProfile {
                vertical_angles: vec![0.0, 90.0],
                horizontal_angles: vec![0.0, 45.0],
                candela: vec![1.0; 4],
            }),
        ] {
            assert!(BuiltProfile::build(&p, false).is_err(), "{p:?}");
        }
        assert!(
            BuiltProfile::build(&EmissionProfile::Spot { cutoff_angle: 2.0, beam_width: 1.0 }, true).is_err()
        );
        // The constructors check what `build` checks, and say which parameter is wrong.
        assert_eq!(
            EmissionProfile::spot(0.5, 0.3),
            Ok(EmissionProfile::Spot { cutoff_angle: 0.5, beam_width: 0.3 })
        );
        assert_eq!(EmissionProfile::spot(0.0, 0.0), Err(ProfileError::Cutoff { cutoff: 0.0, max: PI }));
        assert_eq!(EmissionProfile::spot(0.5, 0.6), Err(ProfileError::Beam { beam: 0.6, cutoff: 0.5 }));
        assert!(EmissionProfile::spot(4.0, 1.0).unwrap_err().to_string().contains("cutoff angle"));
        assert_eq!(EmissionProfile::cosine_power(4.0), Ok(EmissionProfile::CosinePower { exponent: 4.0 }));
        assert_eq!(EmissionProfile::cosine_power(-1.0), Err(ProfileError::Exponent(-1.0)));
    }
}
