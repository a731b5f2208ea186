//! The light table and sample chunks: the bookkeeping that makes the estimator exact.

use super::{MisRecord, Sample};
use crate::math::Rgb;

/// One light's row in the dataset: its power Φ_k at trace time and its path count N_k.
#[derive(Clone, Debug, PartialEq)]
pub struct LightRecord {
    /// Name from the scene (lights are matched by name).
    pub name: String,
    /// The light's shape hash at trace time ([`crate::scene::Scene::light_shapes`]).
    pub shape: [u8; 16],
    /// Power Φ_k, W per channel.
    pub power: Rgb,
    /// Number of light paths emitted from this light (not stored vertices).
    pub paths: u64,
}

/// The light table of a dataset.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightTable {
    /// One record per scene light, in scene order.
    pub lights: Vec<LightRecord>,
}

impl LightTable {
    /// Flux carried by a sample of weight β = 1 from light `k`: Φ_k / N_k (zero if N_k = 0).
    #[inline]
    pub fn flux_per_path(&self, k: usize) -> Rgb {
        let l = &self.lights[k];
        if l.paths == 0 { Rgb::ZERO } else { l.power / l.paths as f32 }
    }

    /// Total paths over all lights. Datasets hold at most [`super::MAX_PATHS`] (readers and
    /// writers check it), so this never saturates for one read or written; it never wraps.
    pub fn total_paths(&self) -> u64 {
        self.lights.iter().fold(0u64, |a, l| a.saturating_add(l.paths))
    }
}

/// A run of samples traced from one light: `paths` paths produced `samples`.
/// Chunks are the unit of tracing, writing, checksumming, merging and rendering.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Chunk {
    /// Index of the light in the [`LightTable`].
    pub light: u32,
    /// Light paths this chunk accounts for (added to N_k).
    pub paths: u64,
    /// The stored vertices of those paths.
    pub samples: Vec<Sample>,
    /// The bidirectional estimator's MIS record of each sample (`docs/bidirectional.md` §5),
    /// parallel to `samples` (same length, same order), or empty when the chunk has none
    /// (traced without [`super::TraceSettings::mis`], or read from a format-2 file).
    pub records: Vec<MisRecord>,
}

impl Chunk {
    /// Whether the chunk carries MIS records (one per sample; a chunk without samples has
    /// records vacuously, so this is false only when samples lack them).
    #[inline]
    pub fn has_records(&self) -> bool {
        self.records.len() == self.samples.len()
    }
}
