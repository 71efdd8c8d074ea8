//! The OBJ loader: any bytes give models or a message, never a panic.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = glint::fuzzing::obj(data);
});
