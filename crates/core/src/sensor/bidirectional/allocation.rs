//! How many camera paths each pixel gets in a camera pass: the same number everywhere, or a
//! number per pixel (design change 3 of issue 25: spend camera paths where they buy the most
//! error per second, and let the light-tracing splats carry the pixels where they are strong).
//!
//! Any allocation fixed before a render's passes keeps the bidirectional estimator unbiased:
//! the light-tracing strategy's count c_LT = N/M (`mis` module docs) becomes, pixel by pixel,
//! N/(W·H·m_p) with m_p the camera paths planned for pixel p in the whole render, and every
//! strategy of a path that ends in pixel p — the splat that lands there, the camera strategies
//! of that pixel's camera paths — weighs itself with the same c_LT(p), so the weights of each
//! path still sum to one (`docs/bidirectional.md` §2, §10.2: any positive counts are unbiased).
//!
//! **Pixels without camera paths** (m_p = 0, c_LT(p) = ∞). A pixel may go without camera paths
//! only where the light-tracing splat alone samples every path that reaches it: then its splats
//! weigh 1 and it is the light estimator's pixel, unbiased. The splat (t = 1) samples a path
//! whenever the path's vertex next to the camera is stored, i.e. not on a delta surface (the
//! tracer keeps every non-delta vertex; emission points of area lights included) and not at
//! infinity (an environment seen directly). [`cameras_needed`] proves it per pixel from the
//! geometry alone, before any pass ([`VisibilityBuffer::pixels_meeting`]): a pixel needs camera
//! paths if the projection of any triangle whose material is not one the splats suffice for
//! ([`splats_suffice`]: diffuse, or a rough plastic or rough conductor of broad lobe; and
//! unmasked) meets the footprint of its camera rays (the pixel grown by the filter's radius),
//! hidden or not, or — with an environment in the scene — if no triangle is known to cover that
//! footprint. Those materials have no delta lobe, so the splats alone are unbiased there; which
//! non-delta materials count is a choice of efficiency only, measured (`docs/performance.md`:
//! on diffuse scenes the light estimator is 1.4–2× more efficient than camera paths everywhere;
//! sharp glossy surfaces and rough glass are where camera paths pay). Mirrors, glass, sharp
//! glossy surfaces and the sky keep their camera paths. No pilot decides it, so no rare path
//! can be missed (the pilot-driven allocations measured before failed that way). Cameras
//! without a visibility buffer (lens, orthographic, 360°) keep camera paths everywhere.

use crate::bsdf::Bsdf;
use crate::light::Light;
use crate::scene::Scene;
use crate::sensor::{Sensor, VisibilityBuffer};

/// Microfacet roughness from which a rough plastic's coating counts as broad enough for the
/// splats alone (a heuristic of efficiency, not of correctness: module docs). Measured on the
/// furnished room (`testdata/mitsuba/room`, 1 M paths, 16 spp, one thread), its floor's α
/// varied: at α = 0.05 camera paths on it are 1.3× more efficient than its splats alone, at
/// 0.08 they are even, at the room's 0.12 the splats alone are 1.3× more efficient (the whole
/// image: 18.5 against 14.0, in 1/(relMSE·s)) — and at 0.05 the pilot, left to choose, gave the
/// floor no camera paths, so below this roughness the choice is not left to it.
pub const BROAD_ALPHA: f32 = 0.1;

/// The same for a rough conductor, whose lobe carries all of its reflection (a plastic's
/// diffuse base carries most of its): GGX gold of α = 0.25 (`testdata/mitsuba/rough`) left to
/// the pilot gets camera paths where they pay, within 3 % of the same efficiency as when it
/// always had them; the room's gold sphere (α = 0.2) is 2 % of its view.
pub const BROAD_METAL_ALPHA: f32 = 0.2;

/// Whether pixels that see only surfaces of `bsdf` can do without camera paths (the pilot
/// decides whether they do): the diffuse ones, rough plastics of roughness at least
/// [`BROAD_ALPHA`] and rough conductors of at least [`BROAD_METAL_ALPHA`] (no delta lobe, and a
/// lobe broad enough for the splats to reach it often).
pub fn splats_suffice(bsdf: &Bsdf) -> bool {
    let alpha = |m: &crate::sampling::microfacet::Microfacet| m.alpha_u.min(m.alpha_v);
    match bsdf {
        Bsdf::Lambert(_) => true,
        Bsdf::RoughPlastic(p) => alpha(&p.microfacet) >= BROAD_ALPHA,
        Bsdf::RoughConductor(c) => alpha(&c.microfacet) >= BROAD_METAL_ALPHA,
        _ => false,
    }
}

/// Per pixel of `sensor`'s image, whether it needs camera paths (module docs), from the
/// sensor's visibility buffer (`Sensor::visibility`: only pinhole cameras have one; without it
/// every pixel does); `None` when it cannot be proven for any pixel.
pub fn cameras_needed(scene: &Scene, sensor: &Sensor, buffer: &VisibilityBuffer) -> Option<Vec<bool>> {
    let diffuse = |t: u32| !scene.is_masked(t) && splats_suffice(&scene.material(t).bsdf);
    let escapes = scene.lights.iter().any(|l| matches!(l, Light::Environment(_)));
    // Camera rays of a pixel start within its filter's radius of its centre.
    let grow = (sensor.raster().filter.radius() - 0.5).max(0.0).ceil() as usize;
    buffer.pixels_meeting(scene, |t| !diffuse(t), grow, escapes)
}

/// Camera paths per pixel in each camera pass of a render.
#[derive(Clone, Debug, PartialEq)]
pub enum Allocation {
    /// The same number for every pixel (at least 1).
    Uniform(u32),
    /// One number per pixel (row-major; 0 only where the splats alone are unbiased: module
    /// docs).
    PerPixel(Vec<u32>),
}

impl Allocation {
    /// `spp` camera paths where `needed` (per pixel, [`cameras_needed`]) says so, none
    /// elsewhere; `spp` everywhere without `needed`.
    pub fn where_needed(needed: Option<&[bool]>, spp: u32) -> Allocation {
        match needed {
            Some(n) if !n.iter().all(|&x| x) => {
                Allocation::PerPixel(n.iter().map(|&x| if x { spp } else { 0 }).collect())
            }
            _ => Allocation::Uniform(spp),
        }
    }

    /// Camera paths of pixel `p` in one pass.
    #[inline]
    pub fn at(&self, p: usize) -> u32 {
        match self {
            Allocation::Uniform(n) => *n,
            Allocation::PerPixel(v) => v[p],
        }
    }

    /// Camera paths of one pass over `pixels` pixels.
    pub fn total(&self, pixels: usize) -> u64 {
        match self {
            Allocation::Uniform(n) => *n as u64 * pixels as u64,
            Allocation::PerPixel(v) => v.iter().map(|&n| n as u64).sum(),
        }
    }

    /// The most camera paths any pixel gets in one pass.
    pub fn max(&self) -> u32 {
        match self {
            Allocation::Uniform(n) => *n,
            Allocation::PerPixel(v) => v.iter().copied().max().unwrap_or(0),
        }
    }

    /// Per pixel, the light-tracing count c_LT(p) = N/(W·H·m_p) of a render of `passes`
    /// passes over `pixels` pixels with `light_paths` (N) light paths: `None` if uniform (the
    /// render's single count then holds). A pixel without camera paths gets ∞: its splats
    /// weigh 1.
    pub(super) fn light_trace_counts(
        &self,
        light_paths: u64,
        pixels: usize,
        passes: u64,
    ) -> Option<Vec<f64>> {
        match self {
            Allocation::Uniform(_) => None,
            Allocation::PerPixel(v) => {
                let n = light_paths as f64;
                let each = |m: u32| match m {
                    0 => f64::INFINITY,
                    m => n / (pixels as f64 * m as f64 * passes.max(1) as f64),
                };
                Some(v.iter().map(|&m| each(m)).collect())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::SmoothConductor;
    use crate::geometry::Ray;
    use crate::math::{Rgb, Vec2};
    use crate::sampling::RandomStream;
    use crate::scene::cornell_box;
    use crate::sensor::Pinhole;
    use crate::sensor::bidirectional::camera_ray;

    /// The Cornell box with its red wall a mirror, through its own camera.
    fn mirror_cornell() -> (Scene, Sensor) {
        let mut desc = cornell_box();
        desc.materials[1].bsdf = Bsdf::SmoothConductor(SmoothConductor::new(Rgb::ONE, None).unwrap());
        let scene = Scene::build(&desc).unwrap();
        let sensor = Sensor::from(Pinhole::new(scene.camera.as_ref().unwrap()).unwrap());
        (scene, sensor)
    }

    /// Per pixel, what 16 random camera rays through it first meet: whether any hits a surface
    /// the splats do not suffice for, and whether any leaves the scene.
    fn brute_force(scene: &Scene, sensor: &Sensor) -> Vec<(bool, bool)> {
        let (w, h) = (sensor.width(), sensor.height());
        let mut rng = RandomStream::new(7, &[1]);
        (0..w * h)
            .map(|p| {
                let (mut glossy, mut escapes) = (false, false);
                for _ in 0..16 {
                    let r = camera_ray(sensor, p % w, p / w, rng.next_2d(), Vec2::ZERO);
                    match scene.intersect(&Ray { origin: r.origin, dir: r.dir, t_max: f32::INFINITY }) {
                        Some(hit) => glossy |= !splats_suffice(&scene.material(hit.prim).bsdf),
                        None => escapes = true,
                    }
                }
                (glossy, escapes)
            })
            .collect()
    }

    /// Every pixel through which a camera ray meets the mirror is flagged (a pixel left to the
    /// splats there would render the mirror black), and so is every pixel through which one
    /// leaves the scene when escapes count (an environment); the diffuse rest is not.
    #[test]
    fn every_pixel_that_sees_a_mirror_or_the_sky_gets_camera_paths() {
        let (scene, sensor) = mirror_cornell();
        let buffer = sensor.visibility(&scene).expect("a pinhole has a buffer");
        let needed = cameras_needed(&scene, &sensor, &buffer).unwrap();
        let truth = brute_force(&scene, &sensor);
        let (mut mirror, mut free) = (0, 0);
        for (p, &(glossy, _)) in truth.iter().enumerate() {
            assert!(!glossy || needed[p], "pixel {p} sees the mirror but gets no camera paths");
            mirror += glossy as usize;
            free += !needed[p] as usize;
        }
        let n = truth.len();
        assert!(mirror > n / 20 && free > n / 2, "{mirror} mirror pixels, {free} left to the splats of {n}");
        // With escapes counted (as with an environment): every pixel a ray leaves through.
        let sky = buffer.pixels_meeting(&scene, |_| false, 0, true).unwrap();
        let escaping = truth.iter().filter(|t| t.1).count();
        assert!(escaping > 0, "the camera sees past the box's open side");
        for (p, &(_, escapes)) in truth.iter().enumerate() {
            assert!(!escapes || sky[p], "pixel {p} sees the sky but gets no camera paths");
        }
        // The diffuse box alone needs none (the light estimator's image, exactly).
        let desc = cornell_box();
        let diffuse = Scene::build(&desc).unwrap();
        let buffer = sensor.visibility(&diffuse).unwrap();
        assert!(!cameras_needed(&diffuse, &sensor, &buffer).unwrap().contains(&true));
    }

    /// Growing by a filter's radius flags the neighbours of every flagged pixel.
    #[test]
    fn a_wide_filter_grows_the_flagged_pixels() {
        let (scene, sensor) = mirror_cornell();
        let buffer = sensor.visibility(&scene).unwrap();
        let flagged = |t: u32| !splats_suffice(&scene.material(t).bsdf);
        let (a, b) = (
            buffer.pixels_meeting(&scene, flagged, 0, false).unwrap(),
            buffer.pixels_meeting(&scene, flagged, 2, false).unwrap(),
        );
        let w = sensor.width() as usize;
        for (p, &f) in a.iter().enumerate() {
            let (i, j) = (p % w, p / w);
            for (di, dj) in [(0, 0), (2, 0), (0, 2), (2, 2)] {
                let (x, y) = ((i + di).saturating_sub(1), (j + dj).saturating_sub(1));
                if f && x < w && y < a.len() / w {
                    assert!(b[y * w + x], "({x}, {y}) next to flagged ({i}, {j})");
                }
            }
        }
        assert!(b.iter().filter(|&&f| f).count() > a.iter().filter(|&&f| f).count());
    }

    /// A pixel without camera paths gets c_LT = ∞ (its splats weigh 1); the others N/(W·H·m_p).
    #[test]
    fn pixels_without_camera_paths_weigh_their_splats_one() {
        let a = Allocation::where_needed(Some(&[true, false, true, true]), 4);
        assert_eq!(a, Allocation::PerPixel(vec![4, 0, 4, 4]));
        let c = a.light_trace_counts(400, 4, 2).unwrap();
        assert_eq!(c, vec![400.0 / 32.0, f64::INFINITY, 400.0 / 32.0, 400.0 / 32.0]);
        assert_eq!(Allocation::where_needed(Some(&[true; 3]), 4), Allocation::Uniform(4));
        assert_eq!(Allocation::where_needed(None, 4), Allocation::Uniform(4));
    }
}
