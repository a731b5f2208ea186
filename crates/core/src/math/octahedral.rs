//! Octahedral encoding of unit vectors into 32 bits (2 × 16-bit snorm), as in psychopath and
//! Cigolle et al. 2014, "A Survey of Efficient Representations for Independent Unit Vectors".
//! Worst-case angular error is about 0.003°, far below anything a BRDF evaluation can see.

use glam::{Vec2, Vec3};

#[inline]
fn sign_not_zero(v: f32) -> f32 {
    if v >= 0.0 { 1.0 } else { -1.0 }
}

/// Encodes a unit vector into 32 bits.
#[inline]
pub fn encode_unit_vector(v: Vec3) -> u32 {
    let l1 = v.x.abs() + v.y.abs() + v.z.abs();
    let mut p = Vec2::new(v.x, v.y) / l1;
    if v.z < 0.0 {
        p = Vec2::new((1.0 - p.y.abs()) * sign_not_zero(p.x), (1.0 - p.x.abs()) * sign_not_zero(p.y));
    }
    let q = |x: f32| (round_half_away(x.clamp(-1.0, 1.0) * 32767.0) as i16) as u16 as u32;
    q(p.x) | (q(p.y) << 16)
}

/// `x.round() as i32` for |x| ≤ 32767 (and NaN, which gives 0 either way), without the call
/// to `roundf` that baseline x86-64 (no SSE4.1 `roundss`) makes of `f32::round`: the
/// truncation and the fraction x − trunc(x) are exact at this magnitude, and a fraction of at
/// least one half rounds away from zero, as `round` does. Every stored direction is encoded
/// once in the tracer's hot loop.
#[inline(always)]
fn round_half_away(x: f32) -> i32 {
    let t = x as i32;
    let f = x - t as f32;
    t + i32::from(f >= 0.5) - i32::from(f <= -0.5)
}

/// Decodes a vector encoded by [`encode_unit_vector`]; the result is normalised.
#[inline]
pub fn decode_unit_vector(bits: u32) -> Vec3 {
    let x = (bits as u16 as i16) as f32 / 32767.0;
    let y = ((bits >> 16) as u16 as i16) as f32 / 32767.0;
    let z = 1.0 - x.abs() - y.abs();
    let t = (-z).max(0.0);
    let x = x + if x >= 0.0 { -t } else { t };
    let y = y + if y >= 0.0 { -t } else { t };
    Vec3::new(x, y, z).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_error_is_tiny_everywhere() {
        // Angles from atan2(|a×b|, a·b) in f64: acos of an f32 dot product cannot resolve 0.003°.
        let angle = |a: Vec3, b: Vec3| {
            let (a, b) = (a.as_dvec3(), b.as_dvec3());
            a.cross(b).length().atan2(a.dot(b)).to_degrees()
        };
        let mut worst = 0.0f64;
        let n = 200;
        for i in 0..n {
            for j in 0..n {
                let z = -1.0 + 2.0 * (i as f32 + 0.5) / n as f32;
                let phi = std::f32::consts::TAU * (j as f32 + 0.37) / n as f32;
                let r = (1.0 - z * z).sqrt();
                let v = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                worst = worst.max(angle(decode_unit_vector(encode_unit_vector(v)), v));
            }
        }
        for v in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
            worst = worst.max(angle(decode_unit_vector(encode_unit_vector(v)), v));
        }
        assert!(worst < 0.01, "worst angular error {worst}°");
    }

    /// The rounding the encoder uses is `f32::round` on its whole range: at every integer and
    /// every half from −32768 to 32768 and the floats on either side of them (where rounding
    /// can go wrong), at zero's neighbours, and at a million floats in between.
    #[test]
    fn rounding_is_f32_round_on_the_whole_range() {
        let check = |x: f32| assert_eq!(round_half_away(x), x.round() as i32, "x = {x:e}");
        let near = |x: f32| [x, x.next_up(), x.next_down()];
        for k in -32768..=32768 {
            for x in [k as f32, k as f32 + 0.5].into_iter().flat_map(near) {
                check(x);
            }
        }
        [0.0, -0.0, f32::MIN_POSITIVE, -f32::MIN_POSITIVE, 1e-30, -1e-30].into_iter().for_each(check);
        let mut rng = crate::sampling::RandomStream::new(5, &[8]);
        for _ in 0..1_000_000 {
            check((rng.next_f32() * 2.0 - 1.0) * 32768.0);
        }
        assert_eq!(round_half_away(f32::NAN), f32::NAN.round() as i32);
    }
}
