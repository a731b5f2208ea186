//! Tests of the raster: each filter's sampling density against its normalised closed form (a χ²
//! test, and one that must fail for a wrong sampler), the gaussian's inverse CDF, the splat
//! weights' sums, footprints clipped to the crop window, and the refusal of bad crops and filters.

use super::*;
use crate::sampling::RandomStream;

fn raster(filter: Filter) -> Raster {
    Raster::new(40, 30, FilmSpec { crop: None, filter }).unwrap()
}

const FILTERS: [Filter; 5] = [
    Filter::Box,
    Filter::Tent { radius: 1.0 },
    Filter::Tent { radius: 1.7 },
    Filter::Gaussian { stddev: 0.5 },
    Filter::Gaussian { stddev: 0.9 },
];

/// Each axis of a filter's samples is distributed as its normalised filter: a χ² test of a
/// histogram against the filter integrated over each bin (Simpson's rule on the closed form).
#[test]
fn sampling_density_is_the_normalised_filter() {
    let mut rng = RandomStream::new(11, &[]);
    for filter in FILTERS {
        let ras = raster(filter);
        let (r, bins, n) = (filter.radius(), 40usize, 200_000usize);
        let mut hist = vec![0usize; bins];
        for _ in 0..n {
            let d = filter.sample(rng.next_2d());
            for x in [d.x, d.y] {
                assert!(x.abs() <= r, "{filter:?}: {x}");
                hist[(((x + r) / (2.0 * r) * bins as f32) as usize).min(bins - 1)] += 1;
            }
        }
        let width = 2.0 * r / bins as f32;
        let mut chi2 = 0.0;
        let mut total_p = 0.0;
        for (b, &count) in hist.iter().enumerate() {
            let a = -r + b as f32 * width;
            let steps = 64;
            let h = width / steps as f32;
            let mut p = 0.0;
            for k in 0..=steps {
                let c = if k == 0 || k == steps {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                p += c * ras.weight_1d(a + k as f32 * h) as f64;
            }
            let p = p * h as f64 / 3.0;
            total_p += p;
            let expected = p * 2.0 * n as f64;
            chi2 += (count as f64 - expected).powi(2) / expected;
        }
        assert!((total_p - 1.0).abs() < 1e-3, "{filter:?}: the normalised filter integrates to {total_p}");
        // 39 degrees of freedom: mean 39, standard deviation 8.8.
        assert!(chi2 < 39.0 + 5.0 * 8.8, "{filter:?}: χ² = {chi2}");
    }
}

/// A shifted filter fails the same test: the χ² test above can fail.
#[test]
fn the_density_test_sees_a_wrong_sampler() {
    let ras = raster(Filter::Gaussian { stddev: 0.5 });
    let mut rng = RandomStream::new(3, &[]);
    let (bins, n, r) = (40usize, 100_000usize, 2.0f32);
    let mut hist = vec![0usize; bins];
    for _ in 0..n {
        // The stddev-0.6 gaussian's samples, tested against the stddev-0.5 one.
        let x = Filter::Gaussian { stddev: 0.6 }.sample(rng.next_2d()).x.clamp(-r, r - 1e-6);
        hist[((x + r) / (2.0 * r) * bins as f32) as usize] += 1;
    }
    let width = 2.0 * r / bins as f32;
    let chi2: f64 = (0..bins)
        .map(|b| {
            let mid = -r + (b as f32 + 0.5) * width;
            let expected = (ras.weight_1d(mid) * width) as f64 * n as f64;
            (hist[b] as f64 - expected).powi(2) / expected.max(1.0)
        })
        .sum();
    assert!(chi2 > 39.0 + 5.0 * 8.8, "χ² = {chi2}");
}

/// The inverse CDF of the truncated gaussian inverts its closed-form CDF.
#[test]
fn gaussian_inverse_cdf_inverts_the_cdf() {
    for stddev in [0.3f64, 0.5, 2.0] {
        let total = gaussian_cdf_unnormalised(stddev, 4.0 * stddev);
        for u in [0.0, 1e-6, 0.1, 0.5, 0.77, 0.999_999] {
            let x = gaussian_inverse_cdf(stddev, u);
            let back = gaussian_cdf_unnormalised(stddev, x) / total;
            assert!((back - u).abs() < 1e-9, "σ {stddev}, u {u}: x {x}, F(x) {back}");
        }
        assert!(gaussian_inverse_cdf(stddev, 0.5).abs() < 1e-9);
    }
}

/// The splat weights of one point, away from the border: they sum to one exactly for the box and
/// the tent of radius 1 (partitions of unity); for the others to one on average over the point's
/// position in its pixel (∫₀¹ Σ_p f̂(s − c_p) ds = ∫ f̂ = 1) and within their ripple at any
/// one point (gaussian σ ½: 1.5 %). The 2-D footprint's sum is the product of the axes'.
#[test]
fn splat_weights_sum_to_one() {
    for filter in FILTERS {
        let ras = raster(filter);
        let ripple = match filter {
            Filter::Box | Filter::Tent { radius: 1.0 } => 1e-5,
            Filter::Gaussian { stddev: 0.5 } => 0.015,
            _ => 0.08,
        };
        // The weights along one axis of a point at film coordinate x (pixels): pixel centres
        // within the radius (at most 34 of them either side).
        let axis_sum = |x: f32| -> f64 {
            let centres = (-40..40).map(|k| (x.floor() + k as f32) + 0.5);
            centres.map(|c| ras.weight_1d(x - c) as f64).sum()
        };
        let (mut mean, n) = (0.0f64, 1000);
        for k in 0..n {
            let x = 20.0 + (k as f32 + 0.5) / n as f32;
            let sum = axis_sum(x);
            assert!((sum - 1.0).abs() < ripple, "{filter:?} at {x}: {sum}");
            mean += sum / n as f64;
        }
        assert!((mean - 1.0).abs() < 1e-4, "{filter:?}: mean sum {mean}");
        for (fx, fy) in [(20.0f32, 15.0f32), (20.3, 15.77), (21.9, 14.05)] {
            let fp = ras.footprint(fx / 40.0, fy / 30.0).unwrap();
            let mut sum = 0.0f64;
            fp.for_each(|_, w| sum += w as f64);
            let expected = axis_sum(fx) * axis_sum(fy);
            assert!((sum - expected).abs() < 1e-5, "{filter:?} at ({fx}, {fy}): {sum} vs {expected}");
        }
    }
}

/// A footprint holds exactly the window's pixels within the radius, indexed in the window.
#[test]
fn footprints_are_clipped_to_the_window() {
    let spec = FilmSpec {
        crop: Some(Crop { x: 10, y: 5, width: 6, height: 4 }),
        filter: Filter::Gaussian { stddev: 0.5 },
    };
    let ras = Raster::new(40, 30, spec).unwrap();
    assert_eq!((ras.width(), ras.height()), (6, 4));
    // Film pixel (10, 5) is the window's first; a point at its top-left corner reaches only it
    // and its window neighbours to the right and below.
    let fp = ras.footprint(10.0 / 40.0, 5.0 / 30.0).unwrap();
    let mut pixels = Vec::new();
    fp.for_each(|p, w| {
        assert!(w > 0.0);
        pixels.push(p)
    });
    assert_eq!(pixels, vec![0, 1, 6, 7]);
    // Beyond the window's reach: nothing; just outside it, its edge.
    assert!(ras.footprint(7.0 / 40.0, 6.0 / 30.0).is_none());
    assert!(ras.footprint(9.9 / 40.0, 6.5 / 30.0).is_some());
    assert!(ras.footprint(f32::NAN, 0.5).is_none());
    // Box pixels in the window.
    assert_eq!(ras.box_pixel(10.5 / 40.0, 5.5 / 30.0), Some(0));
    assert_eq!(ras.box_pixel(15.5 / 40.0, 8.5 / 30.0), Some(23));
    assert_eq!(ras.box_pixel(16.5 / 40.0, 8.5 / 30.0), None);
    assert_eq!(ras.film_point(0, 0, Vec2::ZERO), (10.5 / 40.0, 5.5 / 30.0));
}

#[test]
fn bad_crops_and_filters_are_refused() {
    let crop =
        |x, y, width, height| FilmSpec { crop: Some(Crop { x, y, width, height }), filter: Filter::Box };
    assert!(Raster::new(40, 30, crop(0, 0, 40, 30)).is_ok());
    for bad in [crop(1, 0, 40, 30), crop(0, 0, 0, 30), crop(39, 29, 2, 1), crop(u32::MAX, 0, 2, 2)] {
        assert!(matches!(Raster::new(40, 30, bad), Err(CameraError::Crop { .. })), "{bad:?}");
    }
    for f in [
        Filter::Gaussian { stddev: f32::NAN },
        Filter::Gaussian { stddev: -1.0 },
        Filter::Gaussian { stddev: f32::INFINITY },
        Filter::Tent { radius: 0.0 },
        Filter::Tent { radius: 100.0 },
    ] {
        let spec = FilmSpec { crop: None, filter: f };
        assert!(matches!(Raster::new(40, 30, spec), Err(CameraError::Filter(_))), "{f:?}");
    }
}
