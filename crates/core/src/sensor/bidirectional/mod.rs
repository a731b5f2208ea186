//! The bidirectional estimator (issue 11): camera subpaths from the sensor combined with the
//! stored dataset as the light half of a light-vertex-cache bidirectional path tracer
//! (Davidovič et al., *Progressive Light Transport Simulation on the GPU*, TOG 2014). At every
//! non-delta camera vertex the camera path estimates next-event (s = 1) and connects to n_c
//! vertices drawn from the whole cache (s ≥ 2); camera paths that hit an emitter estimate s = 0;
//! and every stored sample is still splatted to the camera (t = 1, the thesis's light tracer).
//!
//! So far this holds the multiple-importance-sampling mathematics that combines those
//! strategies ([`mis`]): the per-vertex quantities the tracer stores with each sample and the
//! camera path carries, and the weights. Its derivation, the storage it needs (dataset format
//! v3) and how it keeps every dataset law exact are in `docs/bidirectional.md`.

pub mod mis;

pub use mis::{
    CameraVertexMis, ConnectionEnd, Counts, Emitter, Heuristic, LightKind, LightVertexMis, MisRecord,
    VcmClass, weight_connection, weight_emitter_hit, weight_light_trace, weight_nee,
};
