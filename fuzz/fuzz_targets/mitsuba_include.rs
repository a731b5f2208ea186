//! Fuzz target `mitsuba_include`: [`opticks_fuzz::mitsuba_include`] on every input (see `fuzz/src/entry.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| opticks_fuzz::mitsuba_include(data));
