//! Fuzz target `dataset`: [`opticks_fuzz::dataset`] on every input (see `fuzz/src/entry.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| opticks_fuzz::dataset(data));
