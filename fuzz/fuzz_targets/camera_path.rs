//! Fuzz target `camera_path`: [`opticks_fuzz::camera_path`] on every input (see `fuzz/src/entry.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| opticks_fuzz::camera_path(data));
