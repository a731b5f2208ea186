//! Random numbers and warps: seeded per-block random streams ([`RandomStream`]) and the maps
//! from the unit square to directions and points ([`warp`]), and the microfacet normal
//! distributions of the rough BSDFs ([`microfacet`]).

pub mod microfacet;
mod rng;
pub mod warp;

pub use rng::RandomStream;
pub(crate) use rng::{mix, unit_from_hash};
