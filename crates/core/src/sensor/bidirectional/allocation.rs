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
//! Every pixel keeps at least one camera path, so the strategies that only camera paths have
//! (a mirror or glass seen by the camera) are never switched off.

/// Camera paths per pixel in each camera pass of a render.
#[derive(Clone, Debug, PartialEq)]
pub enum Allocation {
    /// The same number for every pixel (at least 1).
    Uniform(u32),
    /// One number per pixel (row-major; each at least 1).
    PerPixel(Vec<u32>),
}

impl Allocation {
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
    /// render's single count then holds).
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
                Some(
                    v.iter().map(|&m| n / (pixels as f64 * m.max(1) as f64 * passes.max(1) as f64)).collect(),
                )
            }
        }
    }
}
