//! Orthonormal frames: world ↔ local shading coordinates (z = normal).

use glam::Vec3;

/// An orthonormal basis with `n` as its z axis. BSDFs work in this local frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Local x axis.
    pub s: Vec3,
    /// Local y axis.
    pub t: Vec3,
    /// Local z axis (the normal).
    pub n: Vec3,
}

impl Frame {
    /// A frame around the unit vector `n` (branchless construction of Duff et al. 2017,
    /// "Building an Orthonormal Basis, Revisited").
    #[inline]
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Frame { s, t, n }
    }

    /// The frame around the unit vector `n` whose x axis is the unit vector `s` (orthogonal to
    /// `n`), y = n × s: Mitsuba's shading frame from ∂p/∂u (`initialize_sh_frame`), which
    /// orients anisotropic BSDFs. Right-handed like [`Frame::from_normal`], and the frame of
    /// −n with the same `s` is (s, −t, −n) exactly (negation is exact), as there.
    #[inline]
    pub fn with_tangent(n: Vec3, s: Vec3) -> Self {
        Frame { s, t: n.cross(s), n }
    }

    /// World direction → local coordinates.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local coordinates → world direction.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal_and_invertible() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.3, -0.4, 0.866).normalize(),
            Vec3::new(1e-7, 0.0, -1.0).normalize(),
        ] {
            let f = Frame::from_normal(n);
            assert!((f.s.length() - 1.0).abs() < 1e-5 && (f.t.length() - 1.0).abs() < 1e-5);
            assert!(f.s.dot(f.t).abs() < 1e-5 && f.s.dot(f.n).abs() < 1e-5 && f.t.dot(f.n).abs() < 1e-5);
            assert!(f.s.cross(f.t).dot(f.n) > 0.999, "right-handed");
            let v = Vec3::new(0.2, 0.5, -0.7);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-5);
        }
    }

    /// A tangent frame is right-handed like `from_normal`'s, and the frame of −n with the same
    /// tangent is (s, −t, −n) exactly: the flip `ShadingPoint` applies to local coordinates.
    #[test]
    fn tangent_frames_are_right_handed_and_flip_exactly() {
        let n = Vec3::new(0.3, -0.4, 0.866).normalize();
        let s = (Vec3::X - n * n.dot(Vec3::X)).normalize();
        let f = Frame::with_tangent(n, s);
        assert!(f.s.dot(f.t).abs() < 1e-6 && f.t.dot(f.n).abs() < 1e-6 && (f.t.length() - 1.0).abs() < 1e-6);
        assert!(f.s.cross(f.t).dot(f.n) > 0.999, "right-handed");
        let b = Frame::with_tangent(-n, s);
        assert_eq!((b.s, b.t, b.n), (f.s, -f.t, -f.n));
        let v = Vec3::new(0.2, 0.5, -0.7);
        let (l, lb) = (f.to_local(v), b.to_local(v));
        assert_eq!((lb.x, lb.y, lb.z), (l.x, -l.y, -l.z));
    }
}
