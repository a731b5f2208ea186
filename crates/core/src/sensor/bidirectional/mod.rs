//! The bidirectional estimator (issue 11): camera subpaths from the sensor combined with the
//! stored dataset as the light half of a light-vertex-cache bidirectional path tracer
//! (Davidovič et al., *Progressive Light Transport Simulation on the GPU*, TOG 2014). At every
//! non-delta camera vertex the camera path estimates next-event (s = 1) and connects to n_c
//! vertices drawn from the whole cache (s ≥ 2); camera paths that hit an emitter estimate s = 0;
//! and every stored sample is still splatted to the camera (t = 1, the thesis's light tracer).
//! All of them are combined with multiple importance sampling; the derivation is
//! `docs/bidirectional.md`.
//!
//! | module | its one job |
//! |---|---|
//! | [`mis`] | the MIS weights and the camera side's per-vertex quantities (the light side's, stored with each sample, are the dataset's) |
//! | `camera.rs` | camera rays of every sensor, the image-wide density of a direction |
//! | `lights.rs` | the lights that are on: NEE's pick and light points, emitter hits |
//! | `cache.rs` | the light vertex cache: uniform draws, |Y|, per-light N_k |
//! | `vertex.rs` | what a camera-side vertex (a [`Receiver`]) gathers: NEE and connections |
//! | `path.rs` | camera subpaths and their emitter hits |
//! | `splat.rs` | the MIS-weighted light-tracing splat |
//! | `allocation.rs` | camera paths per pixel: uniform, or allocated pixel by pixel |
//! | `render.rs` | the [`Renderer`]: passes, counts, determinism |
//! | `progressive.rs` | camera passes accumulated into one image, with a running error estimate |
//! | `run.rs` | a whole render: the splat pass, then one camera pass or passes until a deadline, with progress callbacks |

mod allocation;
mod cache;
mod camera;
mod lights;
pub mod mis;
mod path;
pub mod pilot;
mod progressive;
mod render;
pub mod run;
mod splat;
mod vertex;

pub use allocation::{Allocation, cameras_needed};
pub use cache::{CANDIDATES, CacheChunk, CachedVertex, LightCache, PendingDraw, RecordMismatch};
pub use camera::{CameraRay, camera_ray, image_pdf};
pub use lights::{LightPoint, RenderLight, RenderLights};
pub use mis::{
    CameraPdf, CameraVertexMis, ConnectionEnd, Counts, weight_connection, weight_emitter_hit,
    weight_light_trace, weight_nee,
};
pub use path::{camera_path, scatter_mis};
pub use progressive::Progressive;
pub use render::{MAX_CONNECTIONS, Renderer, STOP_WORK, Settings, combine};
pub use splat::{light_trace_weight, splat_chunk};
pub(crate) use vertex::shadow_ray;
pub use vertex::{Context, DrawsAhead, Receiver, connect, connect_ahead, connection_weight, nee, nee_weight};
