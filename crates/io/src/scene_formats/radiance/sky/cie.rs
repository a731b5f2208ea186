//! The CIE general skies (ISO 15469:2004 / CIE S 011/E:2003) and the Perez all-weather sky as
//! relative luminance distributions, for front ends that describe a sky by its model (Mitsuba
//! XML's `<emitter type="ciesky">`, through `ciesky.rs`): Radiance's own files reach skies only
//! through `!gensky` and `!gendaylit`, and no Radiance syntax is invented for these.
//!
//! A general sky's luminance relative to the zenith's is L/L_z = f(χ)·φ(Z) / (f(Z_s)·φ(0)):
//! gradation φ(Z) = 1 + a·exp(b/cos Z) (φ = 1 at the horizon), indicatrix
//! f(χ) = 1 + c·(exp(dχ) − exp(dπ/2)) + e·cos²χ, Z the element's zenith angle, χ its angle from
//! the sun, Z_s the sun's zenith angle; a–e per type from the standard's Table 1.

use super::perez::{perez_parameters, perez_relative};
use glam::DVec3;
use std::f64::consts::PI;

/// The standard's Table 1: gradation a, b and indicatrix c, d, e of types 1–15.
#[rustfmt::skip]
const TYPES: [[f64; 5]; 15] = [
    [4.0, -0.70, 0.0, -1.0, 0.00],   // 1 overcast, steep gradation, azimuthal uniformity
    [4.0, -0.70, 2.0, -1.5, 0.15],   // 2 overcast, steep, slight brightening toward the sun
    [1.1, -0.80, 0.0, -1.0, 0.00],   // 3 overcast, moderate gradation, azimuthal uniformity
    [1.1, -0.80, 2.0, -1.5, 0.15],   // 4 overcast, moderate, slight brightening toward the sun
    [0.0, -1.00, 0.0, -1.0, 0.00],   // 5 sky of uniform luminance
    [0.0, -1.00, 2.0, -1.5, 0.15],   // 6 partly cloudy, no gradation, slight brightening
    [0.0, -1.00, 5.0, -2.5, 0.30],   // 7 partly cloudy, no gradation, brighter circumsolar region
    [0.0, -1.00, 10.0, -3.0, 0.45],  // 8 partly cloudy, no gradation, distinct solar corona
    [-1.0, -0.55, 2.0, -1.5, 0.15],  // 9 partly cloudy, obscured sun
    [-1.0, -0.55, 5.0, -2.5, 0.30],  // 10 partly cloudy, brighter circumsolar region
    [-1.0, -0.55, 10.0, -3.0, 0.45], // 11 white-blue sky, distinct solar corona
    [-1.0, -0.32, 10.0, -3.0, 0.45], // 12 CIE standard clear sky, low turbidity
    [-1.0, -0.32, 16.0, -3.0, 0.30], // 13 CIE standard clear sky, polluted atmosphere
    [-1.0, -0.15, 16.0, -3.0, 0.30], // 14 cloudless turbid sky, broad solar corona
    [-1.0, -0.15, 24.0, -2.8, 0.15], // 15 white-blue turbid sky, broad solar corona
];

/// One of the 15 CIE general skies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CieGeneralSky(u8);

impl CieGeneralSky {
    /// Type `n`, 1–15 (None otherwise).
    pub fn new(n: u8) -> Option<Self> {
        (1..=15).contains(&n).then_some(CieGeneralSky(n))
    }

    /// The type's number.
    pub fn number(self) -> u8 {
        self.0
    }

    /// The type's (a, b, c, d, e).
    pub fn parameters(self) -> [f64; 5] {
        TYPES[self.0 as usize - 1]
    }

    /// Gradation φ at zenith angle `z` (radians; 1 at and below the horizon).
    pub fn gradation(self, z: f64) -> f64 {
        let [a, b, ..] = self.parameters();
        let cos_z = z.cos();
        if cos_z <= 0.0 { 1.0 } else { 1.0 + a * (b / cos_z).exp() }
    }

    /// Scattering indicatrix f at angle `chi` from the sun (radians).
    pub fn indicatrix(self, chi: f64) -> f64 {
        let [_, _, c, d, e] = self.parameters();
        1.0 + c * ((d * chi).exp() - (d * PI / 2.0).exp()) + e * chi.cos().powi(2)
    }
}

/// A sky's relative luminance distribution, with the sun at a direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SkyModel {
    /// A CIE general sky.
    CieGeneral(CieGeneralSky),
    /// The Perez all-weather sky of clearness ε ∈ [1, 12) and brightness Δ (gendaylit's).
    Perez {
        /// ε.
        epsilon: f64,
        /// Δ.
        delta: f64,
    },
}

impl SkyModel {
    /// L/L_z toward `d` (unit, z up) with the sun toward `sun` (unit, above the horizon):
    /// 1 at the zenith, 0 below the horizon.
    pub fn relative_luminance(&self, d: DVec3, sun: DVec3) -> f64 {
        if d.z <= 0.0 {
            return 0.0;
        }
        let z = d.z.clamp(-1.0, 1.0).acos();
        let zs = sun.z.clamp(-1.0, 1.0).acos();
        let chi = d.dot(sun).clamp(-1.0, 1.0).acos();
        match *self {
            SkyModel::CieGeneral(t) => {
                t.indicatrix(chi) * t.gradation(z) / (t.indicatrix(zs) * t.gradation(0.0))
            }
            SkyModel::Perez { epsilon, delta } => {
                let c = perez_parameters(epsilon, delta, zs);
                perez_relative(&c, z, chi) / perez_relative(&c, 0.0, zs)
            }
        }
    }

    /// ∫ L/L_z cos θ dω over the sky (sr): the horizontal illuminance of a unit zenith
    /// luminance, by the midpoint rule on an `n` × 4`n` grid in (cos θ, φ).
    pub fn horizontal_integral(&self, sun: DVec3, n: usize) -> f64 {
        let mut sum = 0.0;
        for i in 0..n {
            let mu = (i as f64 + 0.5) / n as f64;
            let s = (1.0 - mu * mu).sqrt();
            for j in 0..4 * n {
                let phi = 2.0 * PI * (j as f64 + 0.5) / (4 * n) as f64;
                sum += self.relative_luminance(DVec3::new(s * phi.cos(), s * phi.sin(), mu), sun) * mu;
            }
        }
        sum * 2.0 * PI / (4 * n * n) as f64
    }

    /// The zenith luminance (or radiance) for a horizontal diffuse illuminance (or irradiance)
    /// `horizontal` with the sun toward `sun`.
    pub fn zenith_for(&self, horizontal: f64, sun: DVec3) -> f64 {
        horizontal / self.horizontal_integral(sun, 256)
    }
}
