//! Fresnel reflectance of smooth interfaces (unpolarised light), refraction by Snell's law, and
//! the table of named indices of refraction that Mitsuba accepts for `int_ior` / `ext_ior`.
//!
//! All functions take cosines measured on the side the light arrives from and a *relative* index
//! η = η_transmitted / η_incident (e.g. 1.5 for light entering glass from air, 1/1.5 leaving it).

use crate::math::{Rgb, Vec3};

/// Exact Fresnel reflectance of a dielectric interface for unpolarised light arriving with
/// `cos_i` (≥ 0) and relative index `eta`; 1 beyond the critical angle (total internal
/// reflection). Also returns cos θ_t (0 under total internal reflection).
#[inline]
pub fn dielectric(cos_i: f32, eta: f32) -> (f32, f32) {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return (1.0, 0.0);
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    (0.5 * (rs * rs + rp * rp), cos_t)
}

/// The diffuse Fresnel reflectance F_dr(η) of a smooth interface of relative index `eta`: the
/// fraction of uniformly diffuse (cosine-weighted) light arriving from the side of index 1 that
/// it reflects. The fits Mitsuba 3 uses (`fresnel_diffuse_reflectance`): Egan & Hilgeman (1973)
/// for η < 1, d'Eon & Irving (2011) for η ≥ 1 (errors below 0.6% for η in 1/2 … 2).
pub fn diffuse_reflectance(eta: f32) -> f32 {
    let inv = 1.0 / eta;
    if eta < 1.0 {
        0.0636 * inv + eta * (eta * -1.4399 + 0.7099) + 0.6681
    } else {
        0.919317 + inv * (-3.4793 + inv * (6.75335 + inv * (-7.80989 + inv * (4.98554 + inv * -1.36881))))
    }
}

/// Exact Fresnel reflectance of a conductor of complex relative index η + iκ, per channel, for
/// light arriving with `cos_i` (the formula of Mitsuba's `fresnel_conductor`, after Born & Wolf).
/// η = 0, κ = 1 (Mitsuba's `material="none"`) gives exactly 1.
#[inline]
pub fn conductor(cos_i: f32, eta: Rgb, k: Rgb) -> Rgb {
    let c = cos_i.clamp(0.0, 1.0);
    let (cos2, sin2) = (c * c, 1.0 - c * c);
    let (eta2, k2) = (eta * eta, k * k);
    let t0 = eta2 - k2 - Rgb::splat(sin2);
    let a2pb2 = (t0 * t0 + 4.0 * eta2 * k2).max(Rgb::ZERO);
    let a2pb2 = Rgb::new(a2pb2.x.sqrt(), a2pb2.y.sqrt(), a2pb2.z.sqrt());
    let a = (0.5 * (a2pb2 + t0)).max(Rgb::ZERO);
    let a = Rgb::new(a.x.sqrt(), a.y.sqrt(), a.z.sqrt());
    let t1 = a2pb2 + Rgb::splat(cos2);
    let t2 = 2.0 * c * a;
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = cos2 * a2pb2 + Rgb::splat(sin2 * sin2);
    let t4 = t2 * sin2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    let f = 0.5 * (rp + rs);
    // 0/0 only when c = 0 and the index vanishes: grazing light is reflected entirely.
    Rgb::new(nan_to_one(f.x), nan_to_one(f.y), nan_to_one(f.z)).clamp(Rgb::ZERO, Rgb::ONE)
}

#[inline]
fn nan_to_one(x: f32) -> f32 {
    if x.is_nan() { 1.0 } else { x }
}

/// Refracts `wi` (pointing away from the surface, on the side of `m`) through the interface of
/// unit normal `m` with relative index `eta`, given cos θ_t from [`dielectric`]; the result
/// points away on the other side.
#[inline]
pub fn refract(wi: Vec3, m: Vec3, eta: f32, cos_t: f32) -> Vec3 {
    let cos_i = wi.dot(m);
    (m * (cos_i / eta - cos_t) - wi / eta).normalize()
}

/// Mitsuba's named indices of refraction (`int_ior="bk7"` etc.), at 589 nm.
pub const NAMED_IORS: [(&str, f32); 23] = [
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// The index of a named material (case-insensitive), if Mitsuba knows it.
pub fn named_ior(name: &str) -> Option<f32> {
    NAMED_IORS.iter().find(|(n, _)| n.eq_ignore_ascii_case(name.trim())).map(|&(_, v)| v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_fresnel_known_values() {
        // Normal incidence: ((η − 1)/(η + 1))².
        let (f, ct) = dielectric(1.0, 1.5);
        assert!((f - 0.04).abs() < 1e-6 && (ct - 1.0).abs() < 1e-6);
        // Symmetric across the interface at normal incidence, and TIR beyond the critical angle.
        assert!((dielectric(1.0, 1.0 / 1.5).0 - 0.04).abs() < 1e-6);
        let crit = (1.0f32 - 1.0 / 2.25).sqrt(); // cos of the critical angle from inside glass
        assert_eq!(dielectric(crit * 0.99, 1.0 / 1.5).0, 1.0);
        assert!(dielectric(crit * 1.01, 1.0 / 1.5).0 < 1.0);
        // Grazing incidence reflects everything; η = 1 nothing.
        assert!((dielectric(0.0, 1.5).0 - 1.0).abs() < 1e-6);
        assert!(dielectric(0.3, 1.0).0 < 1e-12);
        // Transmission is the same seen from either side (Stokes relations).
        let ci = 0.7f32;
        let (f1, ct) = dielectric(ci, 1.5);
        let (f2, ci2) = dielectric(ct, 1.0 / 1.5);
        assert!((f1 - f2).abs() < 1e-6 && (ci2 - ci).abs() < 1e-5);
    }

    #[test]
    fn conductor_fresnel_reduces_to_known_cases() {
        // κ = 0: the dielectric formula.
        for c in [0.1f32, 0.5, 0.9, 1.0] {
            let f = conductor(c, Rgb::splat(1.5), Rgb::ZERO);
            assert!((f.x - dielectric(c, 1.5).0).abs() < 1e-5, "{c}: {f}");
        }
        // Normal incidence: ((η−1)² + κ²)/((η+1)² + κ²).
        let f = conductor(1.0, Rgb::new(0.2, 1.0, 2.0), Rgb::new(3.0, 2.0, 0.5));
        let want = |e: f32, k: f32| ((e - 1.0).powi(2) + k * k) / ((e + 1.0).powi(2) + k * k);
        assert!((f - Rgb::new(want(0.2, 3.0), want(1.0, 2.0), want(2.0, 0.5))).abs().max_element() < 1e-5);
        // Mitsuba's perfect mirror.
        for c in [0.0f32, 0.3, 1.0] {
            assert_eq!(conductor(c, Rgb::ZERO, Rgb::ONE), Rgb::ONE);
        }
    }

    #[test]
    fn refraction_obeys_snell() {
        let wi = Vec3::new(0.6, 0.0, 0.8);
        let (_, ct) = dielectric(0.8, 1.5);
        let wt = refract(wi, Vec3::Z, 1.5, ct);
        assert!((wt.x + 0.6 / 1.5).abs() < 1e-6 && wt.z < 0.0 && (wt.length() - 1.0).abs() < 1e-6);
        assert_eq!(named_ior("BK7"), Some(1.5046));
        assert_eq!(named_ior("unobtainium"), None);
    }
}
