//! The scene reader's diagnostics, printed: any bytes give a scene or
//! diagnostics that print (escaped, capped), never a panic.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    // Files named are found nowhere, as in the `scene` target.
    if let Err(e) = glint::fuzzing::scene(&text) {
        let _ = e.render(false);
    }
});
