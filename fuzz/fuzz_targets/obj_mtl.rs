//! Fuzz target `obj_mtl`: [`opticks_fuzz::obj_mtl`] on every input (see `fuzz/src/entry.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| opticks_fuzz::obj_mtl(data));
