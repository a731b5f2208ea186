//! Image comparison with the project's metric, reproducing `imgcmp.py` (the project's image
//! comparison tool, kept outside this repository; the tests here pin values it computed).
//!
//! Both images are interleaved linear RGB `f32` buffers of the same size (three channels: drop
//! alpha and broadcast grey images to RGB before calling, as `imgcmp.py` does when loading).
//! Arithmetic is in `f64`, as `imgcmp.py` loads every image as float64; sums are compensated
//! (Neumaier), so the results agree with numpy's pairwise sums to about 1e-15 relative.

/// The constant added to `r^2` in the relMSE denominator (`EPS` in `imgcmp.py`).
pub const RELMSE_EPS: f64 = 1e-2;

/// Result of [`compare`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    /// Relative mean squared error of the test image against the reference:
    ///
    /// `relMSE = mean over all pixels p and channels c of (t[p,c] - r[p,c])^2 / (r[p,c]^2 + 1e-2)`
    ///
    /// (`t` test, `r` reference, linear values, every pixel and channel weighted equally; the
    /// `1e-2` keeps dark reference pixels from dominating). Exactly `imgcmp.py`'s `relmse=`
    /// line. 0 for identical images; NaN if the test image holds a NaN or infinity (so compare
    /// with `is_finite()` before applying a threshold, as `imgcmp.py` does). For an unbiased
    /// Monte-Carlo render it falls as 1/samples.
    pub relmse: f64,
    /// Mean of each channel (R, G, B) of the test image.
    pub mean_test: [f64; 3],
    /// Mean of each channel (R, G, B) of the reference image.
    pub mean_ref: [f64; 3],
    /// `mean_test / mean_ref` per channel (inf or NaN where the reference mean is 0, like
    /// numpy's division). An unbiased estimator gives 1 up to noise.
    pub mean_ratio: [f64; 3],
}

/// Compares `test` against `reference`, both interleaved RGB (`[r, g, b, r, g, b, ...]`) of
/// the same number of pixels; see [`Comparison`] for the quantities.
///
/// # Panics
/// If the lengths differ, are not a multiple of 3, or are 0.
pub fn compare(test: &[f32], reference: &[f32]) -> Comparison {
    assert_eq!(
        test.len(),
        reference.len(),
        "compare: image sizes differ ({} vs {} values)",
        test.len(),
        reference.len()
    );
    assert!(
        !test.is_empty() && test.len().is_multiple_of(3),
        "compare: buffer length {} is not a positive multiple of 3 (interleaved RGB)",
        test.len()
    );
    let pixels = (test.len() / 3) as f64;
    let mut err = Sum::default();
    let mut st = [Sum::default(); 3];
    let mut sr = [Sum::default(); 3];
    for (t, r) in test.chunks_exact(3).zip(reference.chunks_exact(3)) {
        for c in 0..3 {
            let (t, r) = (t[c] as f64, r[c] as f64);
            let d = t - r;
            err.add(d * d / (r * r + RELMSE_EPS));
            st[c].add(t);
            sr[c].add(r);
        }
    }
    let mean_test = st.map(|s| s.value() / pixels);
    let mean_ref = sr.map(|s| s.value() / pixels);
    Comparison {
        relmse: err.value() / (test.len() as f64),
        mean_test,
        mean_ref,
        mean_ratio: [0, 1, 2].map(|c| mean_test[c] / mean_ref[c]),
    }
}

/// Neumaier compensated sum.
#[derive(Clone, Copy, Default)]
struct Sum {
    sum: f64,
    comp: f64,
}

impl Sum {
    fn add(&mut self, x: f64) {
        let t = self.sum + x;
        if self.sum.abs() >= x.abs() {
            self.comp += (self.sum - t) + x;
        } else {
            self.comp += (x - t) + self.sum;
        }
        self.sum = t;
    }

    fn value(self) -> f64 {
        // Non-finite sums: the compensation is meaningless (inf - inf = NaN).
        if self.sum.is_finite() { self.sum + self.comp } else { self.sum }
    }
}

#[cfg(test)]
mod tests {
    //! Expected values were computed independently of this code, with numpy 2.4.6 through
    //! `imgcmp.py`'s own `relmse()` on the same inputs (given as float32, widened to float64 as
    //! `imgcmp.py` loads images), and are committed here; the decimal hand calculations beside
    //! them say where they come from.
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1e-300)
    }

    #[test]
    fn identical_images_have_zero_error() {
        let img = [0.1, 0.2, 0.3, 4.0, 5.0, 6.0];
        let c = compare(&img, &img);
        assert_eq!(c.relmse, 0.0);
        assert_eq!(c.mean_ratio, [1.0; 3]);
    }

    #[test]
    fn hand_computed_two_pixels() {
        // Pixel 0: t = (1, 0, 0.5), r = (1, 0.1, 0)   -> terms 0, 0.01/0.02 = 0.5, 0.25/0.01 = 25
        // Pixel 1: t = (3, 2, 1),   r = (2, 2, 0.9)   -> terms 1/4.01, 0, 0.01/0.82
        let test = [1.0, 0.0, 0.5, 3.0, 2.0, 1.0];
        let reference = [1.0, 0.1, 0.0, 2.0, 2.0, 0.9];
        let c = compare(&test, &reference);
        // numpy (module docs); with decimal arithmetic (0 + 0.5 + 25 + 1/4.01 + 0 + 0.01/0.82) / 6,
        // which differs only by 0.1 and 0.9 not being float32 numbers.
        assert!(close(c.relmse, 4.29359528240977), "{}", c.relmse);
        assert!((c.relmse - (25.5 + 1.0 / 4.01 + 0.01 / 0.82) / 6.0).abs() < 1e-7);
        for (got, want) in [
            (c.mean_test, [2.0, 1.0, 0.75]),
            (c.mean_ref, [1.5, 1.050000000745058, 0.44999998807907104]),
            (c.mean_ratio, [1.3333333333333333, 0.9523809517051628, 1.6666667108182565]),
        ] {
            for ch in 0..3 {
                assert!(close(got[ch], want[ch]), "{got:?} vs {want:?}");
            }
        }
    }

    #[test]
    fn single_pixel_black_reference() {
        // r = 0 everywhere: relMSE = mean(t^2) / 0.01 = (0.01 + 0.04 + 0.09) / 0.03 = 14/3 in
        // decimals; numpy on the float32 inputs: 4.6666669547557875. Mean ratio infinite.
        let c = compare(&[0.1, 0.2, 0.3], &[0.0, 0.0, 0.0]);
        assert!(close(c.relmse, 4.6666669547557875), "{}", c.relmse);
        assert!((c.relmse - 14.0 / 3.0).abs() < 1e-6);
        assert!(c.mean_ratio.iter().all(|r| r.is_infinite()));
    }

    #[test]
    fn uniform_scale_error() {
        // t = 1.1 r with r = 1 everywhere: each term 0.1² / 1.01 = 0.00990099… in decimals;
        // numpy on float32 1.1: 0.009900994820170445.
        let reference = vec![1.0f32; 3 * 50];
        let test: Vec<f32> = reference.iter().map(|r| r * 1.1).collect();
        let c = compare(&test, &reference);
        assert!(close(c.relmse, 0.009900994820170445), "{}", c.relmse);
        assert!(close(c.mean_ratio[1], 1.100000023841858));
    }

    #[test]
    fn nan_in_test_gives_nan() {
        let c = compare(&[f32::NAN, 0.0, 0.0], &[1.0, 1.0, 1.0]);
        assert!(c.relmse.is_nan());
        let c = compare(&[f32::INFINITY, 0.0, 0.0], &[1.0, 1.0, 1.0]);
        assert!(!c.relmse.is_finite());
    }

    #[test]
    #[should_panic(expected = "sizes differ")]
    fn size_mismatch_panics() {
        compare(&[0.0; 3], &[0.0; 6]);
    }
}
