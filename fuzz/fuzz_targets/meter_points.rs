//! Fuzz target `meter_points`: [`opticks_fuzz::meter_points`] on every input (see `fuzz/src/entry.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| opticks_fuzz::meter_points(data));
