//! How a scene's RGB radiometric values become photometric ones: a luminous efficacy (lm/W)
//! times a weighted sum of the channels. The rule belongs to the scene description, because it
//! is the scene's format that says what its RGB numbers mean: Radiance's "visible watts" are
//! defined against 179 lm/W and Radiance's own primaries, the other formats here are read as
//! Rec. 709 linear RGB with the 555 nm efficacy. A meter's E_v column, its standard error and
//! the daylight factor's E_v,h all use the rule of the scene measured (so DF stays a ratio of
//! like quantities). It is not part of the dataset file: it comes from the scene, which every
//! use of a dataset loads.

use crate::light::LUMENS_PER_WATT;

/// A photometric rule: E_v = efficacy × (w_R·R + w_G·G + w_B·B).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Photometry {
    /// Luminous efficacy of the channels' white, lm/W.
    pub efficacy: f64,
    /// Weights of R, G, B in the luminance (summing to 1: white RGB (1, 1, 1) W is `efficacy` lm).
    pub weights: [f64; 3],
    /// The rule in words, for summaries ("683 lm/W, Rec. 709 weights").
    pub name: &'static str,
}

impl Photometry {
    /// The rule for every format but Radiance's: 683 lm/W (the efficacy at 555 nm) times the
    /// Rec. 709 luminance weights 0.2126, 0.7152, 0.0722 — an approximation, exact only if the
    /// channels were radiometric quantities with the spectral shapes the weights assume.
    pub const REC709_683: Photometry = Photometry {
        efficacy: LUMENS_PER_WATT as f64,
        weights: [0.2126, 0.7152, 0.0722],
        name: "683 lm/W, Rec. 709 weights",
    };

    /// Radiance's rule, for scenes read from `.rad`: `luminance(col) = WHTEFFICACY ·
    /// bright(col)` with WHTEFFICACY = 179 lm/W (equal-energy white over 380–780 nm) and
    /// bright's weights CIE_rf, CIE_gf, CIE_bf, which Radiance's `src/common/color.h` (2.38,
    /// Radiance 6) computes from its default primaries R (0.640, 0.330), G (0.290, 0.600),
    /// B (0.150, 0.060) and white (1/3, 1/3): 0.2651058, 0.6701058, 0.0647884 (the file's
    /// comment still quotes .265074126, .670114631, .064811243, the values for the white
    /// (0.3333, 0.3333) of older versions: 10⁻⁴ apart). What Radiance's users compute from
    /// `rtrace -I` irradiances as lux: `rcalc -e '$1=179*(.265*$1+.670*$2+.065*$3)'`.
    pub const RADIANCE: Photometry = Photometry {
        efficacy: 179.0,
        weights: [0.26510582010582007, 0.67010582010582, 0.06478835978835978],
        name: "Radiance's 179 lm/W",
    };

    /// The illuminance (lux) of an RGB irradiance (W/m²), or the luminance of a radiance.
    #[inline]
    pub fn lux(&self, e: [f64; 3]) -> f64 {
        let w = self.weights;
        self.efficacy * (w[0] * e[0] + w[1] * e[1] + w[2] * e[2])
    }
}

impl Default for Photometry {
    /// [`Photometry::REC709_683`].
    fn default() -> Self {
        Photometry::REC709_683
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_light_reads_the_efficacy() {
        assert_eq!(Photometry::default(), Photometry::REC709_683);
        for (p, lm) in [(Photometry::REC709_683, 683.0), (Photometry::RADIANCE, 179.0)] {
            assert!((p.lux([2.0; 3]) / (2.0 * lm) - 1.0).abs() < 1e-8, "{}", p.name);
        }
        // The default rule is the formula the meter's lux had before rules were the scene's, bit
        // for bit, so the other formats' E_v columns are unchanged.
        let mut rng = crate::sampling::RandomStream::new(5, &[]);
        for _ in 0..1000 {
            let e = [0; 3].map(|_| f64::from(rng.next_f32()) * 1e3);
            let before = f64::from(LUMENS_PER_WATT) * (0.2126 * e[0] + 0.7152 * e[1] + 0.0722 * e[2]);
            assert_eq!(Photometry::REC709_683.lux(e).to_bits(), before.to_bits());
        }
        // Radiance's weights from its primaries (color.h's CIE_D, CIE_C_*D and CIE_*f macros).
        let (xr, yr, xg, yg, xb, yb, xw, yw) =
            (0.640, 0.330, 0.290, 0.600, 0.150, 0.060, 1.0 / 3.0, 1.0 / 3.0);
        let d = xr * (yg - yb) + xg * (yb - yr) + xb * (yr - yg);
        let cr = (xw * (yg - yb) - yw * (xg - xb) + xg * yb - xb * yg) / yw;
        let cg = (xw * (yb - yr) - yw * (xb - xr) - xr * yb + xb * yr) / yw;
        let cb = (xw * (yr - yg) - yw * (xr - xg) + xr * yg - xg * yr) / yw;
        let w = [yr * cr / d, yg * cg / d, yb * cb / d];
        assert_eq!(w, Photometry::RADIANCE.weights);
    }
}
