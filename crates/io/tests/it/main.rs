//! The file formats' integration tests, one binary: every reader and writer through the public
//! API of `opticks-io` (scene formats, the dataset file, images, hostile input, fuzz regressions),
//! and a tidy check of its sources (files opened only through `input_file`).
//! The VRML module installs a thread-local counting allocator for the whole binary (its budgets
//! are checked as bytes); the one test that needs a process-wide peak has a binary of its own
//! (`vrml_bomb_memory.rs`).

mod dataset_file;
mod dataset_file_contents;
mod front_end;
mod fuzz_regressions;
mod gltf;
mod gltf_textures;
mod hostile_readers;
mod image_file;
mod mitsuba;
mod mitsuba_bumpmap;
mod mitsuba_emitters;
mod mitsuba_fragment;
mod mitsuba_normalmap;
mod mitsuba_principled;
mod mitsuba_principledthin;
mod mitsuba_sensors;
mod mitsuba_structure;
mod mitsuba_textures;
mod obj_mtl;
mod radiance;
mod scene_loading;
mod tidy;
mod vrml;
