//! The rays reader: any bytes give rays or errors with places, never a panic.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = glint::read_rays(data);
    if let Ok(line) = std::str::from_utf8(data) {
        let _ = glint::parse_ray(line);
    }
});
