//! The end-to-end tests, one binary: the `opticks` binary as a user runs it (`cli_run`, which
//! needs `CARGO_BIN_EXE_opticks`, so these live in the CLI package), and the product checked
//! against closed forms, Mitsuba 3 references and its own guarantees through the libraries. The
//! MPI cluster tests have a binary of their own (`../cluster.rs`, `--features mpi`).

mod analytic;
mod bidirectional_references;
mod caustics;
mod cie171;
mod cli;
mod cli_run;
mod dataset_product;
mod daylight;
mod environment;
mod fingerprints;
mod guarantees;
mod hostile_input;
mod lights;
mod limits;
mod meter;
mod meters;
mod mitsuba_scenes;
mod photometry;
mod reference_scenes;
mod scene_formats;
mod sensors;
mod sky;
mod strategies;
mod tidy;
