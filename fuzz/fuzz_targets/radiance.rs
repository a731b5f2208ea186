//! Fuzz target `radiance`: [`opticks_fuzz::radiance`] on every input (see `fuzz/src/entry.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| opticks_fuzz::radiance(data));
