//! The scene reader: any bytes give a scene or diagnostics, never a panic.
//! (Printing the diagnostics is the `diagnostics` target's: it costs
//! several times the reading, which this target exists to drive.)
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    // As `glint::Scene::parse`, but the files the scene names are found
    // nowhere (not even in the working directory): the fuzzer would
    // otherwise bend a name into one of the repository's meshes or
    // textures and decode it at each execution (see docs/fuzzing.md).
    let _ = glint::fuzzing::scene(&text);
});
