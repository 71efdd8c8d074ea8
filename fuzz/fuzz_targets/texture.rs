//! Texture decoding: any bytes give a texture or a message, never a panic.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = glint::fuzzing::texture(data);
});
