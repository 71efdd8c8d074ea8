//! The scene reader: any bytes give a scene or diagnostics, never a panic.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    // A base folder that does not exist: names in the scene find nothing there.
    if let Err(e) = glint::Scene::parse(&text, "/nonexistent-glint-fuzz") {
        let _ = e.render(false);
    }
});
