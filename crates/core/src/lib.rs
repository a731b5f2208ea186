//! # opticks-core
//!
//! The engine of Opticks, a light-sampling renderer after the thesis *Newtonian Global
//! Illumination*. The pipeline, one module per stage:
//!
//! ```text
//! scene::SceneDescription ──build──▶ scene::Scene ──trace──▶ dataset chunks ──sensor──▶ film::Film
//! ```
//!
//! * [`scene`] turns a plain description (from any file format) into a validated scene with a BVH,
//!   a light table and a content fingerprint.
//! * [`trace`] runs the thesis's Algorithm 1: paths start at the lights and every non-specular
//!   vertex is kept as a [`dataset::Sample`]. **Trace never sees a camera.**
//! * [`dataset`] holds the sample record, the light table (Φ_k, N_k), the header and the trace
//!   plan, and every law and operation of the dataset (relighting, merging, refining, adding a
//!   light, resuming, previews).
//! * [`sensor`] connects stored samples to a sensor (pinhole camera) and accumulates a [`film::Film`].
//! * [`bench`](mod@bench) times a trace and a render in memory (`opticks bench`).
//!
//! This crate does no file IO and is deterministic for a given seed.
// `unsafe_code` is denied and `missing_docs` warned by the workspace's lints (Cargo.toml). One
// exception to the first, allowed where it stands: the prefetch hint (`math::prefetch`, used by
// the light vertex cache and the splat loop), which reads no memory into the program.
// `!(x > 0.0)` is how this crate rejects NaN along with the out-of-range values: deliberate.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod accel;
pub mod bench;
pub mod bsdf;
pub mod dataset;
pub mod film;
pub mod geometry;
pub mod light;
pub mod math;
pub mod sampling;
pub mod scene;
pub mod sensor;
pub mod texture;
pub mod trace;
