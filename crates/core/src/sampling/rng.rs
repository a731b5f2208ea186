//! Seeded random streams. Every block of light paths gets its own PCG32 stream, derived from
//! (seed, light, block) alone, so a dataset does not depend on how many threads traced it.

use glam::Vec2;
use rand_core::Rng;
use rand_pcg::Pcg32;

/// A deterministic stream of uniform random numbers in [0, 1).
#[derive(Clone, Debug)]
pub struct RandomStream {
    rng: Pcg32,
}

/// SplitMix64 finaliser: decorrelates the key words that name a stream (and the bits of the
/// values hashed where a decision must follow from its inputs alone: a splat's aperture point,
/// a masked surface's pass).
#[inline]
pub(crate) fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A uniform number in [0, 1) from the top 24 bits of a hash (every float of that grid exact).
#[inline]
pub(crate) fn unit_from_hash(h: u64) -> f32 {
    (h >> 40) as f32 * (1.0 / 16_777_216.0)
}

impl RandomStream {
    /// The stream named by a seed and a key (e.g. the light index and the block index).
    /// Distinct keys give independent PCG streams.
    pub fn new(seed: u64, key: &[u64]) -> Self {
        let mut state = mix(seed ^ 0x6f70_7469_636b_7321);
        let mut stream = mix(seed.wrapping_add(0x9e37_79b9_7f4a_7c15));
        for &k in key {
            state = mix(state ^ mix(k.wrapping_add(0x632b_e59b_d9b4_e019)));
            stream = mix(stream.wrapping_add(k).wrapping_mul(0x9e37_79b9_7f4a_7c15));
        }
        RandomStream { rng: Pcg32::new(state, stream) }
    }

    /// A uniform number in [0, 1) with 24 random bits (never returns 1.0).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        (self.rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Two uniform numbers in [0, 1)².
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        Vec2::new(self.next_f32(), self.next_f32())
    }

    /// A uniform 64-bit integer.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        ((self.rng.next_u32() as u64) << 32) | self.rng.next_u32() as u64
    }

    /// A uniform number in [0, 1) with 53 random bits (never returns 1.0).
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let a: Vec<f32> = (0..8).scan(RandomStream::new(7, &[1, 2]), |s, _| Some(s.next_f32())).collect();
        let b: Vec<f32> = (0..8).scan(RandomStream::new(7, &[1, 2]), |s, _| Some(s.next_f32())).collect();
        let c: Vec<f32> = (0..8).scan(RandomStream::new(7, &[1, 3]), |s, _| Some(s.next_f32())).collect();
        let d: Vec<f32> = (0..8).scan(RandomStream::new(8, &[1, 2]), |s, _| Some(s.next_f32())).collect();
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_ne!(a, d);
    }

    #[test]
    fn uniform_mean_and_range() {
        let mut s = RandomStream::new(1, &[]);
        let n = 200_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let x = s.next_f32();
            assert!((0.0..1.0).contains(&x));
            sum += x as f64;
        }
        let mean = sum / n as f64;
        // σ of the mean is sqrt(1/12/n) ≈ 6.5e-4; 5σ bound.
        assert!((mean - 0.5).abs() < 3.3e-3, "mean {mean}");
    }
}
