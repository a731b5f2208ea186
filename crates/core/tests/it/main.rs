//! The core's integration tests, one binary (modules, not one executable per file: each extra
//! binary links everything again): physics checks of the light tracer and the bidirectional
//! estimator that need nothing but the core and the shared helpers of `opticks-testkit`.

mod bidirectional;
mod filters;
mod materials;
mod shading_normals;
