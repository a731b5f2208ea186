//! The dataset: what light sampling produces and every sensor consumes. A light table
//! (Φ_k, N_k per light) and chunks of compact [`Sample`] records, each chunk from one light.
//!
//! The estimator contract (docs/estimator.md §2): a sample of light k with weight β stands for the
//! incident flux Φ_k·β/N_k. Each light's energy is split only among its own N_k paths, so
//! relighting (scaling Φ_k) and merging (summing N_k) are exact laws, not approximations.

mod laws;
mod sample;
mod table;

pub use laws::{LightScale, Lighting, LightingError, MergeError, lighting, merge_tables};
pub use sample::{EMISSION_FLAG, Sample};
pub use table::{Chunk, LightRecord, LightTable};
