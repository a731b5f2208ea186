//! Fuzz target `spectrum`: [`opticks_fuzz::spectrum`] on every input (see `fuzz/src/entry.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| opticks_fuzz::spectrum(data));
