//! Fuzz target `cluster_wire`: [`opticks_fuzz::cluster_wire`] on every input (see `fuzz/src/entry.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| opticks_fuzz::cluster_wire(data));
